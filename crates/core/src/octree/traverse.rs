//! Octree traversal, front to back: Revelles, Ureña & Lastra 2000, "An efficient parametric
//! algorithm for octree traversal".
//!
//! A ray's part of a cell, `[t_near, t_far]`, meets the cell's middle plane on each axis at
//! `t_mid` (where it crosses it, if it does inside the part). It starts in the child holding
//! its entry: above the middle along an axis when it has crossed that plane already, moving
//! up, or has not yet crossed it, moving down (with the ray's direction signs, the octant
//! numbering's bits). Each `t_mid` inside the part flips that axis's bit: the children the
//! ray passes, in the order it passes them, at most `D + 1` of the `2^D`, each with its part
//! of the ray between two crossings. Near first visits them in that order and culls a child
//! that starts beyond the closest hit; file order visits them by their numbers. The observer
//! hears each cell entered with its part, each child the ray does not reach, and the order.

use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::octree::tree::{Octree, child_count};
use crate::primitive::LeafPrimitives;
use crate::query::{Hit, Order, TraceOptions};
use crate::ray::Ray;
use crate::search::{CellSearch, Mailbox};

/// A cell waiting to be visited: its node, its box (low and high corners, padded to three
/// axes) and the ray's part of it.
type Waiting<S> = (u32, [[S; 3]; 2], S, S);

/// Reusable stack of cells still to visit: one per thread, so tracing allocates nothing per
/// ray.
#[derive(Clone, Debug, Default)]
pub struct OctreeStack<S: Real> {
    entries: Vec<Waiting<S>>,
}

/// Traces `ray` through `tree` over `primitives` (in their own numbering, or the tree's
/// [`leaf_ordered`](Octree::leaf_ordered) copy).
pub fn traverse<V, P, O>(
    tree: &Octree<V>,
    primitives: &P,
    ray: &Ray<V>,
    options: &TraceOptions,
    stack: &mut OctreeStack<V::Scalar>,
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
    let mut mailbox = Mailbox::new(options.mailboxing);
    let origin = ray.origin.to_array3();
    let inverse = slab_ray.inv_direction.to_array3();
    let negative = slab_ray.negative;
    let children = child_count::<V>();
    let entries = &mut stack.entries;
    entries.clear();
    let root = [tree.bounds.min.to_array3(), tree.bounds.max.to_array3()];
    let mut current = Some((0u32, root, t_enter, t_exit));
    while let Some((node_index, [low, high], t_near, t_far)) =
        current.take().or_else(|| entries.pop())
    {
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
            // ends the search.
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
        // Where the ray crosses each middle plane (±∞ along an axis it does not move on), and
        // the child it starts in.
        let half = V::Scalar::ONE / V::Scalar::TWO;
        let mut middle = [V::Scalar::ZERO; 3];
        let mut t_mid = [V::Scalar::INFINITY; 3];
        let mut child = 0usize;
        for axis in 0..V::DIM {
            middle[axis] = low[axis] + (high[axis] - low[axis]) * half;
            let above = if inverse[axis].is_finite() {
                t_mid[axis] = (middle[axis] - origin[axis]) * inverse[axis];
                if negative[axis] {
                    t_mid[axis] > t_near
                } else {
                    t_mid[axis] <= t_near
                }
            } else {
                origin[axis] >= middle[axis]
            };
            child |= usize::from(above) << axis;
        }
        // The planes crossed inside the part, in the order they are crossed.
        let mut crossed = [0usize; 3];
        let mut crossings = 0;
        for axis in 0..V::DIM {
            if t_near < t_mid[axis] && t_mid[axis] < t_far {
                let mut at = crossings;
                while at > 0 && t_mid[crossed[at - 1]] > t_mid[axis] {
                    crossed[at] = crossed[at - 1];
                    at -= 1;
                }
                crossed[at] = axis;
                crossings += 1;
            }
        }
        // The children passed, each with its part of the ray.
        let mut passed = [(0usize, t_near, t_far); 4];
        let mut start = t_near;
        for (index, &axis) in crossed[..crossings].iter().enumerate() {
            passed[index] = (child, start, t_mid[axis]);
            start = t_mid[axis];
            child ^= 1 << axis;
        }
        passed[crossings] = (child, start, t_far);
        let passed = &mut passed[..=crossings];
        if options.order == Order::FileOrder {
            passed.sort_by_key(|&(child, _, _)| child);
        }
        if O::ACTIVE {
            let mut reached = 0u32;
            let mut order = [0u32; 8];
            for (place, &(child, _, _)) in order.iter_mut().zip(passed.iter()) {
                *place = node.first + child as u32;
                reached |= 1 << child;
            }
            // No box was tested: the order comes from the middle planes.
            observer.children_ordered(node_index, 0, &order[..passed.len()]);
            for child in (0..children).filter(|&child| reached & (1 << child) == 0) {
                observer.cell_missed(node.first + child as u32);
            }
        }
        // Visit the first, keep the others for when its subtree is done (the last deepest).
        for &(child, t_from, t_to) in passed[1..].iter().rev() {
            entries.push((
                node.first + child as u32,
                child_box([low, high], middle, child),
                t_from,
                t_to,
            ));
        }
        if O::ACTIVE && passed.len() > 1 {
            observer.stack_depth(entries.len());
        }
        let (child, t_from, t_to) = passed[0];
        current = Some((
            node.first + child as u32,
            child_box([low, high], middle, child),
            t_from,
            t_to,
        ));
    }
    search.finish(observer)
}

/// Child `child`'s box within `[low, high]` cut at `middle` (what
/// [`child_cell`](crate::octree::tree::child_cell) gives, on padded arrays).
#[inline(always)]
fn child_box<S: Real>([low, high]: [[S; 3]; 2], middle: [S; 3], child: usize) -> [[S; 3]; 2] {
    let (mut low, mut high) = (low, high);
    for axis in 0..3 {
        if child & (1 << axis) != 0 {
            low[axis] = middle[axis];
        } else {
            high[axis] = middle[axis];
        }
    }
    [low, high]
}
