//! The BVH's memory layout.

use crate::aabb::Aabb;
use crate::facts::{Children, Hierarchy};
use crate::math::Vector;
use crate::primitive::{LeafOrdered, PrimitiveSet};

/// One node: its box, and either two children or a run of primitives.
///
/// 32 bytes in 3D f32. A leaf has `count > 0` and owns `primitive_indices[first..first +
/// count]`; an interior node has `count == 0` and children `first` and `first + 1`, side by side
/// so that one cache line holds both boxes traversal tests together.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct BvhNode<V: Vector> {
    /// Bounds of everything below.
    pub bounds: Aabb<V>,
    /// Leaf: the first slot in `primitive_indices`. Interior: the left child's index.
    pub first: u32,
    /// Leaf: how many primitives. Interior: 0.
    pub count: u32,
}

impl<V: Vector> BvhNode<V> {
    /// True for a leaf.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// The two children's indices, for an interior node.
    #[inline(always)]
    pub fn children(&self) -> [u32; 2] {
        [self.first, self.first + 1]
    }
}

/// A bounding volume hierarchy over primitives numbered `0..n`. Node 0 is the root.
///
/// An empty primitive set gives a tree with no nodes (a leaf with `count == 0` would read as
/// an interior node), which every ray misses.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh<V: Vector> {
    /// The nodes; `nodes[0]` is the root.
    pub nodes: Vec<BvhNode<V>>,
    /// Primitive numbers in leaf order.
    pub primitive_indices: Vec<u32>,
}

impl<V: Vector> Bvh<V> {
    /// The same tree in another precision `W`, node for node (exact from f32 to f64; see
    /// [`Vector::converted`]): a tree built in f32 drawn by a view that works in f64.
    pub fn converted<W: Vector>(&self) -> Bvh<W> {
        Bvh {
            nodes: self
                .nodes
                .iter()
                .map(|node| BvhNode {
                    bounds: node.bounds.converted(),
                    first: node.first,
                    count: node.count,
                })
                .collect(),
            primitive_indices: self.primitive_indices.clone(),
        }
    }

    /// The number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The root's box (empty without primitives).
    pub fn bounds(&self) -> Aabb<V> {
        self.nodes
            .first()
            .map_or_else(Aabb::empty, |root| root.bounds)
    }

    /// A copy of `primitives` stored in this tree's leaf order, for faster traversal (the
    /// hits keep their numbers).
    pub fn leaf_ordered<P: PrimitiveSet<V>>(&self, primitives: &P) -> LeafOrdered<P> {
        LeafOrdered::new(primitives.permuted(&self.primitive_indices))
    }

    /// The primitives of a leaf.
    pub fn leaf_primitives(&self, node: &BvhNode<V>) -> &[u32] {
        let first = node.first as usize;
        &self.primitive_indices[first..first + node.count as usize]
    }
}

impl<V: Vector> Hierarchy<V> for Bvh<V> {
    fn node_count(&self) -> usize {
        self.nodes.len()
    }

    fn children(&self, node: u32) -> Option<Children> {
        let node = &self.nodes[node as usize];
        (!node.is_leaf()).then(|| Children::pair(node.children()[0]))
    }

    fn leaf_primitives(&self, node: u32) -> &[u32] {
        let node = &self.nodes[node as usize];
        if node.is_leaf() {
            Bvh::leaf_primitives(self, node)
        } else {
            &[]
        }
    }

    fn node_bounds(&self) -> Vec<Aabb<V>> {
        self.nodes.iter().map(|node| node.bounds).collect()
    }
}
