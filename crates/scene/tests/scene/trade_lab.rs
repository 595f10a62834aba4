//! The trade lab's measurement ([`accelviz_core::trade::Lab`]), run task by task as a worker
//! thread or a browser runs it: its rows are what the parts measure when called directly,
//! every ray gets one outcome, the clock it is given times it, and on a closed mesh the
//! watertight rows leak nothing while a fast f32 row does.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use std::cell::Cell;

use accelviz_core::outcome::Outcome;
use accelviz_core::params::BuildParams;
use accelviz_core::trade::{Lab, Precision, Switches, TradeScene, contenders};
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
