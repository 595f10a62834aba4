//! Heat maps in the app: every pixel of the view's camera traced by the core's traversal with
//! its counting observer, near first and in file order, a band of rows at a time, one ray at
//! a time or in packets of 8×8 pixels (the core's packet traversal). On the desktop the bands
//! are shared by worker threads (both cores); in the browser, whose page has one thread, by
//! a pool of Web Workers running the same WASM module on the packed tree (the bunny's
//! 512×512 maps in 0.3-0.5 s in headless Chromium, against 1.3-1.7 s traced on the page a
//! slice a frame, which the page still falls back to). Every way calls [`trace_band`]; the
//! maps fill in band by band, the view shows them as they grow, and the UI never waits.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use accelviz_core::camera::{Camera, Projection};
use accelviz_core::heatmap::{HeatMap, PixelCost, trace_rows, trace_rows_in_packets};
use accelviz_core::{Order, Query, TraceOptions, TraversalStacks, compiled};
use accelviz_scene::rays::{RayKind, pixel_secondary_rays};
use glam::DVec3;
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
    /// A Web Worker failed: the page traces the maps itself.
    workers_failed: AtomicBool,
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
    /// Bands are traced on the UI thread, in slices (the browser without Web Workers, tests);
    /// else by worker threads (the desktop) or Web Workers (the browser).
    on_ui_thread: AtomicBool,
    /// When the last slice ended (the browser): the time since is what the page took to draw.
    last_slice: Mutex<Option<Instant>>,
    /// The Web Workers' job (the browser); dropped, they stop tracing it.
    web_workers: Mutex<Vec<Box<dyn std::any::Any>>>,
    /// Where the bands are traced, in words (for the log).
    traced_where: Mutex<String>,
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
    /// threads, or (`threads == 0`) in the browser's pool of Web Workers (a core each but
    /// one, holding the tree packed), else a slice a frame on the UI thread.
    pub fn start(key: HeatKey, tree: Arc<MeshTree>, threads: usize) -> Self {
        let shared = Arc::new(Shared {
            maps: Mutex::new([
                HeatMap::new(key.width, key.height),
                HeatMap::new(key.width, key.height),
            ]),
            next_band: AtomicUsize::new(0),
            bands_done: AtomicUsize::new(0),
            cancelled: AtomicBool::new(false),
            workers_failed: AtomicBool::new(false),
            started: Instant::now(),
            finished_ms: Mutex::new(None),
        });
        let (web_workers, worker_count) = if threads == 0 {
            start_web_workers(&key, &tree, &shared)
        } else {
            (Vec::new(), 0)
        };
        let job = Self {
            key,
            tree,
            shared,
            on_ui_thread: AtomicBool::new(threads == 0 && web_workers.is_empty()),
            last_slice: Mutex::new(None),
            traced_where: Mutex::new(match (threads, worker_count) {
                (0, 0) => "on the page".to_owned(),
                (0, 1) => "in a Web Worker".to_owned(),
                (0, workers) => format!("in {workers} Web Workers"),
                (1, _) => "on a worker thread".to_owned(),
                (threads, _) => format!("on {threads} worker threads"),
            }),
            web_workers: Mutex::new(web_workers),
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
    /// (native, workers off), all of them, so a test sees whole maps. With workers: nothing,
    /// unless a Web Worker failed: then the page takes the job over.
    pub fn advance(&self) {
        if self.shared.workers_failed.load(Ordering::Acquire)
            && !self.on_ui_thread.load(Ordering::Acquire)
        {
            // Whatever the workers traced is drawn; the page traces every band again (and
            // what the stopped workers may still have sent is ignored).
            if let Ok(mut workers) = self.web_workers.lock() {
                workers.clear();
            }
            self.shared.next_band.store(0, Ordering::Release);
            self.shared.bands_done.store(0, Ordering::Release);
            self.on_ui_thread.store(true, Ordering::Release);
            if let Ok(mut traced_where) = self.traced_where.lock() {
                *traced_where = "on the page (its Web Workers failed)".to_owned();
            }
        }
        if !self.on_ui_thread.load(Ordering::Acquire) {
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

    /// Where the bands are traced, in words: "in a Web Worker", "on 2 worker threads", ….
    pub fn traced_where(&self) -> String {
        self.traced_where
            .lock()
            .map(|traced_where| traced_where.clone())
            .unwrap_or_default()
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

/// Has the browser's Web Workers trace `key`'s maps into `shared`: their job (dropped, they
/// stop) and how many workers; none where there are none, or they cannot start.
#[cfg(target_arch = "wasm32")]
fn start_web_workers(
    key: &HeatKey,
    tree: &Arc<MeshTree>,
    shared: &Arc<Shared>,
) -> (Vec<Box<dyn std::any::Any>>, usize) {
    match web::start_workers(key, tree, shared) {
        Ok((job, count)) => (vec![Box::new(job)], count),
        Err(problem) => {
            log::error!("accelviz: heat maps traced on the page: {problem}");
            (Vec::new(), 0)
        }
    }
}

/// Native builds have worker threads instead.
#[cfg(not(target_arch = "wasm32"))]
fn start_web_workers(
    _key: &HeatKey,
    _tree: &Arc<MeshTree>,
    _shared: &Arc<Shared>,
) -> (Vec<Box<dyn std::any::Any>>, usize) {
    (Vec::new(), 0)
}

/// Traces the next band not yet taken into both maps; false when there is none left.
fn trace_next_band(shared: &Shared, tree: &MeshTree, key: &HeatKey) -> bool {
    if shared.cancelled.load(Ordering::Acquire) {
        return false;
    }
    let band = shared.next_band.fetch_add(1, Ordering::AcqRel);
    if band >= band_count(key) {
        return false;
    }
    put_band(shared, key, band, &trace_band(tree, key, band));
    true
}

/// How many bands `key`'s image has.
fn band_count(key: &HeatKey) -> usize {
    key.height.div_ceil(BAND_ROWS)
}

/// The rows of band `band`.
fn band_rows(key: &HeatKey, band: usize) -> std::ops::Range<usize> {
    band * BAND_ROWS..((band + 1) * BAND_ROWS).min(key.height)
}

/// Puts band `band`'s pixels into both maps, and notes the time when it was the last.
fn put_band(shared: &Shared, key: &HeatKey, band: usize, traced: &[Vec<PixelCost>; 2]) {
    let rows = band_rows(key, band);
    if let Ok(mut maps) = shared.maps.lock() {
        for (map, out) in maps.iter_mut().zip(traced) {
            map.pixels[rows.start * key.width..rows.end * key.width].copy_from_slice(out);
        }
    }
    let done = shared.bands_done.fetch_add(1, Ordering::AcqRel) + 1;
    if done == band_count(key)
        && let Ok(mut finished) = shared.finished_ms.lock()
    {
        *finished = Some(shared.started.elapsed().as_secs_f64() * 1e3);
    }
}

/// Traces band `band` of `key`'s image through `tree`: its pixels' costs, near first and in
/// file order (what every way of running a job, threads, slices or Web Workers, calls).
fn trace_band(tree: &MeshTree, key: &HeatKey, band: usize) -> [Vec<PixelCost>; 2] {
    let rows = band_rows(key, band);
    let mut stacks = TraversalStacks::default();
    let ordered = tree.ordered();
    let bounds = tree.mesh.bounds();
    ORDERS.map(|order| {
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
                    compiled::trace_packet_counted(
                        built,
                        ordered,
                        rays,
                        &options,
                        &mut stacks,
                        counters,
                        hits,
                    );
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
                        compiled::trace_triangles(built, ordered, ray, &primary, &mut stacks)
                    else {
                        return;
                    };
                    for secondary in
                        pixel_secondary_rays(key.ray_kind, &tree.mesh, &bounds, ray, hit)
                    {
                        compiled::trace_triangles_counted(
                            built,
                            ordered,
                            &secondary,
                            &options,
                            &mut stacks,
                            counters,
                        );
                    }
                },
            );
        }
        out
    })
}

/// Heat maps traced in Web Workers (the browser, which gives the page one thread): a pool of
/// workers kept for the page's life, which hold the last tree they were sent, so a new camera
/// (an orbit's every frame) costs a message, not a worker's start and the tree's trip.
#[cfg(target_arch = "wasm32")]
mod web {
    use std::cell::{Cell, RefCell};
    use std::rc::Rc;
    use std::sync::atomic::Ordering;
    use std::sync::{Arc, Weak};

    use wasm_bindgen::JsValue;

    use super::{HeatKey, Shared, band_of_numbers, put_band};
    use crate::mesh::MeshTree;
    use crate::mesh::packed::{flat_triangles, pack};
    use crate::mesh::worker::{Spawned, field};

    thread_local! {
        static POOL: RefCell<Option<Pool>> = const { RefCell::new(None) };
    }

    /// The job whose bands the workers' messages are for.
    struct Sink {
        id: u64,
        key: HeatKey,
        shared: Arc<Shared>,
    }

    struct Pool {
        workers: Vec<Spawned>,
        /// The tree the workers hold.
        tree: Weak<MeshTree>,
        sink: Rc<RefCell<Option<Sink>>>,
        /// A worker failed: the pool is made again for the next job.
        broken: Rc<Cell<bool>>,
        jobs: u64,
    }

    impl Pool {
        /// A worker per core but one (at least one, at most four). One core is left to the
        /// page, which draws in software where there is no GPU (on two cores, one worker
        /// traced the bunny's maps as fast as two: they took the page's core from it).
        fn new() -> Result<Self, String> {
            let cores =
                web_sys::window().map_or(2.0, |window| window.navigator().hardware_concurrency());
            let count = (cores as usize).saturating_sub(1).clamp(1, 4);
            let sink: Rc<RefCell<Option<Sink>>> = Rc::default();
            let broken: Rc<Cell<bool>> = Rc::default();
            let workers = (0..count)
                .map(|_| {
                    let (sink, sink_on_error) = (sink.clone(), sink.clone());
                    let (broken, broken_on_error) = (broken.clone(), broken.clone());
                    Spawned::new(
                        move |data| hear(&data, &sink, &broken),
                        move |problem| {
                            log::error!("accelviz: a heat map's worker failed: {problem}");
                            broken_on_error.set(true);
                            if let Some(sink) = sink_on_error.borrow().as_ref() {
                                sink.shared.workers_failed.store(true, Ordering::Release);
                            }
                        },
                    )
                })
                .collect::<Result<_, _>>()?;
            Ok(Self {
                workers,
                tree: Weak::new(),
                sink,
                broken,
                jobs: 0,
            })
        }
    }

    /// A worker's message: a band of the job the pool traces (one it stopped is ignored), or
    /// why it could not trace it.
    fn hear(data: &JsValue, sink: &RefCell<Option<Sink>>, broken: &Cell<bool>) {
        let sink = sink.borrow();
        let Some(sink) = sink.as_ref() else {
            return;
        };
        if field(data, "id").and_then(|id| id.as_f64()) != Some(sink.id as f64)
            || sink.shared.workers_failed.load(Ordering::Acquire)
        {
            return;
        }
        let failed = if let Some(values) = field(data, "part") {
            let at = field(data, "at").and_then(|at| at.as_f64()).unwrap_or(-1.0) as usize;
            let numbers = js_sys::Uint32Array::new(&values).to_vec();
            match band_of_numbers(&sink.key, at, &numbers) {
                Ok(traced) => {
                    put_band(&sink.shared, &sink.key, at, &traced);
                    None
                }
                Err(problem) => Some(problem),
            }
        } else {
            field(data, "problem").map(|problem| problem.as_string().unwrap_or_default())
        };
        if let Some(problem) = failed {
            log::error!("accelviz: a heat map's worker: {problem}");
            broken.set(true);
            sink.shared.workers_failed.store(true, Ordering::Release);
        }
    }

    /// A job the pool traces; dropped, the workers stop tracing it (after the band each is
    /// tracing).
    pub struct PoolJob {
        id: u64,
    }

    impl Drop for PoolJob {
        fn drop(&mut self) {
            POOL.with(|pool| {
                let Ok(pool) = pool.try_borrow() else {
                    return;
                };
                let Some(pool) = pool.as_ref() else {
                    return;
                };
                let mut sink = pool.sink.borrow_mut();
                if sink.as_ref().is_some_and(|sink| sink.id == self.id) {
                    *sink = None;
                    for worker in &pool.workers {
                        let _ = worker.post(&[("job", "heat-cancel".into())], &[]);
                    }
                }
            });
        }
    }

    /// Has the pool's workers trace `key`'s bands through `tree`, each every n-th band, the
    /// bands going into `shared` as they come; sends the tree first if they hold another.
    /// The job, and how many workers trace it.
    pub fn start_workers(
        key: &HeatKey,
        tree: &Arc<MeshTree>,
        shared: &Arc<Shared>,
    ) -> Result<(PoolJob, usize), String> {
        POOL.with(|cell| {
            let mut slot = cell.borrow_mut();
            if slot.as_ref().is_some_and(|pool| pool.broken.get()) {
                *slot = None;
            }
            if slot.is_none() {
                *slot = Some(Pool::new()?);
            }
            let Some(pool) = slot.as_mut() else {
                return Err("no pool".to_owned());
            };
            if !pool
                .tree
                .upgrade()
                .is_some_and(|held| Arc::ptr_eq(&held, tree))
            {
                let packed = pack(&tree.build);
                let triangles = flat_triangles(&tree.mesh.triangles);
                for worker in &pool.workers {
                    let tree_bytes = js_sys::Uint8Array::from(&packed[..]);
                    let triangle_numbers = js_sys::Float64Array::from(triangles);
                    let transfer = [tree_bytes.buffer().into(), triangle_numbers.buffer().into()];
                    worker.post(
                        &[
                            ("job", "heat-tree".into()),
                            ("tree", tree_bytes.into()),
                            ("triangles", triangle_numbers.into()),
                        ],
                        &transfer,
                    )?;
                }
                pool.tree = Arc::downgrade(tree);
            }
            pool.jobs += 1;
            let id = pool.jobs;
            *pool.sink.borrow_mut() = Some(Sink {
                id,
                key: *key,
                shared: shared.clone(),
            });
            let numbers = js_sys::Float64Array::from(&key.to_numbers()[..]);
            let step = pool.workers.len();
            for (first, worker) in pool.workers.iter().enumerate() {
                worker.post(
                    &[
                        ("job", "heat-bands".into()),
                        ("id", JsValue::from_f64(id as f64)),
                        ("key", numbers.clone().into()),
                        ("first", (first as u32).into()),
                        ("step", (step as u32).into()),
                    ],
                    &[],
                )?;
            }
            Ok((PoolJob { id }, step))
        })
    }
}

/// How many numbers [`HeatKey::to_numbers`] makes.
const KEY_NUMBERS: usize = 15;

impl HeatKey {
    /// The key as numbers, to send to a Web Worker: the camera's eye, target and up, its
    /// projection (0 perspective, 1 orthographic) and that projection's angle or size, the
    /// image's width and height, the packet tile and the ray kind's place in
    /// [`RayKind::ALL`]. (The tree's generation stays on the page.)
    pub fn to_numbers(&self) -> Vec<f64> {
        let camera = &self.camera;
        let (projection, size) = match camera.projection {
            Projection::Perspective { fov } => (0.0, fov),
            Projection::Orthographic { half_size } => (1.0, half_size),
        };
        let kind = RayKind::ALL
            .iter()
            .position(|kind| *kind == self.ray_kind)
            .unwrap_or(0);
        [camera.eye, camera.target, camera.up]
            .iter()
            .flat_map(|point| point.to_array())
            .chain([
                projection,
                size,
                self.width as f64,
                self.height as f64,
                self.tile as f64,
                kind as f64,
            ])
            .collect()
    }

    /// The key [`HeatKey::to_numbers`] made (its tree generation 0), or what is wrong.
    pub fn from_numbers(numbers: &[f64]) -> Result<Self, String> {
        let &[
            ex,
            ey,
            ez,
            tx,
            ty,
            tz,
            ux,
            uy,
            uz,
            projection,
            size,
            width,
            height,
            tile,
            kind,
        ] = numbers
        else {
            return Err(format!(
                "a heat map's key has {KEY_NUMBERS} numbers, not {}",
                numbers.len()
            ));
        };
        let count = |value: f64, what: &str, most: f64| {
            if value.fract() == 0.0 && (1.0..=most).contains(&value) {
                Ok(value as usize)
            } else {
                Err(format!(
                    "a heat map's {what} {value} is not a count up to {most}"
                ))
            }
        };
        let projection = match projection {
            0.0 => Projection::Perspective { fov: size },
            1.0 => Projection::Orthographic { half_size: size },
            other => return Err(format!("unknown projection {other}")),
        };
        let ray_kind = *RayKind::ALL
            .get(count(kind + 1.0, "ray kind", RayKind::ALL.len() as f64)? - 1)
            .ok_or("unknown ray kind")?;
        Ok(Self {
            tree: 0,
            camera: Camera {
                eye: DVec3::new(ex, ey, ez),
                target: DVec3::new(tx, ty, tz),
                up: DVec3::new(ux, uy, uz),
                projection,
            },
            width: count(width, "width", 1e5)?,
            height: count(height, "height", 1e5)?,
            tile: count(tile, "packet tile", PACKET_TILE as f64)?,
            ray_kind,
        })
    }
}

/// A band's costs as numbers (both orders, three counts a pixel), to send back from a worker.
fn band_numbers(traced: &[Vec<PixelCost>; 2]) -> Vec<u32> {
    traced
        .iter()
        .flatten()
        .flat_map(|cost| [cost.nodes, cost.boxes, cost.prims])
        .collect()
}

/// Band `band`'s costs from [`band_numbers`], or what is wrong with them.
#[cfg(any(target_arch = "wasm32", test))]
fn band_of_numbers(
    key: &HeatKey,
    band: usize,
    numbers: &[u32],
) -> Result<[Vec<PixelCost>; 2], String> {
    let pixels = band_rows(key, band).len() * key.width;
    if band >= band_count(key) || numbers.len() != 2 * 3 * pixels {
        return Err(format!(
            "band {band} of a heat map came back with {} numbers",
            numbers.len()
        ));
    }
    let costs = |numbers: &[u32]| {
        numbers
            .chunks_exact(3)
            .map(|n| PixelCost {
                nodes: n[0],
                boxes: n[1],
                prims: n[2],
            })
            .collect()
    };
    let (near_first, file_order) = numbers.split_at(3 * pixels);
    Ok([costs(near_first), costs(file_order)])
}

/// The work a Web Worker does for a heat map, called by `web/worker.js` through `main.rs`.
pub mod work {
    use std::sync::Arc;

    use accelviz_core::TriangleSet;
    use accelviz_scene::Mesh;

    use super::{HeatKey, band_count, band_numbers, trace_band};
    use crate::mesh::MeshTree;
    use crate::mesh::packed::{triangles_of, unpack};

    /// A heat map's tree in a worker: taken in once, then traced band by band for any camera.
    pub struct Tracer {
        tree: MeshTree,
    }

    impl Tracer {
        /// The [`pack`](crate::mesh::packed::pack)ed `tree` over `triangles` (nine numbers
        /// each), or why they are not one.
        pub fn new(tree: &[u8], triangles: &[f64]) -> Result<Self, String> {
            let mesh = Mesh {
                name: String::new(),
                triangles: triangles_of(triangles),
            };
            let set = TriangleSet::from_f64(&mesh.triangles);
            let build = unpack(tree)?;
            if build.root_triangles > mesh.triangles.len() {
                return Err("a heat map's tree and triangles do not belong together".to_owned());
            }
            Ok(Self {
                tree: MeshTree::with_built(Arc::new(mesh), set, build),
            })
        }

        /// How many bands the image `key` (numbers, see [`HeatKey::to_numbers`]) has.
        pub fn band_count(key: &[f64]) -> Result<usize, String> {
            Ok(band_count(&HeatKey::from_numbers(key)?))
        }

        /// Band `band` of the image `key`: its pixels' costs as numbers, both orders.
        pub fn trace_band(&self, key: &[f64], band: usize) -> Result<Vec<u32>, String> {
            let key = HeatKey::from_numbers(key)?;
            if band >= band_count(&key) {
                return Err(format!(
                    "no band {band} in a heat map of {} rows",
                    key.height
                ));
            }
            Ok(band_numbers(&trace_band(&self.tree, &key, band)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use accelviz_core::Structure;

    /// The maps a Web Worker's bands make are the page's, pixel for pixel, whichever way the
    /// bands are shared out; and the key survives the trip as numbers.
    #[test]
    fn bands_traced_aside_make_the_same_maps() {
        let mesh = Arc::new(accelviz_scene::builtin::teapot());
        let structure = Structure::parse("bvh8:sah-binned").expect("in the catalogue");
        let tree = Arc::new(MeshTree::build(mesh.clone(), structure));
        // One tracer, as a worker holds: taken in once, traced for every key.
        let tracer = work::Tracer::new(
            &super::super::packed::pack(&tree.build),
            super::super::packed::flat_triangles(&mesh.triangles),
        )
        .expect("takes the tree in");
        // 21 rows: the last band is short.
        for (ray_kind, tile) in [(RayKind::Camera, PACKET_TILE), (RayKind::Shadow, 1)] {
            let key = HeatKey {
                tree: 0,
                camera: Camera::framing(&mesh.bounds()),
                width: 37,
                height: 21,
                tile,
                ray_kind,
            };
            assert_eq!(HeatKey::from_numbers(&key.to_numbers()), Ok(key));
            let job = HeatJob::start(key, tree.clone(), 0);
            job.finish();
            let on_page = job.snapshot();
            assert!(on_page.millis.is_some());
            assert!(on_page.maps[0].pixels.iter().any(|cost| cost.nodes > 0));
            for workers in 1..=3 {
                let mut aside = [
                    HeatMap::new(key.width, key.height),
                    HeatMap::new(key.width, key.height),
                ];
                let mut bands = Vec::new();
                let numbers = key.to_numbers();
                let count = work::Tracer::band_count(&numbers).expect("a key");
                for first in 0..workers {
                    for band in (first..count).step_by(workers) {
                        let costs = tracer.trace_band(&numbers, band).expect("traces");
                        let traced = band_of_numbers(&key, band, &costs).expect("a whole band");
                        let rows = band_rows(&key, band);
                        for (map, out) in aside.iter_mut().zip(&traced) {
                            map.pixels[rows.start * key.width..rows.end * key.width]
                                .copy_from_slice(out);
                        }
                        bands.push(band);
                    }
                }
                bands.sort_unstable();
                assert_eq!(bands, (0..band_count(&key)).collect::<Vec<_>>());
                assert_eq!(
                    aside,
                    on_page.maps,
                    "{} in {workers} workers",
                    ray_kind.name()
                );
            }
        }
    }

    /// A job whose Web Workers failed half-way is taken over by the page: whole maps, each
    /// band counted once.
    #[test]
    fn the_page_takes_over_from_failed_workers() {
        let mesh = Arc::new(accelviz_scene::builtin::teapot());
        let structure = Structure::parse("bvh:sah-binned").expect("in the catalogue");
        let tree = Arc::new(MeshTree::build(mesh.clone(), structure));
        let key = HeatKey {
            tree: 0,
            camera: Camera::framing(&mesh.bounds()),
            width: 24,
            height: 40,
            tile: 1,
            ray_kind: RayKind::Camera,
        };
        let whole = HeatJob::start(key, tree.clone(), 0);
        whole.finish();
        // As if workers had sent two of the five bands and then one had failed.
        let job = HeatJob::start(key, tree.clone(), 0);
        job.on_ui_thread.store(false, Ordering::Release);
        for band in [3, 0] {
            put_band(&job.shared, &key, band, &trace_band(&tree, &key, band));
        }
        job.advance();
        assert_eq!(job.bands_done(), 2, "workers at work: the page waits");
        job.shared.workers_failed.store(true, Ordering::Release);
        job.advance();
        assert!(job.done());
        assert_eq!(job.bands_done(), band_count(&key));
        assert_eq!(job.snapshot().maps, whole.snapshot().maps);
    }

    /// Numbers that are not a key or a band: an error, never a panic.
    #[test]
    fn bad_numbers_are_refused() {
        let key = HeatKey {
            tree: 0,
            camera: Camera::framing(&accelviz_scene::builtin::teapot().bounds()),
            width: 16,
            height: 16,
            tile: 1,
            ray_kind: RayKind::Ao,
        };
        let numbers = key.to_numbers();
        assert!(HeatKey::from_numbers(&numbers[1..]).is_err());
        for (at, bad) in [
            (9, 2.0),
            (11, 0.0),
            (12, 1.5),
            (13, 9.0),
            (14, 6.0),
            (14, -1.0),
            (11, f64::NAN),
        ] {
            let mut wrong = numbers.clone();
            wrong[at] = bad;
            assert!(
                HeatKey::from_numbers(&wrong).is_err(),
                "number {at} = {bad}"
            );
        }
        assert!(band_of_numbers(&key, 0, &[0; 5]).is_err());
        assert!(band_of_numbers(&key, 2, &vec![0; 2 * 3 * 8 * 16]).is_err());
        assert!(band_of_numbers(&key, 1, &vec![0; 2 * 3 * 8 * 16]).is_ok());
        let tree = super::super::packed::pack(
            &MeshTree::build(
                Arc::new(accelviz_scene::builtin::teapot()),
                accelviz_core::Structure::parse("bvh:sah-binned").expect("in the catalogue"),
            )
            .build,
        );
        assert!(work::Tracer::new(&tree[..10], &[]).is_err());
        assert!(work::Tracer::new(&tree, &[]).is_err());
        let triangles =
            super::super::packed::flat_triangles(&accelviz_scene::builtin::teapot().triangles)
                .to_vec();
        let tracer = work::Tracer::new(&tree, &triangles).expect("takes the tree in");
        assert_eq!(work::Tracer::band_count(&numbers), Ok(2));
        assert!(tracer.trace_band(&numbers, 1).is_ok());
        assert!(tracer.trace_band(&numbers, 2).is_err());
        assert!(tracer.trace_band(&numbers[..3], 0).is_err());
    }
}
