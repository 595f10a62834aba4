//! Interaction tests: what a student does with the mouse and keyboard changes what the core
//! computed, stepping is reversible, and opening and saving scenes work, also without a file
//! dialog.

use crate::common;

use common::{app_harness, lesson_harness, lesson_text};

use accelviz_app::AccelvizApp;
use accelviz_app::lessons::slab::SlabLesson;
use accelviz_app::lessons::splits::SplitsLesson;
use egui::Key;
use egui_kittest::kittest::Queryable;

fn shown(app: &AccelvizApp) -> usize {
    app.lesson()
        .map(|lesson| lesson.stage().timeline.shown)
        .expect("a lesson")
}

#[test]
fn stepping_forward_then_back_restores_the_same_picture() {
    let mut harness = app_harness();
    let titles = harness.state().titles();
    for lesson in ["Bounding volume hierarchy", "Near first", "kD-tree"] {
        let index = titles
            .iter()
            .position(|title| title.contains(lesson))
            .expect("lesson exists");
        harness.state_mut().selected = index;
        harness.run();
        // Part-way in, by the keyboard.
        for _ in 0..4 {
            harness.key_press(Key::ArrowRight);
            harness.run();
        }
        assert_eq!(shown(harness.state()), 4, "{lesson}: the right arrow steps");
        let before = harness.render().expect("renders");
        // Forward and back by the buttons.
        harness.get_by_label("step >").click();
        harness.run();
        assert_eq!(
            shown(harness.state()),
            5,
            "{lesson}: 'step >' steps forward"
        );
        let after_forward = harness.render().expect("renders");
        assert_ne!(
            before, after_forward,
            "{lesson}: a step changes the picture"
        );
        harness.get_by_label("< step").click();
        harness.run();
        harness.remove_cursor();
        harness.run();
        assert_eq!(shown(harness.state()), 4, "{lesson}: '< step' steps back");
        let after_back = harness.render().expect("renders");
        assert!(before == after_back, "{lesson}: back to the same picture");
        harness.key_press(Key::ArrowLeft);
        harness.run();
        assert_eq!(
            shown(harness.state()),
            3,
            "{lesson}: the left arrow steps back"
        );
    }
}

#[test]
fn dragging_the_ray_changes_the_slab_intervals() {
    let lesson = SlabLesson::new(lesson_text("03-slab-test.ron"));
    let mut harness = lesson_harness(lesson);
    harness.run();
    let (_, before) = harness.state().record().expect("box and ray");
    let origin = common::flat(harness.state()).scene.ray_origin;
    let start = common::flat(harness.state())
        .screen_position(origin)
        .expect("drawn");
    let end = start + egui::vec2(60.0, -80.0);
    common::drag(&mut harness, start, end);
    let moved = common::flat(harness.state()).scene.ray_origin;
    assert!(
        moved.x > origin.x && moved.y > origin.y,
        "the origin followed the drag: {origin} to {moved}"
    );
    let (_, after) = harness.state().record().expect("box and ray");
    assert_ne!(before.t_near, after.t_near, "the near crossings moved");
    assert_ne!(before.t_far, after.t_far, "the far crossings moved");
}

#[test]
fn hovering_a_sah_candidate_selects_it() {
    let lesson = SplitsLesson::new(lesson_text("07-middle-median-sah.ron"));
    let mut harness = lesson_harness(lesson);
    harness.run();
    assert_eq!(
        harness.state().selected_candidate(),
        None,
        "nothing is selected before hovering"
    );
    let candidates = harness.state().candidates();
    assert!(
        candidates.len() > 10,
        "the root has many candidates: {}",
        candidates.len()
    );
    // Three candidates across the curve, each hovered in turn.
    for index in [1, candidates.len() / 2, candidates.len() - 2] {
        let candidate = candidates[index];
        let position = harness
            .state()
            .candidate_screen_position(&candidate)
            .expect("the plot was drawn");
        harness.hover_at(position);
        harness.run();
        let selected = harness
            .state()
            .selected_candidate()
            .expect("a candidate is selected");
        assert_eq!(
            selected.position, candidate.position,
            "hovering candidate {index} selects its position"
        );
        // The formula shows the selected candidate's numbers.
        let cost = accelviz_core::format::number(selected.cost);
        assert!(
            harness.query_all_by_label_contains(&cost).count() >= 1,
            "the formula shows the cost {cost}"
        );
    }
}

#[test]
fn a_saved_scene_opens_in_another_lesson_and_a_broken_one_is_refused() {
    let mut app = AccelvizApp::new();
    let saved = common::flat(app.lesson().expect("lesson 1")).scene.to_ron();
    app.selected = 3;
    assert!(app.open_scene_text("saved.ron", &saved));
    let opened = common::flat(app.lesson().expect("lesson 4")).scene.clone();
    assert_eq!(
        opened.shapes.shapes.len(),
        16,
        "lesson 1's sixteen shapes are in lesson 4 now"
    );
    assert_eq!(app.status, Some(("opened saved.ron".to_owned(), false)));

    let broken = saved.replacen("Disc(", "Dics(", 1);
    assert!(!app.open_scene_text("broken.ron", &broken));
    let (message, problem) = app.status.clone().expect("a message");
    assert!(problem, "reported as a problem");
    assert!(
        message.starts_with("broken.ron:") && message.contains("Dics"),
        "{message}"
    );
    let after = common::flat(app.lesson().expect("lesson 4")).scene.clone();
    assert_eq!(after, opened, "a broken file changes nothing");

    app.lesson_mut()
        .expect("lesson 4")
        .stage_mut()
        .reset_scene();
    let reset = common::flat(app.lesson().expect("lesson 4")).scene.clone();
    assert_eq!(
        reset.shapes.shapes.len(),
        5,
        "reset puts back the slide's A to E"
    );
}

/// Where the system has no file dialog (no desktop portal, no zenity: CI, a lecture-hall PC
/// set up by hand), "Open scene…" says so in the app and opens the in-app panel, whose path
/// field opens the scene; "Save scene…" saves through the same panel.
#[test]
fn without_a_file_dialog_the_in_app_panel_opens_and_saves_scenes() {
    let display = ["DISPLAY", "WAYLAND_DISPLAY", "DBUS_SESSION_BUS_ADDRESS"]
        .iter()
        .find(|name| std::env::var_os(name).is_some());
    if let Some(name) = display {
        // A desktop session could open a real dialog and wait for a person: not here.
        eprintln!("skipped: {name} is set, so a real file dialog could open");
        return;
    }
    accelviz_app::files::install_logger(None, log::LevelFilter::Warn);
    let folder = std::env::temp_dir().join(format!("accelviz-files-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap_or_else(|error| panic!("{error}"));
    let mut harness = app_harness();
    harness.state_mut().selected = 3;
    harness.run();
    harness.get_by_label("Save scene…").click();
    harness.run();
    let panel = harness
        .state()
        .file_panel
        .clone()
        .expect("the panel opened");
    assert!(
        panel
            .reason
            .as_deref()
            .is_some_and(|reason| !reason.is_empty()),
        "the panel says why the dialog failed"
    );
    assert!(
        harness.query_by_label_contains("could not open").is_some(),
        "the reason is on screen"
    );
    let path = folder.join("four.ron");
    harness.state_mut().file_panel.as_mut().expect("panel").path = path.display().to_string();
    harness.run();
    harness.get_by_label("Save").click();
    harness.run();
    assert!(path.is_file(), "saved through the panel");
    assert!(harness.state().file_panel.is_none(), "the panel closed");

    harness.state_mut().selected = 0;
    harness.run();
    harness.get_by_label("Open scene…").click();
    harness.run();
    assert!(harness.state().file_panel.is_some(), "the panel opened");
    harness.state_mut().file_panel.as_mut().expect("panel").path = path.display().to_string();
    harness.run();
    harness.get_by_label("Open").click();
    harness.run();
    let opened = common::flat(harness.state().lesson().expect("lesson 1"))
        .scene
        .clone();
    assert_eq!(
        opened.shapes.shapes.len(),
        5,
        "lesson 4's A to E, opened in lesson 1"
    );
    assert!(harness.state().file_panel.is_none(), "the panel closed");
    std::fs::remove_dir_all(&folder).unwrap_or_else(|error| panic!("{error}"));
}
