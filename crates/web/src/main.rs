//! The browser app's entry: the page's start, and the functions `web/worker.js` (Web Workers
//! reading and building meshes, measuring the trade lab, tracing heat maps) and
//! `web/bench.mjs` call. Everything else is the app's library (`accelviz-app`).
//!
//! A package of its own for the build's sake: the `web` profile (`Cargo.toml`) compiles the
//! app small and the core fast, and the whole-program optimisation (LTO) runs at the
//! optimisation level of the crate that is linked, this one (3). Linked from the app's own
//! binary, it ran at the app's `"z"`, which does not vectorise: the core's builds ran 1.5×
//! and its traversal about 1.2× slower. Code compiled small keeps its size through it.
//! Natively this binary does nothing (`scripts/build-web` builds it).

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    eprintln!("accelviz-web is the browser app's entry: build it with scripts/build-web");
}

/// Gives the 3D views eframe's GPU (there is none if eframe fell back to another renderer).
#[cfg(target_arch = "wasm32")]
fn install_gpu(creation: &eframe::CreationContext<'_>) {
    if let Some(render_state) = &creation.wgpu_render_state {
        accelviz_app::view3d::Gpu::install(&creation.egui_ctx, render_state.clone());
    }
}

#[cfg(target_arch = "wasm32")]
fn main() {
    use wasm_bindgen::JsCast;

    // In a Web Worker (`web/worker.js`, which reads and builds large meshes aside) there is
    // no page: the worker calls the exports below.
    if web_sys::window().is_none() {
        return;
    }
    eframe::WebLogger::init(log::LevelFilter::Info).ok();
    let document = web_sys::window().and_then(|window| window.document());
    let canvas = document
        .as_ref()
        .and_then(|document| document.get_element_by_id("accelviz_canvas"))
        .and_then(|element| element.dyn_into::<web_sys::HtmlCanvasElement>().ok());
    let Some(canvas) = canvas else {
        show_start_failure("the page has no <canvas id=\"accelviz_canvas\">");
        return;
    };
    wasm_bindgen_futures::spawn_local(async move {
        let started = eframe::WebRunner::new()
            .start(
                canvas,
                eframe::WebOptions::default(),
                Box::new(|creation| {
                    creation
                        .egui_ctx
                        .set_fonts(accelviz_app::fonts::web_fonts());
                    install_gpu(creation);
                    let mut app = accelviz_app::AccelvizApp::new();
                    // A shared link: the view its fragment holds (or, if it holds none that
                    // can be read, the first lesson and a message saying why).
                    if let Some(fragment) = accelviz_app::files::page_fragment() {
                        let _ = app.open_state(&fragment);
                    }
                    Ok(Box::new(app))
                }),
            )
            .await;
        match started {
            Ok(()) => {
                // The page's loading note goes once the app draws.
                if let Some(loading) = web_sys::window()
                    .and_then(|window| window.document())
                    .and_then(|document| document.get_element_by_id("loading"))
                {
                    loading.remove();
                }
                log::info!("accelviz: started");
            }
            Err(error) => show_start_failure(&format!("{error:?}")),
        }
    });
}

/// Replaces the loading note with a readable reason the app could not start.
#[cfg(target_arch = "wasm32")]
fn show_start_failure(reason: &str) {
    log::error!("accelviz could not start: {reason}");
    if let Some(loading) = web_sys::window()
        .and_then(|window| window.document())
        .and_then(|document| document.get_element_by_id("loading"))
    {
        loading.set_inner_html(&format!(
            "<p><strong>accelviz could not start.</strong></p><p>{}</p><p>It needs a browser with WebGL2 or WebGPU.</p>",
            reason.replace('<', "&lt;")
        ));
        let _ = loading.set_attribute("class", "failed");
    }
}

/// For `web/worker.js`: reads OBJ `bytes` named `name`, calling `progress` with the per mille
/// read; the triangles' corners, nine numbers a triangle.
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen]
pub fn read_obj_aside(
    name: &str,
    bytes: &[u8],
    progress: &js_sys::Function,
) -> Result<Vec<f64>, String> {
    accelviz_app::mesh::work::read_obj(name, bytes, &|permille| {
        let _ = progress.call1(&wasm_bindgen::JsValue::NULL, &permille.into());
    })
}

/// For `web/worker.js`: builds the structure named `structure` over `triangles` (nine
/// numbers each); the tree packed as bytes.
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen]
pub fn build_tree_aside(triangles: &[f64], structure: &str) -> Result<Vec<u8>, String> {
    accelviz_app::mesh::work::build(triangles, structure)
}

/// For `web/worker.js`: the trade lab's measurement of `triangles` (nine numbers each) with
/// `rays` (eight numbers each) for `query` (`closest` or `any`) over `rounds` rounds, calling
/// `progress` with (tasks done, tasks in all, the task next) after each task; the rows packed.
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen]
pub fn measure_trade_aside(
    triangles: &[f64],
    rays: &[f64],
    query: &str,
    rounds: u32,
    progress: &js_sys::Function,
) -> Result<Vec<u8>, String> {
    accelviz_app::mesh::trade::work::measure(triangles, rays, query, rounds as usize, &|told| {
        // Tasks done, tasks in all, the task next, milliseconds spent and left (NaN while
        // unknown).
        let arguments = js_sys::Array::of5(
            &(told.done as f64).into(),
            &(told.total as f64).into(),
            &told.doing.as_str().into(),
            &told.spent_ms.into(),
            &told.left_ms.unwrap_or(f64::NAN).into(),
        );
        let _ = progress.apply(&wasm_bindgen::JsValue::NULL, &arguments);
    })
}

/// For `web/worker.js`: a heat map's tree, taken in once (packed, over its triangles, nine
/// numbers each), then traced a band at a time for any camera (see
/// `accelviz_app::mesh::heat::work`).
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen]
pub struct HeatTracer(accelviz_app::mesh::heat::work::Tracer);

#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen]
impl HeatTracer {
    /// Takes in the packed `tree` over `triangles`.
    #[wasm_bindgen::prelude::wasm_bindgen(constructor)]
    pub fn new(tree: &[u8], triangles: &[f64]) -> Result<HeatTracer, String> {
        accelviz_app::mesh::heat::work::Tracer::new(tree, triangles).map(HeatTracer)
    }

    /// How many bands the image `key` (numbers) has.
    pub fn band_count(key: &[f64]) -> Result<u32, String> {
        accelviz_app::mesh::heat::work::Tracer::band_count(key).map(|count| count as u32)
    }

    /// Band `band` of the image `key`: its pixels' costs, both orders.
    pub fn trace_band(&self, key: &[f64], band: u32) -> Result<Vec<u32>, String> {
        self.0.trace_band(key, band as usize)
    }
}

/// For `web/bench.mjs`: a structure built over triangles, tracing rays as the app does
/// (see `accelviz_app::web_bench`).
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen]
pub struct BenchTracer(accelviz_app::web_bench::Tracer);

#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen]
impl BenchTracer {
    /// Builds `structure` (e.g. `bvh8:sah-binned`) over `triangles`, nine numbers each.
    #[wasm_bindgen::prelude::wasm_bindgen(constructor)]
    pub fn new(triangles: &[f64], structure: &str) -> Result<BenchTracer, String> {
        accelviz_app::web_bench::Tracer::new(triangles, structure).map(BenchTracer)
    }

    /// The build's milliseconds.
    pub fn build_millis(&self) -> f64 {
        self.0.build_millis()
    }

    /// Traces `rays` (six numbers each), writing hit distances (+inf for a miss); the hits.
    pub fn trace(&mut self, rays: &[f32], distances: &mut [f32]) -> Result<u32, String> {
        self.0.trace(rays, distances)
    }
}

/// For `web/bench.mjs`: the rays `accelviz-cli bench` traces for these triangles, six
/// numbers each: `count` random rays from `seed`, or one per pixel of `camera` (`WxH`).
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen]
pub fn bench_rays(
    triangles: &[f64],
    camera: Option<String>,
    count: usize,
    seed: u64,
) -> Result<Vec<f32>, String> {
    accelviz_app::web_bench::bench_rays(triangles, camera.as_deref(), count, seed)
}
