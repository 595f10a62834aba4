//! The one wide-BVH traversal: a node's children are tested together, the ones hit are
//! visited nearest first (or in slot order), and each step is told to the observer in the
//! binary tree's numbering (see [`WideBvh`]).
//!
//! Wald, Benthin & Boulos 2008, "Getting rid of packets: efficient SIMD single-ray traversal
//! using multi-branching BVHs": one ray against the `W` boxes of a node at once, instead of a
//! packet of rays against one box.

use std::any::Any;

use glam::Vec3;

use crate::bvh::wide::{LEAF_BLOCK, WideBvh, WideNode};
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::{HitTest, LeafPrimitives, PrimitiveSet, TriangleBlock};
use crate::query::{Hit, Order, Query, TraceOptions};
use crate::ray::Ray;
use crate::search::HitSearch;
use crate::simd::Kernel;
use crate::slab::SlabRay;

/// One child waiting to be visited: a wide node or a leaf, and where the ray enters its box.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pending<S: Real> {
    /// A node's index or a leaf's first slot.
    child: u32,
    /// A leaf's primitive count; 0 for a node.
    count: u32,
    t_enter: S,
}

/// Reusable stack for [`traverse_wide`]: make one per thread, so tracing allocates nothing per
/// ray.
#[derive(Clone, Debug, Default)]
pub struct WideStack<S: Real> {
    entries: Vec<Pending<S>>,
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
        let (near, far) = if ray.negative[axis] {
            (&node.upper[axis], &node.lower[axis])
        } else {
            (&node.lower[axis], &node.upper[axis])
        };
        let origin = ray.origin[axis];
        let inverse = ray.inv_direction[axis];
        for slot in 0..W {
            let t_near = (near[slot] - origin) * inverse;
            let t_far = (far[slot] - origin) * inverse;
            // `a > b ? a : b` ignores a NaN `a` (see the slab module).
            t_enter[slot] = if t_near > t_enter[slot] {
                t_near
            } else {
                t_enter[slot]
            };
            t_exit[slot] = if t_far < t_exit[slot] {
                t_far
            } else {
                t_exit[slot]
            };
        }
    }
    let mut hit_mask = 0;
    for slot in 0..W {
        let scaled = t_exit[slot] * ray.far_scale;
        t_exit[slot] = if scaled < t_max { scaled } else { t_max };
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
    let slab_ray = SlabRay::new(ray, options.robust_traversal);
    let primitive_ray = primitives.stored().prepare(ray, options.hit_test);
    // Blocks of four triangles are 3D f32 (the type test is resolved at compile time), and
    // hold the fast test's arithmetic.
    let block_ray = (ray as &dyn Any).downcast_ref::<Ray<Vec3>>();
    let blocks = match (primitives.triangle_blocks(), block_ray, options.hit_test) {
        (Some(blocks), Some(block_ray), HitTest::Fast) => Some((blocks, block_ray)),
        _ => None,
    };
    let mut search = HitSearch::new(ray.t_max, options.query);
    let nodes = tree.nodes.as_slice();
    let entries = &mut stack.entries;
    entries.clear();
    let mut current = Some(Pending {
        child: 0,
        count: 0,
        t_enter: ray.t_min,
    });
    while let Some(Pending {
        child,
        count,
        t_enter,
    }) = current.take().or_else(|| entries.pop())
    {
        if t_enter > search.t_closest {
            if O::ACTIVE {
                observer.node_culled(tree.source(child, count), t_enter, search.t_closest);
            }
            continue;
        }
        if O::ACTIVE {
            observer.node_entered(tree.source(child, count));
        }
        if count > 0 {
            let numbers = tree.leaf_primitives(child, count);
            let done = match blocks {
                Some((blocks, block_ray)) => {
                    search.test_blocks::<K, O>(blocks, block_ray, child, numbers, observer)
                }
                None => search.test_leaf(
                    primitives,
                    &primitive_ray,
                    ray.t_min,
                    child as usize,
                    numbers,
                    |_| false,
                    observer,
                ),
            };
            if done {
                return search.closest;
            }
            continue;
        }
        let node = &nodes[child as usize];
        let tests = K::test_children(node, &slab_ray, search.t_closest);
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
        current = visit_children(node, &tests, options.order, entries);
    }
    search.closest
}

impl<S: Real> HitSearch<S> {
    /// Tests a wide leaf's triangles a block of four at a time (`first` is its first slot, a
    /// multiple of four). The observer hears each triangle in slot order, hit only within
    /// the interval as it stood when the triangle's turn came, as if tested one by one; the
    /// closest hit is the same either way (the least `t`, ties to the lower number). Returns
    /// true when an any-hit query has its answer.
    #[inline(always)]
    fn test_blocks<K: Kernel, O: Observer<S>>(
        &mut self,
        blocks: &[TriangleBlock],
        ray: &Ray<Vec3>,
        first: u32,
        numbers: &[u32],
        observer: &mut O,
    ) -> bool {
        let t_min = ray.t_min;
        for (block_index, block_numbers) in (first as usize / LEAF_BLOCK..).zip(numbers.chunks(4)) {
            let t_hits = K::test_triangles(
                &blocks[block_index],
                ray.origin,
                ray.direction,
                t_min,
                self.t_closest.to_f64() as f32,
            );
            // Most blocks are missed by every lane: then only an observer has work to do.
            let any_hit = t_hits.iter().any(|t| !t.is_nan());
            if !any_hit && !O::ACTIVE {
                continue;
            }
            for (&primitive, &t) in block_numbers.iter().zip(&t_hits) {
                let t = S::from_f32(t);
                let hit = t <= self.t_closest;
                observer.primitive_tested(primitive, hit.then_some(t));
                if hit
                    && self
                        .closest
                        .is_none_or(|closest| closest.is_beaten_by(primitive, t))
                {
                    self.closest = Some(Hit { primitive, t });
                    self.t_closest = t;
                    observer.closest_hit_updated(primitive, t);
                    if self.query == Query::Any {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// Pushes the children hit, farthest (or last) first, and returns the one to visit next.
/// One and two hits, the common cases, take no loop (as in Embree's single-ray traversal).
#[inline(always)]
fn visit_children<S: Real, const W: usize>(
    node: &WideNode<S, W>,
    tests: &ChildTests<S, W>,
    order: Order,
    entries: &mut Vec<Pending<S>>,
) -> Option<Pending<S>> {
    let pending = |slot: usize| Pending {
        child: node.child[slot],
        count: node.count[slot],
        t_enter: tests.t_enter[slot],
    };
    let mut mask = tests.hit_mask;
    if mask == 0 {
        return None;
    }
    let first = mask.trailing_zeros() as usize;
    mask &= mask - 1;
    if mask == 0 {
        return Some(pending(first));
    }
    let second = mask.trailing_zeros() as usize;
    mask &= mask - 1;
    let near_first = order == Order::NearFirst;
    if mask == 0 {
        let (near, far) = if near_first && tests.t_enter[second] < tests.t_enter[first] {
            (second, first)
        } else {
            (first, second)
        };
        entries.push(pending(far));
        return Some(pending(near));
    }
    // Three or more: the slots hit, sorted by entry (near first) with an insertion sort that
    // keeps slot order for equal entries.
    let mut slots = [0u8; W];
    slots[0] = first as u8;
    slots[1] = second as u8;
    let mut hit_count = 2;
    while mask != 0 {
        slots[hit_count] = mask.trailing_zeros() as u8;
        mask &= mask - 1;
        hit_count += 1;
    }
    if near_first {
        for index in 1..hit_count {
            let slot = slots[index];
            let t_enter = tests.t_enter[slot as usize];
            let mut at = index;
            while at > 0 && tests.t_enter[slots[at - 1] as usize] > t_enter {
                slots[at] = slots[at - 1];
                at -= 1;
            }
            slots[at] = slot;
        }
    }
    entries.extend(
        slots[1..hit_count]
            .iter()
            .rev()
            .map(|&slot| pending(slot as usize)),
    );
    Some(pending(slots[0] as usize))
}

impl<V: Vector, const W: usize> WideBvh<V, W> {
    /// The binary node a pending child stands for.
    #[inline(always)]
    fn source(&self, child: u32, count: u32) -> u32 {
        match count {
            0 => self.node_sources[child as usize],
            _ => self.leaf_sources[child as usize / LEAF_BLOCK],
        }
    }
}
