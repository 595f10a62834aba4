//! Measurements of a built tree (BVH or kD-tree).

use crate::aabb::Aabb;
use crate::bvh::Bvh;
use crate::kd::KdTree;
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
    /// The SAH cost of the whole tree: `Σ_interior C_trav·A(n)/A(root) +
    /// Σ_leaves N·C_isect·A(n)/A(root)`, the expected cost of a random ray through the root
    /// (A is a node's box in a BVH, its cell in a kD-tree).
    pub sah_cost: f64,
}

/// Adds up nodes as a walk from the root meets them.
struct Tally<'a> {
    stats: TreeStats,
    cost: &'a SahCost,
    root_area: f64,
    leaf_primitives: usize,
}

impl<'a> Tally<'a> {
    fn new(node_count: usize, root_area: f64, cost: &'a SahCost) -> Self {
        Self {
            stats: TreeStats {
                node_count,
                min_leaf_size: usize::MAX,
                ..TreeStats::default()
            },
            cost,
            root_area,
            leaf_primitives: 0,
        }
    }

    fn relative(&self, area: f64) -> f64 {
        if self.root_area > 0.0 {
            area / self.root_area
        } else {
            1.0
        }
    }

    fn leaf(&mut self, area: f64, count: usize, depth: usize) {
        let weight = self.relative(area);
        let stats = &mut self.stats;
        stats.leaf_count += 1;
        stats.max_depth = stats.max_depth.max(depth);
        stats.min_leaf_size = stats.min_leaf_size.min(count);
        stats.max_leaf_size = stats.max_leaf_size.max(count);
        stats.sah_cost += weight * self.cost.leaf_cost(count);
        self.leaf_primitives += count;
    }

    fn interior(&mut self, area: f64) {
        self.stats.sah_cost += self.relative(area) * self.cost.traversal_cost;
    }

    fn finish(mut self) -> TreeStats {
        self.stats.mean_leaf_size = self.leaf_primitives as f64 / self.stats.leaf_count as f64;
        self.stats
    }
}

impl TreeStats {
    /// Measures `bvh` with the cost constants `cost`.
    pub fn of_bvh<V: Vector>(bvh: &Bvh<V>, cost: &SahCost) -> Self {
        let Some(root) = bvh.nodes.first() else {
            return Self::default();
        };
        let mut tally = Tally::new(bvh.nodes.len(), root.bounds.area().to_f64(), cost);
        let mut pending = vec![(0u32, 0usize)];
        while let Some((index, depth)) = pending.pop() {
            let node = &bvh.nodes[index as usize];
            let area = node.bounds.area().to_f64();
            if node.is_leaf() {
                tally.leaf(area, node.count as usize, depth);
            } else {
                tally.interior(area);
                pending.extend(node.children().map(|child| (child, depth + 1)));
            }
        }
        tally.finish()
    }

    /// Measures `tree` with the cost constants `cost` (a straddling primitive counts in every
    /// leaf that lists it).
    pub fn of_kd<V: Vector>(tree: &KdTree<V>, cost: &SahCost) -> Self {
        if tree.nodes.is_empty() {
            return Self::default();
        }
        let mut tally = Tally::new(tree.nodes.len(), tree.bounds.area().to_f64(), cost);
        let mut pending: Vec<(u32, Aabb<V>, usize)> = vec![(0, tree.bounds, 0)];
        while let Some((index, cell, depth)) = pending.pop() {
            let node = &tree.nodes[index as usize];
            let area = cell.area().to_f64();
            if node.is_leaf() {
                tally.leaf(area, node.count as usize, depth);
            } else {
                tally.interior(area);
                let cells = KdTree::child_cells(node, &cell);
                for (child, cell) in node.children().into_iter().zip(cells) {
                    pending.push((child, cell, depth + 1));
                }
            }
        }
        tally.finish()
    }
}
