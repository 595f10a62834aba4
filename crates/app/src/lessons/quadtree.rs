//! Lesson 20, "The quadtree": the lecture names octrees and quad trees beside its kD-trees.
//! A quadtree cuts a cell at its middle along both axes at once into four equal children,
//! until a cell holds at most the leaf size or reaches the depth limit. The build is stepped
//! from the builder's own report (a `BuildRecorder`), the traversal from the core's, front to
//! back in the order the ray's direction sets (Revelles, Ureña & Lastra 2000); beside it the
//! kD-tree of lesson 5 on the same scene, and both measured on the same rays.

use std::sync::Arc;

use accelviz_core::format::{count, number};
use accelviz_core::{BuildRecorder, BuildStep, Order, Step, Structure, TraceOptions, TreeFacts};
use accelviz_scene::document::SceneSettings;
use egui::{Color32, RichText, Stroke, Vec2};
use glam::DVec2;

use crate::background::{Cached, Derived};
use crate::canvas::{Canvas, View2d, faded, palette};
use crate::editor::Editing;
use crate::lesson::{self, Lesson, Parts};
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage, request_over_shapes};
use crate::trace::{Trace, describe_step};
use crate::views::compare::Comparison;
use crate::views::scene_view::{
    building_note, draw_ray, draw_shapes, draw_tested_shapes, number_shapes,
};
use crate::views::tree_view::{TreeLook, draw_tree, node_outline};

/// What the timeline steps through.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// The build, node by node, as the builder reported it.
    Build,
    /// The ray's traversal.
    Traverse,
}

/// The kD-trees it can stand beside.
pub const KD_CHOICES: [Structure; 2] = [Structure::KdMiddle, Structure::KdSah];

/// The inspector's parts a lecture slide can name.
const BUILD_PART: lesson::Part = lesson::Part::new(
    "build",
    "build or traverse, the leaf size and the kD-tree beside",
);
const NUMBERS_PART: lesson::Part = lesson::Part::new(
    "numbers",
    "the quadtree against the kD-tree, measured on the same rays",
);
const PARTS: [lesson::Part; 2] = [BUILD_PART, NUMBERS_PART];

/// The quadrants' names by child number: bit 0 the x half (east above the middle), bit 1 the
/// y half (north).
pub const QUADRANTS: [&str; 4] = ["SW", "SE", "NW", "NE"];

/// A node's name: `root`, or its quadrants from the root down (`NE·SW`).
pub fn quadrant_path(facts: &TreeFacts<DVec2>, node: u32) -> String {
    let mut names = Vec::new();
    let mut current = node;
    while let Some(parent) = facts.parent.get(current as usize).copied().flatten() {
        let index = facts.children[parent as usize]
            .and_then(|children| children.position(current))
            .unwrap_or(0);
        names.push(QUADRANTS.get(index).copied().unwrap_or("?"));
        current = parent;
    }
    if names.is_empty() {
        return "root".to_owned();
    }
    names.reverse();
    names.join("·")
}

/// The quadtree with its builder's report, and the kD-tree beside it, both measured.
pub struct RecordedQuadtree {
    /// What the builder reported, step by step.
    pub steps: Vec<BuildStep>,
    /// The quadtree (pane 0) and the kD-tree (pane 1) on the same rays.
    pub comparison: Comparison,
}

impl RecordedQuadtree {
    /// The quadtree.
    pub fn tree(&self) -> &SceneTree {
        &self.comparison.trees[0]
    }

    /// The kD-tree beside it.
    pub fn kd_tree(&self) -> &SceneTree {
        &self.comparison.trees[1]
    }
}

/// The quadtree with the scene's leaf size.
pub fn quadtree_structure(settings: &SceneSettings) -> Structure {
    Structure::Octree {
        leaf: settings.max_leaf_size.clamp(1, u16::MAX as usize) as u16,
    }
}

/// The lesson.
pub struct QuadtreeLesson {
    stage: Stage,
    mode: Mode,
    kd: Structure,
    build: Derived<(u64, Structure), RecordedQuadtree>,
    trace: Cached<(u64, u64), Trace>,
    kd_trace: Cached<(u64, u64), Trace>,
}

impl QuadtreeLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::ALL),
            mode: Mode::Build,
            kd: Structure::KdMiddle,
            build: Derived::default(),
            trace: Cached::default(),
            kd_trace: Cached::default(),
        }
    }

    /// The recorded build, with the kD-tree beside it.
    pub fn recorded(&self) -> Option<&Arc<RecordedQuadtree>> {
        self.build.get()
    }

    /// The recorded traversal.
    pub fn trace(&self) -> Option<&Trace> {
        self.trace.get()
    }

    /// What the timeline steps through.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Steps through `mode` from its start.
    pub fn set_mode(&mut self, mode: Mode) {
        self.mode = mode;
        self.stage.timeline.rewind();
    }

    /// The build steps shown.
    fn shown_steps(&self) -> &[BuildStep] {
        let steps = self.build.get().map_or(&[][..], |build| &build.steps);
        &steps[..self.stage.timeline.shown.min(steps.len())]
    }

    /// The build's step `step` in words.
    fn describe_build(&self, build: &RecordedQuadtree, step: &BuildStep) -> String {
        let facts = &build.tree().built.facts;
        let name = |node: u32| quadrant_path(facts, node);
        let leaf = build.tree().settings.max_leaf_size;
        match *step {
            BuildStep::NodeStarted {
                node,
                depth,
                primitive_count,
            } => format!(
                "Cell {} (depth {depth}) reaches {}",
                name(node),
                accelviz_core::format::counted(primitive_count, "primitive", "primitives")
            ),
            BuildStep::Split { node, children, .. } => {
                let cuts = build.tree().built.cuts(node);
                let lines: Vec<String> = cuts
                    .iter()
                    .map(|&(axis, position)| {
                        format!("{} = {}", ["x", "y"][axis.min(1)], number(position))
                    })
                    .collect();
                format!(
                    "More than {leaf} (the leaf size): cut {} at its middle, {}, into {} equal cells; each primitive goes to every cell it reaches",
                    name(node),
                    lines.join(" and "),
                    children.len()
                )
            }
            BuildStep::Leaf { node, reason } => format!("Cell {} is a leaf: {reason}", name(node)),
            BuildStep::Sorted { node, .. }
            | BuildStep::Swept { node, .. }
            | BuildStep::ListsDivided { node } => format!("cell {}", name(node)),
        }
    }

    fn build_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.label("Step through");
            for (mode, name) in [
                (Mode::Build, "the build"),
                (Mode::Traverse, "the traversal"),
            ] {
                if ui.selectable_label(self.mode == mode, name).clicked() {
                    self.set_mode(mode);
                }
            }
        });
        let mut leaf_size = self.stage.scene.scene.settings.max_leaf_size;
        if ui
            .add(egui::Slider::new(&mut leaf_size, 1..=8).text("max leaf size"))
            .on_hover_text("A cell holding more is cut (within the depth limit); both trees use it")
            .changed()
        {
            self.stage.scene.scene.settings.max_leaf_size = leaf_size;
            self.stage.scene.touch();
            self.stage.timeline.rewind();
        }
        ui.horizontal_wrapped(|ui| {
            ui.label("Beside it:");
            for structure in KD_CHOICES {
                let entry = structure.entry();
                if ui
                    .selectable_label(self.kd == structure, format!("{} kD-tree", entry.label))
                    .on_hover_text(entry.about)
                    .clicked()
                {
                    self.kd = structure;
                }
            }
        });
    }

    fn numbers_ui(&self, ui: &mut egui::Ui) {
        let Some(comparison) = self.build.get().map(|build| &build.comparison) else {
            ui.label("Measuring…");
            return;
        };
        egui::ScrollArea::horizontal()
            .id_salt("quadtree numbers")
            .show(ui, |ui| {
                egui::Grid::new("quadtree against kd")
                    .striped(true)
                    .show(ui, |ui| {
                        ui.label("");
                        ui.strong("quadtree");
                        ui.strong(format!("{} kD-tree", self.kd.entry().label));
                        ui.end_row();
                        type Figure = fn(&Comparison, usize) -> String;
                        let rows: [(&str, Figure); 7] = [
                            ("nodes", |c, pane| count(c.trees[pane].stats.node_count)),
                            ("leaves (empty)", |c, pane| {
                                let stats = &c.trees[pane].stats;
                                format!(
                                    "{} ({})",
                                    count(stats.leaf_count),
                                    count(stats.empty_leaf_count)
                                )
                            }),
                            ("depth", |c, pane| c.trees[pane].stats.max_depth.to_string()),
                            ("references per primitive", |c, pane| {
                                format!("{:.2}", c.measured(pane).references_per_primitive)
                            }),
                            ("cells visited per ray", |c, pane| {
                                format!("{:.1}", c.measured(pane).nodes_per_ray)
                            }),
                            ("primitive tests per ray", |c, pane| {
                                format!("{:.1}", c.measured(pane).tests_per_ray)
                            }),
                            ("cost per ray", |c, pane| {
                                number(c.measured(pane).cost_per_ray)
                            }),
                        ];
                        for (name, figure) in rows {
                            ui.label(name);
                            for pane in 0..2 {
                                ui.label(figure(comparison, pane));
                            }
                            ui.end_row();
                        }
                    });
            });
        ui.label(
            RichText::new(format!(
                "Measured on {} seeded rays through the scene; cost = C_trav · cells + C_isect · tests. A quadtree node is one cut along each axis at once, at the middle whatever the cell holds: it cannot move a cut to where the primitives are, as the SAH kD-tree does, nor cut only the axis that pays.",
                comparison.ray_count
            ))
            .small()
            .weak(),
        );
    }

    /// The build so far on `canvas`: the cuts made, the leaves finished (blue, grey when
    /// empty), the current cell and what reaches it lit.
    fn draw_build(&self, ui: &egui::Ui, canvas: &Canvas, build: &RecordedQuadtree) {
        let tree = build.tree();
        let facts = &tree.built.facts;
        let shown = self.shown_steps();
        let current = shown.last().map(BuildStep::node);
        // What reaches the current cell, as a mask: a lookup per shape drawn, not a search.
        let mut lit = vec![false; tree.shapes.shapes.len()];
        for primitive in current.map_or_else(Vec::new, |node| tree.built.primitives_below(node)) {
            if let Some(entry) = lit.get_mut(primitive as usize) {
                *entry = true;
            }
        }
        draw_shapes(ui, canvas, &tree.shapes, |index| {
            lit[index].then_some(palette::CURRENT)
        });
        canvas.box_outline(
            &tree.built.root_bounds(),
            Stroke::new(1.5, canvas.depth_color(0)),
            None,
        );
        for step in shown {
            match *step {
                BuildStep::Split { node, .. } => {
                    let color = canvas.depth_color(facts.depth[node as usize] as usize + 1);
                    for (axis, position) in tree.built.cuts(node) {
                        canvas.split_line(
                            &facts.bounds[node as usize],
                            axis,
                            position,
                            Stroke::new(2.0, color),
                        );
                    }
                }
                BuildStep::Leaf { node, .. } => {
                    let empty = facts.leaf_sizes[node as usize] == 0;
                    let fill = if empty {
                        faded(Color32::GRAY, 30)
                    } else {
                        faded(palette::BOX, 35)
                    };
                    node_outline(canvas, tree, node, Stroke::NONE, Some(fill));
                }
                _ => {}
            }
        }
        if let Some(node) = current {
            node_outline(canvas, tree, node, Stroke::new(3.5, palette::CURRENT), None);
            let bounds = facts.bounds[node as usize];
            canvas.label(bounds.max, &quadrant_path(facts, node), palette::CURRENT);
        }
        number_shapes(ui, canvas, &tree.shapes);
    }

    /// The traversal so far: the tree, the tested shapes, the current cell with its part of
    /// the ray, and the children's order (1, 2, …) where the step orders them.
    fn draw_traversal(&self, ui: &egui::Ui, canvas: &Canvas, tree: &SceneTree, trace: &Trace) {
        let frame = self.stage.timeline.shown;
        let shown = trace.shown(frame);
        let current_primitive = match trace.frame(frame).first() {
            Some(Step::PrimitiveTested { primitive, .. }) => Some(*primitive),
            _ => None,
        };
        fill_entered_leaves(canvas, tree, shown);
        draw_tested_shapes(ui, canvas, &tree.shapes, shown, current_primitive);
        draw_tree(canvas, tree, &TreeLook::default());
        if let Some(Step::ChildrenOrdered { order, count, .. }) = trace.frame(frame).last() {
            for (place, &child) in order[..*count as usize].iter().enumerate() {
                node_outline(canvas, tree, child, Stroke::new(2.5, palette::HIT), None);
                let bounds = tree.built.facts.bounds[child as usize];
                canvas.label(bounds.center(), &(place + 1).to_string(), palette::HIT);
            }
        }
        if let Some(Step::CellEntered {
            node,
            t_near,
            t_far,
        }) = trace.frame(frame).first()
            && let Ok(ray) = self.stage.scene.ray()
        {
            node_outline(
                canvas,
                tree,
                *node,
                Stroke::new(3.5, palette::CURRENT),
                None,
            );
            canvas.ray_mark(
                ray.origin,
                ray.direction,
                *t_near,
                palette::CURRENT,
                "",
                0.0,
            );
            canvas.ray_mark(ray.origin, ray.direction, *t_far, palette::CURRENT, "", 0.0);
        }
        number_shapes(ui, canvas, &tree.shapes);
    }

    /// The kD-tree beside: its cells, and the leaves its traversal of the same ray entered.
    fn draw_kd(&self, ui: &egui::Ui, canvas: &Canvas, tree: &SceneTree) {
        let trace = self.kd_trace.get().cloned().unwrap_or_default();
        fill_entered_leaves(canvas, tree, &trace.steps);
        draw_tested_shapes(ui, canvas, &tree.shapes, &trace.steps, None);
        draw_tree(canvas, tree, &TreeLook::default());
        if let Ok(ray) = self.stage.scene.ray() {
            draw_ray(canvas, &ray, trace.hit.map(|hit| hit.t));
        }
        number_shapes(ui, canvas, &tree.shapes);
        let counters = accelviz_core::counters_of(&trace.steps);
        canvas.caption(&[
            (
                format!("{} kD-tree, the same ray", self.kd.entry().label),
                Color32::WHITE,
            ),
            (
                format!(
                    "{} cells entered, {}",
                    counters.nodes_visited,
                    accelviz_core::format::counted(
                        counters.primitive_tests as usize,
                        "primitive test",
                        "primitive tests"
                    )
                ),
                Color32::WHITE,
            ),
        ]);
    }
}

impl Lesson for QuadtreeLesson {
    crate::staged!(build);

    fn share(&self) -> Vec<(String, String)> {
        let mode = match self.mode {
            Mode::Build => "build",
            Mode::Traverse => "traverse",
        };
        vec![
            ("mode".into(), mode.into()),
            crate::share::structure_value(&self.kd),
        ]
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        match (key, value) {
            ("mode", "build") => self.mode = Mode::Build,
            ("mode", "traverse") => self.mode = Mode::Traverse,
            ("mode", _) => return Err(format!("mode '{value}' is not build or traverse")),
            ("structure", _) => {
                let structure = crate::share::parse_structure(value)?;
                if !KD_CHOICES.contains(&structure) {
                    return Err(format!(
                        "'{value}' is not a kD-tree this lesson stands beside"
                    ));
                }
                self.kd = structure;
            }
            _ => return Err(format!("this lesson keeps no '{key}'")),
        }
        Ok(())
    }

    fn update(&mut self) {
        let scene = &self.stage.scene;
        let kd = self.kd;
        request_over_shapes(&mut self.build, scene, kd, move |shapes, settings| {
            let mut recorder = BuildRecorder::default();
            let quadtree = SceneTree::build_observed(
                quadtree_structure(&settings),
                shapes.clone(),
                settings,
                &mut recorder,
            );
            let kd_tree = SceneTree::build(kd, shapes, settings);
            RecordedQuadtree {
                steps: recorder.steps,
                comparison: Comparison::of_trees(vec![quadtree, kd_tree]),
            }
        });
        let options = TraceOptions {
            order: Order::NearFirst,
            ..TraceOptions::default()
        };
        if let Some(build) = self.build.get().cloned() {
            let trace = self
                .trace
                .get_or_make((self.build.generation(), scene.revision), || {
                    match scene.ray() {
                        Ok(ray) => Trace::of_tree(build.tree(), &ray, &options),
                        Err(_) => Trace::default(),
                    }
                });
            let frames = match self.mode {
                Mode::Build => build.steps.len(),
                Mode::Traverse => trace.frames(),
            };
            self.stage.timeline.set_len(frames);
        }
        if let Some(build) = self.build.get().cloned() {
            self.kd_trace
                .get_or_make((self.build.generation(), scene.revision), || {
                    match scene.ray() {
                        Ok(ray) => Trace::of_tree(build.kd_tree(), &ray, &options),
                        Err(_) => Trace::default(),
                    }
                });
        }
    }

    fn caption(&self) -> Option<String> {
        let build = self.build.get()?;
        let frame = self.stage.timeline.shown;
        match self.mode {
            Mode::Build => {
                let Some(step) = self.shown_steps().last() else {
                    return Some("Press step: the builder starts at the root, the box around every primitive.".to_owned());
                };
                let said = self.describe_build(build, step);
                Some(if frame >= build.steps.len() {
                    let stats = &build.tree().stats;
                    format!(
                        "{said}. Done: {} nodes, {} leaves ({} empty), depth {}, {} references for {} primitives.",
                        count(stats.node_count),
                        count(stats.leaf_count),
                        count(stats.empty_leaf_count),
                        stats.max_depth,
                        count(stats.primitive_references),
                        count(build.tree().shapes.shapes.len())
                    )
                } else {
                    said
                })
            }
            Mode::Traverse => {
                let trace = self.trace.get()?;
                let facts = &build.tree().built.facts;
                Some(
                    trace.caption(frame, "Press step: the ray enters the root cell.", |step| {
                        describe_step(step, |node| quadrant_path(facts, node))
                    }),
                )
            }
        }
    }

    fn parts(&self) -> &'static [lesson::Part] {
        &PARTS
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, parts: Parts<'_>) {
        if parts.show(&BUILD_PART) {
            self.build_ui(ui);
        }
        if parts.show(&NUMBERS_PART) {
            ui.separator();
            self.numbers_ui(ui);
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.stage.scene.toolbar_ui(ui);
        let gap = 6.0;
        let size = ui.available_size();
        let width = ((size.x - gap) * 0.5).max(50.0);
        let bounds = self.stage.scene.bounds();
        let mut view: View2d = self.stage.scene.view;
        let (main, side) = ui
            .horizontal(|ui| {
                ui.spacing_mut().item_spacing.x = gap;
                let main =
                    Canvas::allocate(ui, Vec2::new(width, size.y), &mut view, &bounds, false);
                let side =
                    Canvas::allocate(ui, Vec2::new(width, size.y), &mut view, &bounds, false);
                (main, side)
            })
            .inner;
        self.stage.scene.view = view;
        if let Some(build) = self.build.get().cloned() {
            match self.mode {
                Mode::Build => self.draw_build(ui, &main, &build),
                Mode::Traverse => {
                    let trace = self.trace.get().cloned().unwrap_or_default();
                    self.draw_traversal(ui, &main, build.tree(), &trace);
                    if let Ok(ray) = self.stage.scene.ray() {
                        let shown = trace.shown(self.stage.timeline.shown);
                        draw_ray(
                            &main,
                            &ray,
                            crate::trace::closest_so_far(shown).map(|(_, t)| t),
                        );
                    }
                }
            }
            main.caption(&[(
                match self.mode {
                    Mode::Build => "quadtree: the build, step by step".to_owned(),
                    Mode::Traverse => "quadtree: front to back, step by step".to_owned(),
                },
                Color32::WHITE,
            )]);
        }
        if let Some(build) = self.build.get().cloned() {
            self.draw_kd(ui, &side, build.kd_tree());
        }
        building_note(ui, &main, self.build.working_for(), "the quadtree");
        for canvas in [&main, &side] {
            self.stage.scene.interact(ui, canvas);
            self.stage.scene.draw_handles(canvas);
        }
        self.stage.scene.draw_footer(&side);
        main.finish();
        side.finish();
    }
}

/// The leaf cells a traversal has entered in `steps`, filled faintly.
fn fill_entered_leaves(canvas: &Canvas, tree: &SceneTree, steps: &[Step<f64>]) {
    for step in steps {
        if let Step::CellEntered { node, .. } = *step
            && tree.built.facts.is_leaf(node)
        {
            node_outline(
                canvas,
                tree,
                node,
                Stroke::NONE,
                Some(faded(palette::CURRENT, 30)),
            );
        }
    }
}
