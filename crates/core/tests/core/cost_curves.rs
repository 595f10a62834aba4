//! SAH cost curves: the exact minimum equals a brute-force evaluation of every candidate, the
//! binned minimum is never below it, and the SAH builders split where the curve is lowest.
//! In 3D (triangles) and 2D (discs, boxes, segments), on random and snapped coordinates.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::bvh::{BinnedSah, Builder, SweepSah};
use accelviz_core::curve::{self, CostCurve};
use accelviz_core::kd::{KdBuilder, KdSah, KdSahPresorted};
use accelviz_core::params::BuildParams;
use accelviz_core::{
    Aabb, Built, LeafReason, NoBuildObserver, PrimitiveSet, Real, SahCost, Shape, ShapeSet, Sphere,
    Structure, Tree, TreeFacts, TriangleSet, Vector,
};
use glam::{DVec2, DVec3};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

fn config() -> Config {
    Config {
        cases: 64,
        rng_seed: RngSeed::Fixed(0xc0_57c0),
        failure_persistence: None,
        ..Config::default()
    }
}

fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![3 => -10.0..10.0f64, 2 => (-3i32..3).prop_map(f64::from)]
}

fn triangles() -> impl Strategy<Value = TriangleSet<DVec3>> {
    prop::collection::vec(
        prop::array::uniform3(prop::array::uniform3(coordinate())),
        2..40,
    )
    .prop_map(|triangles| TriangleSet::from_f64(&triangles))
}

fn shapes() -> impl Strategy<Value = ShapeSet<DVec2>> {
    let shape = (coordinate(), coordinate(), 0.0..2.0f64, 0u8..3).prop_map(|(x, y, size, kind)| {
        let center = DVec2::new(x, y);
        match kind {
            0 => Shape::Sphere(Sphere {
                center,
                radius: size + 0.01,
            }),
            1 => Shape::Box(Aabb::new(center, center + DVec2::splat(size))),
            _ => Shape::Segment([center, center + DVec2::new(size, 0.0)]),
        }
    });
    prop::collection::vec(shape, 2..40).prop_map(|shapes| ShapeSet { shapes })
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
}

fn minimum(curve: &CostCurve) -> Option<f64> {
    curve.axes.iter().flatten().map(|c| c.cost).reduce(f64::min)
}

/// Every kD candidate costed from scratch: each primitive bound inside the cell as a plane,
/// primitives counted by where their boxes lie, in-plane ones put on either side.
fn kd_brute_force<V: Vector>(bounds: &[Aabb<V>], cell: &Aabb<V>, cost: &SahCost) -> Option<f64> {
    let mut best: Option<f64> = None;
    for axis in 0..V::DIM {
        for bound in bounds {
            for position in [bound.min[axis], bound.max[axis]] {
                if !(cell.min[axis] < position && position < cell.max[axis]) {
                    continue;
                }
                let (mut below, mut above, mut planar) = (0, 0, 0);
                for other in bounds {
                    let (low, high) = (other.min[axis], other.max[axis]);
                    if low == position && high == position {
                        planar += 1;
                    } else {
                        below += (low < position) as usize;
                        above += (high > position) as usize;
                    }
                }
                let (mut left, mut right) = (*cell, *cell);
                left.max[axis] = position;
                right.min[axis] = position;
                let area = |b: &Aabb<V>| b.area().to_f64();
                for (n_left, n_right) in [(below + planar, above), (below, above + planar)] {
                    let value =
                        cost.kd_split_cost(area(cell), area(&left), n_left, area(&right), n_right);
                    best = Some(best.map_or(value, |b| b.min(value)));
                }
            }
        }
    }
    best
}

/// Every BVH partition by sorted centroids costed from scratch.
fn bvh_brute_force<V: Vector>(bounds: &[Aabb<V>], cost: &SahCost) -> Option<f64> {
    let node = bounds.iter().fold(Aabb::empty(), |acc, b| acc.union(*b));
    let mut best: Option<f64> = None;
    for axis in 0..V::DIM {
        let mut order: Vec<usize> = (0..bounds.len()).collect();
        order.sort_by(|&a, &b| {
            let (ca, cb) = (bounds[a].center()[axis], bounds[b].center()[axis]);
            ca.partial_cmp(&cb).unwrap().then(a.cmp(&b))
        });
        for split in 1..bounds.len() {
            let side = |slots: &[usize]| {
                slots
                    .iter()
                    .fold(Aabb::empty(), |acc: Aabb<V>, &i| acc.union(bounds[i]))
            };
            let (left, right) = (side(&order[..split]), side(&order[split..]));
            let value = cost.split_cost(
                node.area().to_f64(),
                left.area().to_f64(),
                split,
                right.area().to_f64(),
                bounds.len() - split,
            );
            best = Some(best.map_or(value, |b| b.min(value)));
        }
    }
    best
}

fn check_curves<V: Vector, P: PrimitiveSet<V>>(primitives: &P) -> Result<(), TestCaseError> {
    let bounds = primitives.all_bounds();
    let all: Vec<u32> = (0..bounds.len() as u32).collect();
    let cost = SahCost::default();
    let params = BuildParams {
        max_leaf_size: 1,
        ..BuildParams::default()
    };

    // kD: the exact minimum is the brute-force minimum; binned is never below it.
    let tree = KdSahPresorted.build(&bounds, &params);
    prop_assert_eq!(&tree, &KdSah.build(&bounds, &params));
    let cell = tree.bounds;
    let kd_curve = curve::kd_curve(&bounds, &all, &cell, &cost, Some(8));
    let exact = minimum(&kd_curve);
    let brute = kd_brute_force(&bounds, &cell, &cost);
    prop_assert_eq!(exact.is_some(), brute.is_some());
    if let (Some(exact), Some(brute)) = (exact, brute) {
        prop_assert!(
            close(exact, brute),
            "kD exact {exact} vs brute force {brute}"
        );
    }
    let binned = kd_curve.binned.as_ref().unwrap();
    if let (Some(binned), Some(exact)) = (binned.best, exact) {
        prop_assert!(
            binned.cost >= exact,
            "kD binned {} below exact {exact}",
            binned.cost
        );
    }
    // The builder cut where the curve is lowest, at every interior node; and kept leaves
    // where no cut was cheaper than the leaf, for the reason the curve shows.
    let built = Built::new(Structure::KdSah, primitives, &params, &mut NoBuildObserver);
    prop_assert_eq!(&built.tree, &Tree::Kd(tree.clone()));
    for index in 0..built.facts.node_count() as u32 {
        let path = built.facts.path_to(index);
        prop_assert_eq!(built.facts.node_at(&path), Ok(index));
        let members = built.primitives_below(index);
        let node_curve = curve::node_curve(&built, index, &bounds, &cost, None);
        let node = &tree.nodes[index as usize];
        if node.is_leaf() {
            if let Some(best) = node_curve.best {
                prop_assert!(members.len() <= 1 || best.cost >= node_curve.leaf_cost - 1e-12);
            }
            if let Some(LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: Some(split_cost),
            }) = built.facts.leaf_reason(index)
            {
                prop_assert_eq!(leaf_cost, node_curve.leaf_cost);
                prop_assert!(close(split_cost, node_curve.best.unwrap().cost));
            }
            continue;
        }
        let best = node_curve.best.unwrap();
        prop_assert_eq!(
            (best.axis, best.position),
            (node.axis as usize, node.split.to_f64())
        );
        prop_assert!(best.cost < node_curve.leaf_cost);
    }

    // BVH: the same three facts, with the sweep builder and the binned one.
    let bvh_curve = curve::bvh_curve(&bounds, &all, &cost, Some(8));
    let exact = minimum(&bvh_curve).unwrap();
    let brute = bvh_brute_force(&bounds, &cost).unwrap();
    prop_assert!(
        close(exact, brute),
        "BVH exact {exact} vs brute force {brute}"
    );
    let binned = bvh_curve.binned.as_ref().unwrap();
    if let Some(binned) = binned.best {
        prop_assert!(
            binned.cost >= exact - 1e-9 * exact,
            "BVH binned {} < {exact}",
            binned.cost
        );
    }
    let sweep = SweepSah.build(&bounds, &params);
    let [left, _] = sweep.nodes[0].children();
    let left_count = TreeFacts::of(&sweep).primitives_below(&sweep, left).len();
    let best = bvh_curve.best.unwrap();
    let best_candidate = bvh_curve.axes[best.axis]
        .iter()
        .find(|c| c.position == best.position && c.cost == best.cost)
        .unwrap();
    prop_assert_eq!(left_count, best_candidate.count_left);
    let left_box = sweep.nodes[left as usize].bounds;
    prop_assert!(close(left_box.area().to_f64(), best_candidate.area_left));
    // The binned builder bins the longest axis of the centroids' box: its split is that
    // axis's cheapest binned candidate.
    let centroid_bounds = Aabb::from_points(bounds.iter().map(Aabb::center));
    let axis = centroid_bounds.largest_axis();
    let binned_builder = BinnedSah { bins: 8 }.build(&bounds, &params);
    let cheapest_on_axis = binned.axes[axis]
        .iter()
        .reduce(|a, b| if b.cost < a.cost { b } else { a });
    if let Some(cheapest) = cheapest_on_axis {
        let [left, _] = binned_builder.nodes[0].children();
        let left_count = TreeFacts::of(&binned_builder)
            .primitives_below(&binned_builder, left)
            .len();
        prop_assert_eq!(left_count, cheapest.count_left);
    }
    Ok(())
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn curves_of_triangle_scenes(triangles in triangles()) {
        check_curves(&triangles)?;
    }

    #[test]
    fn curves_of_2d_scenes(shapes in shapes()) {
        check_curves(&shapes)?;
    }
}

/// The written-down curve of a small 2D scene: two unit boxes at x 0..1 and 3..4, y 0..1.
/// The kD cell is 4 × 1 (perimeter 10); the cut at x = 1 leaves 1 box below in a 1 × 1 cell
/// (perimeter 4) and 1 above in a 3 × 1 cell (perimeter 8): 3 + 0.4 + 0.8 = 4.2.
#[test]
fn a_small_scene_has_the_costs_written_down() {
    let shapes = ShapeSet {
        shapes: vec![
            Shape::Box(Aabb::new(DVec2::ZERO, DVec2::ONE)),
            Shape::Box(Aabb::new(DVec2::new(3.0, 0.0), DVec2::new(4.0, 1.0))),
        ],
    };
    let bounds = shapes.all_bounds();
    let cell = Aabb::new(DVec2::ZERO, DVec2::new(4.0, 1.0));
    let cost = SahCost::default();
    let kd = curve::kd_curve(&bounds, &[0, 1], &cell, &cost, Some(4));
    let x: Vec<(f64, f64, usize, usize)> = kd.axes[0]
        .iter()
        .map(|c| (c.position, c.cost, c.count_left, c.count_right))
        .collect();
    assert_eq!(x, [(1.0, 4.2, 1, 1), (3.0, 4.2, 1, 1)]);
    assert!(
        kd.axes[1].is_empty(),
        "no y plane lies strictly inside the cell"
    );
    assert_eq!(kd.leaf_cost, 2.0);
    assert_eq!(kd.area, 10.0);
    // Middle: x = 2, one box each side, cells 2 × 1 each (perimeter 6): 3 + 0.6 + 0.6.
    let middle = kd.middle.unwrap();
    assert_eq!((middle.axis, middle.position), (0, 2.0));
    assert!((middle.cost - 4.2).abs() < 1e-12);
    // Binned at x = 1, 2, 3: all 4.2.
    let binned = kd.binned.unwrap();
    assert_eq!(binned.axes[0].len(), 3);
    assert!(binned.axes[0].iter().all(|c| (c.cost - 4.2).abs() < 1e-12));
    // BVH: the only split puts one box each side; each child's perimeter is 4 of 10:
    // 3 + 0.4 + 0.4 = 3.8, between the centroids 0.5 and 3.5.
    let bvh = curve::bvh_curve(&bounds, &[0, 1], &cost, None);
    let candidate = bvh.axes[0][0];
    assert_eq!(
        (
            candidate.position,
            candidate.count_left,
            candidate.count_right
        ),
        (2.0, 1, 1)
    );
    assert!((candidate.cost - 3.8).abs() < 1e-12);
    assert!((candidate.p_left - 0.4).abs() < 1e-12);
}
