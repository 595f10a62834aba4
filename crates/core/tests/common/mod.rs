//! Shared by the core's integration tests: every builder, every switch, checked against brute
//! force.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.
#![allow(dead_code)]

use accelviz_core::bvh::{
    BinnedSah, BuildParams, Builder, Bvh, MedianSplit, MiddleSplit, SweepSah, TraversalStack,
    traverse, validate,
};
use accelviz_core::kd::{
    self, KdBuilder, KdMedianSplit, KdMiddleSplit, KdSah, KdSahPresorted, KdTraversalStack, KdTree,
};
use accelviz_core::{
    Counters, Hit, LeafPrimitives, NoObserver, Order, PrimitiveSet, Query, Ray, Real, TraceOptions,
    Vector, brute_force,
};

/// Builds with every builder (and a few bin counts), validating each tree.
pub fn all_trees<V: Vector, P: PrimitiveSet<V>>(primitives: &P) -> Vec<(String, Bvh<V>)> {
    let bounds = primitives.all_bounds();
    let mut trees = Vec::new();
    for max_leaf_size in [1, 4] {
        let params = BuildParams {
            max_leaf_size,
            ..BuildParams::default()
        };
        let mut add = |name: String, bvh: Bvh<V>| {
            validate(&bvh, &bounds).unwrap_or_else(|error| panic!("{name}: {error}"));
            trees.push((format!("{name} leaf {max_leaf_size}"), bvh));
        };
        add(MiddleSplit.name(), MiddleSplit.build(&bounds, &params));
        add(MedianSplit.name(), MedianSplit.build(&bounds, &params));
        for bins in [2, 16] {
            let builder = BinnedSah { bins };
            add(builder.name(), builder.build(&bounds, &params));
        }
        add(SweepSah.name(), SweepSah.build(&bounds, &params));
    }
    trees
}

/// Builds a kD-tree with every kD builder (two leaf sizes), validating each.
pub fn all_kd_trees<V: Vector, P: PrimitiveSet<V>>(primitives: &P) -> Vec<(String, KdTree<V>)> {
    let bounds = primitives.all_bounds();
    let mut trees = Vec::new();
    for max_leaf_size in [1, 4] {
        let params = BuildParams {
            max_leaf_size,
            ..BuildParams::default()
        };
        // Sorting at every node and sorting once build the same tree.
        assert_eq!(
            KdSah.build(&bounds, &params),
            KdSahPresorted.build(&bounds, &params),
            "kd:sah and kd:sah-presorted differ"
        );
        for (name, tree) in [
            ("kd:middle", KdMiddleSplit.build(&bounds, &params)),
            ("kd:median", KdMedianSplit.build(&bounds, &params)),
            ("kd:sah", KdSah.build(&bounds, &params)),
            ("kd:sah-presorted", KdSahPresorted.build(&bounds, &params)),
        ] {
            kd::validate(&tree, &bounds).unwrap_or_else(|error| panic!("{name}: {error}"));
            trees.push((format!("{name} leaf {max_leaf_size}"), tree));
        }
        let perfect = KdSahPresorted.build_with_perfect_splits(primitives, &params);
        kd::validate_clipped(&perfect, primitives)
            .unwrap_or_else(|error| panic!("kd:sah-perfect: {error}"));
        trees.push((format!("kd:sah-perfect leaf {max_leaf_size}"), perfect));
    }
    trees
}

/// Every combination of order, query and robustness.
pub fn all_options() -> Vec<TraceOptions> {
    let mut options = Vec::new();
    for order in [Order::NearFirst, Order::FileOrder] {
        for robust in [false, true] {
            for query in [Query::Closest, Query::Any] {
                options.push(
                    TraceOptions {
                        order,
                        query,
                        ..TraceOptions::default()
                    }
                    .with_robust(robust),
                );
            }
        }
    }
    options
}

/// Asserts that every tree and every option gives brute force's answer for every ray:
/// the same closest primitive (or, at a tie, the same t within a relative 1e-5), and for
/// any-hit queries a hit exactly when brute force has one.
pub fn assert_agrees_with_brute_force<
    V: Vector,
    P: PrimitiveSet<V> + LeafPrimitives<V, Set = P>,
>(
    primitives: &P,
    rays: &[Ray<V>],
) {
    let trees = all_trees(primitives);
    let leaf_ordered: Vec<_> = trees
        .iter()
        .map(|(_, bvh)| bvh.leaf_ordered(primitives))
        .collect();
    let kd_trees = all_kd_trees(primitives);
    let kd_leaf_ordered: Vec<_> = kd_trees
        .iter()
        .map(|(_, tree)| tree.leaf_ordered(primitives))
        .collect();
    let mut stack = TraversalStack::new();
    let mut kd_stack = KdTraversalStack::new();
    for options in all_options() {
        for (index, ray) in rays.iter().enumerate() {
            let closest_options = TraceOptions {
                query: Query::Closest,
                ..options
            };
            let expected = brute_force(primitives, ray, &closest_options, &mut NoObserver);
            for ((name, bvh), leaf_ordered) in trees.iter().zip(&leaf_ordered) {
                let mut counters = Counters::default();
                let got = traverse(bvh, primitives, ray, &options, &mut stack, &mut counters);
                let context = format!("{name}, {options:?}, ray {index} {ray:?}");
                // The leaf-ordered copy takes exactly the same steps to the same hit.
                let mut counters_ordered = Counters::default();
                let got_ordered = traverse(
                    bvh,
                    leaf_ordered,
                    ray,
                    &options,
                    &mut stack,
                    &mut counters_ordered,
                );
                assert_eq!(
                    (got, counters),
                    (got_ordered, counters_ordered),
                    "{context}: leaf order"
                );
                match options.query {
                    Query::Closest => assert_same_hit(got, expected, &context),
                    Query::Any => assert_eq!(got.is_some(), expected.is_some(), "{context}"),
                }
                if let Some(hit) = got {
                    // Any hit must be a real hit of that primitive.
                    let prepared = primitives.prepare(ray, options.hit_test);
                    assert!(
                        primitives
                            .intersect(&prepared, hit.primitive as usize, ray.t_min, ray.t_max)
                            .is_some(),
                        "{context}: reported hit is not a hit"
                    );
                }
                assert!(counters.primitive_tests <= primitives.len() as u64 * 2 + 1);
            }
            for ((name, tree), leaf_ordered) in kd_trees.iter().zip(&kd_leaf_ordered) {
                let context = format!("{name}, {options:?}, ray {index} {ray:?}");
                let mut counters = Counters::default();
                let got = kd::traverse(
                    tree,
                    primitives,
                    ray,
                    &options,
                    &mut kd_stack,
                    &mut counters,
                );
                let mut counters_ordered = Counters::default();
                let got_ordered = kd::traverse(
                    tree,
                    leaf_ordered,
                    ray,
                    &options,
                    &mut kd_stack,
                    &mut counters_ordered,
                );
                assert_eq!(
                    (got, counters),
                    (got_ordered, counters_ordered),
                    "{context}: leaf order"
                );
                // The mailbox skips repeated tests and changes nothing else.
                let mailbox = TraceOptions {
                    mailboxing: true,
                    ..options
                };
                let mut counters_mailbox = Counters::default();
                let got_mailbox = kd::traverse(
                    tree,
                    primitives,
                    ray,
                    &mailbox,
                    &mut kd_stack,
                    &mut counters_mailbox,
                );
                assert_eq!(got_mailbox, got, "{context}: mailbox");
                assert_eq!(
                    counters_mailbox.primitive_tests + counters_mailbox.mailbox_skips,
                    counters.primitive_tests,
                    "{context}: mailbox"
                );
                match options.query {
                    Query::Closest => assert_same_hit(got, expected, &context),
                    Query::Any => assert_eq!(got.is_some(), expected.is_some(), "{context}"),
                }
            }
        }
    }
}

fn assert_same_hit<S: Real>(got: Option<Hit<S>>, expected: Option<Hit<S>>, context: &str) {
    match (got, expected) {
        (None, None) => {}
        (Some(got), Some(expected)) => {
            let scale = expected.t.abs().to_f64().max(1.0);
            assert!(
                got.primitive == expected.primitive
                    || (got.t.to_f64() - expected.t.to_f64()).abs() <= 1e-5 * scale,
                "{context}: got {got:?}, brute force {expected:?}"
            );
        }
        _ => panic!("{context}: got {got:?}, brute force {expected:?}"),
    }
}
