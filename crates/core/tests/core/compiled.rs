//! The core's `compiled` wrappers (what the browser app calls on its hot paths) give what the
//! generic calls they stand for give: the same trees, hits and counts, for every family.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::camera::Camera;
use accelviz_core::params::BuildParams;
use accelviz_core::{
    Built, CATALOGUE, Counters, NoBuildObserver, NoObserver, Order, Ray, Structure, TraceOptions,
    TraversalStacks, TriangleSet, compiled,
};
use accelviz_scene::builtin::lumpy_grid_sphere;
use glam::{DVec3, Vec3};

#[test]
fn the_compiled_wrappers_build_and_trace_as_the_generic_calls() {
    let mesh = lumpy_grid_sphere(600);
    let in_f64 = TriangleSet::<DVec3>::from_f64(&mesh.triangles);
    let in_f32 = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    let camera = Camera::framing(&mesh.bounds());
    let (width, height) = (16, 12);
    let rays: Vec<Ray<DVec3>> = (0..width * height)
        .map(|pixel| {
            let (x, y) = ((pixel % width) as f64 + 0.5, (pixel / width) as f64 + 0.5);
            let (origin, direction) = camera.ray_through(x, y, width, height);
            Ray::try_new(origin, direction).unwrap()
        })
        .collect();
    let params = BuildParams::default();
    for entry in CATALOGUE {
        let structure = Structure::parse(entry.name).unwrap();
        let name = structure.name();

        let built = compiled::build_triangles(structure, &in_f64, &params);
        let generic = Built::new(structure, &in_f64, &params, &mut NoBuildObserver);
        assert_eq!(
            built.facts.node_count(),
            generic.facts.node_count(),
            "{name}"
        );
        let tree_f32 = compiled::build_tree_f32(structure, &in_f32, &params);
        let built_f32 = compiled::build_triangles_f32(structure, &in_f32, &params);
        assert_eq!(
            tree_f32.stats(&Default::default()),
            built_f32.tree.stats(&Default::default()),
            "{name}"
        );

        let ordered = built.tree.leaf_ordered(&in_f64);
        let ordered_f32 = tree_f32.leaf_ordered(&in_f32);
        for order in [Order::NearFirst, Order::FileOrder] {
            let options = TraceOptions {
                order,
                ..TraceOptions::default()
            };
            let mut stacks = TraversalStacks::default();
            let mut stacks_f32 = TraversalStacks::default();
            let mut hits = 0;
            for ray in &rays {
                let expected =
                    generic
                        .tree
                        .trace(&ordered, ray, &options, &mut stacks, &mut NoObserver);
                let got =
                    compiled::trace_triangles(&built.tree, &ordered, ray, &options, &mut stacks);
                assert_eq!(got, expected, "{name} {order:?}");
                hits += usize::from(got.is_some());

                let (mut counted, mut wrapped) = (Counters::default(), Counters::default());
                generic
                    .tree
                    .trace(&ordered, ray, &options, &mut stacks, &mut counted);
                compiled::trace_triangles_counted(
                    &built.tree,
                    &ordered,
                    ray,
                    &options,
                    &mut stacks,
                    &mut wrapped,
                );
                assert_eq!(wrapped, counted, "{name} {order:?}");

                let narrowed = Ray::try_new(ray.origin.as_vec3(), ray.direction.as_vec3()).unwrap();
                let expected_f32 = tree_f32.trace(
                    &ordered_f32,
                    &narrowed,
                    &options,
                    &mut stacks_f32,
                    &mut NoObserver,
                );
                let got_f32 = compiled::trace_triangles_f32(
                    &tree_f32,
                    &ordered_f32,
                    &narrowed,
                    &options,
                    &mut stacks_f32,
                );
                assert_eq!(got_f32, expected_f32, "{name} {order:?}");
            }
            assert!(
                hits > rays.len() / 10,
                "{name}: the camera sees the mesh ({hits} hits)"
            );

            // A packet: each ray's hit and counts as one by one.
            let packet = &rays[..8];
            let mut counters = vec![Counters::default(); packet.len()];
            let mut packet_hits = vec![None; packet.len()];
            compiled::trace_packet_counted(
                &built.tree,
                &ordered,
                packet,
                &options,
                &mut stacks,
                &mut counters,
                &mut packet_hits,
            );
            let mut expected_hits = vec![None; packet.len()];
            let mut expected_counters = vec![Counters::default(); packet.len()];
            generic.tree.trace_packet(
                &ordered,
                packet,
                &options,
                &mut stacks,
                &mut expected_counters,
                &mut expected_hits,
            );
            assert_eq!(packet_hits, expected_hits, "{name} {order:?}");
            assert_eq!(counters, expected_counters, "{name} {order:?}");
        }
    }
}
