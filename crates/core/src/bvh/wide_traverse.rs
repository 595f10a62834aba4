//! The one wide-BVH traversal: a node's children are tested together, the ones hit are
//! visited nearest first (or in slot order), and each step is told to the observer in the
//! binary tree's numbering (see [`WideBvh`]).
//!
//! Wald, Benthin & Boulos 2008, "Getting rid of packets: efficient SIMD single-ray traversal
//! using multi-branching BVHs": one ray against the `W` boxes of a node at once, instead of a
//! packet of rays against one box.

use crate::bvh::wide::{LEAF_BLOCK, WideBvh, WideNode};
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::{HitTest, LeafPrimitives, PrimitiveSet, TriangleBlock, TriangleRay};
use crate::query::{Hit, Order, TraceOptions};
use crate::ray::Ray;
use crate::search::{HitSearch, NoMemory};
use crate::simd::{
    ChildTests, Kernel, KernelJob, NodeLanes, prefetch_lines, run_with_active_kernels,
};
use crate::slab::SlabRay;

/// One child waiting to be visited: a wide node or a leaf, and where the ray enters its box.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pending<S: Real> {
    /// A node's index or a leaf's first slot.
    pub(crate) child: u32,
    /// A leaf's primitive count; 0 for a node.
    pub(crate) count: u32,
    pub(crate) t_enter: S,
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
    run_with_active_kernels(WideTrace {
        tree,
        primitives,
        ray,
        options,
        stack,
        observer,
    })
}

/// One ray's wide traversal as work over the kernels, for
/// [`run_with_active_kernels`](crate::simd::run_with_active_kernels): [`traverse_wide`]'s
/// arguments.
pub(crate) struct WideTrace<'a, V: Vector, P, O, const W: usize> {
    pub(crate) tree: &'a WideBvh<V, W>,
    pub(crate) primitives: &'a P,
    pub(crate) ray: &'a Ray<V>,
    pub(crate) options: &'a TraceOptions,
    pub(crate) stack: &'a mut WideStack<V::Scalar>,
    pub(crate) observer: &'a mut O,
}

impl<V, P, O, const W: usize> KernelJob for WideTrace<'_, V, P, O, W>
where
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    type Output = Option<Hit<V::Scalar>>;

    #[inline(always)]
    fn run<K: Kernel>(self) -> Self::Output {
        traverse_wide_with::<K, V, P, O, W>(
            self.tree,
            self.primitives,
            self.ray,
            self.options,
            self.stack,
            self.observer,
        )
    }
}

/// [`traverse_wide`] with the kernels of `K`: compiled once per instruction set.
#[inline(always)]
fn traverse_wide_with<K, V, P, O, const W: usize>(
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
    pub(crate) fn root(t_min: S) -> Self {
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
pub(crate) struct RayState<'a, V: Vector, P: LeafPrimitives<V>> {
    pub(crate) ray: &'a Ray<V>,
    primitive_ray: <P::Set as PrimitiveSet<V>>::RayData,
    /// The triangle blocks, when the set has them (3D triangles in a wide BVH's leaf order).
    blocks: Option<&'a [TriangleBlock<V::Scalar>]>,
    pub(crate) search: HitSearch<V::Scalar>,
}

impl<'a, V: Vector, P: LeafPrimitives<V>> RayState<'a, V, P> {
    #[inline(always)]
    pub(crate) fn new(primitives: &'a P, ray: &'a Ray<V>, options: &TraceOptions) -> Self {
        Self {
            ray,
            primitive_ray: primitives.stored().prepare(ray, options.hit_test),
            blocks: primitives.triangle_blocks(),
            search: HitSearch::new(ray.t_max, options.query),
        }
    }

    /// The ray prepared for triangle tests, when the set is one of triangles (a set with
    /// blocks is).
    #[inline(always)]
    pub(crate) fn block_ray(&self) -> Option<&TriangleRay<<V::Scalar as Real>::Vec3>> {
        <P::Set as PrimitiveSet<V>>::block_ray(&self.primitive_ray)
    }

    /// Tests a leaf's primitives into `search` (this ray's, held apart so that the loop can
    /// keep it in registers); true when an any-hit query has its answer.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn test_leaf<K: Kernel, O: Observer<V::Scalar>>(
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
            &mut NoMemory,
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
    pub(crate) fn run<K: Kernel, O: Observer<V::Scalar>, const W: usize>(
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
        let node_lanes = NodeLanes::<V::Scalar, W>::new(&slab_ray);
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
                let tests: ChildTests<V::Scalar, W> =
                    K::test_children(&node.planes, &node_lanes, V::DIM, search.t_closest);
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
                if hit && self.offer(primitive, t, observer, &mut leaf_done) {
                    return true;
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
pub(crate) mod tests {
    use glam::Vec3;

    use super::*;
    use crate::bvh::{BinnedSah, Builder, collapse};
    use crate::observer::{Counters, NoObserver};
    use crate::params::BuildParams;
    use crate::primitive::TriangleSet;
    use crate::simd::{Isa, run_with};

    /// `count` small triangles scattered in a 10-unit cube (seeded: the same every run), and a
    /// source of more points in it.
    pub(crate) fn scattered_triangles(
        seed: u64,
        count: usize,
        size: f32,
    ) -> (TriangleSet<Vec3>, impl FnMut() -> Vec3) {
        let mut state = seed;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut point = move || Vec3::new(next(), next(), next()) * 10.0;
        let corners: Vec<[[f64; 3]; 3]> = (0..count)
            .map(|_| {
                let a = point();
                [a, a + (point() - a) * size, a + (point() - a) * size]
                    .map(|v| v.as_dvec3().to_array())
            })
            .collect();
        (TriangleSet::<Vec3>::from_f64(&corners), point)
    }

    /// Whole traversals on every instruction set: the same hits and the same steps, for trees
    /// of 4 and 8 children, both orders, fast and robust; and the same hits as the triangles
    /// tested one by one (not in blocks).
    #[test]
    fn every_instruction_set_traces_the_same_hits_and_steps() {
        let (triangles, mut point) = scattered_triangles(3, 3000, 0.05);
        let binary = BinnedSah { bins: 16 }.build(&triangles.all_bounds(), &BuildParams::default());
        let cost = BuildParams::default().cost;
        let four: WideBvh<Vec3, 4> = collapse(binary.clone(), &cost);
        let eight: WideBvh<Vec3, 8> = collapse(binary, &cost);
        let (ordered4, ordered8) = (
            four.leaf_ordered(&triangles),
            eight.leaf_ordered(&triangles),
        );
        let rays: Vec<Ray<Vec3>> = (0..2000)
            .filter_map(|_| {
                let origin = point() * 3.0 - Vec3::splat(10.0);
                Ray::try_new(origin, point() - origin).ok()
            })
            .collect();
        let mut stack = WideStack::default();
        for robust in [false, true] {
            for order in [Order::NearFirst, Order::FileOrder] {
                let options = TraceOptions {
                    order,
                    ..TraceOptions::default()
                }
                .with_robust(robust);
                for ray in &rays {
                    let mut reference = None;
                    for isa in Isa::ALL.into_iter().filter(|isa| isa.is_available()) {
                        let mut counters = [Counters::default(); 2];
                        let [counters4, counters8] = &mut counters;
                        let hit4 = run_with(
                            isa,
                            WideTrace {
                                tree: &four,
                                primitives: &ordered4,
                                ray,
                                options: &options,
                                stack: &mut stack,
                                observer: counters4,
                            },
                        );
                        let hit8 = run_with(
                            isa,
                            WideTrace {
                                tree: &eight,
                                primitives: &ordered8,
                                ray,
                                options: &options,
                                stack: &mut stack,
                                observer: counters8,
                            },
                        );
                        let plain = run_with(
                            Isa::Portable,
                            WideTrace {
                                tree: &eight,
                                primitives: &triangles,
                                ray,
                                options: &options,
                                stack: &mut WideStack::default(),
                                observer: &mut NoObserver,
                            },
                        );
                        assert_eq!(hit8, plain, "{isa:?} blocks against one by one");
                        let got = (hit4, hit8, counters);
                        match &reference {
                            None => reference = Some(got),
                            Some(expected) => assert_eq!(&got, expected, "{isa:?} {options:?}"),
                        }
                    }
                }
            }
        }
    }

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
