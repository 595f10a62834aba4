//! The octree's memory layout (a quadtree in 2D, from the same source).

use crate::aabb::Aabb;
use crate::facts::{Children, Hierarchy};
use crate::math::{Real, Vector};
use crate::primitive::{LeafOrdered, PrimitiveSet};

/// One node: a cell cut into `2^D` equal children, or a leaf with a run of primitives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OctreeNode {
    /// Interior: its first child (the others follow it). Leaf: its first slot in
    /// [`Octree::primitive_indices`].
    pub first: u32,
    /// Leaf: how many primitives (0 for an empty cell). Interior: [`OctreeNode::INTERIOR`].
    pub count: u32,
}

impl OctreeNode {
    /// The `count` of an interior node.
    pub const INTERIOR: u32 = u32::MAX;

    /// True for a leaf.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.count != Self::INTERIOR
    }
}

/// An octree (quadtree in 2D) over primitives numbered `0..n`. Node 0 is the root, whose cell
/// is `bounds`; an interior node's cell is cut at its middle along every axis, and child `c`
/// (`0..2^D`) is the part above the middle along each axis whose bit is set in `c` (x the
/// lowest bit): the octant numbering of Revelles, Ureña & Lastra 2000. A primitive is listed
/// in every leaf it reaches.
#[derive(Clone, Debug, PartialEq)]
pub struct Octree<V: Vector> {
    /// The root cell: the box around every primitive.
    pub bounds: Aabb<V>,
    /// The nodes; `nodes[0]` is the root.
    pub nodes: Vec<OctreeNode>,
    /// Primitive numbers in leaf order (with repeats for primitives in several leaves).
    pub primitive_indices: Vec<u32>,
    /// How deep the builder could go, and whether a budget made it stop short.
    pub limits: OctreeLimits,
}

/// The depth an octree build allowed, and what stopped it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OctreeLimits {
    /// The deepest a leaf may lie.
    pub depth_limit: usize,
    /// Leaves made at the depth limit that would otherwise have been cut.
    pub leaves_at_depth_limit: usize,
    /// The usual limit, when a budget (nodes, references) made the build use a lower one.
    pub lowered_from: Option<usize>,
}

/// The children a cell is cut into: `2^D`.
#[inline(always)]
pub fn child_count<V: Vector>() -> usize {
    1 << V::DIM
}

/// The middle of `cell` along each axis, where an interior node cuts it: computed one way,
/// here, by the builder and the traversal alike.
#[inline(always)]
pub fn middle<V: Vector>(cell: &Aabb<V>) -> V {
    let half = V::Scalar::ONE / V::Scalar::TWO;
    let mut middle = cell.min;
    for axis in 0..V::DIM {
        middle[axis] = cell.min[axis] + (cell.max[axis] - cell.min[axis]) * half;
    }
    middle
}

/// Child `child`'s cell within `cell` cut at `middle`.
#[inline(always)]
pub fn child_cell<V: Vector>(cell: &Aabb<V>, middle: V, child: usize) -> Aabb<V> {
    let mut part = *cell;
    for axis in 0..V::DIM {
        if child & (1 << axis) != 0 {
            part.min[axis] = middle[axis];
        } else {
            part.max[axis] = middle[axis];
        }
    }
    part
}

impl<V: Vector> Octree<V> {
    /// The same tree in another precision `W`, node for node (exact from f32 to f64; see
    /// [`Vector::converted`]).
    pub fn converted<W: Vector>(&self) -> Octree<W> {
        Octree {
            bounds: self.bounds.converted(),
            nodes: self.nodes.clone(),
            primitive_indices: self.primitive_indices.clone(),
            limits: self.limits,
        }
    }

    /// The primitives of a leaf.
    pub fn leaf_primitives(&self, node: &OctreeNode) -> &[u32] {
        &self.primitive_indices[node.first as usize..][..node.count as usize]
    }

    /// A copy of `primitives` stored in leaf order (a primitive once for every leaf that lists
    /// it), for faster traversal.
    pub fn leaf_ordered<P: PrimitiveSet<V>>(&self, primitives: &P) -> LeafOrdered<P> {
        LeafOrdered::new(primitives.permuted(&self.primitive_indices))
    }
}

impl<V: Vector> Hierarchy<V> for Octree<V> {
    fn node_count(&self) -> usize {
        self.nodes.len()
    }

    fn children(&self, node: u32) -> Option<Children> {
        let node = &self.nodes[node as usize];
        (!node.is_leaf()).then(|| Children {
            first: node.first,
            count: child_count::<V>() as u32,
        })
    }

    fn leaf_primitives(&self, node: u32) -> &[u32] {
        let node = &self.nodes[node as usize];
        if node.is_leaf() {
            Octree::leaf_primitives(self, node)
        } else {
            &[]
        }
    }

    /// The cells: the root's is the tree's bounds, each interior node's cut at its middle.
    fn node_bounds(&self) -> Vec<Aabb<V>> {
        let mut cells = vec![self.bounds; self.nodes.len()];
        // Parents come before their children: one forward pass.
        for (index, node) in self.nodes.iter().enumerate() {
            if !node.is_leaf() {
                let cell = cells[index];
                let middle = middle(&cell);
                for child in 0..child_count::<V>() {
                    cells[node.first as usize + child] = child_cell(&cell, middle, child);
                }
            }
        }
        cells
    }
}
