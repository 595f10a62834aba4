//! A structure built over a 3D lesson's mesh ([`MeshTree`]): what 3D lessons draw, trace and
//! measure, and what a build makes on the builder's thread ([`MeshBuild`]).

use std::sync::{Arc, OnceLock};

use accelviz_core::camera::bounding_sphere_of_box;
use accelviz_core::params::BuildParams;
use accelviz_core::trade::Precision;
use accelviz_core::{
    Built, LeafOrdered, Ray, Structure, TraceOptions, Tree, TreeStats, TriangleSet, compiled,
};
use accelviz_scene::Mesh;
use glam::{DVec3, Vec3};
use web_time::Instant;

use crate::stage::KD_BUDGET;
use crate::view3d::{DrawTriangle, relative};

/// What building a structure over a mesh makes, on the builder's thread (a worker thread, or
/// a Web Worker whence it comes [`pack`](super::packed::pack)ed): the structure, what is measured of it, and the
/// mesh as drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshBuild {
    /// The tree and its facts.
    pub built: Built<DVec3>,
    /// Its statistics.
    pub stats: TreeStats,
    /// How many triangles lie under the root (the inspector opens on it; counted here, since
    /// a million-triangle tree takes tens of milliseconds).
    pub root_triangles: usize,
    /// How long the build took.
    pub build_millis: f64,
    /// The mesh's bounding sphere (centre, radius): the view's centre and size.
    pub sphere: (DVec3, f64),
    /// The mesh as drawn (relative to the sphere, see [`relative`]).
    pub drawn: Vec<DrawTriangle>,
}

/// The mesh's colour (sRGB).
const MESH_COLOR: [u8; 4] = [178, 188, 204, 255];

/// A structure built over a mesh, with what the view draws of the mesh.
pub struct MeshTree {
    /// The mesh.
    pub mesh: Arc<Mesh>,
    /// Its triangles as the core traces them (rounded to the tree's precision, widened).
    pub triangles: TriangleSet<DVec3>,
    /// The structure, what was measured of it, and the mesh as drawn.
    pub build: MeshBuild,
    /// The precision the tree was built and is traced in: f64, or f32 as a trade row builds
    /// it (the tree then widened to f64 node for node for the view, exactly).
    pub precision: Precision,
    /// The triangles in the tree's leaf order, made when first asked for (only the heat
    /// maps trace that many rays).
    ordered: OnceLock<LeafOrdered<TriangleSet<DVec3>>>,
    /// An f32 tree's own numbers, narrowed back from the view's (exactly), made when first
    /// traced.
    in_f32: OnceLock<(Tree<Vec3>, TriangleSet<Vec3>)>,
}

impl MeshTree {
    /// Builds `structure` over `mesh`.
    pub fn build(mesh: Arc<Mesh>, structure: Structure) -> Self {
        let triangles = TriangleSet::<DVec3>::from_f64(&mesh.triangles);
        let built = Self::build_structure(&mesh, &triangles, structure);
        Self::with_built(mesh, triangles, built)
    }

    /// Builds `structure` over `mesh` in `precision`: in f64 as [`build`](Self::build); in
    /// f32 as a trade row does, over the mesh rounded to f32, the tree then widened to f64
    /// (exactly) for the view.
    pub fn build_in(mesh: Arc<Mesh>, structure: Structure, precision: Precision) -> Self {
        if precision == Precision::F64 {
            return Self::build(mesh, structure);
        }
        let in_f32 = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
        let rounded: Vec<[[f64; 3]; 3]> = in_f32
            .triangles()
            .iter()
            .map(|corners| corners.map(|corner| corner.as_dvec3().to_array()))
            .collect();
        let build = Self::measured(&mesh, |params| {
            compiled::build_triangles_f32(structure, &in_f32, params).converted()
        });
        Self {
            triangles: TriangleSet::<DVec3>::from_f64(&rounded),
            build,
            precision,
            ordered: OnceLock::new(),
            in_f32: OnceLock::new(),
            mesh,
        }
    }

    /// Traces `ray` through the tree in its precision (the ray rounded to it), recorded step
    /// by step in f64: what a trade row of that precision computes.
    pub fn trace(&self, ray: &Ray<DVec3>, options: &TraceOptions) -> crate::trace::Trace {
        match self.precision {
            Precision::F64 => {
                crate::trace::Trace::of(&self.build.built.tree, &self.triangles, ray, options)
            }
            Precision::F32 => {
                let (tree, triangles) = self.in_f32.get_or_init(|| {
                    (
                        self.build.built.tree.converted(),
                        TriangleSet::<Vec3>::from_f64(&self.mesh.triangles),
                    )
                });
                let narrowed = Ray {
                    origin: ray.origin.as_vec3(),
                    direction: ray.direction.as_vec3(),
                    t_min: ray.t_min as f32,
                    t_max: ray.t_max as f32,
                };
                crate::trace::Trace::of_any_precision(tree, triangles, &narrowed, options)
            }
        }
    }

    /// What a build does on the builder's thread: the structure over `triangles` (`mesh`'s),
    /// what is measured of it, and the mesh as drawn (the part a Web Worker does in the
    /// browser, see [`super::aside`]).
    pub fn build_structure(
        mesh: &Mesh,
        triangles: &TriangleSet<DVec3>,
        structure: Structure,
    ) -> MeshBuild {
        Self::measured(mesh, |params| {
            compiled::build_triangles(structure, triangles, params)
        })
    }

    /// A build over `mesh` by `build` (with the lessons' parameters), timed, measured and
    /// with the mesh as drawn.
    fn measured(mesh: &Mesh, build: impl FnOnce(&BuildParams) -> Built<DVec3>) -> MeshBuild {
        let params = BuildParams {
            kd_budget: KD_BUDGET,
            ..BuildParams::default()
        };
        let started = Instant::now();
        let built = build(&params);
        let build_millis = started.elapsed().as_secs_f64() * 1e3;
        let sphere = bounding_sphere_of_box(&mesh.bounds());
        let drawn = mesh
            .triangles
            .iter()
            .map(|triangle| DrawTriangle {
                corners: triangle.map(|corner| relative(DVec3::from_array(corner), sphere)),
                color: MESH_COLOR,
            })
            .collect();
        MeshBuild {
            stats: built.stats(0, &params.cost),
            root_triangles: built.primitives_below(0).len(),
            built,
            build_millis,
            sphere,
            drawn,
        }
    }

    /// The mesh with a structure built over its `triangles`.
    pub fn with_built(mesh: Arc<Mesh>, triangles: TriangleSet<DVec3>, build: MeshBuild) -> Self {
        Self {
            mesh,
            triangles,
            build,
            precision: Precision::F64,
            ordered: OnceLock::new(),
            in_f32: OnceLock::new(),
        }
    }

    /// The triangles in the tree's leaf order, for tracing many rays fast.
    pub fn ordered(&self) -> &LeafOrdered<TriangleSet<DVec3>> {
        self.ordered
            .get_or_init(|| self.build.built.tree.leaf_ordered(&self.triangles))
    }

    /// The timeline's caption for a clicked pixel's `trace` at `frame`, or `idle` before a
    /// pixel is clicked.
    pub fn caption(&self, trace: Option<&crate::trace::Trace>, frame: usize, idle: &str) -> String {
        match trace {
            None => idle.to_owned(),
            Some(trace) => trace.caption(
                frame,
                "Press step: the traversal starts by testing the root's box.",
                |step| crate::trace::describe_step(step, |node| self.node_name(node)),
            ),
        }
    }

    /// A node's name: its path from the root (`the root`, `node LRL`), a grid cell's
    /// coordinates (`cell (3, 1, 4)`), an octree node's octant at each level (`octant 5·0·3`,
    /// the bits of each number saying above the middle along x, y, z).
    pub fn node_name(&self, node: u32) -> String {
        let built = &self.build.built;
        if let Some([x, y, z]) = built.grid_coordinates(node) {
            return format!("cell ({x}, {y}, {z})");
        }
        match built.facts.path_to(node) {
            path if path.is_empty() => "the root".to_owned(),
            path if path.chars().all(|step| step.is_ascii_digit()) => {
                let levels: Vec<String> = path.chars().map(String::from).collect();
                format!("octant {}", levels.join("·"))
            }
            path => format!("node {path}"),
        }
    }
}
