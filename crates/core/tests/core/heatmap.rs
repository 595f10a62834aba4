//! Heat maps count what the traversal does on the benchmark's camera rays: their totals are
//! the counters summed over `bench --camera`'s rays, whatever the number of threads.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::camera::{Camera, Projection};
use accelviz_core::heatmap::{Counter, HeatMap};
use accelviz_core::params::BuildParams;
use accelviz_core::{
    Counters, Order, Structure, TraceOptions, TraversalStacks, TriangleSet, brute_force,
};
use accelviz_scene::builtin::lumpy_grid_sphere;
use accelviz_scene::rays::camera_rays;
use glam::{DVec3, Vec3};

#[test]
fn totals_are_the_benchmarks_counts_on_any_number_of_threads() {
    let mesh = lumpy_grid_sphere(2_000);
    let triangles = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    let (width, height) = (37, 23);
    let camera = Camera::framing(&mesh.bounds());
    for name in ["bvh:sah-binned", "bvh:middle", "kd:sah"] {
        let tree = Structure::parse(name)
            .unwrap()
            .build(&triangles, &BuildParams::default());
        let ordered = tree.leaf_ordered(&triangles);
        for order in [Order::NearFirst, Order::FileOrder] {
            let options = TraceOptions {
                order,
                ..TraceOptions::default()
            };
            let trace = |ray: &accelviz_core::Ray<Vec3>,
                         stacks: &mut TraversalStacks<f32>,
                         counters: &mut Counters| {
                tree.trace(&ordered, ray, &options, stacks, counters);
            };
            let one = HeatMap::compute(&camera, width, height, 1, &trace);
            let two = HeatMap::compute(&camera, width, height, 2, &trace);
            assert_eq!(one, two, "{name} {order:?}: threads change the map");

            // The benchmark's path: camera rays as ray specs, converted, traced one by one.
            let mut summed = Counters::default();
            let mut stacks = TraversalStacks::default();
            for spec in camera_rays(&mesh.bounds(), width, height) {
                let ray = spec.to_ray::<Vec3>().unwrap();
                tree.trace(&ordered, &ray, &options, &mut stacks, &mut summed);
            }
            assert_eq!(one.summary(Counter::Nodes).total, summed.nodes_visited);
            assert_eq!(one.summary(Counter::Boxes).total, summed.box_tests);
            assert_eq!(one.summary(Counter::Prims).total, summed.primitive_tests);
            assert!(summed.nodes_visited > 0);
        }
    }
}

#[test]
fn every_pixel_ray_finds_brute_forces_hit_and_rows_can_be_traced_piece_by_piece() {
    let mesh = lumpy_grid_sphere(500);
    let triangles = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    let tree = Structure::parse("bvh:sah-sweep")
        .unwrap()
        .build(&triangles, &BuildParams::default());
    let ordered = tree.leaf_ordered(&triangles);
    let camera = Camera {
        eye: DVec3::new(0.3, 4.0, 0.2),
        target: DVec3::ZERO,
        up: DVec3::Z,
        projection: Projection::Orthographic { half_size: 1.4 },
    };
    let (width, height) = (16, 12);
    let options = TraceOptions::default();
    let mut stacks = TraversalStacks::default();
    let mut pieces = HeatMap::new(width, height);
    for rows in [0..5, 5..6, 6..12, 12..40] {
        pieces.trace_rows::<Vec3>(&camera, rows, |ray, counters| {
            tree.trace(&ordered, ray, &options, &mut stacks, counters);
        });
    }
    let whole = HeatMap::compute(&camera, width, height, 1, &|ray, stacks, counters| {
        tree.trace(&ordered, ray, &options, stacks, counters);
    });
    assert_eq!(pieces, whole);
    let mut hits = 0;
    for row in 0..height {
        for column in 0..width {
            let ray = camera
                .pixel_ray::<Vec3>(column, row, width, height)
                .unwrap();
            let found = tree.trace(
                &ordered,
                &ray,
                &options,
                &mut stacks,
                &mut accelviz_core::NoObserver,
            );
            let expected = brute_force(&triangles, &ray, &options, &mut accelviz_core::NoObserver);
            assert_eq!(
                found.map(|hit| hit.primitive),
                expected.map(|hit| hit.primitive)
            );
            hits += usize::from(found.is_some());
            // A pixel whose ray hits tested at least one primitive.
            if found.is_some() {
                assert!(whole.at(column, row).unwrap().prims > 0);
            }
        }
    }
    assert!(hits > 20 && hits < width * height, "{hits} hits");
}

#[test]
fn packet_maps_are_the_packet_benchmarks_counts_pixel_by_pixel() {
    let mesh = lumpy_grid_sphere(2_000);
    let triangles = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    let (width, height) = (37, 21);
    let camera = Camera::framing(&mesh.bounds());
    let specs = camera_rays(&mesh.bounds(), width, height);
    let options = TraceOptions::default();
    for name in ["bvh8:sah-binned", "bvh4:middle", "bvh:sah-binned"] {
        let tree = Structure::parse(name)
            .unwrap()
            .build(&triangles, &BuildParams::default());
        let ordered = tree.leaf_ordered(&triangles);
        let packets = |rays: &[accelviz_core::Ray<Vec3>],
                       stacks: &mut TraversalStacks<f32>,
                       counters: &mut [Counters]| {
            let mut hits = vec![None; rays.len()];
            tree.trace_packet(&ordered, rays, &options, stacks, counters, &mut hits);
        };
        let map = HeatMap::compute_in_packets(&camera, width, height, 2, 8, &packets);

        // The benchmark's path (`bench --camera --packet 64`): the same 8×8 tiles.
        let mut stacks = TraversalStacks::default();
        for tile in accelviz_scene::rays::pixel_tiles(width, height, 8, 8) {
            let rays: Vec<_> = tile
                .iter()
                .map(|&pixel| specs[pixel as usize].to_ray::<Vec3>().unwrap())
                .collect();
            let mut counters = vec![Counters::default(); rays.len()];
            let mut hits = vec![None; rays.len()];
            tree.trace_packet(
                &ordered,
                &rays,
                &options,
                &mut stacks,
                &mut counters,
                &mut hits,
            );
            for (&pixel, counters) in tile.iter().zip(&counters) {
                let cost = map.pixels[pixel as usize];
                assert_eq!(
                    (cost.nodes, cost.boxes, cost.prims),
                    (
                        counters.nodes_visited as u32,
                        counters.box_tests as u32,
                        counters.primitive_tests as u32
                    ),
                    "{name}: pixel {pixel}"
                );
            }
        }

        // One ray at a time, for comparison: a wide tree's packets test other boxes (the
        // whole packet's), a binary tree traces its packets ray by ray.
        let single = HeatMap::compute(&camera, width, height, 1, &|ray, stacks, counters| {
            tree.trace(&ordered, ray, &options, stacks, counters);
        });
        if name.starts_with("bvh:") {
            assert_eq!(map, single, "{name}");
        } else {
            assert_ne!(map, single, "{name}");
        }
        // Tiles of one pixel are single rays.
        let ones = HeatMap::compute_in_packets(&camera, width, height, 1, 1, &packets);
        assert_eq!(ones, single, "{name}");
    }
}
