//! Several structures built over one scene, side by side, each measured on the same seeded
//! rays: what lessons 7, 8 and 10 compare.

use std::sync::Arc;

use accelviz_core::{Counters, Ray, ShapeSet, SplitRule, Structure, TraceOptions, TraversalStacks};
use accelviz_scene::document::SceneSettings;
use accelviz_scene::rng::SplitMix64;
use egui::{Color32, Vec2};
use glam::DVec2;

use crate::background::Derived;
use crate::canvas::{Canvas, View2d, palette};
use crate::editor::EditableScene;
use crate::stage::{SceneTree, request_over_shapes};
use crate::views::scene_view::{building_note, draw_shapes};
use crate::views::tree_view::{TreeLook, draw_tree};

/// The lecture's three rules, in pane order.
pub const LECTURE_RULES: [SplitRule; 3] = [SplitRule::Middle, SplitRule::Median, SplitRule::Sah];

/// Rays the panes are measured with: seeded, from a circle around the scene to points in it.
pub const MEASURED_RAYS: usize = 256;

/// Several trees of one scene with their counters on the same rays.
pub struct Comparison {
    /// The trees, in pane order.
    pub trees: Vec<SceneTree>,
    /// Counters summed over the measured rays, by tree.
    pub counters: Vec<Counters>,
    /// How many rays were measured.
    pub ray_count: usize,
    /// Counts on a second set of rays, from points inside the scene (the recap's): each
    /// pane's caption then gives its cost per ray from outside and from inside, so a slide
    /// that shows only the panes does not show the walls' answer alone.
    pub inside: Option<InsideRays>,
}

/// Each structure's counters on rays from points inside the scene, in every direction.
pub struct InsideRays {
    /// Counters summed over the rays, by tree.
    pub counters: Vec<Counters>,
    /// How many rays.
    pub ray_count: usize,
}

impl Comparison {
    /// Builds each structure over `shapes` and traces the measured rays through each.
    pub fn build(
        structures: &[Structure],
        shapes: Arc<ShapeSet<DVec2>>,
        settings: SceneSettings,
    ) -> Self {
        Self::of_trees(
            structures
                .iter()
                .map(|&structure| SceneTree::build(structure, shapes.clone(), settings))
                .collect(),
        )
    }

    /// Traces the measured rays (of the first tree's shapes) through trees already built
    /// over the same shapes.
    pub fn of_trees(trees: Vec<SceneTree>) -> Self {
        let rays = trees
            .first()
            .map_or_else(Vec::new, |tree| measured_rays(&tree.shapes));
        let options = TraceOptions::default();
        let counters = trees
            .iter()
            .map(|tree| count_rays(tree, &rays, &options))
            .collect();
        Self {
            trees,
            counters,
            ray_count: rays.len(),
            inside: None,
        }
    }

    /// Also counts `rays`, from points inside the scene, through every tree.
    pub fn with_inside(mut self, rays: &[Ray<DVec2>]) -> Self {
        let options = TraceOptions::default();
        self.inside = Some(InsideRays {
            counters: self
                .trees
                .iter()
                .map(|tree| count_rays(tree, rays, &options))
                .collect(),
            ray_count: rays.len(),
        });
        self
    }

    /// What pane `pane`'s structure costs per measured ray, and what it holds.
    pub fn measured(&self, pane: usize) -> Measured {
        self.measured_with(pane, &self.counters[pane], self.ray_count)
    }

    /// What pane `pane`'s structure costs per ray by `counters` summed over `rays` rays of
    /// another set, and what it holds.
    pub fn measured_with(&self, pane: usize, counters: &Counters, rays: usize) -> Measured {
        let tree = &self.trees[pane];
        let per_ray = |count: u64| count as f64 / rays.max(1) as f64;
        let (nodes, tests) = (
            per_ray(counters.nodes_visited),
            per_ray(counters.primitive_tests),
        );
        Measured {
            nodes_per_ray: nodes,
            tests_per_ray: tests,
            cost_per_ray: tree.settings.cost().per_ray(nodes, tests),
            references_per_primitive: tree.stats.primitive_references as f64
                / tree.shapes.shapes.len().max(1) as f64,
            empty_share: tree.stats.empty_leaf_share,
            node_count: tree.stats.node_count,
        }
    }

    /// A counter of pane `pane`, per measured ray.
    pub fn per_ray(&self, pane: usize, counter: impl Fn(&Counters) -> u64) -> f64 {
        counter(&self.counters[pane]) as f64 / self.ray_count.max(1) as f64
    }

    /// Short lines of statistics for pane `pane`.
    pub fn summary(&self, pane: usize) -> Vec<String> {
        let stats = &self.trees[pane].stats;
        let mut lines = vec![
            format!(
                "SAH cost {}, depth {}",
                accelviz_core::format::number(stats.sah_cost),
                stats.max_depth
            ),
            format!(
                "{} leaves of {}..{} (mean {:.1})",
                accelviz_core::format::count(stats.leaf_count),
                stats.min_leaf_size,
                stats.max_leaf_size,
                stats.mean_leaf_size
            ),
        ];
        match &self.inside {
            None => lines.push(format!(
                "per ray: {:.1} nodes, {:.1} tests",
                self.per_ray(pane, |c| c.nodes_visited),
                self.per_ray(pane, |c| c.primitive_tests)
            )),
            Some(inside) => {
                let per_ray = |count: u64| count as f64 / inside.ray_count.max(1) as f64;
                lines.push(format!(
                    "outside: {:.1} nodes, {:.1} tests a ray",
                    self.per_ray(pane, |c| c.nodes_visited),
                    self.per_ray(pane, |c| c.primitive_tests)
                ));
                lines.push(format!(
                    "inside: {:.1} nodes, {:.1} tests a ray",
                    per_ray(inside.counters[pane].nodes_visited),
                    per_ray(inside.counters[pane].primitive_tests)
                ));
            }
        }
        if let Some(note) = self.trees[pane].limits_note() {
            lines.push(note);
        }
        lines
    }

    /// How many panes a row: `preferred`, unless another count shows the scene clearly larger
    /// in the room there is (`height` points high, as wide as `ui`), each pane's caption
    /// measured as [`Canvas::caption`] lays it out. Five panes of a wide scene in three
    /// columns left each 60 points of scene under its caption at lecture size; in one row
    /// they are three times that.
    fn best_columns(
        &self,
        ui: &egui::Ui,
        preferred: usize,
        height: f32,
        gap: f32,
        extent: DVec2,
    ) -> usize {
        let panes = self.trees.len().max(1);
        let font = crate::canvas::font(ui.ctx(), 14.0);
        // The tallest and widest caption of any pane, as the canvas lays it out (lines 6
        // points apart, 10 in from the edge).
        let caption = (0..self.trees.len())
            .map(|pane| {
                let mut lines = vec![self.trees[pane].built.structure.name()];
                lines.extend(self.summary(pane));
                lines.iter().fold(Vec2::new(0.0, 8.0), |size, line| {
                    let galley = ui.fonts_mut(|fonts| {
                        fonts.layout_no_wrap(line.clone(), font.clone(), Color32::WHITE)
                    });
                    Vec2::new(
                        size.x.max(galley.size().x + 16.0),
                        size.y + galley.size().y + 6.0,
                    )
                })
            })
            .fold(Vec2::ZERO, Vec2::max);
        let scale = |columns: usize| {
            let rows = panes.div_ceil(columns);
            let size = Vec2::new(
                (ui.available_width() - gap * (columns - 1) as f32) / columns as f32,
                (height - gap * (rows - 1) as f32) / rows as f32,
            );
            View2d::fitted_scale(extent, size, caption, 0.0).0
        };
        let preferred = preferred.clamp(1, panes);
        let best = (1..=panes)
            .max_by(|a, b| scale(*a).total_cmp(&scale(*b)))
            .unwrap_or(preferred);
        if scale(best) > scale(preferred) * 1.2 {
            best
        } else {
            preferred
        }
    }

    /// The panes side by side, `columns` a row (or as many as show the scene larger), sharing one view, each titled with its
    /// structure's name in `title_color(pane)` and drawn by `overlay` after its tree; the
    /// user's edits on any pane go to `scene`. While a newer comparison is `working`, the
    /// first pane says so.
    #[allow(clippy::too_many_arguments)] // The pieces of one call, each used once.
    pub(crate) fn panes_ui(
        &self,
        ui: &mut egui::Ui,
        scene: &mut EditableScene,
        working: Option<std::time::Duration>,
        height: f32,
        columns: usize,
        title_color: impl Fn(usize) -> Color32,
        overlay: impl Fn(usize, &SceneTree, &Canvas),
    ) {
        let gap = 6.0;
        let bounds = scene.bounds();
        let columns = self.best_columns(ui, columns, height, gap, bounds.extent());
        let rows = self.trees.len().div_ceil(columns).max(1);
        let width = (ui.available_width() - gap * (columns - 1) as f32) / columns as f32;
        let height = (height - gap * (rows - 1) as f32) / rows as f32;
        let mut view: View2d = scene.view;
        let mut canvases = Vec::with_capacity(self.trees.len());
        for row in 0..rows {
            if row > 0 {
                ui.add_space(gap - ui.spacing().item_spacing.y);
            }
            let panes = row * columns..((row + 1) * columns).min(self.trees.len());
            ui.horizontal(|ui| {
                ui.spacing_mut().item_spacing.x = gap;
                for pane in panes {
                    let canvas =
                        Canvas::allocate(ui, Vec2::new(width, height), &mut view, &bounds, false);
                    let tree = &self.trees[pane];
                    draw_shapes(ui, &canvas, &tree.shapes, |_| None);
                    draw_tree(
                        &canvas,
                        tree,
                        &TreeLook {
                            structure_alpha: 200,
                            ..TreeLook::default()
                        },
                    );
                    overlay(pane, tree, &canvas);
                    let mut lines = vec![(tree.built.structure.name(), title_color(pane))];
                    lines.extend(
                        self.summary(pane)
                            .into_iter()
                            .map(|line| (line, Color32::WHITE)),
                    );
                    canvas.caption(&lines);
                    canvas.finish();
                    canvases.push(canvas);
                }
            });
        }
        scene.view = view;
        if let Some(canvas) = canvases.first() {
            building_note(ui, canvas, working, "the trees");
        }
        for canvas in &canvases {
            scene.interact(ui, canvas);
        }
        if let Some(canvas) = canvases.last() {
            scene.draw_footer(canvas);
        }
    }
}

/// The panes of the comparison `derived` holds, `height` points high in rows of `columns` (as
/// `Comparison::panes_ui` draws them), or a line saying it is building until the first build is done.
pub fn comparison_ui<K: Clone + PartialEq + Send + 'static>(
    ui: &mut egui::Ui,
    derived: &Derived<K, Comparison>,
    scene: &mut EditableScene,
    height: f32,
    columns: usize,
    title_color: impl Fn(usize) -> Color32,
    overlay: impl Fn(usize, &SceneTree, &Canvas),
) {
    match derived.get() {
        Some(comparison) => comparison.panes_ui(
            ui,
            scene,
            derived.working_for(),
            height,
            columns,
            title_color,
            overlay,
        ),
        None => {
            ui.label("Building…");
        }
    }
}

/// Asks `derived` for the comparison of `structures` over the scene, for the lesson's
/// `choice` (see [`request_over_shapes`]).
pub fn request_comparison<C: Clone + PartialEq + Send + 'static, const N: usize>(
    derived: &mut Derived<(u64, C), Comparison>,
    scene: &EditableScene,
    choice: C,
    structures: [Structure; N],
) {
    request_over_shapes(derived, scene, choice, move |shapes, settings| {
        Comparison::build(&structures, shapes, settings)
    });
}

/// What one structure costs per ray on a scene, and what it holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// Nodes (or cells) entered per ray.
    pub nodes_per_ray: f64,
    /// Primitive tests per ray.
    pub tests_per_ray: f64,
    /// `C_trav · nodes + C_isect · tests` per ray: the measured SAH cost.
    pub cost_per_ray: f64,
    /// Primitive references in leaves per primitive (1 for a BVH).
    pub references_per_primitive: f64,
    /// The share of the scene's area in empty leaves or cells.
    pub empty_share: f64,
    /// Nodes in the tree.
    pub node_count: usize,
}

/// The work of tracing `rays` through `tree` (over the shapes it was built on), counted.
pub fn count_rays(tree: &SceneTree, rays: &[Ray<DVec2>], options: &TraceOptions) -> Counters {
    let mut counters = Counters::default();
    let mut stacks = TraversalStacks::default();
    for ray in rays {
        tree.built.tree.trace(
            tree.shapes.as_ref(),
            ray,
            options,
            &mut stacks,
            &mut counters,
        );
    }
    counters
}

/// Seeded rays from a circle around the shapes to random points in their box.
pub fn measured_rays(shapes: &ShapeSet<DVec2>) -> Vec<Ray<DVec2>> {
    let bounds = shapes.bounding_box();
    if bounds.is_empty() {
        return Vec::new();
    }
    let mut rng = SplitMix64::new(27);
    let center = bounds.center();
    let reach = bounds.extent().length() * 0.75 + 1e-9;
    (0..MEASURED_RAYS)
        .filter_map(|_| {
            let angle = rng.range(0.0, std::f64::consts::TAU);
            let origin = center + DVec2::new(angle.cos(), angle.sin()) * reach;
            let target = DVec2::new(
                rng.range(bounds.min.x, bounds.max.x),
                rng.range(bounds.min.y, bounds.max.y),
            );
            Ray::try_new(origin, target - origin).ok()
        })
        .collect()
}

/// Seeded rays from random points inside the shapes' box in random directions: a walk from
/// wherever a ray may start (a camera inside the scene, a bounce), what a grid's cost at a
/// cell size depends on (rays from outside a scene walled in stop at the wall's cell).
pub fn interior_rays(shapes: &ShapeSet<DVec2>) -> Vec<Ray<DVec2>> {
    let bounds = shapes.bounding_box();
    if bounds.is_empty() {
        return Vec::new();
    }
    let mut rng = SplitMix64::new(31);
    (0..MEASURED_RAYS)
        .filter_map(|_| {
            let origin = DVec2::new(
                rng.range(bounds.min.x, bounds.max.x),
                rng.range(bounds.min.y, bounds.max.y),
            );
            let angle = rng.range(0.0, std::f64::consts::TAU);
            Ray::try_new(origin, DVec2::new(angle.cos(), angle.sin())).ok()
        })
        .collect()
}

/// The colour of a rule's marks (pane titles, curve markers, ghost splits).
pub fn rule_color(rule: SplitRule) -> Color32 {
    match rule {
        SplitRule::Middle => palette::X_AXIS,
        SplitRule::Median => palette::Y_AXIS,
        SplitRule::Sah => palette::CURRENT,
        SplitRule::Uniform => palette::BOX,
    }
}
