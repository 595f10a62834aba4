//! Every lesson at its generator's maximum, in every mode that builds something else, builds
//! and draws within bounded memory: the frame's triangles stay far below what the renderer
//! takes (egui-wgpu refuses buffers over 256 MB; a middle-split kD-tree of 100,000 shapes once
//! asked for a 668 MB index buffer and panicked), the process's peak memory stays bounded
//! (it once grew to 15 GB), and each frame renders on the software adapter.
//!
//! The peak memory read from the system is the whole test binary's (the other app tests run
//! beside this one), so its bound holds for them together.

use accelviz_app::AccelvizApp;
use accelviz_app::editor::MAX_GENERATED;
use accelviz_scene::document::{GeneratorEntry, LayoutEntry, SceneSettings};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

/// The most indices one frame may hand the renderer: a quarter of egui-wgpu's 256 MB limit.
const MAX_FRAME_INDICES: usize = (256 << 20) / 4 / 4;

/// The most memory the process may reach, in kB: the scenes, trees and recordings of ten
/// lessons at 100,000 shapes (about 0.9 GB) and the software renderer's share.
const MAX_PEAK_KB: u64 = 5 << 19;

/// Runs one frame without rendering and counts the indices of its triangles.
fn frame_indices(ctx: &egui::Context, app: &mut AccelvizApp) -> usize {
    app.tessellated_frame(ctx, egui::vec2(1400.0, 860.0))
        .iter()
        .map(|clipped| match &clipped.primitive {
            egui::epaint::Primitive::Mesh(mesh) => mesh.indices.len(),
            egui::epaint::Primitive::Callback(_) => 0,
        })
        .sum()
}

/// The process's peak resident memory in kB (Linux), if the system says.
fn peak_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|line| line.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The buttons a lesson offers that build something else (structures, families, ways).
const MODES: [&str; 11] = [
    "middle",
    "median",
    "SAH",
    "binned SAH",
    "SAH, perfect splits",
    "kD-trees",
    "BVHs",
    "sort once",
    "sort at each node",
    "r1 and r2 together",
    "mailboxing: test a straddling primitive once per ray",
];

#[test]
fn every_lesson_at_its_largest_scene_builds_and_draws_within_bounds() {
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1400.0, 860.0))
        .wgpu()
        .build_ui_state(
            |ui, app: &mut AccelvizApp| app.contents_ui(ui),
            AccelvizApp::new(),
        );
    let ctx = egui::Context::default();
    let mut worst = (0usize, String::new());
    for index in 0..harness.state().lesson_count() {
        harness.state_mut().selected = index;
        let title = harness.state().titles()[index].clone();
        // A 2D lesson gets its generator's largest scene; a 3D lesson's largest mesh is
        // measured by the 3D view's own tests.
        if let Some(scene) = harness
            .state_mut()
            .lesson_mut()
            .expect("every lesson loads")
            .stage_mut()
            .scene
            .as_flat()
        {
            // The generator at its largest, and the smallest leaves the sliders allow.
            scene.generator = GeneratorEntry {
                layout: LayoutEntry::Uniform,
                count: MAX_GENERATED,
                seed: 1,
            };
            scene.generate();
            // Every slider at its far end: the smallest leaves, splitting for free, the
            // largest empty bonus and the most bins.
            scene.scene.settings = SceneSettings {
                max_leaf_size: 1,
                traversal_cost: 0.0,
                intersection_cost: 8.0,
                empty_bonus: 0.9,
                bins: 32,
            };
            scene.touch();
        }
        harness.run_steps(2);
        for mode in std::iter::once(None).chain(MODES.iter().map(Some)) {
            if let Some(mode) = mode {
                let Some(button) = harness.query_by_label(mode) else {
                    continue;
                };
                button.click();
                harness.run_steps(2);
            }
            // To the end of the animation, where the most is drawn.
            if let Some(lesson) = harness.state_mut().lesson_mut() {
                let timeline = &mut lesson.stage_mut().timeline;
                timeline.shown = timeline.len;
            }
            harness.run_steps(1);
            let indices = frame_indices(&ctx, harness.state_mut());
            let case = format!("{title}, {}", mode.copied().unwrap_or("as it opens"));
            assert!(
                indices <= MAX_FRAME_INDICES,
                "{case}: {indices} indices in one frame"
            );
            if indices > worst.0 {
                worst = (indices, case);
            }
        }
        // The renderer takes the lesson's last frame (lavapipe is slow with millions of
        // triangles, so once a lesson; the index counts above cover every mode).
        harness
            .render()
            .unwrap_or_else(|error| panic!("{title}: renders: {error}"));
        if let Some(peak) = peak_kb() {
            eprintln!("after {title}: peak memory {peak} kB");
            assert!(peak <= MAX_PEAK_KB, "after {title}: peak memory {peak} kB");
        }
    }
    eprintln!(
        "most indices in a frame: {} ({}); peak memory {:?} kB",
        worst.0,
        worst.1,
        peak_kb()
    );
}
