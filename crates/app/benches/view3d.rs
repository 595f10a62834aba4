//! The 3D lessons' costs on the Stanford bunny (`../shared/meshes`, 69,451 triangles): the
//! mesh read and its BVH built as the app does it; its 512 × 512 heat maps (near first and
//! file order, every counter) on the machine's cores; and the CPU time of one frame of lesson
//! 12 with the whole BVH drawn (about 33k boxes), the GPU being the software adapter.

use std::sync::Arc;

use accelviz_app::AccelvizApp;
use accelviz_app::mesh::MeshTree;
use accelviz_app::mesh::heat::{HeatJob, HeatKey};
use accelviz_app::view3d::Gpu;
use accelviz_core::Structure;
use criterion::{Criterion, criterion_group, criterion_main};

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

const BUNNY: &str = "../../../shared/meshes/stanford-bunny.obj";

fn bunny_text() -> String {
    std::fs::read_to_string(BUNNY).expect("the shared meshes are beside the repository")
}

fn structure() -> Structure {
    Structure::parse("bvh:sah-binned").expect("in the catalogue")
}

/// Frames of lesson 12 while a mesh of a million triangles is read from OBJ text and its BVH
/// built on worker threads, as the desktop app does it: how many, and the slowest (CPU time,
/// the GPU being the software adapter). Printed, once: a frame is not a repeatable sample.
fn frames_while_a_million_triangles_load(ctx: &egui::Context) {
    let mesh = accelviz_scene::builtin::lumpy_grid_sphere(1_000_000);
    let triangles = mesh.triangles.len();
    let text = accelviz_scene::obj::obj_text(&mesh);
    drop(mesh);
    accelviz_app::background::set_background(true);
    let mut app = lesson_12();
    let size = egui::vec2(1400.0, 860.0);
    for _ in 0..3 {
        app.tessellated_frame(ctx, size);
    }
    let started = std::time::Instant::now();
    assert!(app.open_scene_text("million.obj", &text), "the mesh opens");
    let mut frames: Vec<f64> = Vec::new();
    let mut idle_frames = 0;
    while idle_frames < 40 {
        let frame_started = std::time::Instant::now();
        app.tessellated_frame(ctx, size);
        frames.push(frame_started.elapsed().as_secs_f64() * 1e3);
        let lesson = app.lesson().expect("lesson 12");
        let busy = lesson.building().is_some() || lesson.stage().scene.reading().is_some();
        idle_frames = if busy { 0 } else { idle_frames + 1 };
        if std::env::var_os("ACCELVIZ_BENCH_FRAMES").is_some() {
            eprintln!(
                "frame {} {:.1} ms busy {busy}",
                frames.len(),
                frames[frames.len() - 1]
            );
        }
        assert!(started.elapsed().as_secs() < 300, "the mesh never arrived");
        // A display's pace: the app waits for vsync between frames.
        std::thread::sleep(std::time::Duration::from_millis(16));
    }
    let total = started.elapsed().as_secs_f64();
    let mut sorted = frames.clone();
    sorted.sort_by(f64::total_cmp);
    let slowest: Vec<String> = sorted
        .iter()
        .rev()
        .take(4)
        .map(|ms| format!("{ms:.0}"))
        .collect();
    println!(
        "3D: {triangles} triangles ({:.0} MB of OBJ) read and built aside in {total:.1} s: {} frames, \
         slowest {} ms, {} over 50 ms, median {:.1} ms",
        text.len() as f64 / 1e6,
        frames.len(),
        slowest.join(", "),
        frames.iter().filter(|&&ms| ms > 50.0).count(),
        sorted[sorted.len() / 2],
    );
    accelviz_app::background::set_background(false);
}

/// The app on lesson 12 (a real mesh and its BVH), two frames in.
fn lesson_12() -> AccelvizApp {
    let mut app = AccelvizApp::new();
    let titles = app.titles();
    app.selected = titles
        .iter()
        .position(|title| title.contains("real mesh"))
        .expect("lesson 12");
    app
}

fn view3d_costs(c: &mut Criterion) {
    let text = bunny_text();
    c.bench_function("3D: bunny read and its BVH built (bvh:sah-binned)", |b| {
        b.iter(|| {
            let mesh = accelviz_scene::obj::parse_obj(&text, "bunny.obj").expect("parses");
            MeshTree::build(Arc::new(mesh), structure())
                .build
                .stats
                .node_count
        })
    });

    let mesh = accelviz_scene::obj::parse_obj(&text, "bunny.obj").expect("parses");
    let tree = Arc::new(MeshTree::build(Arc::new(mesh), structure()));
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    for tile in [1, accelviz_app::mesh::heat::PACKET_TILE] {
        let key = HeatKey {
            tree: 1,
            camera: accelviz_app::view3d::Orbit::default()
                .camera(tree.build.sphere.0, tree.build.sphere.1),
            width: 512,
            height: 512,
            tile,
            ray_kind: accelviz_scene::rays::RayKind::Camera,
        };
        c.bench_function(
            &format!("3D: bunny heat maps 512x512, both orders, {threads} threads, tiles of {tile}x{tile}"),
            |b| {
                b.iter(|| {
                    let job = HeatJob::start(key, tree.clone(), threads);
                    while !job.done() {
                        std::thread::yield_now();
                    }
                    job.bands_done()
                })
            },
        );
    }

    // One frame of lesson 12 on the bunny with its whole BVH drawn, on the software adapter.
    let render_state = egui_kittest::wgpu::create_render_state(
        egui_kittest::wgpu::default_wgpu_setup(),
        eframe::egui_wgpu::RendererOptions::PREDICTABLE,
    );
    let ctx = egui::Context::default();
    Gpu::install(&ctx, render_state);
    if std::env::var_os("ACCELVIZ_BENCH_MILLION").is_some() {
        frames_while_a_million_triangles_load(&ctx);
    }
    let mut app = lesson_12();
    for _ in 0..2 {
        app.tessellated_frame(&ctx, egui::vec2(1400.0, 860.0));
    }
    assert!(app.open_scene_text("bunny.obj", &text), "the bunny opens");
    for _ in 0..3 {
        app.tessellated_frame(&ctx, egui::vec2(1400.0, 860.0));
    }
    c.bench_function("3D: frame of lesson 12, bunny, whole BVH drawn", |b| {
        b.iter(|| app.tessellated_frame(&ctx, egui::vec2(1400.0, 860.0)).len())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = view3d_costs
}
criterion_main!(benches);
