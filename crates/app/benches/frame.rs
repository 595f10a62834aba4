//! Frame cost: the CPU time of one frame of the app (the lesson's UI code, then egui's
//! tessellation into triangles) with a 10k-primitive 2D scene and its whole BVH drawn, on the
//! BVH lesson. Target: under 8 ms on the README's machine. Rendering the triangles is the GPU's
//! (or lavapipe's) work and is not counted.

use accelviz_app::AccelvizApp;
use accelviz_scene::document::{GeneratorEntry, LayoutEntry};
use criterion::{Criterion, criterion_group, criterion_main};

fn frame(ctx: &egui::Context, app: &mut AccelvizApp) -> usize {
    app.tessellated_frame(ctx, egui::vec2(1400.0, 860.0)).len()
}

fn frame_cost(c: &mut Criterion) {
    let ctx = egui::Context::default();
    let mut app = AccelvizApp::new();
    let titles = app.titles();
    app.selected = titles
        .iter()
        .position(|title| title.contains("hierarchy"))
        .expect("the BVH lesson");
    let scene = &mut app.lesson_mut().expect("the BVH lesson").stage_mut().scene;
    scene.scene.settings.max_leaf_size = 2;
    scene.generator = GeneratorEntry {
        layout: LayoutEntry::Uniform,
        count: 10_000,
        seed: 1,
    };
    scene.generate();
    // The first frames build the tree and fit the view; the benchmark times the frames after.
    for _ in 0..3 {
        frame(&ctx, &mut app);
    }
    c.bench_function("frame: BVH lesson, 10k shapes, whole tree drawn", |b| {
        b.iter(|| frame(&ctx, &mut app))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = frame_cost
}
criterion_main!(benches);
