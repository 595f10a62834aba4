//! The kD-tree validator every test runs after every build.

use crate::aabb::Aabb;
use crate::kd::tree::KdTree;
use crate::math::{Real, Vector};
use crate::primitive::PrimitiveSet;

/// What is wrong with a kD-tree.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum KdValidationError {
    /// The root cell does not hold every primitive's box.
    #[error("the root cell does not contain primitive {primitive}")]
    RootTooSmall {
        /// The primitive.
        primitive: usize,
    },
    /// An index points outside its array, or an axis is not one of the scene's.
    #[error("node {node}: {what} out of range")]
    OutOfRange {
        /// The node.
        node: usize,
        /// Which index.
        what: &'static str,
    },
    /// A split plane lies outside its node's cell, so the children would not tile it.
    #[error("node {node}: the split plane is outside the cell")]
    PlaneOutsideCell {
        /// The node.
        node: usize,
    },
    /// A node is reached twice, or never.
    #[error("node {node} is reached {times} times from the root")]
    NodeReach {
        /// The node.
        node: usize,
        /// How often.
        times: usize,
    },
    /// A primitive overlapping a leaf's cell is not listed in it.
    #[error("leaf {node} misses primitive {primitive}, which overlaps its cell")]
    MissingPrimitive {
        /// The leaf.
        node: usize,
        /// The primitive.
        primitive: usize,
    },
    /// A primitive is in no leaf.
    #[error("primitive {primitive} is in no leaf")]
    Unlisted {
        /// The primitive.
        primitive: usize,
    },
    /// A leaf lists a primitive that does not reach its cell, or lists one twice.
    #[error("leaf {node} lists primitive {primitive}, which does not belong there")]
    ExtraPrimitive {
        /// The leaf.
        node: usize,
        /// The primitive.
        primitive: usize,
    },
}

/// Checks that the root cell holds every primitive, that each split lies within its cell (so
/// the two child cells tile the parent), that every node is reached once, and that each leaf
/// lists every primitive whose box reaches into its cell and none that stays outside. A box
/// that only touches a leaf's cell from outside, across a split plane, may be listed or not:
/// the builders list it on the side holding the rest of it, and one side for a box lying in
/// the plane. Every primitive must be listed somewhere. O(leaves × primitives): for tests.
pub fn validate<V: Vector>(
    tree: &KdTree<V>,
    primitive_bounds: &[Aabb<V>],
) -> Result<(), KdValidationError> {
    validate_by(tree, primitive_bounds, |primitive, cell| {
        primitive_bounds[primitive].intersection(cell)
    })
}

/// [`validate`] for a tree built with perfect splits
/// ([`KdSahPresorted::build_with_perfect_splits`](crate::kd::KdSahPresorted::build_with_perfect_splits)):
/// a leaf must list every primitive whose part inside its cell (clipped, not its box) reaches
/// into the cell by more than the roundoff of clipping.
pub fn validate_clipped<V: Vector, P: PrimitiveSet<V>>(
    tree: &KdTree<V>,
    primitives: &P,
) -> Result<(), KdValidationError> {
    let bounds = primitives.all_bounds();
    let tolerance = V::Scalar::from_f64(16.0) * V::Scalar::UNIT_ROUNDOFF;
    validate_by(tree, &bounds, |primitive, cell| {
        // The clipped box is widened where clipping rounded; shrink it back by more than that,
        // so only a part that surely reaches into the cell must be listed. A part thinner
        // than that next to a side of the cell may lie just outside it.
        let part = primitives.clipped_bounds(primitive, cell)?;
        let mut shrunk = part;
        for axis in 0..V::DIM {
            let margin = tolerance * part.min[axis].abs().max(part.max[axis].abs());
            if part.max[axis] - part.min[axis] > V::Scalar::TWO * margin {
                shrunk.min[axis] = part.min[axis] + margin;
                shrunk.max[axis] = part.max[axis] - margin;
            } else if part.min[axis] - margin <= cell.min[axis]
                || part.max[axis] + margin >= cell.max[axis]
            {
                return None;
            }
        }
        Some(shrunk)
    })
}

/// The checks, with `part_in(primitive, cell)` the box of the primitive's part in a cell.
fn validate_by<V: Vector>(
    tree: &KdTree<V>,
    primitive_bounds: &[Aabb<V>],
    part_in: impl Fn(usize, &Aabb<V>) -> Option<Aabb<V>>,
) -> Result<(), KdValidationError> {
    if let Some(primitive) = primitive_bounds
        .iter()
        .position(|bounds| !tree.bounds.contains(bounds))
    {
        return Err(KdValidationError::RootTooSmall { primitive });
    }
    let node_count = tree.nodes.len();
    let mut reached = vec![0usize; node_count];
    let mut listed_anywhere = vec![false; primitive_bounds.len()];
    let mut pending = vec![(0usize, tree.bounds)];
    while let Some((index, cell)) = pending.pop() {
        let Some(node) = tree.nodes.get(index) else {
            return Err(KdValidationError::OutOfRange {
                node: index,
                what: "child",
            });
        };
        reached[index] += 1;
        if reached[index] > 1 {
            return Err(KdValidationError::NodeReach {
                node: index,
                times: reached[index],
            });
        }
        if node.is_leaf() {
            let first = node.first as usize;
            let Some(listed) = tree
                .primitive_indices
                .get(first..first + node.count as usize)
            else {
                return Err(KdValidationError::OutOfRange {
                    node: index,
                    what: "primitive range",
                });
            };
            let mut listed_flags = vec![false; primitive_bounds.len()];
            let root = &tree.bounds;
            for &primitive in listed {
                let primitive = primitive as usize;
                let reaches = primitive_bounds
                    .get(primitive)
                    .is_some_and(|bounds| touches(bounds, &cell));
                if !reaches || listed_flags[primitive] {
                    return Err(KdValidationError::ExtraPrimitive {
                        node: index,
                        primitive,
                    });
                }
                listed_flags[primitive] = true;
                listed_anywhere[primitive] = true;
            }
            if let Some(primitive) = (0..primitive_bounds.len()).find(|&p| {
                !listed_flags[p]
                    && part_in(p, &cell).is_some_and(|part| reaches_into(&part, &cell, root))
            }) {
                return Err(KdValidationError::MissingPrimitive {
                    node: index,
                    primitive,
                });
            }
            continue;
        }
        let axis = node.axis as usize;
        if axis >= V::DIM {
            return Err(KdValidationError::OutOfRange {
                node: index,
                what: "axis",
            });
        }
        if !(cell.min[axis] <= node.split && node.split <= cell.max[axis]) {
            return Err(KdValidationError::PlaneOutsideCell { node: index });
        }
        let [below, above] = KdTree::child_cells(node, &cell);
        let [left, right] = node.children();
        pending.push((left as usize, below));
        pending.push((right as usize, above));
    }
    if let Some((node, &times)) = reached.iter().enumerate().find(|(_, t)| **t != 1) {
        return Err(KdValidationError::NodeReach { node, times });
    }
    if let Some(primitive) = listed_anywhere.iter().position(|listed| !listed) {
        return Err(KdValidationError::Unlisted { primitive });
    }
    Ok(())
}

/// Whether a primitive box meets a closed cell (it may only touch its boundary).
fn touches<V: Vector>(bounds: &Aabb<V>, cell: &Aabb<V>) -> bool {
    (0..V::DIM).all(|axis| bounds.min[axis] <= cell.max[axis] && bounds.max[axis] >= cell.min[axis])
}

/// Whether a primitive box reaches into a cell: on every axis it reaches past the cell's lower
/// side and short of its upper side, where a side on the root cell's boundary counts as
/// reached when touched (no cell lies beyond it to take the box instead).
fn reaches_into<V: Vector>(bounds: &Aabb<V>, cell: &Aabb<V>, root: &Aabb<V>) -> bool {
    (0..V::DIM).all(|axis| {
        let (low, high) = (cell.min[axis], cell.max[axis]);
        let below_high =
            bounds.min[axis] < high || (high == root.max[axis] && bounds.min[axis] <= high);
        let above_low =
            bounds.max[axis] > low || (low == root.min[axis] && bounds.max[axis] >= low);
        below_high && above_low
    })
}
