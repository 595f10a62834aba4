//! The wide BVH's packet traversal: up to 64 rays through a node at once, for coherent rays
//! (a camera's tiles). Each ray gets the answer [`traverse_wide`](super::traverse_wide) gives
//! it alone.

use crate::bvh::wide::{LEAF_BLOCK, LOWER, UPPER, WideBvh, WideNode};
use crate::bvh::wide_traverse::{Pending, RayState, WideStack};
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::{HitTest, LeafPrimitives, TriangleBlock};
use crate::query::{Hit, Order, TraceOptions};
use crate::ray::Ray;
use crate::simd::{
    BoxAgainstRays, Kernel, KernelJob, LANES, MAX_PACKET, PacketLanes, run_with_active_kernels,
};
use crate::slab::{SlabRay, earlier, far_scale, later, reciprocal};

/// A packet with this many active rays or fewer goes on ray by ray: what a packet saves (one
/// visit of a node for many rays) is gone, and a ray alone skips what it does not need.
const SCATTERED: u32 = 2;

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
    /// The packet's rays in lanes, kept from packet to packet (filling the lanes of rays a
    /// packet does not have cost as much as a small mesh's rays that miss it).
    lanes: Box<PacketLanes<S>>,
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

/// The slab test of one box (slot `slot` of `node`, its first `dims` axes) against the rays
/// of lane group `group` (with the kernels of `K`): each ray's interval, which of the rays in
/// `active` (the packet's bits) hit, and the nearest entry among those.
#[inline(always)]
fn test_box<K: Kernel, S: Real, const W: usize>(
    lanes: &PacketLanes<S>,
    node: &WideNode<S, W>,
    slot: usize,
    group: usize,
    dims: usize,
    active: u64,
) -> ([S; LANES], [S; LANES], u64, S) {
    let rays = group * LANES..group * LANES + LANES;
    let lower = std::array::from_fn(|axis| node.planes[LOWER][axis][slot]);
    let upper = std::array::from_fn(|axis| node.planes[UPPER][axis][slot]);
    let group_active = ((active >> rays.start) & ((1 << LANES) - 1)) as u32;
    let BoxAgainstRays {
        t_enter,
        t_exit,
        hits,
        mut entries,
    } = K::box_against_rays(lanes, lower, upper, rays.start, dims, group_active);
    // The least entry of the rays that hit, taken pairwise (entries are never NaN: they
    // start at `t_min`, and `later` ignores NaN).
    let mut width = LANES / 2;
    while width > 0 {
        for lane in 0..width {
            entries[lane] = earlier(entries[lane], entries[lane + width]);
        }
        width /= 2;
    }
    (t_enter, t_exit, u64::from(hits) << rays.start, entries[0])
}

/// Traces up to [`MAX_PACKET`] rays through `tree` together, writing each ray's closest (or
/// any) hit to `hits`: the same answers as [`traverse_wide`](super::traverse_wide) gives each
/// ray.
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
    run_with_active_kernels(PacketTrace {
        tree,
        primitives,
        rays,
        options,
        stack,
        observers,
        hits,
    });
}

/// A packet's traversal as work over the kernels: [`traverse_packet`]'s arguments.
pub(crate) struct PacketTrace<'a, V: Vector, P, O, const W: usize> {
    pub(crate) tree: &'a WideBvh<V, W>,
    pub(crate) primitives: &'a P,
    pub(crate) rays: &'a [Ray<V>],
    pub(crate) options: &'a TraceOptions,
    pub(crate) stack: &'a mut PacketStack<V::Scalar>,
    pub(crate) observers: &'a mut [O],
    pub(crate) hits: &'a mut [Option<Hit<V::Scalar>>],
}

impl<V, P, O, const W: usize> KernelJob for PacketTrace<'_, V, P, O, W>
where
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    type Output = ();

    #[inline(always)]
    fn run<K: Kernel>(self) {
        traverse_packet_with::<K, V, P, O, W>(
            self.tree,
            self.primitives,
            self.rays,
            self.options,
            self.stack,
            self.observers,
            self.hits,
        );
    }
}

/// [`traverse_packet`] with the kernels of `K`.
#[inline(always)]
fn traverse_packet_with<K, V, P, O, const W: usize>(
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
    // A ray's state (its triangle set-up and its search) is made when it first reaches a
    // leaf or leaves the packet: on a small mesh most of a camera's rays miss every box, and
    // set them up for nothing (suzanne: 83 % of them).
    let mut states: [Option<RayState<'_, V, P>>; MAX_PACKET] = [const { None }; MAX_PACKET];
    let PacketStack {
        entries,
        single,
        lanes,
    } = stack;
    // The lanes past the packet's last ray keep an earlier packet's values: every test masks
    // them off, but the packet's greatest interval end is taken over all of them, so theirs
    // is −∞.
    lanes.t_closest[rays.len()..].fill(V::Scalar::NEG_INFINITY);
    // What `SlabRay::new` prepares, an axis at a time straight into the lanes (zipped, so
    // that no store is checked against the lanes' length).
    for axis in 0..V::DIM {
        let rows = lanes.origin[axis]
            .iter_mut()
            .zip(&mut lanes.direction[axis])
            .zip(&mut lanes.inv_direction[axis])
            .zip(&mut lanes.negative[axis]);
        for ((((origin, direction), inverse), negative), ray) in rows.zip(rays) {
            *origin = ray.origin[axis];
            *direction = ray.direction[axis];
            (*inverse, *negative) = reciprocal(ray.direction[axis]);
        }
    }
    lanes.far_scale = far_scale(options.robust_traversal);
    let interval = lanes.t_min.iter_mut().zip(&mut lanes.t_closest);
    for ((t_min, t_closest), ray) in interval.zip(rays) {
        *t_min = ray.t_min;
        // A search starts with the ray's whole interval (`HitSearch::new`).
        *t_closest = ray.t_max;
    }
    let lanes: &mut PacketLanes<V::Scalar> = lanes;
    let bounds = PacketBounds::new::<V>(lanes, rays.len());
    // The least and the greatest search-interval end of the packet's rays, kept up to date
    // as leaves shrink them, so that a node costs no loop over the rays when none of them can
    // be culled there (the least), and a box's one test for the whole packet has a bound
    // (the greatest: finished and absent rays hold −∞ or their hit, at most an active ray's).
    let greatest_t_closest = |lanes: &PacketLanes<V::Scalar>| extremes(&lanes.t_closest).1;
    let mut t_closest_least = extremes(&lanes.t_closest[..rays.len()]).0;
    let mut t_farthest = greatest_t_closest(lanes);
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
                let state = states[ray]
                    .get_or_insert_with(|| RayState::new(primitives, &rays[ray], options));
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
            match primitives.triangle_blocks() {
                // The fast test, each triangle against the packet's rays a group of lanes at
                // a time, where that takes fewer tests; a ray's state is made only when it
                // hits.
                Some(blocks)
                    if options.hit_test == HitTest::Fast && fewer_by_triangle(active, count) =>
                {
                    let (done, least) = test_leaf_by_triangle::<K, V, P, O>(
                        &blocks[child as usize / LEAF_BLOCK..],
                        numbers,
                        active,
                        lanes,
                        &mut states,
                        |ray| RayState::new(primitives, &rays[ray], options),
                        observers,
                    );
                    searching &= !done;
                    t_closest_least = earlier(t_closest_least, least);
                }
                _ => for_each_ray(active, |ray| {
                    let state = states[ray]
                        .get_or_insert_with(|| RayState::new(primitives, &rays[ray], options));
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
                }),
            }
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
            t_farthest = greatest_t_closest(lanes);
            t_farthest_stale = false;
        }
        // One test rejects a box the whole packet misses (no ray's observer hears it).
        let missed = bounds.misses::<V, W>(node, t_farthest);
        // The groups of lanes with an active ray: the others are not tested.
        let groups = groups_with(active);
        let tested = !u64::from(missed) & ((1 << node.slots_used()) - 1);
        for_each_ray(tested, |slot| {
            let mut slot_rays = 0u64;
            let mut nearest = V::Scalar::INFINITY;
            for_each_ray(groups, |group| {
                let group_rays = (active >> (group * LANES)) & ((1 << LANES) - 1);
                let (t_enter, t_exit, hit, group_nearest) =
                    test_box::<K, V::Scalar, W>(lanes, node, slot, group, V::DIM, active);
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
    for (hit, state) in hits.iter_mut().zip(&states[..rays.len()]) {
        *hit = state.as_ref().and_then(|state| state.search.closest);
    }
}

/// Tests a leaf's triangles (`numbers`, from the first of `blocks` on) against the packet's
/// rays `active`, each triangle against a group of [`LANES`] rays at a time with the fast
/// test: each ray's observer hears the triangles in the order a ray alone tests them, and its
/// search ends where a ray alone would end it. A ray's state is made (`make_state`) when it
/// first hits. Returns the rays whose search has its answer, and the least interval end.
#[inline(always)]
fn test_leaf_by_triangle<'a, K, V, P, O>(
    blocks: &[TriangleBlock<V::Scalar>],
    numbers: &[u32],
    active: u64,
    lanes: &mut PacketLanes<V::Scalar>,
    states: &mut [Option<RayState<'a, V, P>>; MAX_PACKET],
    make_state: impl Fn(usize) -> RayState<'a, V, P>,
    observers: &mut [O],
) -> (u64, V::Scalar)
where
    K: Kernel,
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    let mut testing = active;
    let mut done = 0u64;
    let mut least = V::Scalar::INFINITY;
    for (block, block_numbers) in blocks.iter().zip(numbers.chunks(4)) {
        for (lane, &primitive) in block_numbers.iter().enumerate() {
            for group in 0..MAX_PACKET / LANES {
                let first = group * LANES;
                let group_rays = (testing >> first) & ((1 << LANES) - 1);
                if group_rays == 0 {
                    continue;
                }
                let (t_hits, hits) = K::triangle_against_rays(block, lane, lanes, first);
                // Without an observer, only the rays hit have anything to do.
                let heard = if O::ACTIVE {
                    group_rays
                } else {
                    group_rays & u64::from(hits)
                };
                for_each_ray(heard << first, |ray| {
                    let t = t_hits[ray - first];
                    let hit = !t.is_nan();
                    observers[ray].primitive_tested(primitive, hit.then_some(t));
                    if !hit {
                        return;
                    }
                    let state = states[ray].get_or_insert_with(|| make_state(ray));
                    let mut leaf_done = false;
                    if state
                        .search
                        .offer(primitive, t, &mut observers[ray], &mut leaf_done)
                    {
                        testing &= !(1 << ray);
                    }
                    // (A query that ends with the leaf tests the rest of it first.)
                    done |= u64::from(leaf_done) << ray;
                    lanes.t_closest[ray] = state.search.t_closest;
                    least = earlier(least, state.search.t_closest);
                });
            }
        }
    }
    (done | (active & !testing), least)
}

/// Whether a leaf of `count` triangles takes fewer kernel calls tested triangle by triangle
/// against the groups of `rays` than ray by ray against its blocks of four. One call of
/// either kind costs about the same instructions, so the rays crowding a few groups (a small
/// mesh's camera rays) choose the first, rays scattered over the groups the second.
#[inline(always)]
fn fewer_by_triangle(rays: u64, count: u32) -> bool {
    count * groups_with(rays).count_ones() < rays.count_ones() * count.div_ceil(4)
}

/// The groups of [`LANES`] rays with a ray of `rays` in them, as bits.
#[inline(always)]
fn groups_with(rays: u64) -> u64 {
    let mut groups = 0u64;
    for group in 0..MAX_PACKET / LANES {
        groups |= u64::from((rays >> (group * LANES)) & ((1 << LANES) - 1) != 0) << group;
    }
    groups
}

/// Calls `visit` with the number of every set bit of `mask`, lowest first.
#[inline(always)]
fn for_each_ray(mut mask: u64, mut visit: impl FnMut(usize)) {
    while mask != 0 {
        visit(mask.trailing_zeros() as usize);
        mask &= mask - 1;
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::bvh::traverse_wide;
    use crate::bvh::wide_traverse::tests::scattered_triangles;
    use crate::bvh::wide_traverse::{WideStack, WideTrace};
    use crate::bvh::{BinnedSah, Builder, collapse};
    use crate::observer::{Counters, NoObserver};
    use crate::params::BuildParams;
    use crate::primitive::PrimitiveSet;
    use crate::query::Query;
    use crate::simd::{Isa, run_with};

    /// Packets on every instruction set: the same hits as the portable packets, and as each
    /// ray alone where no two triangles tie.
    #[test]
    fn every_instruction_set_traces_packets_alike() {
        let (triangles, _) = scattered_triangles(11, 2000, 0.08);
        let binary = BinnedSah { bins: 16 }.build(&triangles.all_bounds(), &BuildParams::default());
        let eight: WideBvh<Vec3, 8> = collapse(binary, &BuildParams::default().cost);
        let ordered = eight.leaf_ordered(&triangles);
        // A camera-like fan of rays: neighbours in a packet are coherent.
        let origin = Vec3::new(5.0, 5.0, -20.0);
        let rays: Vec<Ray<Vec3>> = (0..64 * 40)
            .filter_map(|index| {
                let (x, y) = ((index % 64) as f32 / 64.0, (index / 64) as f32 / 40.0);
                Ray::try_new(origin, Vec3::new(x * 10.0 - 5.0, y * 10.0 - 5.0, 20.0)).ok()
            })
            .collect();
        let options = TraceOptions::default();
        let mut stack = PacketStack::default();
        // Every query and test, traced in packets with and without observers.
        for options in [
            options,
            TraceOptions {
                query: Query::Any,
                order: Order::FileOrder,
                ..options
            },
            TraceOptions {
                hit_test: HitTest::Watertight,
                robust_traversal: true,
                ..options
            },
        ] {
            for packet in rays.chunks(64) {
                let mut hits = vec![None; packet.len()];
                let mut observed_hits = vec![None; packet.len()];
                let mut counters = vec![Counters::default(); packet.len()];
                let mut unobserved = vec![NoObserver; packet.len()];
                let (stack, tree) = (&mut PacketStack::default(), &eight);
                traverse_packet(
                    tree,
                    &ordered,
                    packet,
                    &options,
                    stack,
                    &mut unobserved,
                    &mut hits,
                );
                traverse_packet(
                    tree,
                    &ordered,
                    packet,
                    &options,
                    stack,
                    &mut counters,
                    &mut observed_hits,
                );
                assert_eq!(hits, observed_hits, "{options:?}: observed packets");
                for ((ray, hit), counters) in packet.iter().zip(&hits).zip(&counters) {
                    let alone = traverse_wide(
                        &eight,
                        &ordered,
                        ray,
                        &options,
                        &mut WideStack::default(),
                        &mut NoObserver,
                    );
                    match options.query {
                        Query::Closest => assert_eq!(*hit, alone, "{options:?}: {ray:?}"),
                        _ => assert_eq!(hit.is_some(), alone.is_some(), "{options:?}: {ray:?}"),
                    }
                    // Each ray's observer heard a test of the triangle it hit.
                    assert!(hit.is_none() || counters.primitive_tests > 0);
                }
            }
        }
        let alone: Vec<_> = rays
            .iter()
            .map(|ray| {
                run_with(
                    Isa::Portable,
                    WideTrace {
                        tree: &eight,
                        primitives: &ordered,
                        ray,
                        options: &options,
                        stack: &mut WideStack::default(),
                        observer: &mut NoObserver,
                    },
                )
            })
            .collect();
        assert!(alone.iter().filter(|hit| hit.is_some()).count() > rays.len() / 10);
        for isa in Isa::ALL.into_iter().filter(|isa| isa.is_available()) {
            let mut hits = vec![None; rays.len()];
            for (packet, packet_hits) in rays.chunks(64).zip(hits.chunks_mut(64)) {
                let mut observers = vec![Counters::default(); packet.len()];
                run_with(
                    isa,
                    PacketTrace {
                        tree: &eight,
                        primitives: &ordered,
                        rays: packet,
                        options: &options,
                        stack: &mut stack,
                        observers: &mut observers,
                        hits: packet_hits,
                    },
                );
            }
            assert_eq!(hits, alone, "{isa:?}: packets against single rays");
        }
    }
}
