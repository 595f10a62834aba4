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

/// Lesson files on disk override the embedded ones (a lecturer's edit shows at the next start);
/// a broken one becomes an entry that names its file and line, and the other lessons still load.
#[test]
fn lesson_files_on_disk_override_the_embedded_ones() {
    let dir = std::env::temp_dir().join(format!("accelviz-lessons-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("lessons")).unwrap();
    let (first_path, first_text) = LESSON_FILES[0];
    let edited = first_text.replace("1. The trivial loop", "1. The loop, edited");
    std::fs::write(dir.join(first_path.trim_start_matches("assets/")), edited).unwrap();
    let (second_path, second_text) = LESSON_FILES[1];
    let broken = second_text.replacen("title:", "titel:", 1);
    std::fs::write(dir.join(second_path.trim_start_matches("assets/")), broken).unwrap();

    let app = AccelvizApp::with_assets(&dir);
    let titles = app.titles();
    assert_eq!(titles[0], "1. The loop, edited");
    assert_eq!(titles[1], "(lesson file broken)");
    assert_eq!(
        titles[2], "3. The slab test",
        "files not on disk come embedded"
    );
    let lessons = accelviz_app::lessons::registry_from(Some(&dir));
    let error = lessons[1]
        .as_ref()
        .err()
        .expect("the broken file is an error");
    assert!(
        error.contains("02-bounding-volumes.ron:3:") && error.contains("titel"),
        "{error}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
