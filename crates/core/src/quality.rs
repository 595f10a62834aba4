//! Quality metrics of a built tree beyond its SAH cost: its end-point overlap, its memory
//! and how full its nodes are, its leaves' sizes.
//!
//! The SAH charges every node the chance that a ray crossing the root enters its box, as if
//! nothing stopped rays early. Aila, Karras & Laine 2013 ("On quality metrics of bounding
//! volume hierarchies", HPG) observe that what slows real rays down is geometry a node's box
//! holds that is not its own: a ray hitting that surface first still enters the box. Their
//! *end-point overlap* (EPO) weighs each node's cost by the area of the scene's surface inside
//! its box that belongs to other subtrees, over the whole surface's area:
//!
//! `EPO = Σ_n C(n) · A(S ∩ box(n) \ S(n)) / A(S)`,
//!
//! with `C(n)` = C_trav for an inner node and `N·C_isect` for a leaf of `N` primitives, `S`
//! the scene's triangles and `S(n)` those under `n`. The cells of a kD-tree do not overlap
//! (every part of the surface inside a cell is listed below it), so its EPO is zero: the
//! metric is a BVH's.

use crate::aabb::Aabb;
use crate::facts::{Hierarchy, TreeFacts};
use crate::math::{Vector, Vector3};
use crate::primitive::clip::clipped_area;
use crate::sah::SahCost;
use crate::structure::Tree;

/// The end-point overlap of a tree over `triangles` (the primitives its leaves list, by
/// number), in the SAH's units; 0 for a tree without surface.
pub fn epo<V: Vector3>(tree: &impl Hierarchy<V>, triangles: &[[V; 3]], cost: &SahCost) -> f64 {
    if tree.node_count() == 0 || triangles.is_empty() {
        return 0.0;
    }
    let facts = TreeFacts::of(tree);
    // The leaf each triangle is listed in (a BVH lists each in one).
    let mut leaf_of = vec![u32::MAX; triangles.len()];
    for node in 0..tree.node_count() as u32 {
        for &primitive in tree.leaf_primitives(node) {
            if let Some(slot) = leaf_of.get_mut(primitive as usize) {
                *slot = node;
            }
        }
    }
    let node_cost = |node: u32| {
        if facts.is_leaf(node) {
            cost.leaf_cost(facts.leaf_sizes[node as usize] as usize)
        } else {
            cost.traversal_cost
        }
    };
    let total_area: f64 = triangles.iter().map(|corners| area(corners)).sum();
    if total_area <= 0.0 {
        return 0.0;
    }
    let mut overlap = 0.0;
    let mut pending = Vec::with_capacity(64);
    let mut own = Vec::with_capacity(64);
    for (primitive, corners) in triangles.iter().enumerate() {
        let bounds = Aabb::from_points(*corners);
        // The nodes whose subtree lists this triangle: its leaf and the leaf's ancestors.
        own.clear();
        let mut at = Some(leaf_of[primitive]).filter(|&leaf| leaf != u32::MAX);
        while let Some(node) = at {
            own.push(node);
            at = facts.parent[node as usize];
        }
        pending.clear();
        pending.push(0u32);
        while let Some(node) = pending.pop() {
            let node_bounds = &facts.bounds[node as usize];
            if node_bounds.intersection(&bounds).is_none() {
                continue;
            }
            if !own.contains(&node) {
                overlap += node_cost(node) * clipped_area(corners, node_bounds);
            }
            if let Some(children) = facts.children[node as usize] {
                pending.extend(children);
            }
        }
    }
    overlap / total_area
}

/// What a tree takes in memory for traversal, and how full a wide tree's nodes are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Bytes of the nodes and the leaves' primitive lists that traversal reads (not the
    /// primitives themselves, nor a wide tree's binary source kept for views).
    pub bytes: usize,
    /// A wide BVH's share of child slots in use (1 when every node has all its children).
    pub fill_rate: Option<f64>,
}

impl Footprint {
    /// Measures `tree`.
    pub fn of<V: Vector>(tree: &Tree<V>) -> Self {
        fn fill<V: Vector, const W: usize>(wide: &crate::bvh::WideBvh<V, W>) -> f64 {
            let used: usize = wide.nodes.iter().map(|node| node.slots_used()).sum();
            used as f64 / (wide.nodes.len() * W).max(1) as f64
        }
        match tree {
            Tree::Bvh(bvh) => Self {
                bytes: size_of_val(bvh.nodes.as_slice())
                    + size_of_val(bvh.primitive_indices.as_slice()),
                fill_rate: None,
            },
            Tree::Bvh4(wide) => Self {
                bytes: size_of_val(wide.nodes.as_slice())
                    + size_of_val(wide.primitive_indices.as_slice()),
                fill_rate: Some(fill(wide)),
            },
            Tree::Bvh8(wide) => Self {
                bytes: size_of_val(wide.nodes.as_slice())
                    + size_of_val(wide.primitive_indices.as_slice()),
                fill_rate: Some(fill(wide)),
            },
            Tree::Kd(kd) => Self {
                bytes: size_of_val(kd.nodes.as_slice())
                    + size_of_val(kd.primitive_indices.as_slice()),
                fill_rate: None,
            },
        }
    }
}

/// How many leaves hold each number of primitives: element `k` counts the leaves of `k`
/// (up to the largest leaf).
pub fn leaf_size_histogram<V: Vector>(tree: &impl Hierarchy<V>) -> Vec<u64> {
    let mut histogram: Vec<u64> = Vec::new();
    for node in 0..tree.node_count() as u32 {
        if tree.children(node).is_none() {
            let size = tree.leaf_primitives(node).len();
            if histogram.len() <= size {
                histogram.resize(size + 1, 0);
            }
            histogram[size] += 1;
        }
    }
    histogram
}

fn area<V: Vector3>([a, b, c]: &[V; 3]) -> f64 {
    let to = |point: &V| glam::DVec3::from_array(point.to_f64_array());
    0.5 * (to(b) - to(a)).cross(to(c) - to(a)).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::{BinnedSah, BuildParams, Builder};
    use crate::primitive::{PrimitiveSet, TriangleSet};
    use glam::DVec3;

    #[test]
    fn the_epo_of_two_overlapping_triangles_is_the_part_of_one_in_the_others_leaf() {
        // A: (0,0) (2,0) (0,2); B: (1,1) (3,1) (1,3), both at z = 0, each area 2. A's leaf box
        // [0,2]² holds the unit square [1,2]² of B; B's box [1,3]² holds only A's corner
        // point (1,1). The root lists both. EPO = C_isect·1·1 / (2 + 2) = 0.25.
        let triangles = TriangleSet::<DVec3>::from_f64(&[
            [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]],
            [[1.0, 1.0, 0.0], [3.0, 1.0, 0.0], [1.0, 3.0, 0.0]],
        ]);
        let params = BuildParams {
            max_leaf_size: 1,
            ..BuildParams::default()
        };
        let bvh = BinnedSah::default().build(&triangles.all_bounds(), &params);
        assert_eq!(bvh.nodes.len(), 3, "a root and two leaves");
        let cost = SahCost {
            traversal_cost: 3.0,
            intersection_cost: 1.0,
            empty_bonus: 0.0,
        };
        let value = epo(&bvh, triangles.triangles(), &cost);
        assert!((value - 0.25).abs() < 1e-12, "{value}");
        // Twice the cost of a test, twice the EPO.
        let doubled = SahCost {
            intersection_cost: 2.0,
            ..cost
        };
        assert!((epo(&bvh, triangles.triangles(), &doubled) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn footprint_and_leaf_sizes_of_a_small_tree() {
        let triangles = TriangleSet::<DVec3>::from_f64(&[
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[5.0, 5.0, 0.0], [6.0, 5.0, 0.0], [5.0, 6.0, 0.0]],
            [[9.0, 9.0, 0.0], [9.5, 9.0, 0.0], [9.0, 9.5, 0.0]],
        ]);
        let params = BuildParams {
            max_leaf_size: 1,
            ..BuildParams::default()
        };
        let tree = crate::Structure::BvhMiddle {
            width: crate::Width::Binary,
        }
        .build(&triangles, &params);
        // Five nodes (two inner, three leaves of one) and three primitive numbers.
        let crate::Tree::Bvh(bvh) = &tree else {
            panic!("a binary BVH")
        };
        assert_eq!(bvh.nodes.len(), 5);
        let footprint = Footprint::of(&tree);
        assert_eq!(
            footprint.bytes,
            5 * size_of::<crate::bvh::BvhNode<DVec3>>() + 3 * 4
        );
        assert_eq!(footprint.fill_rate, None);
        assert_eq!(leaf_size_histogram(&tree), [0, 3]);
        // Collapsed into four children a node: one node, three slots of four used.
        let wide = crate::Structure::BvhMiddle {
            width: crate::Width::Four,
        }
        .build(&triangles, &params);
        assert_eq!(Footprint::of(&wide).fill_rate, Some(0.75));
    }

    #[test]
    fn apart_triangles_have_no_overlap() {
        let triangles = TriangleSet::<DVec3>::from_f64(&[
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[5.0, 5.0, 0.0], [6.0, 5.0, 0.0], [5.0, 6.0, 0.0]],
        ]);
        let params = BuildParams {
            max_leaf_size: 1,
            ..BuildParams::default()
        };
        let bvh = BinnedSah::default().build(&triangles.all_bounds(), &params);
        assert_eq!(epo(&bvh, triangles.triangles(), &SahCost::default()), 0.0);
    }
}
