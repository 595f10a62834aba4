//! Lesson 6, the lecture's quiz: "Why first do near side? What happens if we just traverse in
//! file order?" The slide asks it of the kD-tree traversal; the lesson shows it on a kD-tree
//! and on a BVH of the same scene, each traced near side first and in file order: four panes
//! stepping in lockstep through the one traversal of each kind (`Order::NearFirst` against
//! `Order::FileOrder`), under the slide's own rule by default (`Query::FirstInCell`: the far
//! side only `If(no intersection)`, each leaf against the ray clipped to its cell), or culling
//! by the closest hit (`Query::Closest`). Everything shown part-way is the state at that step:
//! the counters are the core's, replayed; the closest hit is the closest so far. The answers
//! stay hidden until asked for.

use accelviz_core::format::{count, number};
use accelviz_core::{Counters, Family, Order, Query, SplitRule, Structure, TraceOptions};
use accelviz_scene::document::Scene2d;
use egui::{Color32, RichText, Vec2};
use glam::DVec2;

use crate::background::{Cached, Derived};
use crate::canvas::{Canvas, View2d};
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage, request_over_shapes};
use crate::trace::{Trace, TraceState, describe_step};
use crate::views::scene_view::{building_note, draw_ray, draw_tested_shapes, t_hint_ui};
use crate::views::tree_view::{TreeLook, draw_tree};

/// The two orders, in column order.
pub const ORDERS: [(Order, &str); 2] = [
    (Order::NearFirst, "near side first"),
    (Order::FileOrder, "file order"),
];

/// The two structures, in row order: the slide's kD-tree, then a BVH.
pub const FAMILIES: [Family; 2] = [Family::Kd, Family::Bvh];

/// The rules the panes can follow: the slide's pseudo-code, and the variant that culls by the
/// closest hit. Its query, its name in a shared link, its label, and what it does.
pub const RULES: [(Query, &str, &str, &str); 2] = [
    (
        Query::FirstInCell,
        "slide",
        "the slide's: stop at the first intersection",
        "The pseudo-code as the slide writes it: a leaf's shapes are tested against the ray clipped to its cell, and the far side is searched only `If(no intersection)` in the near side. The first leaf with an intersection ends the search.",
    ),
    (
        Query::Closest,
        "cull",
        "cull by the closest hit",
        "A variant: every side is searched, unless it starts beyond the closest hit found so far. Both orders then find the closest hit; file order pays in work.",
    ),
];

/// The key of the rule in a shared link.
const RULE: &str = "rule";

/// The quiz's questions and answers.
const QUESTIONS: [(&str, &str); 2] = [
    (
        "Why first do the near side?",
        "Along the ray the near side's part comes first, so a hit found there lies before anything on the far side. With the slide's `If(no intersection)` the search then ends and the far side is never opened: through a kD-tree's cells, which do not overlap, near first finds the closest hit and does the least work. (Culling by the closest hit instead, every cell or box starting beyond the hit is skipped unopened, and near first finds it earliest, so the most is skipped.)",
    ),
    (
        "What happens if we just traverse in file order?",
        "The order in memory has nothing to do with the ray: file order opens the far side first whenever the ray runs against it. With the slide's `If(no intersection)`, a hit there ends the search, so file order can return a hit that is not the closest: the kD file-order pane shows whether it does on this ray. Culling by the closest hit instead (the rule switch above the counters), every waiting side is still searched unless it starts beyond the hit, so both orders find the same hit and file order pays for it in wasted work. Near first never depends on luck. (A BVH's boxes overlap, so under the slide's rule even near first may stop at a hit that is not the closest.)",
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
    traces: Cached<(u64, u64, Query), [[Trace; 2]; 2]>,
    /// The rule the panes follow ([`RULES`]).
    rule: Query,
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
            rule: RULES[0].0,
            revealed: [false; 2],
        }
    }

    /// The rule the panes follow.
    pub fn rule(&self) -> Query {
        self.rule
    }

    /// Makes the panes follow `rule` (one of [`RULES`]).
    pub fn set_rule(&mut self, rule: Query) {
        self.rule = rule;
    }

    /// What the panes trace with: `order`, under the lesson's rule.
    pub fn options(&self, order: Order) -> TraceOptions {
        TraceOptions {
            order,
            query: self.rule,
            ..TraceOptions::default()
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
        let options = ORDERS.map(|(order, _)| self.options(order));
        let traces =
            self.traces
                .get_or_make((self.trees.generation(), scene.revision, self.rule), || {
                    let ray = scene.ray().ok();
                    [0, 1].map(|structure| {
                        options.map(|options| match &ray {
                            Some(ray) => Trace::of_tree(&trees[structure], ray, &options),
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

    fn share(&self) -> Vec<(String, String)> {
        let name = RULES
            .iter()
            .find(|(rule, ..)| *rule == self.rule)
            .map_or("slide", |(_, name, ..)| name);
        vec![(RULE.into(), name.into())]
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        if key != RULE {
            return Err(format!("this lesson keeps no '{key}'"));
        }
        let (rule, ..) = RULES
            .iter()
            .find(|(_, name, ..)| *name == value)
            .ok_or_else(|| format!("rule '{value}' is not one of slide, cull"))?;
        self.rule = *rule;
        Ok(())
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
        ui.horizontal_wrapped(|ui| {
            ui.label("Rule:");
            for (rule, _, label, what) in RULES {
                ui.selectable_value(&mut self.rule, rule, label)
                    .on_hover_text(what);
            }
        });
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
            ui.label(done_summary(traces));
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

/// What the four traversals did, once all are done: the work near first against file order,
/// and whether file order returned the closest hit.
fn done_summary(traces: &[[Trace; 2]; 2]) -> String {
    let mut lines = Vec::new();
    for (structure, family) in ["kD-tree", "BVH"].into_iter().enumerate() {
        let [near, file] = &traces[structure];
        let nodes = |trace: &Trace| accelviz_core::counters_of(&trace.steps).nodes_visited;
        let hit = |trace: &Trace| crate::trace::closest_so_far(&trace.steps);
        let named = |hit: Option<(u32, f64)>| match hit {
            Some((primitive, t)) => format!("#{primitive} at t = {}", number(t)),
            None => "no hit".to_owned(),
        };
        let returned = if hit(near) == hit(file) {
            format!("both return {}", named(hit(near)))
        } else {
            format!(
                "near first returns {}, file order {}",
                named(hit(near)),
                named(hit(file))
            )
        };
        lines.push(format!(
            "{family}: {} nodes near first against {} in file order; {returned}.",
            nodes(near),
            nodes(file)
        ));
    }
    format!("Done. {}", lines.join(" "))
}
