//! Watertightness: rays aimed exactly at vertices and at points on shared edges of closed
//! meshes neither miss nor slip through to the far side in robust mode (watertight triangles,
//! conservative boxes, conservative kD plane crossings), near the origin and far from it, in
//! f32 and f64, through the BVH and the kD-trees. The fast mode's leaks are counted and
//! printed.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::bvh::{BinnedSah, Builder, TraversalStack, traverse, validate};
use accelviz_core::kd::{self, KdBuilder, KdMiddleSplit, KdSahPresorted, KdTraversalStack};
use accelviz_core::params::BuildParams;
use accelviz_core::{
    Hit, NoObserver, PrimitiveSet, Real, TraceOptions, TriangleSet, Vector3, brute_force,
};
use accelviz_scene::Mesh;
use accelviz_scene::builtin::{icosphere, subdivided_cube};
use accelviz_scene::rays::surface_aim_rays;
use glam::{DVec3, Vec3};

/// What went wrong with one way of tracing: rays that missed, and rays that hit something
/// beyond the point they were aimed at (they slipped through the surface).
#[derive(Debug, Default, PartialEq)]
struct Leaks {
    missed: usize,
    slipped: usize,
}

impl Leaks {
    fn count<S: Real>(&mut self, hit: Option<Hit<S>>, aimed_t: f64) {
        match hit {
            None => self.missed += 1,
            // The far side is a mesh's width beyond; the tolerance covers rounding of rays far
            // from the origin in f32.
            Some(hit) if hit.t.to_f64() > aimed_t * (1.0 + 1e-2) => self.slipped += 1,
            Some(_) => {}
        }
    }
}

/// The leaks of brute force, a BVH and three kD-trees over the rays aimed at `mesh`.
fn leaks<V: Vector3>(mesh: &Mesh, robust: bool) -> (Vec<(&'static str, Leaks)>, usize) {
    let triangles = TriangleSet::<V>::from_f64(&mesh.triangles);
    let bounds = triangles.all_bounds();
    let params = BuildParams::default();
    let bvh = BinnedSah::default().build(&bounds, &params);
    validate(&bvh, &bounds).unwrap();
    let kd_trees = [
        ("kd:middle", KdMiddleSplit.build(&bounds, &params)),
        ("kd:sah", KdSahPresorted.build(&bounds, &params)),
        (
            "kd:sah-perfect",
            KdSahPresorted.build_with_perfect_splits(&triangles, &params),
        ),
    ];
    let options = TraceOptions::default().with_robust(robust);
    let mut stack = TraversalStack::new();
    let mut kd_stack = KdTraversalStack::new();
    let rays = surface_aim_rays(&mesh.triangles, 1);
    let axis_distance = mesh.bounds().extent().length();
    let mut found: Vec<(&'static str, Leaks)> = ["brute force", "bvh:sah-binned"]
        .into_iter()
        .chain(kd_trees.iter().map(|(name, _)| *name))
        .map(|name| (name, Leaks::default()))
        .collect();
    for spec in &rays {
        let ray = spec.to_ray::<V>().unwrap();
        // An oblique aimed ray reaches its target at t = 1; one along an axis has a unit
        // direction and starts twice the mesh's bounding radius (its box's diagonal) away.
        let direction = DVec3::from_array(spec.direction);
        let along_axis = direction.abs().max_element() == 1.0 && direction.length() == 1.0;
        let aimed_t = if along_axis { axis_distance } else { 1.0 };
        found[0].1.count(
            brute_force(&triangles, &ray, &options, &mut NoObserver),
            aimed_t,
        );
        found[1].1.count(
            traverse(
                &bvh,
                &triangles,
                &ray,
                &options,
                &mut stack,
                &mut NoObserver,
            ),
            aimed_t,
        );
        for (slot, (_, tree)) in found[2..].iter_mut().zip(&kd_trees) {
            let hit = kd::traverse(
                tree,
                &triangles,
                &ray,
                &options,
                &mut kd_stack,
                &mut NoObserver,
            );
            slot.1.count(hit, aimed_t);
        }
    }
    (found, rays.len())
}

fn meshes() -> Vec<Mesh> {
    let near = [icosphere(3), subdivided_cube(8)];
    let far = near
        .iter()
        .map(|mesh| mesh.translated(accelviz_scene::builtin::FAR_AWAY))
        .collect::<Vec<_>>();
    near.into_iter().chain(far).collect()
}

#[test]
fn robust_mode_never_leaks_through_a_closed_mesh() {
    for mesh in meshes() {
        for (precision, (found, total)) in [
            ("f32", leaks::<Vec3>(&mesh, true)),
            ("f64", leaks::<DVec3>(&mesh, true)),
        ] {
            for (name, leaks) in found {
                assert_eq!(
                    leaks,
                    Leaks::default(),
                    "{} {precision} {name}: leaks out of {total} rays",
                    mesh.name
                );
            }
        }
    }
}

#[test]
fn fast_mode_leaks_are_counted() {
    // Not an assertion on the count: the fast test is allowed to leak; the figure is shown.
    for mesh in meshes() {
        for (precision, (found, total)) in [
            ("f32", leaks::<Vec3>(&mesh, false)),
            ("f64", leaks::<DVec3>(&mesh, false)),
        ] {
            for (name, leaks) in found {
                println!(
                    "fast mode, {} {precision}, {name}: {} missed, {} slipped through, of {total} rays",
                    mesh.name, leaks.missed, leaks.slipped
                );
                assert!(leaks.missed + leaks.slipped <= total);
            }
        }
    }
}
