//! The binned SAH builder on several threads gives the tree it gives on one, and the one its
//! observed (sequential) build gives: node for node, in the same order, over the same
//! primitive order; and so does the whole 8-wide build, its collapse and leaf-ordered copy.
//! So do the kD builders, whose upper levels' subtrees are built at once, with the budget's
//! verdict and the depth limit's count. Inputs large enough to fork many times: a scanned
//! mesh, a cloud of boxes, and the degenerate ones (every box the same, sizes growing
//! geometrically, which splits lopsidedly at every level).

use accelviz_core::bvh::{BinnedSah, Builder, Bvh};
use accelviz_core::kd::{
    KdBudgetExceeded, KdBuilder, KdMedianSplit, KdMiddleSplit, KdSah, KdSahPresorted, KdTree,
};
use accelviz_core::params::{BuildParams, KdBudget};
use accelviz_core::{Aabb, BuildObserver, LeafPrimitives, PrimitiveSet, TriangleSet, Vector};
use glam::{DVec2, DVec3, Vec3};

/// An observer that hears nothing but is there: the builder then builds one node after
/// another (the sequential reference).
struct Listening;

impl BuildObserver for Listening {}

fn on_threads<T: Send>(threads: usize, work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(work)
}

fn assert_same_tree_on_any_threads<V: accelviz_core::Vector>(name: &str, bounds: &[Aabb<V>]) {
    for bins in [4, 16] {
        let builder = BinnedSah { bins };
        let params = BuildParams::default();
        let observed = builder.build_observed(bounds, &params, &mut Listening);
        accelviz_core::bvh::validate(&observed, bounds).expect("a valid tree");
        for threads in [1, 2, 3] {
            let parallel: Bvh<V> = on_threads(threads, || builder.build(bounds, &params));
            assert!(
                parallel == observed,
                "{name}, {bins} bins, {threads} threads: the tree differs from the sequential \
                 build's ({} nodes against {})",
                parallel.nodes.len(),
                observed.nodes.len()
            );
        }
    }
}

/// `count` small boxes scattered through a cube, from the scene crate's seeded generator.
fn cloud(count: usize, seed: u64) -> Vec<Aabb<DVec3>> {
    let mut rng = accelviz_scene::rng::SplitMix64::new(seed);
    (0..count)
        .map(|_| {
            let corner = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 100.0;
            let size = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64());
            Aabb::new(corner, corner + size)
        })
        .collect()
}

fn bunny() -> accelviz_scene::Mesh {
    accelviz_scene::obj::load_obj(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/meshes/stanford-bunny.obj"
    ))
    .expect("the shared bunny")
}

#[test]
fn the_parallel_binned_build_gives_the_sequential_tree() {
    let bunny = bunny();
    let triangles: Vec<Aabb<Vec3>> = bunny
        .triangles
        .iter()
        .map(|corners| {
            Aabb::from_points(
                corners
                    .iter()
                    .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)),
            )
        })
        .collect();
    assert_same_tree_on_any_threads("bunny", &triangles);
    // The whole 8-wide build (boxes, binary build, collapse, leaf-ordered copy in blocks) on
    // one thread and on two.
    let set = accelviz_core::TriangleSet::<Vec3>::from_f64(&bunny.triangles);
    let structure = accelviz_core::Structure::parse("bvh8:sah-binned").expect("a structure");
    let build = || {
        let tree = structure.build(&set, &BuildParams::default());
        let ordered = tree.leaf_ordered(&set);
        (tree, ordered)
    };
    let (one_tree, one_ordered) = on_threads(1, build);
    let (two_tree, two_ordered) = on_threads(2, build);
    assert!(
        one_tree == two_tree,
        "the 8-wide tree differs on two threads"
    );
    assert!(
        one_ordered.stored().triangles() == two_ordered.stored().triangles()
            && one_ordered.stored().blocks() == two_ordered.stored().blocks(),
        "the leaf-ordered copy differs on two threads"
    );
    assert_same_tree_on_any_threads("cloud", &cloud(40_000, 3));
    // Every box the same: no plane separates them, and big nodes are halved.
    let same = vec![Aabb::new(DVec3::ZERO, DVec3::ONE); 20_000];
    assert_same_tree_on_any_threads("identical boxes", &same);
    // Boxes at geometrically growing positions: the SAH peels a few off the far end at every
    // level, a chain of lopsided splits deeper than the forks may nest.
    let chain: Vec<Aabb<DVec3>> = (0..30_000)
        .map(|i| {
            let x = 1.001f64.powi(i);
            Aabb::new(DVec3::new(x, 0.0, 0.0), DVec3::new(x + 0.5, 1.0, 1.0))
        })
        .collect();
    assert_same_tree_on_any_threads("geometric chain", &chain);
}

/// `builder`'s tree on 1, 2 and 3 threads is its observed (sequential) build's, budget verdict
/// and depth limit's count included. Returns that tree.
fn assert_same_kd_tree<V: Vector, B: KdBuilder + Sync>(
    name: &str,
    builder: &B,
    bounds: &[Aabb<V>],
    params: &BuildParams,
) -> KdTree<V> {
    let observed = builder.build_observed(bounds, params, &mut Listening);
    accelviz_core::kd::validate(&observed, bounds).expect("a valid tree");
    for threads in [1, 2, 3] {
        let parallel = on_threads(threads, || builder.build(bounds, params));
        assert!(
            parallel == observed,
            "{name}, kD {}, {threads} threads: the tree differs from the sequential build's \
             ({} nodes against {}; {} against {})",
            builder.name(),
            parallel.nodes.len(),
            observed.nodes.len(),
            parallel.limits,
            observed.limits,
        );
    }
    observed
}

fn assert_every_kd_builder_same<V: Vector>(name: &str, bounds: &[Aabb<V>], params: &BuildParams) {
    assert_same_kd_tree(name, &KdMiddleSplit, bounds, params);
    assert_same_kd_tree(name, &KdMedianSplit, bounds, params);
    assert_same_kd_tree(name, &KdSah, bounds, params);
    assert_same_kd_tree(name, &KdSahPresorted, bounds, params);
}

#[test]
fn the_parallel_kd_builds_give_the_sequential_trees() {
    let params = BuildParams::default();
    // The bunny: the SAH build (sorting once; the one sorting at every node makes the same
    // tree, tested elsewhere, and is forked below), and with perfect splits, where a cut
    // triangle is clipped to each side.
    let bunny = bunny();
    let set = TriangleSet::<Vec3>::from_f64(&bunny.triangles);
    let bounds = set.all_bounds();
    assert_same_kd_tree("bunny", &KdSahPresorted, &bounds, &params);
    let perfect = KdSahPresorted.build_with_perfect_splits_observed(&set, &params, &mut Listening);
    for threads in [1, 2] {
        let parallel = on_threads(threads, || {
            KdSahPresorted.build_with_perfect_splits(&set, &params)
        });
        assert!(
            parallel == perfect,
            "perfect splits differ on {threads} threads"
        );
    }
    // Every builder on a cloud of boxes, in 3D and 2D, and on the lopsided chain.
    assert_every_kd_builder_same("cloud", &cloud(20_000, 5), &params);
    let flat: Vec<Aabb<DVec2>> = cloud(20_000, 6)
        .iter()
        .map(|bounds| Aabb::new(bounds.min.truncate(), bounds.max.truncate()))
        .collect();
    assert_every_kd_builder_same("2D cloud", &flat, &params);
    let chain: Vec<Aabb<DVec3>> = (0..12_000)
        .map(|i| {
            let x = 1.001f64.powi(i);
            Aabb::new(DVec3::new(x, 0.0, 0.0), DVec3::new(x + 0.5, 1.0, 1.0))
        })
        .collect();
    assert_every_kd_builder_same("geometric chain", &chain, &params);
}

/// Over budget, the parallel build stops and the sequential driver decides: the same lowered
/// depth limit, the same budget named, the same tree.
#[test]
fn a_parallel_kd_build_over_budget_lowers_its_limit_as_the_sequential_one_does() {
    let boxes = cloud(20_000, 7);
    for (max_nodes, max_references, exceeded) in [
        (Some(4_000), None, KdBudgetExceeded::Nodes(4_000)),
        (None, Some(20_400), KdBudgetExceeded::References(20_400)),
    ] {
        let params = BuildParams {
            max_leaf_size: 2,
            kd_budget: KdBudget {
                max_nodes,
                max_references,
            },
            ..BuildParams::default()
        };
        for tree in [
            assert_same_kd_tree("budget", &KdMiddleSplit, &boxes, &params),
            assert_same_kd_tree("budget", &KdSahPresorted, &boxes, &params),
        ] {
            let (_, verdict) = tree.limits.lowered_from.expect("a lowered depth limit");
            assert_eq!(verdict, exceeded);
        }
    }
}
