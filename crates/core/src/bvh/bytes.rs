//! A BVH's bytes ([`crate::bytes`]): its nodes (box, first, count) and its primitive order. A
//! wide BVH is written as the binary tree it was collapsed from, and collapsed again when
//! read ([`crate::Tree::from_binary`]: deterministic and quick).

use crate::bytes::{ByteReader, ByteWriter, BytesError, Link, aabb_bytes, check_links};
use crate::math::Vector;

use super::tree::{Bvh, BvhNode};

impl<V: Vector> Bvh<V> {
    /// Writes the tree's nodes and primitive order.
    pub fn write_bytes(&self, out: &mut ByteWriter) {
        out.usize(self.nodes.len());
        out.reserve(self.nodes.len() * (aabb_bytes::<V>() + 8));
        for node in &self.nodes {
            out.aabb(&node.bounds);
            out.u32(node.first);
            out.u32(node.count);
        }
        out.u32s(&self.primitive_indices);
    }

    /// The tree [`Bvh::write_bytes`] wrote.
    pub fn read_bytes(input: &mut ByteReader<'_>) -> Result<Self, BytesError> {
        let nodes = input.items(aabb_bytes::<V>() + 8, |input| {
            Ok(BvhNode {
                bounds: input.aabb()?,
                first: input.u32()?,
                count: input.u32()?,
            })
        })?;
        let primitive_indices = input.u32s()?;
        check_links(nodes.len(), primitive_indices.len(), |index| {
            let node = &nodes[index];
            Ok(Link::of(node.is_leaf(), node.first, node.count, 2))
        })?;
        Ok(Self {
            nodes,
            primitive_indices,
        })
    }
}
