//! Measurements of a built tree.

use crate::bvh::tree::Bvh;
use crate::math::{Real, Vector};
use crate::sah::SahCost;

/// The shape and predicted cost of a BVH.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhStats {
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
    /// The SAH cost of the whole tree: `Σ_interior C_trav·A(n)/A(root) +
    /// Σ_leaves N·C_isect·A(n)/A(root)`, the expected cost of a random ray through the root.
    pub sah_cost: f64,
}

impl BvhStats {
    /// Measures `bvh` with the cost constants `cost`.
    pub fn of<V: Vector>(bvh: &Bvh<V>, cost: &SahCost) -> Self {
        let Some(root) = bvh.nodes.first() else {
            return Self::default();
        };
        let root_area = root.bounds.area().to_f64();
        let relative_area = |area: f64| {
            if root_area > 0.0 {
                area / root_area
            } else {
                1.0
            }
        };
        let mut stats = Self {
            node_count: bvh.nodes.len(),
            min_leaf_size: usize::MAX,
            ..Self::default()
        };
        let mut total_leaf_primitives = 0;
        let mut pending = vec![(0u32, 0usize)];
        while let Some((index, depth)) = pending.pop() {
            let node = &bvh.nodes[index as usize];
            let area = relative_area(node.bounds.area().to_f64());
            if node.is_leaf() {
                let count = node.count as usize;
                stats.leaf_count += 1;
                stats.max_depth = stats.max_depth.max(depth);
                stats.min_leaf_size = stats.min_leaf_size.min(count);
                stats.max_leaf_size = stats.max_leaf_size.max(count);
                total_leaf_primitives += count;
                stats.sah_cost += area * cost.leaf_cost(count);
            } else {
                stats.sah_cost += area * cost.traversal_cost;
                for child in node.children() {
                    pending.push((child, depth + 1));
                }
            }
        }
        stats.mean_leaf_size = total_leaf_primitives as f64 / stats.leaf_count as f64;
        stats
    }
}
