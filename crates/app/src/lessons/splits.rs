//! Lesson 7, "Building good kD-trees" to "Surface Area Heuristic": middle, median and SAH
//! side by side, and the SAH cost of every candidate split of a node (the core's cost curve:
//! the builders' own sweep and the shared `SahCost`, so the curve's minimum is the split the
//! SAH builder made). Hovering a candidate selects it and ghosts its split in the canvas.

use accelviz_core::TreeFacts;
use accelviz_core::curve::{Candidate, CostCurve, bvh_curve, kd_curve};
use accelviz_core::{Aabb, PrimitiveSet};
use egui::{Color32, Pos2, RichText, Stroke, Vec2};
use egui_plot::{
    HLine, Legend, Line, MarkerShape, Plot, PlotPoint, PlotPoints, PlotTransform, Points, VLine,
};
use glam::DVec2;

use super::compare::{BuiltTree, Comparison, Structure, rule_color};
use super::{Lesson, LessonText};
use crate::canvas::{Canvas, faded, palette};
use crate::editor::{EditableScene, Editing};

/// The SAH pane: where the selected node lives.
const SAH_PANE: usize = 2;

/// The lesson.
pub struct SplitsLesson {
    text: LessonText,
    scene: EditableScene,
    structure: Structure,
    comparison: Option<Comparison>,
    comparison_key: (u64, Structure),
    /// The node whose candidates are plotted, in the SAH tree.
    node: u32,
    /// The axis plotted (0 = x, 1 = y).
    axis: usize,
    /// Whether binned candidates are overlaid.
    show_binned: bool,
    curve: Option<CostCurve>,
    /// The candidate under the pointer in the plot (hovering selects it).
    selected: Option<Candidate>,
    plot_transform: Option<PlotTransform>,
}

impl SplitsLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let scene = EditableScene::new(text.scene.clone(), Editing::SHAPES);
        Self {
            text,
            scene,
            structure: Structure::Kd,
            comparison: None,
            comparison_key: (0, Structure::Kd),
            node: 0,
            axis: 0,
            show_binned: true,
            curve: None,
            selected: None,
            plot_transform: None,
        }
    }

    fn refresh(&mut self) {
        let key = (self.scene.revision, self.structure);
        if self.comparison.is_some() && self.comparison_key == key {
            return;
        }
        let comparison = Comparison::new(&self.scene, self.structure);
        let node_count = match &comparison.trees[SAH_PANE] {
            BuiltTree::Bvh(built) => built.bvh.nodes.len(),
            BuiltTree::Kd(built) => built.tree.nodes.len(),
        };
        if self.node as usize >= node_count || self.comparison_key.1 != self.structure {
            self.node = 0;
        }
        self.comparison = Some(comparison);
        self.comparison_key = key;
        self.curve = self.compute_curve();
        self.selected = None;
    }

    /// The cost curve of the selected node of the SAH tree.
    fn compute_curve(&self) -> Option<CostCurve> {
        let comparison = self.comparison.as_ref()?;
        let boxes = self.scene.scene.shapes.all_bounds();
        let cost = self.scene.scene.settings.cost();
        let bins = self.show_binned.then_some(self.scene.scene.settings.bins);
        Some(match &comparison.trees[SAH_PANE] {
            BuiltTree::Bvh(built) => {
                bvh_curve(&boxes, &built.primitives[self.node as usize], &cost, bins)
            }
            BuiltTree::Kd(built) => {
                let facts = TreeFacts::of(&built.tree);
                let (cell, primitives) = (
                    facts.bounds[self.node as usize],
                    facts.primitives_below(&built.tree, self.node),
                );
                kd_curve(&boxes, &primitives, &cell, &cost, bins)
            }
        })
    }

    /// The candidate the plot shows selected.
    pub fn selected_candidate(&self) -> Option<Candidate> {
        self.selected
    }

    /// The exact candidates on the plotted axis.
    pub fn candidates(&self) -> Vec<Candidate> {
        self.curve
            .as_ref()
            .and_then(|curve| curve.axes.get(self.axis).cloned())
            .unwrap_or_default()
    }

    /// Where a candidate was drawn in the last frame's plot.
    pub fn candidate_screen_position(&self, candidate: &Candidate) -> Option<Pos2> {
        let transform = self.plot_transform.as_ref()?;
        Some(transform.position_from_point(&PlotPoint::new(candidate.position, candidate.cost)))
    }

    fn node_box(&self) -> Option<Aabb<DVec2>> {
        match &self.comparison.as_ref()?.trees[SAH_PANE] {
            BuiltTree::Bvh(built) => Some(built.bvh.nodes[self.node as usize].bounds),
            BuiltTree::Kd(built) => Some(built.cells[self.node as usize]),
        }
    }

    fn node_children(&self) -> Option<[u32; 2]> {
        match &self.comparison.as_ref()?.trees[SAH_PANE] {
            BuiltTree::Bvh(built) => built.shape.children[self.node as usize],
            BuiltTree::Kd(built) => built.shape.children[self.node as usize],
        }
    }

    fn node_parent(&self) -> Option<u32> {
        match &self.comparison.as_ref()?.trees[SAH_PANE] {
            BuiltTree::Bvh(built) => built.shape.parent[self.node as usize],
            BuiltTree::Kd(built) => built.shape.parent[self.node as usize],
        }
    }

    fn select_node(&mut self, node: u32) {
        self.node = node;
        self.curve = self.compute_curve();
        self.selected = None;
    }

    /// The ghost of the selected candidate: its split line across the node and the two
    /// children it would make.
    fn draw_ghost(&self, canvas: &Canvas, candidate: &Candidate) {
        let Some(node_box) = self.node_box() else {
            return;
        };
        let axis = candidate.axis;
        let (left, right) = match self.structure {
            Structure::Kd => {
                let mut below = node_box;
                let mut above = node_box;
                below.max[axis] = candidate.position;
                above.min[axis] = candidate.position;
                (below, above)
            }
            Structure::Bvh => {
                // The children group the node's primitives by which side their centre is on.
                let mut left = Aabb::empty();
                let mut right = Aabb::empty();
                if let Some(Some(BuiltTree::Bvh(built))) =
                    self.comparison.as_ref().map(|c| c.trees.get(SAH_PANE))
                {
                    for &primitive in &built.primitives[self.node as usize] {
                        let bounds = self.scene.scene.shapes.bounds(primitive as usize);
                        if bounds.center()[axis] < candidate.position {
                            left = left.union(bounds);
                        } else {
                            right = right.union(bounds);
                        }
                    }
                }
                (left, right)
            }
        };
        canvas.box_outline(
            &left,
            Stroke::new(2.0, palette::X_AXIS),
            Some(faded(palette::X_AXIS, 35)),
        );
        canvas.box_outline(
            &right,
            Stroke::new(2.0, palette::Y_AXIS),
            Some(faded(palette::Y_AXIS, 35)),
        );
        canvas.split_line(
            &node_box,
            axis,
            candidate.position,
            Stroke::new(3.0, palette::CURRENT),
        );
    }

    fn plot_ui(&mut self, ui: &mut egui::Ui, height: f32) {
        let Some(curve) = &self.curve else { return };
        let axis = self.axis;
        let exact = curve.axes.get(axis).cloned().unwrap_or_default();
        let binned: Vec<Candidate> = curve
            .binned
            .as_ref()
            .and_then(|binned| binned.axes.get(axis).cloned())
            .unwrap_or_default();
        let marks = [
            ("middle", curve.middle, rule_color(0)),
            ("median", curve.median, rule_color(1)),
            ("minimum (SAH)", curve.best, rule_color(2)),
        ];
        let leaf_cost = curve.leaf_cost;
        let axis_name = ["x", "y"][axis.min(1)];
        let selected = self.selected;
        let (low, high) = exact
            .iter()
            .map(|candidate| candidate.cost)
            .chain([leaf_cost])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), cost| {
                (low.min(cost), high.max(cost))
            });
        let headroom = if high > low {
            high + (high - low) * 0.8
        } else {
            high + 1.0
        };
        let response = Plot::new("sah cost curve")
            .height(height)
            .legend(Legend::default().position(egui_plot::Corner::RightTop))
            // Headroom above the curve for the legend.
            .include_y(headroom)
            .x_axis_label(format!("split position on {axis_name}"))
            .y_axis_label("SAH cost")
            .allow_scroll(false)
            .allow_drag(false)
            .allow_zoom(false)
            .allow_double_click_reset(false)
            .show(ui, |plot| {
                // A kD plane position can carry two candidates (a primitive's end and the next
                // one's start), and candidates a hair apart would draw a spike no wider than
                // a pixel: the line runs through the cheapest of each pixel-wide group, the
                // dots show every one.
                let span = exact.last().map_or(0.0, |last| last.position)
                    - exact.first().map_or(0.0, |first| first.position);
                let merge = span * 2e-3;
                let mut lowest: Vec<[f64; 2]> = Vec::with_capacity(exact.len());
                for candidate in &exact {
                    match lowest.last_mut() {
                        Some(last) if candidate.position - last[0] <= merge => {
                            last[1] = last[1].min(candidate.cost)
                        }
                        _ => lowest.push([candidate.position, candidate.cost]),
                    }
                }
                // No name: the dots' legend entry stands for both.
                plot.line(Line::new("", PlotPoints::new(lowest)).color(palette::RAY));
                let dots: PlotPoints = exact.iter().map(|c| [c.position, c.cost]).collect();
                plot.points(
                    Points::new("every candidate (exact)", dots)
                        .radius(2.5)
                        .color(palette::RAY),
                );
                if !binned.is_empty() {
                    let bins: PlotPoints = binned.iter().map(|c| [c.position, c.cost]).collect();
                    plot.points(
                        Points::new("binned candidates", bins)
                            .shape(MarkerShape::Diamond)
                            .radius(5.0)
                            .color(palette::SPHERE),
                    );
                }
                plot.hline(HLine::new("leaf cost", leaf_cost).color(Color32::GRAY));
                for (name, mark, color) in marks {
                    if let Some(mark) = mark.filter(|mark| mark.axis == axis) {
                        plot.vline(VLine::new(name, mark.position).color(color).width(2.0));
                    }
                }
                if let Some(candidate) = selected {
                    plot.points(
                        Points::new(
                            "selected",
                            PlotPoints::new(vec![[candidate.position, candidate.cost]]),
                        )
                        .radius(7.0)
                        .color(palette::CURRENT),
                    );
                }
                plot.pointer_coordinate()
            });
        self.plot_transform = Some(response.transform);
        // Hovering picks the candidate nearest the pointer along the axis.
        if response.response.hovered()
            && let Some(pointer) = response.inner
        {
            self.selected = exact
                .iter()
                .min_by(|a, b| {
                    (a.position - pointer.x)
                        .abs()
                        .total_cmp(&(b.position - pointer.x).abs())
                })
                .copied();
        }
    }
}

/// The lecture's cost formula with a candidate's numbers filled in.
pub fn formula_text(candidate: &Candidate, curve: &CostCurve, structure: Structure) -> String {
    let cost = &curve.cost_model;
    let empty_side = candidate.count_left == 0 || candidate.count_right == 0;
    let bonus = if structure == Structure::Kd && empty_side {
        format!(" × (1 − {:.2}) for the empty side", cost.empty_bonus)
    } else {
        String::new()
    };
    format!(
        "cost = C_trav + P(L)·N_L·C_isect + P(R)·N_R·C_isect\n     = {:.2} + {:.3}·{}·{:.2} + {:.3}·{}·{:.2}{}\n     = {:.3}   (leaf: N·C_isect = {:.3})\nP(L) = SA(L)/SA(node) = {:.2}/{:.2}, P(R) = {:.2}/{:.2}",
        cost.traversal_cost,
        candidate.p_left,
        candidate.count_left,
        cost.intersection_cost,
        candidate.p_right,
        candidate.count_right,
        cost.intersection_cost,
        bonus,
        candidate.cost,
        curve.leaf_cost,
        candidate.area_left,
        curve.area,
        candidate.area_right,
        curve.area,
    )
}

impl Lesson for SplitsLesson {
    fn text(&self) -> &LessonText {
        &self.text
    }

    fn scene_mut(&mut self) -> Option<&mut EditableScene> {
        Some(&mut self.scene)
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui) {
        self.refresh();
        ui.horizontal(|ui| {
            ui.label("Compare");
            ui.selectable_value(&mut self.structure, Structure::Kd, "kD-trees");
            ui.selectable_value(&mut self.structure, Structure::Bvh, "BVHs");
        });
        ui.label(RichText::new("Cost model").strong());
        let settings = &mut self.scene.scene.settings;
        let mut changed = false;
        changed |= ui
            .add(egui::Slider::new(&mut settings.traversal_cost, 0.0..=8.0).text("C_trav"))
            .changed();
        changed |= ui
            .add(egui::Slider::new(&mut settings.intersection_cost, 0.1..=8.0).text("C_isect"))
            .changed();
        changed |= ui
            .add(egui::Slider::new(&mut settings.empty_bonus, 0.0..=0.9).text("kD empty bonus"))
            .changed();
        changed |= ui
            .add(egui::Slider::new(&mut settings.max_leaf_size, 1..=16).text("max leaf size"))
            .changed();
        ui.horizontal(|ui| {
            changed |= ui
                .checkbox(&mut self.show_binned, "binned candidates")
                .changed();
            changed |= ui
                .add_enabled(
                    self.show_binned,
                    egui::Slider::new(&mut settings.bins, 2..=32).text("bins"),
                )
                .changed();
        });
        if changed {
            self.scene.touch();
        }
        self.refresh();
        ui.separator();
        ui.label(RichText::new("Node").strong());
        ui.horizontal(|ui| {
            ui.label("plot axis");
            let before = self.axis;
            ui.selectable_value(&mut self.axis, 0, "x");
            ui.selectable_value(&mut self.axis, 1, "y");
            if before != self.axis {
                self.selected = None;
            }
        });
        ui.horizontal(|ui| {
            if ui.button("root").clicked() {
                self.select_node(0);
            }
            if let Some(parent) = self.node_parent()
                && ui.button("parent").clicked()
            {
                self.select_node(parent);
            }
            if let Some([left, right]) = self.node_children() {
                if ui.button("left child").clicked() {
                    self.select_node(left);
                }
                if ui.button("right child").clicked() {
                    self.select_node(right);
                }
            }
        });
        if let Some(curve) = &self.curve {
            ui.label(format!(
                "node {}: {} primitives, leaf cost {:.3}; best split {}",
                self.node,
                curve.count,
                curve.leaf_cost,
                match curve.best {
                    Some(best) => format!(
                        "on {} at {:.3}, cost {:.3}",
                        ["x", "y"][best.axis.min(1)],
                        best.position,
                        best.cost
                    ),
                    None => "none".to_owned(),
                }
            ));
            let shown = self.selected.or_else(|| {
                let best = curve.best?;
                curve
                    .axes
                    .get(best.axis)?
                    .iter()
                    .find(|c| c.position == best.position)
                    .copied()
            });
            if let Some(candidate) = shown {
                ui.label(
                    RichText::new(if self.selected.is_some() {
                        "The hovered split"
                    } else {
                        "The best split"
                    })
                    .strong(),
                );
                ui.label(
                    RichText::new(formula_text(&candidate, curve, self.structure))
                        .monospace()
                        .size(11.5),
                );
            }
        }
        ui.label(
            RichText::new("Hover the plot to pick a candidate: its split and children are ghosted in the SAH pane.")
                .small()
                .weak(),
        );
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.scene.toolbar_ui(ui);
        self.refresh();
        let pane_height = (ui.available_height() * 0.55).max(120.0);
        let Some(comparison) = self.comparison.take() else {
            return;
        };
        let canvases = comparison.panes_ui(ui, &mut self.scene, pane_height);
        self.comparison = Some(comparison);
        // The selected node, and the ghost of the selected candidate, in the SAH pane.
        if let (Some(canvas), Some(node_box)) = (canvases.get(SAH_PANE), self.node_box()) {
            canvas.box_outline(&node_box, Stroke::new(2.5, Color32::WHITE), None);
            if let Some(candidate) = self.selected {
                self.draw_ghost(canvas, &candidate);
            }
        }
        let mut changed = false;
        for canvas in &canvases {
            changed |= self.scene.interact(ui, canvas);
        }
        if changed {
            self.refresh();
        }
        ui.add_space(4.0);
        let plot_height = (ui.available_height() - 8.0).max(80.0);
        ui.allocate_ui(Vec2::new(ui.available_width(), plot_height), |ui| {
            self.plot_ui(ui, plot_height)
        });
    }
}
