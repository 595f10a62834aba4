//! Lesson 9, "Splitting is optimization" and "Two ways to build, one without sort": a kD SAH
//! build stepped node by node in the builder's recursion order: sort per axis (or, the second
//! way, partition lists sorted once at the root), sweep each axis, choose the best, recurse.
//!
//! The tree is the core's: `KdSah` (events sorted at every node) or `KdSahPresorted` (sorted
//! once, split stably; the core's tests assert both build the same tree). Each node's sweep is
//! the core's cost curve, the builders' own sweep.

use accelviz_core::TreeFacts;
use accelviz_core::curve::{CostCurve, kd_curve};
use accelviz_core::kd::{KdBuilder, KdSah, KdSahPresorted, KdTree};
use accelviz_core::{Aabb, PrimitiveSet};
use egui::{Color32, RichText, Stroke};
use egui_plot::{HLine, Line, Plot, PlotPoints, VLine};
use glam::DVec2;

use super::common::number;
use super::kd::BuiltKd;
use super::{Lesson, LessonText};
use crate::canvas::{faded, palette};
use crate::editor::{EditableScene, Editing};
use crate::timeline::Timeline;

/// The lecture's two ways.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Way {
    /// `build(nodes)`: sort along each axis at every node.
    SortAtEachNode,
    /// `build(xNodes, yNodes)`: sort once, then split the sorted lists keeping their order.
    SortOnce,
}

/// One step of the build; `node` is the node worked on, `axis` 0 for x and 1 for y.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum BuildStep {
    /// Sort the node's primitives along an axis.
    Sort { node: u32, axis: usize },
    /// Take the node's sorted lists from its parent's, in order (the second way).
    Partition { node: u32 },
    /// Cost every candidate split on an axis.
    Sweep { node: u32, axis: usize },
    /// Keep the cheapest split (recurse into both sides next).
    Choose { node: u32 },
    /// Make a leaf: no split is cheaper (or nothing left to split).
    Leaf { node: u32 },
}

impl BuildStep {
    /// The node the step works on.
    pub fn node(&self) -> u32 {
        match *self {
            BuildStep::Sort { node, .. }
            | BuildStep::Partition { node }
            | BuildStep::Sweep { node, .. }
            | BuildStep::Choose { node }
            | BuildStep::Leaf { node } => node,
        }
    }
}

/// The steps of building `built` the given way, in recursion order (depth first, below the
/// plane first, as the builders recurse).
pub fn build_steps(built: &BuiltKd, way: Way) -> Vec<BuildStep> {
    let mut steps = Vec::new();
    let mut pending = vec![0u32];
    while let Some(node) = pending.pop() {
        let is_root = node == 0;
        if way == Way::SortOnce && !is_root {
            steps.push(BuildStep::Partition { node });
        } else {
            steps.extend((0..2).map(|axis| BuildStep::Sort { node, axis }));
        }
        steps.extend((0..2).map(|axis| BuildStep::Sweep { node, axis }));
        match built.shape.children[node as usize] {
            Some([below, above]) => {
                steps.push(BuildStep::Choose { node });
                pending.push(above);
                pending.push(below);
            }
            None => steps.push(BuildStep::Leaf { node }),
        }
    }
    steps
}

/// The lesson.
pub struct BuildStepsLesson {
    text: LessonText,
    scene: EditableScene,
    way: Way,
    built: Option<BuiltKd>,
    built_key: (u64, Way),
    steps: Vec<BuildStep>,
    curves: Vec<Option<CostCurve>>,
    timeline: Timeline,
}

impl BuildStepsLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let scene = EditableScene::new(text.scene.clone(), Editing::SHAPES);
        Self {
            text,
            scene,
            way: Way::SortAtEachNode,
            built: None,
            built_key: (0, Way::SortAtEachNode),
            steps: Vec::new(),
            curves: Vec::new(),
            timeline: Timeline::default(),
        }
    }

    fn refresh(&mut self) {
        let key = (self.scene.revision, self.way);
        if self.built.is_some() && self.built_key == key {
            return;
        }
        let shapes = &self.scene.scene.shapes;
        let bounds = shapes.all_bounds();
        let params = accelviz_core::bvh::BuildParams {
            max_leaf_size: self.scene.scene.settings.max_leaf_size,
            cost: self.scene.scene.settings.cost(),
            ..Default::default()
        };
        let tree: KdTree<DVec2> = match self.way {
            Way::SortAtEachNode => KdSah.build(&bounds, &params),
            Way::SortOnce => KdSahPresorted.build(&bounds, &params),
        };
        let built = BuiltKd::with_tree(tree);
        self.steps = build_steps(&built, self.way);
        self.curves = vec![None; built.tree.nodes.len()];
        self.timeline.set_len(self.steps.len());
        self.built = Some(built);
        self.built_key = key;
    }

    /// The cost curve of a node (computed when first shown).
    fn curve(&mut self, node: u32) -> Option<&CostCurve> {
        let built = self.built.as_ref()?;
        if self.curves[node as usize].is_none() {
            let path = built.shape.path_to(node);
            let _ = path;
            let facts = TreeFacts::of(&built.tree);
            let (cell, primitives) = (
                facts.bounds[node as usize],
                facts.primitives_below(&built.tree, node),
            );
            let boxes = self.scene.scene.shapes.all_bounds();
            let cost = self.scene.scene.settings.cost();
            self.curves[node as usize] = Some(kd_curve(&boxes, &primitives, &cell, &cost, None));
        }
        self.curves[node as usize].as_ref()
    }

    fn current(&self) -> Option<BuildStep> {
        self.timeline
            .shown
            .checked_sub(1)
            .and_then(|index| self.steps.get(index).copied())
    }

    /// The node's primitives in order along `axis` (by the lower side of their boxes, as the
    /// sweep meets them).
    fn sorted(&self, node: u32, axis: usize) -> Vec<u32> {
        let Some(built) = &self.built else {
            return Vec::new();
        };
        let mut primitives = TreeFacts::of(&built.tree).primitives_below(&built.tree, node);
        let shapes = &self.scene.scene.shapes;
        primitives.sort_by(|&a, &b| {
            shapes.bounds(a as usize).min[axis]
                .total_cmp(&shapes.bounds(b as usize).min[axis])
                .then(a.cmp(&b))
        });
        primitives
    }

    fn caption(&mut self) -> String {
        let Some(step) = self.current() else {
            return "Press step: the build starts at the root, with every primitive.".to_owned();
        };
        let axis_name = |axis: usize| ["x", "y"][axis.min(1)];
        match step {
            BuildStep::Sort { node, axis } => {
                let order = self.sorted(node, axis);
                format!(
                    "node {node}: sort{}({} primitives) along {}",
                    axis_name(axis).to_uppercase(),
                    order.len(),
                    axis_name(axis)
                )
            }
            BuildStep::Partition { node } => format!(
                "node {node}: no sort; its x and y lists are the parent's, split at the plane and still in order"
            ),
            BuildStep::Sweep { node, axis } => match self.curve(node) {
                Some(curve) => {
                    let candidates = curve.axes.get(axis).map_or(0, Vec::len);
                    let best = curve
                        .axes
                        .get(axis)
                        .and_then(|axis| axis.iter().min_by(|a, b| a.cost.total_cmp(&b.cost)));
                    format!(
                        "node {node}: findSplit on {}: {candidates} candidates costed in one sweep; cheapest {}",
                        axis_name(axis),
                        best.map_or("none".to_owned(), |c| format!(
                            "at {} (cost {})",
                            number(c.position),
                            number(c.cost)
                        ))
                    )
                }
                None => format!("node {node}: sweep {}", axis_name(axis)),
            },
            BuildStep::Choose { node } => {
                let split = self
                    .built
                    .as_ref()
                    .map(|built| built.tree.nodes[node as usize]);
                match (split, self.curve(node)) {
                    (Some(split), Some(curve)) => format!(
                        "node {node}: best(xS, yS) = {} = {} at cost {} < leaf {}: split, then build(left) and build(right)",
                        axis_name(split.axis as usize),
                        number(split.split),
                        curve.best.map_or("?".to_owned(), |best| number(best.cost)),
                        number(curve.leaf_cost)
                    ),
                    _ => format!("node {node}: split"),
                }
            }
            BuildStep::Leaf { node } => match self.curve(node) {
                Some(curve) => format!(
                    "node {node}: leaf of {} primitives: leaf cost {} ≤ best split {}",
                    curve.count,
                    number(curve.leaf_cost),
                    curve
                        .best
                        .map_or("(none)".to_owned(), |best| number(best.cost))
                ),
                None => format!("node {node}: leaf"),
            },
        }
    }
}

impl Lesson for BuildStepsLesson {
    fn text(&self) -> &LessonText {
        &self.text
    }

    fn scene_mut(&mut self) -> Option<&mut EditableScene> {
        Some(&mut self.scene)
    }

    fn timeline(&mut self) -> Option<(&mut Timeline, String)> {
        self.refresh();
        let caption = self.caption();
        Some((&mut self.timeline, caption))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.label("Build");
            ui.selectable_value(&mut self.way, Way::SortAtEachNode, "sort at each node");
            ui.selectable_value(&mut self.way, Way::SortOnce, "sort once");
        });
        self.refresh();
        let code: &[&str] = match self.way {
            Way::SortAtEachNode => &[
                "build(nodes)",
                "  xS = findSplit(sortX(nodes))",
                "  yS = findSplit(sortY(nodes))",
                "  S = best(xS, yS)",
                "  build(left(S, nodes))",
                "  build(right(S, nodes))",
            ],
            Way::SortOnce => &[
                "xNodes = sortX(nodes); yNodes = sortY(nodes)",
                "build(xNodes, yNodes)",
                "  xS = findSplit(xNodes)",
                "  yS = findSplit(yNodes)",
                "  S = best(xS, yS)",
                "  build(left(S, xNodes, yNodes))",
                "  build(right(S, xNodes, yNodes))",
            ],
        };
        let current = self.current();
        let lines: Vec<usize> = match (self.way, current) {
            (_, None) => Vec::new(),
            (Way::SortAtEachNode, Some(step)) => match step {
                BuildStep::Sort { axis, .. } | BuildStep::Sweep { axis, .. } => vec![1 + axis],
                BuildStep::Choose { .. } => vec![3, 4, 5],
                BuildStep::Leaf { .. } | BuildStep::Partition { .. } => vec![0],
            },
            (Way::SortOnce, Some(step)) => match step {
                BuildStep::Sort { .. } => vec![0],
                BuildStep::Partition { .. } => vec![5, 6],
                BuildStep::Sweep { axis, .. } => vec![2 + axis],
                BuildStep::Choose { .. } => vec![4, 5, 6],
                BuildStep::Leaf { .. } => vec![1],
            },
        };
        egui::Frame::new()
            .fill(ui.visuals().extreme_bg_color)
            .inner_margin(6.0)
            .show(ui, |ui| {
                for (index, line) in code.iter().enumerate() {
                    let mut text = RichText::new(*line).monospace().size(11.5);
                    if lines.contains(&index) {
                        text = text.background_color(faded(palette::CURRENT, 90)).strong();
                    }
                    ui.add(egui::Label::new(text).wrap_mode(egui::TextWrapMode::Extend));
                }
            });
        let sorts = self.steps[..self.timeline.shown.min(self.steps.len())]
            .iter()
            .filter(|step| matches!(step, BuildStep::Sort { .. }))
            .count();
        let total_sorts = self
            .steps
            .iter()
            .filter(|step| matches!(step, BuildStep::Sort { .. }))
            .count();
        ui.label(format!(
            "sorts so far: {sorts} (of {total_sorts} in this build)"
        ));
        ui.separator();
        let Some(step) = current else { return };
        let node = step.node();
        if let BuildStep::Sort { axis, .. } = step {
            let order: Vec<String> = self.sorted(node, axis).iter().map(u32::to_string).collect();
            ui.label(format!(
                "order along {}: {}",
                ["x", "y"][axis],
                order.join(", ")
            ));
        }
        let sweep_axis = match step {
            BuildStep::Sweep { axis, .. } => Some(axis),
            BuildStep::Choose { node } | BuildStep::Leaf { node } => self
                .built
                .as_ref()
                .map(|built| built.tree.nodes[node as usize])
                .filter(|node| !node.is_leaf())
                .map(|node| node.axis as usize),
            _ => None,
        };
        if let (Some(axis), Some(curve)) = (sweep_axis, self.curve(node).cloned()) {
            let candidates = curve.axes.get(axis).cloned().unwrap_or_default();
            let points: PlotPoints = candidates.iter().map(|c| [c.position, c.cost]).collect();
            Plot::new("build sweep")
                .height(170.0)
                .x_axis_label(format!("split on {}", ["x", "y"][axis]))
                .y_axis_label("cost")
                .allow_scroll(false)
                .allow_drag(false)
                .allow_zoom(false)
                .show(ui, |plot| {
                    plot.line(Line::new("cost", points).color(palette::RAY));
                    plot.hline(HLine::new("leaf cost", curve.leaf_cost).color(Color32::GRAY));
                    if let Some(best) = curve.best.filter(|best| best.axis == axis) {
                        plot.vline(VLine::new("best", best.position).color(palette::CURRENT));
                    }
                });
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let canvas = self.scene.canvas_ui(ui, None);
        self.refresh();
        let current = self.current();
        let shown = self.timeline.shown.min(self.steps.len());
        let Some(built) = &self.built else { return };
        // The tree as far as built: the splits chosen so far.
        let chosen: Vec<u32> = self.steps[..shown]
            .iter()
            .filter_map(|step| match step {
                BuildStep::Choose { node } => Some(*node),
                _ => None,
            })
            .collect();
        let partial = partial_tree(built, &chosen);
        let node_primitives = current
            .map(|step| TreeFacts::of(&built.tree).primitives_below(&built.tree, step.node()))
            .unwrap_or_default();
        super::common::draw_shapes(ui, &canvas, &self.scene.scene.shapes, |index| {
            node_primitives
                .contains(&(index as u32))
                .then_some(palette::RAY)
        });
        partial.draw_splits(&canvas, None);
        let Some(step) = current else {
            canvas.box_outline(&built.tree.bounds, Stroke::new(2.0, palette::CURRENT), None);
            return;
        };
        let node = step.node();
        let cell: Aabb<DVec2> = built.cells[node as usize];
        let fill = matches!(step, BuildStep::Leaf { .. }).then(|| faded(palette::HIT, 40));
        canvas.box_outline(&cell, Stroke::new(3.0, palette::CURRENT), fill);
        match step {
            BuildStep::Sort { axis, .. } => {
                // Each primitive's rank along the axis, written beside it.
                for (rank, primitive) in self.sorted(node, axis).iter().enumerate() {
                    let shape_bounds = self.scene.scene.shapes.bounds(*primitive as usize);
                    canvas.label(
                        shape_bounds.max,
                        &format!("{}{}", ["x", "y"][axis], rank + 1),
                        Color32::WHITE,
                    );
                }
            }
            BuildStep::Sweep { axis, .. } => {
                // Every candidate plane as a tick on the cell's edge.
                if let Some(curve) = self.curves.get(node as usize).cloned().flatten() {
                    for candidate in curve.axes.get(axis).into_iter().flatten() {
                        let (from, to) = tick(&cell, axis, candidate.position);
                        canvas.painter.line_segment(
                            [canvas.to_screen(from), canvas.to_screen(to)],
                            Stroke::new(1.5, faded(palette::RAY, 160)),
                        );
                    }
                }
            }
            BuildStep::Choose { .. } => {
                let split = built.tree.nodes[node as usize];
                canvas.split_line(
                    &cell,
                    split.axis as usize,
                    split.split,
                    Stroke::new(4.0, palette::CURRENT),
                );
            }
            BuildStep::Partition { .. } | BuildStep::Leaf { .. } => {}
        }
        canvas.caption(&[(
            format!(
                "{} of {} nodes built",
                chosen.len() * 2 + 1,
                built.tree.nodes.len()
            ),
            Color32::WHITE,
        )]);
    }
}

/// A short tick across the bottom (x) or left (y) edge of a cell at `position`.
fn tick(cell: &Aabb<DVec2>, axis: usize, position: f64) -> (DVec2, DVec2) {
    let length = cell.extent()[1 - axis] * 0.08;
    if axis == 0 {
        (
            DVec2::new(position, cell.min.y),
            DVec2::new(position, cell.min.y + length),
        )
    } else {
        (
            DVec2::new(cell.min.x, position),
            DVec2::new(cell.min.x + length, position),
        )
    }
}

/// The tree with only the chosen nodes split (the rest drawn as leaves): the build so far.
fn partial_tree(built: &BuiltKd, chosen: &[u32]) -> BuiltKd {
    let mut tree = built.tree.clone();
    for (index, node) in tree.nodes.iter_mut().enumerate() {
        if !node.is_leaf() && !chosen.contains(&(index as u32)) {
            node.axis = accelviz_core::kd::KdNode::<f64>::LEAF;
        }
    }
    BuiltKd::with_tree(tree)
}
