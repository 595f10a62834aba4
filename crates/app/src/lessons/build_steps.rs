//! Lesson 9, "Splitting is optimization" and "Two ways to build, one without sort": a kD SAH
//! build stepped node by node, the steps being the builder's own, recorded by a
//! `BuildRecorder` as it runs: start a node, sort its events per axis (the first way, `KdSah`)
//! or divide the parent's sorted lists keeping their order (the second way, `KdSahPresorted`,
//! which sorts once at the root), sweep each axis, then split or make a leaf for the reason
//! the builder gives. Each sweep is the core's cost curve of that node: the same sweep.

use accelviz_core::curve::{CostCurve, kd_curve};
use accelviz_core::format::{count, counted, number};
use accelviz_core::{BuildRecorder, BuildStep, PrimitiveSet, Structure};
use egui::{Color32, RichText, Stroke, Vec2};
use egui_plot::{HLine, Line, Plot, PlotPoints, VLine};
use glam::DVec2;

use crate::background::{Cached, Derived};
use crate::canvas::{Labels, faded, palette};
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage, request_over_shapes};
use crate::views::scene_view::{building_note, draw_shapes, narrow_x_axis};

/// The lecture's two ways.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Way {
    /// `build(nodes)`: sort along each axis at every node.
    SortAtEachNode,
    /// `build(xNodes, yNodes)`: sort once, then split the sorted lists keeping their order.
    SortOnce,
}

impl Way {
    /// The structure of the catalogue that builds this way (both make the same tree).
    pub fn structure(self) -> Structure {
        match self {
            Way::SortAtEachNode => Structure::KdSahPerNode,
            Way::SortOnce => Structure::KdSah,
        }
    }

    /// The slide's pseudo-code.
    fn code(self) -> &'static [&'static str] {
        match self {
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
        }
    }

    /// The code lines a step runs.
    fn lines(self, step: &BuildStep) -> Vec<usize> {
        match (self, step) {
            (
                Way::SortAtEachNode,
                BuildStep::Sorted { axis, .. } | BuildStep::Swept { axis, .. },
            ) => {
                vec![1 + axis.min(&1)]
            }
            (Way::SortAtEachNode, BuildStep::Split { .. }) => vec![3],
            (Way::SortAtEachNode, BuildStep::ListsDivided { .. }) => vec![4, 5],
            (Way::SortAtEachNode, _) => vec![0],
            (Way::SortOnce, BuildStep::Sorted { .. }) => vec![0],
            (Way::SortOnce, BuildStep::Swept { axis, .. }) => vec![2 + axis.min(&1)],
            (Way::SortOnce, BuildStep::Split { .. }) => vec![4],
            (Way::SortOnce, BuildStep::ListsDivided { .. }) => vec![5, 6],
            (Way::SortOnce, _) => vec![1],
        }
    }
}

/// A build and the steps its builder reported.
struct RecordedBuild {
    tree: SceneTree,
    steps: Vec<BuildStep>,
}

/// The axis names.
const AXES: [&str; 2] = ["x", "y"];

/// The lesson.
pub struct BuildStepsLesson {
    stage: Stage,
    way: Way,
    build: Derived<(u64, Way), RecordedBuild>,
    /// Each node's cost curve (computed when first shown), for the build it is of.
    curves: Cached<(u64, u32), CostCurve>,
    /// The current step in words (made in `update`, which may compute a curve).
    caption: String,
}

impl BuildStepsLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::SHAPES),
            way: Way::SortAtEachNode,
            build: Derived::default(),
            curves: Cached::default(),
            caption: String::new(),
        }
    }

    /// The builder's steps, as recorded.
    pub fn steps(&self) -> &[BuildStep] {
        self.build.get().map_or(&[], |build| &build.steps)
    }

    /// The step shown (the last of the first `shown`).
    pub fn current(&self) -> Option<BuildStep> {
        let shown = self.stage.timeline.shown;
        shown
            .checked_sub(1)
            .and_then(|index| self.steps().get(index).copied())
    }

    /// The cost curve of `node` in the current build.
    fn curve(&mut self, node: u32) -> Option<&CostCurve> {
        let build = self.build.get()?.clone();
        let tree = &build.tree;
        let facts = &tree.built.facts;
        let generation = self.build.generation();
        Some(self.curves.get_or_make((generation, node), || {
            let primitives = tree.built.primitives_below(node);
            let boxes = tree.shapes.all_bounds();
            kd_curve(
                &boxes,
                &primitives,
                &facts.bounds[node as usize],
                &tree.settings.cost(),
                None,
            )
        }))
    }

    /// The node's primitives in order along `axis` (by the lower side of their boxes, as the
    /// sweep meets them).
    fn sorted(tree: &SceneTree, node: u32, axis: usize) -> Vec<u32> {
        let mut primitives = tree.built.primitives_below(node);
        let shapes = &tree.shapes;
        primitives.sort_by(|&a, &b| {
            shapes.bounds(a as usize).min[axis]
                .total_cmp(&shapes.bounds(b as usize).min[axis])
                .then(a.cmp(&b))
        });
        primitives
    }

    fn describe(&mut self, step: BuildStep) -> String {
        let Some(build) = self.build.get().cloned() else {
            return String::new();
        };
        let tree = &build.tree;
        match step {
            BuildStep::NodeStarted {
                node,
                depth,
                primitive_count,
            } => format!(
                "build node {node}: depth {depth}, {}",
                counted(primitive_count, "primitive", "primitives")
            ),
            BuildStep::Sorted { node, axis } => {
                let axis_name = AXES[axis.min(1)];
                match self.way {
                    Way::SortOnce => format!(
                        "{axis_name}Nodes = sort{}(nodes): every primitive's events along {axis_name}, sorted once, at the root",
                        axis_name.to_uppercase()
                    ),
                    Way::SortAtEachNode => format!(
                        "node {node}: sort{}({}) along {axis_name}",
                        axis_name.to_uppercase(),
                        counted(
                            tree.built.primitives_below(node).len(),
                            "primitive",
                            "primitives"
                        )
                    ),
                }
            }
            BuildStep::Swept { node, axis } => match self.curve(node) {
                Some(curve) => {
                    let candidates = curve.axes.get(axis).map_or(0, Vec::len);
                    let best = curve
                        .axes
                        .get(axis)
                        .and_then(|axis| axis.iter().min_by(|a, b| a.cost.total_cmp(&b.cost)));
                    format!(
                        "node {node}: findSplit on {}: {candidates} candidates costed in one sweep; cheapest {}",
                        AXES[axis.min(1)],
                        best.map_or("none".to_owned(), |c| format!(
                            "at {} (cost {})",
                            number(c.position),
                            number(c.cost)
                        ))
                    )
                }
                None => format!("node {node}: sweep {}", AXES[axis.min(1)]),
            },
            BuildStep::Split {
                node,
                children,
                cost,
            } => {
                let [left, right] = children.as_pair().unwrap_or([children.first; 2]);
                let plane = tree
                    .built
                    .plane(node)
                    .map_or("?".to_owned(), |(axis, position)| {
                        format!("{} = {}", AXES[axis.min(1)], number(position))
                    });
                let leaf = self.curve(node).map(|curve| curve.leaf_cost);
                format!(
                    "node {node}: S = best(xS, yS): {plane} at cost {}{}: split into nodes {left} and {right}",
                    cost.map_or("?".to_owned(), number),
                    leaf.map_or(String::new(), |leaf| format!(" < leaf {}", number(leaf)))
                )
            }
            BuildStep::ListsDivided { node } => format!(
                "node {node}: left(S, xNodes, yNodes) and right(…): each sorted list is split at the plane, keeping its order: the children need no sort"
            ),
            BuildStep::Leaf { node, reason } => format!("node {node} is a leaf: {reason}"),
        }
    }
}

impl Lesson for BuildStepsLesson {
    crate::staged!(build);

    fn update(&mut self) {
        let scene = &self.stage.scene;
        let way = self.way;
        request_over_shapes(&mut self.build, scene, way, move |shapes, settings| {
            let mut recorder = BuildRecorder::default();
            let tree = SceneTree::build_observed(way.structure(), shapes, settings, &mut recorder);
            RecordedBuild {
                tree,
                steps: recorder.steps,
            }
        });
        let steps = self.steps().len();
        self.stage.timeline.set_len(steps);
        self.caption = match self.current() {
            None => "Press step: the build starts at the root, with every primitive.".to_owned(),
            Some(step) => {
                let said = self.describe(step);
                if self.stage.timeline.shown >= steps {
                    let nodes = self
                        .steps()
                        .iter()
                        .filter(|step| matches!(step, BuildStep::NodeStarted { .. }))
                        .count();
                    format!("{said}. Done: the tree has {} nodes.", count(nodes))
                } else {
                    said
                }
            }
        };
    }

    fn caption(&self) -> Option<String> {
        self.build.get()?;
        Some(self.caption.clone())
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        ui.horizontal(|ui| {
            ui.label("Build");
            ui.selectable_value(&mut self.way, Way::SortAtEachNode, "sort at each node");
            ui.selectable_value(&mut self.way, Way::SortOnce, "sort once");
        });
        let current = self.current();
        let lines = current
            .map(|step| self.way.lines(&step))
            .unwrap_or_default();
        egui::Frame::new()
            .fill(ui.visuals().extreme_bg_color)
            .inner_margin(6.0)
            .show(ui, |ui| {
                for (index, line) in self.way.code().iter().enumerate() {
                    let mut text = RichText::new(*line).monospace();
                    if lines.contains(&index) {
                        text = text.background_color(faded(palette::CURRENT, 110)).strong();
                    }
                    ui.add(egui::Label::new(text).wrap_mode(egui::TextWrapMode::Extend));
                }
            });
        let shown = self.stage.timeline.shown.min(self.steps().len());
        let sorts = self.steps()[..shown]
            .iter()
            .filter(|step| matches!(step, BuildStep::Sorted { .. }))
            .count();
        if shown >= self.steps().len() && shown > 0 {
            ui.label(format!("sorts in this build: {sorts}"));
        } else {
            ui.label(format!("sorts so far: {sorts}"));
        }
        ui.separator();
        let Some(step) = current else { return };
        let Some(build) = self.build.get().cloned() else {
            return;
        };
        let node = step.node();
        if let BuildStep::Sorted { axis, .. } = step {
            let order: Vec<String> = Self::sorted(&build.tree, node, axis)
                .iter()
                .take(40)
                .map(u32::to_string)
                .collect();
            ui.label(format!(
                "order along {}: {}",
                AXES[axis.min(1)],
                order.join(", ")
            ));
        }
        let sweep_axis = match step {
            BuildStep::Swept { axis, .. } => Some(axis),
            BuildStep::Split { node, .. } | BuildStep::ListsDivided { node } => {
                build.tree.built.plane(node).map(|(axis, _)| axis)
            }
            _ => None,
        };
        if let (Some(axis), Some(curve)) = (sweep_axis, self.curve(node).cloned()) {
            let candidates = curve.axes.get(axis).cloned().unwrap_or_default();
            let points: PlotPoints = candidates.iter().map(|c| [c.position, c.cost]).collect();
            let [low, high] = curve.bounds[axis.min(2)];
            let plot_bg = ui.visuals().extreme_bg_color;
            Plot::new("build sweep")
                .height(190.0)
                .custom_x_axes(vec![narrow_x_axis(&format!(
                    "split on {}",
                    AXES[axis.min(1)]
                ))])
                .y_axis_label("cost")
                // The whole cell along the axis, so the numbers under the axis always show.
                .include_x(low)
                .include_x(high)
                .include_y(curve.leaf_cost)
                .allow_scroll(false)
                .allow_drag(false)
                .allow_zoom(false)
                .show(ui, |plot| {
                    plot.line(
                        Line::new("cost", points)
                            .color(crate::canvas::ink_on(palette::RAY, plot_bg)),
                    );
                    plot.hline(HLine::new("leaf cost", curve.leaf_cost).color(Color32::GRAY));
                    if let Some(best) = curve.best.filter(|best| best.axis == axis) {
                        plot.vline(
                            VLine::new("best", best.position)
                                .color(crate::canvas::ink_on(palette::CURRENT, plot_bg)),
                        );
                    }
                });
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let canvas = self.stage.scene.canvas_ui(ui, None);
        let Some(build) = self.build.get().cloned() else {
            return;
        };
        let tree = &build.tree;
        let facts = &tree.built.facts;
        let shown = self.stage.timeline.shown.min(build.steps.len());
        let current = self.current();
        // The tree as far as built: the splits made so far.
        let split: Vec<u32> = build.steps[..shown]
            .iter()
            .filter_map(|step| match step {
                BuildStep::Split { node, .. } => Some(*node),
                _ => None,
            })
            .collect();
        let node_primitives = current
            .map(|step| tree.built.primitives_below(step.node()))
            .unwrap_or_default();
        draw_shapes(ui, &canvas, &tree.shapes, |index| {
            node_primitives
                .binary_search(&(index as u32))
                .is_ok()
                .then_some(palette::RAY)
        });
        canvas.box_outline(
            &tree.built.root_bounds(),
            Stroke::new(1.5, canvas.depth_color(0)),
            None,
        );
        canvas.split_lines(split.iter().filter_map(|&node| {
            let (axis, position) = tree.built.plane(node)?;
            let stroke = Stroke::new(
                1.5,
                canvas.depth_color(facts.depth[node as usize] as usize + 1),
            );
            Some((facts.bounds[node as usize], axis, position, stroke))
        }));
        let Some(step) = current else {
            canvas.box_outline(
                &tree.built.root_bounds(),
                Stroke::new(2.5, palette::CURRENT),
                None,
            );
            canvas.finish();
            return;
        };
        let node = step.node();
        let cell = facts.bounds[node as usize];
        let fill = matches!(step, BuildStep::Leaf { .. }).then(|| faded(palette::HIT, 40));
        canvas.box_outline(&cell, Stroke::new(3.0, palette::CURRENT), fill);
        match step {
            BuildStep::Sorted { axis, .. } => {
                // Each primitive's rank along the axis, written beside it where there is room.
                let mut labels = Labels::new(canvas.rect);
                for (rank, primitive) in Self::sorted(tree, node, axis).iter().enumerate().take(200)
                {
                    let bounds = tree.shapes.bounds(*primitive as usize);
                    labels.place(
                        &canvas.painter,
                        &format!("{}{}", AXES[axis.min(1)], rank + 1),
                        crate::canvas::font(canvas.painter.ctx(), 12.0),
                        Color32::WHITE,
                        canvas.to_screen(bounds.max),
                        &[
                            Vec2::new(10.0, -8.0),
                            Vec2::new(-10.0, -8.0),
                            Vec2::new(10.0, 8.0),
                        ],
                        Some(Color32::from_black_alpha(150)),
                    );
                }
            }
            BuildStep::Swept { axis, .. } => {
                // Every candidate plane as a tick on the cell's edge.
                if let Some(curve) = self.curve(node).cloned() {
                    for candidate in curve.axes.get(axis).into_iter().flatten() {
                        let (from, to) = tick(&cell, axis, candidate.position);
                        canvas.painter.line_segment(
                            [canvas.to_screen(from), canvas.to_screen(to)],
                            Stroke::new(1.5, faded(palette::RAY, 160)),
                        );
                    }
                }
            }
            BuildStep::Split { .. } | BuildStep::ListsDivided { .. } => {
                if let Some((axis, position)) = tree.built.plane(node) {
                    canvas.split_line(&cell, axis, position, Stroke::new(4.0, palette::CURRENT));
                }
            }
            BuildStep::NodeStarted { .. } | BuildStep::Leaf { .. } => {}
        }
        let built_nodes = build.steps[..shown]
            .iter()
            .filter(|step| matches!(step, BuildStep::NodeStarted { .. }))
            .count();
        canvas.caption(&[(
            format!(
                "{} started, {} split so far",
                match built_nodes {
                    1 => "1 node".to_owned(),
                    nodes => format!("{} nodes", count(nodes)),
                },
                count(split.len())
            ),
            Color32::WHITE,
        )]);
        building_note(ui, &canvas, self.build.working_for(), "the tree");
        if let Some(note) = tree.limits_note() {
            canvas.note(&note);
        }
        self.stage.scene.draw_footer(&canvas);
        canvas.finish();
    }
}

/// A short tick across the bottom (x) or left (y) edge of a cell at `position`.
fn tick(cell: &accelviz_core::Aabb<DVec2>, axis: usize, position: f64) -> (DVec2, DVec2) {
    let length = cell.extent()[1 - axis.min(1)] * 0.08;
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
