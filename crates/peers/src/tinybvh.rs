//! tinybvh (Bikker), through its Rust wrapper `tinybvh-rs`: its binned SAH build with leaves
//! of at most 4 triangles, collapsed to its 8-wide `BVH8_CPU` layout (after Fuetterling et
//! al. 2015, "Accelerated single ray tracing for wide vector units") and traced with its
//! AVX2 traversal, one ray at a time. The wrapper offers that traversal only when AVX2 is
//! enabled at compile time, so without it this peer says how to build it (`scripts/bench`
//! builds this crate with `-C target-cpu=native`).
//!
//! The wrapper has no occlusion query: any-hit queries are answered by the closest hit
//! (`tinybvh:bvh8-cpu(closest)` in the tables).
//!
//! (tinybvh's binary BVH and its own traversal are left out: on the bunny they miss 16 % of
//! the hits every other tracer finds.)

use accelviz_core::Query;
use accelviz_scene::Mesh;
use accelviz_scene::rays::RaySpec;
use anyhow::Result;

use crate::Figures;

#[cfg(not(target_feature = "avx2"))]
pub fn run(_mesh: &Mesh, _rays: &[RaySpec], _query: Query) -> Result<Figures> {
    anyhow::bail!(
        "tinybvh's BVH8_CPU traversal needs AVX2 at compile time: build accelviz-peers with \
         RUSTFLAGS='-C target-cpu=native' (scripts/bench does)"
    )
}

#[cfg(target_feature = "avx2")]
pub fn run(mesh: &Mesh, rays: &[RaySpec], query: Query) -> Result<Figures> {
    use std::time::Instant;
    use tinybvh_rs::{bvh, bvh8_cpu, mbvh};

    // Three corners a triangle, four numbers a corner (the fourth unused).
    let corners: Vec<[f32; 4]> = mesh
        .triangles
        .iter()
        .flatten()
        .map(|&corner| {
            let [x, y, z] = crate::to_f32(corner);
            [x, y, z, 0.0]
        })
        .collect();
    let start = Instant::now();
    let mut binary = bvh::BVH::new(corners.as_slice().into())
        .map_err(|error| anyhow::anyhow!("tinybvh refused the mesh: {error}"))?;
    binary.split_leaves(4);
    let collapsed = mbvh::BVH::new(&binary);
    let wide = bvh8_cpu::BVH::new(&collapsed)
        .map_err(|error| anyhow::anyhow!("tinybvh could not make its BVH8_CPU: {error}"))?;
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    let hits = rays
        .iter()
        .filter(|r| {
            let mut ray = PaddedRay::new(
                crate::to_f32(r.origin),
                crate::to_f32(r.direction),
                crate::t_max_f32(r),
            );
            let t_end = ray.ray.hit.t;
            tinybvh_rs::Intersector::intersect(&wide, &mut ray.ray);
            // A miss leaves `t` where it began: the ray's end, or tinybvh's "infinity", 1e30.
            ray.ray.hit.t < t_end
        })
        .count();
    Ok(Figures {
        name: match query {
            Query::Any => "tinybvh:bvh8-cpu(closest)".to_owned(),
            _ => "tinybvh:bvh8-cpu".to_owned(),
        },
        build_ms,
        trace_ms: start.elapsed().as_secs_f64() * 1e3,
        hits,
    })
}

/// A tinybvh ray with room behind it. The C++ `Ray` is 128 bytes (its hit record carries 64
/// bytes of user data) while `tinybvh_rs::Ray` mirrors only the first 64, so
/// `tinybvh_rs::Ray::new`, which returns the C++ struct by value, writes past it and breaks
/// the stack (0.1.0-beta.3). Rays are made here instead, field by field as tinybvh's own
/// constructor makes them, in a block as large as the C++ struct.
#[cfg(target_feature = "avx2")]
#[repr(C, align(64))]
struct PaddedRay {
    ray: tinybvh_rs::Ray,
    _user_data: [u8; 64],
}

#[cfg(target_feature = "avx2")]
impl PaddedRay {
    fn new(origin: [f32; 3], direction: [f32; 3], t_max: f32) -> Self {
        // As tinybvh's `Ray(O, D, rayLength)`: the direction normalised, its reciprocal, every
        // mask bit (the first padding word is the C++ ray's mask), the hit's `t` at the end
        // of the ray (counted in lengths of the normalised direction).
        let direction = glam::Vec3::from_array(direction);
        let length = direction.length();
        let direction = direction / length;
        let mut hit = tinybvh_rs::Intersection::new();
        hit.t = (t_max * length).min(tinybvh_rs::INFINITE);
        Self {
            ray: tinybvh_rs::Ray {
                origin,
                padding_0: 0xFFFF,
                dir: direction.to_array(),
                padding_1: 0,
                r_d: direction.recip().to_array(),
                padding_2: 0,
                hit,
            },
            _user_data: [0; 64],
        }
    }
}
