//! Interaction tests: what a student does with the mouse and keyboard changes what the core
//! computed, and stepping is reversible.

use accelviz_app::AccelvizApp;
use accelviz_app::lessons::common::BvhRule;
use accelviz_app::lessons::near_first::{NearFirstLesson, ORDERS};
use accelviz_app::lessons::slab::SlabLesson;
use accelviz_app::lessons::splits::SplitsLesson;
use accelviz_app::lessons::{LESSON_FILES, Lesson, LessonText};
use accelviz_core::bvh::{TraversalStack, traverse};
use accelviz_core::{Counters, TraceOptions};
use egui::Key;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

fn lesson_text(file: &str) -> LessonText {
    let (path, text) = LESSON_FILES
        .iter()
        .find(|(path, _)| path.ends_with(file))
        .expect("lesson file is registered");
    LessonText::parse(text, path).expect("lesson file parses")
}

/// One lesson with the app's panels around it.
fn lesson_harness<L: Lesson + 'static>(lesson: L) -> Harness<'static, L> {
    Harness::builder()
        .with_size(egui::vec2(1200.0, 760.0))
        .wgpu()
        .build_ui_state(
            |ui, lesson: &mut L| {
                egui::Panel::bottom("timeline").show(ui, |ui| {
                    if let Some((timeline, caption)) = lesson.timeline() {
                        timeline.ui(ui, &caption);
                    }
                });
                egui::Panel::right("inspector").show(ui, |ui| lesson.inspector_ui(ui));
                egui::CentralPanel::default().show(ui, |ui| lesson.canvas_ui(ui));
            },
            lesson,
        )
}

fn shown(app: &mut AccelvizApp) -> usize {
    app.lesson_mut()
        .and_then(|lesson| lesson.timeline().map(|(timeline, _)| timeline.shown))
        .expect("the lesson animates")
}

#[test]
fn stepping_forward_then_back_restores_the_same_picture() {
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1400.0, 860.0))
        .wgpu()
        .build_ui_state(
            |ui, app: &mut AccelvizApp| app.contents_ui(ui),
            AccelvizApp::new(),
        );
    let titles = harness.state().titles();
    for lesson in ["Bounding volume hierarchy", "Near first"] {
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
        assert_eq!(
            shown(harness.state_mut()),
            4,
            "{lesson}: the right arrow steps"
        );
        let before = harness.render().expect("renders");
        // Forward and back by the buttons.
        harness.get_by_label("step >").click();
        harness.run();
        assert_eq!(
            shown(harness.state_mut()),
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
        assert_eq!(
            shown(harness.state_mut()),
            4,
            "{lesson}: '< step' steps back"
        );
        let after_back = harness.render().expect("renders");
        assert!(before == after_back, "{lesson}: back to the same picture");
        harness.key_press(Key::ArrowLeft);
        harness.run();
        assert_eq!(
            shown(harness.state_mut()),
            3,
            "{lesson}: the left arrow steps back"
        );
    }
}

#[test]
fn near_first_panes_show_the_counters_the_core_computes() {
    let lesson = NearFirstLesson::new(lesson_text("06-near-first.ron"));
    let mut harness = lesson_harness(lesson);
    harness.run();
    harness.get_by_label(">|").click();
    harness.run();
    let shown_counters = harness.state_mut().pane_counters();
    // The core's own count, tracing the same scene and ray without any recording.
    let scene = harness
        .state_mut()
        .scene_mut()
        .expect("has a scene")
        .clone();
    let ray = scene.ray().expect("the lesson's ray is valid");
    let bvh = BvhRule::BinnedSah.build(&scene.scene.shapes, &scene.scene.settings);
    for (pane, (order, name)) in ORDERS.iter().enumerate() {
        let mut counters = Counters::default();
        let options = TraceOptions {
            order: *order,
            ..TraceOptions::default()
        };
        traverse(
            &bvh,
            &scene.scene.shapes,
            &ray,
            &options,
            &mut TraversalStack::new(),
            &mut counters,
        );
        assert_eq!(shown_counters[pane], counters, "{name}");
        // The inspector's table says the same.
        let cell = format!("{} of {}", counters.nodes_visited, counters.nodes_visited);
        assert!(
            harness.query_all_by_label(&cell).count() >= 1,
            "{name}: the table shows {cell}"
        );
    }
    assert!(
        shown_counters[0].nodes_visited < shown_counters[1].nodes_visited,
        "on the lesson's ray near-first visits fewer nodes: {shown_counters:?}"
    );
}

#[test]
fn dragging_the_ray_changes_the_slab_intervals() {
    let lesson = SlabLesson::new(lesson_text("03-slab-test.ron"));
    let mut harness = lesson_harness(lesson);
    harness.run();
    let (_, before) = harness.state().record().expect("box and ray");
    let origin = harness
        .state_mut()
        .scene_mut()
        .expect("scene")
        .scene
        .ray_origin;
    let start = harness
        .state_mut()
        .scene_mut()
        .expect("scene")
        .screen_position(origin)
        .expect("drawn");
    let end = start + egui::vec2(60.0, -80.0);
    harness.hover_at(start);
    harness.run();
    harness.drag_at(start);
    harness.run();
    for step in 1..=4 {
        harness.hover_at(start + (end - start) * step as f32 / 4.0);
        harness.run();
    }
    harness.drop_at(end);
    harness.run();
    let moved = harness
        .state_mut()
        .scene_mut()
        .expect("scene")
        .scene
        .ray_origin;
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
        let cost = format!("{:.3}", selected.cost);
        assert!(
            harness.query_all_by_label_contains(&cost).count() >= 1,
            "the formula shows the cost {cost}"
        );
    }
}

#[test]
fn a_saved_scene_opens_in_another_lesson_and_a_broken_one_is_refused() {
    let mut app = AccelvizApp::new();
    let saved = app
        .lesson_mut()
        .and_then(|lesson| lesson.scene_mut())
        .expect("lesson 1 has a scene")
        .scene
        .to_ron();
    app.selected = 3;
    app.open_scene_text("saved.ron", &saved);
    let opened = app
        .lesson_mut()
        .and_then(|lesson| lesson.scene_mut())
        .expect("scene")
        .scene
        .clone();
    assert_eq!(
        opened.shapes.shapes.len(),
        16,
        "lesson 1's sixteen shapes are in lesson 4 now"
    );
    assert_eq!(app.status, Some(("opened saved.ron".to_owned(), false)));

    let broken = saved.replacen("Disc(", "Dics(", 1);
    app.open_scene_text("broken.ron", &broken);
    let (message, problem) = app.status.clone().expect("a message");
    assert!(problem, "reported as a problem");
    assert!(
        message.starts_with("broken.ron:") && message.contains("Dics"),
        "{message}"
    );
    let after = app
        .lesson_mut()
        .and_then(|lesson| lesson.scene_mut())
        .expect("scene")
        .scene
        .clone();
    assert_eq!(after, opened, "a broken file changes nothing");

    app.lesson_mut().expect("lesson 4").reset_scene();
    let reset = app
        .lesson_mut()
        .and_then(|lesson| lesson.scene_mut())
        .expect("scene")
        .scene
        .clone();
    assert_eq!(
        reset.shapes.shapes.len(),
        5,
        "reset puts back the slide's A to E"
    );
}

/// Every lesson takes a large generated scene (as a student's "generate n = 5000" makes) and
/// keeps drawing: no panic, and the lesson still animates or plots.
#[test]
fn every_lesson_copes_with_a_large_scene() {
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1400.0, 860.0))
        .build_ui_state(
            |ui, app: &mut AccelvizApp| app.contents_ui(ui),
            AccelvizApp::new(),
        );
    for index in 0..harness.state().lesson_count() {
        harness.state_mut().selected = index;
        let scene = harness
            .state_mut()
            .lesson_mut()
            .and_then(|lesson| lesson.scene_mut())
            .expect("every lesson has a scene");
        scene.scene.shapes =
            accelviz_scene::scene2d::generate(accelviz_scene::scene2d::Layout::Clustered, 5_000, 9);
        scene.touch();
        harness.run_steps(2);
        if let Some((timeline, _)) = harness
            .state_mut()
            .lesson_mut()
            .and_then(|lesson| lesson.timeline())
        {
            timeline.shown = timeline.len;
        }
        harness.run_steps(2);
    }
}
