//! Criterion benches of the core: the slab test, each builder, and traversal in both orders,
//! on the built-in lumpy sphere (20,480 triangles) and its seeded random rays.
//! `accelviz-cli bench` measures the same on any mesh.

#![allow(missing_docs, clippy::unwrap_used)]

use std::hint::black_box;

use accelviz_core::bvh::{
    BinnedSah, BuildParams, Builder, MedianSplit, MiddleSplit, SweepSah, TraversalStack, traverse,
};
use accelviz_core::{
    Aabb, NoObserver, Order, PrimitiveSet, Ray, SlabRay, TraceOptions, TriangleSet, slab_clip,
};
use accelviz_scene::builtin::lumpy_sphere;
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

fn builders(c: &mut Criterion) {
    let mesh = lumpy_sphere();
    let triangles = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    let bounds = triangles.all_bounds();
    let params = BuildParams::default();
    let mut group = c.benchmark_group("build lumpy sphere");
    group.sample_size(10);
    group.bench_function("middle", |b| b.iter(|| MiddleSplit.build(&bounds, &params)));
    group.bench_function("median", |b| b.iter(|| MedianSplit.build(&bounds, &params)));
    group.bench_function("sah-binned:16", |b| {
        b.iter(|| BinnedSah { bins: 16 }.build(&bounds, &params))
    });
    group.bench_function("sah-sweep", |b| b.iter(|| SweepSah.build(&bounds, &params)));
    group.finish();
}

fn traversal(c: &mut Criterion) {
    let mesh = lumpy_sphere();
    let triangles = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    let bvh = BinnedSah::default().build(&triangles.all_bounds(), &BuildParams::default());
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
        group.bench_function(name, |b| {
            let mut stack = TraversalStack::new();
            b.iter(|| {
                rays.iter()
                    .filter(|ray| {
                        traverse(&bvh, &triangles, ray, &options, &mut stack, &mut NoObserver)
                            .is_some()
                    })
                    .count()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, slab, builders, traversal);
criterion_main!(benches);
