//! The outcomes of rays aimed exactly at the vertices and shared edges of the closed meshes
//! (the shared ones that are closed, and the built-in sphere and cube, near the origin and
//! far from it): the watertight test with the conservative box test leaks nothing in f32 or
//! f64, through brute force, a BVH and kD-trees; the fast test leaks in f32. Every ray gets
//! exactly one outcome.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::outcome::{Outcome, OutcomeCounts, ReferenceScene};
use accelviz_core::params::BuildParams;
use accelviz_core::{
    NoObserver, Query, Structure, TraceOptions, TraversalStacks, TriangleSet, Vector3, Width,
    brute_force,
};
use accelviz_scene::Mesh;
use accelviz_scene::builtin::{FAR_AWAY, icosphere, subdivided_cube};
use accelviz_scene::rays::surface_aim_rays;
use glam::{DVec3, Vec3};

use crate::shared_meshes::shared_mesh;

/// The shared meshes whose every edge two triangles share, consistently oriented (checked
/// by welding corners by position): of the four, only the rocker arm. The bunny, the ogre
/// and Suzanne have boundary edges.
const CLOSED_SHARED_MESHES: [&str; 1] = ["rocker-arm.obj"];

/// Each way of tracing's outcomes over `mesh`'s aimed rays (every `stride`-th).
fn outcomes<V: Vector3>(mesh: &Mesh, robust: bool, stride: usize) -> Vec<(String, OutcomeCounts)> {
    let triangles = TriangleSet::<V>::from_f64(&mesh.triangles);
    let reference = ReferenceScene::new(&triangles);
    let params = BuildParams::default();
    let structures = [
        Structure::BvhSahBinned {
            bins: 16,
            width: Width::Binary,
        },
        Structure::KdSah,
        Structure::KdSahPerfect,
    ];
    let trees: Vec<_> = structures
        .iter()
        .map(|structure| structure.build(&triangles, &params))
        .collect();
    let options = TraceOptions::default().with_robust(robust);
    let mut stacks = TraversalStacks::default();
    let mut counts = vec![OutcomeCounts::default(); structures.len() + 1];
    for spec in surface_aim_rays(&mesh.triangles, 1).iter().step_by(stride) {
        let ray = spec.to_ray::<V>().unwrap();
        let found = reference.reference(&ray);
        let mut count = |slot: usize, got: Option<u32>| {
            counts[slot].add(reference.classify(&ray, found.as_ref(), got, Query::Closest));
        };
        // Brute force on the small meshes only: it tests every triangle for every ray.
        if mesh.triangles.len() <= 5_000 {
            count(
                0,
                brute_force(&triangles, &ray, &options, &mut NoObserver).map(|hit| hit.primitive),
            );
        }
        for (slot, tree) in trees.iter().enumerate() {
            let hit = tree.trace(&triangles, &ray, &options, &mut stacks, &mut NoObserver);
            count(slot + 1, hit.map(|hit| hit.primitive));
        }
    }
    std::iter::once("brute force".to_owned())
        .chain(structures.iter().map(|structure| structure.name()))
        .zip(counts)
        .collect()
}

fn closed_meshes() -> Vec<(Mesh, usize)> {
    let built_in = [icosphere(3), subdivided_cube(8)];
    let far: Vec<Mesh> = built_in
        .iter()
        .map(|mesh| mesh.translated(FAR_AWAY))
        .collect();
    let shared = CLOSED_SHARED_MESHES.map(shared_mesh);
    built_in
        .into_iter()
        .chain(far)
        .map(|mesh| (mesh, 1))
        // Every seventh of the rocker arm's 360,000 rays: the test's time, at the test
        // build's optimisation.
        .chain(shared.into_iter().map(|mesh| (mesh, 7)))
        .collect()
}

fn report(mesh: &Mesh, mode: &str, found: &[(String, OutcomeCounts)]) {
    for (name, counts) in found.iter().filter(|(_, counts)| counts.total() > 0) {
        let line: Vec<String> = Outcome::ALL
            .iter()
            .map(|&outcome| format!("{} {}", outcome.name(), counts.count(outcome)))
            .collect();
        println!("{} {mode} {name}: {}", mesh.name, line.join(", "));
    }
}

#[test]
fn the_watertight_test_leaks_nothing_through_a_closed_mesh_and_the_fast_f32_test_does() {
    let mut fast_f32_leaks = 0;
    for (mesh, stride) in closed_meshes() {
        let rays = surface_aim_rays(&mesh.triangles, 1).len().div_ceil(stride) as u64;
        for (precision, found) in [
            ("f32", outcomes::<Vec3>(&mesh, true, stride)),
            ("f64", outcomes::<DVec3>(&mesh, true, stride)),
        ] {
            report(&mesh, &format!("watertight {precision}"), &found);
            for (name, counts) in &found {
                if counts.total() == 0 {
                    continue; // (brute force, not run on a large mesh)
                }
                assert_eq!(counts.total(), rays, "every ray has one outcome");
                for outcome in [Outcome::Leak, Outcome::FalseHit, Outcome::Wrong] {
                    assert_eq!(
                        counts.count(outcome),
                        0,
                        "{} watertight {precision} {name}: {}",
                        mesh.name,
                        outcome.name()
                    );
                }
            }
        }
        let fast = outcomes::<Vec3>(&mesh, false, stride);
        report(&mesh, "fast f32", &fast);
        fast_f32_leaks += fast[1].1.count(Outcome::Leak);
    }
    assert!(
        fast_f32_leaks > 0,
        "the fast f32 test slips through somewhere"
    );
}
