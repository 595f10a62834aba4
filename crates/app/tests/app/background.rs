//! Long builds do not freeze the UI: on the desktop a build over many shapes runs on a worker
//! thread, the frame that asked for it returns at once and draws the last build, the top bar
//! says a build is running, and the new build shows when it is done.
//!
//! The background mode is a setting of the thread that asks for the work: this test turns it
//! on for its own thread only.

use accelviz_app::AccelvizApp;
use accelviz_scene::document::{GeneratorEntry, LayoutEntry};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

#[test]
fn a_long_build_runs_while_the_app_keeps_drawing() {
    accelviz_app::background::set_background(true);
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1400.0, 860.0))
        .build_ui_state(
            |ui, app: &mut AccelvizApp| app.contents_ui(ui),
            AccelvizApp::new(),
        );
    let titles = harness.state().titles();
    harness.state_mut().selected = titles
        .iter()
        .position(|title| title.contains("Middle, median or SAH"))
        .expect("lesson 7");
    harness.run_steps(2);
    assert!(
        harness
            .state()
            .lesson()
            .is_some_and(|lesson| lesson.building().is_none())
    );
    // The lesson's small scene is drawn: its panes' captions name the structures.
    assert!(harness.query_by_label_contains("building…").is_none());
    assert!(harness.state_mut().generate_scene(GeneratorEntry {
        layout: LayoutEntry::Uniform,
        count: 100_000,
        seed: 3,
    }));
    // The frame after the edit returns with the build still running, and says so.
    harness.step();
    harness.step();
    assert!(
        harness
            .state()
            .lesson()
            .is_some_and(|lesson| lesson.building().is_some()),
        "the three trees over 100,000 shapes are built on a worker thread"
    );
    assert!(
        harness.query_by_label_contains("building…").is_some(),
        "the top bar says a build is running"
    );
    // Frames keep coming until the build is done (no time is asserted: only that it ends).
    let mut frames = 0;
    while harness
        .state()
        .lesson()
        .is_some_and(|lesson| lesson.building().is_some())
    {
        harness.step();
        frames += 1;
        std::thread::sleep(std::time::Duration::from_millis(20));
        assert!(frames < 30_000, "the build never finished");
    }
    harness.step();
    assert!(frames > 0, "the app drew frames while it built");
    assert!(harness.query_by_label_contains("building…").is_none());
}
