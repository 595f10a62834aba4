//! Property tests: on random, clustered and degenerate scenes in 2D and 3D, every builder,
//! both orders, both precisions, fast and robust modes, closest and any hit, agree with brute
//! force. Seeded, so a failure reproduces.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use crate::common;

use accelviz_core::{Aabb, Ray, Shape, ShapeSet, Sphere, TriangleSet, Vector};
use common::assert_agrees_with_brute_force;
use glam::{DVec2, DVec3, Vec2, Vec3};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

fn config() -> Config {
    Config {
        cases: 48,
        rng_seed: RngSeed::Fixed(0x5eed_acce_1512),
        failure_persistence: None,
        ..Config::default()
    }
}

fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0f64,
        // Snapped values make coplanar, axis-aligned and coincident geometry common.
        1 => (-4i32..4).prop_map(|value| value as f64),
    ]
}

fn point3() -> impl Strategy<Value = [f64; 3]> {
    [coordinate(), coordinate(), coordinate()]
}

/// Triangles scattered uniformly, in tight clusters, or degenerate (repeated or collinear
/// corners, all in one plane, duplicates).
fn triangles() -> impl Strategy<Value = Vec<[[f64; 3]; 3]>> {
    let uniform = prop::collection::vec([point3(), point3(), point3()], 0..80);
    let clustered = (
        prop::collection::vec(point3(), 1..4),
        prop::collection::vec((0usize..4, point3(), point3(), point3()), 1..120),
    )
        .prop_map(|(centers, items)| {
            items
                .into_iter()
                .map(|(cluster, a, b, c)| {
                    let center = centers[cluster % centers.len()];
                    [a, b, c].map(|p| [0, 1, 2].map(|axis| center[axis] + p[axis] * 0.01))
                })
                .collect()
        });
    let degenerate =
        prop::collection::vec((point3(), point3(), 0usize..4), 1..60).prop_map(|items| {
            items
                .into_iter()
                .map(|(a, b, kind)| match kind {
                    0 => [a, a, b],
                    1 => [a, b, [0, 1, 2].map(|axis| 2.0 * b[axis] - a[axis])],
                    2 => [[a[0], a[1], 0.0], [b[0], b[1], 0.0], [a[1], b[0], 0.0]],
                    _ => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                })
                .collect()
        });
    prop_oneof![uniform, clustered, degenerate]
}

fn direction3() -> impl Strategy<Value = [f64; 3]> {
    prop_oneof![
        3 => point3(),
        // Axis-aligned directions, with ±0 components.
        1 => (0usize..3, prop::bool::ANY, prop::bool::ANY).prop_map(|(axis, negative, negative_zero)| {
            let zero = if negative_zero { -0.0 } else { 0.0 };
            let mut direction = [zero; 3];
            direction[axis] = if negative { -1.0 } else { 1.0 };
            direction
        }),
    ]
    .prop_filter("nonzero", |d| d.iter().any(|&c| c != 0.0))
}

fn rays3() -> impl Strategy<Value = Vec<([f64; 3], [f64; 3], bool)>> {
    prop::collection::vec((point3(), direction3(), prop::bool::ANY), 1..24)
}

fn make_rays<V: Vector>(rays: &[([f64; 3], [f64; 3], bool)]) -> Vec<Ray<V>> {
    rays.iter()
        .filter_map(|(origin, direction, bounded)| {
            let t_max = if *bounded { 5.0 } else { f64::INFINITY };
            Ray::try_with_interval(
                V::from_f64_slice(origin),
                V::from_f64_slice(direction),
                V::Scalar::from_f64(0.0),
                V::Scalar::from_f64(t_max),
            )
            .ok()
        })
        .collect()
}

use accelviz_core::Real;

proptest! {
    #![proptest_config(config())]

    #[test]
    fn triangles_3d_agree_with_brute_force(scene in triangles(), rays in rays3()) {
        assert_agrees_with_brute_force(&TriangleSet::<Vec3>::from_f64(&scene), &make_rays::<Vec3>(&rays));
        assert_agrees_with_brute_force(&TriangleSet::<DVec3>::from_f64(&scene), &make_rays::<DVec3>(&rays));
    }

    #[test]
    fn rays_aimed_at_the_scene_agree_with_brute_force(
        scene in triangles(),
        aims in prop::collection::vec((point3(), 0usize..1000, 0.0..1.0f64, 0.0..1.0f64), 1..24),
    ) {
        // Rays from outside towards points on the triangles themselves: hits, edges, ties.
        prop_assume!(!scene.is_empty());
        let rays: Vec<_> = aims
            .iter()
            .map(|(origin, which, u, v)| {
                let [a, b, c] = scene[which % scene.len()];
                let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (*u, *v) };
                let target = [0, 1, 2].map(|axis| a[axis] + u * (b[axis] - a[axis]) + v * (c[axis] - a[axis]));
                let origin = origin.map(|x| x * 3.0);
                (origin, [0, 1, 2].map(|axis| target[axis] - origin[axis]), false)
            })
            .collect();
        assert_agrees_with_brute_force(&TriangleSet::<Vec3>::from_f64(&scene), &make_rays::<Vec3>(&rays));
        assert_agrees_with_brute_force(&TriangleSet::<DVec3>::from_f64(&scene), &make_rays::<DVec3>(&rays));
    }

    #[test]
    fn shapes_2d_agree_with_brute_force(scene in shapes2(), rays in rays3()) {
        let rays2: Vec<_> = rays
            .iter()
            .map(|(o, d, bounded)| ([o[0], o[1], 0.0], [d[0], d[1], 0.0], *bounded))
            .collect();
        assert_agrees_with_brute_force(&shape_set::<Vec2>(&scene), &make_rays::<Vec2>(&rays2));
        assert_agrees_with_brute_force(&shape_set::<DVec2>(&scene), &make_rays::<DVec2>(&rays2));
    }
}

/// A 2D shape in f64 before conversion: (kind, a, b, radius).
type ShapeSpec = (usize, [f64; 3], [f64; 3], f64);

fn shapes2() -> impl Strategy<Value = Vec<ShapeSpec>> {
    let one = || (0usize..3, point3(), point3(), 0.0..2.0f64);
    prop_oneof![
        prop::collection::vec(one(), 0..80),
        // A cluster: everything within 0.05 of one point.
        (point3(), prop::collection::vec(one(), 1..100)).prop_map(|(center, items)| {
            items
                .into_iter()
                .map(|(kind, a, b, r)| {
                    let near = |p: [f64; 3]| [0, 1, 2].map(|axis| center[axis] + p[axis] * 0.005);
                    (kind, near(a), near(b), r * 0.01)
                })
                .collect()
        }),
    ]
}

fn shape_set<V: Vector>(specs: &[ShapeSpec]) -> ShapeSet<V> {
    let point = |p: &[f64; 3]| V::from_f64_slice(p);
    ShapeSet {
        shapes: specs
            .iter()
            .map(|(kind, a, b, radius)| match kind {
                0 => Shape::Segment([point(a), point(b)]),
                1 => Shape::Sphere(Sphere {
                    center: point(a),
                    radius: V::Scalar::from_f64(*radius),
                }),
                _ => Shape::Box(Aabb::from_points([point(a), point(b)])),
            })
            .collect(),
    }
}
