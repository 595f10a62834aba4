//! Shared views: every lesson, changed (its step, its scene and ray, its structure, its camera
//! and mesh), written as a link and opened in a new app, shows exactly that view; a garbage
//! link opens the first lesson with a message saying why.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use crate::common;

use accelviz_app::AccelvizApp;
use accelviz_app::share::ViewState;

/// What a view is made of, to compare two apps.
fn view_of(app: &AccelvizApp) -> (usize, usize, Option<String>, Vec<(String, String)>) {
    let lesson = app.lesson().unwrap();
    let stage = lesson.stage();
    (
        app.selected,
        stage.timeline.shown,
        stage.scene.flat().map(|flat| flat.scene.to_ron()),
        lesson.share(),
    )
}

#[test]
fn every_lesson_changed_opens_the_same_from_its_link() {
    let mut harness = common::app_harness();
    let count = harness.state().lesson_count();
    for index in 0..count {
        harness.state_mut().selected = index;
        harness.run_steps(2);
        {
            let app = harness.state_mut();
            let lesson = app.lesson_mut().unwrap();
            // The ray moved, the structure and camera changed where the lesson has them.
            if let Some(flat) = lesson.stage_mut().scene.as_flat() {
                flat.scene.ray_origin += glam::DVec2::new(1.25, -0.5);
                flat.touch_ray();
            }
            let _ = lesson.restore("structure", "kd:median");
            let _ = lesson.restore("structure", "bvh:median");
            let _ = lesson.restore("camera", "47.5,-12.25,3.5,0.1,0,-0.2,o");
            let _ = lesson.restore("mesh", "builtin:icosphere");
            let _ = lesson.restore("counter", "boxes");
            let _ = lesson.restore("packets", "8x8");
            let _ = lesson.restore("cells", "13");
            let _ = lesson.restore("places", "97");
            let _ = lesson.restore("mailbox", "false");
            let _ = lesson.restore("mode", "traverse");
        }
        harness.run_steps(3);
        if let Some(lesson) = harness.state_mut().lesson_mut() {
            let timeline = &mut lesson.stage_mut().timeline;
            timeline.shown = timeline.len * 2 / 3;
        }
        harness.run();
        let before = view_of(harness.state());
        let link = harness.state().share_state().unwrap().encode();
        let title = harness.state().titles()[index].clone();

        let mut other = common::app_harness();
        other
            .state_mut()
            .open_state(&format!("https://example.invalid/#{link}"))
            .unwrap();
        other.run_steps(4);
        let after = view_of(other.state());
        assert_eq!(after, before, "{title}: {link}");
    }
}

#[test]
fn a_garbage_link_opens_the_first_lesson_with_a_reason() {
    for garbage in [
        "#hello",
        "#v=1&lesson=99",
        "#v=1&lesson=4&structure=bvh:nonsense",
        "#v=1&lesson=12&camera=1,2,3",
        "#v=1&lesson=14&packets=3x3",
        "#v=1&lesson=4&scene=KGJyb2tlbg",
        "#v=9&lesson=4",
    ] {
        let mut harness = common::app_harness();
        harness.state_mut().selected = 5;
        let error = harness.state_mut().open_state(garbage).unwrap_err();
        harness.run();
        let app = harness.state();
        assert_eq!(app.selected, 0, "{garbage}");
        let (message, problem) = app.status.clone().unwrap();
        assert!(problem && message.contains(&error), "{garbage}: {message}");
    }
}

#[test]
fn a_link_keeps_the_lesson_s_own_scene_out() {
    let mut harness = common::app_harness();
    harness.state_mut().selected = 3;
    harness.run_steps(2);
    let state = harness.state().share_state().unwrap();
    assert!(
        state.scene.is_none(),
        "the lesson's own scene needs no copy"
    );
    let text = state.encode();
    assert!(text.len() < 200, "{text}");
    assert_eq!(ViewState::decode(&text).unwrap().lesson, 3);
}

/// A named ray of the lesson file (lesson 4's r2, as a lecture script shows it) goes in a
/// link by its name, not as a whole scene, and opens the same view.
#[test]
fn a_named_ray_is_shared_by_its_name() {
    let mut harness = common::app_harness();
    let titles = harness.state().titles();
    harness.state_mut().selected = titles
        .iter()
        .position(|title| title.contains("Bounding volume hierarchy"))
        .unwrap();
    harness.run_steps(2);
    assert!(harness.state_mut().lesson_mut().unwrap().show_named("r2"));
    harness.run_steps(2);
    let before = view_of(harness.state());
    let link = harness.state().share_state().unwrap().encode();
    assert!(link.contains("show=r2"), "{link}");
    assert!(!link.contains("scene="), "{link}");
    assert!(link.len() < 120, "{} characters: {link}", link.len());
    let mut other = common::app_harness();
    other.state_mut().open_state(&link).unwrap();
    other.run_steps(3);
    assert_eq!(view_of(other.state()), before);
}

#[test]
fn a_3d_link_reopens_on_the_same_clicked_pixel_order_and_step() {
    let mut harness = common::app_harness();
    let titles = harness.state().titles();
    for title in ["real mesh", "kD-tree in 3D"] {
        let index = titles.iter().position(|t| t.contains(title)).unwrap();
        harness.state_mut().selected = index;
        harness.run_steps(2);
        {
            let lesson = harness.state_mut().lesson_mut().unwrap();
            lesson.restore("order", "file-order").unwrap();
            // The pixel a click on the teapot's body gives in a 960 × 680 view.
            lesson.restore("pixel", "480,330,960,680").unwrap();
        }
        harness.run_steps(3);
        let steps = {
            let lesson = harness.state_mut().lesson_mut().unwrap();
            let timeline = &mut lesson.stage_mut().timeline;
            assert!(timeline.len > 6, "{title}: the pixel's ray is traced");
            timeline.shown = timeline.len / 2;
            timeline.len
        };
        harness.run();
        let caption = |app: &AccelvizApp| app.lesson().unwrap().caption();
        let before = (view_of(harness.state()), caption(harness.state()));
        let link = harness.state().share_state().unwrap().encode();
        assert!(link.contains("pixel=480,330,960,680"), "{link}");
        assert!(link.contains("order=file-order"), "{link}");

        // Opened where the tree is built on a worker thread (as on the desktop, or in a Web
        // Worker in the browser): the step waits for the tree and its trace.
        accelviz_app::background::set_background(true);
        let mut other = common::app_harness();
        other.state_mut().open_state(&link).unwrap();
        for _ in 0..400 {
            other.step();
            let lesson = other.state().lesson().unwrap();
            if lesson.building().is_none() && lesson.stage().timeline.len > 0 {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        other.run_steps(2);
        accelviz_app::background::set_background(false);
        let after = (view_of(other.state()), caption(other.state()));
        assert_eq!(after, before, "{title}: {link}");
        assert_eq!(
            other.state().lesson().unwrap().stage().timeline.len,
            steps,
            "{title}: the same ray, traced in as many steps"
        );
    }
    let mut harness = common::app_harness();
    for (bad, problem) in [
        ("480,330,960", "not four numbers"),
        ("960,10,960,680", "outside a 960×680 picture"),
        ("a,b,c,d", "not four whole numbers"),
    ] {
        let index = titles.iter().position(|t| t.contains("real mesh")).unwrap();
        let link = format!("v=1&lesson={}&pixel={bad}", index + 1);
        let error = harness.state_mut().open_state(&link).unwrap_err();
        assert!(error.contains(problem), "{bad}: {error}");
    }
}

/// A 2D view the user zoomed and panned goes in the link and comes back as it was; a camera
/// dragged to a noisy angle is written in ten significant digits; Escape closes the Share
/// window.
#[test]
fn a_moved_2d_view_and_a_tidy_camera_go_in_the_link_and_escape_closes_it() {
    use accelviz_app::share::{parse_camera, tidy};
    let mut harness = common::app_harness();
    harness.state_mut().selected = 3;
    harness.run_steps(2);
    {
        let app = harness.state_mut();
        let flat = app
            .lesson_mut()
            .unwrap()
            .stage_mut()
            .scene
            .as_flat()
            .unwrap();
        flat.view.center = glam::DVec2::new(12.5, -3.25);
        flat.view.points_per_unit = 7.75;
        flat.view.placed = true;
        flat.view.fitted_size = None;
    }
    let encoded = harness.state().share_state().unwrap().encode();
    assert!(encoded.contains("view=12.5,-3.25,7.75"), "{encoded}");
    let mut opened = common::app_harness();
    opened.state_mut().open_state(&encoded).unwrap();
    opened.run_steps(2);
    let view = opened
        .state()
        .lesson()
        .unwrap()
        .stage()
        .scene
        .flat()
        .unwrap()
        .view;
    assert_eq!(
        (view.center, view.points_per_unit),
        (glam::DVec2::new(12.5, -3.25), 7.75)
    );
    // A camera angle with float noise, tidied, and read back within a millionth.
    assert_eq!(tidy(34.00000000000001), "34");
    assert_eq!(tidy(-0.000123456789012), "-0.000123456789");
    assert_eq!(tidy(0.1 + 0.2), "0.3");
    let orbit = parse_camera("34.00000000000001,20,5,0,0,0,p").unwrap();
    let (_, value) = accelviz_app::share::camera_value(&orbit);
    assert_eq!(value, "34,20,5,0,0,0,p");
    // Escape closes the Share window.
    harness.state_mut().share_window = Some(String::new());
    harness.run();
    assert!(harness.state().share_window.is_some());
    harness.key_press(egui::Key::Escape);
    harness.run();
    assert!(harness.state().share_window.is_none(), "Escape closes it");
}
