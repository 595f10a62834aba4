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
        common::draw_lesson::<SlabLesson>,
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

/// Content never pushes the inspector: in every lesson, at its first and its last step and
/// with each thing it shows by name (lesson 17's ten-column table of distances among them),
/// the inspector keeps the width it opened with, and what is wider scrolls sideways. A panel
/// that grew with its content kept the width of the widest thing it had shown: lesson 16's
/// layout depended on which structure its measurement happened to find fastest.
#[test]
fn content_never_widens_the_inspector() {
    // A laptop's window, where the inspector is narrower than on a projector.
    let mut harness = common::app_harness_sized(egui::vec2(1100.0, 760.0));
    harness.run();
    let opened = harness.state().last_layout.inspector.width();
    for index in 0..harness.state().lesson_count() {
        harness.state_mut().selected = index;
        common::run_until_built(&mut harness, 100);
        let title = harness.state().titles()[index].clone();
        let names = harness
            .state()
            .lesson()
            .map(|lesson| lesson.named())
            .unwrap_or_default();
        for name in std::iter::once(None).chain(names.iter().map(Some)) {
            if let (Some(name), Some(lesson)) = (name, harness.state_mut().lesson_mut()) {
                assert!(lesson.show_named(name), "{title}: shows {name}");
            }
            for last in [false, true] {
                if let Some(lesson) = harness.state_mut().lesson_mut() {
                    let timeline = &mut lesson.stage_mut().timeline;
                    timeline.shown = if last { timeline.len } else { 0 };
                }
                harness.run_steps(2);
                let width = harness.state().last_layout.inspector.width();
                assert!(
                    (width - opened).abs() < 0.5,
                    "{title}, {name:?}, last step {last}: the inspector is {width} points wide, it opened {opened} wide"
                );
            }
        }
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

/// A box's name reads as that box's: a parent named with its children takes its name outside
/// its box (above its top edge, or below its bottom edge), well apart from another name
/// outside; a child's name sits inside its own box. What made "root R" and "R RR" of the
/// findings read as one name.
#[test]
fn a_parents_name_goes_outside_its_box_and_a_childs_inside() {
    use accelviz_app::canvas::Labels;
    use egui::{Color32, FontId, Rect, pos2};
    let ctx = egui::Context::default();
    let mut output = ctx.run_ui(egui::RawInput::default(), |ui| {
        let painter = ui.painter().clone();
        let area = Rect::from_min_max(pos2(0.0, 0.0), pos2(600.0, 600.0));
        let mut labels = Labels::new(area);
        let font = FontId::proportional(13.0);
        let root = Rect::from_min_max(pos2(100.0, 100.0), pos2(500.0, 500.0));
        // The right child shares the root's top edge, moved in by its depth.
        let right = Rect::from_min_max(pos2(110.0, 103.0), pos2(497.0, 250.0));
        let leaf = Rect::from_min_max(pos2(120.0, 110.0), pos2(200.0, 180.0));
        let place = |labels: &mut Labels, text: &str, boxed: Rect, outside: bool| {
            labels
                .place_for_box(
                    &painter,
                    text,
                    font.clone(),
                    Color32::WHITE,
                    boxed,
                    outside,
                    None,
                )
                .expect("a spot is free")
        };
        let at_root = place(&mut labels, "root", root, true);
        let at_right = place(&mut labels, "R", right, true);
        let at_leaf = place(&mut labels, "RL", leaf, false);
        assert!(
            at_root.max.y <= root.top(),
            "the root's name is above it: {at_root:?}"
        );
        assert!(
            !right.intersects(at_right),
            "R's name is outside R: {at_right:?}"
        );
        assert!(
            at_root.expand(5.0).intersect(at_right.expand(5.0)).area() <= 0.0,
            "the two names outside keep apart: {at_root:?} {at_right:?}"
        );
        assert!(
            leaf.contains_rect(at_leaf),
            "RL's name is inside RL: {at_leaf:?}"
        );
        assert!(!any_overlap(labels.placed()));
    });
    output.textures_delta.clear();
}

/// A fitted view keeps clear of the caption's room at the top and the notes' at the bottom:
/// a ray's origin in the scene's corner was hidden under "5 shapes · the lesson's scene".
/// Where a short, wide pane has more room beside its caption than below it (the recap's five
/// panes: a scene 60 points high under four lines of caption), the scene goes beside it.
#[test]
fn a_fitted_view_keeps_clear_of_the_caption_and_the_notes() {
    use accelviz_app::canvas::View2d;
    use accelviz_core::Aabb;
    use glam::DVec2;
    let rect = egui::Rect::from_min_size(egui::pos2(10.0, 20.0), egui::vec2(800.0, 500.0));
    let bounds = Aabb::new(DVec2::new(0.0, 0.0), DVec2::new(40.0, 20.0));
    let on_screen = |view: &View2d, point: DVec2| {
        rect.center()
            + egui::vec2(
                ((point.x - view.center.x) * view.points_per_unit) as f32,
                -((point.y - view.center.y) * view.points_per_unit) as f32,
            )
    };
    let (caption, bottom) = (egui::vec2(300.0, 60.0), 40.0);
    let view = View2d::fitted_between(&bounds, rect, caption, bottom);
    let (top_left, bottom_right) = (
        on_screen(&view, DVec2::new(bounds.min.x, bounds.max.y)),
        on_screen(&view, DVec2::new(bounds.max.x, bounds.min.y)),
    );
    assert!(
        top_left.y >= rect.top() + caption.y,
        "below the caption: {top_left:?}"
    );
    assert!(
        bottom_right.y <= rect.bottom() - bottom,
        "above the notes: {bottom_right:?}"
    );
    // Centred between them.
    let middle = (rect.top() + caption.y + rect.bottom() - bottom) / 2.0;
    assert!(((top_left.y + bottom_right.y) / 2.0 - middle).abs() < 0.5);

    // A square scene in a wide, short pane under a tall caption: beside it, larger.
    let pane = egui::Rect::from_min_size(egui::pos2(0.0, 0.0), egui::vec2(420.0, 300.0));
    let square = Aabb::new(DVec2::ZERO, DVec2::splat(100.0));
    let caption = egui::vec2(180.0, 120.0);
    // Below it, with the 24-point margins: 300 − 48 − 120 = 132 points for 100 units.
    let below = 1.32;
    let view = View2d::fitted_between(&square, pane, caption, 0.0);
    assert!(
        view.points_per_unit > below * 1.3,
        "beside the caption the scene is larger: {} against {below}",
        view.points_per_unit,
    );
    let left = pane.center().x + ((square.min.x - view.center.x) * view.points_per_unit) as f32;
    let right = pane.center().x + ((square.max.x - view.center.x) * view.points_per_unit) as f32;
    assert!(
        left >= pane.left() + caption.x,
        "right of the caption: {left}"
    );
    assert!(right <= pane.right(), "inside the pane: {right}");
}

/// The slots' batches drawn in a frame: their vertices, in drawing order.
fn batched_meshes(harness: &Harness<'_, BatchScene>) -> Vec<Vec<egui::Pos2>> {
    fn walk(shape: &egui::Shape, found: &mut Vec<Vec<egui::Pos2>>) {
        match shape {
            egui::Shape::Mesh(mesh) => found.push(mesh.vertices.iter().map(|v| v.pos).collect()),
            egui::Shape::Vec(shapes) => shapes.iter().for_each(|shape| walk(shape, found)),
            _ => {}
        }
    }
    let mut found = Vec::new();
    for clipped in &harness.output().shapes {
        walk(&clipped.shape, &mut found);
    }
    found
}

/// Three slots of batched boxes on one canvas, as lesson 7's panes draw their trees.
struct BatchScene {
    view: accelviz_app::canvas::View2d,
    key: u64,
    fills: usize,
}

/// Three new batches at once (lesson 7's three trees arriving) are made one a frame, the
/// others shown meanwhile as they were, moved to the frame's view; a pan moves the waiting
/// ones exactly where a fresh batch puts them.
#[test]
fn one_batch_is_made_a_frame_while_the_others_wait_moved_to_the_view() {
    use accelviz_app::canvas::Canvas;
    use accelviz_core::Aabb;
    use glam::DVec2;
    let bounds = Aabb::new(DVec2::ZERO, DVec2::new(30.0, 10.0));
    let mut harness = Harness::builder()
        .with_size(egui::vec2(600.0, 300.0))
        .build_ui_state(
            move |ui, scene: &mut BatchScene| {
                let size = ui.available_size();
                let canvas = Canvas::allocate(ui, size, &mut scene.view, &bounds, false);
                for slot in 0..3u32 {
                    let fills = &mut scene.fills;
                    canvas.cached_batch(&format!("slot {slot}"), (scene.key, slot), |batch| {
                        *fills += 1;
                        for index in 0..4 {
                            let min = DVec2::new(slot as f64 * 10.0 + index as f64, index as f64);
                            let boxed = Aabb::new(min, min + DVec2::splat(1.5));
                            batch.rect(canvas.screen_rect(&boxed), egui::Color32::WHITE);
                        }
                    });
                }
            },
            BatchScene {
                view: accelviz_app::canvas::View2d::default(),
                key: 0,
                fills: 0,
            },
        );
    harness.step();
    assert_eq!(
        harness.state().fills,
        3,
        "nothing to show yet: all three are made"
    );
    // New contents for all three: one a frame.
    harness.state_mut().key = 1;
    for frame in 1..=3 {
        harness.step();
        assert_eq!(harness.state().fills, 3 + frame, "frame {frame}");
    }
    harness.step();
    assert_eq!(harness.state().fills, 6, "all made: none again");
    // A pan: one made at once, the others moved, where the fresh ones then go.
    harness.state_mut().view.center += DVec2::new(3.0, -1.5);
    harness.state_mut().view.points_per_unit *= 1.25;
    harness.state_mut().view.fitted_size = None;
    harness.step();
    assert_eq!(harness.state().fills, 7);
    let moved = batched_meshes(&harness);
    harness.run();
    assert_eq!(harness.state().fills, 9);
    let fresh = batched_meshes(&harness);
    assert_eq!(moved.len(), 3);
    for (moved, fresh) in moved.iter().zip(&fresh) {
        assert_eq!(moved.len(), fresh.len());
        for (a, b) in moved.iter().zip(fresh) {
            assert!((*a - *b).length() < 1e-3, "{a:?} against {b:?}");
        }
    }
}
