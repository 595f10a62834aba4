//! kD-tree traversal, the lecture's pseudo-code with an explicit stack:
//!
//! ```text
//! intersectKDTree(ray, node)
//!   if empty(ray) return
//!   if isLeaf(node) intersectObjects(node.objects, ray)
//!   else
//!     rayNear = clip ray to near side of the split;  intersectKDTree(rayNear, nearChild)
//!     if (no intersection) rayFar = clip ray to far side;  intersectKDTree(rayFar, farChild)
//! ```
//!
//! By default a pending far side is culled when it starts beyond the closest hit so far, so
//! the answer is the closest hit in either order (file order does more work), and a far side
//! the ray never reaches is dropped at once. [`Query::FirstInCell`] is the pseudo-code as it
//! reads: each leaf's objects are intersected with the ray clipped to the leaf's cell (a hit
//! beyond the cell, on a primitive reaching past the plane, is no intersection there; it is
//! one in the cell where it lies), the first leaf with an intersection ends the search, and a
//! side's fate is decided when the recursion comes to it (an empty side is dropped after the
//! side before it is done). Near first that is the closest hit; in file order it need not be.

use crate::kd::tree::KdTree;
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::LeafPrimitives;
use crate::query::{Hit, Order, Query, TraceOptions};
use crate::ray::Ray;
use crate::search::{CellSearch, Mailbox};

/// Reusable stack of far sides still to visit: one per thread, so tracing allocates nothing
/// per ray.
#[derive(Clone, Debug, Default)]
pub struct KdTraversalStack<S: Real> {
    entries: Vec<(u32, S, S)>,
}

impl<S: Real> KdTraversalStack<S> {
    /// An empty stack.
    pub fn new() -> Self {
        Self {
            entries: Vec::with_capacity(64),
        }
    }
}

/// Traces `ray` through `tree` over `primitives` (in their own numbering, or the tree's
/// [`leaf_ordered`](KdTree::leaf_ordered) copy). With [`Order::FileOrder`] the child below the
/// plane is always visited first, whatever the ray's direction.
pub fn traverse<V, P, O>(
    tree: &KdTree<V>,
    primitives: &P,
    ray: &Ray<V>,
    options: &TraceOptions,
    stack: &mut KdTraversalStack<V::Scalar>,
    observer: &mut O,
) -> Option<Hit<V::Scalar>>
where
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    // Clip the ray to the root cell.
    let CellSearch {
        slab_ray,
        t_enter,
        t_exit,
        primitive_ray,
        mut search,
    } = CellSearch::enter(&tree.bounds, primitives, ray, options, observer)?;
    if tree.nodes.is_empty() {
        return None;
    }
    let entries = &mut stack.entries;
    entries.clear();
    let mut mailbox = Mailbox::new(options.mailboxing);
    let origins = ray.origin.to_array3();
    let directions = ray.direction.to_array3();
    let inverse_directions = slab_ray.inv_direction.to_array3();
    let negative = slab_ray.negative;
    let mut current = Some((0u32, t_enter, t_exit));
    let pseudo_code = options.query == Query::FirstInCell;
    while let Some((node_index, t_near, t_far)) = current.take().or_else(|| entries.pop()) {
        // The pseudo-code's `if empty(ray) return`, for a side the ray does not reach, once
        // the side before it is done.
        if pseudo_code && t_near > t_far {
            observer.cell_missed(node_index);
            continue;
        }
        // The part of the ray in this cell starts beyond the closest hit: nothing here is nearer.
        if t_near > search.t_closest {
            observer.node_culled(node_index, t_near, search.t_closest);
            continue;
        }
        observer.cell_entered(node_index, t_near, t_far);
        let node = &tree.nodes[node_index as usize];
        if node.is_leaf() {
            // Test the leaf's primitives (once per ray with the mailbox). Under the
            // pseudo-code's rule, against the ray clipped to the cell: an intersection there
            // ends the search (`If(no intersection)`: every side still waiting is the far side
            // of a split whose near side now holds one).
            search.clip_to_cell(t_near, t_far);
            if search.test_leaf(
                primitives,
                &primitive_ray,
                ray.t_min,
                node.first as usize,
                tree.leaf_primitives(node),
                &mut mailbox,
                observer,
            ) {
                return search.closest;
            }
            continue;
        }
        let axis = node.axis as usize;
        let origin = origins[axis];
        let [below, above] = node.children();
        if origin == node.split {
            // The ray starts in the plane. A primitive touching the plane from either side can
            // be met there, so both cells are visited: first the one it moves into, the other
            // only at the start (or all along, if the ray lies in the plane).
            let direction = directions[axis];
            let (near, far) = if direction <= V::Scalar::ZERO {
                (below, above)
            } else {
                (above, below)
            };
            let far_exit = if direction == V::Scalar::ZERO {
                t_far
            } else {
                t_near
            };
            // The pseudo-code's rule ends the search at the first side with a hit, so there
            // the side met only at the start, nearer along the ray, goes first. (A ray lying
            // in the plane meets both sides all along: the rule may then stop at a hit that is
            // not the closest, as in a BVH's overlapping boxes.)
            if options.query == Query::FirstInCell && direction != V::Scalar::ZERO {
                entries.push((near, t_near, t_far));
                current = Some((far, t_near, far_exit));
            } else {
                entries.push((far, t_near, far_exit));
                current = Some((near, t_near, t_far));
            }
            if O::ACTIVE {
                observer.stack_depth(entries.len());
            }
            continue;
        }
        // The child the ray meets first, by the sign of its direction on this axis (the sign
        // of the inverse, so −0 and ±∞ agree): the same at every node of a ray, so the branch
        // predicts well, where "which side holds the origin" changes from node to node.
        let (first, second) = if negative[axis] {
            (above, below)
        } else {
            (below, above)
        };
        // Where the ray crosses the plane: ±∞ when it runs parallel, behind the origin (< 0)
        // when it moves away.
        let t_plane = (node.split - origin) * inverse_directions[axis];
        // In robust mode the crossing counts as inside the cell's interval within its
        // roundoff (Ize 2013's bound, as for the root box): where the ray leaves through a
        // corner shared with another plane, a primitive touching this plane from the far side
        // is then still visited.
        let (first_part, second_part) = if t_plane > t_far * slab_ray.far_scale {
            // It leaves the cell before reaching the plane (or never reaches it): its part on
            // the second side is empty. Dropped at once, but by the pseudo-code, which comes to
            // it (empty) once the first side is done.
            if !pseudo_code {
                observer.cell_missed(second);
                current = Some((first, t_near, t_far));
                continue;
            }
            ((first, t_near, t_far), (second, t_plane, t_far))
        } else if t_plane * slab_ray.far_scale < t_near {
            // It crossed the plane before entering the cell (or moves away from it): its part
            // on the first side is empty.
            if !pseudo_code {
                observer.cell_missed(first);
                current = Some((second, t_near, t_far));
                continue;
            }
            ((first, t_near, t_plane), (second, t_near, t_far))
        } else {
            // Both parts. Both include the crossing point, where a primitive touching the
            // plane from one side only is met.
            (
                (first, t_near, t_plane.max(t_near)),
                (second, t_plane.min(t_far), t_far),
            )
        };
        // Visit one now, keep the other for when this subtree is done. File order visits the
        // side below the plane first.
        let (now, later) = if options.order == Order::FileOrder && first != below {
            (second_part, first_part)
        } else {
            (first_part, second_part)
        };
        entries.push(later);
        if O::ACTIVE {
            observer.stack_depth(entries.len());
        }
        current = Some(now);
    }
    search.finish(observer)
}
