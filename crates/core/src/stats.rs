//! Measurements of a built tree (BVH or kD-tree), or of one subtree of it.

use crate::facts::{Hierarchy, TreeFacts};
use crate::math::{Real, Vector};
use crate::sah::SahCost;

/// The shape and predicted cost of a tree.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TreeStats {
    /// All nodes.
    pub node_count: usize,
    /// Leaves.
    pub leaf_count: usize,
    /// The deepest leaf's depth (the root is at depth 0).
    pub max_depth: usize,
    /// Fewest primitives in a leaf.
    pub min_leaf_size: usize,
    /// Most primitives in a leaf.
    pub max_leaf_size: usize,
    /// Mean primitives per leaf.
    pub mean_leaf_size: f64,
    /// Primitives listed in leaves, counting a kD primitive once in every leaf that lists it.
    pub primitive_references: usize,
    /// Leaves that list nothing (kD cells of empty space).
    pub empty_leaf_count: usize,
    /// The share of the root's area (2D) or volume (3D) that empty leaves cover: space a ray
    /// crosses without a single test.
    pub empty_leaf_share: f64,
    /// The SAH cost of the whole tree: `Σ_interior C_trav·A(n)/A(root) +
    /// Σ_leaves N·C_isect·A(n)/A(root)`, the expected cost of a random ray through the root
    /// (A is a node's box in a BVH, its cell in a kD-tree).
    pub sah_cost: f64,
}

impl TreeStats {
    /// Measures `tree` with the cost constants `cost`.
    pub fn of<V: Vector>(tree: &impl Hierarchy<V>, cost: &SahCost) -> Self {
        if tree.node_count() == 0 {
            return Self::default();
        }
        Self::of_subtree(&TreeFacts::of(tree), 0, cost)
    }

    /// Measures the subtree of `node` as if it were a tree of its own: depths from `node`, and
    /// costs and shares relative to its box or cell (the SAH cost of that subtree).
    pub fn of_subtree<V: Vector>(facts: &TreeFacts<V>, node: u32, cost: &SahCost) -> Self {
        let top = &facts.bounds[node as usize];
        let (top_area, top_measure) = (top.area().to_f64(), top.measure().to_f64());
        let relative = |value: f64, whole: f64| if whole > 0.0 { value / whole } else { 1.0 };
        let top_depth = facts.depth[node as usize];
        let mut stats = Self {
            min_leaf_size: usize::MAX,
            ..Self::default()
        };
        for at in facts.subtree(node) {
            let bounds = &facts.bounds[at as usize];
            let weight = relative(bounds.area().to_f64(), top_area);
            stats.node_count += 1;
            if !facts.is_leaf(at) {
                stats.sah_cost += weight * cost.traversal_cost;
                continue;
            }
            let size = facts.leaf_sizes[at as usize] as usize;
            stats.leaf_count += 1;
            stats.max_depth = stats
                .max_depth
                .max((facts.depth[at as usize] - top_depth) as usize);
            stats.min_leaf_size = stats.min_leaf_size.min(size);
            stats.max_leaf_size = stats.max_leaf_size.max(size);
            stats.primitive_references += size;
            stats.sah_cost += weight * cost.leaf_cost(size);
            if size == 0 {
                stats.empty_leaf_count += 1;
                if top_measure > 0.0 {
                    stats.empty_leaf_share += bounds.measure().to_f64() / top_measure;
                }
            }
        }
        stats.mean_leaf_size = stats.primitive_references as f64 / stats.leaf_count as f64;
        stats
    }
}

impl TreeStats {
    /// Writes the measurements ([`crate::bytes`]), for a caller that sends them with a tree
    /// rather than measure it again.
    pub fn write_bytes(&self, out: &mut crate::bytes::ByteWriter) {
        for count in [
            self.node_count,
            self.leaf_count,
            self.max_depth,
            self.min_leaf_size,
            self.max_leaf_size,
            self.primitive_references,
            self.empty_leaf_count,
        ] {
            out.usize(count);
        }
        for value in [self.mean_leaf_size, self.empty_leaf_share, self.sah_cost] {
            out.f64(value);
        }
    }

    /// The measurements [`TreeStats::write_bytes`] wrote.
    pub fn read_bytes(
        input: &mut crate::bytes::ByteReader<'_>,
    ) -> Result<Self, crate::bytes::BytesError> {
        let mut counts = [0usize; 7];
        for count in &mut counts {
            *count = input.usize()?;
        }
        let [
            node_count,
            leaf_count,
            max_depth,
            min_leaf_size,
            max_leaf_size,
            primitive_references,
            empty_leaf_count,
        ] = counts;
        Ok(Self {
            node_count,
            leaf_count,
            max_depth,
            min_leaf_size,
            max_leaf_size,
            mean_leaf_size: input.f64()?,
            primitive_references,
            empty_leaf_count,
            empty_leaf_share: input.f64()?,
            sah_cost: input.f64()?,
        })
    }
}
