//! Runaway kD builds stay bounded: a rule that ignores cost (middle cuts down to two
//! primitives a leaf) over thousands of overlapping shapes would make over a million nodes
//! before the usual depth limit stops it. Past the node or reference budget the builder
//! lowers its depth limit to the deepest one that fits, and the tree says so.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::kd::{self, KdBudgetExceeded, KdTree};
use accelviz_core::params::{BuildParams, KdBudget};
use accelviz_core::{
    BuildRecorder, BuildStep, Built, LeafReason, PrimitiveSet, Shape, ShapeSet, Sphere, Structure,
    Tree, TreeStats,
};
use accelviz_scene::scene2d::{Layout, generate};
use glam::DVec2;

fn kd(tree: Tree<DVec2>) -> KdTree<DVec2> {
    match tree {
        Tree::Kd(tree) => tree,
        _ => panic!("a kD structure built a BVH"),
    }
}

fn params(max_nodes: Option<usize>, max_references: Option<usize>) -> BuildParams {
    BuildParams {
        max_leaf_size: 2,
        kd_budget: KdBudget {
            max_nodes,
            max_references,
        },
        ..BuildParams::default()
    }
}

/// 20,000 uniform shapes, middle cuts, two a leaf: bounded to 100,000 nodes, the tree is
/// whole (it validates), even (every cell stopped at one depth limit, lowered from the usual
/// 27) and says which budget lowered it.
#[test]
fn a_runaway_build_lowers_its_depth_limit_to_fit_the_node_budget() {
    let shapes = generate(Layout::Uniform, 20_000, 1);
    let budget = 100_000;
    let mut recorder = BuildRecorder::default();
    let built = Built::new(
        Structure::KdMiddle,
        &shapes,
        &params(Some(budget), None),
        &mut recorder,
    );
    let tree = kd(built.tree.clone());
    kd::validate(&tree, &shapes.all_bounds()).unwrap();
    assert!(tree.nodes.len() <= budget, "{} nodes", tree.nodes.len());
    let limits = tree.limits;
    assert_eq!(
        limits.lowered_from,
        Some((27, KdBudgetExceeded::Nodes(budget)))
    );
    assert!(limits.depth_limit < 27 && limits.leaves_at_depth_limit > 0);
    assert!(limits.reached());
    // One more level would not have fitted: the cells stopped at the limit would each be cut.
    assert!(tree.nodes.len() + 2 * limits.leaves_at_depth_limit > budget);
    assert_eq!(
        limits.to_string(),
        format!(
            "depth limit {} (lowered from 27 to stay within 100\u{a0}000 nodes); {} cells stopped there",
            limits.depth_limit,
            accelviz_core::format::count(limits.leaves_at_depth_limit)
        )
    );
    // The recorder saw only the build that was kept, and the facts know why each leaf stopped.
    let started = recorder
        .steps
        .iter()
        .filter(|step| matches!(step, BuildStep::NodeStarted { .. }))
        .count();
    assert_eq!(started, tree.nodes.len());
    let at_limit = (0..tree.nodes.len() as u32)
        .filter(|&node| {
            matches!(
                built.facts.leaf_reason(node),
                Some(LeafReason::DepthLimit { limit }) if limit == limits.depth_limit
            )
        })
        .count();
    assert_eq!(at_limit, limits.leaves_at_depth_limit);
    assert_eq!(built.facts.max_depth(), limits.depth_limit);
}

/// Big discs overlapping every cut are copied into both children at each one: the reference
/// budget stops them.
#[test]
fn overlapping_primitives_are_bounded_by_the_reference_budget() {
    let mut shapes = generate(Layout::Uniform, 2_000, 3);
    for index in 0..500 {
        shapes.shapes.push(Shape::Sphere(Sphere {
            center: DVec2::new(50.0 + index as f64 * 1e-3, 50.0),
            radius: 60.0,
        }));
    }
    let budget = 30_000;
    let tree = kd(Structure::KdMiddle.build(&shapes, &params(None, Some(budget))));
    kd::validate(&tree, &shapes.all_bounds()).unwrap();
    assert!(tree.primitive_indices.len() <= budget);
    assert_eq!(
        tree.limits.lowered_from.map(|(_, exceeded)| exceeded),
        Some(KdBudgetExceeded::References(budget))
    );
}

/// The default budget leaves cost-driven builds alone, and a small scene's build as it was.
#[test]
fn the_default_budget_does_not_touch_ordinary_builds() {
    let shapes = generate(Layout::Uniform, 5_000, 7);
    for structure in [Structure::KdSah, Structure::KdMedian] {
        let tree = kd(structure.build(&shapes, &BuildParams::default()));
        assert_eq!(tree.limits.lowered_from, None, "{}", structure.name());
        let stats = TreeStats::of(&tree, &BuildParams::default().cost);
        assert!(stats.node_count < 5_000 * KdBudget::DEFAULT_NODES_PER_PRIMITIVE);
    }
    let discs = ShapeSet {
        shapes: (0..8)
            .map(|index| {
                Shape::Sphere(Sphere {
                    center: DVec2::new(index as f64 * 3.0, 0.0),
                    radius: 1.0,
                })
            })
            .collect(),
    };
    let tree = kd(Structure::KdMiddle.build(&discs, &params(None, None)));
    assert_eq!(tree.limits.depth_limit, 12, "8 + 1.3 log2 8");
    assert!(!tree.limits.reached());
}
