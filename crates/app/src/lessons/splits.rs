//! Lesson 7, "Building good kD-trees" to "Surface Area Heuristic": middle, median and SAH
//! side by side (kD-trees or BVHs, each the catalogue's structure for that rule), and the SAH
//! cost of every candidate split of a node (the core's cost curve: the builders' own sweep and
//! the shared `SahCost`, so the curve's minimum is the split the SAH builder made). Hovering a
//! candidate selects it and ghosts its split in the SAH pane. Where a rule cuts on the other
//! axis than the one plotted, its cost still shows, as a dashed level.

use accelviz_core::curve::{Candidate, CostCurve, Mark, node_curve};
use accelviz_core::format::number;
use accelviz_core::{Aabb, Family, PrimitiveSet, SplitRule, Structure};
use egui::{Color32, Pos2, RichText, Stroke, Vec2};
use egui_plot::{
    HLine, Legend, Line, LineStyle, MarkerShape, Plot, PlotPoint, PlotPoints, PlotTransform,
    Points, VLine,
};

use crate::background::Derived;
use crate::canvas::{Canvas, faded, palette};
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage};
use crate::views::compare::{
    Comparison, LECTURE_RULES as RULES, comparison_ui, request_comparison, rule_color,
};

/// The SAH pane: where the selected node lives.
const SAH_PANE: usize = 2;

/// The axis names.
const AXES: [&str; 2] = ["x", "y"];

/// The most candidates the cost plot draws a dot each (see `plot_ui`).
const MOST_DOTS: usize = 4_000;

/// The lesson.
pub struct SplitsLesson {
    stage: Stage,
    family: Family,
    comparison: Derived<(u64, Family), Comparison>,
    /// The node whose candidates are plotted, in the SAH tree.
    node: u32,
    /// The axis plotted (0 = x, 1 = y).
    axis: usize,
    /// Whether binned candidates are overlaid.
    show_binned: bool,
    /// The node's cost curve, for the comparison, node and binning it is of.
    /// The plotted node's cost curve, made aside when the node is large (the root of 100,000
    /// shapes takes a tenth of a second): (comparison, node, bins).
    curve: Derived<(u64, u32, Option<usize>), CostCurve>,
    /// The curve (its generation) the selection was made on.
    curve_shown: u64,
    /// The candidate under the pointer in the plot (hovering selects it).
    selected: Option<Candidate>,
    plot_transform: Option<PlotTransform>,
}

impl SplitsLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::SHAPES),
            family: Family::Kd,
            comparison: Derived::default(),
            node: 0,
            axis: 0,
            show_binned: true,
            curve: Derived::default(),
            curve_shown: 0,
            selected: None,
            plot_transform: None,
        }
    }

    /// The SAH tree (pane 3), if built.
    fn sah_tree(&self) -> Option<&SceneTree> {
        self.comparison.get()?.trees.get(SAH_PANE)
    }

    /// The candidate the plot shows selected.
    pub fn selected_candidate(&self) -> Option<Candidate> {
        self.selected
    }

    /// The exact candidates on the plotted axis.
    pub fn candidates(&self) -> Vec<Candidate> {
        self.curve
            .get()
            .and_then(|curve| curve.axes.get(self.axis).cloned())
            .unwrap_or_default()
    }

    /// Where a candidate was drawn in the last frame's plot.
    pub fn candidate_screen_position(&self, candidate: &Candidate) -> Option<Pos2> {
        let transform = self.plot_transform.as_ref()?;
        Some(transform.position_from_point(&PlotPoint::new(candidate.position, candidate.cost)))
    }

    /// Shows the curve of `axis` (0 = x).
    pub fn set_axis(&mut self, axis: usize) {
        if axis != self.axis {
            self.axis = axis.min(1);
            self.selected = None;
        }
    }

    fn select_node(&mut self, node: u32) {
        self.node = node;
        self.selected = None;
    }

    fn plot_ui(&mut self, ui: &mut egui::Ui, height: f32) {
        let Some(curve) = self.curve.get() else {
            return;
        };
        let axis = self.axis;
        let exact = curve.axes.get(axis).cloned().unwrap_or_default();
        let binned: Vec<Candidate> = curve
            .binned
            .as_ref()
            .and_then(|binned| binned.axes.get(axis).cloned())
            .unwrap_or_default();
        let marks: [(&str, Option<Mark>, Color32); 3] = [
            ("middle", curve.middle, rule_color(SplitRule::Middle)),
            ("median", curve.median, rule_color(SplitRule::Median)),
            ("minimum (SAH)", curve.best, rule_color(SplitRule::Sah)),
        ];
        let leaf_cost = curve.leaf_cost;
        let axis_name = AXES[axis.min(1)];
        let selected = self.selected;
        let (low, high) = exact
            .iter()
            .map(|candidate| candidate.cost)
            .chain([leaf_cost])
            .chain(
                marks
                    .iter()
                    .filter_map(|(_, mark, _)| mark.map(|mark| mark.cost)),
            )
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), cost| {
                (low.min(cost), high.max(cost))
            });
        // Room above the curve for the legend (top right): as much of the plot's height as
        // the legend's rows take at the text size of the moment (lecture mode's is larger),
        // so the legend never covers the curve.
        let legend_rows = 6.0;
        let row = ui.text_style_height(&egui::TextStyle::Body);
        let legend_height = legend_rows * row * 1.2 + 24.0;
        // Of the plot's height, the x axis's numbers and label take about three rows.
        let data_height = (height - 3.0 * row).max(1.0);
        let legend_share = f64::from((legend_height / data_height).clamp(0.1, 0.7));
        let headroom = if high > low {
            low + (high - low) / (1.0 - legend_share)
        } else {
            high + 1.0
        };
        let plot_bg = ui.visuals().extreme_bg_color;
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
                // Up to a few thousand candidates a dot each; beyond (a root of 100,000
                // shapes has 200,000), a dot for each pixel-wide group's cheapest, as the line
                // has: 200,000 dots took egui a tenth of a second a frame to draw.
                let (dots, dots_name): (PlotPoints, &str) = if exact.len() <= MOST_DOTS {
                    (
                        exact.iter().map(|c| [c.position, c.cost]).collect(),
                        "every candidate (exact)",
                    )
                } else {
                    (
                        PlotPoints::new(lowest.clone()),
                        "exact candidates (cheapest a pixel)",
                    )
                };
                // No name: the dots' legend entry stands for both.
                plot.line(
                    Line::new("", PlotPoints::new(lowest))
                        .color(crate::canvas::ink_on(palette::RAY, plot_bg)),
                );
                plot.points(
                    Points::new(dots_name, dots)
                        .radius(2.5)
                        .color(crate::canvas::ink_on(palette::RAY, plot_bg)),
                );
                if !binned.is_empty() {
                    let bins: PlotPoints = binned.iter().map(|c| [c.position, c.cost]).collect();
                    plot.points(
                        Points::new("binned candidates", bins)
                            .shape(MarkerShape::Diamond)
                            .radius(5.0)
                            .color(crate::canvas::ink_on(palette::SPHERE, plot_bg)),
                    );
                }
                plot.hline(HLine::new("leaf cost", leaf_cost).color(Color32::GRAY));
                for (name, mark, color) in marks {
                    let Some(mark) = mark else { continue };
                    if mark.axis == axis {
                        plot.vline(VLine::new(name, mark.position).color(color).width(2.0));
                    } else {
                        // The rule cuts the other axis: its cost still compares, as a level.
                        plot.hline(
                            HLine::new(
                                format!(
                                    "{name}: cuts {} at {}, cost {}",
                                    AXES[mark.axis.min(1)],
                                    number(mark.position),
                                    number(mark.cost)
                                ),
                                mark.cost,
                            )
                            .color(color)
                            .style(LineStyle::dashed_loose())
                            .width(2.0),
                        );
                    }
                }
                if let Some(candidate) = selected {
                    plot.points(
                        Points::new(
                            "selected",
                            PlotPoints::new(vec![[candidate.position, candidate.cost]]),
                        )
                        .radius(7.0)
                        .color(crate::canvas::ink_on(palette::CURRENT, plot_bg)),
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

/// The ghost of the selected candidate: its split line across the node and the two
/// children it would make.
fn draw_ghost(canvas: &Canvas, tree: &SceneTree, family: Family, node: u32, candidate: &Candidate) {
    let node_box = tree.built.facts.bounds[node as usize];
    let axis = candidate.axis;
    let (left, right) = match family {
        // A grid's cell cut as a kD cell would be.
        Family::Kd | Family::Grid | Family::HashedGrid | Family::Octree => {
            let mut below = node_box;
            let mut above = node_box;
            below.max[axis] = candidate.position;
            above.min[axis] = candidate.position;
            (below, above)
        }
        Family::Bvh => {
            // The children group the node's primitives by which side their centre is on.
            let mut left = Aabb::empty();
            let mut right = Aabb::empty();
            for primitive in tree.built.primitives_below(node) {
                let bounds = tree.shapes.bounds(primitive as usize);
                if bounds.center()[axis] < candidate.position {
                    left = left.union(bounds);
                } else {
                    right = right.union(bounds);
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

/// The lecture's cost formula with a candidate's numbers filled in.
pub fn formula_text(candidate: &Candidate, curve: &CostCurve, family: Family) -> String {
    let cost = &curve.cost_model;
    let empty_side = candidate.count_left == 0 || candidate.count_right == 0;
    let bonus = if family == Family::Kd && empty_side {
        format!(" × (1 − {}) for the empty side", number(cost.empty_bonus))
    } else {
        String::new()
    };
    format!(
        "cost = C_trav + P(L)·N_L·C_isect + P(R)·N_R·C_isect\n     = {} + {}·{}·{} + {}·{}·{}{}\n     = {}   (leaf: N·C_isect = {})\nP(L) = SA(L)/SA(node) = {}/{}, P(R) = {}/{}",
        number(cost.traversal_cost),
        number(candidate.p_left),
        candidate.count_left,
        number(cost.intersection_cost),
        number(candidate.p_right),
        candidate.count_right,
        number(cost.intersection_cost),
        bonus,
        number(candidate.cost),
        number(curve.leaf_cost),
        number(candidate.area_left),
        number(curve.area),
        number(candidate.area_right),
        number(curve.area),
    )
}

impl Lesson for SplitsLesson {
    crate::staged!(comparison);

    fn share(&self) -> Vec<(String, String)> {
        vec![("family".to_owned(), self.family.name().to_owned())]
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        match key {
            "family" => {
                self.family = Family::from_name(value)
                    .ok_or_else(|| format!("family '{value}' is not 'bvh' or 'kd'"))?;
                Ok(())
            }
            _ => Err(format!("this lesson keeps no '{key}'")),
        }
    }

    fn update(&mut self) {
        let scene = &self.stage.scene;
        let family = self.family;
        let structures = RULES.map(|rule| Structure::lecture(family, rule));
        request_comparison(&mut self.comparison, scene, family, structures);
        let generation = self.comparison.generation();
        let Some(comparison) = self.comparison.get().cloned() else {
            return;
        };
        let Some(tree) = comparison.trees.get(SAH_PANE) else {
            return;
        };
        if self.node as usize >= tree.built.facts.node_count() {
            self.node = 0;
        }
        let node = self.node;
        let bins = self.show_binned.then_some(tree.settings.bins);
        // The scene's size stands for the node's (at most that): it decides only whether the
        // curve is made aside.
        let size = tree.shapes.shapes.len();
        self.curve.request(&(generation, node, bins), size, || {
            move || {
                let tree = &comparison.trees[SAH_PANE];
                let boxes = tree.shapes.all_bounds();
                node_curve(&tree.built, node, &boxes, &tree.settings.cost(), bins)
            }
        });
        if self.curve.generation() != self.curve_shown {
            self.curve_shown = self.curve.generation();
            self.selected = None;
        }
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        ui.horizontal(|ui| {
            ui.label("Compare");
            for family in [Family::Kd, Family::Bvh] {
                if ui
                    .selectable_label(self.family == family, format!("{}s", family.label()))
                    .clicked()
                {
                    self.family = family;
                    self.select_node(0);
                }
            }
        });
        ui.label(RichText::new("Cost model").strong());
        let settings = &mut self.stage.scene.scene.settings;
        let mut changed = false;
        changed |= ui
            .add(egui::Slider::new(&mut settings.traversal_cost, 0.0..=8.0).text("C_trav"))
            .changed();
        changed |= ui
            .add(egui::Slider::new(&mut settings.intersection_cost, 0.1..=8.0).text("C_isect"))
            .changed();
        if self.family == Family::Kd {
            changed |= ui
                .add(egui::Slider::new(&mut settings.empty_bonus, 0.0..=0.9).text("empty bonus"))
                .on_hover_text(
                    "kD-trees only: how much cheaper a cut that leaves one side empty counts",
                )
                .changed();
        }
        changed |= ui
            .add(egui::Slider::new(&mut settings.max_leaf_size, 1..=16).text("max leaf size"))
            .changed();
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.show_binned, "binned candidates");
            changed |= ui
                .add_enabled(
                    self.show_binned,
                    egui::Slider::new(&mut settings.bins, 2..=32).text("bins"),
                )
                .changed();
        });
        if changed {
            self.stage.scene.touch();
        }
        ui.separator();
        ui.label(RichText::new("Node of the SAH tree").strong());
        ui.horizontal(|ui| {
            ui.label("plot axis");
            for (axis, name) in AXES.iter().enumerate() {
                if ui.selectable_label(self.axis == axis, *name).clicked() {
                    self.set_axis(axis);
                }
            }
        });
        let Some(tree) = self.sah_tree() else {
            ui.label("Building…");
            return;
        };
        let facts = &tree.built.facts;
        let parent = facts.parent.get(self.node as usize).copied().flatten();
        let children = facts.children.get(self.node as usize).copied().flatten();
        let mut go_to = None;
        ui.horizontal(|ui| {
            if ui.button("root").clicked() {
                go_to = Some(0);
            }
            if let Some(parent) = parent
                && ui.button("parent").clicked()
            {
                go_to = Some(parent);
            }
            if let Some([left, right]) = children.and_then(|children| children.as_pair()) {
                if ui.button("left child").clicked() {
                    go_to = Some(left);
                }
                if ui.button("right child").clicked() {
                    go_to = Some(right);
                }
            }
        });
        let path = facts.path_to(self.node);
        let reason = facts.leaf_reason(self.node);
        if let Some(node) = go_to {
            self.select_node(node);
        }
        if let Some(curve) = self.curve.get() {
            ui.label(format!(
                "node {} ({}): {} primitives, leaf cost {}; best split {}",
                self.node,
                if path.is_empty() {
                    "root".to_owned()
                } else {
                    path
                },
                curve.count,
                number(curve.leaf_cost),
                match curve.best {
                    Some(best) => format!(
                        "on {} at {}, cost {}",
                        AXES[best.axis.min(1)],
                        number(best.position),
                        number(best.cost)
                    ),
                    None => "none".to_owned(),
                }
            ));
            if let Some(reason) = reason {
                ui.label(format!("The SAH builder made it a leaf: {reason}."));
            }
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
                ui.label(RichText::new(formula_text(&candidate, curve, self.family)).monospace());
            }
        }
        ui.label(
            RichText::new("Hover the plot to pick a candidate: its split and children are ghosted in the SAH pane. A rule that cuts the other axis shows as a dashed level.")
                .small()
                .weak(),
        );
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.stage.scene.toolbar_ui(ui);
        let pane_height = (ui.available_height() * 0.6).max(120.0);
        let node = self.node;
        let selected = self.selected;
        let family = self.family;
        comparison_ui(
            ui,
            &self.comparison,
            &mut self.stage.scene,
            pane_height,
            3,
            |pane| rule_color(RULES[pane]),
            |pane, tree, canvas| {
                // The selected node, and the ghost of the selected candidate, in the SAH pane.
                if pane == SAH_PANE
                    && let Some(node_box) = tree.built.facts.bounds.get(node as usize)
                {
                    canvas.box_outline(node_box, Stroke::new(3.0, Color32::WHITE), None);
                    if let Some(candidate) = selected {
                        draw_ghost(canvas, tree, family, node, &candidate);
                    }
                }
            },
        );
        ui.add_space(4.0);
        let plot_height = (ui.available_height() - 8.0).max(80.0);
        ui.allocate_ui(Vec2::new(ui.available_width(), plot_height), |ui| {
            self.plot_ui(ui, plot_height)
        });
    }
}
