//! Lesson 5, "kD-Tree" and "Traversing a kD-tree": split lines and cells, and the core's kD
//! traversal stepped with the line of the lecture's pseudo-code it is on. Each frame is read
//! once into a [`KdStepView`]: which code lines run, which cell and which parent plane the
//! call is about, which part of the ray it clips (rayNear, rayFar), and its words. The canvas,
//! the code panel and the status line all draw that one view, so they always tell the same
//! step. A straddling primitive tested twice is said to be, and the mailbox switch shows the
//! test it saves.

use std::sync::Arc;

use accelviz_core::format::{count, number};
use accelviz_core::{CATALOGUE, Family, Order, Ray, SlabRay, Step, Structure, TraceOptions};
use egui::{Color32, RichText, Stroke};
use glam::DVec2;

use crate::background::{Cached, Derived};
use crate::canvas::{Canvas, faded, palette};
use crate::editor::Editing;
use crate::lesson::{self, Lesson, Parts};
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage, request_tree};
use crate::trace::Trace;
use crate::views::scene_view::{building_note, draw_ray, draw_tested_shapes, t_hint_ui};
use crate::views::tree_diagram::diagram_ui;
use crate::views::tree_view::{TreeLook, draw_tree, node_outline, node_under};

/// The lecture's pseudo-code, line by line.
pub const PSEUDO_CODE: [&str; 9] = [
    "intersectKDTree(ray, node)",
    "  If empty(ray) return",
    "  If isLeaf(node) intersectObjects(node.objects, ray)",
    "  else",
    "    rayNear = Clip ray to near side of the split",
    "    intersectKDTree(rayNear, nearChild(node, ray))",
    "    If(no intersection)",
    "      rayFar = Clip ray to far side of the plane",
    "      intersectKDTree(rayFar, farChild(node, ray))",
];

/// The inspector's parts a lecture slide can name.
const BUILD_PART: lesson::Part =
    lesson::Part::new("build", "the kD build, leaf size and mailboxing");
const CODE_PART: lesson::Part =
    lesson::Part::new("code", "the traversal's pseudo-code, the step's lines lit");
const TREE_PART: lesson::Part = lesson::Part::new("tree", "the tree's numbers and diagram");
const PARTS: [lesson::Part; 3] = [BUILD_PART, CODE_PART, TREE_PART];

/// The monospace size at which the longest line of [`PSEUDO_CODE`] fits `width`: the style's
/// size where it fits, else smaller, but not under three quarters of it.
fn code_size(ui: &egui::Ui, width: f32) -> f32 {
    let style_size = egui::TextStyle::Monospace.resolve(ui.style()).size;
    let font = egui::FontId::monospace(style_size);
    let widest = PSEUDO_CODE
        .iter()
        .map(|line| {
            ui.fonts_mut(|fonts| {
                fonts
                    .layout_no_wrap((*line).to_owned(), font.clone(), Color32::WHITE)
                    .size()
                    .x
            })
        })
        .fold(0.0, f32::max);
    if widest <= width || widest <= 0.0 {
        style_size
    } else {
        (style_size * width / widest).max(0.75 * style_size)
    }
}

/// The colour of the part of the ray on the near side, and on the far side.
const NEAR_COLOR: Color32 = Color32::from_rgb(80, 170, 255);
const FAR_COLOR: Color32 = Color32::from_rgb(200, 120, 255);

/// Which part of the ray a call has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The ray clipped to the root cell.
    Root,
    /// rayNear.
    Near,
    /// rayFar.
    Far,
}

/// What one frame of the kD traversal is, read once for every panel.
#[derive(Clone, Debug, PartialEq)]
pub struct KdStepView {
    /// The pseudo-code lines that run.
    pub lines: Vec<usize>,
    /// The step in words.
    pub text: String,
    /// The cell the call is about.
    pub cell: Option<u32>,
    /// The node whose plane the call clips at (the cell's parent).
    pub plane_of: Option<u32>,
    /// The part of the ray the call has: `[t_near, t_far]` and which part it is.
    pub segment: Option<(f64, f64, Part)>,
    /// Whether the call finds nothing to do (an empty part, a skipped far side).
    pub returns_at_once: bool,
}

/// Which part of the ray child `node` gets: near when the ray meets it first (by the sign of
/// the ray's direction across the parent's plane, as the traversal decides).
fn part_of(tree: &SceneTree, node: u32, ray: &Ray<DVec2>) -> (Option<u32>, Part) {
    let facts = &tree.built.facts;
    let Some(parent) = facts.parent[node as usize] else {
        return (None, Part::Root);
    };
    let Some((axis, _)) = tree.built.plane(parent) else {
        return (Some(parent), Part::Near);
    };
    let negative = SlabRay::new(ray, false).negative[axis];
    let below = facts.children[parent as usize].is_some_and(|children| children.first == node);
    (
        Some(parent),
        if below != negative {
            Part::Near
        } else {
            Part::Far
        },
    )
}

/// The plane of `node` in words: `x = 52.00`.
fn plane_text(tree: &SceneTree, node: u32) -> String {
    match tree.built.plane(node) {
        Some((axis, position)) => format!("{} = {}", ["x", "y"][axis.min(1)], number(position)),
        None => format!("node {}", node_name(tree, node)),
    }
}

/// What a frame's new closest hit means to the pseudo-code, said after the test that found
/// it (the two are one frame): an intersection in the cell's part of the ray, so the search
/// ends with this leaf.
fn search_ends(frame: &[Step<f64>]) -> String {
    frame
        .iter()
        .find_map(|step| match *step {
            Step::ClosestHitUpdated { t, .. } => Some(format!(
                ". An intersection in this cell's part of the ray (the closest so far, t = {}): once this leaf is done the search ends, and every far side still waiting is skipped, since If (no intersection) is false",
                number(t)
            )),
            _ => None,
        })
        .unwrap_or_default()
}

/// A node's name as the quiz and the 3D lessons give it: its path from the root (`LRL`), or
/// `root`.
fn node_name(tree: &SceneTree, node: u32) -> String {
    match tree.built.facts.path_to(node) {
        path if path.is_empty() => "root".to_owned(),
        path => path,
    }
}

/// Reads frame `frame` of `trace` into the one view every panel draws.
pub fn step_view(trace: &Trace, frame: usize, tree: &SceneTree, ray: &Ray<DVec2>) -> KdStepView {
    let blank = KdStepView {
        lines: Vec::new(),
        text: String::new(),
        cell: None,
        plane_of: None,
        segment: None,
        returns_at_once: false,
    };
    let Some(step) = trace.frame(frame).first().copied() else {
        return KdStepView {
            text: "Press step: intersectKDTree(ray, root) begins.".to_owned(),
            ..blank
        };
    };
    let shown = trace.shown(frame);
    // The leaf being searched, the last cell entered, and its part of the ray.
    let (leaf, part) = shown
        .iter()
        .rev()
        .find_map(|step| match *step {
            Step::CellEntered {
                node,
                t_near,
                t_far,
            } => Some((Some(node), Some((t_near, t_far)))),
            _ => None,
        })
        .unwrap_or((None, None));
    let leaf_name = leaf.map_or("?".to_owned(), |leaf| node_name(tree, leaf));
    match step {
        Step::BoxTested {
            t_enter,
            t_exit,
            hit,
            ..
        } => KdStepView {
            lines: if hit { vec![0] } else { vec![0, 1] },
            text: if hit {
                format!(
                    "intersectKDTree(ray, root): the ray clipped to the root cell is t in [{}, {}], not empty",
                    number(t_enter),
                    number(t_exit)
                )
            } else {
                "intersectKDTree(ray, root): the ray misses the root cell, so empty(ray): return"
                    .to_owned()
            },
            cell: Some(0),
            segment: hit.then_some((t_enter, t_exit, Part::Root)),
            returns_at_once: !hit,
            ..blank
        },
        Step::CellEntered {
            node,
            t_near,
            t_far,
        } => {
            let (parent, part) = part_of(tree, node, ray);
            let what = if tree.built.facts.is_leaf(node) {
                "a leaf: intersectObjects next"
            } else {
                "split again"
            };
            let (lines, text) = match (parent, part) {
                (Some(parent), Part::Near) => (
                    vec![4, 5],
                    format!(
                        "at {}: rayNear = t in [{}, {}]; intersectKDTree(rayNear, nearChild = node {}), {what}",
                        plane_text(tree, parent),
                        number(t_near),
                        number(t_far),
                        node_name(tree, node)
                    ),
                ),
                (Some(parent), Part::Far) => (
                    vec![6, 7, 8],
                    format!(
                        "at {}: no intersection in the near side, so rayFar = t in [{}, {}]; intersectKDTree(rayFar, farChild = node {}), {what}",
                        plane_text(tree, parent),
                        number(t_near),
                        number(t_far),
                        node_name(tree, node)
                    ),
                ),
                _ => (
                    vec![0, 3],
                    format!(
                        "the root with the ray clipped to its cell, t in [{}, {}]: {what}",
                        number(t_near),
                        number(t_far)
                    ),
                ),
            };
            KdStepView {
                lines,
                text,
                cell: Some(node),
                plane_of: parent,
                segment: Some((t_near, t_far, part)),
                ..blank
            }
        }
        Step::CellMissed { node } => {
            let (parent, part) = part_of(tree, node, ray);
            let (clip, name) = match part {
                Part::Far => (vec![1, 7, 8], "rayFar"),
                _ => (vec![1, 4, 5], "rayNear"),
            };
            KdStepView {
                lines: clip,
                text: format!(
                    "at {}: the ray does not reach node {}'s side inside this cell, so {name} is empty: that call returns at 'If empty(ray)'",
                    parent.map_or("the root".to_owned(), |parent| plane_text(tree, parent)),
                    node_name(tree, node)
                ),
                cell: Some(node),
                plane_of: parent,
                returns_at_once: true,
                ..blank
            }
        }
        Step::NodeCulled {
            node,
            t_enter,
            t_closest,
        } => KdStepView {
            lines: vec![6],
            text: format!(
                "If (no intersection) is false: the hit at t = {} comes before the far part starts (t = {}), so the far child, node {}, is never searched",
                number(t_closest),
                number(t_enter),
                node_name(tree, node)
            ),
            cell: Some(node),
            plane_of: tree.built.facts.parent[node as usize],
            returns_at_once: true,
            ..blank
        },
        Step::PrimitiveTested { primitive, t_hit } => {
            let before = shown[..shown.len() - trace.frame(frame).len()]
                .iter()
                .any(|step| matches!(step, Step::PrimitiveTested { primitive: earlier, .. } if *earlier == primitive));
            let result = match (t_hit, part) {
                (Some(t), Some((t_near, t_far))) if t < t_near || t > t_far => format!(
                    "hit at t = {}, outside this cell's part of the ray, [{}, {}]: no intersection of the clipped ray here (it counts in the cell where it lies)",
                    number(t),
                    number(t_near),
                    number(t_far)
                ),
                (Some(t), _) => format!("hit at t = {}", number(t)),
                (None, _) => "missed".to_owned(),
            };
            let again = if before {
                ". Tested again: it straddles a plane, so it is listed in both cells. A mailbox (a per-ray note of what was tested) would skip this test"
            } else {
                ""
            };
            let ends = search_ends(trace.frame(frame));
            KdStepView {
                lines: vec![2],
                text: format!(
                    "leaf {leaf_name}: intersectObjects: primitive {primitive} {result}{again}{ends}"
                ),
                cell: leaf,
                ..blank
            }
        }
        Step::PrimitiveSkipped { primitive } => KdStepView {
            lines: vec![2],
            text: format!(
                "leaf {leaf_name}: primitive {primitive} is not tested again: the mailbox holds its test from another cell{}",
                search_ends(trace.frame(frame))
            ),
            cell: leaf,
            ..blank
        },
        Step::ClosestHitUpdated { primitive, t } => KdStepView {
            lines: vec![2],
            text: format!(
                "every cell searched, and no hit inside a cell's part of the ray: primitive {primitive}'s hit at t = {} lies at the end of a cell's part, outside it only by rounding, so it is the answer",
                number(t)
            ),
            cell: leaf,
            ..blank
        },
        // kD traversal never orders wide children nor walks a grid; entering is the nearest
        // thing it does.
        Step::NodeEntered { node }
        | Step::ChildrenOrdered { node, .. }
        | Step::CellSkipped { node, .. }
        | Step::CellLookedUp { node, .. } => KdStepView {
            lines: vec![0],
            text: format!("enter node {}", node_name(tree, node)),
            cell: Some(node),
            ..blank
        },
        Step::GridStepped { .. } => KdStepView {
            lines: vec![0],
            text: String::new(),
            ..blank
        },
    }
}

/// The lesson.
pub struct KdLesson {
    stage: Stage,
    structure: Structure,
    mailboxing: bool,
    tree: Derived<(u64, Structure), SceneTree>,
    trace: Cached<(u64, u64, bool), Trace>,
    hovered: Option<u32>,
    selected: Option<u32>,
}

impl KdLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::ALL),
            structure: Structure::KdMiddle,
            mailboxing: false,
            tree: Derived::default(),
            trace: Cached::default(),
            hovered: None,
            selected: None,
        }
    }

    /// The view of the current frame, if there is a tree and a ray.
    pub fn view(&self) -> Option<KdStepView> {
        let tree = self.tree.get()?;
        let trace = self.trace.get()?;
        let ray = self.stage.scene.ray().ok()?;
        Some(step_view(trace, self.stage.timeline.shown, tree, &ray))
    }

    /// The recorded trace.
    pub fn trace(&self) -> Option<&Trace> {
        self.trace.get()
    }

    /// The built tree.
    pub fn tree(&self) -> Option<&Arc<SceneTree>> {
        self.tree.get()
    }

    /// A leaf's label in the diagram: how many primitives it lists.
    fn node_label(tree: &SceneTree, node: u32) -> String {
        if tree.built.facts.is_leaf(node) {
            match tree.built.facts.leaf_sizes[node as usize] {
                0 => "empty".to_owned(),
                1 => "1 prim".to_owned(),
                many => format!("{many} prims"),
            }
        } else {
            plane_text(tree, node)
        }
    }

    /// The ray's part in the current call, drawn beside the ray in its colour.
    fn draw_segment(canvas: &Canvas, ray: &Ray<DVec2>, (t_near, t_far, part): (f64, f64, Part)) {
        let along = (canvas.to_screen(ray.origin + ray.direction) - canvas.to_screen(ray.origin))
            .normalized();
        let side = egui::Vec2::new(-along.y, along.x) * 8.0;
        let t_far = canvas.clip_t(ray.origin, ray.direction, t_far);
        if t_near > t_far {
            return;
        }
        let color = match part {
            Part::Near => NEAR_COLOR,
            Part::Far => FAR_COLOR,
            Part::Root => palette::CURRENT,
        };
        canvas.painter.line_segment(
            [
                canvas.to_screen(ray.at(t_near)) + side,
                canvas.to_screen(ray.at(t_far)) + side,
            ],
            Stroke::new(6.0, color),
        );
        canvas.ray_mark(ray.origin, ray.direction, t_near, color, "", 0.0);
        canvas.ray_mark(ray.origin, ray.direction, t_far, color, "", 0.0);
    }

    /// The builder's settings: which kD build, the leaf size, mailboxing.
    fn build_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.label("Build with");
            for entry in CATALOGUE.iter().filter(|entry| {
                entry.family == Family::Kd && entry.structure != Structure::KdSahPerNode
            }) {
                ui.selectable_value(&mut self.structure, entry.structure, entry.label)
                    .on_hover_text(entry.about);
            }
        });
        let mut leaf_size = self.stage.scene.scene.settings.max_leaf_size;
        if ui
            .add(egui::Slider::new(&mut leaf_size, 1..=8).text("max leaf size"))
            .changed()
        {
            self.stage.scene.scene.settings.max_leaf_size = leaf_size;
            self.stage.scene.touch();
        }
        ui.checkbox(&mut self.mailboxing, "mailboxing: test a straddling primitive once per ray")
            .on_hover_text("A per-ray note of the primitives already tested, so one listed in several cells is tested once (the core's TraceOptions::mailboxing)");
    }

    /// The lecture's pseudo-code with the lines the current step runs lit.
    fn code_ui(&self, ui: &mut egui::Ui) {
        ui.heading("The traversal, line by line");
        let view = self.view();
        let lines = view
            .as_ref()
            .map(|view| view.lines.clone())
            .unwrap_or_default();
        egui::Frame::new()
            .fill(ui.visuals().extreme_bg_color)
            .inner_margin(6.0)
            .show(ui, |ui| {
                // Code lines keep their shape: the font shrinks (to three quarters at most) so
                // the longest line fits the panel, which a student would otherwise have to
                // scroll to find; in a narrower panel still, the lines scroll sideways rather
                // than widen it.
                let size = code_size(ui, ui.available_width());
                egui::ScrollArea::horizontal()
                    .id_salt("pseudo-code")
                    .show(ui, |ui| {
                        for (line, code) in PSEUDO_CODE.iter().enumerate() {
                            let mut text = RichText::new(*code).monospace().size(size);
                            if lines.contains(&line) {
                                text = text.background_color(faded(palette::CURRENT, 110)).strong();
                            }
                            ui.add(egui::Label::new(text).wrap_mode(egui::TextWrapMode::Extend));
                        }
                    });
            });
    }

    /// The tree's numbers and its diagram, linked to the canvas (squeezed to the height left
    /// with `fit_height`).
    fn tree_ui(&mut self, ui: &mut egui::Ui, tree: &Arc<SceneTree>, fit_height: bool) {
        let stats = &tree.stats;
        // Two lines at lecture scale: why references outnumber primitives is on hover.
        ui.label(format!(
            "{} nodes, {} leaves ({} empty), depth {}, {} primitive references for {} primitives, SAH cost {}",
            count(stats.node_count),
            count(stats.leaf_count),
            count(stats.empty_leaf_count),
            stats.max_depth,
            count(stats.primitive_references),
            count(tree.shapes.shapes.len()),
            number(stats.sah_cost)
        ))
        .on_hover_text("A primitive that straddles a split plane is listed in each cell it reaches.");
        if let Some(note) = tree.limits_note() {
            ui.colored_label(crate::canvas::readable(ui, palette::RAY), note);
        }
        let frame = self.stage.timeline.shown;
        let shown = self.trace.get().map_or(&[][..], |trace| trace.shown(frame));
        let label = |node: u32| Self::node_label(tree, node);
        diagram_ui(
            ui,
            &tree.built.facts,
            &label,
            shown,
            &mut self.hovered,
            &mut self.selected,
            fit_height,
        );
        if let Some(reason) = self
            .selected
            .and_then(|node| tree.built.facts.leaf_reason(node))
        {
            ui.label(format!("Selected leaf: {reason}."));
        }
        t_hint_ui(ui);
    }
}

impl Lesson for KdLesson {
    crate::staged!(tree);

    fn share(&self) -> Vec<(String, String)> {
        vec![crate::share::structure_value(&self.structure)]
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        match key {
            "structure" => self.structure = crate::share::parse_structure(value)?,
            _ => return Err(format!("this lesson keeps no '{key}'")),
        }
        Ok(())
    }

    fn update(&mut self) {
        let scene = &self.stage.scene;
        request_tree(&mut self.tree, scene, self.structure);
        let Some(tree) = self.tree.get().cloned() else {
            return;
        };
        let mailboxing = self.mailboxing;
        let trace =
            self.trace
                .get_or_make(
                    (self.tree.generation(), scene.revision, mailboxing),
                    || match scene.ray() {
                        Ok(ray) => Trace::of_tree(
                            &tree,
                            &ray,
                            // The slide's pseudo-code as it reads: a leaf against the ray
                            // clipped to its cell, the far side only `If(no intersection)`.
                            &TraceOptions {
                                order: Order::NearFirst,
                                query: accelviz_core::Query::FirstInCell,
                                mailboxing,
                                ..TraceOptions::default()
                            },
                        ),
                        Err(_) => Trace::default(),
                    },
                );
        self.stage.timeline.set_len(trace.frames());
        let nodes = tree.built.facts.node_count() as u32;
        self.selected = self.selected.filter(|&node| node < nodes);
        self.hovered = self.hovered.filter(|&node| node < nodes);
    }

    fn caption(&self) -> Option<String> {
        let view = self.view()?;
        let trace = self.trace.get()?;
        let frame = self.stage.timeline.shown;
        Some(if frame >= trace.frames() && frame > 0 {
            format!("{}. {}", view.text, trace.summary())
        } else {
            view.text
        })
    }

    fn parts(&self) -> &'static [lesson::Part] {
        &PARTS
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, parts: Parts<'_>) {
        if parts.show(&BUILD_PART) {
            self.build_ui(ui);
        }
        let Some(tree) = self.tree.get().cloned() else {
            ui.label("Building…");
            return;
        };
        if parts.show(&CODE_PART) {
            ui.separator();
            self.code_ui(ui);
        }
        if parts.show(&TREE_PART) {
            ui.separator();
            self.tree_ui(ui, &tree, parts.fit_screen());
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let canvas = self.stage.scene.canvas_ui(ui, None);
        let Some(tree) = self.tree.get().cloned() else {
            return;
        };
        // The leaf cell under the pointer lights up (and its node in the tree).
        if canvas.response.hovered() {
            self.hovered = canvas
                .response
                .hover_pos()
                .and_then(|pos| node_under(&canvas, &tree, pos, &(0..=usize::MAX)));
        }
        let frame = self.stage.timeline.shown;
        let shown = self.trace.get().map_or(&[][..], |trace| trace.shown(frame));
        let view = self.view();
        let current = self
            .trace
            .get()
            .and_then(|trace| match trace.frame(frame).first() {
                Some(Step::PrimitiveTested { primitive, .. }) => Some(*primitive),
                _ => None,
            });
        draw_tested_shapes(ui, &canvas, &tree.shapes, shown, current);
        draw_tree(
            &canvas,
            &tree,
            &TreeLook {
                hovered: self.hovered,
                selected: self.selected,
                ..TreeLook::default()
            },
        );
        let Ok(ray) = self.stage.scene.ray() else {
            canvas.caption(&[(
                "No ray: drag its head away from its origin".to_owned(),
                palette::MISS,
            )]);
            self.stage.scene.draw_handles(&canvas);
            return;
        };
        draw_ray(
            &canvas,
            &ray,
            crate::trace::closest_so_far(shown).map(|(_, t)| t),
        );
        if let Some(view) = &view {
            // The cell the call is about, then the parent's plane it clips at, on top.
            if let Some(cell) = view.cell {
                let color = if view.returns_at_once {
                    palette::MISS
                } else {
                    palette::CURRENT
                };
                node_outline(
                    &canvas,
                    &tree,
                    cell,
                    Stroke::new(3.5, color),
                    Some(faded(color, 30)),
                );
            }
            if let Some(parent) = view.plane_of
                && let Some((axis, position)) = tree.built.plane(parent)
            {
                canvas.split_line(
                    &tree.built.facts.bounds[parent as usize],
                    axis,
                    position,
                    Stroke::new(4.0, Color32::WHITE),
                );
            }
            if let Some(segment) = view.segment {
                Self::draw_segment(&canvas, &ray, segment);
            }
        }
        self.stage.scene.draw_handles(&canvas);
        canvas.caption(&[
            (
                "rayNear: the part of the ray on the near side".to_owned(),
                NEAR_COLOR,
            ),
            ("rayFar: the part on the far side".to_owned(), FAR_COLOR),
        ]);
        building_note(ui, &canvas, self.tree.working_for(), "the kD-tree");
        if let Some(note) = tree.limits_note() {
            canvas.note(&note);
        }
        self.stage.scene.draw_footer(&canvas);
        canvas.finish();
    }
}
