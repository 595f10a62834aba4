//! The `accelviz` binary: the desktop app. The browser app's entry is `crates/web`.

// A frame of a large scene allocates and frees megabytes of meshes. glibc's allocator returns
// them to the system or keeps them depending on what the process freed before (its dynamic
// mmap and trim thresholds), so the same frame cost 4 ms in one build and 9 ms, with 1,900 page
// faults a frame, in another (`benches/frame.rs`, 10k shapes). mimalloc keeps the cost
// steady, as rerun's viewer does.
#[cfg(not(target_arch = "wasm32"))]
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    let logger =
        env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).build();
    let level = logger.filter();
    accelviz_app::files::install_logger(Some(Box::new(logger)), level);
    // A window needs a display; without one, say so in a line, and where to go instead.
    let on_unix_desktop = cfg!(all(unix, not(target_os = "macos")));
    let has_display = ["DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"]
        .iter()
        .any(|name| std::env::var_os(name).is_some_and(|value| !value.is_empty()));
    if on_unix_desktop && !has_display {
        eprintln!("{NO_DISPLAY}");
        return std::process::ExitCode::from(1);
    }
    // Big builds run on worker threads, so the window keeps drawing.
    accelviz_app::background::set_background(true);
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("accelviz")
            .with_inner_size([1400.0, 860.0])
            .with_min_inner_size([900.0, 560.0]),
        ..Default::default()
    };
    // Lesson files are read from ACCELVIZ_ASSETS, or ./assets when run from the repository,
    // so edits to them show at the next start; the embedded copies serve everywhere else.
    let assets = std::env::var_os("ACCELVIZ_ASSETS")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::path::PathBuf::from("assets"));
    // `accelviz STATE` (a shared view's text or link) or `accelviz FILE` (a file holding one).
    let shared = std::env::args().nth(1).map(|argument| {
        let path = std::path::Path::new(&argument);
        if path.is_file() {
            std::fs::read_to_string(path).unwrap_or_default()
        } else {
            argument
        }
    });
    let started = eframe::run_native(
        "accelviz",
        options,
        Box::new(move |creation| {
            install_gpu(creation);
            let mut app = accelviz_app::AccelvizApp::with_assets(&assets);
            if let Some(shared) = &shared {
                let _ = app.open_state(shared);
            }
            Ok(Box::new(app))
        }),
    );
    match started {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("accelviz: the window could not open: {error}. {ALTERNATIVES}");
            std::process::ExitCode::from(1)
        }
    }
}

/// Gives the 3D views eframe's GPU (there is none if eframe fell back to another renderer).
#[cfg(not(target_arch = "wasm32"))]
fn install_gpu(creation: &eframe::CreationContext<'_>) {
    if let Some(render_state) = &creation.wgpu_render_state {
        accelviz_app::view3d::Gpu::install(&creation.egui_ctx, render_state.clone());
    }
}

/// Where to go without a window.
#[cfg(not(target_arch = "wasm32"))]
const ALTERNATIVES: &str = "The same lessons run in a browser (scripts/build-web, then serve web/), and accelviz-cli measures without a display.";

/// What the app says when started without a display.
#[cfg(not(target_arch = "wasm32"))]
const NO_DISPLAY: &str = "accelviz needs a display (X11 or Wayland) and found none (DISPLAY and WAYLAND_DISPLAY are not set). The same lessons run in a browser (scripts/build-web, then serve web/), and accelviz-cli measures without a display.";

/// Built for wasm32 (as `cargo clippy --target wasm32-unknown-unknown` does), this binary is
/// empty: the browser app is `crates/web`.
#[cfg(target_arch = "wasm32")]
fn main() {}
