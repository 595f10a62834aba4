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
use crate::grid::CellStore;
use crate::math::{Real, Vector, Vector3};
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
                pending.extend(children.iter());
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
            Tree::Grid(grid) => Self {
                bytes: grid.store.bytes(),
                fill_rate: None,
            },
            Tree::HashedGrid(grid) => Self {
                bytes: grid.store.bytes(),
                fill_rate: None,
            },
            Tree::Octree(tree) => Self {
                bytes: size_of_val(tree.nodes.as_slice())
                    + size_of_val(tree.primitive_indices.as_slice()),
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

/// Counts how many times each node is entered (an observer): what the SAH's chances are
/// checked against.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NodeEntries(pub Vec<u64>);

impl NodeEntries {
    /// Counts for a tree of `node_count` nodes (numbered as its facts are).
    pub fn new(node_count: usize) -> Self {
        Self(vec![0; node_count])
    }
}

impl<S: Real> crate::observer::Observer<S> for NodeEntries {
    #[inline(always)]
    fn node_entered(&mut self, node: u32) {
        if let Some(count) = self.0.get_mut(node as usize) {
            *count += 1;
        }
    }
}

/// The SAH's assumption, checked: it takes the chance that a ray entering a node enters a
/// child to be the ratio of their areas (rays from outside, uniformly distributed, crossing
/// the whole tree). Measured rays stop at their first hit, start inside, or come from a
/// camera, and enter other shares.
#[derive(Clone, Debug, PartialEq)]
pub struct SahCheck {
    /// For each depth: the nodes a ray entering the root is expected to enter there, as the
    /// SAH predicts (`Σ A(n)/A(root)`) and as the rays did (`Σ entries(n)/entries(root)`).
    pub per_depth: Vec<(usize, f64, f64)>,
    /// The SAH cost of the tree (the predicted chances).
    pub sah_cost: f64,
    /// The same sum with the measured chances: the cost the SAH would have predicted had it
    /// known where these rays go.
    pub measured_chance_cost: f64,
    /// Rays that entered the root.
    pub rays_entering: u64,
}

impl SahCheck {
    /// Compares `facts`'s areas with `entries` counted over some rays.
    pub fn of<V: Vector>(facts: &TreeFacts<V>, entries: &NodeEntries, cost: &SahCost) -> Self {
        let root_area = facts
            .bounds
            .first()
            .map_or(0.0, |root| root.area().to_f64());
        let root_entries = entries.0.first().copied().unwrap_or(0);
        let mut per_depth: Vec<(usize, f64, f64)> = Vec::new();
        let (mut sah_cost, mut measured_chance_cost) = (0.0, 0.0);
        for node in 0..facts.bounds.len() {
            let depth = facts.depth[node] as usize;
            if per_depth.len() <= depth {
                per_depth.extend((per_depth.len()..=depth).map(|depth| (depth, 0.0, 0.0)));
            }
            let predicted = if root_area > 0.0 {
                facts.bounds[node].area().to_f64() / root_area
            } else {
                1.0
            };
            let measured = if root_entries > 0 {
                entries.0.get(node).copied().unwrap_or(0) as f64 / root_entries as f64
            } else {
                0.0
            };
            per_depth[depth].1 += predicted;
            per_depth[depth].2 += measured;
            let node_cost = if facts.is_leaf(node as u32) {
                cost.leaf_cost(facts.leaf_sizes[node] as usize)
            } else {
                cost.traversal_cost
            };
            sah_cost += predicted * node_cost;
            measured_chance_cost += measured * node_cost;
        }
        Self {
            per_depth,
            sah_cost,
            measured_chance_cost,
            rays_entering: root_entries,
        }
    }
}

fn area<V: Vector3>([a, b, c]: &[V; 3]) -> f64 {
    let to = |point: &V| glam::DVec3::from_array(point.to_f64_array());
    0.5 * (to(b) - to(a)).cross(to(c) - to(a)).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::{BinnedSah, Builder};
    use crate::params::BuildParams;
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
    fn rays_that_cross_everything_enter_what_the_sah_predicts_and_stopping_rays_less() {
        use crate::TraversalStacks;
        // Two unit squares side by side (x in [0,1] and [2,3]), facing +z, a leaf each under
        // a root box [0,3] × [0,1] × [0,0]. Its area (a flat box: twice 3 × 1) is 6, each
        // leaf's 2: the SAH gives each leaf a chance of 1/3.
        let square = |x: f64| {
            [
                [[x, 0.0, 0.0], [x + 1.0, 0.0, 0.0], [x + 1.0, 1.0, 0.0]],
                [[x, 0.0, 0.0], [x + 1.0, 1.0, 0.0], [x, 1.0, 0.0]],
            ]
        };
        let mut corners = square(0.0).to_vec();
        corners.extend(square(2.0));
        let triangles = TriangleSet::<DVec3>::from_f64(&corners);
        let params = BuildParams {
            max_leaf_size: 2,
            ..BuildParams::default()
        };
        let tree = crate::Structure::BvhMedian {
            width: crate::Width::Binary,
        }
        .build(&triangles, &params);
        let facts = TreeFacts::of(&tree);
        assert_eq!(facts.bounds.len(), 3);
        // Rays straight down through the left square: each enters the root and the left leaf.
        let mut entries = NodeEntries::new(3);
        let mut stacks = TraversalStacks::default();
        for step in 0..10 {
            let x = 0.05 + 0.09 * f64::from(step);
            let ray = crate::Ray::try_new(DVec3::new(x, 0.5, 1.0), DVec3::NEG_Z).unwrap();
            tree.trace(
                &triangles,
                &ray,
                &Default::default(),
                &mut stacks,
                &mut entries,
            );
        }
        let check = SahCheck::of(&facts, &entries, &SahCost::default());
        assert_eq!(check.rays_entering, 10);
        assert_eq!(check.per_depth.len(), 2);
        let (depth, predicted, measured) = check.per_depth[1];
        assert_eq!(depth, 1);
        assert!((predicted - 2.0 / 3.0).abs() < 1e-12, "{predicted}");
        assert_eq!(measured, 1.0, "one leaf of the two, every time");
        // SAH: C_trav + 2 leaves · (2 · C_isect) · 1/3 = 3 + 4/3; measured: 3 + 2.
        assert!((check.sah_cost - (3.0 + 4.0 / 3.0)).abs() < 1e-12);
        assert!((check.measured_chance_cost - 5.0).abs() < 1e-12);
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
