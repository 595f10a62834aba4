//! What the observer is told, step by step, for the lecture's quiz: "why first do the near
//! side?" and "what happens in file order?". Two discs on a line and a ray that meets the
//! right-hand one first: near-first finds it and culls the other; file order tests both.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::bvh::{BuildParams, Builder, MedianSplit, TraversalStack, traverse, validate};
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
