//! Lesson 6, the lecture's quiz: "Why first do near side? What happens if we just traverse in
//! file order?" The slide asks it of the kD-tree traversal; the lesson shows it on a kD-tree
//! and on a BVH of the same scene, each traced near side first and in file order: four panes
//! stepping in lockstep through the one traversal of each kind (`Order::NearFirst` against
//! `Order::FileOrder`). Everything shown part-way is the state at that step: the counters are
//! the core's, replayed; the closest hit is the closest so far. The answers stay hidden until
//! asked for.

use accelviz_core::format::{count, number};
use accelviz_core::{Counters, Family, Order, SplitRule, Structure};
use accelviz_scene::document::Scene2d;
use egui::{Color32, RichText, Vec2};
use glam::DVec2;

use crate::background::{Cached, Derived};
use crate::canvas::{Canvas, View2d};
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage, request_over_shapes};
use crate::trace::{Trace, TraceState, describe_step, options_in};
use crate::views::scene_view::{building_note, draw_ray, draw_tested_shapes, t_hint_ui};
use crate::views::tree_view::{TreeLook, draw_tree};

/// The two orders, in column order.
pub const ORDERS: [(Order, &str); 2] = [
    (Order::NearFirst, "near side first"),
    (Order::FileOrder, "file order"),
];

/// The two structures, in row order: the slide's kD-tree, then a BVH.
pub const FAMILIES: [Family; 2] = [Family::Kd, Family::Bvh];

/// The quiz's questions and answers.
const QUESTIONS: [(&str, &str); 2] = [
    (
        "Why first do the near side?",
        "The first hit found near the origin is a cut-off: every cell or box that starts beyond it cannot hold anything nearer and is skipped without being opened. Searching the near side first finds the closest hit as early as the tree allows, so the most is skipped. (A kD-tree can even stop at the first leaf with a hit inside its cell.)",
    ),
    (
        "What happens if we just traverse in file order?",
        "The order in memory has nothing to do with the ray: file order opens the far side first whenever the ray runs against it. With the slide's `If(no intersection)`, a hit there ends the search, so file order can return a hit that is not the closest (the quiz shows one). These panes cull by the closest hit instead: every waiting side is still searched unless it starts beyond the hit, so both orders find the same hit, and file order pays for it in wasted work. Near first never depends on luck.",
    ),
];

/// Reads one counter.
type CounterOf = fn(&Counters) -> u64;

/// The counters of the table, in row order.
const COUNTER_ROWS: [(&str, CounterOf); 4] = [
    ("nodes visited", |c| c.nodes_visited),
    ("box tests", |c| c.box_tests),
    ("primitive tests", |c| c.primitive_tests),
    ("nodes skipped", |c| c.nodes_culled),
];

/// The lesson.
pub struct NearFirstLesson {
    stage: Stage,
    /// The kD-tree and the BVH, in [`FAMILIES`] order.
    trees: Derived<(u64, ()), [SceneTree; 2]>,
    /// By structure, then by order.
    traces: Cached<(u64, u64), [[Trace; 2]; 2]>,
    /// Which answers have been asked for.
    revealed: [bool; 2],
}

impl NearFirstLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::ALL),
            trees: Derived::default(),
            traces: Cached::default(),
            revealed: [false; 2],
        }
    }

    /// The recording of pane (structure, order).
    pub fn trace(&self, structure: usize, order: usize) -> Option<&Trace> {
        Some(&self.traces.get()?[structure][order])
    }

    /// What pane (structure, order) shows at the timeline's frame.
    pub fn pane_state(&self, structure: usize, order: usize) -> Option<TraceState> {
        let traces = self.traces.get()?;
        Some(traces[structure][order].state(self.stage.timeline.shown))
    }

    /// The counters every pane shows now, by structure then order.
    pub fn pane_counters(&self) -> Option<[[Counters; 2]; 2]> {
        let traces = self.traces.get()?;
        let frame = self.stage.timeline.shown;
        Some(
            [0, 1].map(|structure| {
                [0, 1].map(|order| traces[structure][order].state(frame).counters)
            }),
        )
    }

    /// Whether answer `question` is shown.
    pub fn revealed(&self, question: usize) -> bool {
        self.revealed[question]
    }

    fn pane_ui(
        &self,
        ui: &mut egui::Ui,
        (structure, order): (usize, usize),
        size: Vec2,
        view: &mut View2d,
    ) -> Canvas {
        let bounds = self.stage.scene.bounds();
        let canvas = Canvas::allocate(ui, size, view, &bounds, false);
        let (Some(trees), Some(traces)) = (self.trees.get(), self.traces.get()) else {
            return canvas;
        };
        let tree = &trees[structure];
        let trace = &traces[structure][order];
        let frame = self.stage.timeline.shown;
        let shown = trace.shown(frame);
        let state = trace.state(frame);
        draw_tested_shapes(ui, &canvas, &tree.shapes, shown, None);
        draw_tree(
            &canvas,
            tree,
            &TreeLook {
                steps: shown,
                structure_alpha: 90,
                ..TreeLook::default()
            },
        );
        if let Ok(ray) = self.stage.scene.ray() {
            draw_ray(&canvas, &ray, state.closest.map(|(_, t)| t));
        }
        self.stage.scene.draw_handles(&canvas);
        if let Some(note) = tree.limits_note() {
            canvas.note(&note);
        }
        let counters = state.counters;
        let progress = if state.done {
            ": done".to_owned()
        } else if frame >= trace.frames() {
            String::new()
        } else {
            format!(", step {frame} of {}", trace.frames())
        };
        canvas.caption(&[
            (
                format!(
                    "{}, {}{progress}",
                    FAMILIES[structure].label(),
                    ORDERS[order].1
                ),
                Color32::WHITE,
            ),
            (
                format!(
                    "nodes {}  boxes {}  tests {}  skipped {}",
                    counters.nodes_visited,
                    counters.box_tests,
                    counters.primitive_tests,
                    counters.nodes_culled
                ),
                Color32::WHITE,
            ),
        ]);
        canvas.finish();
        canvas
    }
}

impl Lesson for NearFirstLesson {
    crate::staged!(trees);

    fn update(&mut self) {
        let scene = &self.stage.scene;
        request_over_shapes(&mut self.trees, scene, (), |shapes, settings| {
            FAMILIES.map(|family| {
                SceneTree::build(
                    Structure::lecture(family, SplitRule::Sah),
                    shapes.clone(),
                    settings,
                )
            })
        });
        let Some(trees) = self.trees.get().cloned() else {
            return;
        };
        let traces = self
            .traces
            .get_or_make((self.trees.generation(), scene.revision), || {
                let ray = scene.ray().ok();
                [0, 1].map(|structure| {
                    ORDERS.map(|(order, _)| match &ray {
                        Some(ray) => Trace::of_tree(&trees[structure], ray, &options_in(order)),
                        None => Trace::default(),
                    })
                })
            });
        let frames = traces
            .iter()
            .flatten()
            .map(Trace::frames)
            .max()
            .unwrap_or(0);
        self.stage.timeline.set_len(frames);
    }

    fn caption(&self) -> Option<String> {
        let traces = self.traces.get()?;
        let frame = self.stage.timeline.shown;
        let describe = |structure: usize, order: usize| {
            let trace = &traces[structure][order];
            match trace.frame(frame).first() {
                Some(step) => describe_step(step, |node| format!("node {node}")),
                None if frame == 0 => "start".to_owned(),
                None => "done".to_owned(),
            }
        };
        Some(format!(
            "kD near first: {}  |  kD file order: {}",
            describe(0, 0),
            describe(0, 1)
        ))
    }

    /// A generated scene gets a ray from beyond its top right corner towards the lower left:
    /// against the order the builders store children in (below the plane, or the lower
    /// centroids, first), so file order meets the far side first and the lesson's point shows.
    fn place_generated_ray(&self, scene: &Scene2d) -> Option<(DVec2, DVec2)> {
        let bounds = scene.shapes.bounding_box();
        if bounds.is_empty() {
            return None;
        }
        let extent = bounds.extent();
        let origin = bounds.max + extent * 0.05;
        Some((
            origin,
            origin - DVec2::new(extent.x * 0.12, extent.y * 0.09),
        ))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        let (Some(counters), Some(traces)) = (self.pane_counters(), self.traces.get()) else {
            ui.label("Building…");
            return;
        };
        let frame = self.stage.timeline.shown;
        ui.heading("Counters so far");
        // A table keeps its columns: in a narrow panel (the app scaled up) it scrolls
        // sideways rather than widen the panel.
        egui::ScrollArea::horizontal()
            .id_salt("order counters columns")
            .show(ui, |ui| {
                egui::Grid::new("order counters")
                    .striped(true)
                    .show(ui, |ui| {
                        ui.label("");
                        for family in ["kD", "BVH"] {
                            for order in ["near", "file"] {
                                ui.strong(format!("{family} {order}"))
                                    .on_hover_text(format!("{family}, {order} order"));
                            }
                        }
                        ui.end_row();
                        for (name, value) in COUNTER_ROWS {
                            ui.label(name);
                            for row in &counters {
                                for pane in row {
                                    ui.label(value(pane).to_string());
                                }
                            }
                            ui.end_row();
                        }
                        // The hit and its t on rows of their own, so the columns stay as
                        // narrow as the counts and all four fit the inspector.
                        ui.label("closest hit so far");
                        for row in traces.iter() {
                            for trace in row {
                                ui.label(match trace.state(frame).closest {
                                    Some((primitive, _)) => format!("#{primitive}"),
                                    None if trace.state(frame).done => "none".to_owned(),
                                    None => "not yet".to_owned(),
                                });
                            }
                        }
                        ui.end_row();
                        ui.label("at t");
                        for row in traces.iter() {
                            for trace in row {
                                ui.label(
                                    trace
                                        .state(frame)
                                        .closest
                                        .map_or_else(|| "–".to_owned(), |(_, t)| number(t)),
                                );
                            }
                        }
                        ui.end_row();
                    });
            });
        if traces.iter().flatten().all(|trace| trace.state(frame).done) {
            let total = |structure: usize, order: usize| {
                accelviz_core::counters_of(&traces[structure][order].steps).nodes_visited
            };
            ui.label(format!(
                "Done. Nodes visited, near first against file order: kD-tree {} against {}, BVH {} against {}.",
                total(0, 0),
                total(0, 1),
                total(1, 0),
                total(1, 1)
            ));
        }
        ui.separator();
        ui.heading("Quiz");
        for (index, (question, answer)) in QUESTIONS.iter().enumerate() {
            ui.label(RichText::new(*question).strong());
            let label = if self.revealed[index] {
                "hide the answer"
            } else {
                "show the answer"
            };
            if ui.button(label).clicked() {
                self.revealed[index] = !self.revealed[index];
            }
            if self.revealed[index] {
                ui.label(*answer);
            }
        }
        ui.label(
            RichText::new(format!(
                "Think first, then play the four panes ({} steps) and compare the counters.",
                count(self.stage.timeline.len)
            ))
            .small()
            .weak(),
        );
        t_hint_ui(ui);
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.stage.scene.toolbar_ui(ui);
        let size = ui.available_size();
        let gap = 6.0;
        let pane_size = Vec2::new((size.x - gap) * 0.5, (size.y - gap) * 0.5);
        let mut view = self.stage.scene.view;
        let mut canvases = Vec::new();
        ui.spacing_mut().item_spacing = Vec2::splat(gap);
        for structure in 0..2 {
            ui.horizontal(|ui| {
                for order in 0..2 {
                    canvases.push(self.pane_ui(ui, (structure, order), pane_size, &mut view));
                }
            });
        }
        self.stage.scene.view = view;
        for canvas in &canvases {
            self.stage.scene.interact(ui, canvas);
        }
        if let Some(canvas) = canvases.first() {
            building_note(
                ui,
                canvas,
                self.trees.working_for(),
                "the kD-tree and the BVH",
            );
        }
        if let Some(canvas) = canvases.last() {
            self.stage.scene.draw_footer(canvas);
        }
    }
}
