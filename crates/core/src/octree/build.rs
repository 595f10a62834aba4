//! Building an octree (a quadtree in 2D): the box around the primitives, cut at its middle
//! along every axis into `2^D` equal cells, and each cell again, until it holds at most a
//! leaf's worth of primitives or reaches the depth limit (Glassner 1984, "Space subdivision
//! for fast ray tracing"). A primitive is listed in every child cell it reaches.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReason};
use crate::facts::Children;
use crate::math::{Real, Vector};
use crate::octree::tree::{Octree, OctreeLimits, OctreeNode, child_cell, child_count, middle};
use crate::params::BuildParams;
use crate::primitive::PrimitiveSet;

/// Primitives a leaf may hold when none is asked for: the other builders' leaf size.
pub const DEFAULT_LEAF_SIZE: usize = 8;

/// The deepest an octree over `primitive_count` primitives goes: the kD-trees' limit
/// (`8 + 1.3 log₂ n` binary cuts, pbrt-v3 §4.4.2) in octree levels, each of which cuts every
/// axis once.
pub fn depth_limit<V: Vector>(primitive_count: usize) -> usize {
    let cuts = 8.0 + 1.3 * (primitive_count.max(1) as f64).log2();
    (cuts / V::DIM as f64).ceil() as usize
}

/// Builds an octree over `primitives`, leaves of at most `leaf_size` primitives, telling
/// `observer` about each node: its start, its cut into `2^D` children, or why it is a leaf
/// (small enough, at the depth limit, or nothing separates its primitives: every child would
/// list them all). Within the build's budget (`params.kd_budget`: nodes and references per
/// primitive, as for kD-trees): past it the build starts over one level shallower, and the
/// tree says so ([`OctreeLimits`]).
pub fn build<V: Vector, P: PrimitiveSet<V>, O: BuildObserver>(
    primitives: &P,
    leaf_size: usize,
    params: &BuildParams,
    observer: &mut O,
) -> Octree<V> {
    let count = primitives.len();
    let usual = depth_limit::<V>(count);
    let budget = (
        params.kd_budget.nodes_for(count),
        params.kd_budget.references_for(count),
    );
    let mut limit = usual;
    loop {
        if let Some(mut tree) = build_within(primitives, leaf_size.max(1), limit, budget, observer)
        {
            tree.limits.lowered_from = (limit < usual).then_some(usual);
            return tree;
        }
        observer.restarted();
        limit -= 1;
    }
}

/// The root cell around primitives whose box is `bounds`: that box, but along an axis it does
/// not span (a flat mesh, every triangle in one plane) it reaches from the primitives' plane
/// up by the box's largest side. Cut at the box's own middle, such an axis would cut through
/// every primitive at every level and list each in both halves, doubling the lists a level
/// (a flat CAD mesh: 646 against a kD-tree's 30 in SAH cost, a build 100 times slower);
/// with the cell reaching up, each middle along it lies above the primitives, which all go
/// below: the tree cuts only the axes the primitives span (a quadtree in their plane), and
/// the children above hold nothing.
pub fn root_cell<V: Vector>(bounds: &Aabb<V>) -> Aabb<V> {
    if bounds.is_empty() {
        return *bounds;
    }
    let extent = bounds.extent();
    let largest = (0..V::DIM).fold(V::Scalar::ZERO, |a, axis| a.max(extent[axis]));
    let mut high = bounds.max;
    for axis in 0..V::DIM {
        if extent[axis] == V::Scalar::ZERO {
            high[axis] += largest;
        }
    }
    Aabb::new(bounds.min, high)
}

/// One build with `depth_limit`; `None` once it passes the (nodes, references) budget (a
/// build of depth 0, one leaf, always fits).
fn build_within<V: Vector, P: PrimitiveSet<V>, O: BuildObserver>(
    primitives: &P,
    leaf_size: usize,
    depth_limit: usize,
    (node_budget, reference_budget): (usize, usize),
    observer: &mut O,
) -> Option<Octree<V>> {
    let primitive_bounds = primitives.all_bounds();
    let bounds = root_cell(
        &primitive_bounds
            .iter()
            .fold(Aabb::empty(), |acc, bounds| acc.union(*bounds)),
    );
    let children = child_count::<V>();
    let mut nodes = vec![OctreeNode { first: 0, count: 0 }];
    let mut primitive_indices = Vec::new();
    let mut limits = OctreeLimits {
        depth_limit,
        leaves_at_depth_limit: 0,
        lowered_from: None,
    };
    let all: Vec<u32> = (0..primitives.len() as u32).collect();
    let mut references = all.len();
    let mut work = vec![(0usize, bounds, all, 0usize)];
    while let Some((node, cell, listed, depth)) = work.pop() {
        observer.node_started(node as u32, depth, listed.len());
        // Stop when the cell holds a leaf's worth, or is at the depth limit.
        let mut reason = if listed.len() <= leaf_size {
            Some(LeafReason::SmallEnough {
                count: listed.len(),
                max_leaf_size: leaf_size,
            })
        } else if depth >= depth_limit {
            limits.leaves_at_depth_limit += 1;
            Some(LeafReason::DepthLimit { limit: depth_limit })
        } else {
            None
        };
        // Cut it in the middle along every axis; each child lists what reaches into it: the
        // children a primitive's box touches (closed: on the middle, both sides), and of
        // those, when it touches more than one, the ones the primitive itself reaches.
        let middle = middle(&cell);
        let mut parts = Vec::new();
        if reason.is_none() {
            parts = (0..children)
                .map(|child| (child_cell(&cell, middle, child), Vec::new()))
                .collect::<Vec<_>>();
            for &primitive in &listed {
                let bounds = &primitive_bounds[primitive as usize];
                // Per axis, the sides of the middle the box touches: bit 0 below, bit 1 above.
                let sides: [u32; 3] = std::array::from_fn(|axis| {
                    if axis >= V::DIM {
                        return 1;
                    }
                    u32::from(bounds.min[axis] <= middle[axis])
                        | u32::from(bounds.max[axis] >= middle[axis]) << 1
                });
                let mut touched = [0usize; 8];
                let mut count = 0;
                for child in 0..children {
                    if (0..V::DIM).all(|axis| sides[axis] & (1 << ((child >> axis) & 1)) != 0) {
                        touched[count] = child;
                        count += 1;
                    }
                }
                let one = count == 1;
                for &child in &touched[..count] {
                    let (part, inside) = &mut parts[child];
                    if one || primitives.overlaps(primitive as usize, part) {
                        inside.push(primitive);
                    }
                }
            }
            if parts.iter().all(|(_, inside)| inside.len() == listed.len()) {
                reason = Some(LeafReason::Inseparable {
                    count: listed.len(),
                });
            }
        }
        if let Some(reason) = reason {
            nodes[node] = OctreeNode {
                first: primitive_indices.len() as u32,
                count: listed.len() as u32,
            };
            primitive_indices.extend_from_slice(&listed);
            observer.leaf(node as u32, reason);
            continue;
        }
        references =
            references + parts.iter().map(|(_, inside)| inside.len()).sum::<usize>() - listed.len();
        if nodes.len() + children > node_budget || references > reference_budget {
            return None;
        }
        let first = nodes.len();
        nodes[node] = OctreeNode {
            first: first as u32,
            count: OctreeNode::INTERIOR,
        };
        nodes.extend((0..children).map(|_| OctreeNode { first: 0, count: 0 }));
        observer.split(
            node as u32,
            Children {
                first: first as u32,
                count: children as u32,
            },
            None,
        );
        // The last child first on the work list, so the subtrees are laid out in order.
        for (child, (part, inside)) in parts.into_iter().enumerate().rev() {
            work.push((first + child, part, inside, depth + 1));
        }
    }
    Some(Octree {
        bounds,
        nodes,
        primitive_indices,
        limits,
    })
}
