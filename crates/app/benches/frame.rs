//! Frame cost: the CPU time of one frame of the app (the lesson's UI code, then egui's
//! tessellation into triangles), with a 10k-primitive 2D scene and its whole BVH drawn on the
//! BVH lesson (target: under 8 ms on the README's machine), and with three kD-trees of 20,000
//! shapes on lesson 7. Rendering the triangles is the GPU's (or lavapipe's) work and is not
//! counted.

use accelviz_app::AccelvizApp;
use accelviz_scene::document::{GeneratorEntry, LayoutEntry};
use criterion::{Criterion, criterion_group, criterion_main};

// The allocator the desktop app runs with, and why: `src/main.rs`.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn frame(ctx: &egui::Context, app: &mut AccelvizApp) -> usize {
    app.tessellated_frame(ctx, egui::vec2(1400.0, 860.0)).len()
}

/// The app on the lesson whose title contains `lesson`, with a generated scene of `count`
/// shapes, leaves of at most two, after the frames that build it and fit the view.
fn app_on(lesson: &str, layout: LayoutEntry, count: usize) -> (egui::Context, AccelvizApp) {
    let ctx = egui::Context::default();
    let mut app = AccelvizApp::new();
    let titles = app.titles();
    app.selected = titles
        .iter()
        .position(|title| title.contains(lesson))
        .expect("the lesson");
    app.lesson_mut()
        .expect("the lesson")
        .stage_mut()
        .scene
        .as_flat()
        .expect("a 2D scene")
        .scene
        .settings
        .max_leaf_size = 2;
    assert!(app.generate_scene(GeneratorEntry {
        layout,
        count,
        seed: 1,
    }));
    // The first frames build (at once: no worker threads here) and fit the view.
    for _ in 0..3 {
        frame(&ctx, &mut app);
    }
    (ctx, app)
}

fn frame_cost(c: &mut Criterion) {
    let (ctx, mut app) = app_on("hierarchy", LayoutEntry::Uniform, 10_000);
    c.bench_function("frame: BVH lesson, 10k shapes, whole tree drawn", |b| {
        b.iter(|| frame(&ctx, &mut app))
    });
    // Lesson 7's kD-trees over 20,000 shapes, two a leaf: once 5 s a frame, 815,859 leaves in
    // the middle-split tree alone.
    let (ctx, mut app) = app_on("Middle, median or SAH", LayoutEntry::Uniform, 20_000);
    c.bench_function(
        "frame: lesson 7, kD-trees, 20k shapes, leaves of two",
        |b| b.iter(|| frame(&ctx, &mut app)),
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = frame_cost
}
criterion_main!(benches);
