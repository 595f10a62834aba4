//! The octree validator: every interior node's children are the next free nodes, cut at its
//! cell's middle; every leaf lists, in increasing order, each primitive that reaches into its
//! cell (the overlap test, [`PrimitiveSet::overlaps`]) and none whose box misses it.

use crate::facts::Hierarchy;
use crate::math::Vector;
use crate::octree::tree::{Octree, child_count};
use crate::primitive::PrimitiveSet;

/// What is wrong with an octree.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum OctreeValidationError {
    /// A node's children or primitives lie outside their arrays, or nodes are unreached or
    /// reached twice.
    #[error("node {node}: {what}")]
    Shape {
        /// The node.
        node: u32,
        /// What is wrong.
        what: String,
    },
    /// A primitive reaches a leaf that does not list it.
    #[error("primitive {primitive} reaches leaf {node}, which does not list it")]
    Missing {
        /// The primitive.
        primitive: u32,
        /// The leaf.
        node: u32,
    },
    /// A leaf lists a primitive whose box does not touch its cell.
    #[error("leaf {node} lists primitive {primitive}, whose box does not touch its cell")]
    Stray {
        /// The primitive.
        primitive: u32,
        /// The leaf.
        node: u32,
    },
}

/// Checks `tree`, built over `primitives`.
pub fn validate<V: Vector, P: PrimitiveSet<V>>(
    tree: &Octree<V>,
    primitives: &P,
) -> Result<(), OctreeValidationError> {
    let shape = |node: usize, what: String| OctreeValidationError::Shape {
        node: node as u32,
        what,
    };
    let count = tree.nodes.len();
    if count == 0 {
        return Err(shape(0, "no root".into()));
    }
    // Children follow their parents, each node reached once.
    let mut reached = vec![false; count];
    reached[0] = true;
    for (index, node) in tree.nodes.iter().enumerate() {
        if node.is_leaf() {
            let end = node.first as usize + node.count as usize;
            if end > tree.primitive_indices.len() {
                return Err(shape(index, "its primitives pass the list's end".into()));
            }
            continue;
        }
        let first = node.first as usize;
        if first <= index || first + child_count::<V>() > count {
            return Err(shape(index, format!("children from {first}")));
        }
        let children = &mut reached[first..first + child_count::<V>()];
        if let Some(twice) = children.iter().position(|&reached| reached) {
            return Err(shape(first + twice, "reached twice".into()));
        }
        children.fill(true);
    }
    if let Some(unreached) = reached.iter().position(|&reached| !reached) {
        return Err(shape(unreached, "unreached".into()));
    }
    // The leaves: exactly the primitives that reach into their cells.
    let cells = tree.node_bounds();
    for (index, node) in tree.nodes.iter().enumerate() {
        if !node.is_leaf() {
            continue;
        }
        let cell = &cells[index];
        let listed = tree.leaf_primitives(node);
        if listed.windows(2).any(|pair| pair[0] >= pair[1]) {
            return Err(shape(index, "its list is not increasing".into()));
        }
        for &primitive in listed {
            if primitive as usize >= primitives.len()
                || primitives
                    .bounds(primitive as usize)
                    .intersection(cell)
                    .is_none()
            {
                return Err(OctreeValidationError::Stray {
                    primitive,
                    node: index as u32,
                });
            }
        }
    }
    // Each primitive, from the root down through the cells its box touches: every leaf it
    // reaches lists it.
    let mut pending = Vec::new();
    for primitive in 0..primitives.len() {
        let bounds = primitives.bounds(primitive);
        pending.clear();
        pending.push(0u32);
        while let Some(at) = pending.pop() {
            let cell = &cells[at as usize];
            if bounds.intersection(cell).is_none() {
                continue;
            }
            match tree.children(at) {
                Some(children) => pending.extend(children),
                None => {
                    let listed = tree.leaf_primitives(&tree.nodes[at as usize]);
                    if primitives.overlaps(primitive, cell)
                        && listed.binary_search(&(primitive as u32)).is_err()
                    {
                        return Err(OctreeValidationError::Missing {
                            primitive: primitive as u32,
                            node: at,
                        });
                    }
                }
            }
        }
    }
    Ok(())
}
