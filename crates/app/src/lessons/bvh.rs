//! Lesson 4, "Bounding Volume Hierarchy": boxes of boxes. The slide's picture as a scene (r1
//! tests A+B, then A and B; r2 tests C and D+E, then D and E), both rays at once if wanted,
//! boxes coloured by depth and drawn nested, a depth range that also filters the traversal,
//! a tree diagram linked to the canvas both ways, and a node inspector (bounds, primitives,
//! SAH cost, why it is a leaf: the core's facts and the builder's own reasons).

use accelviz_core::curve::{CostCurve, node_curve};
use accelviz_core::format::{count, number, point};
use accelviz_core::{CATALOGUE, Family, PrimitiveSet, Ray, Structure};
use accelviz_scene::document::RayEntry;
use egui::Color32;
use glam::DVec2;

use crate::background::{Cached, Derived};
use crate::canvas::palette;
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage, request_tree};
use crate::trace::{Trace, TraceState, describe_step, options_in};
use crate::views::scene_view::{
    building_note, draw_ray_colored, draw_tested_shapes, label_shapes, primitive_name, t_hint_ui,
};
use crate::views::tree_diagram::{depth_range_ui, diagram_ui};
use crate::views::tree_view::{TreeLook, draw_tree, node_under};

/// The second ray's colour when both are shown.
const SECOND_RAY: Color32 = Color32::from_rgb(90, 220, 230);

/// A node's name: its primitives joined with "+" in small scenes ("D+E"), else "node N".
pub fn node_name(tree: &SceneTree, node: u32) -> String {
    let count = tree.shapes.len();
    if count > 26 {
        return format!("node {node}");
    }
    let mut letters: Vec<String> = tree
        .built
        .primitives_below(node)
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

/// One traced ray: its name, colour and recording.
struct Traced {
    name: String,
    color: Color32,
    ray: Ray<DVec2>,
    trace: Trace,
}

/// The lesson.
pub struct BvhLesson {
    stage: Stage,
    structure: Structure,
    tree: Derived<(u64, Structure), SceneTree>,
    /// The traced rays, for the tree and the rays they were made with.
    traces: Cached<(u64, u64, bool), Vec<Traced>>,
    /// Whether the slide's second ray is traced beside the scene's.
    both_rays: bool,
    depth_range: (usize, usize),
    hovered: Option<u32>,
    selected: Option<u32>,
    /// The selected node's cost curve (for why it splits), for the tree and node it is of.
    node_curve: Cached<(u64, u32), CostCurve>,
}

impl BvhLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let structure = text
            .structure()
            .filter(|structure| structure.family() == Family::Bvh)
            .unwrap_or_else(|| Structure::lecture(Family::Bvh, accelviz_core::SplitRule::Sah));
        Self {
            stage: Stage::new(text, Editing::ALL),
            structure,
            tree: Derived::default(),
            traces: Cached::default(),
            both_rays: false,
            depth_range: (0, usize::MAX),
            hovered: None,
            selected: Some(0),
            node_curve: Cached::default(),
        }
    }

    /// The slide's rays by name: r1 is the lesson file's ray, the others are named there.
    fn named_rays(&self) -> Vec<(String, RayEntry)> {
        let scene = &self.stage.text.scene;
        let mut rays = vec![(
            "r1".to_owned(),
            RayEntry {
                origin: (scene.ray_origin.x, scene.ray_origin.y),
                toward: (scene.ray_toward.x, scene.ray_toward.y),
            },
        )];
        rays.extend(
            self.stage
                .text
                .file
                .named_rays
                .iter()
                .map(|named| (named.name.clone(), named.ray)),
        );
        rays
    }

    /// Puts the scene's ray on a named one and fits the view to show it whole.
    fn use_ray(&mut self, ray: RayEntry) {
        let scene = &mut self.stage.scene;
        scene.scene.ray_origin = DVec2::new(ray.origin.0, ray.origin.1);
        scene.scene.ray_toward = DVec2::new(ray.toward.0, ray.toward.1);
        scene.touch_ray();
        scene.view.placed = false;
        self.stage.timeline.rewind();
    }

    /// The depths shown.
    fn depths(&self) -> std::ops::RangeInclusive<usize> {
        self.depth_range.0..=self.depth_range.1
    }

    /// The first ray's recording.
    pub fn trace(&self) -> Option<&Trace> {
        Some(&self.traces.get()?.first()?.trace)
    }

    /// What the first ray's trace shows at the timeline's frame.
    pub fn shown_state(&self) -> Option<TraceState> {
        let traced = self.traces.get()?.first()?;
        Some(traced.trace.state(self.stage.timeline.shown))
    }

    fn inspector_tree_ui(&mut self, ui: &mut egui::Ui, tree: &SceneTree) {
        let max_depth = tree.built.facts.max_depth();
        depth_range_ui(ui, &mut self.depth_range, max_depth);
        ui.separator();
        ui.heading("Tree");
        let frame = self.stage.timeline.shown;
        let shown = self
            .traces
            .get()
            .and_then(|traces| traces.first())
            .map_or(&[][..], |traced| traced.trace.shown(frame));
        let label = |node: u32| node_name(tree, node);
        diagram_ui(
            ui,
            &tree.built.facts,
            &label,
            shown,
            &mut self.hovered,
            &mut self.selected,
            false,
        );
        ui.label(
            egui::RichText::new("Colour: depth; green entered, red missed or skipped. Hover a node to light its box; click to inspect it.")
                .small()
                .weak(),
        );
    }

    fn node_ui(&mut self, ui: &mut egui::Ui, tree: &SceneTree, generation: u64) {
        let Some(node) = self
            .selected
            .filter(|&node| (node as usize) < tree.built.facts.node_count())
        else {
            return;
        };
        let facts = &tree.built.facts;
        let settings = tree.settings;
        let cost = settings.cost();
        let bounds = facts.bounds[node as usize];
        ui.heading(format!("Selected: {}", node_name(tree, node)));
        ui.label(format!(
            "depth {}, box from {} to {}, perimeter {}",
            facts.depth[node as usize],
            point(&[bounds.min.x, bounds.min.y]),
            point(&[bounds.max.x, bounds.max.y]),
            number(bounds.area())
        ));
        let primitives = tree.built.primitives_below(node);
        ui.label(format!("{} primitives under it", count(primitives.len())));
        ui.label(format!(
            "SAH cost of its subtree: {} (C_trav = {}, C_isect = {})",
            number(tree.built.stats(node, &cost).sah_cost),
            number(cost.traversal_cost),
            number(cost.intersection_cost)
        ));
        match facts.leaf_reason(node) {
            Some(reason) => {
                ui.label(format!("It is a leaf: {reason}."));
            }
            None => {
                let boxes = tree.shapes.all_bounds();
                let curve = self.node_curve.get_or_make((generation, node), || {
                    node_curve(&tree.built, node, &boxes, &cost, None)
                });
                if let Some(best) = curve.best {
                    let why = if primitives.len() > settings.max_leaf_size {
                        format!(
                            "more than {} primitives must be split",
                            settings.max_leaf_size
                        )
                    } else {
                        "splitting is cheaper".to_owned()
                    };
                    ui.label(format!(
                        "It splits: leaf cost {} (N·C_isect) against the best split's {}; {why}.",
                        number(curve.leaf_cost),
                        number(best.cost)
                    ));
                }
            }
        }
    }
}

impl Lesson for BvhLesson {
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

    fn show_named(&mut self, name: &str) -> bool {
        let ray = self
            .named_rays()
            .into_iter()
            .find(|(named, _)| named == name)
            .map(|(_, ray)| ray);
        ray.map(|ray| self.use_ray(ray)).is_some()
    }

    fn named(&self) -> Vec<String> {
        self.named_rays()
            .into_iter()
            .map(|(name, _)| name)
            .collect()
    }

    fn update(&mut self) {
        let scene = &self.stage.scene;
        request_tree(&mut self.tree, scene, self.structure);
        let Some(tree) = self.tree.get().cloned() else {
            return;
        };
        let named = self.named_rays();
        let both = self.both_rays;
        let traces =
            self.traces
                .get_or_make((self.tree.generation(), scene.revision, both), || {
                    let mut traced = Vec::new();
                    if let Ok(ray) = scene.ray() {
                        let name = if both { "r1" } else { "the ray" };
                        traced.push(Traced {
                            name: name.to_owned(),
                            color: palette::RAY,
                            ray,
                            trace: Trace::of_tree(
                                &tree,
                                &ray,
                                &options_in(accelviz_core::Order::NearFirst),
                            ),
                        });
                    }
                    if both
                        && let Some((name, entry)) = named.get(1)
                        && let Ok(ray) = Ray::try_new(
                            DVec2::new(entry.origin.0, entry.origin.1),
                            DVec2::new(
                                entry.toward.0 - entry.origin.0,
                                entry.toward.1 - entry.origin.1,
                            ),
                        )
                    {
                        traced.push(Traced {
                            name: name.clone(),
                            color: SECOND_RAY,
                            ray,
                            trace: Trace::of_tree(
                                &tree,
                                &ray,
                                &options_in(accelviz_core::Order::NearFirst),
                            ),
                        });
                    }
                    traced
                });
        let frames = traces
            .iter()
            .map(|traced| traced.trace.frames())
            .max()
            .unwrap_or(0);
        self.stage.timeline.set_len(frames);
        let nodes = tree.built.facts.node_count() as u32;
        if self.selected.is_some_and(|node| node >= nodes) {
            self.selected = Some(0);
        }
        if self.hovered.is_some_and(|node| node >= nodes) {
            self.hovered = None;
        }
    }

    fn caption(&self) -> Option<String> {
        let tree = self.tree.get()?;
        let traces = self.traces.get()?;
        let frame = self.stage.timeline.shown;
        let captions: Vec<String> = traces
            .iter()
            .map(|traced| {
                let said = traced.trace.caption(
                    frame,
                    "Press step: the traversal starts by testing the root's box.",
                    |step| describe_step(step, |node| node_name(tree, node)),
                );
                if traces.len() > 1 {
                    format!("{}: {said}", traced.name)
                } else {
                    said
                }
            })
            .collect();
        Some(if captions.is_empty() {
            "No ray to trace: drag the ray's head away from its origin.".to_owned()
        } else {
            captions.join("   |   ")
        })
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        ui.horizontal_wrapped(|ui| {
            ui.label("Build with");
            for entry in CATALOGUE.iter().filter(|entry| entry.family == Family::Bvh) {
                let chosen = self.structure.entry().name == entry.name;
                if ui
                    .selectable_label(chosen, entry.label)
                    .on_hover_text(entry.about)
                    .clicked()
                {
                    self.structure = entry.structure.with_width(self.structure.width());
                }
            }
        });
        ui.horizontal_wrapped(|ui| crate::views::width_ui(ui, &mut self.structure));
        ui.horizontal(|ui| {
            for (name, ray) in self.named_rays() {
                if ui
                    .button(format!("ray {name}"))
                    .on_hover_text(format!("The slide's ray {name}"))
                    .clicked()
                {
                    self.both_rays = false;
                    self.use_ray(ray);
                }
            }
            if self.named_rays().len() > 1
                && ui
                    .selectable_label(self.both_rays, "r1 and r2 together")
                    .on_hover_text("Trace both of the slide's rays, step by step in lockstep")
                    .clicked()
            {
                self.both_rays = !self.both_rays;
                if self.both_rays
                    && let Some((_, first)) = self.named_rays().first().cloned()
                {
                    self.use_ray(first);
                }
                self.stage.scene.view.placed = false;
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
        let Some(tree) = self.tree.get().cloned() else {
            ui.label("Building…");
            return;
        };
        self.inspector_tree_ui(ui, &tree);
        ui.separator();
        self.node_ui(ui, &tree, self.tree.generation());
        t_hint_ui(ui);
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        // With both rays shown, the view fits the second one too.
        let second_ray = self.both_rays.then(|| {
            self.named_rays().iter().skip(1).fold(
                accelviz_core::Aabb::empty(),
                |bounds, (_, ray)| {
                    bounds
                        .grown(DVec2::new(ray.origin.0, ray.origin.1))
                        .grown(DVec2::new(ray.toward.0, ray.toward.1))
                },
            )
        });
        let canvas = self.stage.scene.canvas_ui(ui, second_ray);
        let Some(tree) = self.tree.get().cloned() else {
            return;
        };
        let depths = self.depths();
        // The deepest box in the depth range under the pointer lights up (and its tree node).
        let pointer_node = canvas
            .response
            .hover_pos()
            .and_then(|pos| node_under(&canvas, &tree, pos, &depths));
        if canvas.response.hovered() {
            self.hovered = pointer_node;
        }
        if canvas.response.clicked()
            && pointer_node.is_some()
            && self.stage.scene.selected.is_none()
        {
            self.selected = pointer_node;
        }
        let frame = self.stage.timeline.shown;
        let traces = self.traces.get();
        let first = traces.and_then(|traces| traces.first());
        let shown = first.map_or(&[][..], |traced| traced.trace.shown(frame));
        draw_tested_shapes(ui, &canvas, &tree.shapes, shown, None);
        let both = traces.is_some_and(|traces| traces.len() > 1);
        // The tree with the first ray's traversal, then each further ray's traversal over it.
        draw_tree(
            &canvas,
            &tree,
            &TreeLook {
                depths: depths.clone(),
                hovered: self.hovered,
                selected: self.selected,
                steps: shown,
                structure_alpha: if both { 120 } else { 230 },
                mark_current: true,
            },
        );
        for traced in traces.into_iter().flatten().skip(1) {
            draw_tree(
                &canvas,
                &tree,
                &TreeLook {
                    depths: depths.clone(),
                    steps: traced.trace.shown(frame),
                    structure_alpha: 0,
                    ..TreeLook::default()
                },
            );
        }
        label_shapes(ui, &canvas, &tree.shapes);
        for traced in traces.into_iter().flatten() {
            let state = traced.trace.state(frame);
            draw_ray_colored(
                &canvas,
                &traced.ray,
                state.closest.map(|(_, t)| t),
                traced.color,
                "closest",
            );
            if traces.is_some_and(|traces| traces.len() > 1) {
                canvas.label(
                    traced.ray.origin,
                    &format!(" {}", traced.name),
                    traced.color,
                );
            }
        }
        if let Err(error) = self.stage.scene.ray() {
            canvas.caption(&[(format!("No ray: {error}"), palette::MISS)]);
        }
        self.stage.scene.draw_handles(&canvas);
        let mut lines = Vec::new();
        for traced in traces.into_iter().flatten() {
            let counters = traced.trace.state(frame).counters;
            lines.push((
                format!(
                    "{}: boxes tested {}, primitives tested {} (of {})",
                    traced.name,
                    counters.box_tests,
                    counters.primitive_tests,
                    count(tree.shapes.len())
                ),
                traced.color,
            ));
        }
        lines.insert(
            0,
            (
                format!(
                    "{} nodes, depth {}",
                    count(tree.built.facts.node_count()),
                    tree.built.facts.max_depth()
                ),
                Color32::WHITE,
            ),
        );
        canvas.caption(&lines);
        building_note(ui, &canvas, self.tree.working_for(), "the BVH");
        self.stage.scene.draw_footer(&canvas);
        canvas.finish();
    }
}
