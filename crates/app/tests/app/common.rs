//! What the app's integration tests share: a lesson's parsed file, and harnesses that draw a
//! lesson or the whole app as the app does.

#![allow(dead_code)] // Each module uses some of these.

use accelviz_app::AccelvizApp;
use accelviz_app::lesson::Lesson;
use accelviz_app::lesson_file::LessonText;
use accelviz_app::registry::LESSONS;
use accelviz_app::view3d::Gpu;
use eframe::egui_wgpu::RenderState;
use egui_kittest::Harness;
use egui_kittest::wgpu::WgpuTestRenderer;

/// The parsed file of the lesson whose file name ends in `file`.
pub fn lesson_text(file: &str) -> LessonText {
    let entry = LESSONS
        .iter()
        .find(|entry| entry.path.ends_with(file))
        .expect("lesson file is registered");
    LessonText::parse(entry.embedded, entry.path).expect("lesson file parses")
}

/// One lesson with the app's panels around it, updated first as the app does (no renderer).
pub fn lesson_harness<L: Lesson + 'static>(lesson: L) -> Harness<'static, L> {
    Harness::builder()
        .with_size(egui::vec2(1300.0, 800.0))
        .build_ui_state(draw_lesson::<L>, lesson)
}

/// A frame of `lesson` as the app draws it: updated first, its timeline at the bottom, the
/// app's own inspector panel at the right, its canvas in the middle.
pub fn draw_lesson<L: Lesson>(ui: &mut egui::Ui, lesson: &mut L) {
    lesson.update();
    let caption = lesson.caption();
    egui::Panel::bottom("timeline").show(ui, |ui| {
        if let Some(caption) = caption {
            lesson.stage_mut().timeline.ui(ui, &caption);
        }
    });
    accelviz_app::app::inspector_panel(ui, |ui| {
        lesson.inspector_ui(ui, accelviz_app::lesson::Parts::All)
    });
    egui::CentralPanel::default().show(ui, |ui| lesson.canvas_ui(ui));
}

/// Runs the app until what its lesson builds or measures aside (a 3D tree, the trade lab) is
/// in, for at most `tries` rounds of two frames and 50 ms.
pub fn run_until_built(harness: &mut Harness<'_, AccelvizApp>, tries: usize) {
    for _ in 0..tries {
        harness.run_steps(2);
        if harness
            .state()
            .lesson()
            .is_none_or(|lesson| lesson.building().is_none())
        {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

/// The 2D scene `lesson` shows (the tests that ask open a 2D lesson).
pub fn flat<L: Lesson + ?Sized>(lesson: &L) -> &accelviz_app::editor::EditableScene {
    lesson.stage().scene.flat().expect("a 2D scene")
}

/// Drags the pointer from `start` to `end` in four moves, as a hand does, and drops it there.
pub fn drag<S>(harness: &mut Harness<'_, S>, start: egui::Pos2, end: egui::Pos2) {
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
}

/// The whole app at a projector-like size, rendered on the software adapter, with the GPU
/// given to the 3D views as eframe gives it.
pub fn app_harness() -> Harness<'static, AccelvizApp> {
    app_harness_sized(egui::vec2(1400.0, 860.0))
}

/// The whole app on a screen of `size` pixels (one a point), as [`app_harness`].
pub fn app_harness_sized(size: egui::Vec2) -> Harness<'static, AccelvizApp> {
    let (render_state, renderer) = software_gpu();
    let harness = Harness::builder()
        .with_size(size)
        .renderer(renderer)
        .build_ui_state(
            |ui, app: &mut AccelvizApp| app.contents_ui(ui),
            AccelvizApp::new(),
        );
    Gpu::install(&harness.ctx, render_state);
    harness
}

/// The software adapter's render state (for the 3D views) and the snapshot renderer on it.
pub fn software_gpu() -> (RenderState, WgpuTestRenderer) {
    let render_state = egui_kittest::wgpu::create_render_state(
        egui_kittest::wgpu::default_wgpu_setup(),
        eframe::egui_wgpu::RendererOptions::PREDICTABLE,
    );
    let renderer = WgpuTestRenderer::from_render_state(render_state.clone());
    (render_state, renderer)
}

/// One 3D lesson with the app's panels around it, rendered on the software adapter.
pub fn lesson_harness_3d<L: Lesson + 'static>(lesson: L) -> Harness<'static, L> {
    let (render_state, renderer) = software_gpu();
    let harness = Harness::builder()
        .with_size(egui::vec2(1300.0, 800.0))
        .renderer(renderer)
        .build_ui_state(draw_lesson::<L>, lesson);
    Gpu::install(&harness.ctx, render_state);
    harness
}
