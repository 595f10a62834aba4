//! The 3D lessons' costs on the Stanford bunny (`../shared/meshes`, 69,451 triangles): the
//! mesh read and its BVH built as the app does it; its 512 × 512 heat maps (near first and
//! file order, every counter) on the machine's cores; and the CPU time of one frame of lesson
//! 12 with the whole BVH drawn (about 33k boxes), the GPU being the software adapter.

use std::sync::Arc;

use accelviz_app::AccelvizApp;
use accelviz_app::view3d::Gpu;
use accelviz_app::view3d::heat::{HeatJob, HeatKey};
use accelviz_app::view3d::mesh_scene::MeshTree;
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

fn view3d_costs(c: &mut Criterion) {
    let text = bunny_text();
    c.bench_function("3D: bunny read and its BVH built (bvh:sah-binned)", |b| {
        b.iter(|| {
            let mesh = accelviz_scene::obj::parse_obj(&text, "bunny.obj").expect("parses");
            MeshTree::build(Arc::new(mesh), structure())
                .stats
                .node_count
        })
    });

    let mesh = accelviz_scene::obj::parse_obj(&text, "bunny.obj").expect("parses");
    let tree = Arc::new(MeshTree::build(Arc::new(mesh), structure()));
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let key = HeatKey {
        tree: 1,
        camera: accelviz_app::view3d::Orbit::default().camera(tree.sphere.0, tree.sphere.1),
        width: 512,
        height: 512,
    };
    c.bench_function(
        &format!("3D: bunny heat maps 512x512, both orders, {threads} threads"),
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

    // One frame of lesson 12 on the bunny with its whole BVH drawn, on the software adapter.
    let render_state = egui_kittest::wgpu::create_render_state(
        egui_kittest::wgpu::default_wgpu_setup(),
        eframe::egui_wgpu::RendererOptions::PREDICTABLE,
    );
    let ctx = egui::Context::default();
    Gpu::install(&ctx, render_state);
    let mut app = AccelvizApp::new();
    let titles = app.titles();
    app.selected = titles
        .iter()
        .position(|title| title.contains("real mesh"))
        .expect("lesson 12");
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
