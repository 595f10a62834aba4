//! The one wide-BVH traversal: a node's children are tested together, the ones hit are
//! visited nearest first (or in slot order), and each step is told to the observer in the
//! binary tree's numbering (see [`WideBvh`]).
//!
//! Wald, Benthin & Boulos 2008, "Getting rid of packets: efficient SIMD single-ray traversal
//! using multi-branching BVHs": one ray against the `W` boxes of a node at once, instead of a
//! packet of rays against one box.

use std::any::Any;

use crate::bvh::wide::{LEAF_BLOCK, LOWER, UPPER, WideBvh, WideNode};
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::{HitTest, LeafPrimitives, PrimitiveSet, TriangleBlock, TriangleRay};
use crate::query::{Hit, Order, TraceOptions};
use crate::ray::Ray;
use crate::search::HitSearch;
use crate::simd::{Kernel, NodeRay, prefetch_lines};
use crate::slab::{SlabRay, earlier, later};

/// One child waiting to be visited: a wide node or a leaf, and where the ray enters its box.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pending<S: Real> {
    /// A node's index or a leaf's first slot.
    child: u32,
    /// A leaf's primitive count; 0 for a node.
    count: u32,
    t_enter: S,
}

/// How many pending children a traversal keeps at hand; deeper stacks spill their bottom half
/// to the heap (an 8-wide tree pushes at most 7 a level, so trees of up to 9 wide levels, the
/// bunny's is 7, never spill).
const STACK_SLOTS: usize = 64;

/// Reusable stack for [`traverse_wide`]: make one per thread, so tracing allocates nothing per
/// ray.
#[derive(Clone, Debug)]
pub struct WideStack<S: Real> {
    /// The top of the stack; its depth lives in a register while a ray is traced.
    slots: Box<[Pending<S>; STACK_SLOTS]>,
    /// Entries below the slots, bottom first, for trees deeper than the slots hold.
    spilled: Vec<Pending<S>>,
}

impl<S: Real> Default for WideStack<S> {
    fn default() -> Self {
        Self {
            slots: Box::new([Pending::root(S::ZERO); STACK_SLOTS]),
            spilled: Vec::new(),
        }
    }
}

/// A ray's stack of pending children while it is traced: the slots of a [`WideStack`] and
/// the depth in them (kept in a register, where a `Vec`'s length is written back to memory
/// at every push and pop).
struct PendingStack<'a, S: Real> {
    slots: &'a mut [Pending<S>; STACK_SLOTS],
    spilled: &'a mut Vec<Pending<S>>,
    top: usize,
}

impl<'a, S: Real> PendingStack<'a, S> {
    /// An empty stack over `stack`'s storage.
    #[inline(always)]
    fn new(stack: &'a mut WideStack<S>) -> Self {
        stack.spilled.clear();
        Self {
            slots: &mut stack.slots,
            spilled: &mut stack.spilled,
            top: 0,
        }
    }

    /// Makes room for `count` (at most half the slots) more entries in the slots, side by
    /// side.
    #[inline(always)]
    fn reserve(&mut self, count: usize) {
        if self.top + count > STACK_SLOTS {
            self.spill();
        }
    }

    /// Moves the bottom half of the slots to the heap.
    #[cold]
    #[inline(never)]
    fn spill(&mut self) {
        let half = STACK_SLOTS / 2;
        self.spilled.extend_from_slice(&self.slots[..half]);
        self.slots.copy_within(half..self.top, 0);
        self.top -= half;
    }

    /// Brings entries back from the heap into the empty slots; false when there are none.
    #[cold]
    #[inline(never)]
    fn refill(&mut self) -> bool {
        let count = self.spilled.len().min(STACK_SLOTS / 2);
        let from = self.spilled.len() - count;
        self.slots[..count].copy_from_slice(&self.spilled[from..]);
        self.spilled.truncate(from);
        self.top = count;
        count > 0
    }

    /// How many entries wait, spilled ones too.
    #[inline(always)]
    fn depth(&self) -> usize {
        self.spilled.len() + self.top
    }

    /// Pushes `entry` (after a [`reserve`](Self::reserve) for it).
    #[inline(always)]
    fn push(&mut self, entry: Pending<S>) {
        self.slots[self.top] = entry;
        self.top += 1;
    }

    /// The most recently pushed entry, taken off.
    #[inline(always)]
    fn pop(&mut self) -> Option<Pending<S>> {
        if self.top == 0 && (self.spilled.is_empty() || !self.refill()) {
            return None;
        }
        self.top -= 1;
        Some(self.slots[self.top])
    }

    /// The top `count` entries, the top last.
    fn top_entries(&self, count: usize) -> &[Pending<S>] {
        &self.slots[self.top - count..self.top]
    }
}

/// The ray/box tests of one node's children: each slot's interval and which slots are hit.
#[derive(Clone, Copy, Debug)]
pub struct ChildTests<S: Real, const W: usize> {
    /// Where the ray enters each child's box (clipped to the ray's interval).
    pub t_enter: [S; W],
    /// Where it leaves.
    pub t_exit: [S; W],
    /// Bit `s` set when slot `s` is hit (`t_enter <= t_exit`).
    pub hit_mask: u32,
}

/// The slab test of all `W` children of `node` at once: the arithmetic of
/// [`slab_clip_scalar`](crate::slab::slab_clip_scalar) lane by lane (the same planes, products
/// and NaN-ignoring reductions), so each child's interval is the one the binary traversal
/// computes for its box.
#[inline(always)]
pub fn test_children<V: Vector, const W: usize>(
    node: &WideNode<V::Scalar, W>,
    ray: &SlabRay<V>,
    t_max: V::Scalar,
) -> ChildTests<V::Scalar, W> {
    let mut t_enter = [ray.t_min; W];
    let mut t_exit = [V::Scalar::INFINITY; W];
    for axis in 0..V::DIM {
        let near = &node.planes[ray.near_side(axis)][axis];
        let far = &node.planes[ray.far_side(axis)][axis];
        let origin = ray.origin[axis];
        let inverse = ray.inv_direction[axis];
        for slot in 0..W {
            let t_near = (near[slot] - origin) * inverse;
            let t_far = (far[slot] - origin) * inverse;
            t_enter[slot] = later(t_enter[slot], t_near);
            t_exit[slot] = earlier(t_exit[slot], t_far);
        }
    }
    let mut hit_mask = 0;
    for slot in 0..W {
        t_exit[slot] = earlier(t_max, t_exit[slot] * ray.far_scale);
        hit_mask |= u32::from(t_enter[slot] <= t_exit[slot]) << slot;
    }
    ChildTests {
        t_enter,
        t_exit,
        hit_mask,
    }
}

/// Traces `ray` through `tree` over `primitives` (a [`PrimitiveSet`] in its own numbering, or
/// the tree's [`leaf_ordered`](WideBvh::leaf_ordered) copy of one).
///
/// From the root: test every child's box of the node at once; order the children hit (nearest
/// entry first, or slot order), visit the first and push the others; at a leaf, test its
/// primitives (four triangles at once where they are stored in blocks), shrinking the interval
/// at each hit; skip a pushed child the ray enters beyond the closest hit (a cull). The
/// observer hears the binary numbering: a node entered, each child's box test, culls,
/// primitives. The kernels are those of [`Isa::active`](crate::simd::Isa::active).
pub fn traverse_wide<V, P, O, const W: usize>(
    tree: &WideBvh<V, W>,
    primitives: &P,
    ray: &Ray<V>,
    options: &TraceOptions,
    stack: &mut WideStack<V::Scalar>,
    observer: &mut O,
) -> Option<Hit<V::Scalar>>
where
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    crate::simd::traverse_wide(tree, primitives, ray, options, stack, observer)
}

/// [`traverse_wide`] with the kernels of `K`: compiled once per instruction set.
#[inline(always)]
pub(crate) fn traverse_wide_with<K, V, P, O, const W: usize>(
    tree: &WideBvh<V, W>,
    primitives: &P,
    ray: &Ray<V>,
    options: &TraceOptions,
    stack: &mut WideStack<V::Scalar>,
    observer: &mut O,
) -> Option<Hit<V::Scalar>>
where
    K: Kernel,
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    if tree.nodes.is_empty() {
        return None;
    }
    let state = RayState::new(primitives, ray, options);
    // The search is a local, not the state's (which lives in memory): its closest hit is then
    // returned from registers, not written in pieces and read back whole (a store-forwarding
    // stall on every ray).
    let mut search = state.search;
    state.run::<K, O, W>(
        &mut search,
        tree,
        primitives,
        SlabRay::new(ray, options.robust_traversal),
        Pending::root(ray.t_min),
        options,
        stack,
        observer,
    );
    search.closest
}

impl<S: Real> Pending<S> {
    /// The root node, entered where the ray starts.
    fn root(t_min: S) -> Self {
        Self {
            child: 0,
            count: 0,
            t_enter: t_min,
        }
    }
}

/// One ray's traversal under way: the ray prepared for primitive tests, and its search. (The
/// ray prepared for box tests is passed to the loop by value: held here, in memory that the
/// leaf tests' functions out of line might change, its lanes were reloaded at every node, and
/// a copy read it whole just after it was written in pieces, a store-forwarding stall on every
/// ray.)
struct RayState<'a, V: Vector, P: LeafPrimitives<V>> {
    ray: &'a Ray<V>,
    primitive_ray: <P::Set as PrimitiveSet<V>>::RayData,
    /// The triangle blocks, when the set has them (3D triangles in a wide BVH's leaf order).
    blocks: Option<&'a [TriangleBlock<V::Scalar>]>,
    search: HitSearch<V::Scalar>,
}

impl<'a, V: Vector, P: LeafPrimitives<V>> RayState<'a, V, P> {
    #[inline(always)]
    fn new(primitives: &'a P, ray: &'a Ray<V>, options: &TraceOptions) -> Self {
        Self {
            ray,
            primitive_ray: primitives.stored().prepare(ray, options.hit_test),
            blocks: primitives.triangle_blocks(),
            search: HitSearch::new(ray.t_max, options.query),
        }
    }

    /// The ray prepared for triangle tests, when the set is one of triangles (a set with
    /// blocks is; the type test is resolved when the code is compiled).
    #[inline(always)]
    fn block_ray(&self) -> Option<&TriangleRay<<V::Scalar as Real>::Vec3>> {
        (&self.primitive_ray as &dyn Any).downcast_ref::<TriangleRay<<V::Scalar as Real>::Vec3>>()
    }

    /// Tests a leaf's primitives into `search` (this ray's, held apart so that the loop can
    /// keep it in registers); true when an any-hit query has its answer.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn test_leaf<K: Kernel, O: Observer<V::Scalar>>(
        &self,
        search: &mut HitSearch<V::Scalar>,
        primitives: &P,
        block_ray: Option<&TriangleRay<<V::Scalar as Real>::Vec3>>,
        first: u32,
        numbers: &[u32],
        observer: &mut O,
    ) -> bool {
        if let (Some(blocks), Some(block_ray)) = (self.blocks, block_ray) {
            let (t_min, ray) = (block_ray.ray.t_min, &block_ray.ray);
            return match block_ray.test {
                // Möller–Trumbore compares `t` itself with the interval: a lane inside the
                // interval the block was tested with is inside a shrunk one when its `t` is.
                HitTest::Fast => search.test_blocks(
                    blocks,
                    first,
                    numbers,
                    observer,
                    |block, t_max| {
                        K::moller_trumbore(block, ray.origin, ray.direction, t_min, t_max)
                    },
                    |_, _, t, t_max| t <= t_max,
                ),
                // The watertight test compares before it divides: ask it again.
                HitTest::Watertight => search.test_blocks(
                    blocks,
                    first,
                    numbers,
                    observer,
                    |block, t_max| K::watertight(block, block_ray, t_min, t_max),
                    |block, lane, _, t_max| {
                        block
                            .intersect_lane(block_ray, lane, t_min, t_max)
                            .is_some()
                    },
                ),
            };
        }
        search.test_leaf(
            primitives,
            &self.primitive_ray,
            self.ray.t_min,
            first as usize,
            numbers,
            |_| false,
            observer,
        )
    }

    /// Starts bringing the children hit (`hit_mask`) into the caches: their nodes, or their
    /// leaves' triangle blocks, so that the one visited next and the ones pushed arrive while
    /// the children are ordered (as Embree's traversal does).
    #[inline(always)]
    fn prefetch_children<const W: usize>(
        &self,
        nodes: &[WideNode<V::Scalar, W>],
        node: &WideNode<V::Scalar, W>,
        hit_mask: u32,
    ) {
        let blocks = self.blocks.unwrap_or_default();
        let mut mask = hit_mask;
        while mask != 0 {
            let slot = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let (child, count) = (node.child[slot] as usize, node.count[slot]);
            // A node is four lines; a leaf's first four lines hold its first block and most
            // of its second (a block is 2.25 lines).
            let address = if count == 0 {
                nodes.as_ptr().wrapping_add(child).cast::<u8>()
            } else {
                blocks
                    .as_ptr()
                    .wrapping_add(child / LEAF_BLOCK)
                    .cast::<u8>()
            };
            prefetch_lines::<4>(address);
        }
    }

    /// The traversal loop from `start` (the root, or where a packet left this ray), with
    /// `slab_ray` the ray prepared for box tests, searching into `search_out` with `stack`'s
    /// storage. True when an any-hit query has its answer.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn run<K: Kernel, O: Observer<V::Scalar>, const W: usize>(
        &self,
        search_out: &mut HitSearch<V::Scalar>,
        tree: &WideBvh<V, W>,
        primitives: &P,
        slab_ray: SlabRay<V>,
        start: Pending<V::Scalar>,
        options: &TraceOptions,
        stack: &mut WideStack<V::Scalar>,
        observer: &mut O,
    ) -> bool {
        let nodes = tree.nodes.as_slice();
        let mut search = *search_out;
        let mut pending = PendingStack::new(stack);
        let near_first = options.order == Order::NearFirst;
        let node_ray = NodeRay::<V, W>::new(slab_ray);
        // A child waiting on the stack is skipped when the ray enters it beyond the closest
        // hit (a cull); the child visited straight after its node's test never is (it is
        // entered before the interval's end), so only a popped child (or `start`) is checked.
        let culled = |entry: &Pending<V::Scalar>, t_closest: V::Scalar, observer: &mut O| {
            let culled = entry.t_enter > t_closest;
            if O::ACTIVE && culled {
                observer.node_culled(
                    tree.child_source(entry.child, entry.count),
                    entry.t_enter,
                    t_closest,
                );
            }
            culled
        };
        if culled(&start, search.t_closest, observer) {
            return false;
        }
        let mut next = start;
        'trace: loop {
            let Pending { child, count, .. } = next;
            'visit: {
                if O::ACTIVE {
                    observer.node_entered(tree.child_source(child, count));
                }
                if count > 0 {
                    let numbers = tree.leaf_primitives(child, count);
                    if self.test_leaf::<K, O>(
                        &mut search,
                        primitives,
                        self.block_ray(),
                        child,
                        numbers,
                        observer,
                    ) {
                        *search_out = search;
                        return true;
                    }
                    break 'visit;
                }
                let node = &nodes[child as usize];
                let tests = K::test_children(node, &node_ray, search.t_closest);
                self.prefetch_children(nodes, node, tests.hit_mask);
                if O::ACTIVE {
                    for slot in 0..node.slots_used() {
                        observer.box_tested(
                            tree.slot_source(child as usize, slot),
                            tests.t_enter[slot],
                            tests.t_exit[slot],
                            tests.hit_mask & (1 << slot) != 0,
                        );
                    }
                }
                let Some((visited, pushed)) =
                    visit_children(node, &tests, near_first, &mut pending)
                else {
                    if O::ACTIVE {
                        observer.children_ordered(
                            tree.child_source(child, count),
                            node.slots_used() as u32,
                            &[],
                        );
                    }
                    break 'visit;
                };
                if O::ACTIVE && pushed > 0 {
                    observer.stack_depth(pending.depth());
                }
                if O::ACTIVE {
                    // The order chosen: the child visited next, then the ones just pushed,
                    // the nearest last on the stack.
                    let mut order = [0u32; W];
                    let chosen =
                        std::iter::once(&visited).chain(pending.top_entries(pushed).iter().rev());
                    for (place, entry) in order.iter_mut().zip(chosen) {
                        *place = tree.child_source(entry.child, entry.count);
                    }
                    observer.children_ordered(
                        tree.child_source(child, count),
                        node.slots_used() as u32,
                        &order[..pushed + 1],
                    );
                }
                next = visited;
                continue 'trace;
            }
            loop {
                let Some(entry) = pending.pop() else {
                    break 'trace;
                };
                if !culled(&entry, search.t_closest, observer) {
                    next = entry;
                    break;
                }
            }
        }
        *search_out = search;
        false
    }
}

/// The most rays a packet holds (one bit each in a `u64` mask).
pub const MAX_PACKET: usize = 64;

/// A packet with this many active rays or fewer goes on ray by ray: what a packet saves (one
/// visit of a node for many rays) is gone, and a ray alone skips what it does not need.
const SCATTERED: u32 = 2;

/// Rays whose lanes are tested together: a group of eight.
pub(crate) const LANES: usize = 8;

/// A child waiting to be visited by some rays of a packet.
#[derive(Clone, Copy, Debug)]
struct PacketPending<S: Real> {
    child: u32,
    count: u32,
    /// Which rays hit its box.
    rays: u64,
    /// The nearest of their entries (the packet skips the child when every one of its rays
    /// has found a hit before it).
    t_enter: S,
}

/// Reusable stacks for [`traverse_packet`]: make one per thread.
#[derive(Clone, Debug, Default)]
pub struct PacketStack<S: Real> {
    entries: Vec<PacketPending<S>>,
    /// For a ray that leaves its packet.
    single: WideStack<S>,
}

/// A packet's rays lane by lane, for testing one box against many rays at once.
pub(crate) struct PacketLanes<S: Real> {
    pub(crate) origin: [[S; MAX_PACKET]; 3],
    pub(crate) inv_direction: [[S; MAX_PACKET]; 3],
    pub(crate) negative: [[bool; MAX_PACKET]; 3],
    pub(crate) t_min: [S; MAX_PACKET],
    /// Each ray's closest hit so far (its search interval's end).
    pub(crate) t_closest: [S; MAX_PACKET],
    pub(crate) far_scale: S,
}

/// Bounds on a packet's rays, axis by axis, for rejecting a box every ray misses with one test
/// (interval arithmetic over the packet, Boulos, Wald et al. 2006, "Geometric and arithmetic
/// culling methods for entire ray packets"). Kept in the frame where the directions are
/// positive (a negative axis is mirrored, which is exact).
#[derive(Clone, Copy, Debug)]
struct AxisBounds<S: Real> {
    /// The rays move towards −∞ on this axis (all of them).
    negative: bool,
    /// Origins, mirrored when negative: smallest and largest.
    origin_min: S,
    origin_max: S,
    /// Reciprocal directions, made positive: smallest and largest.
    inverse_min: S,
    inverse_max: S,
}

/// What every ray of a packet shares, for the one test per box (see [`AxisBounds`]); an axis
/// whose rays go both ways (or along which one does not move) bounds nothing.
struct PacketBounds<S: Real> {
    axes: [Option<AxisBounds<S>>; 3],
    /// The smallest `t_min` of the rays.
    t_min: S,
    far_scale: S,
}

impl<S: Real> PacketBounds<S> {
    // Inlined into each instruction set's packet traversal, so its reductions are compiled
    // for that set's vectors (out of line they ran in SSE2: 17 % of a packet's time).
    #[inline(always)]
    fn new<V: Vector<Scalar = S>>(lanes: &PacketLanes<S>, count: usize) -> Self {
        let mut axes = [None; 3];
        for (axis, bounds) in axes.iter_mut().enumerate().take(V::DIM) {
            let (origin_min, origin_max) = extremes(&lanes.origin[axis][..count]);
            let (inverse_min, inverse_max) = extremes(&lanes.inv_direction[axis][..count]);
            // Every ray moves one way along the axis (a reciprocal's sign is its direction's;
            // −0 gives −∞, which is not finite) and none is parallel to it: else the axis
            // bounds nothing.
            let finite = inverse_min > S::NEG_INFINITY && inverse_max < S::INFINITY;
            *bounds = if finite && inverse_min >= S::ZERO {
                Some(AxisBounds {
                    negative: false,
                    origin_min,
                    origin_max,
                    inverse_min,
                    inverse_max,
                })
            } else if finite && inverse_max < S::ZERO {
                // Mirrored (exact): the smallest of the negated values is the negated largest.
                Some(AxisBounds {
                    negative: true,
                    origin_min: -origin_max,
                    origin_max: -origin_min,
                    inverse_min: -inverse_max,
                    inverse_max: -inverse_min,
                })
            } else {
                None
            };
        }
        Self {
            axes,
            t_min: extremes(&lanes.t_min[..count]).0,
            far_scale: lanes.far_scale,
        }
    }

    /// Bit `slot` set for each child box of `node` that no ray of the packet can enter before
    /// `t_max`: the lowest entry any ray can have is past the highest exit any can have.
    /// Conservative: each bound is computed from the rays' own products, rounded the same way
    /// (rounding is monotonic). Every slot at once, in lanes the compiler can vectorise.
    #[inline(always)]
    fn misses<V: Vector<Scalar = S>, const W: usize>(
        &self,
        node: &WideNode<S, W>,
        t_max: S,
    ) -> u32 {
        let mut near = [self.t_min; W];
        let mut far = [S::INFINITY; W];
        for (axis, bounds) in self.axes.iter().enumerate().take(V::DIM) {
            let Some(bounds) = bounds else { continue };
            let (lower, upper) = (&node.planes[LOWER][axis], &node.planes[UPPER][axis]);
            for slot in 0..W {
                let (near_plane, far_plane) = if bounds.negative {
                    (-upper[slot], -lower[slot])
                } else {
                    (lower[slot], upper[slot])
                };
                // The least (near plane − origin) and the greatest (far plane − origin).
                let to_near = near_plane - bounds.origin_max;
                let to_far = far_plane - bounds.origin_min;
                let t_near = if to_near >= S::ZERO {
                    to_near * bounds.inverse_min
                } else {
                    to_near * bounds.inverse_max
                };
                let t_far = if to_far >= S::ZERO {
                    to_far * bounds.inverse_max
                } else {
                    to_far * bounds.inverse_min
                };
                near[slot] = later(near[slot], t_near);
                far[slot] = earlier(far[slot], t_far);
            }
        }
        let mut missed = 0;
        for slot in 0..W {
            let far = far[slot] * self.far_scale;
            missed |= u32::from(near[slot] > far || near[slot] > t_max) << slot;
        }
        missed
    }
}

/// The least and the greatest of `values` (none NaN), `(∞, −∞)` for none: reduced in eight
/// running lanes, which the compiler turns into vector minimums and maximums (a running
/// scalar, with its dependence from one value to the next, it does not).
#[inline(always)]
fn extremes<S: Real>(values: &[S]) -> (S, S) {
    let mut least = [S::INFINITY; LANES];
    let mut greatest = [S::NEG_INFINITY; LANES];
    let mut chunks = values.chunks_exact(LANES);
    for chunk in &mut chunks {
        for lane in 0..LANES {
            least[lane] = earlier(least[lane], chunk[lane]);
            greatest[lane] = later(greatest[lane], chunk[lane]);
        }
    }
    for (lane, &value) in chunks.remainder().iter().enumerate() {
        least[lane] = earlier(least[lane], value);
        greatest[lane] = later(greatest[lane], value);
    }
    let least = least.iter().fold(S::INFINITY, |a, &b| earlier(a, b));
    let greatest = greatest.iter().fold(S::NEG_INFINITY, |a, &b| later(a, b));
    (least, greatest)
}

/// One box against a group of [`LANES`] rays of a packet: each ray's interval, clipped to its
/// search interval (`t_exit` below `t_enter` where it misses).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BoxAgainstRays<S: Real> {
    pub(crate) t_enter: [S; LANES],
    pub(crate) t_exit: [S; LANES],
    /// Bit `lane` set where the ray is active and `t_enter <= t_exit`.
    pub(crate) hits: u32,
    /// `t_enter` where a ray hits, `+∞` elsewhere.
    pub(crate) entries: [S; LANES],
}

impl<S: Real> PacketLanes<S> {
    /// The slab test of the box `lower`–`upper` (the first `dims` axes) against the rays
    /// `first..first + LANES` (those whose bits are set in `active` count as hits): the
    /// arithmetic of [`test_children`] for each ray, so each ray's interval is the one its
    /// single-ray traversal computes for that box. What the SIMD kernels compute in lanes.
    #[inline(always)]
    pub(crate) fn box_against_rays(
        &self,
        lower: [S; 3],
        upper: [S; 3],
        first: usize,
        dims: usize,
        active: u32,
    ) -> BoxAgainstRays<S> {
        let mut t_enter: [S; LANES] = std::array::from_fn(|lane| self.t_min[first + lane]);
        let mut t_exit = [S::INFINITY; LANES];
        for axis in 0..dims {
            for lane in 0..LANES {
                let ray = first + lane;
                let origin = self.origin[axis][ray];
                let inverse = self.inv_direction[axis][ray];
                let t_lower = (lower[axis] - origin) * inverse;
                let t_upper = (upper[axis] - origin) * inverse;
                let negative = self.negative[axis][ray];
                let t_near = if negative { t_upper } else { t_lower };
                let t_far = if negative { t_lower } else { t_upper };
                t_enter[lane] = later(t_enter[lane], t_near);
                t_exit[lane] = earlier(t_exit[lane], t_far);
            }
        }
        let mut hits = 0;
        let mut entries = [S::INFINITY; LANES];
        for lane in 0..LANES {
            t_exit[lane] = earlier(self.t_closest[first + lane], t_exit[lane] * self.far_scale);
            let hit = t_enter[lane] <= t_exit[lane] && (active >> lane) & 1 != 0;
            hits |= u32::from(hit) << lane;
            if hit {
                entries[lane] = t_enter[lane];
            }
        }
        BoxAgainstRays {
            t_enter,
            t_exit,
            hits,
            entries,
        }
    }

    /// The slab test of one box (slot `slot` of `node`) against the rays of lane group
    /// `group` (with the kernels of `K`): each ray's interval, which of the rays in `active`
    /// (the packet's bits) hit, and the nearest entry among those.
    #[inline(always)]
    fn test_box<K: Kernel, V: Vector<Scalar = S>, const W: usize>(
        &self,
        node: &WideNode<S, W>,
        slot: usize,
        group: usize,
        active: u64,
    ) -> ([S; LANES], [S; LANES], u64, S) {
        let lanes = group * LANES..group * LANES + LANES;
        let lower = std::array::from_fn(|axis| node.planes[LOWER][axis][slot]);
        let upper = std::array::from_fn(|axis| node.planes[UPPER][axis][slot]);
        let group_active = ((active >> lanes.start) & ((1 << LANES) - 1)) as u32;
        let BoxAgainstRays {
            t_enter,
            t_exit,
            hits,
            mut entries,
        } = K::box_against_rays(self, lower, upper, lanes.start, V::DIM, group_active);
        // The least entry of the rays that hit, taken pairwise (entries are never NaN: they
        // start at `t_min`, and `later` ignores NaN).
        let mut width = LANES / 2;
        while width > 0 {
            for lane in 0..width {
                entries[lane] = earlier(entries[lane], entries[lane + width]);
            }
            width /= 2;
        }
        (t_enter, t_exit, u64::from(hits) << lanes.start, entries[0])
    }
}

/// Traces up to [`MAX_PACKET`] rays through `tree` together, writing each ray's closest (or
/// any) hit to `hits`: the same answers as [`traverse_wide`] gives each ray.
///
/// A packet visits a node once for all its rays that reach it (Wald, Slusallek, Benthin &
/// Wagner 2001, "Interactive Rendering with Coherent Ray Tracing", there with four rays and a
/// binary tree): a child's box that the whole packet misses is rejected with one test of
/// bounds on the packet (interval arithmetic, Boulos et al. 2006); any other is tested
/// against every active ray, lanes of rays at a time; the children some ray hits are visited
/// nearest first by the nearest entry among their rays, each with the rays that hit it. Where
/// only a few rays are left (the packet has scattered), they go on one by one. Each ray's observer hears that ray's steps, as the
/// single-ray traversal would tell them (a packet may test a ray against boxes and leaves a
/// lone ray would have skipped, so counts can differ; answers do not).
pub fn traverse_packet<V, P, O, const W: usize>(
    tree: &WideBvh<V, W>,
    primitives: &P,
    rays: &[Ray<V>],
    options: &TraceOptions,
    stack: &mut PacketStack<V::Scalar>,
    observers: &mut [O],
    hits: &mut [Option<Hit<V::Scalar>>],
) where
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    crate::simd::traverse_packet(tree, primitives, rays, options, stack, observers, hits);
}

/// [`traverse_packet`] with the kernels of `K`.
#[inline(always)]
pub(crate) fn traverse_packet_with<K, V, P, O, const W: usize>(
    tree: &WideBvh<V, W>,
    primitives: &P,
    rays: &[Ray<V>],
    options: &TraceOptions,
    stack: &mut PacketStack<V::Scalar>,
    observers: &mut [O],
    hits: &mut [Option<Hit<V::Scalar>>],
) where
    K: Kernel,
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    assert!(
        rays.len() <= MAX_PACKET && observers.len() >= rays.len() && hits.len() >= rays.len(),
        "a packet holds at most {MAX_PACKET} rays, each with an observer and a hit"
    );
    hits.iter_mut().for_each(|hit| *hit = None);
    if tree.nodes.is_empty() || rays.is_empty() {
        return;
    }
    let mut states: Vec<RayState<'_, V, P>> = rays
        .iter()
        .map(|ray| RayState::new(primitives, ray, options))
        .collect();
    let mut lanes = PacketLanes {
        origin: [[V::Scalar::ZERO; MAX_PACKET]; 3],
        inv_direction: [[V::Scalar::ZERO; MAX_PACKET]; 3],
        negative: [[false; MAX_PACKET]; 3],
        t_min: [V::Scalar::ZERO; MAX_PACKET],
        t_closest: [V::Scalar::NEG_INFINITY; MAX_PACKET],
        far_scale: V::Scalar::ZERO,
    };
    for (ray, state) in states.iter().enumerate() {
        let slab_ray = SlabRay::new(state.ray, options.robust_traversal);
        for axis in 0..V::DIM {
            lanes.origin[axis][ray] = slab_ray.origin[axis];
            lanes.inv_direction[axis][ray] = slab_ray.inv_direction[axis];
            lanes.negative[axis][ray] = slab_ray.negative[axis];
        }
        lanes.far_scale = slab_ray.far_scale;
        lanes.t_min[ray] = state.ray.t_min;
        lanes.t_closest[ray] = state.search.t_closest;
    }
    let bounds = PacketBounds::new::<V>(&lanes, rays.len());
    // The least and the greatest search-interval end of the packet's rays, kept up to date
    // as leaves shrink them, so that a node costs no loop over the rays when none of them can
    // be culled there (the least), and a box's one test for the whole packet has a bound
    // (the greatest: finished and absent rays hold −∞ or their hit, at most an active ray's).
    let greatest_t_closest = |lanes: &PacketLanes<V::Scalar>| extremes(&lanes.t_closest).1;
    let mut t_closest_least = extremes(&lanes.t_closest[..rays.len()]).0;
    let mut t_farthest = greatest_t_closest(&lanes);
    // Set when a leaf shrank some ray's interval: `t_farthest` is then made again before it
    // is next needed (a stale one is larger, so only less tight).
    let mut t_farthest_stale = false;
    // Rays still searching (an any-hit query drops a ray at its first hit).
    let mut searching = if rays.len() == MAX_PACKET {
        u64::MAX
    } else {
        (1u64 << rays.len()) - 1
    };
    let nodes = tree.nodes.as_slice();
    let PacketStack { entries, single } = stack;
    entries.clear();
    entries.push(PacketPending {
        child: 0,
        count: 0,
        rays: searching,
        t_enter: bounds.t_min,
    });
    while let Some(PacketPending {
        child,
        count,
        rays: entry_rays,
        t_enter,
    }) = entries.pop()
    {
        let mut active = entry_rays & searching;
        // Rays that found a hit before the child's box skip it.
        let mut culled = 0u64;
        if t_enter > t_closest_least {
            for_each_ray(active, |ray| {
                culled |= u64::from(t_enter > lanes.t_closest[ray]) << ray;
            });
        }
        if O::ACTIVE {
            for_each_ray(culled, |ray| {
                observers[ray].node_culled(
                    tree.child_source(child, count),
                    t_enter,
                    lanes.t_closest[ray],
                );
            });
        }
        active &= !culled;
        if active == 0 {
            continue;
        }
        if active.count_ones() <= SCATTERED {
            // The packet has scattered: its last rays go on alone from here.
            for_each_ray(active, |ray| {
                let start = Pending {
                    child,
                    count,
                    t_enter,
                };
                let state = &mut states[ray];
                let mut search = state.search;
                state.run::<K, O, W>(
                    &mut search,
                    tree,
                    primitives,
                    SlabRay::new(state.ray, options.robust_traversal),
                    start,
                    options,
                    single,
                    &mut observers[ray],
                );
                state.search = search;
                lanes.t_closest[ray] = search.t_closest;
                t_closest_least = earlier(t_closest_least, search.t_closest);
            });
            t_farthest_stale = true;
            continue;
        }
        if O::ACTIVE {
            for_each_ray(active, |ray| {
                observers[ray].node_entered(tree.child_source(child, count))
            });
        }
        if count > 0 {
            let numbers = tree.leaf_primitives(child, count);
            for_each_ray(active, |ray| {
                let state = &mut states[ray];
                let mut search = state.search;
                let done = state.test_leaf::<K, O>(
                    &mut search,
                    primitives,
                    state.block_ray(),
                    child,
                    numbers,
                    &mut observers[ray],
                );
                state.search = search;
                if done {
                    searching &= !(1 << ray);
                }
                lanes.t_closest[ray] = search.t_closest;
                t_closest_least = earlier(t_closest_least, search.t_closest);
            });
            t_farthest_stale = true;
            continue;
        }
        // Every child's box against every active ray, a group of lanes at a time.
        let node = &nodes[child as usize];
        let mut children = [PacketPending {
            child: 0,
            count: 0,
            rays: 0,
            t_enter: V::Scalar::INFINITY,
        }; W];
        let mut used = 0;
        if t_farthest_stale {
            t_farthest = greatest_t_closest(&lanes);
            t_farthest_stale = false;
        }
        // One test rejects a box the whole packet misses (no ray's observer hears it).
        let missed = bounds.misses::<V, W>(node, t_farthest);
        // The groups of lanes with an active ray: the others are not tested.
        let mut groups = 0u64;
        for group in 0..MAX_PACKET / LANES {
            groups |= u64::from((active >> (group * LANES)) & ((1 << LANES) - 1) != 0) << group;
        }
        let tested = !u64::from(missed) & ((1 << node.slots_used()) - 1);
        for_each_ray(tested, |slot| {
            let mut slot_rays = 0u64;
            let mut nearest = V::Scalar::INFINITY;
            for_each_ray(groups, |group| {
                let group_rays = (active >> (group * LANES)) & ((1 << LANES) - 1);
                let (t_enter, t_exit, hit, group_nearest) =
                    lanes.test_box::<K, V, W>(node, slot, group, active);
                slot_rays |= hit;
                nearest = earlier(nearest, group_nearest);
                if O::ACTIVE {
                    let source = tree.slot_source(child as usize, slot);
                    for_each_ray(group_rays, |lane| {
                        let ray = group * LANES + lane;
                        observers[ray].box_tested(
                            source,
                            t_enter[lane],
                            t_exit[lane],
                            hit & (1 << ray) != 0,
                        );
                    });
                }
            });
            if slot_rays != 0 {
                children[used] = PacketPending {
                    child: node.child[slot],
                    count: node.count[slot],
                    rays: slot_rays,
                    t_enter: nearest,
                };
                used += 1;
            }
        });
        // Farthest pushed first, so the nearest comes off the stack next (stable: slot order
        // for equal entries, and for file order).
        if options.order == Order::NearFirst {
            for index in 1..used {
                let entry = children[index];
                let mut at = index;
                while at > 0 && children[at - 1].t_enter > entry.t_enter {
                    children[at] = children[at - 1];
                    at -= 1;
                }
                children[at] = entry;
            }
        }
        entries.extend(children[..used].iter().rev());
    }
    for (hit, state) in hits.iter_mut().zip(&states) {
        *hit = state.search.closest;
    }
}

/// Calls `visit` with the number of every set bit of `mask`, lowest first.
#[inline(always)]
fn for_each_ray(mut mask: u64, mut visit: impl FnMut(usize)) {
    while mask != 0 {
        visit(mask.trailing_zeros() as usize);
        mask &= mask - 1;
    }
}

impl<S: Real> HitSearch<S> {
    /// Tests a wide leaf's triangles a block of four at a time (`first` is its first slot, a
    /// multiple of four) with `test` (a block and the interval's end: each lane's `t` inside
    /// the interval, NaN where missed). The observer hears each triangle in slot order, hit
    /// only within the interval as it stood when the triangle's turn came, as if tested one
    /// by one: once an earlier lane of the block has shrunk the interval, a lane's hit is
    /// confirmed by `still_inside` (block, lane, its `t`, the interval's new end). The closest
    /// hit is then the one-by-one test's (the least `t`, ties to the lower number). Returns
    /// true when the search has its answer (as [`HitSearch::test_leaf`]).
    #[inline(always)]
    fn test_blocks<O: Observer<S>>(
        &mut self,
        blocks: &[TriangleBlock<S>],
        first: u32,
        numbers: &[u32],
        observer: &mut O,
        test: impl Fn(&TriangleBlock<S>, S) -> [S; 4],
        still_inside: impl Fn(&TriangleBlock<S>, usize, S, S) -> bool,
    ) -> bool {
        let mut leaf_done = false;
        for (block_index, block_numbers) in (first as usize / LEAF_BLOCK..).zip(numbers.chunks(4)) {
            let block = &blocks[block_index];
            let t_max = self.t_closest;
            let t_hits = test(block, t_max);
            // Most blocks are missed by every lane: then only an observer has work to do.
            let any_hit = t_hits.iter().any(|t| !t.is_nan());
            if !any_hit && !O::ACTIVE {
                continue;
            }
            for (lane, (&primitive, &t)) in block_numbers.iter().zip(&t_hits).enumerate() {
                let hit = !t.is_nan()
                    && (self.t_closest == t_max || still_inside(block, lane, t, self.t_closest));
                observer.primitive_tested(primitive, hit.then_some(t));
                if hit
                    && self
                        .closest
                        .is_none_or(|closest| closest.is_beaten_by(primitive, t))
                {
                    self.closest = Some(Hit { primitive, t });
                    self.t_closest = t;
                    observer.closest_hit_updated(primitive, t);
                    if self.ends_search(&mut leaf_done) {
                        return true;
                    }
                }
            }
        }
        leaf_done
    }
}

/// Pushes the children hit but the first to visit onto `pending`, farthest (or last) first,
/// and returns the one to visit and how many were pushed; `None` when no child is hit. One and
/// two hits, the common cases, take no loop (as in Embree's single-ray traversal); more are
/// sorted where they lie on the stack.
#[inline(always)]
fn visit_children<S: Real, const W: usize>(
    node: &WideNode<S, W>,
    tests: &ChildTests<S, W>,
    near_first: bool,
    pending: &mut PendingStack<'_, S>,
) -> Option<(Pending<S>, usize)> {
    let child = |slot: usize| Pending {
        child: node.child[slot],
        count: node.count[slot],
        t_enter: tests.t_enter[slot],
    };
    let mut mask = tests.hit_mask;
    if mask == 0 {
        return None;
    }
    let first = child(mask.trailing_zeros() as usize);
    mask &= mask - 1;
    if mask == 0 {
        return Some((first, 0));
    }
    let second = child(mask.trailing_zeros() as usize);
    mask &= mask - 1;
    pending.reserve(W);
    if mask == 0 {
        let (near, far) = if near_first && second.t_enter < first.t_enter {
            (second, first)
        } else {
            (first, second)
        };
        pending.push(far);
        return Some((near, 1));
    }
    // Three or more: pushed from the last slot to the first, each (near first) sunk below the
    // entries it is nearer than, so the nearest ends on top and equal entries keep slot order.
    let bottom = pending.top;
    let mut slots = mask;
    let mut last_slots = [0u8; W];
    let mut rest = 0;
    while slots != 0 {
        last_slots[rest] = slots.trailing_zeros() as u8;
        slots &= slots - 1;
        rest += 1;
    }
    let place = |entry: Pending<S>, pending: &mut PendingStack<'_, S>| {
        let mut at = pending.top;
        pending.push(entry);
        if near_first {
            while at > bottom && pending.slots[at - 1].t_enter < entry.t_enter {
                pending.slots[at] = pending.slots[at - 1];
                at -= 1;
            }
            pending.slots[at] = entry;
        }
    };
    for &slot in last_slots[..rest].iter().rev() {
        place(child(slot as usize), pending);
    }
    place(second, pending);
    place(first, pending);
    let pushed = pending.top - bottom - 1;
    let visited = pending.pop().unwrap_or(first);
    Some((visited, pushed))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stack spills its bottom half to the heap and brings it back, and stays a stack:
    /// against a `Vec`, through pushes and pops far deeper than its slots.
    #[test]
    fn pending_stack_spills_and_refills_in_order() {
        let mut storage = WideStack::<f32>::default();
        let mut stack = PendingStack::new(&mut storage);
        let mut model = Vec::new();
        let entry = |number: u32| Pending {
            child: number,
            count: number % 3,
            t_enter: number as f32,
        };
        let mut number = 0;
        // Grow by five and shrink by two, three hundred times, then empty it.
        for _ in 0..300 {
            stack.reserve(5);
            for _ in 0..5 {
                stack.push(entry(number));
                model.push(entry(number));
                number += 1;
            }
            for _ in 0..2 {
                let (got, want) = (stack.pop(), model.pop());
                assert_eq!(got.map(|e| e.child), want.map(|e| e.child));
            }
        }
        assert!(model.len() > 4 * STACK_SLOTS);
        while let Some(want) = model.pop() {
            let got = stack.pop().expect("as deep as the model");
            assert_eq!(
                (got.child, got.count, got.t_enter),
                (want.child, want.count, want.t_enter)
            );
        }
        assert!(stack.pop().is_none());
        // Emptied, it starts again from nothing.
        let mut stack = PendingStack::new(&mut storage);
        assert!(stack.pop().is_none());
    }
}
