//! The speed/accuracy trade, measured: every structure of the catalogue built in f32 and f64,
//! every switch (near first or file order, f32 or f64, the fast or the watertight triangle
//! test) traced over the same rays, each figure the median of interleaved rounds with the
//! range it moved in, and every ray's answer judged by [`crate::outcome`]'s reference.
//!
//! The CLI's `tradeoff` and the app's trade lab measure with this module, so the lab's table
//! is the CLI's. It keeps no clock of its own (the core runs in browsers, where
//! `std::time::Instant` does not): the caller passes one. [`crate::trade_lab::Lab`] is the measurement as a
//! list of small tasks, so that a worker thread can run it to the end, or a browser a slice
//! a frame, with its progress shown and a cancel between any two tasks.

use glam::DVec3;

use crate::break_even::Contender;
use crate::math::Vector3;
use crate::observer::{Counters, NoObserver};
use crate::outcome::{Outcome, OutcomeCounts, Reference, ReferenceScene};
use crate::params::BuildParams;
use crate::primitive::{HitTest, LeafOrdered, TriangleSet};
use crate::quality::Footprint;
use crate::query::{Order, Query, TraceOptions};
use crate::ray::Ray;
use crate::stats::TreeStats;
use crate::structure::{Structure, TraversalStacks, Tree};

/// The precision a row's tree, triangles and rays are held in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Precision {
    /// Single precision.
    F32,
    /// Double precision.
    F64,
}

impl Precision {
    /// `"f32"` or `"f64"`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
}

/// One setting of the switches a row is traced with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Switches {
    /// Near first or file order.
    pub order: Order,
    /// The tree's and the rays' precision.
    pub precision: Precision,
    /// The watertight triangle test with the conservative box test (Woop et al. 2013, Ize
    /// 2013), or Möller–Trumbore with the plain slab test.
    pub watertight: bool,
}

impl Switches {
    /// What every other setting is compared with: near first, f32, the fast test.
    pub const BASE: Switches = Switches {
        order: Order::NearFirst,
        precision: Precision::F32,
        watertight: false,
    };

    /// The settings measured, each one switch away from [`BASE`](Self::BASE) but the last
    /// (f64 and watertight).
    pub const ALL: [Switches; 5] = [
        Self::BASE,
        Switches {
            order: Order::FileOrder,
            ..Self::BASE
        },
        Switches {
            watertight: true,
            ..Self::BASE
        },
        Switches {
            precision: Precision::F64,
            ..Self::BASE
        },
        Switches {
            precision: Precision::F64,
            watertight: true,
            ..Self::BASE
        },
    ];

    /// `"fast"` or `"watertight"`.
    pub fn test_name(self) -> &'static str {
        if self.watertight {
            HitTest::Watertight.name()
        } else {
            HitTest::Fast.name()
        }
    }

    /// The trace options of this setting for `query`.
    pub fn options(self, query: Query) -> TraceOptions {
        let options = TraceOptions {
            order: self.order,
            query,
            ..TraceOptions::default()
        }
        .with_robust(self.watertight);
        debug_assert_eq!(options.hit_test == HitTest::Watertight, self.watertight);
        options
    }
}

/// The times of one configuration, one per round, in milliseconds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    millis: Vec<f64>,
}

impl Samples {
    /// Adds one round's time.
    pub fn push(&mut self, millis: f64) {
        self.millis.push(millis);
    }

    /// How many rounds are in.
    pub fn len(&self) -> usize {
        self.millis.len()
    }

    /// Whether no round is in.
    pub fn is_empty(&self) -> bool {
        self.millis.is_empty()
    }

    /// The median (the mean of the middle two for an even count; 0 without samples).
    pub fn median(&self) -> f64 {
        let mut sorted = self.millis.clone();
        sorted.sort_by(f64::total_cmp);
        match sorted.len() {
            0 => 0.0,
            n if n % 2 == 1 => sorted[n / 2],
            n => (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0,
        }
    }

    /// The fastest round.
    pub fn min(&self) -> f64 {
        self.millis.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// The slowest round.
    pub fn max(&self) -> f64 {
        self.millis.iter().copied().fold(0.0, f64::max)
    }

    /// Half the range as a share of the median, in percent: `±spread` around the median
    /// covers every round. Two figures whose ranges overlap are not shown to differ.
    pub fn spread_percent(&self) -> f64 {
        let median = self.median();
        if median > 0.0 {
            (self.max() - self.min()) / 2.0 / median * 100.0
        } else {
            0.0
        }
    }
}

/// The shortest a timed sample is, milliseconds. Browsers give the time to a tenth of a
/// millisecond and jitter it, and a shared machine's scheduler moves by as much: a build or a
/// trace of a few thousand rays, timed once, took 1 to 2 ms and its rounds spread by ±100 % and
/// more in the browser's trade lab. So a configuration runs again until this much time has
/// passed, and its sample is the time per run.
pub const MIN_SAMPLE_MS: f64 = 10.0;

/// Runs `run` once, and again until [`MIN_SAMPLE_MS`] have passed by `now_ms`; the time per
/// run, milliseconds.
pub fn timed(now_ms: &dyn Fn() -> f64, mut run: impl FnMut()) -> f64 {
    let start = now_ms();
    let mut runs = 0u32;
    loop {
        run();
        runs += 1;
        let elapsed = now_ms() - start;
        if elapsed >= MIN_SAMPLE_MS {
            return elapsed / f64::from(runs);
        }
    }
}

/// The `step`-th configuration run in `round` of `count`: odd rounds go through the
/// configurations backwards, so that none is always first after a pause.
pub fn interleaved_index(round: usize, step: usize, count: usize) -> usize {
    if round % 2 == 1 {
        count - 1 - step
    } else {
        step
    }
}

/// Runs `rounds` rounds; in each, runs every configuration `0..count` (in
/// [`interleaved_index`]'s order) with `run(index)` and times it with `now_ms` (milliseconds
/// from any fixed start; [`timed`]: `run` may be called more than once a sample), telling
/// `after` (samples done, samples in all) after each sample, outside its timing. Returns
/// each configuration's samples.
pub fn interleaved(
    rounds: usize,
    count: usize,
    now_ms: impl Fn() -> f64,
    mut run: impl FnMut(usize),
    mut after: impl FnMut(usize, usize),
) -> Vec<Samples> {
    let rounds = rounds.max(1);
    let mut samples = vec![Samples::default(); count];
    for round in 0..rounds {
        for step in 0..count {
            let index = interleaved_index(round, step, count);
            samples[index].push(timed(&now_ms, || run(index)));
            after(round * count + step + 1, rounds * count);
        }
    }
    samples
}

/// A mesh and its rays in one precision, and the reference that judges their answers.
pub struct TradeScene<V: Vector3> {
    /// The triangles as this precision holds them.
    pub triangles: TriangleSet<V>,
    /// The rays as this precision rounds them.
    pub rays: Vec<Ray<V>>,
    /// The reference over exactly these triangles.
    pub reference: ReferenceScene,
}

/// What an untimed pass of a row's rays found.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// The tree's statistics.
    pub stats: TreeStats,
    /// The work counted over every ray.
    pub counters: Counters,
    /// Every ray's outcome.
    pub outcomes: OutcomeCounts,
    /// The first ray of each outcome (in [`Outcome::ALL`]'s order), as the row's precision
    /// rounded it, widened exactly to f64.
    pub examples: [Option<Ray<DVec3>>; 6],
}

impl<V: Vector3> TradeScene<V> {
    /// The mesh (corners in f64) and the rays rounded to `V`'s precision.
    pub fn new(triangles: &[[[f64; 3]; 3]], rays: &[Ray<DVec3>]) -> Self {
        let triangles = TriangleSet::from_f64(triangles);
        let reference = ReferenceScene::new(&triangles);
        Self {
            triangles,
            rays: rays.iter().map(|ray| ray.cast::<V>()).collect(),
            reference,
        }
    }

    /// The reference's answers for the rays in `range`.
    pub fn references(&self, range: std::ops::Range<usize>) -> Vec<Option<Reference>> {
        self.rays[range]
            .iter()
            .map(|ray| self.reference.reference(ray))
            .collect()
    }

    /// Untimed: `tree`'s statistics, the work counted, and every ray's outcome against
    /// `references` (one per ray), with the first ray of each.
    pub fn evaluate(
        &self,
        tree: &Tree<V>,
        ordered: &LeafOrdered<TriangleSet<V>>,
        options: &TraceOptions,
        references: &[Option<Reference>],
        params: &BuildParams,
    ) -> Evaluation {
        let stats = tree.stats(&params.cost);
        let mut stacks = TraversalStacks::default();
        let mut counters = Counters::default();
        let mut outcomes = OutcomeCounts::default();
        let mut examples: [Option<Ray<DVec3>>; 6] = Default::default();
        for (ray, reference) in self.rays.iter().zip(references) {
            let got = tree
                .trace(ordered, ray, options, &mut stacks, &mut counters)
                .map(|hit| hit.primitive);
            let outcome = self
                .reference
                .classify(ray, reference.as_ref(), got, options.query);
            outcomes.add(outcome);
            examples[outcome.index()].get_or_insert_with(|| ray.cast::<DVec3>());
        }
        Evaluation {
            stats,
            counters,
            outcomes,
            examples,
        }
    }

    /// Traces every ray with the observer that does nothing (what is timed); the hits found.
    #[inline(never)]
    pub fn count_hits(
        &self,
        tree: &Tree<V>,
        ordered: &LeafOrdered<TriangleSet<V>>,
        options: &TraceOptions,
    ) -> usize {
        let mut stacks = TraversalStacks::default();
        self.rays
            .iter()
            .filter(|ray| {
                tree.trace(ordered, ray, options, &mut stacks, &mut NoObserver)
                    .is_some()
            })
            .count()
    }
}

/// One row of the trade: a structure traced with one setting of the switches.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeRow {
    /// The structure.
    pub structure: Structure,
    /// The switches.
    pub switches: Switches,
    /// The build's median time (in the row's precision), milliseconds.
    pub build_ms: f64,
    /// The build times' spread, percent of their median.
    pub build_spread_percent: f64,
    /// The fastest and the slowest build, milliseconds.
    pub build_range_ms: (f64, f64),
    /// The tree's SAH cost.
    pub sah_cost: f64,
    /// End-point overlap (BVHs only, [`crate::quality::epo`]).
    pub epo: Option<f64>,
    /// Bytes of the nodes and primitive lists traversal reads.
    pub bytes: usize,
    /// Nodes entered per ray.
    pub nodes_per_ray: f64,
    /// Primitives tested per ray.
    pub primitives_per_ray: f64,
    /// Millions of rays a second (one thread, the median round).
    pub mrays_per_s: f64,
    /// Half the range of the trace times, percent of their median.
    pub trace_spread_percent: f64,
    /// One ray's traversal in the fastest and the slowest round, milliseconds.
    pub ms_per_ray_range: (f64, f64),
    /// Every ray's outcome.
    pub outcomes: OutcomeCounts,
    /// The first ray of each outcome, as in [`Evaluation::examples`].
    pub examples: [Option<Ray<DVec3>>; 6],
}

/// What a tree is besides its speed, shared by every switch setting of it: its end-point
/// overlap (BVHs only, [`crate::quality::epo`]: a kD-tree's cells do not overlap) and its
/// memory.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeQuality {
    /// End-point overlap.
    pub epo: Option<f64>,
    /// Memory and fill rate.
    pub footprint: Footprint,
}

impl TreeQuality {
    /// Measures `tree` over `triangles` (in their own numbering).
    pub fn of<V: Vector3>(tree: &Tree<V>, triangles: &[[V; 3]], params: &BuildParams) -> Self {
        let epo = matches!(tree, Tree::Bvh(_) | Tree::Bvh4(_) | Tree::Bvh8(_))
            .then(|| crate::quality::epo(tree, triangles, &params.cost));
        Self {
            epo,
            footprint: Footprint::of(tree),
        }
    }
}

impl TradeRow {
    /// The row of `structure` traced with `switches` over `rays` rays: its builds' and
    /// traces' rounds, its untimed pass, and its tree's quality.
    pub fn new(
        (structure, switches): (Structure, Switches),
        (builds, traces): (&Samples, &Samples),
        evaluation: Evaluation,
        quality: TreeQuality,
        rays: usize,
    ) -> Self {
        let count = rays.max(1) as f64;
        Self {
            structure,
            switches,
            build_ms: builds.median(),
            build_spread_percent: builds.spread_percent(),
            build_range_ms: (builds.min(), builds.max()),
            sah_cost: evaluation.stats.sah_cost,
            epo: quality.epo,
            bytes: quality.footprint.bytes,
            nodes_per_ray: evaluation.counters.nodes_visited as f64 / count,
            primitives_per_ray: evaluation.counters.primitive_tests as f64 / count,
            mrays_per_s: count / (traces.median().max(1e-9) * 1e3),
            trace_spread_percent: traces.spread_percent(),
            ms_per_ray_range: (traces.min() / count, traces.max() / count),
            outcomes: evaluation.outcomes,
            examples: evaluation.examples,
        }
    }

    /// What a ray cost, in the SAH's units: `C_trav·nodes + C_isect·primitives`.
    pub fn measured_cost(&self, params: &BuildParams) -> f64 {
        params
            .cost
            .per_ray(self.nodes_per_ray, self.primitives_per_ray)
    }

    /// One ray's traversal, milliseconds.
    pub fn ms_per_ray(&self) -> f64 {
        // Mrays/s is rays per microsecond: a thousand of them a millisecond.
        1.0 / (self.mrays_per_s * 1e3)
    }

    /// The row as a contender of the break-even ([`crate::break_even`]), with its rounds'
    /// ranges.
    pub fn contender(&self) -> Contender {
        Contender {
            name: self.structure.name(),
            build_ms: self.build_ms,
            ms_per_ray: self.ms_per_ray(),
            build_range_ms: self.build_range_ms,
            ms_per_ray_range: self.ms_per_ray_range,
        }
    }

    /// The row's first example ray of `outcome`.
    pub fn example(&self, outcome: Outcome) -> Option<&Ray<DVec3>> {
        self.examples[outcome.index()].as_ref()
    }
}

/// The contenders of the break-even: the rows with the base switches, and their indices in
/// `rows`.
pub fn contenders(rows: &[TradeRow]) -> (Vec<Contender>, Vec<usize>) {
    rows.iter()
        .enumerate()
        .filter(|(_, row)| row.switches == Switches::BASE)
        .map(|(index, row)| (row.contender(), index))
        .unzip()
}

/// The rows as CSV: a header line, then one line a row with every digit (`tradeoff.csv`, and
/// the trade lab's export).
pub fn csv(rows: &[TradeRow], params: &BuildParams) -> String {
    let mut out = String::from(
        "structure,order,precision,triangle_test,build_ms,sah_cost,epo,bytes,measured_cost,nodes_per_ray,prims_per_ray,mrays_per_s,trace_spread_percent",
    );
    for outcome in Outcome::ALL {
        out.push_str(&format!(",{}_per_million", outcome.name()));
    }
    out.push('\n');
    for row in rows {
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            row.structure.name(),
            row.switches.order.name(),
            row.switches.precision.name(),
            row.switches.test_name(),
            row.build_ms,
            row.sah_cost,
            row.epo.map_or(String::new(), |epo| epo.to_string()),
            row.bytes,
            row.measured_cost(params),
            row.nodes_per_ray,
            row.primitives_per_ray,
            row.mrays_per_s,
            row.trace_spread_percent,
        ));
        for outcome in Outcome::ALL {
            out.push_str(&format!(",{}", row.outcomes.per_million(outcome)));
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_ranges_and_the_order_of_rounds() {
        let samples = Samples {
            millis: vec![12.0, 10.0, 30.0, 11.0],
        };
        assert_eq!(samples.median(), 11.5);
        assert_eq!((samples.min(), samples.max()), (10.0, 30.0));
        assert!((samples.spread_percent() - 10.0 / 11.5 * 100.0).abs() < 1e-9);
        let mut order = Vec::new();
        let mut told = Vec::new();
        let clock = std::cell::Cell::new(0.0);
        // A clock that moves a whole sample's time a read: each configuration runs once.
        let timed = interleaved(
            3,
            3,
            || {
                clock.set(clock.get() + MIN_SAMPLE_MS);
                clock.get()
            },
            |index| order.push(index),
            |done, total| told.push((done, total)),
        );
        assert_eq!(order, [0, 1, 2, 2, 1, 0, 0, 1, 2]);
        assert_eq!(told, (1..=9).map(|done| (done, 9)).collect::<Vec<_>>());
        assert!(
            timed
                .iter()
                .all(|samples| samples.millis == [MIN_SAMPLE_MS; 3])
        );
    }

    #[test]
    fn the_switches_are_one_away_from_the_base_but_the_last() {
        let away = |s: &Switches| {
            usize::from(s.order != Switches::BASE.order)
                + usize::from(s.precision != Switches::BASE.precision)
                + usize::from(s.watertight != Switches::BASE.watertight)
        };
        let distances: Vec<usize> = Switches::ALL.iter().map(away).collect();
        assert_eq!(distances, [0, 1, 1, 1, 2]);
        assert_eq!(
            Switches::ALL[2].options(Query::Closest).hit_test,
            HitTest::Watertight
        );
    }
}
