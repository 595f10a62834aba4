//! The ray kinds: made from a seed, the same every time; shadow and ambient occlusion rays
//! start off the surface and end where they say; an any-hit query never does more work than a
//! closest-hit one on the same rays and finds the same rays blocked.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::camera::bounding_sphere_of_box;
use accelviz_core::params::BuildParams;
use accelviz_core::{
    Counters, NoObserver, Query, Structure, TraceOptions, TraversalStacks, TriangleSet, Width,
    brute_force,
};
use accelviz_scene::builtin::teapot;
use accelviz_scene::rays::{AO_REACH, RayKind, light_position, surface_offset};
use glam::DVec3;

#[test]
fn every_kind_makes_the_same_rays_from_the_same_seed() {
    let mesh = teapot();
    for kind in RayKind::ALL {
        let rays = kind.rays(&mesh, 500, 7, None).unwrap();
        assert!(
            rays == kind.rays(&mesh, 500, 7, None).unwrap(),
            "{}: the same seed",
            kind.name()
        );
        // (A camera's rays are its pixels': no seed.)
        assert!(
            kind == RayKind::Camera || rays != kind.rays(&mesh, 500, 8, None).unwrap(),
            "{}: another seed",
            kind.name()
        );
        let expected = match kind {
            // A camera's image of about 500 pixels: 23 × 22.
            RayKind::Camera => 506,
            _ => 500,
        };
        assert_eq!(rays.len(), expected, "{}", kind.name());
        assert!(
            rays.len() >= 500 * 9 / 10,
            "{}: {}",
            kind.name(),
            rays.len()
        );
        for ray in &rays {
            assert!(
                ray.to_ray::<glam::Vec3>().is_ok(),
                "{}: {ray:?}",
                kind.name()
            );
        }
    }
    // The camera's image can be given.
    let rays = RayKind::Camera.rays(&mesh, 1, 1, Some((4, 3))).unwrap();
    assert_eq!(rays.len(), 12);
}

#[test]
fn shadow_and_ao_rays_start_off_the_surface_and_end_where_stated() {
    let mesh = teapot();
    let bounds = mesh.bounds();
    let (_, radius) = bounding_sphere_of_box(&bounds);
    let light = light_position(&bounds);
    let triangles = TriangleSet::<DVec3>::from_f64(&mesh.triangles);
    let options = TraceOptions::default().with_robust(true);
    for kind in [RayKind::Shadow, RayKind::Ao, RayKind::Bounce] {
        for spec in kind.rays(&mesh, 300, 3, None).unwrap() {
            let ray = spec.to_ray::<DVec3>().unwrap();
            let origin = DVec3::from_array(spec.origin);
            let direction = DVec3::from_array(spec.direction);
            match kind {
                RayKind::Shadow => {
                    assert_eq!(spec.t_max, 1.0);
                    let end = origin + direction;
                    assert!((end - light).length() <= 1e-9 * light.length(), "{spec:?}");
                }
                RayKind::Ao => {
                    assert_eq!(spec.t_max, AO_REACH * radius);
                    assert!((direction.length() - 1.0).abs() < 1e-12);
                }
                _ => assert_eq!(spec.t_max, f64::INFINITY),
            }
            // Off the surface: nothing is hit within half the offset of the start.
            let offset = surface_offset(&bounds, origin);
            if let Some(hit) = brute_force(&triangles, &ray, &options, &mut NoObserver) {
                assert!(
                    hit.t * direction.length() > 0.5 * offset,
                    "{}: {spec:?} hits {hit:?} at its start",
                    kind.name()
                );
            }
        }
    }
}

#[test]
fn any_hit_never_visits_more_than_closest_hit_and_finds_the_same_blocked_rays() {
    let mesh = teapot();
    let triangles = TriangleSet::<glam::Vec3>::from_f64(&mesh.triangles);
    let params = BuildParams::default();
    for structure in [
        Structure::BvhSahBinned {
            bins: 16,
            width: Width::Binary,
        },
        Structure::KdSah,
    ] {
        let tree = structure.build(&triangles, &params);
        let mut stacks = TraversalStacks::default();
        for kind in [RayKind::Shadow, RayKind::Ao, RayKind::Random] {
            for spec in kind.rays(&mesh, 400, 5, None).unwrap() {
                let ray = spec.to_ray::<glam::Vec3>().unwrap();
                let trace = |query: Query, stacks: &mut TraversalStacks<f32>| {
                    let options = TraceOptions {
                        query,
                        ..TraceOptions::default()
                    };
                    let mut counters = Counters::default();
                    let hit = tree.trace(&triangles, &ray, &options, stacks, &mut counters);
                    (hit.is_some(), counters.nodes_visited)
                };
                let (closest_hit, closest_nodes) = trace(Query::Closest, &mut stacks);
                let (any_hit, any_nodes) = trace(Query::Any, &mut stacks);
                assert_eq!(any_hit, closest_hit, "{} {}", structure.name(), kind.name());
                assert!(
                    any_nodes <= closest_nodes,
                    "{} {}: {any_nodes} > {closest_nodes}",
                    structure.name(),
                    kind.name()
                );
            }
        }
    }
}
