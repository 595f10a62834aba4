//! What several lessons share: drawing the scene's shapes, building a BVH of it, recording a
//! traversal, and describing a recorded step in words.

use accelviz_core::bvh::{
    self, BinnedSah, BuildParams, Builder, Bvh, MedianSplit, MiddleSplit, SweepSah,
};
use accelviz_core::kd::{self, KdBuilder, KdMedianSplit, KdMiddleSplit, KdSah, KdTree};
use accelviz_core::{
    Hit, Order, PrimitiveSet, Ray, Recorder, ShapeSet, Step, TraceOptions, brute_force,
};
use accelviz_scene::document::SceneSettings;
use egui::{Color32, Stroke};
use glam::DVec2;

use crate::canvas::{BATCH_ABOVE, Batch, Canvas, faded, palette};

/// The fill of a shape nobody is looking at, readable on either theme.
pub fn shape_fill(ui: &egui::Ui) -> Color32 {
    if ui.visuals().dark_mode {
        Color32::from_gray(150)
    } else {
        Color32::from_gray(110)
    }
}

/// Draws every shape; `color_of` picks a colour for shapes that stand out.
pub fn draw_shapes(
    ui: &egui::Ui,
    canvas: &Canvas,
    shapes: &ShapeSet<DVec2>,
    color_of: impl Fn(usize) -> Option<Color32>,
) {
    let plain = shape_fill(ui);
    if shapes.shapes.len() > BATCH_ABOVE {
        let mut batch = Batch::default();
        // A disc takes up to 41 vertices; boxes and segments 4.
        batch.reserve(shapes.shapes.len() * 16, shapes.shapes.len() * 14);
        for (index, shape) in shapes.shapes.iter().enumerate() {
            canvas.batch_shape(&mut batch, shape, color_of(index).unwrap_or(plain));
        }
        canvas.draw_batch(batch);
        return;
    }
    for (index, shape) in shapes.shapes.iter().enumerate() {
        let color = color_of(index).unwrap_or(plain);
        canvas.shape(shape, faded(color, 200), Stroke::new(1.0, color));
    }
}

/// Draws every shape, coloured by the last test of it in `steps` (green hit, red missed),
/// `current` in the "now" colour.
pub fn draw_tested_shapes(
    ui: &egui::Ui,
    canvas: &Canvas,
    shapes: &ShapeSet<DVec2>,
    steps: &[Step<f64>],
    current: Option<usize>,
) {
    let mut tested: Vec<Option<bool>> = vec![None; shapes.shapes.len()];
    for step in steps {
        if let Step::PrimitiveTested { primitive, t_hit } = step
            && let Some(entry) = tested.get_mut(*primitive as usize)
        {
            *entry = Some(t_hit.is_some());
        }
    }
    draw_shapes(ui, canvas, shapes, |index| {
        if Some(index) == current {
            return Some(palette::CURRENT);
        }
        tested[index].map(|hit| if hit { palette::HIT } else { palette::MISS })
    });
}

/// A tree node's colour after the first steps of a traversal: red if its box was missed or
/// it was skipped, green if it was entered (the tree diagrams' emphasis).
pub fn traversal_emphasis(steps: &[Step<f64>], node_count: usize) -> Vec<Option<Color32>> {
    let mut emphasis = vec![None; node_count];
    for step in steps {
        let (node, color) = match *step {
            Step::NodeEntered { node } | Step::CellEntered { node, .. } => (node, palette::HIT),
            Step::BoxTested {
                node, hit: false, ..
            }
            | Step::NodeCulled { node, .. } => (node, faded(palette::MISS, 200)),
            _ => continue,
        };
        if let Some(entry) = emphasis.get_mut(node as usize) {
            // A miss or a skip is final; an entry does not hide it.
            if *entry != Some(faded(palette::MISS, 200)) {
                *entry = Some(color);
            }
        }
    }
    emphasis
}

/// The parameters every builder gets from a scene's settings.
fn build_params(settings: &SceneSettings) -> BuildParams {
    BuildParams {
        max_leaf_size: settings.max_leaf_size,
        cost: settings.cost(),
        ..BuildParams::default()
    }
}

/// The BVH builders a lesson can pick, the lecture's rules first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhRule {
    /// Split the node's box in the middle of its longest axis.
    Middle,
    /// Split at the median primitive.
    Median,
    /// The surface area heuristic, every candidate evaluated (sweep).
    Sah,
    /// The SAH over a few bins.
    BinnedSah,
}

impl BvhRule {
    /// Name for the user.
    pub fn label(self) -> &'static str {
        match self {
            BvhRule::Middle => "middle",
            BvhRule::Median => "median",
            BvhRule::Sah => "SAH",
            BvhRule::BinnedSah => "binned SAH",
        }
    }

    /// Builds a BVH over `shapes` with this rule and the scene's settings.
    pub fn build(self, shapes: &ShapeSet<DVec2>, settings: &SceneSettings) -> Bvh<DVec2> {
        let bounds = shapes.all_bounds();
        let params = build_params(settings);
        match self {
            BvhRule::Middle => MiddleSplit.build(&bounds, &params),
            BvhRule::Median => MedianSplit.build(&bounds, &params),
            BvhRule::Sah => SweepSah.build(&bounds, &params),
            BvhRule::BinnedSah => BinnedSah {
                bins: settings.bins,
            }
            .build(&bounds, &params),
        }
    }
}

/// The kD builders a lesson can pick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KdRule {
    /// Cut the cell in the middle of its longest axis.
    Middle,
    /// Cut at the median primitive.
    Median,
    /// The SAH with the empty-space bonus.
    Sah,
}

impl KdRule {
    /// Name for the user.
    pub fn label(self) -> &'static str {
        match self {
            KdRule::Middle => "middle",
            KdRule::Median => "median",
            KdRule::Sah => "SAH",
        }
    }

    /// Builds a kD-tree over `shapes` with this rule and the scene's settings.
    pub fn build(self, shapes: &ShapeSet<DVec2>, settings: &SceneSettings) -> KdTree<DVec2> {
        let bounds = shapes.all_bounds();
        let params = build_params(settings);
        match self {
            KdRule::Middle => KdMiddleSplit.build(&bounds, &params),
            KdRule::Median => KdMedianSplit.build(&bounds, &params),
            KdRule::Sah => KdSah.build(&bounds, &params),
        }
    }
}

/// One recorded trace: every step, and the answer.
#[derive(Clone, Debug, Default)]
pub struct Recording {
    /// The steps, in order.
    pub steps: Vec<Step<f64>>,
    /// The closest hit.
    pub hit: Option<Hit<f64>>,
}
impl Recording {
    /// Runs `trace` with a recorder and keeps its steps and answer.
    fn of(trace: impl FnOnce(&mut Recorder<f64>) -> Option<Hit<f64>>) -> Self {
        let mut recorder = Recorder::default();
        let hit = trace(&mut recorder);
        Self {
            steps: recorder.steps,
            hit,
        }
    }
}

/// The options of a recorded trace: the core's defaults in the given order.
fn options_in(order: Order) -> TraceOptions {
    TraceOptions {
        order,
        ..TraceOptions::default()
    }
}

/// Records the one BVH traversal on a ray.
pub fn record_bvh(
    bvh: &Bvh<DVec2>,
    shapes: &ShapeSet<DVec2>,
    ray: &Ray<DVec2>,
    order: Order,
) -> Recording {
    Recording::of(|recorder| {
        bvh::traverse(
            bvh,
            shapes,
            ray,
            &options_in(order),
            &mut bvh::TraversalStack::new(),
            recorder,
        )
    })
}

/// Records the one kD traversal on a ray.
pub fn record_kd(
    tree: &KdTree<DVec2>,
    shapes: &ShapeSet<DVec2>,
    ray: &Ray<DVec2>,
    order: Order,
) -> Recording {
    Recording::of(|recorder| {
        kd::traverse(
            tree,
            shapes,
            ray,
            &options_in(order),
            &mut kd::KdTraversalStack::new(),
            recorder,
        )
    })
}

/// Records the trivial loop (every primitive in file order) on a ray.
pub fn record_brute_force(shapes: &ShapeSet<DVec2>, ray: &Ray<DVec2>) -> Recording {
    Recording::of(|recorder| brute_force(shapes, ray, &TraceOptions::default(), recorder))
}

/// The closest hit after the first steps of a recording: primitive and t.
pub fn closest_so_far(steps: &[Step<f64>]) -> Option<(u32, f64)> {
    steps.iter().rev().find_map(|step| match *step {
        Step::ClosestHitUpdated { primitive, t } => Some((primitive, t)),
        _ => None,
    })
}

/// What a step did, in words; `node_name` names a node.
pub fn describe_step(step: &Step<f64>, node_name: impl Fn(u32) -> String) -> String {
    match *step {
        Step::BoxTested {
            node,
            t_enter,
            t_exit,
            hit,
        } => {
            if hit {
                format!(
                    "box of {} tested: hit, the ray is inside for t in [{}, {}]",
                    node_name(node),
                    number(t_enter),
                    number(t_exit)
                )
            } else {
                format!(
                    "box of {} tested: missed, skip everything inside it",
                    node_name(node)
                )
            }
        }
        Step::NodeEntered { node } => format!("enter {}", node_name(node)),
        Step::CellEntered {
            node,
            t_near,
            t_far,
        } => format!(
            "enter {} with the ray clipped to it: t in [{}, {}]",
            node_name(node),
            number(t_near),
            number(t_far)
        ),
        Step::NodeCulled {
            node,
            t_enter,
            t_closest,
        } => format!(
            "skip {}: it starts at t = {} beyond the closest hit so far (t = {})",
            node_name(node),
            number(t_enter),
            number(t_closest)
        ),
        Step::PrimitiveTested { primitive, t_hit } => match t_hit {
            Some(t) => format!("primitive {primitive} tested: hit at t = {}", number(t)),
            None => format!("primitive {primitive} tested: miss"),
        },
        Step::ClosestHitUpdated { primitive, t } => {
            format!(
                "closest hit so far: primitive {primitive} at t = {}",
                number(t)
            )
        }
        Step::PrimitiveSkipped { primitive } => {
            format!("primitive {primitive} skipped: already tested (mailbox)")
        }
        Step::CellMissed { node } => format!("{}: the ray does not reach it", node_name(node)),
    }
}

/// A number for a caption: ±∞ spelled out, three decimals otherwise.
pub fn number(value: f64) -> String {
    if value == f64::INFINITY {
        "+∞".to_owned()
    } else if value == f64::NEG_INFINITY {
        "−∞".to_owned()
    } else if value.is_nan() {
        "NaN".to_owned()
    } else {
        format!("{value:.3}")
    }
}

/// Draws the ray: solid up to `t_solid`, faded beyond it.
pub fn draw_ray(canvas: &Canvas, ray: &Ray<DVec2>, t_solid: Option<f64>) {
    let t_end = canvas.clip_t(ray.origin, ray.direction, f64::INFINITY);
    if let Some(t) = t_solid.filter(|t| *t < t_end) {
        let cut = ray.origin + ray.direction * t;
        canvas.painter.line_segment(
            [
                canvas.to_screen(cut),
                canvas.to_screen(ray.origin + ray.direction * t_end),
            ],
            Stroke::new(1.5, faded(palette::RAY, 70)),
        );
        canvas.ray(ray.origin, ray.direction, t, Stroke::new(2.5, palette::RAY));
        canvas.ray_mark(ray.origin, ray.direction, t, palette::HIT, "closest", 2.0);
    } else {
        canvas.ray(
            ray.origin,
            ray.direction,
            t_end,
            Stroke::new(2.5, palette::RAY),
        );
    }
}
