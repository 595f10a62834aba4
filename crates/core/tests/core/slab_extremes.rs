//! The slab test at the extremes, with the expected answers written down.
//!
//! Each case runs in f64 and f32, fast and robust, through the record (what a lesson shows)
//! and through the hot path (what traversal runs); both must give the written answer. Every
//! hit whose origin is outside the box is run reversed too, and must miss.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::{Aabb, Ray, Real, SlabRay, Vector, slab_clip, slab_record};
use glam::{DVec2, DVec3, Vec2, Vec3};

struct Case {
    /// What the case is about.
    what: &'static str,
    min: [f64; 3],
    max: [f64; 3],
    origin: [f64; 3],
    direction: [f64; 3],
    /// Expected (t_enter, t_exit) of the record, or None for a miss.
    expected: Option<(f64, f64)>,
}

fn cases() -> Vec<Case> {
    let unit = ([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
    let case = |what, (min, max): ([f64; 3], [f64; 3]), origin, direction, expected| Case {
        what,
        min,
        max,
        origin,
        direction,
        expected,
    };
    vec![
        case(
            "straight through along +x",
            unit,
            [-1.0, 0.5, 0.5],
            [1.0, 0.0, 0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "straight through along -x",
            unit,
            [2.0, 0.5, 0.5],
            [-1.0, 0.0, 0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "-0 components, origin inside the other slabs",
            unit,
            [-1.0, 0.5, 0.5],
            [1.0, -0.0, -0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "+0 y component, origin above the y slab",
            unit,
            [-1.0, 2.0, 0.5],
            [1.0, 0.0, 0.0],
            None,
        ),
        case(
            "-0 y component, origin above the y slab",
            unit,
            [-1.0, 2.0, 0.5],
            [1.0, -0.0, 0.0],
            None,
        ),
        case(
            "+0 y component, origin below the y slab",
            unit,
            [-1.0, -1.0, 0.5],
            [1.0, 0.0, 0.0],
            None,
        ),
        case(
            "+0 y, origin exactly on the lower y plane",
            unit,
            [-1.0, 0.0, 0.5],
            [1.0, 0.0, 0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "-0 y, origin exactly on the lower y plane",
            unit,
            [-1.0, 0.0, 0.5],
            [1.0, -0.0, 0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "+0 y, origin exactly on the upper y plane",
            unit,
            [-1.0, 1.0, 0.5],
            [1.0, 0.0, 0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "-0 y, origin exactly on the upper y plane",
            unit,
            [-1.0, 1.0, 0.5],
            [1.0, -0.0, 0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "grazing along an edge (on two planes)",
            unit,
            [-1.0, 1.0, 1.0],
            [1.0, 0.0, -0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "grazing along a face diagonally",
            unit,
            [-1.0, -1.0, 1.0],
            [1.0, 1.0, 0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "touching a corner only",
            unit,
            [2.0, 0.0, 0.5],
            [-1.0, 1.0, 0.0],
            Some((1.0, 1.0)),
        ),
        case(
            "passing a corner by a hair",
            unit,
            [2.0, 0.000_001, 0.5],
            [-1.0, 1.0, 0.0],
            None,
        ),
        case(
            "origin inside",
            unit,
            [0.5, 0.5, 0.5],
            [1.0, 2.0, 4.0],
            Some((-0.125, 0.125)),
        ),
        case(
            "origin on a face, leaving",
            unit,
            [1.0, 0.5, 0.5],
            [1.0, 0.0, 0.0],
            Some((-1.0, 0.0)),
        ),
        case(
            "origin on a face, entering",
            unit,
            [0.0, 0.5, 0.5],
            [1.0, 0.0, 0.0],
            Some((0.0, 1.0)),
        ),
        case(
            "origin on a corner, along the diagonal",
            unit,
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 1.0],
            Some((0.0, 1.0)),
        ),
        case(
            "box behind the ray",
            unit,
            [2.0, 0.5, 0.5],
            [1.0, 0.0, 0.0],
            None,
        ),
        case(
            "flat box, crossed",
            ([0.0, 0.0, 0.0], [1.0, 0.0, 1.0]),
            [0.5, -1.0, 0.5],
            [0.0, 1.0, 0.0],
            Some((1.0, 1.0)),
        ),
        case(
            "flat box, ray in its plane",
            ([0.0, 0.0, 0.0], [1.0, 0.0, 1.0]),
            [-1.0, 0.0, 0.5],
            [1.0, 0.0, 0.0],
            Some((1.0, 2.0)),
        ),
        case(
            "flat box, ray parallel beside it",
            ([0.0, 0.0, 0.0], [1.0, 0.0, 1.0]),
            [-1.0, 0.25, 0.5],
            [1.0, 0.0, 0.0],
            None,
        ),
        case(
            "point box, hit",
            ([1.0, 1.0, 1.0], [1.0, 1.0, 1.0]),
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 1.0],
            Some((1.0, 1.0)),
        ),
        case(
            "huge coordinates",
            ([1e30, 1e30, 1e30], [2e30, 2e30, 2e30]),
            [0.0, 1.5e30, 1.5e30],
            [1.0, 0.0, 0.0],
            Some((1e30, 2e30)),
        ),
        case(
            "huge coordinates, miss",
            ([1e30, 1e30, 1e30], [2e30, 2e30, 2e30]),
            [0.0, 2.5e30, 1.5e30],
            [1.0, 0.0, 0.0],
            None,
        ),
        case(
            "tiny coordinates",
            ([1e-30, 1e-30, 1e-30], [2e-30, 2e-30, 2e-30]),
            [0.0, 1.5e-30, 1.5e-30],
            [1.0, 0.0, 0.0],
            Some((1e-30, 2e-30)),
        ),
        case(
            "tiny coordinates, miss",
            ([1e-30, 1e-30, 1e-30], [2e-30, 2e-30, 2e-30]),
            [0.0, 2.5e-30, 1.5e-30],
            [1.0, 0.0, 0.0],
            None,
        ),
        case(
            "tiny box crossed by a unit-scale ray",
            ([1e-30, 1e-30, 1e-30], [2e-30, 2e-30, 2e-30]),
            [-1.0, -1.0, -1.0],
            [1.0, 1.0, 1.0],
            Some((1.0, 1.0)),
        ),
        // 1e-40 is subnormal in f32 (the smallest normal is about 1.2e-38).
        case(
            "subnormal box",
            ([1e-40, 1e-40, 1e-40], [2e-40, 2e-40, 2e-40]),
            [0.0, 1.5e-40, 1.5e-40],
            [1.0, 0.0, 0.0],
            Some((1e-40, 2e-40)),
        ),
        // A subnormal direction component: its reciprocal overflows to ∞ in f32; the ray
        // still starts inside that slab, so the slab never constrains it.
        case(
            "subnormal direction component",
            unit,
            [-1.0, 0.5, 0.5],
            [1.0, 1e-40, 0.0],
            Some((1.0, 2.0)),
        ),
    ]
}

fn close(got: f64, expected: f64) -> bool {
    got == expected || (got - expected).abs() <= 1e-6 * expected.abs()
}

fn check<V: Vector>(case: &Case, robust: bool) {
    let bounds = Aabb::new(V::from_f64_slice(&case.min), V::from_f64_slice(&case.max));
    let origin = V::from_f64_slice(&case.origin);
    let direction = V::from_f64_slice(&case.direction);
    let label = format!(
        "{} ({}D, {}, robust {robust})",
        case.what,
        V::DIM,
        std::any::type_name::<V>()
    );
    // The CLI's convention: the interval is [0, +∞), a hit needs t_enter <= t_exit and t_exit >= 0.
    let ray = Ray::try_new(origin, direction).expect(&label);
    let record = slab_record(&bounds, &ray, robust);
    match case.expected {
        Some((t_enter, t_exit)) => {
            // The written answer, rounded to this precision (1e-40 is inexact as an f32 subnormal).
            let (t_enter, t_exit) = (
                V::Scalar::from_f64(t_enter).to_f64(),
                V::Scalar::from_f64(t_exit).to_f64(),
            );
            assert!(record.hit, "{label}: expected a hit, got {record:?}");
            assert!(
                close(record.t_enter.to_f64(), t_enter),
                "{label}: t_enter {record:?}"
            );
            // Robust mode widens t_exit by a few ulps at most.
            let slack = if robust { 1e-5 } else { 1e-6 };
            let t_exit_got = record.t_exit.to_f64();
            assert!(
                t_exit_got == t_exit || (t_exit_got - t_exit).abs() <= slack * t_exit.abs(),
                "{label}: t_exit {record:?}"
            );
            for axis in 0..V::DIM {
                assert!(
                    !record.t_near[axis].is_nan() && !record.t_far[axis].is_nan(),
                    "{label}: NaN in the record"
                );
            }
        }
        None => assert!(!record.hit, "{label}: expected a miss, got {record:?}"),
    }
    // The hot path agrees with the record.
    let (t_enter, t_exit) = slab_clip(&bounds, &SlabRay::new(&ray, robust), V::Scalar::INFINITY);
    assert_eq!(
        t_enter <= t_exit,
        record.hit,
        "{label}: hot path disagrees with the record"
    );
    // A hit from outside, reversed, must miss.
    if let Some((t_enter, _)) = case.expected
        && t_enter > 0.0
    {
        let reversed = Ray::try_new(origin, -direction).expect(&label);
        assert!(
            !slab_record(&bounds, &reversed, robust).hit,
            "{label}: reversed ray hits"
        );
    }
}

#[test]
fn slab_cases_in_3d() {
    for case in cases() {
        for robust in [false, true] {
            check::<DVec3>(&case, robust);
            check::<Vec3>(&case, robust);
        }
    }
}

#[test]
fn slab_cases_in_2d() {
    // The same cases seen from above: drop z (cases that need z to miss are skipped).
    for case in cases().into_iter().filter(|case| {
        case.direction[2] == 0.0 && (case.min[2]..=case.max[2]).contains(&case.origin[2])
    }) {
        for robust in [false, true] {
            check::<DVec2>(&case, robust);
            check::<Vec2>(&case, robust);
        }
    }
}

#[test]
fn lecture_example_record() {
    // The 2D table of the slides: a ray from the lower left crossing a box.
    let bounds = Aabb::new(DVec2::new(2.0, 1.0), DVec2::new(6.0, 3.0));
    let ray = Ray::try_new(DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.5)).unwrap();
    let record = slab_record(&bounds, &ray, false);
    assert_eq!(record.t_near, DVec2::new(2.0, 2.0));
    assert_eq!(record.t_far, DVec2::new(6.0, 6.0));
    assert_eq!(
        (record.t_enter, record.t_exit, record.hit),
        (2.0, 6.0, true)
    );
    let above = Ray::try_new(DVec2::new(0.0, 2.0), DVec2::new(1.0, 1.0)).unwrap();
    let record = slab_record(&bounds, &above, false);
    // Enters x at 2 but has already left y at 1: max near > min far.
    assert_eq!(record.t_near, DVec2::new(2.0, -1.0));
    assert_eq!(record.t_far, DVec2::new(6.0, 1.0));
    assert!(!record.hit);
}

mod hot_path_matches_record {
    use super::*;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngSeed};

    /// Coordinates drawn so that zeros, −0, shared values and exact plane hits are common.
    fn value() -> impl Strategy<Value = f64> {
        prop_oneof![
            3 => -4.0..4.0f64,
            2 => (-2i32..=2).prop_map(f64::from),
            1 => Just(-0.0),
        ]
    }

    proptest! {
        #![proptest_config(Config {
            cases: 2000,
            rng_seed: RngSeed::Fixed(0x51ab),
            failure_persistence: None,
            ..Config::default()
        })]

        /// The traversal's slab test and the lesson's record agree on every box and ray, in
        /// both precisions and both modes, and the record never holds a NaN.
        #[test]
        fn slab_clip_agrees_with_slab_record(
            a in [value(), value(), value()],
            b in [value(), value(), value()],
            origin in [value(), value(), value()],
            direction in [value(), value(), value()],
            t_max in prop_oneof![Just(f64::INFINITY), 0.0..6.0f64],
            robust in any::<bool>(),
        ) {
            let min = [0, 1, 2].map(|axis| a[axis].min(b[axis]));
            let max = [0, 1, 2].map(|axis| a[axis].max(b[axis]));
            check_agreement::<DVec3>(min, max, origin, direction, t_max, robust);
            check_agreement::<Vec3>(min, max, origin, direction, t_max, robust);
            check_lanes_match_scalar::<Vec3>(min, max, origin, direction, t_max, robust);
        }
    }

    /// The lanes form (3D f32: four SIMD lanes; the other types run the axis-by-axis form
    /// itself) gives the axis-by-axis form's interval, hit or miss (a zero may differ in sign,
    /// which `==` ignores).
    fn check_lanes_match_scalar<V: Vector>(
        min: [f64; 3],
        max: [f64; 3],
        origin: [f64; 3],
        direction: [f64; 3],
        t_max: f64,
        robust: bool,
    ) {
        use accelviz_core::slab::slab_clip_scalar;
        let bounds = Aabb::new(V::from_f64_slice(&min), V::from_f64_slice(&max));
        let Ok(ray) = Ray::try_new(V::from_f64_slice(&origin), V::from_f64_slice(&direction))
        else {
            return;
        };
        let slab_ray = SlabRay::new(&ray, robust);
        let t_max = V::Scalar::from_f64(t_max);
        let scalar = slab_clip_scalar(&bounds, &slab_ray, t_max);
        let simd = slab_clip(&bounds, &slab_ray, t_max);
        assert!(
            scalar.0 == simd.0 && scalar.1 == simd.1,
            "{bounds:?} {ray:?}: {scalar:?} vs {simd:?}"
        );
    }

    fn check_agreement<V: Vector>(
        min: [f64; 3],
        max: [f64; 3],
        origin: [f64; 3],
        direction: [f64; 3],
        t_max: f64,
        robust: bool,
    ) {
        let bounds = Aabb::new(V::from_f64_slice(&min), V::from_f64_slice(&max));
        let Ok(ray) = Ray::try_with_interval(
            V::from_f64_slice(&origin),
            V::from_f64_slice(&direction),
            V::Scalar::ZERO,
            V::Scalar::from_f64(t_max),
        ) else {
            return; // a zero direction is refused before any slab test
        };
        let record = slab_record(&bounds, &ray, robust);
        let (t_enter, t_exit) = slab_clip(&bounds, &SlabRay::new(&ray, robust), ray.t_max);
        assert_eq!(
            t_enter <= t_exit,
            record.hit,
            "{bounds:?} {ray:?} {record:?}"
        );
        for axis in 0..V::DIM {
            assert!(!record.t_near[axis].is_nan() && !record.t_far[axis].is_nan());
        }
        if record.hit {
            // The clipped interval is the record's, clipped to the ray's.
            assert_eq!(t_enter, record.t_enter.max(ray.t_min));
            assert_eq!(t_exit, record.t_exit.min(ray.t_max));
        }
    }
}
