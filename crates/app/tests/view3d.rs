//! The 3D lessons drawn on the software adapter (snapshots named `*_3d*`), and what they
//! trace: a clicked pixel's recorded hit is brute force's.

mod common;

use accelviz_app::lesson::Lesson;
use accelviz_app::lessons::mesh_tree::MeshTreeLesson;
use accelviz_app::view3d::HiddenEdges;
use accelviz_core::{Order, Ray, TraceOptions, brute_force};
use common::{lesson_harness_3d, lesson_text};
use glam::DVec3;

fn mesh_lesson() -> MeshTreeLesson {
    MeshTreeLesson::new(lesson_text("12-mesh-bvh.ron"))
}

#[test]
fn the_mesh_and_its_boxes_at_two_depth_ranges_with_and_without_xray() {
    let mut harness = lesson_harness_3d(mesh_lesson());
    harness.run();
    let mut failures = Vec::new();
    let mut check = |harness: &mut egui_kittest::Harness<'_, MeshTreeLesson>, name: &str| {
        harness.run();
        if let Err(error) = harness.try_snapshot(name) {
            failures.push(error.to_string());
        }
    };
    check(&mut harness, "mesh_3d_all_depths_xray");
    harness.state_mut().depth_range = (3, 4);
    check(&mut harness, "mesh_3d_depths_3_4_xray");
    harness.state_mut().hidden_edges = HiddenEdges::Hidden;
    check(&mut harness, "mesh_3d_depths_3_4_hidden");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_clicked_pixels_traversal_half_way() {
    let mut harness = lesson_harness_3d(mesh_lesson());
    harness.run();
    let (center, _) = harness.state().tree().expect("built").sphere;
    // A ray from the upper left front into the teapot's body.
    let origin = center + DVec3::new(-2.0, 2.5, 4.0);
    harness.state_mut().pick(origin, center - origin);
    harness.run();
    let trace = harness.state().trace().expect("traced");
    let frames = trace.frames();
    assert!(trace.hit.is_some(), "the ray hits the teapot");
    harness.state_mut().stage_mut().timeline.shown = frames / 2;
    // Orbit a quarter turn so the ray is seen from the side.
    harness.state_mut().view.orbit.yaw += 70.0;
    harness.run();
    harness.snapshot("mesh_3d_traversal_half_way");
}

#[test]
fn a_clicked_pixels_recorded_hit_is_brute_forces() {
    let mut harness = lesson_harness_3d(mesh_lesson());
    harness.run();
    let tree = harness.state().tree().expect("built").clone();
    let (center, radius) = tree.sphere;
    let camera = harness.state().view.orbit.camera(center, radius);
    let (width, height) = (24, 18);
    let mut hits = 0;
    for order in [Order::NearFirst, Order::FileOrder] {
        harness.state_mut().order = order;
        for row in 0..height {
            for column in 0..width {
                let (origin, direction) =
                    camera.ray_through(column as f64 + 0.5, row as f64 + 0.5, width, height);
                harness.state_mut().pick(origin, direction);
                // What a frame does first; drawing is not needed here.
                harness.state_mut().update();
                let trace = harness.state().trace().expect("traced");
                let ray = Ray::try_new(origin, direction).expect("a ray");
                let expected = brute_force(
                    &tree.triangles,
                    &ray,
                    &TraceOptions::default(),
                    &mut accelviz_core::NoObserver,
                );
                assert_eq!(
                    trace.hit.map(|hit| hit.primitive),
                    expected.map(|hit| hit.primitive),
                    "pixel ({column}, {row}), {order:?}"
                );
                hits += usize::from(expected.is_some());
            }
        }
    }
    assert!(hits > 50, "{hits} pixels hit the teapot");
}
