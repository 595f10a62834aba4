//! A large OBJ opened in a 3D lesson on the desktop: it is read and built on worker threads
//! while frames keep coming, its progress is shown with a cancel button, and cancelling goes
//! back to the mesh shown before. It turns worker threads on for its own thread.

use crate::common;

use accelviz_app::background::set_background;
use accelviz_app::lesson::Lesson;
use accelviz_app::lessons::mesh_tree::MeshTreeLesson;
use common::{lesson_harness_3d, lesson_text};
use egui_kittest::kittest::Queryable;

/// A mesh of about `triangles` triangles as OBJ text.
fn obj_text(triangles: usize) -> String {
    accelviz_scene::obj::obj_text(&accelviz_scene::builtin::lumpy_grid_sphere(triangles))
}

/// Opens `text` as `large.obj` in the lesson: it starts being read aside.
fn open_large(harness: &mut egui_kittest::Harness<'_, MeshTreeLesson>, text: &str) {
    harness
        .state_mut()
        .stage_mut()
        .scene
        .open("large.obj", text)
        .expect("starts reading");
}

/// Runs frames until no widget is labelled `label` (true), or ten frames have passed.
fn steps_until_gone(harness: &mut egui_kittest::Harness<'_, MeshTreeLesson>, label: &str) -> bool {
    for _ in 0..10 {
        harness.run_steps(1);
        if harness.query_by_label(label).is_none() {
            return true;
        }
    }
    false
}

#[test]
fn a_large_mesh_loads_aside_with_progress_and_cancel() {
    set_background(true);
    let text = obj_text(120_000);
    assert!(text.len() > 3 << 20, "{} bytes", text.len());

    // Cancelled: back to the teapot.
    let mut harness = lesson_harness_3d(MeshTreeLesson::new(lesson_text("12-mesh-bvh.ron")));
    harness.run_steps(2);
    open_large(&mut harness, &text);
    harness.run_steps(1);
    assert!(
        harness
            .query_by_label_contains("reading large.obj")
            .is_some()
            || harness
                .query_by_label_contains("building the structure")
                .is_some(),
        "progress is shown"
    );
    harness.get_by_label("cancel").click();
    // A frame or two: the read may end as the click arrives, which is then the build's.
    assert!(
        steps_until_gone(&mut harness, "cancel"),
        "nothing is loading"
    );
    assert!(
        harness.query_by_label_contains("teapot: ").is_some(),
        "the teapot is back"
    );

    // Let through: read, built, shown, while frames keep coming.
    open_large(&mut harness, &text);
    let mut frames = 0;
    let arrived = |lesson: &MeshTreeLesson| {
        lesson
            .tree()
            .is_some_and(|tree| tree.mesh.name == "large.obj")
    };
    while !arrived(harness.state()) {
        harness.run_steps(1);
        std::thread::sleep(std::time::Duration::from_millis(20));
        frames += 1;
        assert!(frames < 3_000, "the mesh never arrived");
    }
    assert!(frames > 2, "frames kept coming while it loaded ({frames})");
    let tree = harness.state().tree().expect("built");
    assert!(tree.mesh.triangles.len() > 100_000);

    // A slow structure asked for over it, then cancelled: the same mesh and the structure
    // on screen stay (not the mesh before, nor the new structure).
    let structure = |lesson: &MeshTreeLesson| {
        lesson
            .share()
            .into_iter()
            .find(|(key, _)| key == "structure")
            .map(|(_, value)| value)
    };
    let shown = structure(harness.state());
    harness
        .state_mut()
        .restore("structure", "kd:sah-perfect")
        .expect("a structure");
    harness.run_steps(1);
    harness.get_by_label("cancel").click();
    assert!(steps_until_gone(&mut harness, "cancel"), "nothing builds");
    assert_eq!(structure(harness.state()), shown);
    assert_eq!(harness.state().stage().scene.noun(), "mesh");
    let tree = harness.state().tree().expect("still built");
    assert_eq!(tree.mesh.name, "large.obj", "the mesh opened stays");
}
