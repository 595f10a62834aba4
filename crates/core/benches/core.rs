//! Criterion benches of the core: the slab test, each BVH and kD builder, traversal of both
//! kinds of tree in both orders, what observing a wide traversal costs (nothing for
//! `NoObserver`), and a node's SAH cost curve, on the built-in lumpy sphere
//! (20,480 triangles) and its seeded random rays; and how the kD SAH build scales (10k, 100k
//! and 1M triangles, both ways of sorting). `accelviz-cli bench` measures the same on any mesh.

#![allow(missing_docs, clippy::unwrap_used)]

use std::hint::black_box;

use accelviz_core::bvh::{BinnedSah, Builder, TraversalStack, traverse};
use accelviz_core::kd::{self, KdBuilder, KdSah, KdSahPresorted};
use accelviz_core::params::BuildParams;
use accelviz_core::{
    Aabb, CATALOGUE, Counters, LeafOrdered, NoObserver, Observer, Order, PrimitiveSet, Ray,
    Recorder, SahCost, SlabRay, Structure, TraceOptions, TraversalStacks, Tree, TriangleSet, Width,
    curve, slab_clip,
};
use accelviz_scene::builtin::{lumpy_grid_sphere, lumpy_sphere};
use accelviz_scene::rays::random_rays;
use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;

fn slab(c: &mut Criterion) {
    let bounds = Aabb::new(Vec3::ZERO, Vec3::ONE);
    let rays: Vec<SlabRay<Vec3>> =
        random_rays(&Aabb::new(glam::DVec3::ZERO, glam::DVec3::ONE), 1024, 1)
            .iter()
            .map(|spec| SlabRay::new(&spec.to_ray::<Vec3>().unwrap(), false))
            .collect();
    c.bench_function("slab test x1024", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|ray| {
                    let (t_enter, t_exit) = slab_clip(black_box(&bounds), ray, f32::INFINITY);
                    t_enter <= t_exit
                })
                .count()
        })
    });
}

/// Every structure of the catalogue, built the way the CLI builds it.
fn builders(c: &mut Criterion) {
    let mesh = lumpy_sphere();
    let triangles = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    let params = BuildParams::default();
    let mut group = c.benchmark_group("build lumpy sphere");
    group.sample_size(10);
    for entry in &CATALOGUE {
        let structure = entry.structure;
        group.bench_function(structure.name(), |b| {
            b.iter(|| structure.build(&triangles, &params))
        });
    }
    group.finish();
}

/// The kD SAH build at 10k, 100k and 1M triangles: sorting once should grow as n log n,
/// sorting at every node as n log² n.
fn kd_scaling(c: &mut Criterion) {
    let params = BuildParams::default();
    let mut group = c.benchmark_group("kd:sah build scaling");
    group.sample_size(10);
    for count in [10_000, 100_000, 1_000_000] {
        let bounds =
            TriangleSet::<Vec3>::from_f64(&lumpy_grid_sphere(count).triangles).all_bounds();
        group.bench_function(format!("sorted once, {count} triangles"), |b| {
            b.iter(|| KdSahPresorted.build(&bounds, &params))
        });
        if count <= 100_000 {
            group.bench_function(format!("sorted per node, {count} triangles"), |b| {
                b.iter(|| KdSah.build(&bounds, &params))
            });
        }
    }
    group.finish();
}

/// The root's cost curves (what the SAH lesson plots at every slider move).
fn curves(c: &mut Criterion) {
    let mesh = lumpy_sphere();
    let bounds = TriangleSet::<Vec3>::from_f64(&mesh.triangles).all_bounds();
    let all: Vec<u32> = (0..bounds.len() as u32).collect();
    let cell = bounds.iter().fold(Aabb::empty(), |acc, b| acc.union(*b));
    let cost = SahCost::default();
    let mut group = c.benchmark_group("cost curve of the root");
    group.sample_size(10);
    group.bench_function("bvh, exact + 16 bins", |b| {
        b.iter(|| curve::bvh_curve(&bounds, &all, &cost, Some(16)))
    });
    group.bench_function("kd, exact + 16 bins", |b| {
        b.iter(|| curve::kd_curve(&bounds, &all, &cell, &cost, Some(16)))
    });
    group.finish();
}

fn traversal(c: &mut Criterion) {
    let mesh = lumpy_sphere();
    let triangles = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    let bvh = BinnedSah::default().build(&triangles.all_bounds(), &BuildParams::default());
    let bvh_triangles = bvh.leaf_ordered(&triangles);
    let tree = KdSahPresorted.build(&triangles.all_bounds(), &BuildParams::default());
    let kd_triangles = tree.leaf_ordered(&triangles);
    let rays: Vec<Ray<Vec3>> = random_rays(&mesh.bounds(), 10_000, 1)
        .iter()
        .map(|spec| spec.to_ray().unwrap())
        .collect();
    let mut group = c.benchmark_group("trace 10k random rays");
    group.sample_size(10);
    for (name, order) in [
        ("near-first", Order::NearFirst),
        ("file-order", Order::FileOrder),
    ] {
        let options = TraceOptions {
            order,
            ..TraceOptions::default()
        };
        group.bench_function(format!("bvh {name}"), |b| {
            let mut stack = TraversalStack::new();
            b.iter(|| {
                rays.iter()
                    .filter(|ray| {
                        traverse(
                            &bvh,
                            &bvh_triangles,
                            ray,
                            &options,
                            &mut stack,
                            &mut NoObserver,
                        )
                        .is_some()
                    })
                    .count()
            })
        });
        group.bench_function(format!("kd:sah {name}"), |b| {
            let mut stack = kd::KdTraversalStack::new();
            b.iter(|| {
                rays.iter()
                    .filter(|ray| {
                        kd::traverse(
                            &tree,
                            &kd_triangles,
                            ray,
                            &options,
                            &mut stack,
                            &mut NoObserver,
                        )
                        .is_some()
                    })
                    .count()
            })
        });
    }
    group.finish();
}

/// Observing a wide traversal: nothing (`NoObserver`, whose `ACTIVE` is false, so traversal does
/// not even compute what it would report), an observer that hears every step and ignores it
/// (what the calls and their arguments cost), counting, and recording every step.
fn observers(c: &mut Criterion) {
    /// Hears everything, keeps nothing.
    struct Silent;
    impl Observer<f32> for Silent {}

    let mesh = lumpy_sphere();
    let triangles = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    let tree = Structure::BvhSahBinned {
        bins: 16,
        width: Width::Eight,
    }
    .build(&triangles, &BuildParams::default());
    let leaf_ordered = tree.leaf_ordered(&triangles);
    let rays: Vec<Ray<Vec3>> = random_rays(&mesh.bounds(), 10_000, 1)
        .iter()
        .map(|spec| spec.to_ray().unwrap())
        .collect();
    let options = TraceOptions::default();
    let mut group = c.benchmark_group("bvh8 10k random rays, observed");
    group.sample_size(20);
    let mut stacks = TraversalStacks::default();
    // Traces every ray with `observer`; the number of hits.
    fn hits<O: Observer<f32>>(
        tree: &Tree<Vec3>,
        primitives: &LeafOrdered<TriangleSet<Vec3>>,
        rays: &[Ray<Vec3>],
        stacks: &mut TraversalStacks<f32>,
        observer: &mut O,
    ) -> usize {
        let options = TraceOptions::default();
        rays.iter()
            .filter(|ray| {
                tree.trace(primitives, ray, &options, stacks, observer)
                    .is_some()
            })
            .count()
    }
    group.bench_function("NoObserver", |b| {
        b.iter(|| hits(&tree, &leaf_ordered, &rays, &mut stacks, &mut NoObserver))
    });
    group.bench_function("an observer that ignores every step", |b| {
        b.iter(|| hits(&tree, &leaf_ordered, &rays, &mut stacks, &mut Silent))
    });
    group.bench_function("Counters", |b| {
        b.iter(|| {
            let mut counters = Counters::default();
            hits(&tree, &leaf_ordered, &rays, &mut stacks, &mut counters);
            counters
        })
    });
    group.bench_function("Recorder", |b| {
        let mut recorder = Recorder::default();
        b.iter(|| {
            for ray in &rays {
                recorder.steps.clear();
                tree.trace(&leaf_ordered, ray, &options, &mut stacks, &mut recorder);
            }
        })
    });
    group.finish();
}

criterion_group!(
    benches, slab, builders, traversal, observers, curves, kd_scaling
);
criterion_main!(benches);
