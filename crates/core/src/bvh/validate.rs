//! The validator every test runs after every build (parry validates after every mutation).

use crate::aabb::Aabb;
use crate::bvh::tree::Bvh;
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
