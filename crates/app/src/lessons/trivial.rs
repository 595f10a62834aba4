//! Lesson 1, "Trivial": loop over every primitive and intersect. The animation steps through
//! the core's brute force, one test a step; the plot shows tests per ray against n on log
//! scales, the trivial loop's n beside a BVH's few dozen, with this scene and this ray marked.

use std::sync::Arc;

use accelviz_core::format::{count, number};
use accelviz_core::{PrimitiveSet, Ray, ShapeSet, SplitRule, Structure, TraceOptions};
use accelviz_scene::document::SceneSettings;
use accelviz_scene::scene2d::{Layout, generate};
use egui::Color32;
use egui_plot::{Legend, Line, MarkerShape, Plot, PlotPoints, Points};
use glam::DVec2;

use crate::background::{Cached, Derived};
use crate::canvas::palette;
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage, request_over_shapes};
use crate::trace::{Trace, describe_step};
use crate::views::compare::{count_rays, measured_rays};
use crate::views::scene_view::{
    building_note, draw_ray, draw_tested_shapes, narrow_x_axis, number_shapes, power_of_ten_label,
    powers_of_ten, t_hint_ui,
};

/// The scene sizes of the growth curve.
const GROWTH_SIZES: [usize; 6] = [16, 64, 256, 1_024, 4_096, 16_384];

/// Tests per ray in a scene of `count` shapes: the trivial loop tests all n; a BVH tests boxes
/// and a few primitives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrowthPoint {
    /// Shapes in the scene.
    pub count: usize,
    /// Tests per ray of the trivial loop (n).
    pub brute_force_tests: f64,
    /// Box and primitive tests per ray of a SAH BVH.
    pub bvh_tests: f64,
}

/// A SAH BVH over the current scene, with its tests per ray averaged over the measured rays.
struct CurrentScene {
    tree: SceneTree,
    point: GrowthPoint,
}

/// Box and primitive tests per ray through `tree`, over `rays`.
fn bvh_tests_per_ray(tree: &SceneTree, rays: &[Ray<DVec2>]) -> f64 {
    let counters = count_rays(tree, rays, &TraceOptions::default());
    (counters.box_tests + counters.primitive_tests) as f64 / rays.len().max(1) as f64
}

fn growth_point(shapes: Arc<ShapeSet<DVec2>>, settings: SceneSettings) -> CurrentScene {
    let structure = Structure::lecture(accelviz_core::Family::Bvh, SplitRule::Sah);
    let rays = measured_rays(&shapes);
    let count = shapes.len();
    let tree = SceneTree::build(structure, shapes, settings);
    let point = GrowthPoint {
        count,
        brute_force_tests: count as f64,
        bvh_tests: bvh_tests_per_ray(&tree, &rays),
    };
    CurrentScene { tree, point }
}

/// The growth curve over uniform scenes of every size in `GROWTH_SIZES`.
pub fn measure_growth() -> Vec<GrowthPoint> {
    GROWTH_SIZES
        .into_iter()
        .map(|size| {
            growth_point(
                Arc::new(generate(Layout::Uniform, size, 5)),
                SceneSettings::default(),
            )
            .point
        })
        .collect()
}

/// The trivial loop, stepped.
pub struct TrivialLoop {
    stage: Stage,
    trace: Cached<u64, Trace>,
    growth: Cached<(), Vec<GrowthPoint>>,
    current: Derived<(u64, ()), CurrentScene>,
}

impl TrivialLoop {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::ALL),
            trace: Cached::default(),
            growth: Cached::default(),
            current: Derived::default(),
        }
    }

    fn trace(&self) -> Option<&Trace> {
        self.trace.get()
    }

    /// What the lesson shows now: the trace's state at the timeline's frame.
    pub fn shown_state(&self) -> Option<crate::trace::TraceState> {
        Some(self.trace()?.state(self.stage.timeline.shown))
    }

    /// BVH tests on the current ray, for the plot's "this ray" mark.
    fn bvh_tests_on_ray(&self) -> Option<f64> {
        let current = self.current.get()?;
        let ray = self.stage.scene.ray().ok()?;
        Some(bvh_tests_per_ray(&current.tree, &[ray]))
    }

    fn plot_ui(&mut self, ui: &mut egui::Ui) {
        let growth = self.growth.get_or_make((), measure_growth).clone();
        let current = self.current.get().map(|current| current.point);
        let this_ray = self.bvh_tests_on_ray();
        let log = |value: f64| value.max(1.0).log10();
        let line = |value: fn(&GrowthPoint) -> f64| -> PlotPoints {
            growth
                .iter()
                .map(|point| [log(point.count as f64), log(value(point))])
                .collect()
        };
        let plot_bg = ui.visuals().extreme_bg_color;
        Plot::new("growth")
            .height(220.0)
            .legend(Legend::default().position(egui_plot::Corner::LeftTop))
            // Room above the curves for the legend.
            .custom_x_axes(vec![
                narrow_x_axis("primitives n (log scale)").formatter(power_of_ten_label),
            ])
            .y_axis_label("tests per ray (log)")
            .y_axis_formatter(power_of_ten_label)
            .x_grid_spacer(powers_of_ten)
            .y_grid_spacer(powers_of_ten)
            .include_y(0.0)
            .include_y(6.6)
            .include_x(1.0)
            .include_x(5.0)
            .allow_scroll(false)
            .allow_drag(false)
            .allow_zoom(false)
            .show(ui, |plot| {
                plot.line(
                    Line::new("trivial loop: n", line(|p| p.brute_force_tests))
                        .color(crate::canvas::ink_on(palette::MISS, plot_bg)),
                );
                plot.line(
                    Line::new("SAH BVH: boxes + primitives", line(|p| p.bvh_tests))
                        .color(crate::canvas::ink_on(palette::HIT, plot_bg)),
                );
                if let Some(point) = current {
                    let n = log(point.count as f64);
                    plot.points(
                        Points::new(
                            format!("this scene, n = {}", count(point.count)),
                            PlotPoints::new(vec![
                                [n, log(point.brute_force_tests)],
                                [n, log(point.bvh_tests)],
                            ]),
                        )
                        .shape(MarkerShape::Diamond)
                        .radius(6.0)
                        .color(Color32::WHITE),
                    );
                    if let Some(tests) = this_ray {
                        plot.points(
                            Points::new(
                                "this ray, with a BVH",
                                PlotPoints::new(vec![[n, log(tests)]]),
                            )
                            .shape(MarkerShape::Circle)
                            .radius(5.0)
                            .color(crate::canvas::ink_on(palette::RAY, plot_bg)),
                        );
                    }
                }
            });
        match current {
            Some(point) => {
                let ratio = point.brute_force_tests / point.bvh_tests.max(1e-9);
                let saving = if ratio >= 1.5 {
                    format!("{ratio:.0}× fewer")
                } else {
                    "about as many: at this size a structure does not pay yet".to_owned()
                };
                ui.label(format!(
                    "This scene: the loop tests all {} shapes for every ray; a BVH tests {:.1} boxes and primitives per ray on average (256 seeded rays through the scene), {saving}.{}",
                    count(point.count),
                    point.bvh_tests,
                    this_ray.map_or(String::new(), |tests| format!(" This ray: {tests:.0}."))
                ))
            }
            None => ui.label("Measuring this scene…"),
        };
    }
}

impl Lesson for TrivialLoop {
    crate::staged!(current);

    fn update(&mut self) {
        let scene = &self.stage.scene;
        let trace = self
            .trace
            .get_or_make(scene.revision, || match scene.ray() {
                Ok(ray) => Trace::of_brute_force(&scene.scene.shapes, &ray),
                Err(_) => Trace::default(),
            });
        self.stage.timeline.set_len(trace.frames());
        request_over_shapes(&mut self.current, scene, (), growth_point);
    }

    fn caption(&self) -> Option<String> {
        let trace = self.trace()?;
        Some(trace.caption(
            self.stage.timeline.shown,
            "Press step (or the right arrow): the loop tests primitive 0 first, then every other in file order.",
            |step| describe_step(step, |node| format!("node {node}")),
        ))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        let total = self.stage.scene.scene.shapes.len();
        ui.heading("This ray");
        if let Some(state) = self.shown_state() {
            ui.label(format!(
                "primitives tested: {} of {}",
                state.counters.primitive_tests,
                count(total)
            ));
            ui.label(match state.closest {
                Some((primitive, t)) => {
                    format!(
                        "closest hit so far: primitive {primitive} at t = {}",
                        number(t)
                    )
                }
                None if state.done => "done: the ray hits nothing".to_owned(),
                None => "no hit yet".to_owned(),
            });
        }
        ui.label("Every ray tests every primitive, hit or not: n tests per ray, n·m for m rays.");
        t_hint_ui(ui);
        ui.separator();
        ui.heading("Tests per ray as n grows");
        self.plot_ui(ui);
        ui.label(
            egui::RichText::new(
                "Both axes are logarithmic, so the loop's n and the BVH's few dozen both show. Can we do better? Yes: lesson 2 on.",
            )
            .small()
            .weak(),
        );
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let canvas = self.stage.scene.canvas_ui(ui, None);
        let Some(trace) = self.trace.get() else {
            return;
        };
        let frame = self.stage.timeline.shown;
        let state = trace.state(frame);
        let shown = trace.shown(frame);
        let current = match state.current {
            Some(accelviz_core::Step::PrimitiveTested { primitive, .. }) => Some(primitive),
            _ => None,
        };
        let shapes = &self.stage.scene.scene.shapes;
        draw_tested_shapes(ui, &canvas, shapes, shown, current);
        match self.stage.scene.ray() {
            Ok(ray) => draw_ray(&canvas, &ray, state.closest.map(|(_, t)| t)),
            Err(error) => canvas.caption(&[(format!("No ray: {error}"), palette::MISS)]),
        }
        number_shapes(ui, &canvas, shapes);
        self.stage.scene.draw_handles(&canvas);
        canvas.caption(&[(
            format!(
                "tested {} of {}: red missed, green hit, blue now",
                state.counters.primitive_tests,
                count(shapes.len())
            ),
            Color32::WHITE,
        )]);
        building_note(
            ui,
            &canvas,
            self.current.working_for(),
            "the BVH of this scene",
        );
        self.stage.scene.draw_footer(&canvas);
        canvas.finish();
    }
}
