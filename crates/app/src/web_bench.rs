//! What `web/bench.mjs` times against three-mesh-bvh, the web's usual BVH: accelviz's own
//! traversal (the one every lesson observes), compiled to WebAssembly as the browser app is
//! (f32, simd128 kernels), over the same triangles and the same rays.
//!
//! Rays cross the boundary as six f32 numbers each (origin, then direction, normalised so
//! that a hit's `t` is its distance, which three.js reports), and come from the generators
//! `accelviz-cli bench` uses ([`RaySource`]), so the browser figures sit beside the CLI's.

use accelviz_core::params::BuildParams;
use accelviz_core::{
    LeafOrdered, Ray3, Structure, TraceOptions, TraversalStacks, Tree, TriangleSet, compiled,
};
use accelviz_scene::Mesh;
use accelviz_scene::rays::RaySource;
use glam::{DVec3, Vec3};
use web_time::Instant;

use crate::mesh::packed::triangles_of;

/// Numbers per ray: origin x, y, z, then direction x, y, z.
pub const RAY_NUMBERS: usize = 6;

/// A structure built over triangles, ready to trace rays one at a time.
pub struct Tracer {
    tree: Tree<Vec3>,
    primitives: LeafOrdered<TriangleSet<Vec3>>,
    stacks: TraversalStacks<f32>,
    build_millis: f64,
}

impl Tracer {
    /// Builds `structure` (a CLI name such as `bvh8:sah-binned`) over `triangles`, nine
    /// numbers each, in f32.
    pub fn new(triangles: &[f64], structure: &str) -> Result<Self, String> {
        let structure = Structure::parse(structure).map_err(|error| error.to_string())?;
        if !triangles.len().is_multiple_of(9) {
            return Err(format!(
                "{} numbers are not whole triangles (nine numbers each)",
                triangles.len()
            ));
        }
        let set = TriangleSet::<Vec3>::from_f64(&triangles_of(triangles));
        // Timed as the CLI times a build: the tree and the copy of the triangles in its leaf
        // order that traversal reads.
        let started = Instant::now();
        let tree = compiled::build_tree_f32(structure, &set, &BuildParams::default());
        let primitives = tree.leaf_ordered(&set);
        let build_millis = started.elapsed().as_secs_f64() * 1e3;
        Ok(Self {
            tree,
            primitives,
            stacks: TraversalStacks::default(),
            build_millis,
        })
    }

    /// How long the build took, in milliseconds.
    pub fn build_millis(&self) -> f64 {
        self.build_millis
    }

    /// Traces `rays` ([`RAY_NUMBERS`] each) for their closest hits over `[0, +inf)`, writing
    /// each ray's hit distance to `distances` (+inf for a miss); the number of hits. A ray
    /// that is not one (a zero or non-finite direction) is refused by its number, before
    /// anything is written.
    pub fn trace(&mut self, rays: &[f32], distances: &mut [f32]) -> Result<u32, String> {
        if !rays.len().is_multiple_of(RAY_NUMBERS) || rays.len() / RAY_NUMBERS != distances.len() {
            return Err(format!(
                "{} numbers are not {} rays of {RAY_NUMBERS} numbers each",
                rays.len(),
                distances.len()
            ));
        }
        let ray_of = |numbers: &[f32]| {
            Ray3::try_new(
                Vec3::new(numbers[0], numbers[1], numbers[2]),
                Vec3::new(numbers[3], numbers[4], numbers[5]),
            )
        };
        // Every ray checked first, so a bad one leaves `distances` as it was; then made again
        // as it is traced (cheaper than keeping them all).
        for (index, numbers) in rays.chunks_exact(RAY_NUMBERS).enumerate() {
            ray_of(numbers).map_err(|error| format!("ray {index}: {error}"))?;
        }
        let options = TraceOptions::default();
        let mut hit_count = 0;
        for (numbers, distance) in rays.chunks_exact(RAY_NUMBERS).zip(distances) {
            let Ok(ray) = ray_of(numbers) else { continue };
            let hit = compiled::trace_triangles_f32(
                &self.tree,
                &self.primitives,
                &ray,
                &options,
                &mut self.stacks,
            );
            *distance = hit.map_or(f32::INFINITY, |hit| hit.t);
            hit_count += u32::from(hit.is_some());
        }
        Ok(hit_count)
    }
}

/// The rays `accelviz-cli bench` traces for the mesh of `triangles`: `count` random rays
/// with `seed`, or, with `camera` (`WIDTHxHEIGHT`), one per pixel of the camera framing the
/// mesh. Directions are normalised (see the module's notes).
pub fn bench_rays(
    triangles: &[f64],
    camera: Option<&str>,
    count: usize,
    seed: u64,
) -> Result<Vec<f32>, String> {
    let mesh = Mesh {
        name: String::new(),
        triangles: triangles_of(triangles),
    };
    let source = RaySource::from_options(None, camera, count, seed)?;
    let rays = source.rays(&mesh).map_err(|error| error.to_string())?;
    let mut numbers = Vec::with_capacity(rays.len() * RAY_NUMBERS);
    for ray in rays {
        let direction = DVec3::from_array(ray.direction).normalize();
        numbers.extend(ray.origin.iter().map(|&x| x as f32));
        numbers.extend(direction.to_array().iter().map(|&x| x as f32));
    }
    Ok(numbers)
}

#[cfg(test)]
mod tests {
    use super::*;
    use accelviz_core::{NoObserver, brute_force};

    /// Two unit squares facing +z, at z = 0 and z = 1, as nine numbers a triangle.
    fn squares() -> Vec<f64> {
        let mut numbers = Vec::new();
        for z in [0.0, 1.0] {
            numbers.extend([0.0, 0.0, z, 1.0, 0.0, z, 1.0, 1.0, z]);
            numbers.extend([0.0, 0.0, z, 1.0, 1.0, z, 0.0, 1.0, z]);
        }
        numbers
    }

    #[test]
    fn distances_are_brute_forces_closest_hits_for_every_width() {
        let triangles = squares();
        let rays = bench_rays(&triangles, None, 500, 7).unwrap();
        let set = TriangleSet::<Vec3>::from_f64(&triangles_of(&triangles));
        for structure in [
            "bvh:sah-binned",
            "bvh4:sah-binned",
            "bvh8:sah-sweep",
            "kd:sah",
        ] {
            let mut tracer = Tracer::new(&triangles, structure).unwrap();
            let mut distances = vec![0.0; rays.len() / RAY_NUMBERS];
            let hit_count = tracer.trace(&rays, &mut distances).unwrap();
            let mut expected_hits = 0;
            for (numbers, distance) in rays.chunks_exact(RAY_NUMBERS).zip(&distances) {
                let ray = Ray3::try_new(
                    Vec3::from_slice(&numbers[..3]),
                    Vec3::from_slice(&numbers[3..]),
                )
                .unwrap();
                let expected = brute_force(&set, &ray, &TraceOptions::default(), &mut NoObserver);
                expected_hits += u32::from(expected.is_some());
                assert_eq!(
                    *distance,
                    expected.map_or(f32::INFINITY, |hit| hit.t),
                    "{structure}"
                );
            }
            assert_eq!(hit_count, expected_hits, "{structure}");
            assert!(hit_count > 0 && hit_count < 500, "{structure}: {hit_count}");
        }
    }

    #[test]
    fn directions_are_unit_so_t_is_a_distance() {
        let rays = bench_rays(&squares(), Some("8x4"), 0, 1).unwrap();
        assert_eq!(rays.len(), 32 * RAY_NUMBERS);
        for numbers in rays.chunks_exact(RAY_NUMBERS) {
            assert!((Vec3::from_slice(&numbers[3..]).length() - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn bad_input_is_refused_with_where() {
        let triangles = squares();
        assert!(Tracer::new(&triangles[..10], "bvh8:sah-binned").is_err());
        let unknown = Tracer::new(&triangles, "bvh9:sah").err().unwrap();
        assert!(unknown.contains("bvh9"), "{unknown}");
        let mut tracer = Tracer::new(&triangles, "bvh8:sah-binned").unwrap();
        let mut distances = [5.0; 2];
        let rays = [0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0];
        let error = tracer.trace(&rays, &mut distances).unwrap_err();
        assert!(error.starts_with("ray 1:"), "{error}");
        assert_eq!(distances, [5.0; 2], "nothing written before the refusal");
        assert!(tracer.trace(&rays[..6], &mut distances).is_err());
    }
}
