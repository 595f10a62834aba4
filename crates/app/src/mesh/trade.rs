//! The trade lab's measurement in the app: the core's [`Lab`] (every structure, every switch,
//! interleaved rounds, each ray's outcome) run on a worker thread on the desktop, or a slice
//! a frame on the UI thread in the browser, with its progress and a cancel between any two
//! of its tasks. What it measures is what `accelviz-cli tradeoff` measures.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use accelviz_core::break_even::BreakEven;
use accelviz_core::params::BuildParams;
use accelviz_core::trade::{Lab, TradeRow, contenders};
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
}

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
        self.break_even = BreakEven::of(contenders);
        self.contender_rows = contender_rows;
        self.rows = rows;
        self
    }

    /// What `source`'s finished `lab` measured.
    fn of(source: &Source, lab: &Lab) -> Option<Self> {
        let millis = if source.steady {
            0.0
        } else {
            source.started.elapsed().as_secs_f64() * 1e3
        };
        let measured = Self {
            key: source.key.clone(),
            mesh_name: source.mesh_name.clone(),
            triangles: source.triangles,
            rays: lab.ray_count(),
            query: source.query,
            params: *lab.params(),
            rows: Vec::new(),
            break_even: BreakEven::of(Vec::new()),
            contender_rows: Vec::new(),
            millis,
        };
        Some(measured.with_rows(lab.rows()?))
    }
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
}

impl TradeProgress {
    /// Done as a share, 0 to 1.
    pub fn fraction(&self) -> f32 {
        self.done as f32 / self.total.max(1) as f32
    }
}

/// What the worker and the UI share.
struct Shared {
    cancelled: AtomicBool,
    progress: Mutex<TradeProgress>,
    result: Mutex<Option<TradeResult>>,
}

/// What a job is being made of, and by whom.
struct Source {
    key: TradeKey,
    mesh_name: String,
    triangles: usize,
    query: Query,
    started: Instant,
    steady: bool,
}

/// A measurement under way, or done.
pub struct TradeJob {
    shared: Arc<Shared>,
    /// The browser's lab, stepped on the UI thread (the desktop's is on its worker).
    on_ui_thread: Option<Mutex<(Lab, Source)>>,
    key: TradeKey,
    /// See [`set_steady_clock`].
    steady: bool,
}

/// How long the browser measures in one frame: long enough to get on, short enough that the
/// page answers (a timed task runs whole, so one frame may take longer).
const BROWSER_SLICE_MS: f64 = 40.0;

impl TradeJob {
    /// Starts measuring every structure of `structures` over `triangles` with `rays`: on a
    /// worker thread when `threads > 0`, else a slice a frame ([`advance`](Self::advance)).
    #[allow(clippy::too_many_arguments)]
    pub fn start(
        key: TradeKey,
        mesh_name: String,
        triangles: &[[[f64; 3]; 3]],
        rays: &[Ray<DVec3>],
        structures: Vec<Structure>,
        query: Query,
        params: BuildParams,
        threads: usize,
    ) -> Self {
        let lab = Lab::new(triangles, rays, structures, query, params, key.rounds);
        let (done, total) = lab.progress();
        let shared = Arc::new(Shared {
            cancelled: AtomicBool::new(false),
            progress: Mutex::new(TradeProgress {
                done,
                total,
                doing: lab.doing(),
            }),
            result: Mutex::new(None),
        });
        let source = Source {
            key: key.clone(),
            mesh_name,
            triangles: triangles.len(),
            query,
            started: Instant::now(),
            steady: STEADY.get(),
        };
        let steady = source.steady;
        if threads == 0 {
            return Self {
                shared,
                on_ui_thread: Some(Mutex::new((lab, source))),
                key,
                steady,
            };
        }
        let worker = shared.clone();
        std::thread::spawn(move || {
            let mut lab = lab;
            let now = clock(steady, Instant::now());
            while !worker.cancelled.load(Ordering::Acquire) && lab.step(&now) {
                publish(&worker, &lab);
            }
            publish(&worker, &lab);
            finish(&worker, &lab, &source);
        });
        Self {
            shared,
            on_ui_thread: None,
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
        let Some(lab) = &self.on_ui_thread else {
            return;
        };
        let Ok(mut guard) = lab.lock() else {
            return;
        };
        let (lab, source) = &mut *guard;
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
            finish(&self.shared, lab, source);
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
    let (done, total) = lab.progress();
    if let Ok(mut progress) = shared.progress.lock() {
        *progress = TradeProgress {
            done,
            total,
            doing: lab.doing(),
        };
    }
}

fn finish(shared: &Shared, lab: &Lab, source: &Source) {
    if shared.cancelled.load(Ordering::Acquire) {
        return;
    }
    let result = TradeResult::of(source, lab);
    if let Ok(mut slot) = shared.result.lock() {
        *slot = result;
    }
}

/// A query's name, as the CLI's `--query` spells it.
pub fn query_name(query: Query) -> &'static str {
    match query {
        Query::Any => "any",
        Query::Closest | Query::FirstInCell => "closest",
    }
}
