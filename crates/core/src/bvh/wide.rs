//! The wide BVH's memory layout: nodes of `W` children (4 or 8) whose boxes are stored axis by
//! axis, so one node's children are tested together, in SIMD lanes where the machine has them.
//!
//! A wide BVH is a binary BVH collapsed ([`collapse`](super::collapse)): each wide node stands
//! for a few binary nodes, and each of its children is a binary subtree, either another wide
//! node or a leaf. The tree keeps the binary tree it came from, and names every wide node and
//! leaf by the binary node at the top of its subtree, so the app's views, the heat maps and
//! [`TreeFacts`](crate::facts::TreeFacts) see a wide traversal in the binary tree's numbering:
//! "node 12 entered" is the same box whichever width traced it.

use crate::aabb::Aabb;
use crate::bvh::tree::Bvh;
use crate::math::{Real, Vector};
use crate::primitive::{LeafOrdered, PrimitiveSet};
use crate::sah::SahCost;
use crate::stats::TreeStats;

/// How many primitives a wide leaf stores side by side: the width of the triangle test that
/// tests a leaf at once. Each leaf's primitives start at a multiple of this in
/// [`WideBvh::primitive_indices`].
pub const LEAF_BLOCK: usize = 4;

/// The side of [`WideNode::planes`] with the children's smallest coordinates.
pub const LOWER: usize = 0;
/// The side with their largest coordinates.
pub const UPPER: usize = 1;

/// A child slot that holds nothing (its box is empty, so every ray misses it).
pub const EMPTY_SLOT: u32 = u32::MAX;

/// One wide node: the boxes of up to `W` children, axis by axis, and where each child is.
///
/// `planes[LOWER][axis][slot]` and `planes[UPPER][axis][slot]` are child `slot`'s box (2D trees
/// leave the z rows unused). The two sides are indexed, not named, so a traversal picks a ray's
/// near and far planes by the sign of its direction with an index it computes once per ray
/// (Williams et al. 2005), instead of a select at every node. Slot `s` is:
/// - a wide node when `count[s] == 0` and `child[s] != EMPTY_SLOT`: `child[s]` is its index;
/// - a leaf when `count[s] > 0`: its primitives are `primitive_indices[child[s]..][..count[s]]`,
///   and `child[s]` is a multiple of [`LEAF_BLOCK`];
/// - empty when `child[s] == EMPTY_SLOT`: its box is the empty box (`+∞` lower, `−∞` upper),
///   which every slab test misses without a special case. Empty slots come last.
///
/// In f32: 128 bytes for `W = 4` and 256 for `W = 8`, two and four cache lines.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct WideNode<S: Real, const W: usize> {
    /// The children's smallest ([`LOWER`]) and largest ([`UPPER`]) coordinates, per axis.
    pub planes: [[[S; W]; 3]; 2],
    /// A wide node's index, a leaf's first primitive slot, or [`EMPTY_SLOT`].
    pub child: [u32; W],
    /// A leaf's primitive count; 0 for a wide node or an empty slot.
    pub count: [u32; W],
}

impl<S: Real, const W: usize> Default for WideNode<S, W> {
    fn default() -> Self {
        Self {
            planes: [[[S::INFINITY; W]; 3], [[S::NEG_INFINITY; W]; 3]],
            child: [EMPTY_SLOT; W],
            count: [0; W],
        }
    }
}

/// What a slot of a wide node holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// Nothing.
    Empty,
    /// The wide node with this index.
    Node(u32),
    /// A leaf: primitive slots `first..first + count`.
    Leaf {
        /// Its first slot in [`WideBvh::primitive_indices`].
        first: u32,
        /// How many primitives.
        count: u32,
    },
}

impl<S: Real, const W: usize> WideNode<S, W> {
    /// What slot `slot` holds.
    #[inline(always)]
    pub fn slot(&self, slot: usize) -> Slot {
        match (self.child[slot], self.count[slot]) {
            (EMPTY_SLOT, _) => Slot::Empty,
            (node, 0) => Slot::Node(node),
            (first, count) => Slot::Leaf { first, count },
        }
    }

    /// Child `slot`'s box.
    pub fn slot_bounds<V: Vector<Scalar = S>>(&self, slot: usize) -> Aabb<V> {
        let mut bounds = Aabb::<V>::empty();
        for axis in 0..V::DIM {
            bounds.min[axis] = self.planes[LOWER][axis][slot];
            bounds.max[axis] = self.planes[UPPER][axis][slot];
        }
        bounds
    }

    /// The number of slots in use (they come first).
    pub fn slots_used(&self) -> usize {
        // Empty slots come last, so the used ones are those not empty: counted without a
        // branch, which compiles to one vector comparison (a loop that stops at the first
        // empty slot took 2 % of a packet traversal's time).
        self.child
            .iter()
            .map(|&child| usize::from(child != EMPTY_SLOT))
            .sum()
    }
}

/// A BVH with `W` children per node, collapsed from the binary BVH it keeps.
///
/// Node 0 is the root; its box is the binary root's, and traversal starts by testing its
/// children. An empty primitive set gives no nodes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WideBvh<V: Vector, const W: usize> {
    /// The wide nodes; `nodes[0]` is the root. A node's wide children are side by side.
    pub nodes: Vec<WideNode<V::Scalar, W>>,
    /// Primitive numbers in leaf order, each leaf starting at a multiple of [`LEAF_BLOCK`]
    /// and padded to one by repeating its last primitive (padding is never tested).
    pub primitive_indices: Vec<u32>,
    /// Per wide node, the binary node it stands for (the top of its binary subtree).
    pub node_sources: Vec<u32>,
    /// Per block of [`LEAF_BLOCK`] primitive slots, the binary node of the leaf starting
    /// there (the top of the binary subtree it holds); [`EMPTY_SLOT`] inside longer leaves.
    pub leaf_sources: Vec<u32>,
    /// The binary tree this one was collapsed from: its numbering names nodes to observers.
    pub binary: Bvh<V>,
}

impl<V: Vector, const W: usize> WideBvh<V, W> {
    /// The same tree in another precision `U`, node for node (see [`Bvh::converted`]).
    pub fn converted<U: Vector>(&self) -> WideBvh<U, W> {
        let scalar = |value: V::Scalar| U::Scalar::from_f64(value.to_f64());
        WideBvh {
            nodes: self
                .nodes
                .iter()
                .map(|node| WideNode {
                    planes: node.planes.map(|side| side.map(|axis| axis.map(scalar))),
                    child: node.child,
                    count: node.count,
                })
                .collect(),
            primitive_indices: self.primitive_indices.clone(),
            node_sources: self.node_sources.clone(),
            leaf_sources: self.leaf_sources.clone(),
            binary: self.binary.converted(),
        }
    }

    /// The number of wide nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The root's box (empty without primitives).
    pub fn bounds(&self) -> Aabb<V> {
        self.binary.bounds()
    }

    /// The binary node a child stands for: wide node `child` when `count` is 0, else the leaf
    /// of `count` primitives from slot `child`.
    #[inline(always)]
    pub fn child_source(&self, child: u32, count: u32) -> u32 {
        match count {
            0 => self.node_sources[child as usize],
            _ => self.leaf_sources[child as usize / LEAF_BLOCK],
        }
    }

    /// The binary node slot `slot` of wide node `node` stands for ([`EMPTY_SLOT`] when empty).
    #[inline(always)]
    pub fn slot_source(&self, node: usize, slot: usize) -> u32 {
        let node = &self.nodes[node];
        match node.child[slot] {
            EMPTY_SLOT => EMPTY_SLOT,
            child => self.child_source(child, node.count[slot]),
        }
    }

    /// A copy of `primitives` stored in this tree's (padded) leaf order, for faster traversal
    /// (the hits keep their numbers); 3D triangles are also packed four to a block, so a
    /// leaf's triangles are tested at once.
    pub fn leaf_ordered<P: PrimitiveSet<V>>(&self, primitives: &P) -> LeafOrdered<P> {
        LeafOrdered::with_blocks(primitives.permuted(&self.primitive_indices))
    }

    /// The primitives of a leaf slot.
    pub fn leaf_primitives(&self, first: u32, count: u32) -> &[u32] {
        &self.primitive_indices[first as usize..][..count as usize]
    }

    /// The wide tree's shape and SAH cost: wide nodes and leaves count as nodes, depths are
    /// wide levels, and the cost is `Σ_wide nodes C_trav·A(n)/A(root) + Σ_leaves
    /// N·C_isect·A(leaf)/A(root)`, what [`collapse`](super::collapse) minimises.
    pub fn stats(&self, cost: &SahCost) -> TreeStats {
        if self.nodes.is_empty() {
            return TreeStats::default();
        }
        let root_area = self.bounds().area().to_f64();
        let relative = |area: V::Scalar| {
            if root_area > 0.0 {
                area.to_f64() / root_area
            } else {
                1.0
            }
        };
        let mut stats = TreeStats {
            min_leaf_size: usize::MAX,
            sah_cost: cost.traversal_cost,
            ..TreeStats::default()
        };
        let mut pending = vec![(0usize, 0usize)];
        while let Some((index, depth)) = pending.pop() {
            stats.node_count += 1;
            let node = &self.nodes[index];
            for slot in 0..node.slots_used() {
                let area = relative(node.slot_bounds::<V>(slot).area());
                match node.slot(slot) {
                    Slot::Empty => {}
                    Slot::Node(child) => {
                        stats.sah_cost += area * cost.traversal_cost;
                        pending.push((child as usize, depth + 1));
                    }
                    Slot::Leaf { count, .. } => {
                        let size = count as usize;
                        stats.node_count += 1;
                        stats.leaf_count += 1;
                        stats.max_depth = stats.max_depth.max(depth + 1);
                        stats.min_leaf_size = stats.min_leaf_size.min(size);
                        stats.max_leaf_size = stats.max_leaf_size.max(size);
                        stats.primitive_references += size;
                        stats.sah_cost += area * cost.leaf_cost(size);
                    }
                }
            }
        }
        stats.mean_leaf_size = stats.primitive_references as f64 / stats.leaf_count as f64;
        stats
    }
}
