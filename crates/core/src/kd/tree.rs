//! The kD-tree's memory layout.

use crate::aabb::Aabb;
use crate::facts::{Children, Hierarchy};
use crate::math::{Real, Vector};
use crate::primitive::{LeafOrdered, PrimitiveSet};

/// One node: a split plane with two children, or a leaf with a run of primitives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KdNode<S: Real> {
    /// Interior: where the plane cuts its axis. Leaf: unused (0).
    pub split: S,
    /// Interior: the split axis (0, 1, 2). Leaf: [`KdNode::LEAF`].
    pub axis: u32,
    /// Interior: the left (below the plane) child; the right child is `first + 1`.
    /// Leaf: the first slot in `primitive_indices`.
    pub first: u32,
    /// Leaf: how many primitives (may be 0: an empty cell). Interior: 0.
    pub count: u32,
}

impl<S: Real> KdNode<S> {
    /// The `axis` value that marks a leaf.
    pub const LEAF: u32 = u32::MAX;

    /// True for a leaf.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.axis == Self::LEAF
    }

    /// The two children (below and above the plane), for an interior node.
    #[inline(always)]
    pub fn children(&self) -> [u32; 2] {
        [self.first, self.first + 1]
    }
}

/// A kD-tree over primitives numbered `0..n`. Node 0 is the root, whose cell is `bounds`. A
/// primitive whose box straddles a plane is listed in both children, so a primitive number can
/// appear in several leaves.
#[derive(Clone, Debug, PartialEq)]
pub struct KdTree<V: Vector> {
    /// The root cell: the box around every primitive.
    pub bounds: Aabb<V>,
    /// The nodes; `nodes[0]` is the root.
    pub nodes: Vec<KdNode<V::Scalar>>,
    /// Primitive numbers in leaf order (with repeats for straddling primitives).
    pub primitive_indices: Vec<u32>,
    /// How deep the builder went, and whether a budget made it stop short.
    pub limits: KdLimits,
}

/// Which budget a kD build would have passed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KdBudgetExceeded {
    /// More than this many nodes.
    Nodes(usize),
    /// More than this many primitive references in leaves.
    References(usize),
}

impl std::fmt::Display for KdBudgetExceeded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            KdBudgetExceeded::Nodes(nodes) => {
                write!(f, "{} nodes", crate::format::count(nodes))
            }
            KdBudgetExceeded::References(references) => write!(
                f,
                "{} primitive references",
                crate::format::count(references)
            ),
        }
    }
}

/// The depth a kD build went to and what stopped it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KdLimits {
    /// No cell deeper than this was cut.
    pub depth_limit: usize,
    /// Leaves at the depth limit that the builder would otherwise have tried to cut.
    pub leaves_at_depth_limit: usize,
    /// When the usual limit would have passed a budget: that limit and the budget. The tree
    /// was then built with the deepest `depth_limit` that fits.
    pub lowered_from: Option<(usize, KdBudgetExceeded)>,
}

impl std::fmt::Display for KdLimits {
    /// What a lecturer is told: `depth limit 12 (lowered from 27 to stay within 200 000
    /// nodes); 3 401 cells stopped there`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "depth limit {}", self.depth_limit)?;
        if let Some((usual, budget)) = self.lowered_from {
            write!(f, " (lowered from {usual} to stay within {budget})")?;
        }
        if self.leaves_at_depth_limit > 0 {
            write!(
                f,
                "; {} cells stopped there",
                crate::format::count(self.leaves_at_depth_limit)
            )?;
        }
        Ok(())
    }
}

impl KdLimits {
    /// Whether a limit changed the tree: cells stopped at the depth limit, or the limit was
    /// lowered for a budget.
    pub fn reached(&self) -> bool {
        self.leaves_at_depth_limit > 0 || self.lowered_from.is_some()
    }
}

impl<V: Vector> KdTree<V> {
    /// The same tree in another precision `W`, node for node (exact from f32 to f64; see
    /// [`Vector::converted`]).
    pub fn converted<W: Vector>(&self) -> KdTree<W> {
        KdTree {
            bounds: self.bounds.converted(),
            nodes: self
                .nodes
                .iter()
                .map(|node| KdNode {
                    split: W::Scalar::from_f64(node.split.to_f64()),
                    axis: node.axis,
                    first: node.first,
                    count: node.count,
                })
                .collect(),
            primitive_indices: self.primitive_indices.clone(),
            limits: self.limits,
        }
    }

    /// The primitives of a leaf.
    pub fn leaf_primitives(&self, node: &KdNode<V::Scalar>) -> &[u32] {
        let first = node.first as usize;
        &self.primitive_indices[first..first + node.count as usize]
    }

    /// The cells of a node's two children: the node's cell cut at its plane.
    pub fn child_cells(node: &KdNode<V::Scalar>, cell: &Aabb<V>) -> [Aabb<V>; 2] {
        let axis = node.axis as usize;
        let mut below = *cell;
        let mut above = *cell;
        below.max[axis] = node.split;
        above.min[axis] = node.split;
        [below, above]
    }

    /// A copy of `primitives` in this tree's leaf order (straddling primitives are copied once
    /// per leaf), for faster traversal; hits keep their numbers.
    pub fn leaf_ordered<P: PrimitiveSet<V>>(&self, primitives: &P) -> LeafOrdered<P> {
        LeafOrdered::new(primitives.permuted(&self.primitive_indices))
    }
}

impl<V: Vector> Hierarchy<V> for KdTree<V> {
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
            KdTree::leaf_primitives(self, node)
        } else {
            &[]
        }
    }

    /// The cells: the root's is the tree's bounds, and each node's plane cuts its cell in two.
    fn node_bounds(&self) -> Vec<Aabb<V>> {
        let mut cells = vec![self.bounds; self.nodes.len()];
        // Parents come before their children, so one forward pass cuts every cell.
        for (index, node) in self.nodes.iter().enumerate() {
            if !node.is_leaf() {
                let [below, above] = node.children();
                let [below_cell, above_cell] = KdTree::child_cells(node, &cells[index]);
                cells[below as usize] = below_cell;
                cells[above as usize] = above_cell;
            }
        }
        cells
    }
}
