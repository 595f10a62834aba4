//! Lesson 5, "kD-Tree" and "Traversing a kD-tree": split lines and cells, and the core's kD
//! traversal stepped with the line of the lecture's pseudo-code it is on, and the ray clipped
//! to the near and the far side drawn (the segments are the ones the traversal reports through
//! `Observer::cell_entered`).

use accelviz_core::kd::KdTree;
use accelviz_core::{Aabb, Order, Step, TreeStats};
use egui::{Color32, RichText, Stroke};
use glam::DVec2;

use super::common::{self, KdRule, Recording, number};
use super::tree_diagram::TreeShape;
use super::{Lesson, LessonText};
use crate::canvas::{Canvas, depth_color, faded, palette};
use crate::editor::{EditableScene, Editing};
use crate::timeline::Timeline;

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

/// The colour of the part of the ray on the near side, and on the far side.
const NEAR_COLOR: Color32 = Color32::from_rgb(80, 170, 255);
const FAR_COLOR: Color32 = Color32::from_rgb(200, 120, 255);

/// A built kD-tree with each node's cell, parent and depth.
pub struct BuiltKd {
    /// The tree.
    pub tree: KdTree<DVec2>,
    /// Each node's cell.
    pub cells: Vec<Aabb<DVec2>>,
    /// Its shape, for the diagram.
    pub shape: TreeShape,
}

impl BuiltKd {
    /// Builds with `rule` and finds every node's cell.
    pub fn new(scene: &EditableScene, rule: KdRule) -> Self {
        Self::with_tree(rule.build(&scene.scene.shapes, &scene.scene.settings))
    }

    /// Cells, depths and parents of a built tree.
    pub fn with_tree(tree: KdTree<DVec2>) -> Self {
        let children = tree
            .nodes
            .iter()
            .map(|node| (!node.is_leaf()).then(|| node.children()))
            .collect();
        let shape = TreeShape::new(children);
        let mut cells = vec![tree.bounds; tree.nodes.len()];
        // Parents come before their children, so one forward pass cuts every cell.
        for index in 0..tree.nodes.len() {
            let node = &tree.nodes[index];
            if !node.is_leaf() {
                let [below, above] = node.children();
                let [below_cell, above_cell] = KdTree::child_cells(node, &cells[index]);
                cells[below as usize] = below_cell;
                cells[above as usize] = above_cell;
            }
        }
        Self { tree, cells, shape }
    }

    /// Draws the cells: the root cell, and each node's split line across its cell, coloured by
    /// depth; `emphasized`'s line thicker.
    pub fn draw_splits(&self, canvas: &Canvas, emphasized: Option<u32>) {
        canvas.box_outline(&self.tree.bounds, Stroke::new(1.5, depth_color(0)), None);
        let interior: Vec<usize> = (0..self.tree.nodes.len())
            .filter(|&index| !self.tree.nodes[index].is_leaf())
            .collect();
        canvas.split_lines(interior.into_iter().map(|index| {
            let node = &self.tree.nodes[index];
            let width = if emphasized == Some(index as u32) {
                3.0
            } else {
                1.5
            };
            let stroke = Stroke::new(width, depth_color(self.shape.depth[index] + 1));
            (self.cells[index], node.axis as usize, node.split, stroke)
        }));
    }

    /// Whether `node` is its parent's near child for a ray going `direction`: the child the
    /// ray meets first (below the plane when it moves up the axis).
    pub fn is_near_child(&self, node: u32, direction: DVec2) -> Option<bool> {
        let parent = self.shape.parent[node as usize]?;
        let parent_node = &self.tree.nodes[parent as usize];
        let [below, _] = parent_node.children();
        let moves_up = direction[parent_node.axis as usize] >= 0.0;
        Some((node == below) == moves_up)
    }
}

/// The pseudo-code lines a step is on, and what it means there.
fn code_position(step: &Step<f64>, built: &BuiltKd, direction: DVec2) -> (Vec<usize>, String) {
    match *step {
        Step::BoxTested { hit, .. } => (
            vec![0],
            if hit {
                "clip the ray to the root cell: it is not empty".to_owned()
            } else {
                "the ray misses the root cell: empty, return".to_owned()
            },
        ),
        Step::CellEntered {
            node,
            t_near,
            t_far,
        } => {
            let segment = format!("t in [{}, {}]", number(t_near), number(t_far));
            match built.is_near_child(node, direction) {
                None => (
                    vec![0],
                    format!("start at the root with the ray clipped to its cell, {segment}"),
                ),
                Some(true) => (
                    vec![4, 5],
                    format!("near side first: node {node}, rayNear is {segment}"),
                ),
                Some(false) => (
                    vec![6, 7, 8],
                    format!("no hit before the plane: far side, node {node}, rayFar is {segment}"),
                ),
            }
        }
        Step::NodeCulled {
            node,
            t_enter,
            t_closest,
        } => (
            vec![6],
            format!(
                "a hit at t = {} comes before the far part starts (t = {}): skip node {node}",
                number(t_closest),
                number(t_enter)
            ),
        ),
        Step::PrimitiveTested { primitive, t_hit } => (
            vec![2],
            match t_hit {
                Some(t) => format!("leaf: primitive {primitive} hit at t = {}", number(t)),
                None => format!("leaf: primitive {primitive} missed"),
            },
        ),
        Step::ClosestHitUpdated { primitive, t } => (
            vec![2],
            format!(
                "closest hit so far: primitive {primitive} at t = {}",
                number(t)
            ),
        ),
        Step::NodeEntered { node } => (vec![0], format!("enter node {node}")),
        Step::PrimitiveSkipped { primitive } => {
            (vec![2], format!("primitive {primitive} already tested"))
        }
        Step::CellMissed { node } => (vec![1], format!("node {node}: empty(ray), return")),
    }
}

/// The lesson.
pub struct KdLesson {
    text: LessonText,
    scene: EditableScene,
    rule: KdRule,
    built: Option<BuiltKd>,
    built_key: (u64, KdRule),
    recording: Recording,
    timeline: Timeline,
    hovered: Option<u32>,
    selected: Option<u32>,
}

impl KdLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let scene = EditableScene::new(text.scene.clone(), Editing::ALL);
        Self {
            text,
            scene,
            rule: KdRule::Middle,
            built: None,
            built_key: (0, KdRule::Middle),
            recording: Recording::default(),
            timeline: Timeline::default(),
            hovered: None,
            selected: None,
        }
    }

    fn refresh(&mut self) {
        let key = (self.scene.revision, self.rule);
        if self.built.is_some() && self.built_key == key {
            return;
        }
        let built = BuiltKd::new(&self.scene, self.rule);
        self.recording = match self.scene.ray() {
            Ok(ray) => common::record_kd(
                &built.tree,
                &self.scene.scene.shapes,
                &ray,
                Order::NearFirst,
            ),
            Err(_) => Recording::default(),
        };
        self.timeline.set_len(self.recording.steps.len());
        self.selected = None;
        self.hovered = None;
        self.built = Some(built);
        self.built_key = key;
    }

    fn shown(&self) -> &[Step<f64>] {
        &self.recording.steps[..self.timeline.shown.min(self.recording.steps.len())]
    }

    fn direction(&self) -> DVec2 {
        self.scene
            .ray()
            .map(|ray| ray.direction)
            .unwrap_or(DVec2::X)
    }
}

impl Lesson for KdLesson {
    fn text(&self) -> &LessonText {
        &self.text
    }

    fn scene_mut(&mut self) -> Option<&mut EditableScene> {
        Some(&mut self.scene)
    }

    fn timeline(&mut self) -> Option<(&mut Timeline, String)> {
        self.refresh();
        let caption = match (self.shown().last(), &self.built) {
            (Some(step), Some(built)) => code_position(step, built, self.direction()).1,
            _ => "Press step: intersectKDTree(ray, root) begins.".to_owned(),
        };
        Some((&mut self.timeline, caption))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui) {
        self.refresh();
        ui.horizontal(|ui| {
            ui.label("Build with");
            for rule in [KdRule::Middle, KdRule::Median, KdRule::Sah] {
                ui.selectable_value(&mut self.rule, rule, rule.label());
            }
        });
        let mut leaf_size = self.scene.scene.settings.max_leaf_size;
        if ui
            .add(egui::Slider::new(&mut leaf_size, 1..=8).text("max leaf size"))
            .changed()
        {
            self.scene.scene.settings.max_leaf_size = leaf_size;
            self.scene.touch();
        }
        self.refresh();
        let Some(built) = &self.built else { return };
        ui.separator();
        ui.heading("The traversal, line by line");
        let current = self
            .shown()
            .last()
            .map(|step| code_position(step, built, self.direction()).0)
            .unwrap_or_default();
        egui::Frame::new()
            .fill(ui.visuals().extreme_bg_color)
            .inner_margin(6.0)
            .show(ui, |ui| {
                for (line, code) in PSEUDO_CODE.iter().enumerate() {
                    let mut text = RichText::new(*code).monospace().size(11.5);
                    if current.contains(&line) {
                        text = text.background_color(faded(palette::CURRENT, 90)).strong();
                    }
                    ui.add(egui::Label::new(text).wrap_mode(egui::TextWrapMode::Extend));
                }
            });
        ui.separator();
        let stats = TreeStats::of(&built.tree, &self.scene.scene.settings.cost());
        ui.label(format!(
            "{} nodes, {} leaves, depth {}, {} primitive references for {} primitives (straddlers are in both cells), SAH cost {:.2}",
            stats.node_count,
            stats.leaf_count,
            stats.max_depth,
            built.tree.primitive_indices.len(),
            self.scene.scene.shapes.shapes.len(),
            stats.sah_cost
        ));
        let shown = self.shown();
        let emphasis = common::traversal_emphasis(shown, built.tree.nodes.len());
        let hovered = built.shape.ui(
            ui,
            |node| match built.tree.nodes[node as usize].is_leaf() {
                true => format!("{} prims", built.tree.nodes[node as usize].count),
                false => {
                    let entry = &built.tree.nodes[node as usize];
                    format!(
                        "{} = {:.1}",
                        ["x", "y"][entry.axis as usize % 2],
                        entry.split
                    )
                }
            },
            |node| emphasis[node as usize],
            self.hovered,
            &mut self.selected,
        );
        if hovered.is_some() {
            self.hovered = hovered;
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let canvas = self.scene.canvas_ui(ui, None);
        self.refresh();
        let Some(built) = &self.built else { return };
        let shown = &self.recording.steps[..self.timeline.shown.min(self.recording.steps.len())];
        // The leaf cell under the pointer lights up (and its node in the tree).
        if canvas.response.hovered() {
            self.hovered = canvas.response.hover_pos().and_then(|pos| {
                let at = canvas.to_world(pos);
                (0..built.tree.nodes.len() as u32).find(|&node| {
                    built.tree.nodes[node as usize].is_leaf()
                        && built.cells[node as usize].contains_point(at)
                })
            });
        }
        for node in [self.hovered, self.selected].into_iter().flatten() {
            canvas.box_outline(
                &built.cells[node as usize],
                Stroke::new(2.0, palette::CURRENT),
                Some(faded(palette::CURRENT, 30)),
            );
        }
        common::draw_tested_shapes(ui, &canvas, &self.scene.scene.shapes, shown, None);
        // The hovered cell's plane (its parent's) stands out.
        built.draw_splits(
            &canvas,
            self.hovered
                .and_then(|node| built.shape.parent[node as usize]),
        );
        let Ok(ray) = self.scene.ray() else {
            canvas.caption(&[(
                "No ray: drag its head away from its origin".to_owned(),
                palette::MISS,
            )]);
            return;
        };
        common::draw_ray(&canvas, &ray, common::closest_so_far(shown).map(|(_, t)| t));
        // The segments so far, and the current one split at its plane into near and far.
        let current_cell = shown.iter().rev().find_map(|step| match *step {
            Step::CellEntered {
                node,
                t_near,
                t_far,
            } => Some((node, t_near, t_far)),
            _ => None,
        });
        let along = (canvas.to_screen(ray.origin + ray.direction) - canvas.to_screen(ray.origin))
            .normalized();
        let side = egui::Vec2::new(-along.y, along.x) * 7.0;
        let segment = |t_from: f64, t_to: f64, color: Color32, width: f32| {
            let t_to = canvas.clip_t(ray.origin, ray.direction, t_to);
            if t_from <= t_to {
                canvas.painter.line_segment(
                    [
                        canvas.to_screen(ray.at(t_from)) + side,
                        canvas.to_screen(ray.at(t_to)) + side,
                    ],
                    Stroke::new(width, color),
                );
            }
        };
        if let Some((node, t_near, t_far)) = current_cell {
            let entry = &built.tree.nodes[node as usize];
            canvas.box_outline(
                &built.cells[node as usize],
                Stroke::new(3.0, palette::CURRENT),
                None,
            );
            if entry.is_leaf() {
                let near = built.is_near_child(node, ray.direction).unwrap_or(true);
                segment(
                    t_near,
                    t_far,
                    if near { NEAR_COLOR } else { FAR_COLOR },
                    5.0,
                );
            } else {
                // Where the ray crosses this node's plane splits its part into rayNear, rayFar.
                let axis = entry.axis as usize;
                let t_plane = (entry.split - ray.origin[axis]) / ray.direction[axis];
                let t_cut = t_plane.clamp(t_near, t_far);
                segment(
                    t_near,
                    if t_plane.is_nan() { t_far } else { t_cut },
                    NEAR_COLOR,
                    5.0,
                );
                if t_plane.is_finite() && t_plane < t_far && t_plane > t_near {
                    segment(t_cut, t_far, FAR_COLOR, 5.0);
                }
            }
            canvas.ray_mark(ray.origin, ray.direction, t_near, palette::CURRENT, "", 0.0);
            canvas.ray_mark(ray.origin, ray.direction, t_far, palette::CURRENT, "", 0.0);
        }
        self.scene.draw_handles(&canvas);
        canvas.caption(&[
            (
                "rayNear: the part of the ray on the near side".to_owned(),
                NEAR_COLOR,
            ),
            ("rayFar: the part on the far side".to_owned(), FAR_COLOR),
        ]);
    }
}
