//! The validator every test runs after every build (parry validates after every mutation).

use crate::aabb::Aabb;
use crate::bvh::tree::Bvh;
use crate::bvh::wide::{EMPTY_SLOT, LEAF_BLOCK, Slot, WideBvh};
use crate::math::Vector;

/// What is wrong with a tree.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ValidationError {
    /// Primitives exist but the tree has no nodes, or the reverse.
    #[error("the tree has {nodes} nodes for {primitives} primitives")]
    WrongShape {
        /// Node count.
        nodes: usize,
        /// Primitive count.
        primitives: usize,
    },
    /// An index points outside its array.
    #[error("node {node}: index out of range ({what})")]
    IndexOutOfRange {
        /// The node.
        node: usize,
        /// Which index.
        what: &'static str,
    },
    /// A child's box or a primitive's box is not inside its node's box.
    #[error("node {node}: {what} is not inside the node's box")]
    NotContained {
        /// The node.
        node: usize,
        /// What sticks out.
        what: String,
    },
    /// A node is reached twice, or never.
    #[error("node {node} is reached {times} times from the root")]
    NodeReach {
        /// The node.
        node: usize,
        /// How often it is reached.
        times: usize,
    },
    /// A wide node's slots break the layout's rules.
    #[error("wide node {node}: {problem}")]
    WideLayout {
        /// The wide node.
        node: usize,
        /// What is wrong.
        problem: String,
    },
    /// A primitive is in no leaf, or in several.
    #[error("primitive {primitive} is in {times} leaves")]
    PrimitiveCount {
        /// The primitive.
        primitive: usize,
        /// How many leaves hold it.
        times: usize,
    },
}

/// Checks that each node's box contains its children and its primitives, that every node is
/// reached exactly once from the root, that every primitive is in exactly one leaf, and that
/// every index is in range.
pub fn validate<V: Vector>(
    bvh: &Bvh<V>,
    primitive_bounds: &[Aabb<V>],
) -> Result<(), ValidationError> {
    let node_count = bvh.nodes.len();
    if (node_count == 0) != primitive_bounds.is_empty()
        || bvh.primitive_indices.len() != primitive_bounds.len()
    {
        return Err(ValidationError::WrongShape {
            nodes: node_count,
            primitives: primitive_bounds.len(),
        });
    }
    let mut node_reached = vec![0usize; node_count];
    let mut primitive_seen = vec![0usize; primitive_bounds.len()];
    let mut pending = if node_count > 0 { vec![0usize] } else { vec![] };
    while let Some(index) = pending.pop() {
        node_reached[index] += 1;
        if node_reached[index] > 1 {
            return Err(ValidationError::NodeReach {
                node: index,
                times: node_reached[index],
            });
        }
        let node = &bvh.nodes[index];
        if node.is_leaf() {
            let first = node.first as usize;
            let end = first + node.count as usize;
            if end > bvh.primitive_indices.len() {
                return Err(ValidationError::IndexOutOfRange {
                    node: index,
                    what: "primitive range",
                });
            }
            for &primitive in &bvh.primitive_indices[first..end] {
                let primitive = primitive as usize;
                let Some(bounds) = primitive_bounds.get(primitive) else {
                    return Err(ValidationError::IndexOutOfRange {
                        node: index,
                        what: "primitive number",
                    });
                };
                if !node.bounds.contains(bounds) {
                    return Err(ValidationError::NotContained {
                        node: index,
                        what: format!("primitive {primitive}"),
                    });
                }
                primitive_seen[primitive] += 1;
            }
        } else {
            for child in node.children() {
                let child = child as usize;
                if child >= node_count || child == 0 {
                    return Err(ValidationError::IndexOutOfRange {
                        node: index,
                        what: "child",
                    });
                }
                if !node.bounds.contains(&bvh.nodes[child].bounds) {
                    return Err(ValidationError::NotContained {
                        node: index,
                        what: format!("child {child}"),
                    });
                }
                pending.push(child);
            }
        }
    }
    if let Some((node, &times)) = node_reached.iter().enumerate().find(|(_, t)| **t != 1) {
        return Err(ValidationError::NodeReach { node, times });
    }
    if let Some((primitive, &times)) = primitive_seen.iter().enumerate().find(|(_, t)| **t != 1) {
        return Err(ValidationError::PrimitiveCount { primitive, times });
    }
    Ok(())
}

/// Checks a wide BVH: its binary tree (with [`validate`]), then that every wide node is reached
/// once from the root; that each used slot's box contains its wide node's slot boxes or its
/// leaf's primitives; that used slots come first and empty ones hold the empty box; that each
/// leaf starts at a multiple of [`LEAF_BLOCK`] and names its binary subtree; and that every
/// primitive is in exactly one leaf.
pub fn validate_wide<V: Vector, const W: usize>(
    wide: &WideBvh<V, W>,
    primitive_bounds: &[Aabb<V>],
) -> Result<(), ValidationError> {
    validate(&wide.binary, primitive_bounds)?;
    let node_count = wide.nodes.len();
    if (node_count == 0) != primitive_bounds.is_empty() || wide.node_sources.len() != node_count {
        return Err(ValidationError::WrongShape {
            nodes: node_count,
            primitives: primitive_bounds.len(),
        });
    }
    let layout = |node: usize, problem: String| ValidationError::WideLayout { node, problem };
    let mut node_reached = vec![0usize; node_count];
    let mut primitive_seen = vec![0usize; primitive_bounds.len()];
    let mut pending = if node_count > 0 { vec![0usize] } else { vec![] };
    while let Some(index) = pending.pop() {
        node_reached[index] += 1;
        if node_reached[index] > 1 {
            return Err(ValidationError::NodeReach {
                node: index,
                times: node_reached[index],
            });
        }
        let node = &wide.nodes[index];
        let used = node.slots_used();
        if used == 0 {
            return Err(layout(index, "no children".into()));
        }
        for slot in 0..W {
            let bounds: Aabb<V> = node.slot_bounds(slot);
            match node.slot(slot) {
                Slot::Empty => {
                    if slot < used || bounds != Aabb::empty() || node.count[slot] != 0 {
                        return Err(layout(
                            index,
                            format!("slot {slot} is not a clean empty slot"),
                        ));
                    }
                }
                _ if slot >= used => {
                    return Err(layout(index, format!("slot {slot} follows an empty slot")));
                }
                Slot::Node(child) => {
                    let child = child as usize;
                    if child >= node_count || child == 0 {
                        return Err(ValidationError::IndexOutOfRange {
                            node: index,
                            what: "child",
                        });
                    }
                    let child_node = &wide.nodes[child];
                    for child_slot in 0..child_node.slots_used() {
                        if !bounds.contains(&child_node.slot_bounds(child_slot)) {
                            return Err(ValidationError::NotContained {
                                node: index,
                                what: format!("slot {child_slot} of wide child {child}"),
                            });
                        }
                    }
                    pending.push(child);
                }
                Slot::Leaf { first, count } => {
                    let (first, count) = (first as usize, count as usize);
                    let end = first + count;
                    if first % LEAF_BLOCK != 0
                        || end > wide.primitive_indices.len()
                        || wide
                            .leaf_sources
                            .get(first / LEAF_BLOCK)
                            .is_none_or(|&source| {
                                source == EMPTY_SLOT || source as usize >= wide.binary.nodes.len()
                            })
                    {
                        return Err(layout(
                            index,
                            format!("leaf in slot {slot} is misplaced or names no binary node"),
                        ));
                    }
                    for &primitive in &wide.primitive_indices[first..end] {
                        let primitive = primitive as usize;
                        let Some(primitive_box) = primitive_bounds.get(primitive) else {
                            return Err(ValidationError::IndexOutOfRange {
                                node: index,
                                what: "primitive number",
                            });
                        };
                        if !bounds.contains(primitive_box) {
                            return Err(ValidationError::NotContained {
                                node: index,
                                what: format!("primitive {primitive}"),
                            });
                        }
                        primitive_seen[primitive] += 1;
                    }
                }
            }
        }
    }
    if let Some((node, &times)) = node_reached.iter().enumerate().find(|(_, t)| **t != 1) {
        return Err(ValidationError::NodeReach { node, times });
    }
    if let Some((primitive, &times)) = primitive_seen.iter().enumerate().find(|(_, t)| **t != 1) {
        return Err(ValidationError::PrimitiveCount { primitive, times });
    }
    Ok(())
}
