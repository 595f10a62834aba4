//! Lesson 4, "Bounding Volume Hierarchy": boxes of boxes. The lecture's picture as a scene (r1
//! tests A+B, then A and B; r2 tests C and D+E, then D and E), boxes coloured by depth with a
//! depth range, a tree diagram linked to the canvas both ways, a node inspector (bounds,
//! primitives, SAH cost, why it is a leaf), and the traversal stepped.

use accelviz_core::bvh::Bvh;
use accelviz_core::curve::{CostCurve, bvh_curve};
use accelviz_core::{Order, PrimitiveSet, Step};
use egui::{Color32, Stroke};
use glam::DVec2;

use super::common::{self, BvhRule, Recording};
use super::tree_diagram::TreeShape;
use super::{Lesson, LessonText};
use crate::canvas::{BATCH_ABOVE, Batch, depth_color, faded, palette};
use crate::editor::{EditableScene, Editing};
use crate::timeline::Timeline;

/// A built BVH with what the views need about each node.
pub struct BuiltBvh {
    /// The tree.
    pub bvh: Bvh<DVec2>,
    /// Its shape, for the diagram.
    pub shape: TreeShape,
    /// Every primitive under each node.
    pub primitives: Vec<Vec<u32>>,
}

impl BuiltBvh {
    /// Builds with `rule` and gathers per-node facts.
    pub fn new(scene: &EditableScene, rule: BvhRule) -> Self {
        let bvh = rule.build(&scene.scene.shapes, &scene.scene.settings);
        let children = bvh
            .nodes
            .iter()
            .map(|node| (!node.is_leaf()).then(|| node.children()))
            .collect();
        let shape = TreeShape::new(children);
        let mut primitives = vec![Vec::new(); bvh.nodes.len()];
        // Children come after their parent, so a backward pass sees children first.
        for node in (0..bvh.nodes.len()).rev() {
            primitives[node] = match shape.children[node] {
                None => bvh.leaf_primitives(&bvh.nodes[node]).to_vec(),
                Some([left, right]) => {
                    let mut both = primitives[left as usize].clone();
                    both.extend_from_slice(&primitives[right as usize]);
                    both
                }
            };
        }
        Self {
            bvh,
            shape,
            primitives,
        }
    }

    /// The SAH cost of the subtree at `node`, relative to the node (the builder's model).
    pub fn subtree_cost(&self, node: u32, cost: &accelviz_core::SahCost) -> f64 {
        let entry = &self.bvh.nodes[node as usize];
        match self.shape.children[node as usize] {
            None => cost.leaf_cost(entry.count as usize),
            Some(children) => {
                let area = entry.bounds.area().max(f64::MIN_POSITIVE);
                cost.traversal_cost
                    + children
                        .iter()
                        .map(|&child| {
                            self.bvh.nodes[child as usize].bounds.area() / area
                                * self.subtree_cost(child, cost)
                        })
                        .sum::<f64>()
            }
        }
    }
}

/// A name for primitive `index`: a letter in small scenes (as on the slide), else a number.
pub fn primitive_name(index: u32, count: usize) -> String {
    if count <= 26 {
        char::from(b'A' + index as u8).to_string()
    } else {
        index.to_string()
    }
}

/// A node's name: its primitives joined with "+" in small scenes ("D+E"), else "node N".
pub fn node_name(built: &BuiltBvh, node: u32, count: usize) -> String {
    let primitives = &built.primitives[node as usize];
    if count > 26 {
        return format!("node {node}");
    }
    let mut letters: Vec<String> = primitives
        .iter()
        .map(|&p| primitive_name(p, count))
        .collect();
    letters.sort();
    if letters.len() > 4 {
        letters.truncate(3);
        letters.push("…".to_owned());
    }
    letters.join("+")
}

/// The lesson.
pub struct BvhLesson {
    text: LessonText,
    scene: EditableScene,
    rule: BvhRule,
    built: Option<BuiltBvh>,
    built_revision: u64,
    built_rule: BvhRule,
    recording: Recording,
    timeline: Timeline,
    depth_range: (usize, usize),
    hovered: Option<u32>,
    selected: Option<u32>,
    /// The selected node's cost curve (for "why it is a leaf"), kept until the tree or the
    /// selection changes.
    node_curve: Option<(u32, CostCurve)>,
}

impl BvhLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let scene = EditableScene::new(text.scene.clone(), Editing::ALL);
        Self {
            text,
            scene,
            rule: BvhRule::Sah,
            built: None,
            built_revision: 0,
            built_rule: BvhRule::Sah,
            recording: Recording::default(),
            timeline: Timeline::default(),
            depth_range: (0, usize::MAX),
            hovered: None,
            selected: Some(0),
            node_curve: None,
        }
    }

    fn refresh(&mut self) {
        if self.built.is_some()
            && self.built_revision == self.scene.revision
            && self.built_rule == self.rule
        {
            return;
        }
        let built = BuiltBvh::new(&self.scene, self.rule);
        self.recording = match self.scene.ray() {
            Ok(ray) => {
                common::record_bvh(&built.bvh, &self.scene.scene.shapes, &ray, Order::NearFirst)
            }
            Err(_) => Recording::default(),
        };
        self.timeline.set_len(self.recording.steps.len());
        if self
            .selected
            .is_some_and(|node| node as usize >= built.bvh.nodes.len())
        {
            self.selected = Some(0);
        }
        self.hovered = None;
        self.node_curve = None;
        self.built = Some(built);
        self.built_revision = self.scene.revision;
        self.built_rule = self.rule;
    }

    fn shown(&self) -> &[Step<f64>] {
        &self.recording.steps[..self.timeline.shown.min(self.recording.steps.len())]
    }

    /// Sets the ray to one of the slide's two rays (from the lesson file's scene: r1 is the
    /// file's ray; r2 comes from the right, through C and D+E).
    fn set_slide_ray(&mut self, second: bool) {
        let file_scene = &self.text.scene;
        let (origin, toward) = if second {
            (DVec2::new(100.0, 30.0), DVec2::new(90.0, 35.0))
        } else {
            (file_scene.ray_origin, file_scene.ray_toward)
        };
        self.scene.scene.ray_origin = origin;
        self.scene.scene.ray_toward = toward;
        self.scene.touch();
        self.timeline.shown = 0;
    }
}

impl Lesson for BvhLesson {
    fn text(&self) -> &LessonText {
        &self.text
    }

    fn scene_mut(&mut self) -> Option<&mut EditableScene> {
        Some(&mut self.scene)
    }

    fn timeline(&mut self) -> Option<(&mut Timeline, String)> {
        self.refresh();
        let count = self.scene.scene.shapes.len();
        let caption = match (self.shown().last(), &self.built) {
            (Some(step), Some(built)) => {
                common::describe_step(step, |node| node_name(built, node, count))
            }
            _ => "Press step: the traversal starts by testing the root's box.".to_owned(),
        };
        Some((&mut self.timeline, caption))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui) {
        self.refresh();
        ui.horizontal(|ui| {
            ui.label("Build with");
            for rule in [
                BvhRule::Middle,
                BvhRule::Median,
                BvhRule::Sah,
                BvhRule::BinnedSah,
            ] {
                ui.selectable_value(&mut self.rule, rule, rule.label());
            }
        });
        ui.horizontal(|ui| {
            if ui
                .button("ray r1")
                .on_hover_text("The slide's first ray")
                .clicked()
            {
                self.set_slide_ray(false);
            }
            if ui
                .button("ray r2")
                .on_hover_text("The slide's second ray")
                .clicked()
            {
                self.set_slide_ray(true);
            }
            let mut leaf_size = self.scene.scene.settings.max_leaf_size;
            if ui
                .add(egui::Slider::new(&mut leaf_size, 1..=8).text("max leaf size"))
                .changed()
            {
                self.scene.scene.settings.max_leaf_size = leaf_size;
                self.scene.touch();
            }
        });
        self.refresh();
        let Some(built) = &self.built else { return };
        let max_depth = built.shape.max_depth();
        // The depths whose boxes are drawn: a range, so one level can be shown at a time.
        let (mut low, mut high) = self.depth_range;
        high = high.min(max_depth);
        ui.add(egui::Slider::new(&mut low, 0..=max_depth).text("shallowest depth shown"));
        ui.add(egui::Slider::new(&mut high, 0..=max_depth).text("deepest depth shown"));
        if low > high {
            // Dragging one past the other moves both.
            if (low, high) != self.depth_range {
                if low != self.depth_range.0 {
                    high = low;
                } else {
                    low = high;
                }
            }
        }
        // The deepest level stays "all the way down" when the tree grows.
        self.depth_range = (low, if high >= max_depth { usize::MAX } else { high });
        ui.separator();
        ui.heading("Tree");
        let count = self.scene.scene.shapes.len();
        let shown = &self.recording.steps[..self.timeline.shown.min(self.recording.steps.len())];
        let emphasis = common::traversal_emphasis(shown, built.bvh.nodes.len());
        let hovered = built.shape.ui(
            ui,
            |node| node_name(built, node, count),
            |node| emphasis[node as usize],
            self.hovered,
            &mut self.selected,
        );
        if hovered.is_some() {
            self.hovered = hovered;
        }
        ui.label(
            egui::RichText::new("Colour: depth; green entered, red missed or skipped. Hover a node to light its box; click to inspect it.")
                .small()
                .weak(),
        );
        ui.separator();
        if let Some(node) = self.selected {
            if self
                .node_curve
                .as_ref()
                .is_none_or(|(cached, _)| *cached != node)
            {
                let boxes = self.scene.scene.shapes.all_bounds();
                let cost = self.scene.scene.settings.cost();
                let curve = bvh_curve(&boxes, &built.primitives[node as usize], &cost, None);
                self.node_curve = Some((node, curve));
            }
            if let Some((_, curve)) = &self.node_curve {
                node_inspector_ui(ui, built, node, &self.scene, count, self.rule, curve);
            }
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let canvas = self.scene.canvas_ui(ui, None);
        self.refresh();
        let Some(built) = &self.built else { return };
        let count = self.scene.scene.shapes.len();
        let shown = &self.recording.steps[..self.timeline.shown.min(self.recording.steps.len())];
        let (low, high) = self.depth_range;
        // The deepest box in the depth range under the pointer lights up (and its tree node).
        let pointer_node = canvas.response.hover_pos().and_then(|pos| {
            let at = canvas.to_world(pos);
            (0..built.bvh.nodes.len() as u32)
                .filter(|&node| {
                    let depth = built.shape.depth[node as usize];
                    depth >= low
                        && depth <= high
                        && built.bvh.nodes[node as usize].bounds.contains_point(at)
                })
                .max_by_key(|&node| built.shape.depth[node as usize])
        });
        if canvas.response.hovered() {
            self.hovered = pointer_node;
        }
        if canvas.response.clicked() && pointer_node.is_some() && self.scene.selected.is_none() {
            self.selected = pointer_node;
        }
        common::draw_tested_shapes(ui, &canvas, &self.scene.scene.shapes, shown, None);
        let mut batch = (built.bvh.nodes.len() > BATCH_ABOVE).then(|| {
            let mut batch = Batch::default();
            batch.reserve(built.bvh.nodes.len() * 8, built.bvh.nodes.len() * 8);
            batch
        });
        for (node, entry) in built.bvh.nodes.iter().enumerate() {
            let depth = built.shape.depth[node];
            if depth < low || depth > high {
                continue;
            }
            if let Some(batch) = &mut batch
                && self.hovered != Some(node as u32)
                && self.selected != Some(node as u32)
            {
                canvas.batch_box(batch, &entry.bounds, 1.0, depth_color(depth));
                continue;
            }
            let color = depth_color(depth);
            let highlighted =
                self.hovered == Some(node as u32) || self.selected == Some(node as u32);
            let fill = highlighted.then(|| faded(color, 30));
            let width = if highlighted { 3.0 } else { 1.5 };
            canvas.box_outline(&entry.bounds, Stroke::new(width, color), fill);
        }
        if let Some(batch) = batch {
            canvas.draw_batch(batch);
        }
        // What the traversal has done so far: boxes it tested, hit or missed.
        for step in shown {
            if let Step::BoxTested { node, hit, .. } = step {
                let color = if *hit { palette::HIT } else { palette::MISS };
                canvas.box_outline(
                    &built.bvh.nodes[*node as usize].bounds,
                    Stroke::new(2.5, faded(color, 200)),
                    None,
                );
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
        if count <= 26 {
            for (index, shape) in self.scene.scene.shapes.shapes.iter().enumerate() {
                let shape_bounds = shape.bounds();
                canvas.label(
                    DVec2::new(shape_bounds.max.x, shape_bounds.max.y),
                    &primitive_name(index as u32, count),
                    ui.visuals().strong_text_color(),
                );
            }
        }
        match self.scene.ray() {
            Ok(ray) => {
                common::draw_ray(&canvas, &ray, common::closest_so_far(shown).map(|(_, t)| t))
            }
            Err(error) => canvas.caption(&[(format!("No ray: {error}"), palette::MISS)]),
        }
        self.scene.draw_handles(&canvas);
        let counters = accelviz_core::counters_of(shown);
        canvas.caption(&[(
            format!(
                "{} nodes, depth {}: boxes tested {}, primitives tested {} (of {count})",
                built.bvh.nodes.len(),
                built.shape.max_depth(),
                counters.box_tests,
                counters.primitive_tests
            ),
            Color32::WHITE,
        )]);
    }
}

/// Bounds, primitives, SAH cost, and why the node is a leaf or where it splits.
fn node_inspector_ui(
    ui: &mut egui::Ui,
    built: &BuiltBvh,
    node: u32,
    scene: &EditableScene,
    count: usize,
    rule: BvhRule,
    curve: &CostCurve,
) {
    let Some(entry) = built.bvh.nodes.get(node as usize) else {
        return;
    };
    let settings = &scene.scene.settings;
    let cost = settings.cost();
    ui.heading(format!("Selected: {}", node_name(built, node, count)));
    ui.label(format!(
        "depth {}, box [{:.2}, {:.2}] × [{:.2}, {:.2}], perimeter {:.2}",
        built.shape.depth[node as usize],
        entry.bounds.min.x,
        entry.bounds.max.x,
        entry.bounds.min.y,
        entry.bounds.max.y,
        entry.bounds.area()
    ));
    let primitives = &built.primitives[node as usize];
    ui.label(format!("{} primitives under it", primitives.len()));
    ui.label(format!(
        "SAH cost of its subtree: {:.3} (C_trav = {}, C_isect = {})",
        built.subtree_cost(node, &cost),
        cost.traversal_cost,
        cost.intersection_cost
    ));
    let best = curve.best.map(|mark| mark.cost);
    let leaf_cost = curve.leaf_cost;
    match built.shape.children[node as usize] {
        None => {
            let why = match best {
                _ if primitives.len() <= 1 => "one primitive: nothing to split".to_owned(),
                Some(best_cost) if leaf_cost <= best_cost => format!(
                    "it is a leaf: leaf cost {leaf_cost:.3} (N·C_isect) ≤ best split cost {best_cost:.3}, and {} ≤ max leaf size {}",
                    primitives.len(),
                    settings.max_leaf_size
                ),
                Some(best_cost) => format!(
                    "it is a leaf: {} primitives ≤ max leaf size {}, where the {} rule stops (the SAH would split: {best_cost:.3} < leaf {leaf_cost:.3})",
                    primitives.len(),
                    settings.max_leaf_size,
                    rule.label()
                ),
                None => format!(
                    "it is a leaf of {} primitives with no split candidate",
                    primitives.len()
                ),
            };
            ui.label(why);
        }
        Some(_) => {
            if let Some(best_cost) = best {
                ui.label(format!(
                    "split: leaf cost {leaf_cost:.3} vs the best split's {best_cost:.3}; {}",
                    if primitives.len() > settings.max_leaf_size {
                        format!(
                            "more than {} primitives must be split",
                            settings.max_leaf_size
                        )
                    } else {
                        "splitting is cheaper".to_owned()
                    }
                ));
            }
        }
    }
}
