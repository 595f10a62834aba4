//! The one BVH traversal: closest or any hit, near-first or file order, told to an observer.

use crate::bvh::tree::Bvh;
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::{LeafPrimitives, PrimitiveSet};
use crate::query::{Hit, Order, TraceOptions};
use crate::ray::Ray;
use crate::search::{HitSearch, NoMemory};
use crate::slab::{SlabRay, slab_clip};

/// Reusable traversal stack: make one per thread and pass it to every [`traverse`] call, so
/// tracing allocates nothing per ray.
#[derive(Clone, Debug, Default)]
pub struct TraversalStack<S: Real> {
    /// Nodes still to visit, with the `t` at which the ray enters each.
    entries: Vec<(u32, S)>,
}

impl<S: Real> TraversalStack<S> {
    /// An empty stack with room for a deep tree.
    pub fn new() -> Self {
        Self {
            entries: Vec::with_capacity(64),
        }
    }
}

/// Traces `ray` through `bvh` over `primitives` (a [`PrimitiveSet`] in its own numbering, or
/// the tree's [`leaf_ordered`](Bvh::leaf_ordered) copy of one).
///
/// Test the root's box; then, node by node: skip a node that starts beyond the closest hit so
/// far (a cull); test a leaf's primitives, shrinking the interval at each hit; test both
/// children's boxes of an interior node, visit the one chosen by [`Order`] next and push the
/// other. When a subtree is done, the next node comes off the stack.
pub fn traverse<V, P, O>(
    bvh: &Bvh<V>,
    primitives: &P,
    ray: &Ray<V>,
    options: &TraceOptions,
    stack: &mut TraversalStack<V::Scalar>,
    observer: &mut O,
) -> Option<Hit<V::Scalar>>
where
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    let root = bvh.nodes.first()?;
    let slab_ray = SlabRay::new(ray, options.robust_traversal);
    let (t_enter, t_exit) = slab_clip(&root.bounds, &slab_ray, ray.t_max);
    observer.box_tested(0, t_enter, t_exit, t_enter <= t_exit);
    if t_enter > t_exit {
        return None;
    }
    let primitive_ray = primitives.stored().prepare(ray, options.hit_test);
    let mut search = HitSearch::new(ray.t_max, options.query);
    let nodes = bvh.nodes.as_slice();
    let entries = &mut stack.entries;
    entries.clear();
    // The node being visited and where the ray enters it; the far children wait on the stack.
    let mut current = Some((0u32, t_enter));
    while let Some((node_index, t_enter)) = current.take().or_else(|| entries.pop()) {
        // A hit found since this node was pushed may already be nearer than its box.
        if t_enter > search.t_closest {
            observer.node_culled(node_index, t_enter, search.t_closest);
            continue;
        }
        observer.node_entered(node_index);
        let node = &nodes[node_index as usize];
        if node.is_leaf() {
            // Test the leaf's primitives, shrinking the interval with every closer hit.
            let numbers = bvh.leaf_primitives(node);
            let first = node.first as usize;
            if search.test_leaf(
                primitives,
                &primitive_ray,
                ray.t_min,
                first,
                numbers,
                &mut NoMemory,
                observer,
            ) {
                return search.closest;
            }
            continue;
        }
        // Test both children's boxes against what is left of the interval.
        let [left, right] = node.children();
        let (left_enter, left_exit) =
            slab_clip(&nodes[left as usize].bounds, &slab_ray, search.t_closest);
        let (right_enter, right_exit) =
            slab_clip(&nodes[right as usize].bounds, &slab_ray, search.t_closest);
        let left_hit = left_enter <= left_exit;
        let right_hit = right_enter <= right_exit;
        observer.box_tested(left, left_enter, left_exit, left_hit);
        observer.box_tested(right, right_enter, right_exit, right_hit);
        current = match (left_hit, right_hit) {
            (true, true) => {
                // Visit one child next and keep the other on the stack for later.
                let right_first = options.order == Order::NearFirst && right_enter < left_enter;
                let (now, later) = if right_first {
                    ((right, right_enter), (left, left_enter))
                } else {
                    ((left, left_enter), (right, right_enter))
                };
                entries.push(later);
                if O::ACTIVE {
                    observer.stack_depth(entries.len());
                }
                Some(now)
            }
            (true, false) => Some((left, left_enter)),
            (false, true) => Some((right, right_enter)),
            (false, false) => None,
        };
    }
    search.closest
}
