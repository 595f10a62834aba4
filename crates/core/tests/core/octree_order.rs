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

/// A mesh in one plane (every triangle at z = 0, as a flat CAD part): the octree cuts only the
/// axes its triangles span, so it is a quadtree in their plane, within a small factor of the
/// kD-tree's SAH cost and of its references (cut at the box's middle along z, every level listed
/// every triangle in both halves: 20 times the kD-tree's cost), and still finds brute force's
/// hits.
#[test]
fn an_octree_over_a_flat_mesh_cuts_only_the_axes_the_mesh_spans() {
    use accelviz_core::sah::SahCost;
    use accelviz_core::{NoObserver, TriangleSet, brute_force};
    use glam::Vec3;
    // 40 × 40 squares of two triangles each in z = 0, and a ray through every square.
    let mut triangles = Vec::new();
    for row in 0..40 {
        for column in 0..40 {
            let (x, y) = (column as f64, row as f64);
            triangles.push([[x, y, 0.0], [x + 1.0, y, 0.0], [x, y + 1.0, 0.0]]);
            triangles.push([
                [x + 1.0, y, 0.0],
                [x + 1.0, y + 1.0, 0.0],
                [x, y + 1.0, 0.0],
            ]);
        }
    }
    let triangles = TriangleSet::<Vec3>::from_f64(&triangles);
    let params = BuildParams::default();
    let cost = SahCost::default();
    let stats = |name: &str| {
        let structure = Structure::parse(name).unwrap();
        let tree = structure.build(&triangles, &params);
        structure.validate(&tree, &triangles).unwrap();
        (tree.stats(&cost), tree)
    };
    let (octree, tree) = stats("octree");
    let (kd, _) = stats("kd:sah");
    println!(
        "octree: SAH {:.2}, references {}; kD-tree: SAH {:.2}, references {}",
        octree.sah_cost, octree.primitive_references, kd.sah_cost, kd.primitive_references
    );
    assert!(
        octree.sah_cost < 3.0 * kd.sah_cost,
        "octree SAH cost {} against the kD-tree's {}",
        octree.sah_cost,
        kd.sah_cost
    );
    assert!(
        octree.primitive_references < 8 * kd.primitive_references.max(3200),
        "octree references {} against the kD-tree's {}",
        octree.primitive_references,
        kd.primitive_references
    );
    let mut stacks = TraversalStacks::default();
    for row in 0..40 {
        for column in 0..40 {
            let target = Vec3::new(column as f32 + 0.3, row as f32 + 0.6, 0.0);
            for origin in [Vec3::new(20.0, 20.0, 10.0), Vec3::new(-3.0, 45.0, -7.0)] {
                let ray = Ray::try_new(origin, target - origin).unwrap();
                let options = TraceOptions::default();
                let got = tree.trace(&triangles, &ray, &options, &mut stacks, &mut NoObserver);
                let expected = brute_force(&triangles, &ray, &options, &mut NoObserver);
                assert_eq!(
                    got.map(|hit| hit.primitive),
                    expected.map(|hit| hit.primitive)
                );
            }
        }
    }
}
