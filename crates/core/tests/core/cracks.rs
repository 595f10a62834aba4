//! The cases of the lesson on cracks (`accelviz_core::crack`): what each test computes at a
//! shared edge, far from the origin, and at a box's corner, with the answers written down.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::crack::{SharedEdge, corner_graze, slip_count};
use accelviz_core::outcome::Outcome;
use accelviz_core::{Aabb, HitTest, Real};
use glam::{DVec2, DVec3, Vec2, Vec3};

/// A deterministic source of numbers in [0, 1) (SplitMix64), so the cases are the same on
/// every machine.
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn cases(count: usize, seed: u64) -> Vec<SharedEdge> {
    let mut numbers = uniform(seed);
    (0..count).map(|_| SharedEdge::draw(&mut numbers)).collect()
}

#[test]
fn ulp_is_the_gap_to_the_next_number() {
    assert_eq!(1.0f32.ulp(), f32::EPSILON);
    assert_eq!(1.0f64.ulp(), f64::EPSILON);
    assert_eq!(1024.0f32.ulp(), 2f32.powi(-13));
    assert_eq!((-3.0f32).ulp(), 2f32.powi(-22));
    assert_eq!(1.0e6f64.ulp(), 2f64.powi(19 - 52));
}

#[test]
fn the_watertight_test_computes_the_shared_edge_alike_and_never_slips() {
    for case in cases(2000, 1) {
        for tested in [
            case.test::<Vec3>(HitTest::Watertight).unwrap(),
            case.test::<DVec3>(HitTest::Watertight).unwrap(),
        ] {
            // A's edge function of c–a (weight of b) and B's of a–c (weight of d): the same
            // products subtracted the other way round, so exactly opposite.
            let a_edge = tested.values[0].coordinates[1].unwrap();
            let b_edge = tested.values[1].coordinates[2].unwrap();
            assert_eq!(a_edge, -b_edge, "{case:?}");
            assert!(tested.hit.is_some(), "slipped through: {case:?}");
            assert!(
                matches!(tested.outcome, Outcome::Agree | Outcome::Tie),
                "{:?}: {case:?}",
                tested.outcome
            );
            // Both hit only where the edge function is exactly zero; then each computes its
            // own t, and the closest is kept (equal t: the lower number, A).
            if tested.both_hit() {
                assert_eq!(a_edge, 0.0);
                let [t_a, t_b] = tested.values.map(|values| values.t.unwrap());
                let closest = if t_b < t_a { 1 } else { 0 };
                assert_eq!(tested.hit.unwrap().primitive, closest);
            }
        }
    }
}

#[test]
fn the_fast_test_slips_through_in_f32_with_both_points_outside() {
    let mut slipped = 0;
    for case in cases(2000, 2) {
        let tested = case.test::<Vec3>(HitTest::Fast).unwrap();
        if tested.hit.is_none() {
            slipped += 1;
            assert_eq!(tested.outcome, Outcome::Leak, "{case:?}");
            // Rounding put the ray's point outside A and outside B, across the shared edge.
            assert!(tested.across(0).unwrap() < 0.0, "{tested:?}");
            assert!(tested.across(1).unwrap() < 0.0, "{tested:?}");
        } else {
            assert_ne!(tested.outcome, Outcome::Leak);
        }
    }
    // About one ray in six to twelve aimed exactly at the edge slips through in f32.
    assert!((100..=400).contains(&slipped), "{slipped} of 2000 slipped");
}

#[test]
fn far_from_the_origin_the_crack_keeps_its_width_and_the_numbers_grow_apart() {
    let near = cases(2000, 3);
    let offset = DVec3::splat(1000.0);
    let far: Vec<SharedEdge> = near.iter().map(|case| case.moved(offset)).collect();
    // Aimed exactly at the edge, rounding decides near and far alike: some slip.
    let (slipped_near, tested_near) = slip_count::<Vec3>(&near, HitTest::Fast);
    let (slipped_far, tested_far) = slip_count::<Vec3>(&far, HitTest::Fast);
    assert_eq!((tested_near, tested_far), (2000, 2000));
    assert!(
        slipped_near > 100 && slipped_far > 100,
        "{slipped_near} {slipped_far}"
    );
    // A millionth beside it, none slip, near or far: the tests work on exact differences.
    for cases in [&near, &far] {
        let aside: Vec<SharedEdge> = cases.iter().map(|case| case.aimed_aside(1e-6)).collect();
        assert_eq!(slip_count::<Vec3>(&aside, HitTest::Fast).0, 0);
    }
    assert_eq!(slip_count::<Vec3>(&far, HitTest::Watertight).0, 0);
    assert_eq!(slip_count::<DVec3>(&far, HitTest::Watertight).0, 0);
    // Near 1000 (in [512, 1024)) f32's numbers are 2^-14 apart; near 1 they are 2^-23 or
    // 2^-24 apart.
    let tested = far[0].test::<Vec3>(HitTest::Watertight).unwrap();
    assert_eq!(tested.coordinate_ulp, 2f64.powi(-14));
    // The ray reaches the edge at t = 1: the hit's t is within a few of its own ulps of the
    // reference's (the watertight test works relative to the ray's origin) ...
    let (t, ulp, error) = tested.t_error().unwrap();
    assert!((t - 1.0).abs() < 1e-3, "{t}");
    assert!(ulp == 2f64.powi(-23) || ulp == 2f64.powi(-24), "{ulp}");
    assert!(error <= 4.0, "{error}");
    // ... but the hit point it gives, o + t·d, can only be placed to within the coordinates'
    // spacing: off the surface by up to about an ulp of them (2^-14 here), tens of times
    // more than near the origin.
    let off = |cases: &[SharedEdge]| {
        cases
            .iter()
            .take(200)
            .filter_map(|case| case.test::<Vec3>(HitTest::Watertight)?.hit_point_off)
            .fold(0.0, f64::max)
    };
    let (off_near, off_far) = (off(&near), off(&far));
    assert!(off_far > 10.0 * off_near, "{off_far} vs {off_near}");
    assert!(
        off_far > 0.1 * 2f64.powi(-14) && off_far < 4.0 * 2f64.powi(-14),
        "{off_far}"
    );
}

#[test]
fn a_ray_through_a_corner_misses_the_plain_box_and_hits_the_widened_one() {
    let bounds = Aabb::new(Vec2::new(0.25, 0.25), Vec2::new(1.75, 1.125));
    let graze = corner_graze(&bounds).unwrap();
    assert!(graze.t_enter > graze.t_exit);
    assert!(graze.t_exit_widened >= graze.t_enter);
    // Both would be exactly 1 without rounding: each is within an ulp or two of it.
    for t in [graze.t_enter, graze.t_exit] {
        assert!((t - 1.0).abs() <= 2.0 * f32::EPSILON, "{t}");
    }
    // The ray passes exactly through the corner (min x, max y).
    let corner = [
        graze.origin[0] + graze.direction[0],
        graze.origin[1] + graze.direction[1],
    ];
    assert_eq!(corner, [0.25, 1.125]);
    let wide = Aabb::new(DVec2::new(0.25, 0.25), DVec2::new(1.75, 1.125));
    let graze = corner_graze(&wide).unwrap();
    assert!(graze.t_enter > graze.t_exit && graze.t_exit_widened >= graze.t_enter);
}

#[test]
fn each_test_reads_back_from_its_name() {
    for test in HitTest::ALL {
        assert_eq!(HitTest::from_name(test.name()), Some(test));
    }
    assert_eq!(HitTest::from_name("exact"), None);
}
