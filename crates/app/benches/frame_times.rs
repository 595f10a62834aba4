//! Frame times while lesson 7 rebuilds its three trees over 100,000 shapes, with worker
//! threads on as in the desktop app: every frame's UI-thread time (the lesson's code, then
//! egui's tessellation), from a generate and from each switch between kD-trees and BVHs
//! until the new trees are shown, and the slowest frame of each. The app's promise: no frame
//! over 100 ms while the trees are built aside. Timings, not a test: run it on a quiet
//! machine, `cargo bench -p accelviz-app --bench frame_times`.

use std::time::{Duration, Instant};

use accelviz_app::AccelvizApp;
use accelviz_scene::document::{GeneratorEntry, LayoutEntry};

// The allocator the desktop app runs with, and why: `src/main.rs`.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The shapes lesson 7 is given: the findings' 100,000.
const SHAPES: usize = 100_000;

/// A frame of the app at the projector's 1920 × 1080, timed: the whole of it; the part that
/// is egui's tessellation of what the lesson drew is summed in `TESSELLATION`.
fn frame(ctx: &egui::Context, app: &mut AccelvizApp) -> Duration {
    let started = Instant::now();
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(
            egui::Pos2::ZERO,
            egui::vec2(1920.0, 1080.0),
        )),
        ..Default::default()
    };
    let mut output = ctx.run_ui(input, |ui| app.contents_ui(ui));
    output.textures_delta.clear();
    let ui_done = started.elapsed();
    std::hint::black_box(ctx.tessellate(output.shapes, output.pixels_per_point));
    let total = started.elapsed();
    TESSELLATION.with(|sum| sum.set(sum.get() + (total - ui_done)));
    SLOW.with(|slow| {
        let mut slow = slow.borrow_mut();
        if slow.is_none_or(|(slowest, _)| total > slowest) {
            *slow = Some((total, total - ui_done));
        }
    });
    total
}

thread_local! {
    /// Time spent tessellating, summed over the frames of a phase.
    static TESSELLATION: std::cell::Cell<Duration> = const { std::cell::Cell::new(Duration::ZERO) };
    /// The slowest frame of a phase and its tessellation.
    static SLOW: std::cell::RefCell<Option<(Duration, Duration)>> = const { std::cell::RefCell::new(None) };
}

/// Frames until the lesson has the trees it asked for (at most `limit`), each one timed.
fn frames_until_built(
    ctx: &egui::Context,
    app: &mut AccelvizApp,
    limit: Duration,
) -> Vec<Duration> {
    let started = Instant::now();
    let mut times = vec![frame(ctx, app)];
    // A few frames more once built: the first frames with the new trees draw them.
    let mut after = 0;
    while after < 3 && started.elapsed() < limit {
        std::thread::sleep(Duration::from_millis(5));
        times.push(frame(ctx, app));
        if app.lesson().and_then(|lesson| lesson.building()).is_none() {
            after += 1;
        }
    }
    times
}

fn report(what: &str, times: &[Duration]) {
    let slowest = times.iter().max().copied().unwrap_or_default();
    let over = times
        .iter()
        .filter(|t| **t > Duration::from_millis(100))
        .count();
    let total: Duration = times.iter().sum();
    let tessellation = TESSELLATION.with(|sum| sum.replace(Duration::ZERO));
    let slowest_tessellation = SLOW
        .with(|slow| slow.borrow_mut().take())
        .map_or(Duration::ZERO, |(_, tessellation)| tessellation);
    let each: Vec<String> = times
        .iter()
        .map(|t| format!("{:.0}", t.as_secs_f64() * 1e3))
        .collect();
    println!(
        "{what}: {} frames in {:.2} s ({:.2} s tessellating), slowest {:.1} ms ({:.1} ms of it tessellating), {over} over 100 ms; ms each: {}",
        times.len(),
        total.as_secs_f64(),
        tessellation.as_secs_f64(),
        slowest.as_secs_f64() * 1e3,
        slowest_tessellation.as_secs_f64() * 1e3,
        each.join(" ")
    );
}

fn main() {
    // `cargo bench` passes --bench; a filter argument (as `cargo test --benches` may) is
    // ignored: there is one measurement.
    accelviz_app::background::set_background(true);
    let ctx = egui::Context::default();
    let mut app = AccelvizApp::new();
    app.selected = app
        .titles()
        .iter()
        .position(|title| title.contains("Middle, median or SAH"))
        .expect("lesson 7");
    frame(&ctx, &mut app);
    let limit = Duration::from_secs(120);
    assert!(app.generate_scene(GeneratorEntry {
        layout: LayoutEntry::Uniform,
        count: SHAPES,
        seed: 1,
    }));
    report(
        &format!("generate {SHAPES} shapes (kD-trees)"),
        &frames_until_built(&ctx, &mut app, limit),
    );
    for family in ["bvh", "kd", "bvh"] {
        app.lesson_mut()
            .expect("the lesson")
            .restore("family", family)
            .expect("a family");
        report(
            &format!("switch to {family}"),
            &frames_until_built(&ctx, &mut app, limit),
        );
    }
}
