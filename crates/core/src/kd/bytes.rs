//! A kD-tree's bytes ([`crate::bytes`]): its root cell, its nodes (plane, axis, first,
//! count), its primitive references and the limits its builder kept to.

use crate::bytes::{ByteReader, ByteWriter, BytesError, Link, REAL_BYTES, check_links};
use crate::math::Vector;

use super::tree::{KdBudgetExceeded, KdLimits, KdNode, KdTree};

impl<V: Vector> KdTree<V> {
    /// Writes the tree, with its limits.
    pub fn write_bytes(&self, out: &mut ByteWriter) {
        out.aabb(&self.bounds);
        out.usize(self.nodes.len());
        out.reserve(self.nodes.len() * (REAL_BYTES + 12));
        for node in &self.nodes {
            out.real(node.split);
            out.u32(node.axis);
            out.u32(node.first);
            out.u32(node.count);
        }
        out.u32s(&self.primitive_indices);
        let limits = &self.limits;
        out.usize(limits.depth_limit);
        out.usize(limits.leaves_at_depth_limit);
        let (tag, usual, budget) = match limits.lowered_from {
            None => (0, 0, 0),
            Some((usual, KdBudgetExceeded::Nodes(budget))) => (1, usual, budget),
            Some((usual, KdBudgetExceeded::References(budget))) => (2, usual, budget),
        };
        out.u8(tag);
        out.usize(usual);
        out.usize(budget);
    }

    /// The tree [`KdTree::write_bytes`] wrote.
    pub fn read_bytes(input: &mut ByteReader<'_>) -> Result<Self, BytesError> {
        let bounds = input.aabb()?;
        let nodes = input.items(REAL_BYTES + 12, |input| {
            Ok(KdNode {
                split: input.real()?,
                axis: input.u32()?,
                first: input.u32()?,
                count: input.u32()?,
            })
        })?;
        let primitive_indices = input.u32s()?;
        check_links(nodes.len(), primitive_indices.len(), |index| {
            let node = &nodes[index];
            if node.is_leaf() || (node.axis as usize) < V::DIM {
                Ok(Link::of(node.is_leaf(), node.first, node.count, 2))
            } else {
                Err(BytesError::Invalid(format!(
                    "node {index}: axis {}",
                    node.axis
                )))
            }
        })?;
        let depth_limit = input.usize()?;
        let leaves_at_depth_limit = input.usize()?;
        let (tag, usual, budget) = (input.u8()?, input.usize()?, input.usize()?);
        let lowered_from = match tag {
            0 => None,
            1 => Some((usual, KdBudgetExceeded::Nodes(budget))),
            2 => Some((usual, KdBudgetExceeded::References(budget))),
            _ => {
                return Err(BytesError::Unknown {
                    what: "kD budget",
                    tag: tag.into(),
                });
            }
        };
        Ok(Self {
            bounds,
            nodes,
            primitive_indices,
            limits: KdLimits {
                depth_limit,
                leaves_at_depth_limit,
                lowered_from,
            },
        })
    }
}
