//! The trade lab's measurement ([`accelviz_core::trade_lab::Lab`]), run task by task as a worker
//! thread or a browser runs it: its rows are what the parts measure when called directly,
//! every ray gets one outcome, the clock it is given times it, and on a closed mesh the
//! watertight rows leak nothing while a fast f32 row does.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use std::cell::Cell;

use accelviz_core::outcome::Outcome;
use accelviz_core::params::BuildParams;
use accelviz_core::trade::{Precision, Switches, TradeScene, contenders};
use accelviz_core::trade_lab::Lab;
use accelviz_core::{Query, Ray, Structure, Width};
use accelviz_scene::builtin::icosphere;
use accelviz_scene::rays::RayKind;
use glam::{DVec3, Vec3};

#[test]
fn the_lab_measures_what_its_parts_measure() {
    let mesh = icosphere(2);
    let rays: Vec<Ray<DVec3>> = RayKind::Aimed
        .rays(&mesh, 900, 3, None)
        .unwrap()
        .iter()
        .map(|spec| spec.to_ray().unwrap())
        .collect();
    let structures = vec![
        Structure::BvhSahBinned {
            bins: 16,
            width: Width::Binary,
        },
        Structure::BvhMiddle {
            width: Width::Eight,
        },
        Structure::KdSah,
    ];
    let params = BuildParams::default();
    let mut lab = Lab::new(
        &mesh.triangles,
        &rays,
        structures.clone(),
        Query::Closest,
        params,
        3,
    );
    // A clock that moves 2 ms whenever it is read: every timed task takes 2 ms.
    let clock = Cell::new(0.0);
    let now = || {
        clock.set(clock.get() + 2.0);
        clock.get()
    };
    let (_, total) = lab.progress();
    let mut done = 0;
    while !lab.done() {
        assert!(lab.rows().is_none(), "no rows before the last task");
        assert!(!lab.doing().is_empty());
        lab.step(&now);
        let (now_done, now_total) = lab.progress();
        assert_eq!((now_done, now_total), (done + 1, total));
        done = now_done;
    }
    assert!(!lab.step(&now), "nothing after the last task");
    let rows = lab.rows().unwrap();
    assert_eq!(rows.len(), structures.len() * Switches::ALL.len());
    let single = TradeScene::<Vec3>::new(&mesh.triangles, &rays);
    let double = TradeScene::<DVec3>::new(&mesh.triangles, &rays);
    let references32 = single.references(0..rays.len());
    let references64 = double.references(0..rays.len());
    for (index, row) in rows.iter().enumerate() {
        assert_eq!(row.structure, structures[index / Switches::ALL.len()]);
        assert_eq!(row.switches, Switches::ALL[index % Switches::ALL.len()]);
        assert_eq!(row.outcomes.total(), rays.len() as u64, "{row:?}");
        let per_million: f64 = Outcome::ALL
            .iter()
            .map(|&outcome| row.outcomes.per_million(outcome))
            .sum();
        assert!((per_million - 1e6).abs() < 1e-6, "{per_million}");
        // Every timed task read the clock twice: 2 ms each, so every median is 2 ms.
        assert_eq!((row.build_ms, row.build_spread_percent), (2.0, 0.0));
        let expected_mrays = rays.len() as f64 / (2.0 * 1e3);
        assert!((row.mrays_per_s - expected_mrays).abs() < 1e-9);
        assert!(row.bytes > 0);
        assert_eq!(
            row.epo.is_some(),
            row.structure.family() == accelviz_core::Family::Bvh
        );
        // The same untimed pass, called directly.
        let options = row.switches.options(Query::Closest);
        let evaluation = match row.switches.precision {
            Precision::F32 => {
                let tree = row.structure.build(&single.triangles, &params);
                let ordered = tree.leaf_ordered(&single.triangles);
                single.evaluate(&tree, &ordered, &options, &references32, &params)
            }
            Precision::F64 => {
                let tree = row.structure.build(&double.triangles, &params);
                let ordered = tree.leaf_ordered(&double.triangles);
                double.evaluate(&tree, &ordered, &options, &references64, &params)
            }
        };
        assert_eq!(row.outcomes, evaluation.outcomes, "{row:?}");
        assert_eq!(row.examples, evaluation.examples);
        assert_eq!(row.sah_cost, evaluation.stats.sah_cost);
        let nodes = evaluation.counters.nodes_visited as f64 / rays.len() as f64;
        assert_eq!(row.nodes_per_ray, nodes);
        // Each outcome's example is a ray of that outcome, as the row's precision holds it.
        for outcome in Outcome::ALL {
            assert_eq!(
                row.example(outcome).is_some(),
                row.outcomes.count(outcome) > 0,
                "{outcome:?}"
            );
        }
        if row.switches.watertight {
            for outcome in [Outcome::Leak, Outcome::FalseHit, Outcome::Wrong] {
                assert_eq!(row.outcomes.count(outcome), 0, "{row:?}");
            }
        }
    }
    assert!(
        rows.iter().any(|row| !row.switches.watertight
            && row.switches.precision == Precision::F32
            && row.outcomes.count(Outcome::Leak) > 0),
        "the fast f32 test leaks somewhere on edge-aimed rays"
    );
    let (contenders, indices) = contenders(&rows);
    assert_eq!(contenders.len(), structures.len());
    assert!(indices.iter().all(|&i| rows[i].switches == Switches::BASE));
}

/// On a large mesh the lab measures its structures a group at a time and lets each group's
/// trees go before the next is built (all nineteen structures' trees of a 269k-triangle mesh
/// at once took 2 GB): a group holds at most its own trees, and the rows are the ones
/// measured all at once. What is left is estimated from what each task took: unknown at
/// first, nothing at the end.
#[test]
fn the_lab_in_groups_holds_one_groups_trees_and_measures_the_same_rows() {
    use accelviz_core::trade_lab::{TREES_MEMORY_BUDGET, structures_a_group};
    assert_eq!(
        structures_a_group(5_120, 19),
        19,
        "a small mesh: all at once"
    );
    assert_eq!(
        structures_a_group(269_000, 19),
        2,
        "the scanned head: two at a time"
    );
    let per_structure = TREES_MEMORY_BUDGET / structures_a_group(100_000, 19);
    assert!(
        per_structure >= 2 * 100_000 * 300,
        "{per_structure} bytes a structure"
    );

    let mesh = icosphere(1);
    let rays: Vec<Ray<DVec3>> = RayKind::Aimed
        .rays(&mesh, 300, 5, None)
        .unwrap()
        .iter()
        .map(|spec| spec.to_ray().unwrap())
        .collect();
    let structures = vec![
        Structure::BvhMiddle {
            width: Width::Binary,
        },
        Structure::KdMiddle,
        Structure::KdSah,
    ];
    let clock = Cell::new(0.0);
    let now = || {
        clock.set(clock.get() + 1.0);
        clock.get()
    };
    let measure = |group: usize| {
        let mut lab = Lab::in_groups(
            &mesh.triangles,
            &rays,
            structures.clone(),
            Query::Closest,
            BuildParams::default(),
            2,
            group,
        );
        assert_eq!(lab.time().1, None, "nothing is known before the first task");
        let mut most = 0;
        while lab.step(&now) {
            most = most.max(lab.trees_held());
        }
        assert_eq!(lab.time().1, Some(0.0), "nothing left at the end");
        (lab.rows().unwrap(), most)
    };
    let (together, held_together) = measure(3);
    let (one_by_one, held_one_by_one) = measure(1);
    assert_eq!(held_together, 6, "three structures in two precisions");
    assert_eq!(
        held_one_by_one, 2,
        "one structure in two precisions at a time"
    );
    let counts = |rows: &[accelviz_core::trade::TradeRow]| {
        rows.iter()
            .map(|row| {
                (
                    row.structure,
                    row.switches,
                    row.outcomes,
                    row.nodes_per_ray,
                    row.bytes,
                )
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(counts(&together), counts(&one_by_one));
}
