//! The builds and traversals of a triangle mesh, compiled here, once, for the types the apps
//! trace meshes in.
//!
//! Rust compiles a generic function where it is used with concrete types: `Tree::trace` over
//! f32 triangles, called from the app, is compiled in the app. The browser app is compiled
//! for size (its download) and the core for speed (`Cargo.toml`, profile `web`), so the
//! hot paths the browser runs on many rays (the benchmark against three-mesh-bvh, heat maps,
//! the builds of a mesh's tree) go through these functions: not generic, so compiled in the
//! core, at the core's optimisation, whoever calls them. They do exactly what the generic
//! calls they wrap do.

use glam::{DVec3, Vec3};

use crate::built::Built;
use crate::params::BuildParams;
use crate::primitive::{LeafOrdered, TriangleSet};
use crate::structure::{Structure, TraversalStacks, Tree};
use crate::{Counters, Hit, NoBuildObserver, NoObserver, Ray, TraceOptions};

/// [`Built::new`] over triangles in f64, with no observer.
#[inline(never)]
pub fn build_triangles(
    structure: Structure,
    triangles: &TriangleSet<DVec3>,
    params: &BuildParams,
) -> Built<DVec3> {
    Built::new(structure, triangles, params, &mut NoBuildObserver)
}

/// [`Built::new`] over triangles in f32, with no observer.
#[inline(never)]
pub fn build_triangles_f32(
    structure: Structure,
    triangles: &TriangleSet<Vec3>,
    params: &BuildParams,
) -> Built<Vec3> {
    Built::new(structure, triangles, params, &mut NoBuildObserver)
}

/// [`Structure::build`] over triangles in f32: the tree alone, as the benchmarks time it.
#[inline(never)]
pub fn build_tree_f32(
    structure: Structure,
    triangles: &TriangleSet<Vec3>,
    params: &BuildParams,
) -> Tree<Vec3> {
    structure.build(triangles, params)
}

/// [`Tree::trace`] of one ray through triangles in f32 (in leaf order), unobserved.
#[inline(never)]
pub fn trace_triangles_f32(
    tree: &Tree<Vec3>,
    triangles: &LeafOrdered<TriangleSet<Vec3>>,
    ray: &Ray<Vec3>,
    options: &TraceOptions,
    stacks: &mut TraversalStacks<f32>,
) -> Option<Hit<f32>> {
    tree.trace(triangles, ray, options, stacks, &mut NoObserver)
}

/// [`Tree::trace`] of one ray through triangles in f64 (in leaf order), unobserved.
#[inline(never)]
pub fn trace_triangles(
    tree: &Tree<DVec3>,
    triangles: &LeafOrdered<TriangleSet<DVec3>>,
    ray: &Ray<DVec3>,
    options: &TraceOptions,
    stacks: &mut TraversalStacks<f64>,
) -> Option<Hit<f64>> {
    tree.trace(triangles, ray, options, stacks, &mut NoObserver)
}

/// [`Tree::trace`] of one ray through triangles in f64 (in leaf order), counted.
#[inline(never)]
pub fn trace_triangles_counted(
    tree: &Tree<DVec3>,
    triangles: &LeafOrdered<TriangleSet<DVec3>>,
    ray: &Ray<DVec3>,
    options: &TraceOptions,
    stacks: &mut TraversalStacks<f64>,
    counters: &mut Counters,
) -> Option<Hit<f64>> {
    tree.trace(triangles, ray, options, stacks, counters)
}

/// [`Tree::trace_packet`] of rays through triangles in f64 (in leaf order), each counted.
#[inline(never)]
pub fn trace_packet_counted(
    tree: &Tree<DVec3>,
    triangles: &LeafOrdered<TriangleSet<DVec3>>,
    rays: &[Ray<DVec3>],
    options: &TraceOptions,
    stacks: &mut TraversalStacks<f64>,
    counters: &mut [Counters],
    hits: &mut [Option<Hit<f64>>],
) {
    tree.trace_packet(triangles, rays, options, stacks, counters, hits);
}
