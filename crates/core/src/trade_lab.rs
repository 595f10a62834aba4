//! The trade lab's measurement as a list of small tasks ([`Lab`]): the references' answers,
//! then group by group of structures their builds and traces, interleaved round by round, and
//! each row's untimed pass; so that a worker thread runs it to the end, or a browser's Web
//! Worker a task at a time, with its progress, the time it has left, and a cancel between any
//! two tasks. Its figures are [`crate::trade`]'s: the CLI's `tradeoff` and the app's lesson 16
//! both run it.

use glam::{DVec3, Vec3};

use crate::math::Vector3;
use crate::outcome::Reference;
use crate::params::BuildParams;
use crate::primitive::{LeafOrdered, TriangleSet};
use crate::query::{Query, TraceOptions};
use crate::ray::Ray;
use crate::structure::{Structure, Tree};
use crate::trade::{
    Evaluation, Precision, Samples, Switches, TradeRow, TradeScene, TreeQuality, interleaved_index,
    timed,
};

/// A built tree and the triangles in its leaf order.
type Built<V> = (Tree<V>, LeafOrdered<TriangleSet<V>>);

/// One precision's side of the lab.
struct Side<V: Vector3> {
    scene: TradeScene<V>,
    references: Vec<Option<Reference>>,
    /// The first round's tree of each structure.
    trees: Vec<Option<Built<V>>>,
    /// Each tree's quality, once (every switch setting of a tree shares it).
    quality: Vec<Option<TreeQuality>>,
}

impl<V: Vector3> Side<V> {
    fn new(triangles: &[[[f64; 3]; 3]], rays: &[Ray<DVec3>], structures: usize) -> Self {
        let scene = TradeScene::new(triangles, rays);
        Self {
            references: Vec::with_capacity(scene.rays.len()),
            scene,
            trees: (0..structures).map(|_| None).collect(),
            quality: vec![None; structures],
        }
    }

    fn build(&mut self, index: usize, structure: &Structure, params: &BuildParams) {
        let tree = structure.build(&self.scene.triangles, params);
        let slot = &mut self.trees[index];
        if slot.is_none() {
            let ordered = tree.leaf_ordered(&self.scene.triangles);
            *slot = Some((tree, ordered));
        }
    }

    fn trace(&self, index: usize, options: &TraceOptions) -> usize {
        self.trees[index].as_ref().map_or(0, |(tree, ordered)| {
            self.scene.count_hits(tree, ordered, options)
        })
    }

    fn evaluate(
        &mut self,
        index: usize,
        options: &TraceOptions,
        params: &BuildParams,
    ) -> Option<(Evaluation, TreeQuality)> {
        let (tree, ordered) = self.trees[index].as_ref()?;
        let quality = *self.quality[index]
            .get_or_insert_with(|| TreeQuality::of(tree, self.scene.triangles.triangles(), params));
        let evaluation = self
            .scene
            .evaluate(tree, ordered, options, &self.references, params);
        Some((evaluation, quality))
    }
}

/// One piece of the lab's work.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Task {
    /// The reference's answers for a block of rays, in one precision.
    References(Precision, usize),
    /// One round's build of a structure (its index) in one precision (timed).
    Build(usize, Precision),
    /// One round's trace of a row (its index in the rows, structure by structure, then
    /// switches; timed).
    Trace(usize),
    /// A row's untimed pass: its counts and outcomes.
    Evaluate(usize),
    /// The trees of a structure (its index) let go, its group measured.
    Release(usize),
}

impl Task {
    /// The kind of work, for the estimate of what is left: tasks of a kind take alike.
    fn kind(self) -> usize {
        match self {
            Task::References(..) => 0,
            Task::Build(..) => 1,
            Task::Trace(..) => 2,
            Task::Evaluate(..) => 3,
            Task::Release(..) => 4,
        }
    }
}

/// Rays the reference judges in one task.
const REFERENCE_BLOCK: usize = 256;

/// The memory the lab's trees may hold at once: the structures are measured in groups whose
/// trees (both precisions) fit it, each group's let go before the next is built. All nineteen
/// structures' trees of a 269k-triangle mesh at once took 2 GB.
pub const TREES_MEMORY_BUDGET: usize = 384 << 20;

/// About what one structure's tree holds a triangle, bytes (its nodes, its references, its
/// own copy of the triangles in leaf order): measured as the mean over the catalogue on a
/// 100,000-triangle mesh, 1.24 GB for 38 trees.
const TREE_BYTES_PER_TRIANGLE: usize = 330;

/// How many structures a group holds so that its trees, in both precisions, fit
/// [`TREES_MEMORY_BUDGET`] over `triangles` triangles (at least one; all of them on a small
/// mesh, where every contender is interleaved with every other).
pub fn structures_a_group(triangles: usize, structures: usize) -> usize {
    let per_structure = 2 * TREE_BYTES_PER_TRIANGLE * triangles.max(1);
    (TREES_MEMORY_BUDGET / per_structure).clamp(1, structures.max(1))
}

/// The whole trade measured as small tasks ([`step`](Self::step)): the references' answers,
/// then, group by group of structures ([`structures_a_group`]: all of them on a mesh of a few
/// thousand triangles), every build of every round, every trace of every round (each
/// round's configurations interleaved as [`interleaved_index`] says), each row's untimed
/// pass, and the group's trees let go.
pub struct Lab {
    structures: Vec<Structure>,
    query: Query,
    params: BuildParams,
    single: Side<Vec3>,
    double: Side<DVec3>,
    tasks: Vec<Task>,
    next: usize,
    builds: Vec<Samples>,
    traces: Vec<Samples>,
    evaluations: Vec<Option<(Evaluation, TreeQuality)>>,
    /// Milliseconds spent on each task done (its wall time, every run of a timed one).
    spent: Vec<f64>,
    /// Structures a group.
    group: usize,
}

impl Lab {
    /// The measurement of every structure in `structures` with every setting of
    /// [`Switches::ALL`] over `triangles` and `rays` (given in f64: each precision rounds
    /// them), answering `query`, timed over `rounds` rounds.
    pub fn new(
        triangles: &[[[f64; 3]; 3]],
        rays: &[Ray<DVec3>],
        structures: Vec<Structure>,
        query: Query,
        params: BuildParams,
        rounds: usize,
    ) -> Self {
        let group = structures_a_group(triangles.len(), structures.len());
        Self::in_groups(triangles, rays, structures, query, params, rounds, group)
    }

    /// [`Lab::new`] with `group` structures measured together (at least one), whatever the
    /// mesh's size.
    pub fn in_groups(
        triangles: &[[[f64; 3]; 3]],
        rays: &[Ray<DVec3>],
        structures: Vec<Structure>,
        query: Query,
        params: BuildParams,
        rounds: usize,
        group: usize,
    ) -> Self {
        let rounds = rounds.max(1);
        let count = structures.len();
        let switches = Switches::ALL.len();
        let rows = count * switches;
        let group = group.clamp(1, count.max(1));
        let mut tasks = Vec::new();
        for precision in [Precision::F32, Precision::F64] {
            tasks.extend(
                (0..rays.len())
                    .step_by(REFERENCE_BLOCK)
                    .map(|start| Task::References(precision, start)),
            );
        }
        for first in (0..count).step_by(group) {
            let members = first..(first + group).min(count);
            let builds = members.len() * 2;
            for round in 0..rounds {
                for step in 0..builds {
                    let index = interleaved_index(round, step, builds);
                    let precision = [Precision::F32, Precision::F64][index % 2];
                    tasks.push(Task::Build(first + index / 2, precision));
                }
            }
            let group_rows = members.len() * switches;
            for round in 0..rounds {
                tasks.extend((0..group_rows).map(|step| {
                    Task::Trace(first * switches + interleaved_index(round, step, group_rows))
                }));
            }
            tasks.extend((first * switches..first * switches + group_rows).map(Task::Evaluate));
            tasks.extend(members.map(Task::Release));
        }
        Self {
            single: Side::new(triangles, rays, count),
            double: Side::new(triangles, rays, count),
            structures,
            query,
            params,
            tasks,
            next: 0,
            builds: vec![Samples::default(); count * 2],
            traces: vec![Samples::default(); rows],
            evaluations: vec![None; rows],
            spent: Vec::new(),
            group,
        }
    }

    /// Structures measured together, interleaved with one another ([`structures_a_group`]).
    pub fn group_size(&self) -> usize {
        self.group
    }

    /// How many trees the lab holds now, both precisions counted: a group's at most.
    pub fn trees_held(&self) -> usize {
        self.single.trees.iter().flatten().count() + self.double.trees.iter().flatten().count()
    }

    /// The structure and switches of row `row`.
    fn row_key(&self, row: usize) -> (usize, Switches) {
        let switches = Switches::ALL.len();
        (row / switches, Switches::ALL[row % switches])
    }

    /// Runs the next task, timed by `now_ms` (milliseconds from any fixed start); false once
    /// every task is done.
    pub fn step(&mut self, now_ms: &dyn Fn() -> f64) -> bool {
        let Some(&task) = self.tasks.get(self.next) else {
            return false;
        };
        self.next += 1;
        let start = now_ms();
        self.run(task, now_ms);
        self.spent.push(now_ms() - start);
        self.next < self.tasks.len()
    }

    /// Milliseconds spent so far, and about how many are left (`None` until a task of each
    /// kind still to come has run once). A task left takes what the same task took in an
    /// earlier round, else the mean of its kind so far: a kD-tree's build is a hundred times
    /// a BVH's, so the tasks done are a poor clock, and their count a poorer one.
    pub fn time(&self) -> (f64, Option<f64>) {
        let done = &self.tasks[..self.next];
        let spent: f64 = self.spent.iter().sum();
        let mut by_kind = [(0.0f64, 0usize); 5];
        for (task, millis) in done.iter().zip(&self.spent) {
            let entry = &mut by_kind[task.kind()];
            entry.0 += millis;
            entry.1 += 1;
        }
        let left = self.tasks[self.next..].iter().try_fold(0.0, |total, task| {
            let same = done
                .iter()
                .zip(&self.spent)
                .rev()
                .find(|(earlier, _)| *earlier == task)
                .map(|(_, millis)| *millis);
            let (sum, runs) = by_kind[task.kind()];
            let mean = (runs > 0).then(|| sum / runs as f64);
            same.or(mean).map(|millis| total + millis)
        });
        (spent, left)
    }

    /// Runs `task`.
    fn run(&mut self, task: Task, now_ms: &dyn Fn() -> f64) {
        match task {
            Task::References(precision, start) => {
                let end = (start + REFERENCE_BLOCK).min(self.single.scene.rays.len());
                match precision {
                    Precision::F32 => {
                        let answers = self.single.scene.references(start..end);
                        self.single.references.extend(answers);
                    }
                    Precision::F64 => {
                        let answers = self.double.scene.references(start..end);
                        self.double.references.extend(answers);
                    }
                }
            }
            Task::Build(index, precision) => {
                let structure = self.structures[index];
                let (single, double, params) = (&mut self.single, &mut self.double, &self.params);
                let millis = timed(now_ms, || match precision {
                    Precision::F32 => single.build(index, &structure, params),
                    Precision::F64 => double.build(index, &structure, params),
                });
                let slot = 2 * index + usize::from(precision == Precision::F64);
                self.builds[slot].push(millis);
            }
            Task::Trace(row) => {
                let (index, switches) = self.row_key(row);
                let options = switches.options(self.query);
                let millis = timed(now_ms, || {
                    let hits = match switches.precision {
                        Precision::F32 => self.single.trace(index, &options),
                        Precision::F64 => self.double.trace(index, &options),
                    };
                    std::hint::black_box(hits);
                });
                self.traces[row].push(millis);
            }
            Task::Evaluate(row) => {
                let (index, switches) = self.row_key(row);
                let options = switches.options(self.query);
                self.evaluations[row] = match switches.precision {
                    Precision::F32 => self.single.evaluate(index, &options, &self.params),
                    Precision::F64 => self.double.evaluate(index, &options, &self.params),
                };
            }
            Task::Release(index) => {
                self.single.trees[index] = None;
                self.double.trees[index] = None;
            }
        }
    }

    /// Runs every task left.
    pub fn finish(&mut self, now_ms: &dyn Fn() -> f64) {
        while self.step(now_ms) {}
    }

    /// Tasks done and tasks in all.
    pub fn progress(&self) -> (usize, usize) {
        (self.next, self.tasks.len())
    }

    /// Whether every task is done.
    pub fn done(&self) -> bool {
        self.next >= self.tasks.len()
    }

    /// What the current task does, in words (for a progress bar).
    pub fn doing(&self) -> String {
        match self.tasks.get(self.next) {
            None => "done".into(),
            Some(Task::References(precision, start)) => format!(
                "judging rays {start}… by the reference ({})",
                precision.name()
            ),
            Some(&Task::Build(index, precision)) => format!(
                "building {} ({})",
                self.structures[index].name(),
                precision.name()
            ),
            Some(&Task::Release(index)) => {
                format!("letting go of the {} trees", self.structures[index].name())
            }
            Some(&task @ (Task::Trace(row) | Task::Evaluate(row))) => {
                let (index, switches) = self.row_key(row);
                let what = match task {
                    Task::Trace(_) => "timing",
                    _ => "judging the answers of",
                };
                format!(
                    "{what} {} {} {} {}",
                    self.structures[index].name(),
                    switches.order.name(),
                    switches.precision.name(),
                    switches.test_name()
                )
            }
        }
    }

    /// The rays traced a row.
    pub fn ray_count(&self) -> usize {
        self.single.scene.rays.len()
    }

    /// The build parameters.
    pub fn params(&self) -> &BuildParams {
        &self.params
    }

    /// Every row, structure by structure and within one in [`Switches::ALL`]'s order, once
    /// every task is done.
    pub fn rows(&self) -> Option<Vec<TradeRow>> {
        if !self.done() {
            return None;
        }
        (0..self.traces.len())
            .map(|row| {
                let (index, switches) = self.row_key(row);
                let (evaluation, quality) = self.evaluations[row].clone()?;
                let builds =
                    &self.builds[2 * index + usize::from(switches.precision == Precision::F64)];
                Some(TradeRow::new(
                    (self.structures[index], switches),
                    (builds, &self.traces[row]),
                    evaluation,
                    quality,
                    self.ray_count(),
                ))
            })
            .collect()
    }
}
