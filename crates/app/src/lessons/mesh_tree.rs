//! Lessons 12, "A real mesh and its BVH", and 13, "kD-tree in 3D": a shaded mesh in the boxes
//! (or cells, and a kD-tree's split planes clipped to their cells, coloured by axis) of any
//! structure of the catalogue, coloured by depth, a depth range, inner nodes and leaves
//! toggled, hidden edges faint or gone; the tree diagram and a node inspector linked to the
//! view both ways; a clicked pixel's ray traced by the one traversal with a `Recorder` and
//! stepped on the timeline (each box test with its slab interval, culls, triangle tests, the
//! closest hit so far), near-first or in file order.

use std::sync::Arc;

use accelviz_core::camera::{Camera, bounding_sphere_of_box};
use accelviz_core::format::{count, number, point_at_scale};
use accelviz_core::params::BuildParams;
use accelviz_core::trade::Precision;
use accelviz_core::{Aabb, CATALOGUE, Family, Order, Ray, Step, Structure, Width, slab_record};
use egui::{Color32, RichText};
use glam::DVec3;

use crate::background::{Cached, Derived};
use crate::canvas::{depth_color, palette};
use crate::lesson::{self, Lesson, Parts};
use crate::lesson_file::LessonText;
use crate::mesh::{MeshScene, MeshTree, Overlay, loading_ui, mesh_and_structure_ui, trace_overlay};
use crate::stage::Stage;
use crate::trace::{Trace, TraceState, options_in, step_node};
use crate::view3d::{
    Content, DrawTriangle, HiddenEdges, Instance, Pixel, View3d, relative, revision_of,
};
use crate::views::tree_diagram::{depth_range_ui, diagram_ui, traversal_emphasis};

/// The ray of a clicked pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PickedRay {
    ray: Ray<DVec3>,
    /// The pixel it goes through (none for a ray given by its numbers).
    pixel: Option<Pixel>,
    revision: u64,
}

/// A ray another lesson asked to be shown (the trade lab's "show me"): what the lab found
/// for it, so that the inspector shows the triangle tests as that row computed them.
#[derive(Clone, Debug)]
pub struct Examined {
    /// The row's switches (its order and test are the trace's; its precision the numbers').
    pub switches: accelviz_core::trade::Switches,
    /// The query the row answered.
    pub query: accelviz_core::Query,
    /// What the row's answer was.
    pub outcome: accelviz_core::outcome::Outcome,
    /// The structure the row traced.
    pub structure: Structure,
    /// The ray (so that a ray clicked since is not taken for it).
    pub ray: Ray<DVec3>,
}

/// The triangle test `test` of `corners` against `ray`, both rounded to `V`'s precision:
/// its coordinates (barycentrics or edge functions), its t and its answer, as text.
fn explain_in<V: accelviz_core::Vector3>(
    corners: &[[f64; 3]; 3],
    ray: Ray<DVec3>,
    test: accelviz_core::HitTest,
) -> ([String; 3], String, bool) {
    let triangles = accelviz_core::TriangleSet::<V>::from_f64(&[*corners]);
    let ray = ray.cast::<V>();
    let prepared = accelviz_core::primitive::TriangleRay::new(&ray, test);
    let values = triangles.explain(&prepared, 0, ray.t_min, ray.t_max);
    // Every digit the precision holds (the shortest that reads back): a coordinate just
    // outside, 1.0000001 against 1, is the point.
    let show =
        |value: Option<V::Scalar>| value.map_or("–".to_owned(), |value| format!("{value:?}"));
    let coordinates = values.coordinates.map(show);
    (coordinates, show(values.t), values.hit)
}

/// The share key of the clicked pixel.
const PIXEL: &str = "pixel";

/// The key of the precision in a shared link (kept when it is f32).
const PRECISION: &str = "precision";

/// The key of the triangle test in a shared link (kept when it is the watertight one).
const TEST: &str = "test";

/// Trees up to this many nodes open with every depth shown.
const SMALL_TREE_NODES: usize = 63;

/// The inspector's parts a lecture slide can name.
const RAY_PART: lesson::Part =
    lesson::Part::new("ray", "the clicked ray and the step's slab table");
const DEPTHS_PART: lesson::Part = lesson::Part::new("depths", "the depths whose boxes are drawn");
const TREE_PART: lesson::Part = lesson::Part::new("tree", "the tree's numbers and diagram");
const NODE_PART: lesson::Part = lesson::Part::new("node", "the selected node");
const PARTS: [lesson::Part; 4] = [RAY_PART, DEPTHS_PART, TREE_PART, NODE_PART];

/// The depths a newly built tree opens on: every depth of a small tree; a big tree's first two
/// levels, since a real mesh's boxes (or planes) all at once cover it like a blob (a scanned
/// head's 126k boxes), while the root and its children show the first cut.
fn opening_depths(node_count: usize) -> (usize, usize) {
    if node_count <= SMALL_TREE_NODES {
        (0, usize::MAX)
    } else {
        (0, 1)
    }
}

/// A split plane as drawn: a flat box, filled as a quad or outlined (a box's edges), and its
/// centre in world space (to sort planes back to front).
struct PlaneQuad {
    center: DVec3,
    instance: Instance,
}

/// The lesson.
pub struct MeshTreeLesson {
    stage: Stage<MeshScene>,
    /// The view and its camera.
    pub view: View3d,
    /// The structure built.
    pub structure: Structure,
    tree: Derived<crate::mesh::scene::TreeKey, MeshTree>,
    /// The clicked ray's traversal order.
    pub order: Order,
    picked: Option<PickedRay>,
    /// The precision the tree is built and the ray traced in: f64, or f32 as the trade lab's
    /// f32 rows (and the CLI by default) trace it.
    pub precision: Precision,
    /// Whether the traversal uses the watertight triangle test and the conservative slab test
    /// (else Möller–Trumbore and the plain one).
    pub watertight: bool,
    /// The ray the trade lab asked to show, while it is the ray shown.
    pub examined: Option<Examined>,
    trace: Cached<(u64, u64, Order, bool), Trace>,
    /// The depths whose boxes are drawn (the deepest may be `usize::MAX`: all the way down).
    pub depth_range: (usize, usize),
    /// The tree (its generation) the depth range was last opened for ([`opening_depths`]).
    opened: Option<u64>,
    /// A pixel from a shared link, traced once the tree (and so the camera) is there.
    pending_pixel: Option<Pixel>,
    /// Whether inner nodes' boxes are drawn.
    pub show_inner: bool,
    /// Whether leaves' boxes are drawn.
    pub show_leaves: bool,
    /// Whether kD split planes are drawn (kD-trees only).
    pub show_planes: bool,
    /// The family the show switches were last set for: a new family gets its own look.
    looks_for: Family,
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
            precision: Precision::F64,
            watertight: false,
            examined: None,
            trace: Cached::default(),
            depth_range: (0, usize::MAX),
            opened: None,
            pending_pixel: None,
            show_inner: Self::looks(structure.family()).0,
            show_leaves: Self::looks(structure.family()).1,
            show_planes: Self::looks(structure.family()).2,
            looks_for: structure.family(),
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
        self.pick_ray(origin, direction, None);
    }

    /// Traces the ray through `pixel`'s centre for the camera now (a click on it).
    pub fn pick_pixel(&mut self, pixel: Pixel, camera: &Camera) {
        let (origin, direction) = pixel.ray(camera);
        self.pick_ray(origin, direction, Some(pixel));
    }

    fn pick_ray(&mut self, origin: DVec3, direction: DVec3, pixel: Option<Pixel>) {
        if let Ok(ray) = Ray::try_new(origin, direction) {
            self.pick_exact(ray, pixel);
        }
    }

    /// Traces `ray` as given (its interval too).
    fn pick_exact(&mut self, ray: Ray<DVec3>, pixel: Option<Pixel>) {
        let revision = self.picked.map_or(1, |picked| picked.revision + 1);
        self.picked = Some(PickedRay {
            ray,
            pixel,
            revision,
        });
        self.stage.timeline.rewind();
    }

    /// The trade lab's ray, while it is the one shown.
    fn examined(&self) -> Option<&Examined> {
        let examined = self.examined.as_ref()?;
        let picked = self.picked?;
        (picked.ray == examined.ray && self.structure == examined.structure).then_some(examined)
    }

    /// The clicked pixel's ray: (its pixel, if it was clicked, and the ray).
    pub fn picked(&self) -> Option<(Option<Pixel>, Ray<DVec3>)> {
        self.picked.map(|picked| (picked.pixel, picked.ray))
    }

    /// What the trace shows at the timeline's frame.
    pub fn shown_state(&self) -> Option<TraceState> {
        Some(self.trace.get()?.state(self.stage.timeline.shown))
    }

    fn depths(&self) -> std::ops::RangeInclusive<usize> {
        self.depth_range.0..=self.depth_range.1
    }

    /// How a family is first shown: (inner boxes, leaf boxes, split planes). A BVH by its
    /// boxes; a kD-tree and an octree by their planes (their cells' outlines on request); a
    /// grid by its cells that hold something (all its cells at once would hide the mesh).
    fn looks(family: Family) -> (bool, bool, bool) {
        match family {
            Family::Bvh => (true, true, false),
            Family::Kd | Family::Octree => (false, false, true),
            Family::Grid | Family::HashedGrid => (false, true, false),
        }
    }

    /// Whether `node`'s box is drawn. A grid's empty cells are not (unless a ray passes them).
    fn shows(&self, tree: &MeshTree, node: u32) -> bool {
        let facts = &tree.build.built.facts;
        let leaf = facts.is_leaf(node);
        let empty_cell =
            leaf && facts.leaf_sizes[node as usize] == 0 && tree.build.built.grid_cells().is_some();
        self.depths()
            .contains(&(facts.depth[node as usize] as usize))
            && !empty_cell
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
    fn boxes(
        &self,
        tree: &MeshTree,
        steps: &[Step<f64>],
        current: Option<u32>,
        dark_mode: bool,
    ) -> Vec<Instance> {
        let facts = &tree.build.built.facts;
        let emphasis = (!steps.is_empty()).then(|| traversal_emphasis(steps, facts.node_count()));
        let mut instances = Vec::new();
        for &node in &facts.by_depth {
            let lit = Some(node) == self.hovered || Some(node) == self.selected;
            // Along a trace, only the boxes the traversal met are drawn.
            let met = emphasis
                .as_ref()
                .is_none_or(|emphasis| emphasis[node as usize].is_some());
            // A grid's cells a ray passed are drawn, empty or not: the walk is the point.
            let passed = emphasis.is_some()
                && met
                && facts.is_leaf(node)
                && tree.build.built.grid_cells().is_some()
                && self.show_leaves;
            let drawn = (self.shows(tree, node) && met) || passed || lit || Some(node) == current;
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
                    None => depth_color(facts.depth[node as usize] as usize, dark_mode),
                }
            };
            let bounds = facts.bounds[node as usize];
            instances.push(Instance {
                a: relative(bounds.min, tree.build.sphere),
                b: relative(bounds.max, tree.build.sphere),
                color: [color.r(), color.g(), color.b(), color.a()],
            });
        }
        // The selected node's planes outlined in their axis's colour, so they stand out of
        // the planes around them.
        if let Some(node) = self.selected {
            instances.extend(
                self.planes_of(tree, node)
                    .into_iter()
                    .map(|plane| plane.instance),
            );
        }
        instances
    }

    /// A kD-tree's split planes in the depth range, each clipped to its node's cell and
    /// coloured by axis (fainter deeper down), sorted back to front for `eye`; the selected
    /// and the hovered node's plane drawn strong at any depth, planes shown or not.
    fn planes(&self, tree: &MeshTree, eye: DVec3) -> Vec<Instance> {
        let facts = &tree.build.built.facts;
        let mut planes: Vec<(f64, Instance)> = Vec::new();
        for node in 0..facts.node_count() as u32 {
            let depth = facts.depth[node as usize] as usize;
            let lit = Some(node) == self.selected || Some(node) == self.hovered;
            let in_range = self.show_planes && self.depths().contains(&depth);
            if !(lit || in_range) {
                continue;
            }
            let alpha = if lit {
                150
            } else {
                (90 - 8 * depth.min(8)) as u8
            };
            for plane in self.planes_of(tree, node) {
                let [r, g, b, _] = plane.instance.color;
                planes.push((
                    (plane.center - eye).length(),
                    Instance {
                        color: [r, g, b, alpha],
                        ..plane.instance
                    },
                ));
            }
        }
        planes.sort_by(|a, b| b.0.total_cmp(&a.0));
        planes.into_iter().map(|(_, plane)| plane).collect()
    }

    /// `node`'s split planes clipped to its cell, each in its axis's colour: a kD node's one,
    /// an octree node's three (none for a leaf or a BVH node).
    fn planes_of(&self, tree: &MeshTree, node: u32) -> Vec<PlaneQuad> {
        let cell = tree.build.built.facts.bounds[node as usize];
        tree.build
            .built
            .cuts(node)
            .into_iter()
            .map(|(axis, position)| {
                let (mut low, mut high) = (cell.min, cell.max);
                low[axis] = position;
                high[axis] = position;
                let color = palette::AXES[axis];
                PlaneQuad {
                    center: (low + high) / 2.0,
                    instance: Instance {
                        a: relative(low, tree.build.sphere),
                        b: relative(high, tree.build.sphere),
                        color: [color.r(), color.g(), color.b(), 255],
                    },
                }
            })
            .collect()
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
            for precision in [Precision::F32, Precision::F64] {
                if ui
                    .selectable_label(self.precision == precision, precision.name())
                    .on_hover_text(
                        "The precision the structure is built in and the ray traced in (f32: as the CLI and the trade lab's f32 rows)",
                    )
                    .clicked()
                {
                    self.precision = precision;
                    self.stage.timeline.rewind();
                }
            }
            if ui
                .checkbox(&mut self.watertight, "watertight")
                .on_hover_text(
                    "The watertight triangle test (Woop et al. 2013) with the conservative slab test (Ize 2013); off: Möller–Trumbore and the plain slab test",
                )
                .changed()
            {
                self.stage.timeline.rewind();
            }
            ui.separator();
            ui.checkbox(&mut self.show_inner, "inner nodes");
            ui.checkbox(&mut self.show_leaves, "leaves");
            if matches!(self.structure.family(), Family::Kd | Family::Octree) {
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

    /// The mesh's and the tree's numbers, and a kD budget reached.
    fn numbers_ui(ui: &mut egui::Ui, tree: &MeshTree) {
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
            ui.colored_label(
                crate::canvas::readable(ui, palette::MISS),
                format!("kD budget: {limits}"),
            );
        }
    }

    /// The tree diagram, linked to the view, with what its colours say (squeezed to the
    /// height left with `fit_height`).
    fn tree_ui(&mut self, ui: &mut egui::Ui, tree: &MeshTree, fit_height: bool) {
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
            fit_height,
        );
        ui.label(
            egui::RichText::new(
                "Colour: depth; green entered, red missed or skipped. Hover a node to light its box; click a node or a box to select it.",
            )
            .small()
            .weak(),
        );
        let width = tree.build.built.structure.width();
        if tree.build.built.structure.family() == Family::Bvh && width != Width::Binary {
            ui.label(format!(
                "With {} children per node the tree drawn is still the binary one: the wide BVH is made from it by melting some binary nodes into their parents, and a wide node tests at once the boxes of the binary nodes just below it, so the steps name binary nodes (lesson 15 shows it in 2D).",
                width.children()
            ));
        }
    }

    /// The selected node: where it is, what is under it, its subtree's cost.
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
                Family::Kd | Family::Grid | Family::HashedGrid | Family::Octree => "cell",
            },
            point_at_scale(&bounds.min.to_array(), tree.build.sphere.1),
            point_at_scale(&bounds.max.to_array(), tree.build.sphere.1),
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

    /// The clicked ray in numbers that read back exactly (f64's shortest form): its pixel,
    /// origin, direction and the closest hit so far, and a button that copies it as a
    /// ray-file line, which `accelviz-cli query --rays` traces to the same hit.
    fn ray_ui(&self, ui: &mut egui::Ui, tree: &MeshTree) {
        let Some(picked) = self.picked else {
            return;
        };
        ui.separator();
        let heading = match picked.pixel {
            Some(pixel) => format!(
                "Clicked ray: pixel {}, {} of {} × {}, {}",
                pixel.column,
                pixel.row,
                pixel.width,
                pixel.height,
                self.order.name().replace('-', " ")
            ),
            None => format!("Ray, {}", self.order.name().replace('-', " ")),
        };
        ui.label(egui::RichText::new(heading).strong());
        let exact = |v: DVec3| format!("({:?}, {:?}, {:?})", v.x, v.y, v.z);
        ui.label(format!("origin {}", exact(picked.ray.origin)));
        ui.label(format!("direction {}", exact(picked.ray.direction)));
        if let Some(state) = self.shown_state() {
            let so_far = if state.done {
                "closest hit"
            } else {
                "closest hit so far"
            };
            ui.label(match state.closest {
                Some((triangle, t)) => format!("{so_far}: triangle #{triangle}, t = {t:?}"),
                None if state.done => "no hit".to_owned(),
                None => format!("{so_far}: none yet"),
            });
        }
        let line = accelviz_scene::rays::ray_line(&accelviz_scene::rays::RaySpec::generated(
            picked.ray.origin,
            picked.ray.direction,
        ));
        if ui
            .button("copy as a ray-file line")
            .on_hover_text(format!(
                "{line}\n\nSaved as ray.txt, the same ray and hit from the command line:\naccelviz-cli query --mesh {} --accel {} --precision {} --order {}{} --rays ray.txt",
                tree.mesh.name,
                self.structure.name(),
                tree.precision.name(),
                self.order.name(),
                if self.watertight { " --robust" } else { "" },
            ))
            .clicked()
        {
            ui.ctx().copy_text(line);
        }
    }

    /// The trade lab's ray: what the lab found for it, and every triangle the traversal tests
    /// as the row's test computes it in f32 and in f64 (`TriangleSet::explain`, the core's
    /// own test with what it computed on the way).
    fn examined_ui(&self, ui: &mut egui::Ui, tree: &MeshTree) {
        let (Some(examined), Some(trace), Some(picked)) =
            (self.examined(), self.trace.get(), self.picked)
        else {
            return;
        };
        let switches = examined.switches;
        ui.separator();
        ui.label(
            RichText::new(format!(
                "From the trade lab: {} for {} {} {} {}",
                examined.outcome.name().replace('_', " "),
                examined.structure.name(),
                switches.order.name(),
                switches.precision.name(),
                switches.test_name()
            ))
            .strong(),
        );
        ui.label(examined.outcome.about());
        ui.label(format!(
            "The ray is as {} rounded it. The steps are traced in {}, the tree built in it, with the {} test, as the row traced them; below, each triangle they test, by that test in f32 and in f64.",
            switches.precision.name(),
            tree.precision.name(),
            switches.test_name()
        ));
        let mut tested: Vec<u32> = Vec::new();
        for step in trace.shown(trace.frames()) {
            if let Step::PrimitiveTested { primitive, .. } = *step
                && !tested.contains(&primitive)
            {
                tested.push(primitive);
            }
        }
        const SHOWN: usize = 6;
        let test = if switches.watertight {
            accelviz_core::HitTest::Watertight
        } else {
            accelviz_core::HitTest::Fast
        };
        let coordinate_names = if switches.watertight {
            ["U", "V", "W"]
        } else {
            ["u", "v", "u+v"]
        };
        let ray = picked.ray;
        for &primitive in tested.iter().take(SHOWN) {
            let Some(corners) = tree.mesh.triangles.get(primitive as usize) else {
                continue;
            };
            ui.label(RichText::new(format!("triangle #{primitive}")).strong());
            let rows = [
                ("f32", explain_in::<glam::Vec3>(corners, ray, test)),
                ("f64", explain_in::<DVec3>(corners, ray, test)),
            ];
            for (precision, (coordinates, t, hit)) in rows {
                let named: Vec<String> = coordinate_names
                    .iter()
                    .zip(&coordinates)
                    .map(|(name, value)| format!("{name} = {value}"))
                    .collect();
                ui.horizontal_wrapped(|ui| {
                    ui.label(format!("{precision}: {}, t = {t}:", named.join(", ")));
                    let answer = RichText::new(if hit { "hit" } else { "miss" }).strong();
                    ui.label(answer.color(if hit { palette::HIT } else { palette::MISS }));
                });
            }
        }
        if tested.len() > SHOWN {
            ui.label(format!("… and {} more triangles", tested.len() - SHOWN));
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

    /// The mesh, structure and camera, the order, and the clicked pixel (its ray is the
    /// camera's through that pixel; the step is the link's own).
    fn share(&self) -> Vec<(String, String)> {
        let mut values =
            crate::share::mesh_view_values(&self.stage.scene, &self.structure, &self.view.orbit);
        values.push(crate::share::order_value(self.order));
        // The trade lab's switches, where they are not the lesson's own defaults.
        if self.precision != Precision::F64 {
            values.push((PRECISION.to_owned(), self.precision.name().to_owned()));
        }
        if self.watertight {
            values.push((TEST.to_owned(), "watertight".to_owned()));
        }
        if let Some(pixel) = self.picked.and_then(|picked| picked.pixel) {
            values.push((PIXEL.to_owned(), pixel.to_text()));
        }
        values
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        match key {
            PIXEL => {
                self.pending_pixel = Some(Pixel::parse(value)?);
                self.picked = None;
                Ok(())
            }
            crate::share::ORDER => {
                self.order = crate::share::parse_order(value)?;
                Ok(())
            }
            PRECISION => {
                self.precision = [Precision::F32, Precision::F64]
                    .into_iter()
                    .find(|precision| precision.name() == value)
                    .ok_or_else(|| format!("precision '{value}' is not f32 or f64"))?;
                Ok(())
            }
            TEST => {
                self.watertight = match value {
                    "watertight" => true,
                    "fast" => false,
                    _ => return Err(format!("test '{value}' is not fast or watertight")),
                };
                Ok(())
            }
            _ => {
                let (scene, structure) = (&mut self.stage.scene, &mut self.structure);
                crate::share::restore_mesh_view(scene, structure, &mut self.view.orbit, key, value)
            }
        }
    }

    fn update(&mut self) {
        let family = self.structure.family();
        if family != self.looks_for {
            (self.show_inner, self.show_leaves, self.show_planes) = Self::looks(family);
            self.looks_for = family;
        }
        self.stage
            .scene
            .request_tree_in(&mut self.tree, self.structure, self.precision);
        let Some(tree) = self.tree.get().cloned() else {
            return;
        };
        let nodes = tree.build.built.facts.node_count() as u32;
        if self.opened != Some(self.tree.generation()) {
            self.opened = Some(self.tree.generation());
            self.depth_range = opening_depths(nodes as usize);
        }
        if let Some(pixel) = self.pending_pixel.take() {
            let camera = self
                .view
                .orbit
                .camera(tree.build.sphere.0, tree.build.sphere.1);
            // As the click did: the box under the pixel selected (lit orange) and its ray
            // traced; a link that traced the ray alone lit the root instead.
            let (origin, direction) = pixel.ray(&camera);
            if let Some(node) = self.box_under(&tree, origin, direction) {
                self.selected = Some(node);
            }
            self.pick_pixel(pixel, &camera);
        }
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
        let (order, watertight) = (self.order, self.watertight);
        let query = self
            .examined()
            .map_or(accelviz_core::Query::Closest, |examined| examined.query);
        let key = (self.tree.generation(), picked.revision, order, watertight);
        let trace = self.trace.get_or_make(key, || {
            let options = accelviz_core::TraceOptions {
                query,
                ..options_in(order)
            }
            .with_robust(watertight);
            tree.trace(&picked.ray, &options)
        });
        self.stage.timeline.set_len(trace.frames());
    }

    fn take_export(&mut self) -> Option<crate::view3d::Export> {
        self.view.take_export()
    }

    fn show_ray(&mut self, request: &lesson::ShowRay) -> bool {
        let scene = &mut self.stage.scene;
        if scene.name != request.mesh_name || scene.mesh.triangles != request.mesh.triangles {
            scene.replace((*request.mesh).clone());
            scene.name = request.mesh_name.clone();
        }
        self.structure = request.structure;
        self.precision = request.switches.precision;
        self.order = request.switches.order;
        self.watertight = request.switches.watertight;
        self.examined = Some(Examined {
            switches: request.switches,
            query: request.query,
            outcome: request.outcome,
            structure: request.structure,
            ray: request.ray,
        });
        self.pick_exact(request.ray, None);
        true
    }

    fn caption(&self) -> Option<String> {
        let tree = self.tree.get()?;
        Some(tree.caption(
            self.trace.get(),
            self.stage.timeline.shown,
            "Click a pixel of the mesh: its ray is traced here, step by step.",
        ))
    }

    fn parts(&self) -> &'static [lesson::Part] {
        &PARTS
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, parts: Parts<'_>) {
        let Some(tree) = self.tree.get().cloned() else {
            ui.label("Building…");
            return;
        };
        if parts.show(&TREE_PART) {
            Self::numbers_ui(ui, &tree);
        }
        // What the class reads while stepping comes first: the ray and this step's slabs.
        if parts.show(&RAY_PART) {
            self.ray_ui(ui, &tree);
            self.examined_ui(ui, &tree);
            self.slab_ui(ui, &tree);
        }
        if parts.show(&DEPTHS_PART) {
            ui.separator();
            let max_depth = tree.build.built.facts.max_depth();
            depth_range_ui(ui, &mut self.depth_range, max_depth);
        }
        if parts.show(&TREE_PART) {
            ui.separator();
            self.tree_ui(ui, &tree, parts.fit_screen());
        }
        if parts.show(&NODE_PART) {
            ui.separator();
            self.node_ui(ui, &tree);
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.controls_ui(ui);
        loading_ui(
            ui,
            &mut self.stage.scene,
            &mut self.tree,
            (&mut self.structure, &mut self.precision),
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
        let dark_mode = ui.visuals().dark_mode;
        let boxes_revision = revision_of((
            self.tree.generation(),
            dark_mode,
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
                Arc::new(self.boxes(&tree, steps, current, dark_mode))
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
        if let Some(pixel) = response.clicked {
            let (origin, direction) = pixel.ray(&response.camera);
            if let Some(node) = self.box_under(&tree, origin, direction) {
                self.selected = Some(node);
            }
            self.pick_pixel(pixel, &response.camera);
        }
    }
}
