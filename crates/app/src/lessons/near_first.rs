//! Lesson 6, the lecture's quiz: near side first, or file order? Two panes step in lockstep
//! through the one BVH traversal, run with `Order::NearFirst` and `Order::FileOrder` on the
//! same tree and ray. The counters are the core's (`counters_of` replays the recorded steps).

use accelviz_core::{Counters, Order, Step, counters_of};
use egui::{Color32, Stroke, Vec2};

use super::bvh::BuiltBvh;
use super::common::{self, BvhRule, Recording};
use super::{Lesson, LessonText};
use crate::canvas::{Canvas, faded, palette};
use crate::editor::{EditableScene, Editing};
use crate::timeline::Timeline;

/// The two orders, left pane first.
pub const ORDERS: [(Order, &str); 2] = [
    (Order::NearFirst, "near side first"),
    (Order::FileOrder, "file order"),
];

/// Reads one counter.
type CounterOf = fn(&Counters) -> u64;

/// The lesson.
pub struct NearFirstLesson {
    text: LessonText,
    scene: EditableScene,
    built: Option<BuiltBvh>,
    built_revision: u64,
    recordings: [Recording; 2],
    timeline: Timeline,
}

impl NearFirstLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let scene = EditableScene::new(text.scene.clone(), Editing::ALL);
        Self {
            text,
            scene,
            built: None,
            built_revision: 0,
            recordings: Default::default(),
            timeline: Timeline::default(),
        }
    }

    fn refresh(&mut self) {
        if self.built.is_some() && self.built_revision == self.scene.revision {
            return;
        }
        let built = BuiltBvh::new(&self.scene, BvhRule::BinnedSah);
        self.recordings = match self.scene.ray() {
            Ok(ray) => ORDERS.map(|(order, _)| {
                common::record_bvh(&built.bvh, &self.scene.scene.shapes, &ray, order)
            }),
            Err(_) => Default::default(),
        };
        self.timeline.set_len(
            self.recordings
                .iter()
                .map(|recording| recording.steps.len())
                .max()
                .unwrap_or(0),
        );
        self.built = Some(built);
        self.built_revision = self.scene.revision;
    }

    /// The steps each pane shows: the same number, or all of a pane's when it is done.
    pub fn shown(&self, pane: usize) -> &[Step<f64>] {
        let steps = &self.recordings[pane].steps;
        &steps[..self.timeline.shown.min(steps.len())]
    }

    /// Counters of what each pane has shown so far.
    pub fn pane_counters(&mut self) -> [Counters; 2] {
        self.refresh();
        [counters_of(self.shown(0)), counters_of(self.shown(1))]
    }

    fn pane_ui(
        &self,
        ui: &mut egui::Ui,
        pane: usize,
        size: Vec2,
        view: &mut crate::canvas::View2d,
    ) -> Canvas {
        let bounds = self.scene.bounds();
        let canvas = Canvas::allocate(ui, size, view, &bounds, false);
        let Some(built) = &self.built else {
            return canvas;
        };
        let shown = self.shown(pane);
        common::draw_tested_shapes(ui, &canvas, &self.scene.scene.shapes, shown, None);
        let faint = faded(ui.visuals().weak_text_color(), 70);
        canvas.box_outlines(
            built
                .bvh
                .nodes
                .iter()
                .map(|entry| (entry.bounds, Stroke::new(1.0, faint))),
        );
        for step in shown {
            match step {
                Step::NodeEntered { node } => canvas.box_outline(
                    &built.bvh.nodes[*node as usize].bounds,
                    Stroke::new(2.0, faded(palette::HIT, 200)),
                    None,
                ),
                Step::NodeCulled { node, .. }
                | Step::BoxTested {
                    node, hit: false, ..
                } => canvas.box_outline(
                    &built.bvh.nodes[*node as usize].bounds,
                    Stroke::new(2.0, faded(palette::MISS, 200)),
                    Some(faded(palette::MISS, 25)),
                ),
                _ => {}
            }
        }
        if let Some(
            Step::BoxTested { node, .. }
            | Step::NodeEntered { node }
            | Step::NodeCulled { node, .. },
        ) = shown.last()
        {
            canvas.box_outline(
                &built.bvh.nodes[*node as usize].bounds,
                Stroke::new(4.0, palette::CURRENT),
                None,
            );
        }
        if let Ok(ray) = self.scene.ray() {
            common::draw_ray(&canvas, &ray, common::closest_so_far(shown).map(|(_, t)| t));
        }
        self.scene.draw_handles(&canvas);
        let counters = counters_of(shown);
        let done = shown.len() == self.recordings[pane].steps.len() && !shown.is_empty();
        canvas.caption(&[
            (
                format!("{}{}", ORDERS[pane].1, if done { ": done" } else { "" }),
                Color32::WHITE,
            ),
            (
                format!(
                    "nodes {}  boxes {}  primitives {}  skipped {}",
                    counters.nodes_visited,
                    counters.box_tests,
                    counters.primitive_tests,
                    counters.nodes_culled
                ),
                Color32::WHITE,
            ),
        ]);
        canvas
    }
}

impl Lesson for NearFirstLesson {
    fn text(&self) -> &LessonText {
        &self.text
    }

    fn scene_mut(&mut self) -> Option<&mut EditableScene> {
        Some(&mut self.scene)
    }

    fn timeline(&mut self) -> Option<(&mut Timeline, String)> {
        self.refresh();
        let describe = |pane: usize| match self.shown(pane).last() {
            Some(step) => common::describe_step(step, |node| format!("node {node}")),
            None => "start".to_owned(),
        };
        let caption = format!(
            "near first: {}  |  file order: {}",
            describe(0),
            describe(1)
        );
        Some((&mut self.timeline, caption))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui) {
        let now = self.pane_counters();
        let totals = [
            counters_of(&self.recordings[0].steps),
            counters_of(&self.recordings[1].steps),
        ];
        ui.heading("Counters");
        egui::Grid::new("order counters")
            .striped(true)
            .show(ui, |ui| {
                ui.label("");
                ui.strong("near first");
                ui.strong("file order");
                ui.end_row();
                let rows: [(&str, CounterOf); 4] = [
                    ("nodes visited", |c| c.nodes_visited),
                    ("box tests", |c| c.box_tests),
                    ("primitive tests", |c| c.primitive_tests),
                    ("nodes skipped", |c| c.nodes_culled),
                ];
                for (name, value) in rows {
                    ui.label(name);
                    for pane in 0..2 {
                        ui.label(format!("{} of {}", value(&now[pane]), value(&totals[pane])));
                    }
                    ui.end_row();
                }
                ui.label("closest hit");
                for recording in &self.recordings {
                    ui.label(match recording.hit {
                        Some(hit) => format!("#{} at t = {}", hit.primitive, common::number(hit.t)),
                        None => "none".to_owned(),
                    });
                }
                ui.end_row();
            });
        ui.separator();
        ui.label(egui::RichText::new("Why first do the near side?").strong());
        ui.label(
            "A hit found early lowers the cut-off, and every node that starts beyond it is skipped \
             without opening it. Near first finds the closest hit as early as the tree allows.",
        );
        ui.label(egui::RichText::new("What happens in file order?").strong());
        ui.label(
            "The far side may be opened first: its hits are found, then beaten by a nearer one, \
             and the work on the far side was wasted. Both orders give the same answer; only the \
             cost differs.",
        );
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.scene.toolbar_ui(ui);
        self.refresh();
        let size = ui.available_size();
        let pane_size = Vec2::new((size.x - 8.0) * 0.5, size.y);
        let mut view = self.scene.view;
        let canvases = ui
            .horizontal(|ui| {
                [
                    self.pane_ui(ui, 0, pane_size, &mut view),
                    self.pane_ui(ui, 1, pane_size, &mut view),
                ]
            })
            .inner;
        self.scene.view = view;
        let mut changed = false;
        for canvas in &canvases {
            changed |= self.scene.interact(ui, canvas);
        }
        if changed {
            self.refresh();
        }
    }
}
