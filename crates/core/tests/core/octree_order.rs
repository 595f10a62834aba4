//! The octree's walk, written down on a quadtree: the children a ray passes, front to back
//! near first and by their numbers in file order, and the ones it does not reach.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::params::BuildParams;
use accelviz_core::{
    Built, NoBuildObserver, Order, Ray, Recorder, Shape, ShapeSet, Sphere, Step, Structure,
    TraceOptions, TraversalStacks,
};
use glam::DVec2;

/// Four small discs, one in each quadrant of [0, 4]² (and specks at two corners to make the
/// box), in a quadtree of leaves of one disc: the root cut into four.
fn quadtree() -> (ShapeSet<DVec2>, Built<DVec2>) {
    let disc = |x: f64, y: f64, radius: f64| {
        Shape::Sphere(Sphere {
            center: DVec2::new(x, y),
            radius,
        })
    };
    let shapes = ShapeSet {
        shapes: vec![
            disc(1.0, 1.0, 0.2),
            disc(3.0, 1.0, 0.2),
            disc(1.0, 3.0, 0.2),
            disc(3.0, 3.0, 0.2),
            disc(0.0, 0.0, 0.0),
            disc(4.0, 4.0, 0.0),
        ],
    };
    let params = BuildParams {
        max_leaf_size: 1,
        ..BuildParams::default()
    };
    let structure = Structure::parse("octree:2").unwrap();
    let built = Built::new(structure, &shapes, &params, &mut NoBuildObserver);
    (shapes, built)
}

/// The order the root's children are visited in, and the children the ray misses.
fn order_at_root(origin: [f64; 2], direction: [f64; 2], order: Order) -> (Vec<u32>, Vec<u32>) {
    let (shapes, built) = quadtree();
    let ray = Ray::try_new(DVec2::from_array(origin), DVec2::from_array(direction)).unwrap();
    let options = TraceOptions {
        order,
        ..TraceOptions::default()
    };
    let mut recorder = Recorder::default();
    built.tree.trace(
        &shapes,
        &ray,
        &options,
        &mut TraversalStacks::default(),
        &mut recorder,
    );
    let first = built.facts.children[0].unwrap().first;
    let visited = recorder
        .steps
        .iter()
        .find_map(|step| match *step {
            Step::ChildrenOrdered {
                node: 0,
                order,
                count,
                ..
            } => Some(
                order[..count as usize]
                    .iter()
                    .map(|child| child - first)
                    .collect(),
            ),
            _ => None,
        })
        .unwrap();
    let missed = recorder
        .steps
        .iter()
        .filter_map(|step| match *step {
            Step::CellMissed { node } if node >= first && node < first + 4 => Some(node - first),
            _ => None,
        })
        .collect();
    (visited, missed)
}

#[test]
fn a_ray_passes_the_quadrants_it_crosses_front_to_back_or_by_number() {
    // From the lower left: quadrant 0 (x and y low), across x = 2 into 1, across y = 2 into 3.
    assert_eq!(
        order_at_root([-1.0, 0.5], [1.0, 0.4], Order::NearFirst),
        (vec![0, 1, 3], vec![2])
    );
    // From the upper right, backwards: 3, across x = 2 into 2, across y = 2 into 0.
    assert_eq!(
        order_at_root([5.0, 3.5], [-1.0, -0.4], Order::NearFirst),
        (vec![3, 2, 0], vec![1])
    );
    // File order: the same quadrants, by their numbers.
    assert_eq!(
        order_at_root([5.0, 3.5], [-1.0, -0.4], Order::FileOrder),
        (vec![0, 2, 3], vec![1])
    );
    // Along x = 3 straight up: quadrants 1 and 3 only.
    assert_eq!(
        order_at_root([3.0, -1.0], [0.0, 1.0], Order::NearFirst),
        (vec![1, 3], vec![0, 2])
    );
}
