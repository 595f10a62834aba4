//! Every lesson rendered on the software wgpu adapter and compared with its committed image
//! (`tests/snapshots/`; refresh with `UPDATE_SNAPSHOTS=1 cargo test -p accelviz-app`), and the
//! lesson files parsed.

use accelviz_app::AccelvizApp;
use accelviz_app::lessons::{LESSON_FILES, LessonText};
use egui_kittest::Harness;

/// The app at a projector-like size.
fn harness() -> Harness<'static, AccelvizApp> {
    Harness::builder()
        .with_size(egui::vec2(1400.0, 860.0))
        .wgpu()
        .build_ui_state(
            |ui, app: &mut AccelvizApp| app.contents_ui(ui),
            AccelvizApp::new(),
        )
}

#[test]
fn every_lesson_file_parses() {
    for (path, text) in LESSON_FILES {
        if let Err(error) = LessonText::parse(text, path) {
            panic!("{error}");
        }
    }
}

#[test]
fn every_lesson_matches_its_snapshot() {
    let mut harness = harness();
    let count = harness.state().lesson_count();
    assert_eq!(count, LESSON_FILES.len());
    let mut failures = Vec::new();
    for index in 0..count {
        harness.state_mut().selected = index;
        harness.run();
        // Part-way through its animation, so the snapshot shows the lesson at work.
        if let Some((timeline, _)) = harness
            .state_mut()
            .lesson_mut()
            .and_then(|lesson| lesson.timeline())
        {
            timeline.shown = timeline.len * 2 / 3;
        }
        harness.run();
        let title = harness.state().titles()[index].clone();
        let name = format!("lesson_{:02}", index + 1);
        if let Err(error) = harness.try_snapshot(&name) {
            failures.push(format!("{title}: {error}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The BVH lesson on a 10k-shape scene, the frame bench's case: shapes and boxes drawn as one
/// batched mesh each.
#[test]
fn a_ten_thousand_shape_scene_matches_its_snapshot() {
    let mut harness = harness();
    let titles = harness.state().titles();
    harness.state_mut().selected = titles
        .iter()
        .position(|title| title.contains("hierarchy"))
        .expect("the BVH lesson");
    let scene = harness
        .state_mut()
        .lesson_mut()
        .and_then(|lesson| lesson.scene_mut())
        .expect("a scene");
    scene.scene.shapes =
        accelviz_scene::scene2d::generate(accelviz_scene::scene2d::Layout::Clustered, 10_000, 1);
    scene.scene.settings.max_leaf_size = 2;
    scene.view.placed = false;
    scene.touch();
    harness.run();
    harness.snapshot("bvh_10k");
}
