//! Heat maps in the app: every pixel of the view's camera traced by the core's traversal with
//! its counting observer, near first and in file order, a band of rows at a time, one ray at
//! a time or in packets of 8×8 pixels (the core's packet traversal). On the
//! desktop the bands are shared by worker threads (both cores); in the browser, which has
//! none, a few bands are traced each frame. Either way the maps fill in band by band, the
//! view shows them as they grow, and the UI never waits.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use accelviz_core::camera::Camera;
use accelviz_core::heatmap::{HeatMap, PixelCost, trace_rows, trace_rows_in_packets};
use accelviz_core::{NoObserver, Order, Query, TraceOptions, TraversalStacks};
use accelviz_scene::rays::{RayKind, pixel_secondary_rays};
use web_time::Instant;

use super::tree::MeshTree;

/// Rows traced as one piece of work (whole packets of rows).
const BAND_ROWS: usize = 8;
/// The side of a packet's square of pixels: 64 rays, the most a packet holds.
pub const PACKET_TILE: usize = 8;
const _: () = assert!(
    BAND_ROWS.is_multiple_of(PACKET_TILE),
    "bands hold whole packets"
);
/// How long the browser traces in one frame at least, and at most: a slice as long as the
/// rest of the frame took, within these, so tracing gets about half the page's time whether
/// the page draws in 5 ms (a GPU) or in 300 ms (a software renderer, where 25 ms slices made
/// 576×528 maps take 10 s), and the page still answers within a tenth of a second.
const BROWSER_SLICE_MS: std::ops::RangeInclusive<f64> = 25.0..=100.0;

/// The two traversal orders a heat map is made for, in the order of [`HeatMaps::maps`].
pub const ORDERS: [Order; 2] = [Order::NearFirst, Order::FileOrder];

/// What a job fills: one map per order, and how far it got.
struct Shared {
    maps: Mutex<[HeatMap; 2]>,
    next_band: AtomicUsize,
    bands_done: AtomicUsize,
    cancelled: AtomicBool,
    started: Instant,
    finished_ms: Mutex<Option<f64>>,
}

/// What a job is for: a tree (its `Derived` generation), a camera and an image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatKey {
    /// The tree's generation.
    pub tree: u64,
    /// The camera.
    pub camera: Camera,
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// Rays are traced in packets of `tile × tile` pixels (1: one at a time).
    pub tile: usize,
    /// Whose cost a pixel shows: its camera ray's, or (shadow, AO, bounce) the secondary
    /// rays' from its camera ray's hit, traced one at a time.
    pub ray_kind: RayKind,
}

/// Heat maps being made or made, for one key.
pub struct HeatJob {
    key: HeatKey,
    tree: Arc<MeshTree>,
    shared: Arc<Shared>,
    /// The browser traces on the UI thread, in slices; the desktop on workers.
    on_ui_thread: bool,
    /// When the last slice ended (the browser): the time since is what the page took to draw.
    last_slice: Mutex<Option<Instant>>,
}

/// A snapshot of a job's maps.
pub struct HeatMaps {
    /// Near first, then file order.
    pub maps: [HeatMap; 2],
    /// Rows done out of the image's height.
    pub progress: f64,
    /// How long the whole job took, once it is done.
    pub millis: Option<f64>,
}

impl HeatJob {
    /// Starts tracing every pixel of `key`'s image through `tree`: on `threads` worker
    /// threads, or (`threads == 0`) a slice a frame on the UI thread.
    pub fn start(key: HeatKey, tree: Arc<MeshTree>, threads: usize) -> Self {
        let shared = Arc::new(Shared {
            maps: Mutex::new([
                HeatMap::new(key.width, key.height),
                HeatMap::new(key.width, key.height),
            ]),
            next_band: AtomicUsize::new(0),
            bands_done: AtomicUsize::new(0),
            cancelled: AtomicBool::new(false),
            started: Instant::now(),
            finished_ms: Mutex::new(None),
        });
        let job = Self {
            key,
            tree,
            shared,
            on_ui_thread: threads == 0,
            last_slice: Mutex::new(None),
        };
        if threads > 0 {
            let (shared, tree) = (job.shared.clone(), job.tree.clone());
            std::thread::spawn(move || {
                std::thread::scope(|scope| {
                    for _ in 0..threads {
                        scope.spawn(|| while trace_next_band(&shared, &tree, &key) {});
                    }
                });
            });
        }
        job
    }

    /// What the job is for.
    pub fn key(&self) -> &HeatKey {
        &self.key
    }

    /// Without workers: in the browser, traces bands for a slice of the frame; in tests
    /// (native, workers off), all of them, so a test sees whole maps. With workers: nothing.
    pub fn advance(&self) {
        if !self.on_ui_thread {
            return;
        }
        if cfg!(not(target_arch = "wasm32")) {
            self.finish();
            return;
        }
        let slice = Instant::now();
        let Ok(mut last_slice) = self.last_slice.lock() else {
            return;
        };
        let drawing_ms =
            last_slice.map_or(0.0, |ended| slice.duration_since(ended).as_secs_f64() * 1e3);
        let budget_ms = drawing_ms.clamp(*BROWSER_SLICE_MS.start(), *BROWSER_SLICE_MS.end());
        while trace_next_band(&self.shared, &self.tree, &self.key) {
            if slice.elapsed().as_secs_f64() * 1e3 > budget_ms {
                break;
            }
        }
        *last_slice = Some(Instant::now());
    }

    /// Traces every band left, here and now (tests; a caller that must have the maps).
    pub fn finish(&self) {
        while trace_next_band(&self.shared, &self.tree, &self.key) {}
    }

    /// How many bands are traced: changes whenever the maps do.
    pub fn bands_done(&self) -> usize {
        self.shared.bands_done.load(Ordering::Acquire)
    }

    /// Whether every band is traced.
    pub fn done(&self) -> bool {
        self.shared
            .finished_ms
            .lock()
            .map(|finished| finished.is_some())
            .unwrap_or(true)
    }

    /// The maps as far as they are traced.
    pub fn snapshot(&self) -> HeatMaps {
        let bands = self.key.height.div_ceil(BAND_ROWS).max(1);
        let done = self.shared.bands_done.load(Ordering::Acquire).min(bands);
        let maps = self
            .shared
            .maps
            .lock()
            .map(|maps| maps.clone())
            .unwrap_or_default();
        HeatMaps {
            maps,
            progress: done as f64 / bands as f64,
            millis: self.shared.finished_ms.lock().ok().and_then(|ms| *ms),
        }
    }

    /// Stops the workers after the bands they are tracing.
    pub fn cancel(&self) {
        self.shared.cancelled.store(true, Ordering::Release);
    }
}

impl Drop for HeatJob {
    fn drop(&mut self) {
        self.cancel();
    }
}

/// Traces the next band not yet taken into both maps; false when there is none left.
fn trace_next_band(shared: &Shared, tree: &MeshTree, key: &HeatKey) -> bool {
    if shared.cancelled.load(Ordering::Acquire) {
        return false;
    }
    let band = shared.next_band.fetch_add(1, Ordering::AcqRel);
    let bands = key.height.div_ceil(BAND_ROWS);
    if band >= bands {
        return false;
    }
    let rows = band * BAND_ROWS..((band + 1) * BAND_ROWS).min(key.height);
    let mut stacks = TraversalStacks::default();
    let ordered = tree.ordered();
    let bounds = tree.mesh.bounds();
    let traced = ORDERS.map(|order| {
        let options = TraceOptions {
            order,
            query: key.ray_kind.default_query(),
            ..TraceOptions::default()
        };
        let mut out = vec![PixelCost::default(); rows.len() * key.width];
        let built = &tree.build.built.tree;
        if key.ray_kind == RayKind::Camera {
            trace_rows_in_packets(
                &key.camera,
                key.width,
                key.height,
                rows.start,
                &mut out,
                key.tile,
                |rays, counters| {
                    let mut hits = [None; accelviz_core::bvh::MAX_PACKET];
                    let hits = &mut hits[..rays.len()];
                    built.trace_packet(ordered, rays, &options, &mut stacks, counters, hits);
                },
            );
        } else {
            // The camera ray finds its hit (uncounted); the secondary rays from
            // there are counted at its pixel: the CLI's `heatmap --ray-kind`, ray for ray.
            let primary = TraceOptions {
                query: Query::Closest,
                ..options
            };
            trace_rows(
                &key.camera,
                key.width,
                key.height,
                rows.start,
                &mut out,
                |ray, counters| {
                    let Some(hit) =
                        built.trace(ordered, ray, &primary, &mut stacks, &mut NoObserver)
                    else {
                        return;
                    };
                    for secondary in
                        pixel_secondary_rays(key.ray_kind, &tree.mesh, &bounds, ray, hit)
                    {
                        built.trace(ordered, &secondary, &options, &mut stacks, counters);
                    }
                },
            );
        }
        out
    });
    if let Ok(mut maps) = shared.maps.lock() {
        for (map, out) in maps.iter_mut().zip(&traced) {
            map.pixels[rows.start * key.width..rows.end * key.width].copy_from_slice(out);
        }
    }
    let done = shared.bands_done.fetch_add(1, Ordering::AcqRel) + 1;
    if done == bands
        && let Ok(mut finished) = shared.finished_ms.lock()
    {
        *finished = Some(shared.started.elapsed().as_secs_f64() * 1e3);
    }
    true
}
