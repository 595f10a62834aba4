//! An octree's bytes ([`crate::bytes`]): its root cell, its nodes (first, count), its
//! primitive references and the limits its builder kept to.

use crate::bytes::{ByteReader, ByteWriter, BytesError, Link, check_links};
use crate::math::Vector;

use super::tree::{Octree, OctreeLimits, OctreeNode, child_count};

impl<V: Vector> Octree<V> {
    /// Writes the tree, with its limits.
    pub fn write_bytes(&self, out: &mut ByteWriter) {
        out.aabb(&self.bounds);
        out.usize(self.nodes.len());
        out.reserve(self.nodes.len() * 8);
        for node in &self.nodes {
            out.u32(node.first);
            out.u32(node.count);
        }
        out.u32s(&self.primitive_indices);
        let limits = &self.limits;
        out.usize(limits.depth_limit);
        out.usize(limits.leaves_at_depth_limit);
        // 0 for none, else one more than the depth it was lowered from.
        out.usize(limits.lowered_from.map_or(0, |usual| usual + 1));
    }

    /// The tree [`Octree::write_bytes`] wrote.
    pub fn read_bytes(input: &mut ByteReader<'_>) -> Result<Self, BytesError> {
        let bounds = input.aabb()?;
        let nodes = input.items(8, |input| {
            Ok(OctreeNode {
                first: input.u32()?,
                count: input.u32()?,
            })
        })?;
        let primitive_indices = input.u32s()?;
        check_links(nodes.len(), primitive_indices.len(), |index| {
            let node = &nodes[index];
            Ok(Link::of(
                node.is_leaf(),
                node.first,
                node.count,
                child_count::<V>(),
            ))
        })?;
        let depth_limit = input.usize()?;
        let leaves_at_depth_limit = input.usize()?;
        let lowered_from = input.usize()?.checked_sub(1);
        Ok(Self {
            bounds,
            nodes,
            primitive_indices,
            limits: OctreeLimits {
                depth_limit,
                leaves_at_depth_limit,
                lowered_from,
            },
        })
    }
}
