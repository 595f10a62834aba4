//! Every kernel held to the portable code, bit for bit, on random and extreme inputs.

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use crate::math::Real;
use crate::primitive::{HitTest, PrimitiveSet, TriangleBlock, TriangleRay, TriangleSet};
use crate::ray::Ray;
use crate::simd::Isa;
use crate::simd::kernel::{
    ChildTests, Kernel, LANES, MAX_PACKET, NodeLanes, PacketLanes, Planes, Portable,
};
use crate::slab::SlabRay;

type Children<S, const W: usize> =
    fn(&Planes<S, W>, &SlabRay<<S as Real>::Vec3>, S) -> ChildTests<S, W>;
type Triangles<S> = fn(&TriangleBlock<S>, &TriangleRay<<S as Real>::Vec3>, S, S) -> [S; 4];

/// The kernels of one instruction set for one precision.
struct Kernels<S: Real> {
    isa: Isa,
    children4: Children<S, 4>,
    children8: Children<S, 8>,
    triangles: Triangles<S>,
    watertight: Triangles<S>,
}

impl<S: Real> Kernels<S> {
    fn of<K: Kernel>(isa: Isa) -> Self {
        Self {
            isa,
            children4: |planes, ray, t_max| {
                K::test_children(planes, &NodeLanes::new(ray), 3, t_max)
            },
            children8: |planes, ray, t_max| {
                K::test_children(planes, &NodeLanes::new(ray), 3, t_max)
            },
            triangles: |block, ray, t_min, t_max| {
                K::moller_trumbore(block, ray.ray.origin, ray.ray.direction, t_min, t_max)
            },
            watertight: K::watertight::<S>,
        }
    }
}

/// Every kernel this machine can run, by instruction set, the portable ones first.
fn kernels<S: Real>() -> Vec<Kernels<S>> {
    let mut kernels = vec![Kernels::of::<Portable>(Isa::Portable)];
    #[cfg(target_arch = "x86_64")]
    {
        use crate::simd::x86::{Avx2, Avx512};
        if Isa::Avx2.is_available() {
            kernels.push(Kernels::of::<Avx2>(Isa::Avx2));
        }
        if Isa::Avx512.is_available() {
            kernels.push(Kernels::of::<Avx512>(Isa::Avx512));
        }
    }
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    kernels.push(Kernels::of::<crate::simd::wasm::Simd128>(Isa::Simd128));
    kernels
}

/// Coordinates that make the hard cases common: planes through the origin, zeros of both
/// signs, huge and tiny values.
fn coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => -10.0..10.0f32,
        2 => (-3i32..3).prop_map(|value| value as f32),
        1 => Just(-0.0f32),
        1 => prop_oneof![Just(1e30f32), Just(-1e30), Just(1e-30), Just(-1e-30)],
    ]
}

fn vec3() -> impl Strategy<Value = Vec3> {
    [coordinate(), coordinate(), coordinate()].prop_map(Vec3::from_array)
}

/// A node's planes: its first slots holding random (possibly flat) boxes, the rest empty.
fn node<const W: usize>() -> impl Strategy<Value = Planes<f32, W>> {
    (prop::collection::vec((vec3(), vec3()), W), 1..=W).prop_map(|(boxes, used)| {
        let mut planes = [[[f32::INFINITY; W]; 3], [[f32::NEG_INFINITY; W]; 3]];
        for (slot, (a, b)) in boxes.into_iter().enumerate().take(used) {
            for axis in 0..3 {
                planes[0][axis][slot] = a[axis].min(b[axis]);
                planes[1][axis][slot] = a[axis].max(b[axis]);
            }
        }
        planes
    })
}

fn ray() -> impl Strategy<Value = (Ray<Vec3>, bool, f32)> {
    (
        vec3(),
        vec3(),
        any::<bool>(),
        prop_oneof![Just(f32::INFINITY), 0.0..20.0f32],
    )
        .prop_filter_map("a direction", |(origin, direction, robust, t_max)| {
            let ray = Ray::try_new(origin, direction).ok()?;
            Some((ray, robust, t_max))
        })
}

/// Bit-for-bit equality, NaN included.
fn bits<S: Real>(values: &[S]) -> Vec<u64> {
    // Widening to f64 is exact, and keeps a NaN's sign and payload apart.
    values
        .iter()
        .map(|value| value.to_f64().to_bits())
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 3000,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn every_child_kernel_computes_the_portable_intervals(
        node4 in node::<4>(),
        node8 in node::<8>(),
        (ray, robust, t_max) in ray(),
    ) {
        same_intervals(&node4, &node8, &ray, robust, t_max)?;
        // The same boxes and ray in f64.
        let (node4, node8) = (widened(&node4), widened(&node8));
        let ray = Ray { origin: ray.origin.as_dvec3(), direction: ray.direction.as_dvec3(), t_min: 0.0, t_max: f64::INFINITY };
        same_intervals(&node4, &node8, &ray, robust, f64::from(t_max))?;
    }

    #[test]
    fn every_triangle_kernel_computes_the_portable_hits(
        corners in prop::collection::vec([vec3(), vec3(), vec3()], 4),
        aim in (0usize..4, 0.0..1.0f32, 0.0..1.0f32, 0usize..3),
        (ray, _, t_max) in ray(),
    ) {
        // Half the rays aim at a corner, an edge or inside one of the triangles.
        let (lane, a, b, kind) = aim;
        let [v0, v1, v2] = corners[lane];
        let target = match kind {
            0 => v0,
            1 => v0 + (v1 - v0) * a,
            _ => v0 + (v1 - v0) * (a * 0.5) + (v2 - v0) * (b * 0.5),
        };
        let aimed = Ray::try_new(ray.origin, target - ray.origin).unwrap_or(ray);
        let wide_corners: Vec<[DVec3; 3]> =
            corners.iter().map(|corner| corner.map(Vec3::as_dvec3)).collect();
        for ray in [ray, aimed] {
            let wide_ray = Ray {
                origin: ray.origin.as_dvec3(),
                direction: ray.direction.as_dvec3(),
                t_min: 0.0,
                t_max: f64::INFINITY,
            };
            for test in [HitTest::Fast, HitTest::Watertight] {
                same_hits(&corners, &ray, test, t_max)?;
                same_hits(&wide_corners, &wide_ray, test, f64::from(t_max))?;
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 500,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn every_packet_box_kernel_computes_the_portable_intervals(
        rays in prop::collection::vec(ray(), LANES * 2),
        corners in (vec3(), vec3()),
        group in 0usize..2,
        dims in 2usize..=3,
        active in any::<u8>(),
    ) {
        let active = u32::from(active);
        let robust = rays[0].1;
        let mut lanes = PacketLanes {
            far_scale: SlabRay::new(&rays[0].0, robust).far_scale,
            ..PacketLanes::default()
        };
        for (index, (ray, _, t_max)) in rays.iter().enumerate() {
            let slab_ray = SlabRay::new(ray, robust);
            for axis in 0..3 {
                lanes.origin[axis][index] = slab_ray.origin[axis];
                lanes.inv_direction[axis][index] = slab_ray.inv_direction[axis];
                lanes.negative[axis][index] = slab_ray.negative[axis];
            }
            lanes.t_min[index] = ray.t_min;
            lanes.t_closest[index] = *t_max;
        }
        let (a, b) = corners;
        let (lower, upper) = (a.min(b).to_array(), a.max(b).to_array());
        let first = group * LANES;
        let want = Portable::box_against_rays(&lanes, lower, upper, first, dims, active);
        for isa in Isa::ALL.into_iter().filter(|isa| isa.is_available()) {
            let got = match isa {
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2 => <crate::simd::x86::Avx2 as Kernel>::box_against_rays(&lanes, lower, upper, first, dims, active),
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => <crate::simd::x86::Avx512 as Kernel>::box_against_rays(&lanes, lower, upper, first, dims, active),
                #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
                Isa::Simd128 => <crate::simd::wasm::Simd128 as Kernel>::box_against_rays(&lanes, lower, upper, first, dims, active),
                _ => Portable::box_against_rays(&lanes, lower, upper, first, dims, active),
            };
            prop_assert_eq!(got.hits, want.hits, "{:?}", isa);
            prop_assert_eq!(bits(&got.t_enter), bits(&want.t_enter), "{:?}", isa);
            prop_assert_eq!(bits(&got.t_exit), bits(&want.t_exit), "{:?}", isa);
            prop_assert_eq!(bits(&got.entries), bits(&want.entries), "{:?}", isa);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 1000,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn every_packet_triangle_kernel_computes_the_block_kernels_hits(
        rays in prop::collection::vec(ray(), LANES * 2),
        corners in prop::collection::vec([vec3(), vec3(), vec3()], 4),
        lane in 0usize..4,
        aims in prop::collection::vec((0.0..1.0f32, 0.0..1.0f32), LANES * 2),
        group in 0usize..2,
    ) {
        // Half the rays aim inside, or at the edges of, the triangle tested.
        let [v0, v1, v2] = corners[lane];
        let rays: Vec<(Ray<Vec3>, f32)> = rays
            .iter()
            .zip(&aims)
            .enumerate()
            .map(|(index, ((ray, _, t_max), &(a, b)))| {
                let target = v0 + (v1 - v0) * a + (v2 - v0) * (b * (1.0 - a));
                let aimed = Ray::try_new(ray.origin, target - ray.origin).unwrap_or(*ray);
                (if index % 2 == 0 { aimed } else { *ray }, *t_max)
            })
            .collect();
        let block = TriangleBlock::pack(&corners)[0];
        same_packet_hits(&block, lane, &packet_lanes(&rays), group * LANES)?;
        let wide_corners: Vec<[DVec3; 3]> =
            corners.iter().map(|corner| corner.map(Vec3::as_dvec3)).collect();
        let wide_rays: Vec<(Ray<DVec3>, f64)> = rays
            .iter()
            .map(|(ray, t_max)| {
                let ray = Ray {
                    origin: ray.origin.as_dvec3(),
                    direction: ray.direction.as_dvec3(),
                    t_min: f64::from(ray.t_min),
                    t_max: f64::from(ray.t_max),
                };
                (ray, f64::from(*t_max))
            })
            .collect();
        let block = TriangleBlock::pack(&wide_corners)[0];
        same_packet_hits(&block, lane, &packet_lanes(&wide_rays), group * LANES)?;
    }
}

/// A packet's lanes holding `rays`, each searching up to its `t_max`.
fn packet_lanes<V: crate::math::Vector3>(rays: &[(Ray<V>, V::Scalar)]) -> PacketLanes<V::Scalar> {
    let mut lanes = PacketLanes::default();
    for (index, (ray, t_max)) in rays.iter().enumerate() {
        for axis in 0..3 {
            lanes.origin[axis][index] = ray.origin[axis];
            lanes.direction[axis][index] = ray.direction[axis];
        }
        lanes.t_min[index] = ray.t_min;
        lanes.t_closest[index] = *t_max;
    }
    lanes
}

/// The portable packet triangle test is the block kernel's lane `lane`, ray by ray (itself the
/// one-triangle test), and every instruction set's gives its `t` bit for bit and its hits.
fn same_packet_hits<S: Real>(
    block: &TriangleBlock<S>,
    lane: usize,
    lanes: &PacketLanes<S>,
    first: usize,
) -> Result<(), TestCaseError> {
    use crate::math::Vector3;
    let (want, want_hits) = Portable::triangle_against_rays(block, lane, lanes, first);
    for (index, &t) in want.iter().enumerate() {
        let ray = first + index;
        let vector = |rows: &[[S; MAX_PACKET]; 3]| {
            <S::Vec3 as Vector3>::new(rows[0][ray], rows[1][ray], rows[2][ray])
        };
        let block_t = Portable::moller_trumbore(
            block,
            vector(&lanes.origin),
            vector(&lanes.direction),
            lanes.t_min[ray],
            lanes.t_closest[ray],
        )[lane];
        prop_assert_eq!(bits(&[t]), bits(&[block_t]), "ray {}", ray);
        prop_assert_eq!(want_hits >> index & 1 == 1, !t.is_nan(), "ray {}", ray);
    }
    for isa in Isa::ALL.into_iter().filter(|isa| isa.is_available()) {
        let (got, got_hits) = match isa {
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => {
                <crate::simd::x86::Avx2 as Kernel>::triangle_against_rays(block, lane, lanes, first)
            }
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => <crate::simd::x86::Avx512 as Kernel>::triangle_against_rays(
                block, lane, lanes, first,
            ),
            #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
            Isa::Simd128 => <crate::simd::wasm::Simd128 as Kernel>::triangle_against_rays(
                block, lane, lanes, first,
            ),
            _ => Portable::triangle_against_rays(block, lane, lanes, first),
        };
        prop_assert_eq!(bits(&got), bits(&want), "{:?}", isa);
        prop_assert_eq!(got_hits, want_hits, "{:?}", isa);
    }
    Ok(())
}

/// `planes` in f64 (the same boxes: f32 widens exactly).
fn widened<const W: usize>(planes: &Planes<f32, W>) -> Planes<f64, W> {
    planes.map(|side| side.map(|row| row.map(f64::from)))
}

/// Every child kernel gives the portable intervals, bit for bit, for nodes of 4 and 8.
fn same_intervals<S: Real>(
    node4: &Planes<S, 4>,
    node8: &Planes<S, 8>,
    ray: &Ray<S::Vec3>,
    robust: bool,
    t_max: S,
) -> Result<(), TestCaseError> {
    let slab_ray = SlabRay::new(ray, robust);
    let kernels = kernels::<S>();
    let want4 = (kernels[0].children4)(node4, &slab_ray, t_max);
    let want8 = (kernels[0].children8)(node8, &slab_ray, t_max);
    for kernel in &kernels {
        let got4 = (kernel.children4)(node4, &slab_ray, t_max);
        let got8 = (kernel.children8)(node8, &slab_ray, t_max);
        let isa = kernel.isa;
        prop_assert_eq!(got4.hit_mask, want4.hit_mask, "{:?}", isa);
        prop_assert_eq!(bits(&got4.t_enter), bits(&want4.t_enter), "{:?}", isa);
        prop_assert_eq!(bits(&got4.t_exit), bits(&want4.t_exit), "{:?}", isa);
        prop_assert_eq!(got8.hit_mask, want8.hit_mask, "{:?}", isa);
        prop_assert_eq!(bits(&got8.t_enter), bits(&want8.t_enter), "{:?}", isa);
        prop_assert_eq!(bits(&got8.t_exit), bits(&want8.t_exit), "{:?}", isa);
    }
    Ok(())
}

/// The portable block test is the one-triangle test lane by lane, and every kernel gives
/// its `t`, bit for bit, and its misses.
fn same_hits<V: crate::math::Vector3>(
    corners: &[[V; 3]],
    ray: &Ray<V>,
    test: HitTest,
    t_max: V::Scalar,
) -> Result<(), TestCaseError> {
    let block = TriangleBlock::pack(corners)[0];
    let prepared = TriangleRay::new(ray, test);
    let zero = V::Scalar::ZERO;
    let kernels = kernels::<V::Scalar>();
    let test_of = |kernel: &Kernels<V::Scalar>| match test {
        HitTest::Fast => kernel.triangles,
        HitTest::Watertight => kernel.watertight,
    };
    let want = test_of(&kernels[0])(&block, &prepared, zero, t_max);
    let triangles = TriangleSet::<V>::from_f64(
        &corners
            .iter()
            .map(|corner| corner.map(|v| v.to_f64_array()))
            .collect::<Vec<_>>(),
    );
    for (lane, &t) in want.iter().enumerate() {
        // A degenerate triangle is stored collapsed, so never hit; skip it.
        if triangles.triangles()[lane] != corners[lane] {
            continue;
        }
        let single = triangles.intersect(&prepared, lane, zero, t_max);
        prop_assert_eq!(
            bits(&[single.unwrap_or(V::Scalar::NAN)]),
            bits(&[t]),
            "{:?}",
            test
        );
    }
    for kernel in &kernels {
        let got = test_of(kernel)(&block, &prepared, zero, t_max);
        prop_assert_eq!(bits(&got), bits(&want), "{:?} {:?}", kernel.isa, test);
    }
    Ok(())
}
