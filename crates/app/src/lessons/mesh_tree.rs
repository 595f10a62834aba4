//! Lessons 12, "A real mesh and its BVH", and 13, "kD-tree in 3D": a shaded mesh in the boxes
//! (or cells, and a kD-tree's split planes clipped to their cells, coloured by axis) of any
//! structure of the catalogue, coloured by depth, a depth range, inner nodes and leaves
//! toggled, hidden edges faint or gone; the tree diagram and a node inspector linked to the
//! view both ways; a clicked pixel's ray traced by the one traversal with a `Recorder` and
//! stepped on the timeline (each box test with its slab interval, culls, triangle tests, the
//! closest hit so far), near-first or in file order.

use std::sync::Arc;

use accelviz_core::bvh::BuildParams;
use accelviz_core::camera::bounding_sphere_of_box;
use accelviz_core::format::{count, number, point};
use accelviz_core::{Aabb, CATALOGUE, Family, Order, Ray, Step, Structure, slab_record};
use egui::Color32;
use glam::DVec3;

use crate::background::{Cached, Derived};
use crate::canvas::{depth_color, palette};
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::mesh::{MeshScene, MeshTree, Overlay, loading_ui, mesh_and_structure_ui, trace_overlay};
use crate::stage::Stage;
use crate::trace::{Trace, TraceState, options_in, step_node};
use crate::view3d::{Content, DrawTriangle, HiddenEdges, Instance, View3d, relative, revision_of};
use crate::views::tree_diagram::{depth_range_ui, diagram_ui, traversal_emphasis};

/// The ray of a clicked pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PickedRay {
    ray: Ray<DVec3>,
    revision: u64,
}

/// The lesson.
pub struct MeshTreeLesson {
    stage: Stage<MeshScene>,
    /// The view and its camera.
    pub view: View3d,
    /// The structure built.
    pub structure: Structure,
    tree: Derived<(u64, Structure), MeshTree>,
    /// The clicked ray's traversal order.
    pub order: Order,
    picked: Option<PickedRay>,
    trace: Cached<(u64, u64, Order), Trace>,
    /// The depths whose boxes are drawn (the deepest may be `usize::MAX`: all the way down).
    pub depth_range: (usize, usize),
    /// Whether inner nodes' boxes are drawn.
    pub show_inner: bool,
    /// Whether leaves' boxes are drawn.
    pub show_leaves: bool,
    /// Whether kD split planes are drawn (kD-trees only).
    pub show_planes: bool,
    /// How box edges behind the surface are drawn.
    pub hidden_edges: HiddenEdges,
    /// Whether the mesh's triangle edges are drawn.
    pub wireframe: bool,
    hovered: Option<u32>,
    /// The node the inspector shows.
    pub selected: Option<u32>,
    /// What the view draws over the mesh, made again only when what it shows changed (a
    /// million-triangle mesh has a million boxes, and its root half a million triangles on
    /// either side): box outlines, planes, the highlighted triangles and ray segments.
    drawn_boxes: Cached<u64, Arc<Vec<Instance>>>,
    drawn_planes: Cached<u64, Arc<Vec<Instance>>>,
    drawn_overlay: Cached<u64, Arc<Overlay>>,
    /// The selected node's triangle count and subtree SAH cost (for the tree, node).
    node_summary: Cached<(u64, u32), (usize, f64)>,
}

impl MeshTreeLesson {
    /// The lesson with its file's mesh and structure.
    pub fn new(text: LessonText) -> Self {
        let scene = MeshScene::of_lesson(&text);
        let structure = text.structure().unwrap_or(CATALOGUE[0].structure);
        Self {
            stage: Stage::with_scene(text, scene),
            view: View3d::default(),
            structure,
            tree: Derived::default(),
            order: Order::NearFirst,
            picked: None,
            trace: Cached::default(),
            // A kD-tree opens on its first cuts: every plane at once hides the mesh.
            depth_range: if structure.family() == Family::Kd {
                (0, 4)
            } else {
                (0, usize::MAX)
            },
            // A kD-tree is shown by its planes; its cells' outlines on request.
            show_inner: structure.family() == Family::Bvh,
            show_leaves: structure.family() == Family::Bvh,
            show_planes: true,
            hidden_edges: HiddenEdges::Dimmed,
            wireframe: false,
            hovered: None,
            selected: Some(0),
            drawn_boxes: Cached::default(),
            drawn_planes: Cached::default(),
            drawn_overlay: Cached::default(),
            node_summary: Cached::default(),
        }
    }

    /// The recorded traversal of the clicked pixel's ray, if one was clicked.
    pub fn trace(&self) -> Option<&Trace> {
        self.trace.get()
    }

    /// The built tree shown.
    pub fn tree(&self) -> Option<&Arc<MeshTree>> {
        self.tree.get()
    }

    /// Traces the ray from `origin` along `direction`, as a click on its pixel does.
    pub fn pick(&mut self, origin: DVec3, direction: DVec3) {
        if let Ok(ray) = Ray::try_new(origin, direction) {
            let revision = self.picked.map_or(1, |picked| picked.revision + 1);
            self.picked = Some(PickedRay { ray, revision });
            self.stage.timeline.rewind();
        }
    }

    /// What the trace shows at the timeline's frame.
    pub fn shown_state(&self) -> Option<TraceState> {
        Some(self.trace.get()?.state(self.stage.timeline.shown))
    }

    fn depths(&self) -> std::ops::RangeInclusive<usize> {
        self.depth_range.0..=self.depth_range.1
    }

    /// Whether `node`'s box is drawn.
    fn shows(&self, tree: &MeshTree, node: u32) -> bool {
        let facts = &tree.build.built.facts;
        let leaf = facts.is_leaf(node);
        self.depths()
            .contains(&(facts.depth[node as usize] as usize))
            && if leaf {
                self.show_leaves
            } else {
                self.show_inner
            }
    }

    /// The deepest shown box the ray enters (nearest first among equals): what a click on
    /// a box selects.
    fn box_under(&self, tree: &MeshTree, origin: DVec3, direction: DVec3) -> Option<u32> {
        let ray = Ray::try_new(origin, direction).ok()?;
        let facts = &tree.build.built.facts;
        (0..facts.node_count() as u32)
            .filter(|&node| self.shows(tree, node))
            .filter_map(|node| {
                let bounds = facts.bounds[node as usize];
                let record = slab_record(&bounds, &ray, false);
                record
                    .hit
                    .then_some((facts.depth[node as usize], record.t_enter, node))
            })
            .max_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)))
            .map(|(_, _, node)| node)
    }

    /// The box outlines: each shown node in its depth's colour; along a trace, entered nodes
    /// green, missed and skipped ones red, the current step's node bright, the rest faint;
    /// hovered and selected nodes lit.
    fn boxes(&self, tree: &MeshTree, steps: &[Step<f64>], current: Option<u32>) -> Vec<Instance> {
        let facts = &tree.build.built.facts;
        let emphasis = (!steps.is_empty()).then(|| traversal_emphasis(steps, facts.node_count()));
        let mut instances = Vec::new();
        for &node in &facts.by_depth {
            let lit = Some(node) == self.hovered || Some(node) == self.selected;
            // Along a trace, only the boxes the traversal met are drawn.
            let met = emphasis
                .as_ref()
                .is_none_or(|emphasis| emphasis[node as usize].is_some());
            let drawn = (self.shows(tree, node) && met) || lit || Some(node) == current;
            if !drawn {
                continue;
            }
            let color = if Some(node) == current {
                palette::CURRENT
            } else if lit {
                Color32::from_rgb(255, 120, 0)
            } else {
                match &emphasis {
                    Some(emphasis) => emphasis[node as usize].unwrap_or(Color32::GRAY),
                    None => depth_color(facts.depth[node as usize] as usize),
                }
            };
            let bounds = facts.bounds[node as usize];
            instances.push(Instance {
                a: relative(bounds.min, tree.build.sphere),
                b: relative(bounds.max, tree.build.sphere),
                color: [color.r(), color.g(), color.b(), color.a()],
            });
        }
        instances
    }

    /// A kD-tree's split planes in the depth range, each clipped to its node's cell and
    /// coloured by axis (fainter deeper down), sorted back to front for `eye`.
    fn planes(&self, tree: &MeshTree, eye: DVec3) -> Vec<Instance> {
        if !self.show_planes {
            return Vec::new();
        }
        let facts = &tree.build.built.facts;
        let mut planes: Vec<(f64, Instance)> = Vec::new();
        for node in 0..facts.node_count() as u32 {
            let depth = facts.depth[node as usize] as usize;
            let Some((axis, position)) = tree.build.built.plane(node) else {
                continue;
            };
            if !self.depths().contains(&depth) {
                continue;
            }
            let cell = facts.bounds[node as usize];
            let (mut low, mut high) = (cell.min, cell.max);
            low[axis] = position;
            high[axis] = position;
            let color = palette::AXES[axis];
            let alpha = if Some(node) == self.selected || Some(node) == self.hovered {
                150
            } else {
                (90 - 8 * depth.min(8)) as u8
            };
            planes.push((
                ((low + high) / 2.0 - eye).length(),
                Instance {
                    a: relative(low, tree.build.sphere),
                    b: relative(high, tree.build.sphere),
                    color: [color.r(), color.g(), color.b(), alpha],
                },
            ));
        }
        planes.sort_by(|a, b| b.0.total_cmp(&a.0));
        planes.into_iter().map(|(_, plane)| plane).collect()
    }

    /// The selected node's triangles, drawn over the mesh (when no ray is traced).
    fn selected_triangles(&self, tree: &MeshTree) -> Vec<DrawTriangle> {
        let Some(node) = self.selected.filter(|&node| node != 0) else {
            return Vec::new();
        };
        tree.build
            .built
            .primitives_below(node)
            .into_iter()
            .filter_map(|primitive| tree.build.drawn.get(primitive as usize))
            .map(|triangle| DrawTriangle {
                color: [80, 170, 255, 255],
                ..*triangle
            })
            .collect()
    }

    fn controls_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            if mesh_and_structure_ui(ui, &mut self.stage.scene, &mut self.structure) {
                self.picked = None;
                self.stage.timeline.rewind();
            }
            ui.separator();
            for (order, name) in [
                (Order::NearFirst, "near first"),
                (Order::FileOrder, "file order"),
            ] {
                if ui.selectable_label(self.order == order, name).clicked() {
                    self.order = order;
                    self.stage.timeline.rewind();
                }
            }
            ui.separator();
            ui.checkbox(&mut self.show_inner, "inner nodes");
            ui.checkbox(&mut self.show_leaves, "leaves");
            if self.structure.family() == Family::Kd {
                ui.checkbox(&mut self.show_planes, "split planes")
                    .on_hover_text(
                        "Each inner node's plane, clipped to its cell, coloured by axis",
                    );
            }
            ui.checkbox(&mut self.wireframe, "wireframe")
                .on_hover_text("The mesh's triangle edges drawn over it");
            ui.selectable_value(&mut self.hidden_edges, HiddenEdges::Dimmed, "x-ray")
                .on_hover_text("Box edges behind the surface drawn faint");
            ui.selectable_value(&mut self.hidden_edges, HiddenEdges::Hidden, "hide hidden")
                .on_hover_text("Box edges behind the surface not drawn");
            ui.separator();
            ui.checkbox(&mut self.view.orbit.orthographic, "orthographic");
            if ui
                .button("focus")
                .on_hover_text("Look at the selected node's box")
                .clicked()
                && let (Some(tree), Some(node)) = (self.tree.get(), self.selected)
            {
                let bounds = tree.build.built.facts.bounds[node as usize];
                let (center, radius) = tree.build.sphere;
                let (box_center, box_radius) = bounding_sphere_of_box(&bounds);
                self.view.orbit.pan = (box_center - center) / radius;
                self.view.orbit.distance = (2.8 * box_radius / radius).max(0.05);
            }
            if ui.button("reset view").clicked() {
                self.view.reset();
            }
            self.view.save_button(ui);
        });
    }

    fn node_ui(&mut self, ui: &mut egui::Ui, tree: &MeshTree) {
        let Some(node) = self
            .selected
            .filter(|&node| (node as usize) < tree.build.built.facts.node_count())
        else {
            return;
        };
        let facts = &tree.build.built.facts;
        let bounds = facts.bounds[node as usize];
        ui.heading(format!("Selected: {}", tree.node_name(node)));
        let kind = if facts.is_leaf(node) {
            "leaf"
        } else {
            "inner node"
        };
        ui.label(format!(
            "{kind} at depth {}; {} from {} to {}, surface area {}",
            facts.depth[node as usize],
            match tree.build.built.structure.family() {
                Family::Bvh => "box",
                Family::Kd => "cell",
            },
            point(&bounds.min.to_array()),
            point(&bounds.max.to_array()),
            number(bounds.area())
        ));
        let (below, sah_cost) =
            *self
                .node_summary
                .get_or_make((self.tree.generation(), node), || match node {
                    0 => (tree.build.root_triangles, tree.build.stats.sah_cost),
                    _ => (
                        tree.build.built.primitives_below(node).len(),
                        tree.build
                            .built
                            .stats(node, &BuildParams::default().cost)
                            .sah_cost,
                    ),
                });
        ui.label(format!("{} triangles under it", count(below)));
        ui.label(format!("SAH cost of its subtree: {}", number(sah_cost)));
        if let Some(reason) = facts.leaf_reason(node) {
            ui.label(format!("It is a leaf: {reason}."));
        }
    }

    /// The current step's box test, axis by axis: the slab intervals the inspector shows.
    fn slab_ui(&self, ui: &mut egui::Ui, tree: &MeshTree) {
        let (Some(picked), Some(state)) = (self.picked, self.shown_state()) else {
            return;
        };
        let Some(node) = state.current.and_then(|step| step_node(&step)) else {
            return;
        };
        let bounds: Aabb<DVec3> = tree.build.built.facts.bounds[node as usize];
        let record = slab_record(&bounds, &picked.ray, false);
        ui.separator();
        ui.label(egui::RichText::new(format!("Slab test of {}", tree.node_name(node))).strong());
        // A table keeps its columns: in a narrow panel (the app scaled up) it scrolls
        // sideways rather than widen the panel.
        egui::ScrollArea::horizontal()
            .id_salt("slabs columns")
            .show(ui, |ui| {
                egui::Grid::new("slabs").striped(true).show(ui, |ui| {
                    ui.label("axis");
                    ui.label("t near");
                    ui.label("t far");
                    ui.end_row();
                    for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
                        ui.label(name);
                        ui.label(number(record.t_near[axis]));
                        ui.label(number(record.t_far[axis]));
                        ui.end_row();
                    }
                });
            });
        ui.label(format!(
            "largest t near {} {} smallest t far {}: {}",
            number(record.t_enter),
            if record.hit { "≤" } else { ">" },
            number(record.t_exit),
            if record.hit { "hit" } else { "miss" }
        ));
    }
}

impl Lesson for MeshTreeLesson {
    crate::staged!(tree);

    fn share(&self) -> Vec<(String, String)> {
        crate::share::mesh_view_values(&self.stage.scene, &self.structure, &self.view.orbit)
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        let (scene, structure) = (&mut self.stage.scene, &mut self.structure);
        crate::share::restore_mesh_view(scene, structure, &mut self.view.orbit, key, value)
    }

    fn update(&mut self) {
        self.stage
            .scene
            .request_tree(&mut self.tree, self.structure);
        let Some(tree) = self.tree.get().cloned() else {
            return;
        };
        let nodes = tree.build.built.facts.node_count() as u32;
        if self.selected.is_some_and(|node| node >= nodes) {
            self.selected = Some(0);
        }
        if self.hovered.is_some_and(|node| node >= nodes) {
            self.hovered = None;
        }
        let Some(picked) = self.picked else {
            self.trace.clear();
            self.stage.timeline.set_len(0);
            return;
        };
        let order = self.order;
        let trace =
            self.trace
                .get_or_make((self.tree.generation(), picked.revision, order), || {
                    Trace::of(
                        &tree.build.built.tree,
                        &tree.triangles,
                        &picked.ray,
                        &options_in(order),
                    )
                });
        self.stage.timeline.set_len(trace.frames());
    }

    fn take_export(&mut self) -> Option<crate::view3d::Export> {
        self.view.take_export()
    }

    fn caption(&self) -> Option<String> {
        let tree = self.tree.get()?;
        Some(tree.caption(
            self.trace.get(),
            self.stage.timeline.shown,
            "Click a pixel of the mesh: its ray is traced here, step by step.",
        ))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui) {
        let Some(tree) = self.tree.get().cloned() else {
            ui.label("Building…");
            return;
        };
        let stats = &tree.build.stats;
        // The build time only on hover: it differs from run to run, the rest does not.
        ui.label(format!(
            "{}: {} triangles; {} nodes, {} leaves, depth {}, SAH cost {}",
            tree.mesh.name.trim_start_matches("builtin:"),
            count(tree.mesh.triangles.len()),
            count(stats.node_count),
            count(stats.leaf_count),
            stats.max_depth,
            number(stats.sah_cost),
        ))
        .on_hover_text(format!("built in {} ms", number(tree.build.build_millis)));
        if let Some(limits) = tree
            .build
            .built
            .tree
            .kd_limits()
            .filter(|limits| limits.reached())
        {
            ui.colored_label(palette::MISS, format!("kD budget: {limits}"));
        }
        let max_depth = tree.build.built.facts.max_depth();
        depth_range_ui(ui, &mut self.depth_range, max_depth);
        ui.separator();
        ui.heading("Tree");
        let shown = self
            .trace
            .get()
            .map_or(&[][..], |trace| trace.shown(self.stage.timeline.shown));
        let label = |node: u32| tree.node_name(node);
        diagram_ui(
            ui,
            &tree.build.built.facts,
            &label,
            shown,
            &mut self.hovered,
            &mut self.selected,
        );
        ui.label(
            egui::RichText::new(
                "Colour: depth; green entered, red missed or skipped. Hover a node to light its box; click a node or a box to select it.",
            )
            .small()
            .weak(),
        );
        ui.separator();
        self.node_ui(ui, &tree);
        self.slab_ui(ui, &tree);
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.controls_ui(ui);
        loading_ui(
            ui,
            &mut self.stage.scene,
            &mut self.tree,
            &mut self.structure,
        );
        let Some(tree) = self.tree.get().cloned() else {
            ui.label("Building…");
            return;
        };
        let trace = self.trace.get();
        let frame = self.stage.timeline.shown;
        let steps = trace.map_or(&[][..], |trace| trace.shown(frame));
        let state = trace.map(|trace| trace.state(frame));
        let current = state
            .and_then(|state| state.current)
            .and_then(|step| step_node(&step));
        let boxes_revision = revision_of((
            self.tree.generation(),
            self.depth_range,
            self.show_inner,
            self.show_leaves,
            self.hovered,
            self.selected,
            self.picked.map(|picked| picked.revision),
            self.order,
            frame,
        ));
        // Taken out while made: making reads the lesson's other fields.
        let mut drawn_boxes = std::mem::take(&mut self.drawn_boxes);
        let boxes = drawn_boxes
            .get_or_make(boxes_revision, || {
                Arc::new(self.boxes(&tree, steps, current))
            })
            .clone();
        self.drawn_boxes = drawn_boxes;
        let overlay_revision = revision_of((
            self.tree.generation(),
            self.picked.map(|picked| picked.revision),
            self.order,
            frame,
            self.selected,
        ));
        let mut drawn_overlay = std::mem::take(&mut self.drawn_overlay);
        let overlay = drawn_overlay
            .get_or_make(overlay_revision, || {
                Arc::new(match self.picked {
                    Some(picked) => trace_overlay(&tree, &picked.ray, steps),
                    None => (self.selected_triangles(&tree), Vec::new()),
                })
            })
            .clone();
        self.drawn_overlay = drawn_overlay;
        let eye = self
            .view
            .orbit
            .camera(tree.build.sphere.0, tree.build.sphere.1)
            .eye;
        let planes_revision = revision_of((
            self.tree.generation(),
            self.depth_range,
            self.show_planes,
            self.hovered,
            self.selected,
            eye.to_array().map(f64::to_bits),
        ));
        let mut drawn_planes = std::mem::take(&mut self.drawn_planes);
        let planes = drawn_planes
            .get_or_make(planes_revision, || Arc::new(self.planes(&tree, eye)))
            .clone();
        self.drawn_planes = drawn_planes;
        let size = ui.available_size();
        let response = self.view.ui(
            ui,
            size,
            &Content {
                sphere: tree.build.sphere,
                mesh: (
                    revision_of((self.tree.generation(), "mesh")),
                    &tree.build.drawn,
                ),
                highlights: (overlay_revision, &overlay.0),
                boxes: (boxes_revision, &boxes),
                segments: (overlay_revision, &overlay.1),
                quads: (planes_revision, &planes),
                hidden_edges: self.hidden_edges,
                wireframe: self.wireframe,
            },
        );
        if let Some((origin, direction)) = response.hovered {
            self.hovered = self.box_under(&tree, origin, direction);
        } else if response.response.hovered() {
            self.hovered = None;
        }
        if let Some((origin, direction)) = response.clicked {
            if let Some(node) = self.box_under(&tree, origin, direction) {
                self.selected = Some(node);
            }
            self.pick(origin, direction);
        }
    }
}
