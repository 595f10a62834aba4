//! The trade lab's measurement in the app: the core's [`Lab`] (every structure, every switch,
//! interleaved rounds, each ray's outcome) run off the UI's frame loop, on a worker thread on
//! the desktop and in a Web Worker in the browser (`web/worker.js`, which sends the rows back
//! as bytes), with its progress and a cancel between any two of its tasks. Timed between the
//! page's frames, on the thread that draws (in software, a frame can take a quarter of a
//! second), the rounds spread by ±50 to 460 % and the verdict changed from run to run; only
//! where no Web Worker starts does the page measure a slice a frame. What it measures is what
//! `accelviz-cli tradeoff` measures.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use accelviz_core::break_even::BreakEven;
use accelviz_core::params::BuildParams;
use accelviz_core::trade::{TradeRow, contenders};
use accelviz_core::trade_lab::Lab;
use accelviz_core::{Query, Ray, Structure};
use accelviz_scene::rays::RayKind;
use glam::DVec3;
use web_time::Instant;

/// What a measurement is of.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeKey {
    /// The mesh's revision (a new mesh is a new measurement).
    pub mesh_revision: u64,
    /// The rays' kind.
    pub ray_kind: RayKind,
    /// About how many rays.
    pub ray_count: usize,
    /// Their seed.
    pub seed: u64,
    /// Timed rounds.
    pub rounds: usize,
}

/// A finished measurement.
#[derive(Clone, Debug)]
pub struct TradeResult {
    /// What was measured.
    pub key: TradeKey,
    /// The mesh measured (a "show me" fires its ray at this mesh, whatever is on screen).
    pub mesh: Arc<accelviz_scene::Mesh>,
    /// The mesh's name.
    pub mesh_name: String,
    /// Its triangle count.
    pub triangles: usize,
    /// The rays traced (each row traced all of them).
    pub rays: usize,
    /// The query.
    pub query: Query,
    /// The build parameters (the SAH's constants for the measured cost).
    pub params: BuildParams,
    /// Every row, structure by structure, each in the switches' order.
    pub rows: Vec<TradeRow>,
    /// The break-even of the rows with the base switches: which is fastest for how many
    /// rays, as far as the rounds' spread tells.
    pub break_even: BreakEven,
    /// Each of its contenders' row in `rows`.
    pub contender_rows: Vec<usize>,
    /// How long the whole measurement took, milliseconds.
    pub millis: f64,
    /// Where it was measured: off the UI's frame loop ("on a worker thread", "in a Web
    /// Worker"), or not ("between the page's frames" where no Web Worker started, "on the UI
    /// thread" in tests).
    pub place: &'static str,
}

/// Where a lab measured, as [`TradeResult::place`] says it.
const ON_A_WORKER_THREAD: &str = "on a worker thread";
#[cfg(target_arch = "wasm32")]
const IN_A_WEB_WORKER: &str = "in a Web Worker";
const ON_THE_UI_THREAD: &str = if cfg!(target_arch = "wasm32") {
    "between the page's frames"
} else {
    "on the UI thread"
};

thread_local! {
    /// Whether measurements this thread starts time every timed task as one millisecond
    /// (snapshot tests: what is drawn must not change from run to run), not by the clock.
    static STEADY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Makes the measurements the calling thread starts from now on time every timed task alike
/// (on: [`accelviz_core::trade::MIN_SAMPLE_MS`] each), or by the clock (off, the default).
/// For snapshot tests only: every row then builds and traces alike.
pub fn set_steady_clock(on: bool) {
    STEADY.set(on);
}

/// A clock that reads the time since `start` or, steady, moves a whole sample's time a read
/// ([`accelviz_core::trade::MIN_SAMPLE_MS`]: each timed task then runs once).
fn clock(steady: bool, start: Instant) -> impl Fn() -> f64 {
    let reads = std::cell::Cell::new(0u64);
    move || {
        if steady {
            reads.set(reads.get() + 1);
            reads.get() as f64 * accelviz_core::trade::MIN_SAMPLE_MS
        } else {
            start.elapsed().as_secs_f64() * 1e3
        }
    }
}

impl TradeResult {
    /// The result with `rows` instead (their break-even made again from their own figures).
    pub fn with_rows(mut self, rows: Vec<TradeRow>) -> Self {
        let (contenders, contender_rows) = contenders(&rows);
        self.break_even = BreakEven::of(contenders, self.key.rounds);
        self.contender_rows = contender_rows;
        self.rows = rows;
        self
    }

    /// What `source`'s finished `lab` measured at `place`.
    fn of(source: &Source, lab: &Lab, place: &'static str) -> Option<Self> {
        Some(Self::of_rows(source, lab.ray_count(), lab.rows()?, place))
    }

    /// `rows`, measured for `source` over `rays` rays with [`measurement_params`] at `place`.
    fn of_rows(source: &Source, rays: usize, rows: Vec<TradeRow>, place: &'static str) -> Self {
        let millis = if source.steady {
            0.0
        } else {
            source.started.elapsed().as_secs_f64() * 1e3
        };
        let measured = Self {
            key: source.key.clone(),
            mesh: source.mesh.clone(),
            mesh_name: source.mesh_name.clone(),
            triangles: source.triangles,
            rays,
            query: source.query,
            params: measurement_params(),
            rows: Vec::new(),
            break_even: BreakEven::of(Vec::new(), source.key.rounds),
            contender_rows: Vec::new(),
            millis,
            place,
        };
        measured.with_rows(rows)
    }
}

/// What every measurement builds with: the defaults, within the lessons' kD budget.
pub fn measurement_params() -> BuildParams {
    BuildParams {
        kd_budget: crate::stage::KD_BUDGET,
        ..BuildParams::default()
    }
}

/// The structures every measurement compares.
fn measured_structures() -> Vec<Structure> {
    Structure::compared()
}

/// How far a measurement is.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TradeProgress {
    /// Tasks done.
    pub done: usize,
    /// Tasks in all.
    pub total: usize,
    /// What the task under way does.
    pub doing: String,
    /// Milliseconds the tasks done took.
    pub spent_ms: f64,
    /// About how many are left ([`accelviz_core::trade_lab::Lab::time`]), once known.
    pub left_ms: Option<f64>,
}

impl TradeProgress {
    /// Done as a share, 0 to 1: of the time, once there is an estimate of what is left (a
    /// kD-tree's build takes a hundred BVH builds, and a bar by tasks sat at 8 % for three
    /// minutes of a nine-minute measurement); of the tasks until then.
    pub fn fraction(&self) -> f32 {
        match self.left_ms {
            Some(left) if self.spent_ms + left > 0.0 => {
                (self.spent_ms / (self.spent_ms + left)) as f32
            }
            _ => self.done as f32 / self.total.max(1) as f32,
        }
    }

    /// The time left in words: `about 2 min left`, or that it is not known yet.
    pub fn left_text(&self) -> String {
        match self.left_ms {
            Some(left) => format!("about {} left", duration_text(left)),
            None => "the time left is known once each kind of task has run".to_owned(),
        }
    }

    /// The progress after `lab`'s tasks done so far.
    fn of(lab: &Lab) -> Self {
        let (done, total) = lab.progress();
        let (spent_ms, left_ms) = lab.time();
        Self {
            done,
            total,
            doing: lab.doing(),
            spent_ms,
            left_ms,
        }
    }
}

/// A duration of `millis` as a person says it: `40 s`, `3 min`, `1 h 5 min`.
pub fn duration_text(millis: f64) -> String {
    let seconds = (millis / 1e3).max(0.0);
    if seconds < 90.0 {
        format!("{} s", seconds.ceil().max(1.0))
    } else if seconds < 3600.0 {
        format!("{} min", (seconds / 60.0).round())
    } else {
        let minutes = (seconds / 60.0).round() as u64;
        format!("{} h {} min", minutes / 60, minutes % 60)
    }
}

/// What the worker and the UI share.
struct Shared {
    cancelled: AtomicBool,
    progress: Mutex<TradeProgress>,
    result: Mutex<Option<TradeResult>>,
}

/// What a job is being made of, and by whom.
#[derive(Clone)]
struct Source {
    key: TradeKey,
    mesh: Arc<accelviz_scene::Mesh>,
    mesh_name: String,
    triangles: usize,
    query: Query,
    started: Instant,
    steady: bool,
}

/// A lab the UI thread steps a slice a frame (the browser without a Web Worker; tests run it
/// to the end at once).
type OnUiThread = Arc<Mutex<Option<(Lab, Source)>>>;

/// A measurement under way, or done.
pub struct TradeJob {
    shared: Arc<Shared>,
    /// The lab stepped on the UI thread, if it is not measured aside.
    on_ui_thread: OnUiThread,
    /// The browser's Web Worker measuring (dropped, it stops).
    #[cfg(target_arch = "wasm32")]
    _web_worker: Option<super::worker::Spawned>,
    key: TradeKey,
    /// See [`set_steady_clock`].
    steady: bool,
}

/// How long the browser measures in one frame when it cannot measure aside: long enough to
/// get on, short enough that the page answers (a timed task runs whole, so one frame may take
/// longer).
const BROWSER_SLICE_MS: f64 = 40.0;

impl TradeJob {
    /// Starts measuring every structure of [`Structure::compared`] over `mesh` (named
    /// `mesh_name`) with `rays`: on a worker thread when `threads > 0`; in the browser in a
    /// Web Worker, or a slice a frame ([`advance`](Self::advance)) if none starts; in tests at
    /// once.
    pub fn start(
        key: TradeKey,
        (mesh, mesh_name): (Arc<accelviz_scene::Mesh>, String),
        rays: &[Ray<DVec3>],
        query: Query,
        threads: usize,
    ) -> Self {
        let triangles = &mesh.triangles[..];
        let source = Source {
            key: key.clone(),
            mesh: mesh.clone(),
            mesh_name,
            triangles: triangles.len(),
            query,
            started: Instant::now(),
            steady: STEADY.get(),
        };
        let steady = source.steady;
        let shared = Arc::new(Shared {
            cancelled: AtomicBool::new(false),
            progress: Mutex::new(TradeProgress {
                done: 0,
                total: 1,
                doing: "starting".to_owned(),
                spent_ms: 0.0,
                left_ms: None,
            }),
            result: Mutex::new(None),
        });
        let on_ui_thread: OnUiThread = Arc::new(Mutex::new(None));
        #[cfg(target_arch = "wasm32")]
        {
            let started = web_worker::start(&shared, &on_ui_thread, &source, triangles, rays);
            match started {
                Ok(worker) => {
                    return Self {
                        shared,
                        on_ui_thread,
                        _web_worker: Some(worker),
                        key,
                        steady,
                    };
                }
                Err(problem) => {
                    log::warn!("accelviz: the trade lab measures on the page: {problem}");
                }
            }
        }
        let lab = new_lab(triangles, rays, query, key.rounds);
        publish(&shared, &lab);
        if threads == 0 {
            if let Ok(mut slot) = on_ui_thread.lock() {
                *slot = Some((lab, source));
            }
        } else {
            let worker = shared.clone();
            std::thread::spawn(move || {
                let mut lab = lab;
                let now = clock(steady, Instant::now());
                while !worker.cancelled.load(Ordering::Acquire) && lab.step(&now) {
                    publish(&worker, &lab);
                }
                publish(&worker, &lab);
                finish(&worker, &lab, &source, ON_A_WORKER_THREAD);
            });
        }
        Self {
            shared,
            on_ui_thread,
            #[cfg(target_arch = "wasm32")]
            _web_worker: None,
            key,
            steady,
        }
    }

    /// What the job measures.
    pub fn key(&self) -> &TradeKey {
        &self.key
    }

    /// On the UI thread: in the browser, measures for a slice of the frame; in tests (native,
    /// no workers), to the end, so a test sees the result. With a worker: nothing.
    pub fn advance(&self) {
        let Ok(mut guard) = self.on_ui_thread.lock() else {
            return;
        };
        let Some((lab, source)) = &mut *guard else {
            return;
        };
        if lab.done() || self.shared.cancelled.load(Ordering::Acquire) {
            return;
        }
        let slice = Instant::now();
        let now = clock(self.steady, slice);
        while lab.step(&now) {
            if cfg!(target_arch = "wasm32")
                && slice.elapsed().as_secs_f64() * 1e3 > BROWSER_SLICE_MS
            {
                break;
            }
        }
        publish(&self.shared, lab);
        if lab.done() {
            finish(&self.shared, lab, source, ON_THE_UI_THREAD);
        }
    }

    /// How far it is.
    pub fn progress(&self) -> TradeProgress {
        self.shared
            .progress
            .lock()
            .map(|progress| progress.clone())
            .unwrap_or_default()
    }

    /// The result, once, when it is done.
    pub fn take_result(&self) -> Option<TradeResult> {
        self.shared.result.lock().ok()?.take()
    }

    /// Stops after the task under way; no result comes.
    pub fn cancel(&self) {
        self.shared.cancelled.store(true, Ordering::Release);
    }
}

impl Drop for TradeJob {
    fn drop(&mut self) {
        self.cancel();
    }
}

fn publish(shared: &Shared, lab: &Lab) {
    if let Ok(mut progress) = shared.progress.lock() {
        *progress = TradeProgress::of(lab);
    }
}

fn finish(shared: &Shared, lab: &Lab, source: &Source, place: &'static str) {
    if shared.cancelled.load(Ordering::Acquire) {
        return;
    }
    let result = TradeResult::of(source, lab, place);
    if let Ok(mut slot) = shared.result.lock() {
        *slot = result;
    }
}

/// The lab of a measurement.
fn new_lab(triangles: &[[[f64; 3]; 3]], rays: &[Ray<DVec3>], query: Query, rounds: usize) -> Lab {
    Lab::new(
        triangles,
        rays,
        measured_structures(),
        query,
        measurement_params(),
        rounds,
    )
}

/// Rows a Web Worker sent back ([`TradeRow::rows_from_bytes`]), or why they are not rows.
pub fn unpack_rows(bytes: &[u8]) -> Result<Vec<TradeRow>, String> {
    TradeRow::rows_from_bytes(bytes).map_err(|error| format!("the trade lab's rows: {error}"))
}

/// A ray as eight numbers: origin, direction, `t_min`, `t_max`.
#[cfg(any(target_arch = "wasm32", test))]
fn flat_ray(ray: &Ray<DVec3>) -> [f64; 8] {
    let [ox, oy, oz] = ray.origin.to_array();
    let [dx, dy, dz] = ray.direction.to_array();
    [ox, oy, oz, dx, dy, dz, ray.t_min, ray.t_max]
}

/// A ray from [`flat_ray`]'s numbers (as measured: not checked again).
fn ray_of(values: &[f64; 8]) -> Ray<DVec3> {
    Ray {
        origin: DVec3::new(values[0], values[1], values[2]),
        direction: DVec3::new(values[3], values[4], values[5]),
        t_min: values[6],
        t_max: values[7],
    }
}

/// What a Web Worker runs (`web/worker.js`, exported from `main.rs`).
pub mod work {
    use super::{Instant, TradeProgress, TradeRow, clock, new_lab, ray_of};
    use crate::mesh::packed::triangles_of;

    /// Measures `triangles` (nine numbers each) with `rays` (eight numbers each: origin,
    /// direction, `t_min`, `t_max`) for `query` (`closest` or `any`) over `rounds` rounds,
    /// telling `progress` (tasks done and in all, the task next, the time spent and left)
    /// after each task; the rows
    /// as bytes ([`TradeRow::rows_to_bytes`]).
    pub fn measure(
        triangles: &[f64],
        rays: &[f64],
        query: &str,
        rounds: usize,
        progress: &dyn Fn(&TradeProgress),
    ) -> Result<Vec<u8>, String> {
        let query = accelviz_core::Query::parse(query).map_err(|error| error.to_string())?;
        if !rays.len().is_multiple_of(8) {
            return Err("rays come as eight numbers each".to_owned());
        }
        let rays: Vec<_> = rays
            .chunks_exact(8)
            .map(|values| ray_of(values.try_into().unwrap_or(&[0.0; 8])))
            .collect();
        let mut lab = new_lab(&triangles_of(triangles), &rays, query, rounds);
        let now = clock(false, Instant::now());
        let report = |lab: &accelviz_core::trade_lab::Lab| progress(&TradeProgress::of(lab));
        report(&lab);
        while lab.step(&now) {
            report(&lab);
        }
        report(&lab);
        lab.rows()
            .map(|rows| TradeRow::rows_to_bytes(&rows))
            .ok_or_else(|| "the measurement ended without its rows".to_owned())
    }
}

/// The browser's measurement in a Web Worker.
#[cfg(target_arch = "wasm32")]
mod web_worker {
    use std::sync::Arc;
    use std::sync::atomic::Ordering;

    use accelviz_core::Ray;
    use glam::DVec3;

    use super::super::packed::flat_triangles;
    use super::super::worker::{Spawned, field};
    use super::{
        OnUiThread, Shared, Source, TradeProgress, TradeResult, flat_ray, new_lab, unpack_rows,
    };

    /// Starts measuring `triangles` with `rays` for `source` in a Web Worker of its own: its
    /// progress into `shared`, then its result. If the worker fails on the way, the lab goes
    /// to `on_ui_thread`, measured a slice a frame.
    pub(super) fn start(
        shared: &Arc<Shared>,
        on_ui_thread: &OnUiThread,
        source: &Source,
        triangles: &[[[f64; 3]; 3]],
        rays: &[Ray<DVec3>],
    ) -> Result<Spawned, String> {
        let flat_rays: Vec<f64> = rays.iter().flat_map(flat_ray).collect();
        let (kept_triangles, kept_rays) = (triangles.to_vec(), rays.to_vec());
        let ray_count = rays.len();
        let fallback = {
            let on_ui_thread = on_ui_thread.clone();
            let source = source.clone();
            move |problem: String| {
                log::error!(
                    "accelviz: the trade lab's worker failed ({problem}); measuring on the page"
                );
                let lab = new_lab(&kept_triangles, &kept_rays, source.query, source.key.rounds);
                if let Ok(mut slot) = on_ui_thread.lock() {
                    *slot = Some((lab, source));
                }
            }
        };
        let fallback = std::rc::Rc::new(std::cell::RefCell::new(Some(fallback)));
        let fail = {
            let fallback = fallback.clone();
            move |problem: String| {
                if let Some(fallback) = fallback.borrow_mut().take() {
                    fallback(problem);
                }
            }
        };
        let fail_on_error = fail.clone();
        let (query, rounds) = (source.query, source.key.rounds);
        let (heard, source) = (shared.clone(), source.clone());
        let spawned = Spawned::new(
            move |data| {
                if heard.cancelled.load(Ordering::Acquire) {
                    return;
                }
                if let Some(done) = field(&data, "tasks").and_then(|value| value.as_f64()) {
                    let total = field(&data, "of").and_then(|value| value.as_f64());
                    let doing = field(&data, "doing").and_then(|value| value.as_string());
                    let number = |name| field(&data, name).and_then(|value| value.as_f64());
                    if let Ok(mut progress) = heard.progress.lock() {
                        *progress = TradeProgress {
                            done: done as usize,
                            total: total.unwrap_or(done) as usize,
                            doing: doing.unwrap_or_default(),
                            spent_ms: number("spent").unwrap_or(0.0),
                            left_ms: number("left").filter(|left| left.is_finite()),
                        };
                    }
                } else if let Some(bytes) = field(&data, "done") {
                    match unpack_rows(&js_sys::Uint8Array::new(&bytes).to_vec()) {
                        Ok(rows) => {
                            let result = TradeResult::of_rows(
                                &source,
                                ray_count,
                                rows,
                                super::IN_A_WEB_WORKER,
                            );
                            if let Ok(mut slot) = heard.result.lock() {
                                *slot = Some(result);
                            }
                        }
                        Err(problem) => fail(problem),
                    }
                } else {
                    let problem = field(&data, "problem").and_then(|value| value.as_string());
                    fail(problem.unwrap_or_else(|| "the worker sent nothing".to_owned()));
                }
            },
            fail_on_error,
        )?;
        let triangles = js_sys::Float64Array::from(flat_triangles(triangles));
        let rays = js_sys::Float64Array::from(&flat_rays[..]);
        let buffers = [triangles.buffer().into(), rays.buffer().into()];
        spawned.post(
            &[
                ("job", "trade".into()),
                ("triangles", triangles.into()),
                ("rays", rays.into()),
                ("query", query.name().into()),
                ("rounds", (rounds as f64).into()),
            ],
            &buffers,
        )?;
        Ok(spawned)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::packed::flat_triangles;

    /// A row with its timings set to nothing, so that two measurements compare.
    fn untimed(row: &TradeRow) -> TradeRow {
        TradeRow {
            build_ms: 0.0,
            build_spread_percent: 0.0,
            build_range_ms: (0.0, 0.0),
            mrays_per_s: 0.0,
            trace_spread_percent: 0.0,
            ms_per_ray_range: (0.0, 0.0),
            ..row.clone()
        }
    }

    #[test]
    fn a_web_workers_rows_come_back_as_the_labs() {
        let mesh = accelviz_scene::builtin::icosphere(1);
        let rays: Vec<Ray<DVec3>> = RayKind::Aimed
            .rays(&mesh, 300, 1, None)
            .expect("rays")
            .iter()
            .map(|spec| spec.to_ray().expect("a ray"))
            .collect();
        let flat_rays: Vec<f64> = rays.iter().flat_map(flat_ray).collect();
        let heard = std::cell::RefCell::new(Vec::new());
        let bytes = work::measure(
            flat_triangles(&mesh.triangles),
            &flat_rays,
            "closest",
            1,
            &|progress: &TradeProgress| {
                heard
                    .borrow_mut()
                    .push((progress.done, progress.total, progress.left_ms))
            },
        )
        .expect("measures");
        let from_worker = unpack_rows(&bytes).expect("unpacks");
        // The lab on the page: the same rows but for their timings.
        let mut lab = new_lab(&mesh.triangles, &rays, Query::Closest, 1);
        lab.finish(&clock(true, Instant::now()));
        let on_page = lab.rows().expect("rows");
        assert_eq!(
            from_worker.iter().map(untimed).collect::<Vec<_>>(),
            on_page.iter().map(untimed).collect::<Vec<_>>()
        );
        assert!(from_worker.iter().all(|row| row.mrays_per_s > 0.0));
        // Progress: every task, in order, to the end.
        let heard = heard.into_inner();
        assert!(
            heard.windows(2).all(|pair| pair[0].0 <= pair[1].0),
            "{heard:?}"
        );
        assert_eq!(
            heard
                .last()
                .map(|(done, total, left)| (done == total, *left)),
            Some((true, Some(0.0)))
        );
        // Packed and unpacked, every field comes back; cut short or padded, an error.
        assert_eq!(
            unpack_rows(&TradeRow::rows_to_bytes(&on_page)),
            Ok(on_page.clone())
        );
        for cut in [0, 7, 8, 20, bytes.len() / 2, bytes.len() - 1] {
            assert!(unpack_rows(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        let mut padded = bytes.clone();
        padded.push(0);
        assert!(unpack_rows(&padded).is_err());
        // Bad input: an error naming it.
        assert!(work::measure(&[], &flat_rays, "nearest", 1, &|_| {}).is_err());
        assert!(work::measure(&[], &[1.0; 7], "any", 1, &|_| {}).is_err());
    }
}
