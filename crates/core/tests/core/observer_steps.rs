//! What the observer is told, step by step, for the lecture's quiz: "why first do the near
//! side?" and "what happens in file order?". Two discs on a line and a ray that meets the
//! right-hand one first: near-first finds it and culls the other; file order tests both.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::bvh::{Builder, MedianSplit, TraversalStack, traverse, validate};
use accelviz_core::params::BuildParams;
use accelviz_core::{
    Counters, Order, PrimitiveSet, Ray, Recorder, Shape, ShapeSet, Sphere, Step, TraceOptions,
};
use glam::DVec2;

fn scene() -> ShapeSet<DVec2> {
    let disc = |x: f64| {
        Shape::Sphere(Sphere {
            center: DVec2::new(x, 0.0),
            radius: 0.5,
        })
    };
    // Primitive 0 at x = 2 (the left child), primitive 1 at x = 8 (the right child).
    ShapeSet {
        shapes: vec![disc(2.0), disc(8.0)],
    }
}

fn record(order: Order) -> (Vec<Step<f64>>, Counters, Option<accelviz_core::Hit<f64>>) {
    let shapes = scene();
    let bounds = shapes.all_bounds();
    let params = BuildParams {
        max_leaf_size: 1,
        ..BuildParams::default()
    };
    let bvh = MedianSplit.build(&bounds, &params);
    validate(&bvh, &bounds).unwrap();
    assert_eq!(bvh.primitive_indices, [0, 1], "left leaf holds disc 0");
    // From x = 10 towards −x: disc 1 is met at t = 1.5, disc 0 at t = 7.5.
    let ray = Ray::try_new(DVec2::new(10.0, 0.0), DVec2::new(-1.0, 0.0)).unwrap();
    let options = TraceOptions {
        order,
        ..TraceOptions::default()
    };
    let mut observers = (Recorder::default(), Counters::default());
    let mut stack = TraversalStack::new();
    let hit = traverse(&bvh, &shapes, &ray, &options, &mut stack, &mut observers);
    (observers.0.steps, observers.1, hit)
}

#[test]
fn near_first_finds_the_near_disc_and_culls_the_far_one() {
    let (steps, counters, hit) = record(Order::NearFirst);
    assert_eq!(hit.map(|hit| (hit.primitive, hit.t)), Some((1, 1.5)));
    assert_eq!(
        steps,
        vec![
            Step::BoxTested {
                node: 0,
                t_enter: 1.5,
                t_exit: 8.5,
                hit: true
            },
            Step::NodeEntered { node: 0 },
            Step::BoxTested {
                node: 1,
                t_enter: 7.5,
                t_exit: 8.5,
                hit: true
            },
            Step::BoxTested {
                node: 2,
                t_enter: 1.5,
                t_exit: 2.5,
                hit: true
            },
            Step::NodeEntered { node: 2 },
            Step::PrimitiveTested {
                primitive: 1,
                t_hit: Some(1.5)
            },
            Step::ClosestHitUpdated {
                primitive: 1,
                t: 1.5
            },
            Step::NodeCulled {
                node: 1,
                t_enter: 7.5,
                t_closest: 1.5
            },
        ]
    );
    assert_eq!(
        (
            counters.nodes_visited,
            counters.box_tests,
            counters.primitive_tests,
            counters.nodes_culled
        ),
        (2, 3, 1, 1)
    );
}

#[test]
fn file_order_tests_the_far_disc_first_and_then_the_near_one() {
    let (steps, counters, hit) = record(Order::FileOrder);
    assert_eq!(hit.map(|hit| (hit.primitive, hit.t)), Some((1, 1.5)));
    assert_eq!(
        steps,
        vec![
            Step::BoxTested {
                node: 0,
                t_enter: 1.5,
                t_exit: 8.5,
                hit: true
            },
            Step::NodeEntered { node: 0 },
            Step::BoxTested {
                node: 1,
                t_enter: 7.5,
                t_exit: 8.5,
                hit: true
            },
            Step::BoxTested {
                node: 2,
                t_enter: 1.5,
                t_exit: 2.5,
                hit: true
            },
            Step::NodeEntered { node: 1 },
            Step::PrimitiveTested {
                primitive: 0,
                t_hit: Some(7.5)
            },
            Step::ClosestHitUpdated {
                primitive: 0,
                t: 7.5
            },
            Step::NodeEntered { node: 2 },
            Step::PrimitiveTested {
                primitive: 1,
                t_hit: Some(1.5)
            },
            Step::ClosestHitUpdated {
                primitive: 1,
                t: 1.5
            },
        ]
    );
    assert_eq!(
        (
            counters.nodes_visited,
            counters.box_tests,
            counters.primitive_tests,
            counters.nodes_culled
        ),
        (3, 3, 2, 0)
    );
}

/// The kD traversal reports each cell with the part of the ray in it: the lecture's rayNear
/// and rayFar. The middle cut of the two discs' cell [1.5, 8.5] is x = 5; the ray from x = 10
/// is in the right cell for t in [1.5, 5] and would reach the left one for t in [5, 8.5].
#[test]
fn kd_traversal_reports_the_clipped_segments() {
    use accelviz_core::kd::{KdBuilder, KdMiddleSplit, KdTraversalStack};
    let shapes = scene();
    let bounds = shapes.all_bounds();
    let params = BuildParams {
        max_leaf_size: 1,
        ..BuildParams::default()
    };
    let tree = KdMiddleSplit.build(&bounds, &params);
    assert_eq!(tree.nodes[0].split, 5.0);
    let ray = Ray::try_new(DVec2::new(10.0, 0.0), DVec2::new(-1.0, 0.0)).unwrap();
    let mut observers = (Recorder::default(), Counters::default());
    let hit = accelviz_core::kd::traverse(
        &tree,
        &shapes,
        &ray,
        &TraceOptions::default(),
        &mut KdTraversalStack::new(),
        &mut observers,
    );
    assert_eq!(hit.map(|hit| (hit.primitive, hit.t)), Some((1, 1.5)));
    let [below, above] = tree.nodes[0].children();
    assert_eq!(
        observers.0.steps,
        vec![
            Step::BoxTested {
                node: 0,
                t_enter: 1.5,
                t_exit: 8.5,
                hit: true
            },
            Step::CellEntered {
                node: 0,
                t_near: 1.5,
                t_far: 8.5
            },
            Step::CellEntered {
                node: above,
                t_near: 1.5,
                t_far: 5.0
            },
            Step::PrimitiveTested {
                primitive: 1,
                t_hit: Some(1.5)
            },
            Step::ClosestHitUpdated {
                primitive: 1,
                t: 1.5
            },
            Step::NodeCulled {
                node: below,
                t_enter: 5.0,
                t_closest: 1.5
            },
        ]
    );
    assert_eq!(
        observers.1.nodes_visited, 2,
        "a cell entered counts as a node visited"
    );
    assert_eq!(accelviz_core::counters_of(&observers.0.steps), observers.1);
}

/// A ray that stays on one side of a plane: the other side's part of it is empty, which the
/// traversal reports (the lecture's `if empty(ray) return`) without entering that cell. The
/// ray goes straight up at x = 2, left of the plane x = 5, through disc 0's cell only.
#[test]
fn kd_traversal_reports_the_side_a_ray_never_reaches() {
    use accelviz_core::kd::{KdBuilder, KdMiddleSplit, KdTraversalStack};
    let shapes = scene();
    let bounds = shapes.all_bounds();
    let params = BuildParams {
        max_leaf_size: 1,
        ..BuildParams::default()
    };
    let tree = KdMiddleSplit.build(&bounds, &params);
    let ray = Ray::try_new(DVec2::new(2.0, -10.0), DVec2::new(0.0, 1.0)).unwrap();
    let mut observers = (Recorder::default(), Counters::default());
    let hit = accelviz_core::kd::traverse(
        &tree,
        &shapes,
        &ray,
        &TraceOptions::default(),
        &mut KdTraversalStack::new(),
        &mut observers,
    );
    assert_eq!(hit.map(|hit| (hit.primitive, hit.t)), Some((0, 9.5)));
    let [below, above] = tree.nodes[0].children();
    assert_eq!(
        observers.0.steps,
        vec![
            Step::BoxTested {
                node: 0,
                t_enter: 9.5,
                t_exit: 10.5,
                hit: true
            },
            Step::CellEntered {
                node: 0,
                t_near: 9.5,
                t_far: 10.5
            },
            Step::CellMissed { node: above },
            Step::CellEntered {
                node: below,
                t_near: 9.5,
                t_far: 10.5
            },
            Step::PrimitiveTested {
                primitive: 0,
                t_hit: Some(9.5)
            },
            Step::ClosestHitUpdated {
                primitive: 0,
                t: 9.5
            },
        ]
    );
    assert_eq!(
        observers.1.nodes_visited, 2,
        "a cell the ray misses is not visited"
    );
}

/// The deepest stack a ray needs: one node waits while the near disc's leaf is visited (the
/// two-leaf tree), and over a row of discs a ray along the row keeps at most one waiting node
/// a level, so never more than the tree's depth; every traversal tells it.
#[test]
fn the_deepest_stack_is_told_and_never_deeper_than_the_tree() {
    use accelviz_core::{MaxStack, Structure, TraversalStacks, Width};
    let row = ShapeSet {
        shapes: (0..32)
            .map(|index| {
                Shape::Sphere(Sphere {
                    center: DVec2::new(2.0 * index as f64, 0.0),
                    radius: 0.6,
                })
            })
            .collect(),
    };
    let params = BuildParams {
        max_leaf_size: 1,
        ..BuildParams::default()
    };
    // Along the row, from its left end: every box is hit, the far sides all wait.
    let ray = Ray::try_new(DVec2::new(-5.0, 0.0), DVec2::new(1.0, 0.0)).unwrap();
    let options = TraceOptions {
        query: accelviz_core::Query::Closest,
        ..TraceOptions::default()
    };
    for structure in [
        Structure::BvhMedian {
            width: Width::Binary,
        },
        Structure::KdMedian,
    ] {
        let tree = structure.build(&row, &params);
        let depth = accelviz_core::TreeStats::of(&tree, &params.cost).max_depth;
        let mut deepest = MaxStack::default();
        let mut stacks = TraversalStacks::default();
        let hit = tree.trace(&row, &ray, &options, &mut stacks, &mut deepest);
        assert_eq!(
            hit.map(|hit| hit.primitive),
            Some(0),
            "{}",
            structure.name()
        );
        assert!(
            deepest.0 >= 1 && deepest.0 <= depth,
            "{}: {} waiting, depth {depth}",
            structure.name(),
            deepest.0
        );
    }
}
