//! The kD-tree's special cases, each with the answer written down: a primitive straddling the
//! plane, primitives lying in the plane or only touching it, and a flat scene whose cells have
//! no thickness. Every tree is validated and every ray checked against brute force.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use crate::common;

use accelviz_core::kd::{self, KdBuilder, KdMiddleSplit, KdSah, KdTree};
use accelviz_core::params::BuildParams;
use accelviz_core::{PrimitiveSet, Ray, TreeFacts, TriangleSet};
use common::assert_agrees_with_brute_force;
use glam::DVec3;

/// The primitives listed in the leaves below `node`, sorted, without repeats.
fn primitives_below(tree: &KdTree<DVec3>, node: u32) -> Vec<u32> {
    TreeFacts::of(tree).primitives_below(tree, node)
}

/// A triangle in the plane `y = height`, spanning `x_low..x_high` and `z` 0..1.
fn flat_triangle(x_low: f64, x_high: f64, height: f64) -> [[f64; 3]; 3] {
    [
        [x_low, height, 0.0],
        [x_high, height, 0.0],
        [x_low, height, 1.0],
    ]
}

fn ray(origin: [f64; 3], direction: [f64; 3]) -> Ray<DVec3> {
    Ray::try_new(DVec3::from_array(origin), DVec3::from_array(direction)).unwrap()
}

fn leaf_one() -> BuildParams {
    BuildParams {
        max_leaf_size: 1,
        ..BuildParams::default()
    }
}

/// The root cell is x 0..10; the middle cut is x = 5. Triangle 2 spans the whole width and so
/// straddles the plane: it is listed on both sides, and found from both.
#[test]
fn a_straddling_primitive_is_listed_on_both_sides() {
    let triangles = TriangleSet::from_f64(&[
        flat_triangle(0.0, 1.0, 0.0),
        flat_triangle(9.0, 10.0, 0.0),
        flat_triangle(0.0, 10.0, 1.0),
    ]);
    let bounds = triangles.all_bounds();
    let tree = KdMiddleSplit.build(&bounds, &leaf_one());
    kd::validate(&tree, &bounds).unwrap();
    let root = tree.nodes[0];
    assert_eq!((root.axis, root.split), (0, 5.0));
    let [below, above] = root.children();
    assert_eq!(primitives_below(&tree, below), [0, 2]);
    assert_eq!(primitives_below(&tree, above), [1, 2]);
    let rays = [
        ray([2.0, 5.0, 0.25], [0.0, -1.0, 0.0]),
        ray([8.0, 5.0, 0.25], [0.0, -1.0, 0.0]),
        // Crossing the plane between the two triangles' heights.
        ray([0.5, 2.0, 0.1], [10.0, -1.5, 0.0]),
        ray([9.5, 2.0, 0.1], [-10.0, -1.5, 0.0]),
    ];
    assert_agrees_with_brute_force(&triangles, &rays);
}

/// Triangle 1 lies in the plane x = 5 of the middle cut: it goes to one side only (below, the
/// middle rule's choice), not both. Triangle 2 ends at the plane and triangle 3 starts there:
/// each touches it, and each is listed only on the side that holds the rest of it. Rays
/// through the plane at those triangles, from either side and along it, still find them.
#[test]
fn primitives_in_or_touching_the_plane_go_to_one_side() {
    let in_plane = [[5.0, 0.0, 0.0], [5.0, 1.0, 0.0], [5.0, 0.0, 1.0]];
    let triangles = TriangleSet::from_f64(&[
        flat_triangle(0.0, 1.0, 0.0),
        in_plane,
        flat_triangle(3.0, 5.0, 0.5),
        flat_triangle(5.0, 7.0, 0.5),
        flat_triangle(9.0, 10.0, 0.0),
    ]);
    let bounds = triangles.all_bounds();
    let tree = KdMiddleSplit.build(&bounds, &leaf_one());
    kd::validate(&tree, &bounds).unwrap();
    let root = tree.nodes[0];
    assert_eq!((root.axis, root.split), (0, 5.0));
    let [below, above] = root.children();
    assert_eq!(primitives_below(&tree, below), [0, 1, 2]);
    assert_eq!(primitives_below(&tree, above), [3, 4]);
    let rays = [
        // Through the in-plane triangle, from above the plane and from below.
        ray([8.0, 0.2, 0.2], [-1.0, 0.0, 0.0]),
        ray([2.0, 0.2, 0.2], [1.0, 0.0, 0.0]),
        // Down onto the triangles' shared edge at x = 5, from either side.
        ray([5.0, 2.0, 0.5], [0.0, -1.0, 0.0]),
        ray([6.0, 2.0, 0.5], [-1.0, -1.5, 0.0]),
        ray([4.0, 2.0, 0.5], [1.0, -1.5, 0.0]),
        // Lying in the plane x = 5, and starting on it.
        ray([5.0, 2.0, 0.2], [0.0, -1.0, 0.3]),
        ray([5.0, 0.5, 0.5], [1.0, 0.0, 0.0]),
        ray([5.0, 0.5, 0.5], [-1.0, 0.0, 0.0]),
    ];
    assert_agrees_with_brute_force(&triangles, &rays);
    // The SAH puts a bundle of triangles lying in one plane on the cheaper side.
    let wall: Vec<_> = (0..6)
        .map(|step| {
            let z = step as f64;
            [[5.0, 0.0, z], [5.0, 1.0, z], [5.0, 0.0, z + 1.0]]
        })
        .chain([flat_triangle(0.0, 1.0, 0.0), flat_triangle(9.0, 10.0, 0.0)])
        .collect();
    let wall = TriangleSet::from_f64(&wall);
    let wall_bounds = wall.all_bounds();
    let sah = KdSah.build(&wall_bounds, &BuildParams::default());
    kd::validate(&sah, &wall_bounds).unwrap();
    let listed: usize = sah.nodes.iter().map(|node| node.count as usize).sum();
    assert!(
        listed < 2 * wall.len(),
        "in-plane triangles listed twice: {listed}"
    );
    assert_agrees_with_brute_force(&wall, &rays);
}

/// Every triangle lies in the plane z = 0, so every cell is flat on z: no cut may be made on
/// z, the builders still finish, and rays at every angle, and along the plane, agree with
/// brute force.
#[test]
fn a_flat_scene_is_cut_only_across_its_plane() {
    let triangles: Vec<[[f64; 3]; 3]> = (0..40)
        .map(|index| {
            let (x, y) = ((index % 8) as f64, (index / 8) as f64);
            [[x, y, 0.0], [x + 0.9, y, 0.0], [x, y + 0.9, 0.0]]
        })
        .collect();
    let triangles = TriangleSet::from_f64(&triangles);
    let bounds = triangles.all_bounds();
    for tree in [
        KdMiddleSplit.build(&bounds, &leaf_one()),
        KdSah.build(&bounds, &BuildParams::default()),
    ] {
        kd::validate(&tree, &bounds).unwrap();
        assert!(tree.nodes.len() > 1, "the flat scene was not cut at all");
        assert!(
            tree.nodes
                .iter()
                .all(|node| node.is_leaf() || node.axis != 2)
        );
    }
    let rays = [
        ray([0.3, 0.3, 5.0], [0.0, 0.0, -1.0]),
        ray([-1.0, -1.0, 3.0], [2.0, 1.5, -1.0]),
        ray([7.2, 4.1, -2.0], [0.0, 0.0, 1.0]),
        // In the plane: the triangles are edge-on.
        ray([-1.0, 0.2, 0.0], [1.0, 0.0, 0.0]),
    ];
    assert_agrees_with_brute_force(&triangles, &rays);
}
