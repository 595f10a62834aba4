//! Layout holds whatever the input: the slab lesson's labels never overlap each other or leave
//! their panel in any edge case at any step, and a scene of huge (but finite) coordinates
//! keeps every panel at its size, numbers written short.

use crate::common;

use common::lesson_text;

use accelviz_app::AccelvizApp;
use accelviz_app::canvas::any_overlap;
use accelviz_app::lesson::Lesson;
use accelviz_app::lessons::slab::{GALLERY, SlabLesson};
use egui_kittest::Harness;

#[test]
fn slab_labels_never_overlap_in_any_edge_case() {
    let size = egui::vec2(1200.0, 760.0);
    let mut harness = Harness::builder().with_size(size).build_ui_state(
        |ui, lesson: &mut SlabLesson| {
            lesson.update();
            egui::Panel::right("inspector").show(ui, |ui| lesson.inspector_ui(ui));
            egui::CentralPanel::default().show(ui, |ui| lesson.canvas_ui(ui));
        },
        SlabLesson::new(lesson_text("03-slab-test.ron")),
    );
    harness.run();
    for (case, (name, _)) in GALLERY.iter().enumerate() {
        harness.state_mut().show_case(case);
        for step in 0..=5 {
            harness.state_mut().stage_mut().timeline.shown = step;
            harness.run_steps(2);
            let rects = harness.state().label_rects().to_vec();
            assert_eq!(rects.len(), 2, "the canvas's labels and the number lines'");
            for (area, placed) in ["canvas", "number lines"].iter().zip(&rects) {
                assert!(
                    !any_overlap(placed),
                    "{}, step {step}, {area}: labels overlap: {placed:?}",
                    name
                );
                for rect in placed {
                    assert!(
                        rect.min.x >= 0.0
                            && rect.max.x <= size.x
                            && rect.min.y >= 0.0
                            && rect.max.y <= size.y,
                        "{}, step {step}: a label leaves the window: {rect:?}",
                        name
                    );
                }
            }
            if step == 5 {
                // Every mark that has a finite t is labelled somewhere: nothing was dropped
                // for want of room in the common cases.
                assert!(rects[0].len() >= 2, "{}: {rects:?}", name);
            }
        }
    }
}

/// A scene with coordinates of 1e300: every lesson still lays out, the inspector keeps its
/// width, the canvas keeps its room, and numbers are written short.
#[test]
fn huge_coordinates_keep_the_layout() {
    let scene = "(
        shapes: [
            Box(min: (1e300, 1e300), max: (3e300, 2e300)),
            Disc(center: (-1e300, 5e299), radius: 4e299),
            Segment(from: (0, 0), to: (2e300, -1e300)),
        ],
        ray: (origin: (-5e300, -5e300), toward: (-4e300, -4.5e300)),
    )";
    let size = egui::vec2(1400.0, 860.0);
    let mut harness = Harness::builder().with_size(size).build_ui_state(
        |ui, app: &mut AccelvizApp| app.contents_ui(ui),
        AccelvizApp::new(),
    );
    // The 3D lessons open a mesh that large.
    let mesh = "v 1e300 1e300 -1e300\nv 3e300 1e300 0\nv 1e300 2e300 2e300\n\
                v -1e300 5e299 0\nf 1 2 3\nf 1 3 4\n";
    for index in 0..harness.state().lesson_count() {
        harness.state_mut().selected = index;
        let is_3d = harness
            .state()
            .lesson()
            .is_some_and(|lesson| lesson.stage().scene.flat().is_none());
        let opens_files = harness
            .state()
            .lesson()
            .is_some_and(|lesson| lesson.stage().scene.filter().is_some());
        let opened = if !opens_files {
            true
        } else if is_3d {
            harness.state_mut().open_scene_text("huge.obj", mesh)
        } else {
            harness.state_mut().open_scene_text("huge.ron", scene)
        };
        assert!(opened, "opens");
        harness.run_steps(3);
        if let Some(lesson) = harness.state_mut().lesson_mut() {
            let timeline = &mut lesson.stage_mut().timeline;
            timeline.shown = timeline.len / 2;
        }
        harness.run_steps(2);
        let title = harness.state().titles()[index].clone();
        let layout = harness.state().last_layout;
        let width = layout.inspector.width();
        assert!(
            width <= 570.0,
            "{title}: the inspector grew to {width} points"
        );
        let canvas_room = layout.canvas.width();
        assert!(
            canvas_room >= 500.0,
            "{title}: the canvas has {canvas_room} points left"
        );
        // No number is written out in full.
        use egui_kittest::kittest::Queryable;
        assert!(
            harness.query_by_label_contains("0000000000").is_none(),
            "{title}: a number written out in full"
        );
    }
}

/// Scaled up (the Scale setting, or Ctrl +), every lesson keeps its layout whole: the panels
/// shrink to shares of the window, the toolbar wraps, and nothing in the middle is pushed past
/// the inspector or the window's edge.
#[test]
fn scaled_up_every_lesson_keeps_its_layout_whole() {
    // Ctrl + twice and three times on the usual window, and the largest scale on a projector.
    for (screen, zoom) in [
        (egui::vec2(1400.0, 860.0), 1.4_f32),
        (egui::vec2(1400.0, 860.0), 1.6),
        (egui::vec2(1920.0, 1080.0), 2.0),
    ] {
        let mut harness = common::app_harness_sized(screen);
        harness.ctx.set_zoom_factor(zoom);
        harness.run();
        let points = harness.ctx.content_rect().size();
        assert!(
            (points.x - screen.x / zoom).abs() < 2.0,
            "{points:?} at {zoom}x of {screen:?}"
        );
        for index in 0..harness.state().lesson_count() {
            harness.state_mut().selected = index;
            harness.run_steps(3);
            let title = harness.state().titles()[index].clone();
            let layout = harness.state().last_layout;
            let (canvas, inspector) = (layout.canvas, layout.inspector);
            assert!(
                canvas.right() <= inspector.left() + 1.0 && inspector.right() <= points.x + 1.0,
                "{title} at {zoom}x: the middle {canvas:?} runs past the inspector {inspector:?} or the window ({points:?})"
            );
            assert!(
                canvas.width() >= 0.4 * points.x,
                "{title} at {zoom}x: the canvas has {} of {} points",
                canvas.width(),
                points.x
            );
        }
    }
}

/// A window made small and large again gives the inspector its width back, and lesson 6's
/// counter table keeps all four columns in it at the end of the traversal.
#[test]
fn the_inspector_comes_back_after_a_small_window_and_lesson_6_s_table_fits_it() {
    use egui_kittest::kittest::Queryable;
    let mut harness = common::app_harness_sized(egui::vec2(1920.0, 1080.0));
    let titles = harness.state().titles();
    harness.state_mut().selected = titles
        .iter()
        .position(|title| title.contains("Near first or file order"))
        .expect("lesson 6");
    harness.run();
    harness.run();
    let before = harness.state().last_layout.inspector;
    harness.set_size(egui::vec2(640.0, 480.0));
    harness.run();
    harness.run();
    assert!(harness.state().last_layout.inspector.width() < before.width());
    harness.set_size(egui::vec2(1920.0, 1080.0));
    harness.run();
    harness.run();
    let after = harness.state().last_layout.inspector;
    assert!(
        (after.width() - before.width()).abs() < 1.0,
        "the inspector was {before:?}, is {after:?}"
    );
    // At the traversal's end, the widest the table gets: every column inside the inspector.
    {
        let timeline = &mut harness
            .state_mut()
            .lesson_mut()
            .expect("lesson")
            .stage_mut()
            .timeline;
        timeline.shown = timeline.len;
    }
    harness.run();
    harness.run();
    let header = harness.get_by_label("BVH file").rect();
    assert!(
        header.max.x <= after.max.x,
        "the last column ends at {} past the inspector's {}",
        header.max.x,
        after.max.x
    );
}
