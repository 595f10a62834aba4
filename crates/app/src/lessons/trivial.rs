//! Lesson 1, "Trivial": loop over every primitive and intersect. The animation steps through
//! the core's brute force; the plot shows tests per ray growing with n, beside a BVH's.

use accelviz_core::{Counters, PrimitiveSet, Ray, Step, TraceOptions};
use accelviz_scene::document::SceneSettings;
use accelviz_scene::rng::SplitMix64;
use accelviz_scene::scene2d::{Layout, generate};
use egui::Color32;
use egui_plot::{Legend, Line, Plot, PlotPoints};
use glam::DVec2;

use super::common::{self, BvhRule, Recording};
use super::{Lesson, LessonText};
use crate::canvas::palette;
use crate::editor::{EditableScene, Editing};
use crate::timeline::Timeline;

/// The trivial loop, stepped.
pub struct TrivialLoop {
    text: LessonText,
    scene: EditableScene,
    built_revision: u64,
    recording: Recording,
    timeline: Timeline,
    growth: Option<Vec<GrowthPoint>>,
}

/// Tests per ray for a scene of `count` shapes.
#[derive(Clone, Copy, Debug)]
struct GrowthPoint {
    count: usize,
    brute_force_tests: f64,
    bvh_tests: f64,
}

impl TrivialLoop {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let scene = EditableScene::new(text.scene.clone(), Editing::ALL);
        Self {
            text,
            scene,
            built_revision: 0,
            recording: Recording::default(),
            timeline: Timeline::default(),
            growth: None,
        }
    }

    fn refresh(&mut self) {
        if self.built_revision == self.scene.revision {
            return;
        }
        self.built_revision = self.scene.revision;
        self.recording = match self.scene.ray() {
            Ok(ray) => common::record_brute_force(&self.scene.scene.shapes, &ray),
            Err(_) => Recording::default(),
        };
        self.timeline.set_len(self.recording.steps.len());
    }

    fn shown(&self) -> &[Step<f64>] {
        &self.recording.steps[..self.timeline.shown.min(self.recording.steps.len())]
    }
}

/// Tests per ray against n, averaged over seeded random rays through uniform scenes: the
/// trivial loop tests all n, a BVH (SAH) tests boxes and a few primitives.
fn measure_growth() -> Vec<GrowthPoint> {
    let settings = SceneSettings::default();
    let mut rng = SplitMix64::new(11);
    [16, 32, 64, 128, 256, 512, 1024, 2048]
        .into_iter()
        .map(|count| {
            let shapes = generate(Layout::Uniform, count, 5);
            let bvh = BvhRule::BinnedSah.build(&shapes, &settings);
            let rays = 64;
            let mut bvh_counters = Counters::default();
            let mut brute_counters = Counters::default();
            for _ in 0..rays {
                let origin = DVec2::new(rng.range(-10.0, 110.0), -10.0);
                let toward = DVec2::new(rng.range(0.0, 100.0), rng.range(0.0, 100.0));
                let Ok(ray) = Ray::try_new(origin, toward - origin) else {
                    continue;
                };
                accelviz_core::bvh::traverse(
                    &bvh,
                    &shapes,
                    &ray,
                    &TraceOptions::default(),
                    &mut accelviz_core::bvh::TraversalStack::new(),
                    &mut bvh_counters,
                );
                accelviz_core::brute_force(
                    &shapes,
                    &ray,
                    &TraceOptions::default(),
                    &mut brute_counters,
                );
            }
            GrowthPoint {
                count: shapes.len(),
                brute_force_tests: brute_counters.primitive_tests as f64 / rays as f64,
                bvh_tests: (bvh_counters.box_tests + bvh_counters.primitive_tests) as f64
                    / rays as f64,
            }
        })
        .collect()
}

impl Lesson for TrivialLoop {
    fn text(&self) -> &LessonText {
        &self.text
    }

    fn scene_mut(&mut self) -> Option<&mut EditableScene> {
        Some(&mut self.scene)
    }

    fn timeline(&mut self) -> Option<(&mut Timeline, String)> {
        self.refresh();
        let caption = match self.shown().last() {
            None => "Press step (or the right arrow): the loop tests primitive 0 first, then every other in file order.".to_owned(),
            Some(step) => common::describe_step(step, |node| format!("node {node}")),
        };
        Some((&mut self.timeline, caption))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui) {
        self.refresh();
        let total = self.scene.scene.shapes.len();
        let tested = self
            .shown()
            .iter()
            .filter(|step| matches!(step, Step::PrimitiveTested { .. }))
            .count();
        ui.heading("This ray");
        ui.label(format!("primitives tested: {tested} of {total}"));
        match common::closest_so_far(self.shown()) {
            Some((primitive, t)) => ui.label(format!(
                "closest hit so far: primitive {primitive} at t = {}",
                common::number(t)
            )),
            None => ui.label("no hit yet"),
        };
        ui.label(
            "Every ray tests every primitive, hit or not: the cost is n per ray, n·m for m rays.",
        );
        ui.separator();
        ui.heading("Tests per ray as n grows");
        let growth = self.growth.get_or_insert_with(measure_growth);
        let brute: PlotPoints = growth
            .iter()
            .map(|point| [point.count as f64, point.brute_force_tests])
            .collect();
        let bvh: PlotPoints = growth
            .iter()
            .map(|point| [point.count as f64, point.bvh_tests])
            .collect();
        Plot::new("growth")
            .height(200.0)
            .legend(Legend::default())
            .x_axis_label("primitives n")
            .y_axis_label("tests per ray")
            .allow_scroll(false)
            .show(ui, |plot| {
                plot.line(Line::new("trivial loop: n", brute).color(palette::MISS));
                plot.line(Line::new("BVH (SAH): boxes + primitives", bvh).color(palette::HIT));
            });
        if let Some(last) = growth.last() {
            ui.label(format!(
                "At n = {}: {:.0} tests per ray for the loop, {:.1} for a BVH (64 random rays, uniform scene). Can we do better? Yes: lesson 2 on.",
                last.count, last.brute_force_tests, last.bvh_tests
            ));
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let canvas = self.scene.canvas_ui(ui, None);
        self.refresh();
        let shown = self.shown();
        let current = match shown.last() {
            Some(Step::PrimitiveTested { primitive, .. }) => Some(*primitive as usize),
            Some(Step::ClosestHitUpdated { primitive, .. }) => Some(*primitive as usize),
            _ => None,
        };
        common::draw_tested_shapes(ui, &canvas, &self.scene.scene.shapes, shown, current);
        let closest = common::closest_so_far(shown);
        match self.scene.ray() {
            Ok(ray) => common::draw_ray(&canvas, &ray, closest.map(|(_, t)| t)),
            Err(error) => canvas.caption(&[(format!("No ray: {error}"), palette::MISS)]),
        }
        for (index, shape) in self.scene.scene.shapes.shapes.iter().enumerate().take(60) {
            let bounds = shape.bounds();
            canvas.label(
                DVec2::new(bounds.max.x, bounds.max.y),
                &index.to_string(),
                ui.visuals().weak_text_color(),
            );
        }
        self.scene.draw_handles(&canvas);
        let tested_count = shown
            .iter()
            .filter(|step| matches!(step, Step::PrimitiveTested { .. }))
            .count();
        canvas.caption(&[(
            format!(
                "tested {tested_count} of {}: red missed, green hit, blue now",
                self.scene.scene.shapes.len()
            ),
            Color32::WHITE,
        )]);
    }
}
