//! Shared by the core's integration tests: every builder, every switch, checked against brute
//! force.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.
#![allow(dead_code)]

use accelviz_core::kd::{self, KdTraversalStack, KdTree};
use accelviz_core::params::BuildParams;
use accelviz_core::structure::Entry;
use accelviz_core::{
    Built, CATALOGUE, Counters, Family, Hit, LeafPrimitives, NoBuildObserver, NoObserver, Order,
    PrimitiveSet, Query, Ray, Real, Structure, TraceOptions, TraversalStacks, Tree, Vector, Width,
    brute_force,
};

/// Every structure of `family` in the catalogue; one with a parameter at its smallest value
/// and at its default; a BVH in every width.
fn structures_of(family: Family) -> Vec<Structure> {
    CATALOGUE
        .iter()
        .filter(|entry| entry.family == family)
        .flat_map(|entry: &Entry| match entry.parameter {
            Some(parameter) => vec![
                entry.structure.with_parameter(parameter.min),
                entry.structure.with_parameter(parameter.default),
            ],
            None => vec![entry.structure],
        })
        .flat_map(|structure| match family {
            Family::Bvh => Width::ALL.map(|width| structure.with_width(width)).to_vec(),
            Family::Kd | Family::Grid | Family::HashedGrid | Family::Octree => vec![structure],
        })
        .collect()
}

/// Builds `structure` at two leaf sizes, checking each tree with its validator and its facts:
/// every leaf has the builder's reason, no interior node has one.
fn build_checked<V: Vector, P: PrimitiveSet<V>>(
    primitives: &P,
    family: Family,
) -> Vec<(String, Tree<V>)> {
    let mut trees = Vec::new();
    for max_leaf_size in [1, 4] {
        let params = BuildParams {
            max_leaf_size,
            ..BuildParams::default()
        };
        for structure in structures_of(family) {
            let name = structure.name();
            let built = Built::new(structure, primitives, &params, &mut NoBuildObserver);
            structure
                .validate(&built.tree, primitives)
                .unwrap_or_else(|error| panic!("{name}: {error}"));
            let by_depth = &built.facts.by_depth;
            assert!(
                by_depth
                    .windows(2)
                    .all(|pair| built.facts.depth[pair[0] as usize]
                        <= built.facts.depth[pair[1] as usize]),
                "{name}: nodes by depth"
            );
            let mut every = by_depth.clone();
            every.sort_unstable();
            assert!(
                every.iter().copied().eq(0..built.facts.node_count() as u32),
                "{name}: each node once"
            );
            for node in 0..built.facts.node_count() as u32 {
                assert_eq!(
                    built.facts.leaf_reason(node).is_some(),
                    built.facts.is_leaf(node),
                    "{name}: node {node}'s leaf reason"
                );
            }
            trees.push((format!("{name} leaf {max_leaf_size}"), built.tree));
        }
    }
    trees
}

/// Builds with every BVH builder of the catalogue (two leaf sizes), binary and wide,
/// validating each tree.
pub fn all_trees<V: Vector, P: PrimitiveSet<V>>(primitives: &P) -> Vec<(String, Tree<V>)> {
    build_checked(primitives, Family::Bvh)
}

/// Builds a kD-tree with every kD builder of the catalogue (two leaf sizes), validating each.
pub fn all_kd_trees<V: Vector, P: PrimitiveSet<V>>(primitives: &P) -> Vec<(String, KdTree<V>)> {
    // Sorting at every node and sorting once build the same tree.
    for max_leaf_size in [1, 4] {
        let params = BuildParams {
            max_leaf_size,
            ..BuildParams::default()
        };
        assert_eq!(
            Structure::KdSahPerNode.build(primitives, &params),
            Structure::KdSah.build(primitives, &params),
            "kd:sah-per-node and kd:sah differ"
        );
    }
    build_checked(primitives, Family::Kd)
        .into_iter()
        .filter_map(|(name, tree)| match tree {
            Tree::Kd(tree) => Some((name, tree)),
            _ => None,
        })
        .collect()
}

/// Builds every grid of the catalogue (dense and hashed, each at its smallest density and its
/// default) and every octree (at the smallest leaf size and the default), validating each.
pub fn all_cell_structures<V: Vector, P: PrimitiveSet<V>>(
    primitives: &P,
) -> Vec<(String, Tree<V>)> {
    let mut trees = build_checked(primitives, Family::Grid);
    trees.extend(build_checked(primitives, Family::HashedGrid));
    trees.extend(build_checked(primitives, Family::Octree));
    trees
}

/// Every combination of order, query and robustness.
pub fn all_options() -> Vec<TraceOptions> {
    let mut options = Vec::new();
    for order in [Order::NearFirst, Order::FileOrder] {
        for robust in [false, true] {
            for query in [Query::Closest, Query::Any, Query::FirstInCell] {
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
/// any-hit queries a hit exactly when brute force has one. The lecture's kD rule
/// ([`Query::FirstInCell`]) gives the closest hit through a kD-tree near first, and otherwise
/// a real hit exactly when brute force has one, never nearer than the closest.
pub fn assert_agrees_with_brute_force<
    V: Vector,
    P: PrimitiveSet<V> + LeafPrimitives<V, Set = P> + 'static,
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
    let grids = all_cell_structures(primitives);
    let grid_leaf_ordered: Vec<_> = grids
        .iter()
        .map(|(_, grid)| grid.leaf_ordered(primitives))
        .collect();
    let mut stacks = TraversalStacks::default();
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
                let got = bvh.trace(primitives, ray, &options, &mut stacks, &mut counters);
                let context = format!("{name}, {options:?}, ray {index} {ray:?}");
                // The leaf-ordered copy takes exactly the same steps to the same hit.
                let mut counters_ordered = Counters::default();
                let got_ordered = bvh.trace(
                    leaf_ordered,
                    ray,
                    &options,
                    &mut stacks,
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
                    Query::FirstInCell => assert_not_nearer(got, expected, &context),
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
            // Packets (of up to 64 rays; wide trees trace them together) give every ray the
            // answer it gets alone (up to a tie: two primitives hit at one distance, which
            // either order of visits may report, as near-first and file order may).
            if index == 0 {
                for (name, bvh) in &trees {
                    for packet_size in [5, 64] {
                        for packet in rays.chunks(packet_size) {
                            let mut hits = vec![None; packet.len()];
                            let mut observers = vec![NoObserver; packet.len()];
                            bvh.trace_packet(
                                primitives,
                                packet,
                                &options,
                                &mut stacks,
                                &mut observers,
                                &mut hits,
                            );
                            for (ray, hit) in packet.iter().zip(&hits) {
                                let alone = bvh.trace(
                                    primitives,
                                    ray,
                                    &options,
                                    &mut stacks,
                                    &mut NoObserver,
                                );
                                let context = format!(
                                    "{name}, {options:?}, packet of {packet_size}, {ray:?}"
                                );
                                match options.query {
                                    Query::Closest => assert_same_hit(*hit, alone, &context),
                                    // A packet visits nodes in its own order, so the first
                                    // hit it finds may be another.
                                    Query::Any | Query::FirstInCell => {
                                        assert_eq!(hit.is_some(), alone.is_some(), "{context}")
                                    }
                                }
                            }
                        }
                    }
                }
            }
            // Grids and octrees, which list a primitive in every cell it reaches. A grid's walk
            // meets cells in the ray's order whatever the order option, and its rule is the
            // pseudo-code's; the hashed grid takes the dense grid's steps. An octree visits
            // the cells a ray passes front to back or by their numbers.
            let mut dense_steps = Vec::new();
            let mut hashed_seen = 0;
            for ((name, grid), leaf_ordered) in grids.iter().zip(&grid_leaf_ordered) {
                let context = format!("{name}, {options:?}, ray {index} {ray:?}");
                let (got, counters) =
                    trace_three_ways(&context, &options, |ordered, options, counters| {
                        if ordered {
                            grid.trace(leaf_ordered, ray, options, &mut stacks, counters)
                        } else {
                            grid.trace(primitives, ray, options, &mut stacks, counters)
                        }
                    });
                let in_file_order =
                    matches!(grid, Tree::Octree(_)) && options.order == Order::FileOrder;
                match options.query {
                    Query::FirstInCell if in_file_order => {
                        assert_not_nearer(got, expected, &context)
                    }
                    Query::Closest | Query::FirstInCell => assert_same_hit(got, expected, &context),
                    Query::Any => assert_eq!(got.is_some(), expected.is_some(), "{context}"),
                }
                // The hashed grids come in the dense grids' order.
                match grid {
                    Tree::Grid(_) => dense_steps.push((got, counters)),
                    Tree::Octree(_) => {}
                    _ => {
                        let twin = dense_steps.get(hashed_seen);
                        assert_eq!(
                            twin,
                            Some(&(got, counters)),
                            "{context}: hashed against dense"
                        );
                        hashed_seen += 1;
                    }
                }
            }
            for ((name, tree), leaf_ordered) in kd_trees.iter().zip(&kd_leaf_ordered) {
                let context = format!("{name}, {options:?}, ray {index} {ray:?}");
                let (got, _) =
                    trace_three_ways(&context, &options, |ordered, options, counters| {
                        if ordered {
                            kd::traverse(tree, leaf_ordered, ray, options, &mut kd_stack, counters)
                        } else {
                            kd::traverse(tree, primitives, ray, options, &mut kd_stack, counters)
                        }
                    });
                // The pseudo-code's rule near first is the closest hit, but for a ray lying in
                // a split plane (it meets both sides all along).
                let in_a_plane = || {
                    let (origin, direction) = (ray.origin.to_array3(), ray.direction.to_array3());
                    tree.nodes.iter().any(|node| {
                        let axis = node.axis as usize;
                        !node.is_leaf()
                            && origin[axis] == node.split
                            && direction[axis] == V::Scalar::ZERO
                    })
                };
                match (options.query, options.order) {
                    (Query::FirstInCell, Order::NearFirst) if in_a_plane() => {
                        assert_not_nearer(got, expected, &context)
                    }
                    (Query::Closest, _) | (Query::FirstInCell, Order::NearFirst) => {
                        assert_same_hit(got, expected, &context)
                    }
                    (Query::Any, _) => {
                        assert_eq!(got.is_some(), expected.is_some(), "{context}")
                    }
                    (Query::FirstInCell, Order::FileOrder) => {
                        assert_not_nearer(got, expected, &context)
                    }
                }
            }
        }
    }
}

/// Traces a ray with `trace` (in leaf order or not, with these options, counting) three ways:
/// over the primitives in their own order, over the leaf-ordered copy, which must take the
/// same steps to the same hit, and with the mailbox, which must skip repeated tests and change
/// nothing else. The first way's hit and counts.
fn trace_three_ways<S: Real>(
    context: &str,
    options: &TraceOptions,
    mut trace: impl FnMut(bool, &TraceOptions, &mut Counters) -> Option<Hit<S>>,
) -> (Option<Hit<S>>, Counters) {
    let mut counters = Counters::default();
    let got = trace(false, options, &mut counters);
    let mut counters_ordered = Counters::default();
    let got_ordered = trace(true, options, &mut counters_ordered);
    assert_eq!(
        (got, counters),
        (got_ordered, counters_ordered),
        "{context}: leaf order"
    );
    let mailbox = TraceOptions {
        mailboxing: true,
        ..*options
    };
    let mut counters_mailbox = Counters::default();
    let got_mailbox = trace(false, &mailbox, &mut counters_mailbox);
    assert_eq!(got_mailbox, got, "{context}: mailbox");
    assert_eq!(
        counters_mailbox.primitive_tests + counters_mailbox.mailbox_skips,
        counters.primitive_tests,
        "{context}: mailbox"
    );
    (got, counters)
}

/// A hit exactly when brute force has one, and never nearer than its closest.
fn assert_not_nearer<S: Real>(got: Option<Hit<S>>, expected: Option<Hit<S>>, context: &str) {
    assert_eq!(got.is_some(), expected.is_some(), "{context}");
    if let (Some(got), Some(expected)) = (got, expected) {
        let scale = expected.t.abs().to_f64().max(1.0);
        assert!(
            got.t.to_f64() >= expected.t.to_f64() - 1e-5 * scale,
            "{context}: got {got:?}, nearer than brute force's {expected:?}"
        );
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
