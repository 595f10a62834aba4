//! Lesson 17, cracks and extremes: its first ray slips through the fast f32 test and not the
//! watertight one, the zoomed views and the tables show the core's own numbers, and every
//! part draws.

use accelviz_app::lesson::Lesson;
use accelviz_app::lessons::cracks::{CracksLesson, Part};
use accelviz_core::HitTest;
use accelviz_core::outcome::Outcome;
use egui_kittest::kittest::Queryable;

use crate::common::{lesson_harness_3d, lesson_text};

fn lesson() -> CracksLesson {
    CracksLesson::new(lesson_text("17-cracks.ron"))
}

#[test]
fn the_first_ray_slips_through_the_fast_f32_test_only() {
    let lesson = lesson();
    let [in_f32, in_f64] = lesson.scene().tested().expect("a ray");
    assert!(in_f32.hit.is_none(), "{in_f32:?}");
    assert_eq!(in_f32.outcome, Outcome::Leak);
    assert!(in_f32.across(0).unwrap() < 0.0 && in_f32.across(1).unwrap() < 0.0);
    // The same ray, in f64, hits.
    assert!(in_f64.hit.is_some(), "{in_f64:?}");
    let mut lesson = lesson;
    lesson.set_test(HitTest::Watertight);
    let [in_f32, in_f64] = lesson.scene().tested().expect("a ray");
    assert!(in_f32.hit.is_some() && in_f64.hit.is_some());
    // "next ray that slips" finds another crack.
    lesson.set_test(HitTest::Fast);
    let seed = lesson.scene().seed;
    lesson.next_slip();
    assert!(lesson.scene().seed > seed);
    assert!(lesson.scene().tested().unwrap()[0].hit.is_none());
}

#[test]
fn far_from_the_origin_the_crack_keeps_its_width_and_the_hit_point_its_grid() {
    let mut lesson = lesson();
    let rows = lesson.far_rows().to_vec();
    for row in &rows {
        assert_eq!(row.tested, 2000);
        // At the edge itself rounding decides: the fast test slips some, in both precisions.
        assert!(row.slipped[0] > 0 && row.slipped[2] > 0, "{row:?}");
        // A ray 10^-6 beside the edge never slips: the tests work on exact differences.
        assert_eq!(row.slipped[1], 0, "{row:?}");
        // The watertight test never lets a ray through, in either precision.
        assert_eq!((row.slipped[3], row.slipped[4]), (0, 0), "{row:?}");
        // The hit point lands within about the spacing of the numbers there.
        for index in 0..2 {
            assert!(
                row.hit_point_off[index] <= 4.0 * row.spacing[index],
                "{row:?}"
            );
        }
    }
    let (near, far) = (&rows[0], &rows[rows.len() - 1]);
    assert_eq!(
        far.spacing[0], 0.0625,
        "f32 numbers near 10^6 are 2^-4 apart"
    );
    assert!(
        far.hit_point_off[0] > 1e4 * near.hit_point_off[0],
        "{rows:?}"
    );
}

#[test]
fn every_part_draws_its_numbers() {
    let mut harness = lesson_harness_3d(lesson());
    harness.run();
    harness.get_by_label("slips through");
    harness.snapshot("crack_shared_edge");
    harness.state_mut().set_zoom(7.0);
    harness.run();
    harness.snapshot("crack_shared_edge_zoomed");
    harness.state_mut().set_test(HitTest::Watertight);
    harness.run();
    harness.snapshot("crack_watertight_zoomed");
    assert!(harness.state_mut().show_named("far-away"));
    harness.state_mut().set_test(HitTest::Fast);
    harness.run();
    harness.get_by_label("f32 point off");
    // The slipped columns, the part's point, are on screen: they sat off to the right of
    // one wide table, behind a scroll bar nobody saw.
    for heading in [
        "fast\nf32",
        "fast\nf64",
        "watertight\nf32",
        "watertight\nf64",
    ] {
        harness.get_by_label(heading);
        let (rect, clip) = drawn_text(&harness, heading).expect("drawn");
        assert!(
            clip.contains_rect(rect),
            "'{heading}' is cut at its panel's edge: {rect:?} in {clip:?}"
        );
    }
    harness.snapshot("crack_far_away");
    assert!(harness.state_mut().show_named("slab-plane"));
    harness.run();
    assert!(harness.query_all_by_label("NaN").count() >= 1);
    harness.snapshot("crack_slab_plane");
    assert!(harness.state_mut().show_named("corner"));
    harness.state_mut().set_zoom(6.0);
    harness.run();
    harness.get_by_label("max t_near");
    // f32 and f64 on one ray: its direction is said once, and what f64 makes of it.
    harness.get_by_label_contains("in f32 and in f64");
    assert!(harness.query_by_label("direction").is_none());
    harness.get_by_label_contains("In f64 this ray");
    harness.snapshot("crack_corner");
    assert_eq!(harness.state().scene().part, Part::Corner);
}

/// Where the last frame drew `text`, and the rectangle it was clipped to.
fn drawn_text<S>(
    harness: &egui_kittest::Harness<'_, S>,
    text: &str,
) -> Option<(egui::Rect, egui::Rect)> {
    fn walk(shape: &egui::Shape, text: &str) -> Option<egui::Rect> {
        match shape {
            egui::Shape::Text(shape) if shape.galley.job.text == text => {
                Some(shape.visual_bounding_rect())
            }
            egui::Shape::Vec(shapes) => shapes.iter().find_map(|shape| walk(shape, text)),
            _ => None,
        }
    }
    harness
        .output()
        .shapes
        .iter()
        .find_map(|clipped| walk(&clipped.shape, text).map(|rect| (rect, clipped.clip_rect)))
}
