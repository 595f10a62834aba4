//! The observer: how one traversal tells a benchmark, the CLI and an animation what it does.
//!
//! Traversal calls these methods at each step. Every method has an empty default that is
//! inlined away, so the benchmark's [`NoObserver`] costs nothing; [`Counters`] counts; the
//! [`Recorder`] keeps every step for the app's timeline.

use crate::math::Real;

/// Told about every step of a traversal (or of brute force).
pub trait Observer<S: Real> {
    /// False for an observer that ignores every step: traversal then skips even computing
    /// what it would report (a node's number in another numbering, say), so observing costs
    /// nothing at all.
    const ACTIVE: bool = true;
    /// A ray/box slab test of node `node`: its clipped interval and whether it hit.
    #[inline(always)]
    fn box_tested(&mut self, _node: u32, _t_enter: S, _t_exit: S, _hit: bool) {}
    /// Traversal entered node `node` (after its box was hit and it was not culled).
    #[inline(always)]
    fn node_entered(&mut self, _node: u32) {}
    /// kD traversal entered cell `node` with the part of the ray inside it, `[t_near, t_far]`
    /// (the lecture's rayNear or rayFar). Unless an observer wants the segment, this is
    /// entering a node.
    #[inline(always)]
    fn cell_entered(&mut self, node: u32, _t_near: S, _t_far: S) {
        self.node_entered(node);
    }
    /// kD traversal: the ray's part in cell `node` is empty (the ray does not reach that side
    /// of its parent's plane inside the parent's cell), so the cell is not entered: the
    /// lecture's `if empty(ray) return`.
    #[inline(always)]
    fn cell_missed(&mut self, _node: u32) {}
    /// A grid walk passed through cell `node` over `[t_near, t_far]` and found nothing listed
    /// there to test. Unless an observer tells the two apart, this is entering a cell: the
    /// walk's cost is every cell it passes.
    #[inline(always)]
    fn cell_skipped(&mut self, node: u32, t_near: S, t_far: S) {
        self.cell_entered(node, t_near, t_far);
    }
    /// A grid walk leaves its cell across the next plane along `axis`: `t_next` holds each
    /// axis's `t` to its next plane (+∞ along an axis the ray does not move on), and `axis`'s
    /// is the least (Amanatides & Woo's `tMax`).
    #[inline(always)]
    fn grid_stepped(&mut self, _axis: usize, _t_next: [S; 3]) {}
    /// A hashed grid's lookup of cell `node` read `probes` places of its table.
    #[inline(always)]
    fn cell_looked_up(&mut self, _node: u32, _probes: u32) {}
    /// A node waiting on the stack was skipped: it is entered only beyond the closest hit.
    #[inline(always)]
    fn node_culled(&mut self, _node: u32, _t_enter: S, _t_closest: S) {}
    /// Primitive `primitive` was tested; `t_hit` is where it was hit inside the interval.
    #[inline(always)]
    fn primitive_tested(&mut self, _primitive: u32, _t_hit: Option<S>) {}
    /// `primitive` at `t` became the closest hit so far.
    #[inline(always)]
    fn closest_hit_updated(&mut self, _primitive: u32, _t: S) {}
    /// `primitive` was not tested again: the mailbox shows it was tested for this ray.
    #[inline(always)]
    fn primitive_skipped(&mut self, _primitive: u32) {}
    /// The traversal's stack now holds `waiting` nodes (told after every push): the deepest
    /// stack a ray needs is the largest of these.
    #[inline(always)]
    fn stack_depth(&mut self, _waiting: usize) {}
    /// A wide traversal tested the boxes of `node`'s `tested` children together (the
    /// `tested` box tests just told, one SIMD test) and will visit the ones hit in `order`:
    /// nearest entry first, or in slot order. An octree tests no boxes (`tested` is 0): its
    /// order, the children the ray passes front to back, comes from the middle planes.
    #[inline(always)]
    fn children_ordered(&mut self, _node: u32, _tested: u32, _order: &[u32]) {}
}

/// The most children a recorded [`Step::ChildrenOrdered`] lists.
pub const MAX_ORDERED: usize = 8;

/// Observes nothing, at no cost: what benchmarks pass.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoObserver;

impl<S: Real> Observer<S> for NoObserver {
    const ACTIVE: bool = false;
}

/// Counts the work of one or many traversals.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Nodes entered.
    pub nodes_visited: u64,
    /// Ray/box slab tests.
    pub box_tests: u64,
    /// Ray/primitive tests.
    pub primitive_tests: u64,
    /// Nodes skipped because they start beyond the closest hit.
    pub nodes_culled: u64,
    /// Primitive tests the mailbox saved.
    pub mailbox_skips: u64,
}

impl std::ops::AddAssign for Counters {
    fn add_assign(&mut self, other: Self) {
        self.nodes_visited += other.nodes_visited;
        self.box_tests += other.box_tests;
        self.primitive_tests += other.primitive_tests;
        self.nodes_culled += other.nodes_culled;
        self.mailbox_skips += other.mailbox_skips;
    }
}

impl<S: Real> Observer<S> for Counters {
    #[inline(always)]
    fn box_tested(&mut self, _node: u32, _t_enter: S, _t_exit: S, _hit: bool) {
        self.box_tests += 1;
    }
    #[inline(always)]
    fn node_entered(&mut self, _node: u32) {
        self.nodes_visited += 1;
    }
    #[inline(always)]
    fn node_culled(&mut self, _node: u32, _t_enter: S, _t_closest: S) {
        self.nodes_culled += 1;
    }
    #[inline(always)]
    fn primitive_tested(&mut self, _primitive: u32, _t_hit: Option<S>) {
        self.primitive_tests += 1;
    }
    #[inline(always)]
    fn primitive_skipped(&mut self, _primitive: u32) {
        self.mailbox_skips += 1;
    }
}

/// The deepest stack the rays traced needed: the most nodes waiting at once (what a
/// fixed-size stack in a GPU kernel must hold). Not a step of the animation, so not in
/// [`Counters`], which a recording replays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MaxStack(pub usize);

impl<S: Real> Observer<S> for MaxStack {
    #[inline(always)]
    fn stack_depth(&mut self, waiting: usize) {
        self.0 = self.0.max(waiting);
    }
}

/// One step of a traversal, as the animation shows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step<S: Real> {
    /// See [`Observer::box_tested`].
    BoxTested {
        /// The node whose box was tested.
        node: u32,
        /// Where the ray enters the box (clipped to the ray's interval).
        t_enter: S,
        /// Where it leaves.
        t_exit: S,
        /// `t_enter <= t_exit`.
        hit: bool,
    },
    /// See [`Observer::node_entered`].
    NodeEntered {
        /// The node.
        node: u32,
    },
    /// See [`Observer::cell_entered`].
    CellEntered {
        /// The kD node.
        node: u32,
        /// Where the ray's part in the cell starts.
        t_near: S,
        /// Where it ends.
        t_far: S,
    },
    /// See [`Observer::cell_missed`].
    CellMissed {
        /// The kD node.
        node: u32,
    },
    /// See [`Observer::cell_skipped`].
    CellSkipped {
        /// The cell's node.
        node: u32,
        /// Where the ray's part in the cell starts.
        t_near: S,
        /// Where it ends.
        t_far: S,
    },
    /// See [`Observer::grid_stepped`].
    GridStepped {
        /// The axis whose plane is crossed.
        axis: u8,
        /// Each axis's `t` to its next plane.
        t_next: [S; 3],
    },
    /// See [`Observer::cell_looked_up`].
    CellLookedUp {
        /// The cell's node.
        node: u32,
        /// Table places read.
        probes: u32,
    },
    /// See [`Observer::node_culled`].
    NodeCulled {
        /// The node.
        node: u32,
        /// Where the ray would enter it.
        t_enter: S,
        /// The closest hit at that moment.
        t_closest: S,
    },
    /// See [`Observer::primitive_tested`].
    PrimitiveTested {
        /// The primitive.
        primitive: u32,
        /// Where it was hit, if it was.
        t_hit: Option<S>,
    },
    /// See [`Observer::closest_hit_updated`].
    ClosestHitUpdated {
        /// The primitive.
        primitive: u32,
        /// Its `t`.
        t: S,
    },
    /// See [`Observer::primitive_skipped`].
    PrimitiveSkipped {
        /// The primitive.
        primitive: u32,
    },
    /// See [`Observer::children_ordered`].
    ChildrenOrdered {
        /// The wide node.
        node: u32,
        /// How many of its children's boxes were tested together.
        tested: u32,
        /// The children hit, in the order they will be visited (the first `count`).
        order: [u32; MAX_ORDERED],
        /// How many were hit.
        count: u32,
    },
}

/// Records every step, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recorder<S: Real> {
    /// The steps so far.
    pub steps: Vec<Step<S>>,
}

impl<S: Real> Observer<S> for Recorder<S> {
    fn box_tested(&mut self, node: u32, t_enter: S, t_exit: S, hit: bool) {
        self.steps.push(Step::BoxTested {
            node,
            t_enter,
            t_exit,
            hit,
        });
    }
    fn node_entered(&mut self, node: u32) {
        self.steps.push(Step::NodeEntered { node });
    }
    fn cell_entered(&mut self, node: u32, t_near: S, t_far: S) {
        self.steps.push(Step::CellEntered {
            node,
            t_near,
            t_far,
        });
    }
    fn cell_missed(&mut self, node: u32) {
        self.steps.push(Step::CellMissed { node });
    }
    fn cell_skipped(&mut self, node: u32, t_near: S, t_far: S) {
        self.steps.push(Step::CellSkipped {
            node,
            t_near,
            t_far,
        });
    }
    fn grid_stepped(&mut self, axis: usize, t_next: [S; 3]) {
        self.steps.push(Step::GridStepped {
            axis: axis as u8,
            t_next,
        });
    }
    fn cell_looked_up(&mut self, node: u32, probes: u32) {
        self.steps.push(Step::CellLookedUp { node, probes });
    }
    fn node_culled(&mut self, node: u32, t_enter: S, t_closest: S) {
        self.steps.push(Step::NodeCulled {
            node,
            t_enter,
            t_closest,
        });
    }
    fn primitive_tested(&mut self, primitive: u32, t_hit: Option<S>) {
        self.steps.push(Step::PrimitiveTested { primitive, t_hit });
    }
    fn closest_hit_updated(&mut self, primitive: u32, t: S) {
        self.steps.push(Step::ClosestHitUpdated { primitive, t });
    }
    fn primitive_skipped(&mut self, primitive: u32) {
        self.steps.push(Step::PrimitiveSkipped { primitive });
    }
    fn children_ordered(&mut self, node: u32, tested: u32, order: &[u32]) {
        let mut kept = [0; MAX_ORDERED];
        let count = order.len().min(MAX_ORDERED);
        kept[..count].copy_from_slice(&order[..count]);
        self.steps.push(Step::ChildrenOrdered {
            node,
            tested,
            order: kept,
            count: count as u32,
        });
    }
}

impl<S: Real> Step<S> {
    /// Tells `observer` about this step, as the traversal did when it was recorded.
    pub fn replay<O: Observer<S>>(&self, observer: &mut O) {
        match *self {
            Step::BoxTested {
                node,
                t_enter,
                t_exit,
                hit,
            } => observer.box_tested(node, t_enter, t_exit, hit),
            Step::NodeEntered { node } => observer.node_entered(node),
            Step::CellEntered {
                node,
                t_near,
                t_far,
            } => observer.cell_entered(node, t_near, t_far),
            Step::CellMissed { node } => observer.cell_missed(node),
            Step::CellSkipped {
                node,
                t_near,
                t_far,
            } => observer.cell_skipped(node, t_near, t_far),
            Step::GridStepped { axis, t_next } => observer.grid_stepped(axis as usize, t_next),
            Step::CellLookedUp { node, probes } => observer.cell_looked_up(node, probes),
            Step::NodeCulled {
                node,
                t_enter,
                t_closest,
            } => observer.node_culled(node, t_enter, t_closest),
            Step::PrimitiveTested { primitive, t_hit } => {
                observer.primitive_tested(primitive, t_hit)
            }
            Step::ClosestHitUpdated { primitive, t } => observer.closest_hit_updated(primitive, t),
            Step::PrimitiveSkipped { primitive } => observer.primitive_skipped(primitive),
            Step::ChildrenOrdered {
                node,
                tested,
                order,
                count,
            } => observer.children_ordered(node, tested, &order[..count as usize]),
        }
    }
}

/// The counters of the first steps of a recording: what an animation shows part-way through
/// (replayed into [`Counters`], so a full replay equals counting while tracing).
pub fn counters_of<S: Real>(steps: &[Step<S>]) -> Counters {
    let mut counters = Counters::default();
    for step in steps {
        step.replay(&mut counters);
    }
    counters
}

/// Forwards every step to two observers (e.g. count and record at once).
impl<S: Real, A: Observer<S>, B: Observer<S>> Observer<S> for (A, B) {
    const ACTIVE: bool = A::ACTIVE || B::ACTIVE;
    #[inline(always)]
    fn box_tested(&mut self, node: u32, t_enter: S, t_exit: S, hit: bool) {
        self.0.box_tested(node, t_enter, t_exit, hit);
        self.1.box_tested(node, t_enter, t_exit, hit);
    }
    #[inline(always)]
    fn node_entered(&mut self, node: u32) {
        self.0.node_entered(node);
        self.1.node_entered(node);
    }
    #[inline(always)]
    fn cell_entered(&mut self, node: u32, t_near: S, t_far: S) {
        self.0.cell_entered(node, t_near, t_far);
        self.1.cell_entered(node, t_near, t_far);
    }
    #[inline(always)]
    fn cell_missed(&mut self, node: u32) {
        self.0.cell_missed(node);
        self.1.cell_missed(node);
    }
    #[inline(always)]
    fn cell_skipped(&mut self, node: u32, t_near: S, t_far: S) {
        self.0.cell_skipped(node, t_near, t_far);
        self.1.cell_skipped(node, t_near, t_far);
    }
    #[inline(always)]
    fn grid_stepped(&mut self, axis: usize, t_next: [S; 3]) {
        self.0.grid_stepped(axis, t_next);
        self.1.grid_stepped(axis, t_next);
    }
    #[inline(always)]
    fn cell_looked_up(&mut self, node: u32, probes: u32) {
        self.0.cell_looked_up(node, probes);
        self.1.cell_looked_up(node, probes);
    }
    #[inline(always)]
    fn node_culled(&mut self, node: u32, t_enter: S, t_closest: S) {
        self.0.node_culled(node, t_enter, t_closest);
        self.1.node_culled(node, t_enter, t_closest);
    }
    #[inline(always)]
    fn primitive_tested(&mut self, primitive: u32, t_hit: Option<S>) {
        self.0.primitive_tested(primitive, t_hit);
        self.1.primitive_tested(primitive, t_hit);
    }
    #[inline(always)]
    fn closest_hit_updated(&mut self, primitive: u32, t: S) {
        self.0.closest_hit_updated(primitive, t);
        self.1.closest_hit_updated(primitive, t);
    }
    #[inline(always)]
    fn stack_depth(&mut self, waiting: usize) {
        self.0.stack_depth(waiting);
        self.1.stack_depth(waiting);
    }
    #[inline(always)]
    fn primitive_skipped(&mut self, primitive: u32) {
        self.0.primitive_skipped(primitive);
        self.1.primitive_skipped(primitive);
    }
    #[inline(always)]
    fn children_ordered(&mut self, node: u32, tested: u32, order: &[u32]) {
        self.0.children_ordered(node, tested, order);
        self.1.children_ordered(node, tested, order);
    }
}

/// Hears a traversal in any precision and tells `O`, an f64 observer, every step with its
/// numbers widened to f64 (exactly): so one recorder serves a traversal in f32, as a trade
/// row traced it, and one in f64.
pub struct Widened<'a, O>(pub &'a mut O);

impl<S: Real, O: Observer<f64>> Observer<S> for Widened<'_, O> {
    const ACTIVE: bool = O::ACTIVE;
    #[inline(always)]
    fn box_tested(&mut self, node: u32, t_enter: S, t_exit: S, hit: bool) {
        self.0
            .box_tested(node, t_enter.to_f64(), t_exit.to_f64(), hit);
    }
    #[inline(always)]
    fn node_entered(&mut self, node: u32) {
        self.0.node_entered(node);
    }
    #[inline(always)]
    fn cell_entered(&mut self, node: u32, t_near: S, t_far: S) {
        self.0.cell_entered(node, t_near.to_f64(), t_far.to_f64());
    }
    #[inline(always)]
    fn cell_missed(&mut self, node: u32) {
        self.0.cell_missed(node);
    }
    #[inline(always)]
    fn cell_skipped(&mut self, node: u32, t_near: S, t_far: S) {
        self.0.cell_skipped(node, t_near.to_f64(), t_far.to_f64());
    }
    #[inline(always)]
    fn grid_stepped(&mut self, axis: usize, t_next: [S; 3]) {
        self.0.grid_stepped(axis, t_next.map(S::to_f64));
    }
    #[inline(always)]
    fn cell_looked_up(&mut self, node: u32, probes: u32) {
        self.0.cell_looked_up(node, probes);
    }
    #[inline(always)]
    fn node_culled(&mut self, node: u32, t_enter: S, t_closest: S) {
        self.0
            .node_culled(node, t_enter.to_f64(), t_closest.to_f64());
    }
    #[inline(always)]
    fn primitive_tested(&mut self, primitive: u32, t_hit: Option<S>) {
        self.0.primitive_tested(primitive, t_hit.map(S::to_f64));
    }
    #[inline(always)]
    fn closest_hit_updated(&mut self, primitive: u32, t: S) {
        self.0.closest_hit_updated(primitive, t.to_f64());
    }
    #[inline(always)]
    fn primitive_skipped(&mut self, primitive: u32) {
        self.0.primitive_skipped(primitive);
    }
    #[inline(always)]
    fn stack_depth(&mut self, waiting: usize) {
        self.0.stack_depth(waiting);
    }
    #[inline(always)]
    fn children_ordered(&mut self, node: u32, tested: u32, order: &[u32]) {
        self.0.children_ordered(node, tested, order);
    }
}
