//! The x86-64 kernels: SSE, AVX2 and AVX-512 registers, each set's kernels compiled for it,
//! and the work over them compiled once per set (`run_avx2`, `run_avx512`).

use std::arch::x86_64::*;

use glam::{DVec3, Vec3};

use crate::primitive::{TriangleBlock, TriangleRay};
use crate::simd::KernelJob;
use crate::simd::kernel::{
    BoxAgainstRays, ChildTests, LANES, NodeLanes, PacketLanes, Planes, impl_kernel,
};
use crate::simd::lanes::{
    Register, box_in_lanes, children_in_lanes, moller_trumbore_rays, moller_trumbore4, watertight4,
};

/// AVX2 + FMA kernels (FMA is not used: it would round differently from the portable
/// code; it comes with every AVX2 processor and the compiler may use it elsewhere).
pub(crate) struct Avx2;
/// AVX-512 F + VL kernels (the AVX2 code, compiled for AVX-512).
pub(crate) struct Avx512;

impl_kernel!(
    Avx2,
    children_avx2,
    children64_avx2,
    moller_trumbore_avx2,
    moller_trumbore64_avx2,
    watertight_avx2,
    watertight64_avx2,
    box_against_rays_avx2,
    box_against_rays64_avx2,
    triangle_against_rays_avx2,
    triangle_against_rays64_avx2
);
impl_kernel!(
    Avx512,
    children_avx512,
    children64_avx512,
    moller_trumbore_avx512,
    moller_trumbore64_avx512,
    watertight_avx512,
    watertight64_avx512,
    box_against_rays_avx512,
    box_against_rays64_avx512,
    triangle_against_rays_avx512,
    triangle_against_rays64_avx512
);

/// Work over the kernels (a traversal) compiled for one instruction set, with that set's
/// kernels inlined into it.
macro_rules! run_compiled_for {
    ($name:ident, $kernel:ty, $features:literal) => {
        #[target_feature(enable = $features)]
        pub(super) fn $name<J: KernelJob>(job: J) -> J::Output {
            job.run::<$kernel>()
        }
    };
}

run_compiled_for!(run_avx2, Avx2, "avx2,fma");
run_compiled_for!(run_avx512, Avx512, "avx2,fma,avx512f,avx512vl");

/// The kernels of one instruction set, compiled for it: the generic lanes code with its
/// registers (f32: `__m256` when the children fill eight lanes, `__m128` otherwise and for
/// a triangle block; f64: `__m256d`).
macro_rules! kernels {
    (
        $children:ident,
        $children64:ident,
        $moller_trumbore:ident,
        $moller_trumbore64:ident,
        $watertight:ident,
        $watertight64:ident,
        $box_against_rays:ident,
        $box_against_rays64:ident,
        $triangle_against_rays:ident,
        $triangle_against_rays64:ident,
        $features:literal
    ) => {
        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $children<const W: usize>(
            planes: &Planes<f32, W>,
            ray: &NodeLanes<f32, W>,
            t_max: f32,
        ) -> ChildTests<f32, W> {
            if W % 8 == 0 {
                children_in_lanes::<__m256, W>(planes, ray, t_max)
            } else {
                children_in_lanes::<__m128, W>(planes, ray, t_max)
            }
        }

        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $children64<const W: usize>(
            planes: &Planes<f64, W>,
            ray: &NodeLanes<f64, W>,
            t_max: f64,
        ) -> ChildTests<f64, W> {
            children_in_lanes::<__m256d, W>(planes, ray, t_max)
        }

        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $moller_trumbore(
            block: &TriangleBlock<f32>,
            origin: Vec3,
            direction: Vec3,
            t_min: f32,
            t_max: f32,
        ) -> [f32; 4] {
            moller_trumbore4::<__m128>(block, origin, direction, t_min, t_max)
        }

        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $moller_trumbore64(
            block: &TriangleBlock<f64>,
            origin: DVec3,
            direction: DVec3,
            t_min: f64,
            t_max: f64,
        ) -> [f64; 4] {
            moller_trumbore4::<__m256d>(block, origin, direction, t_min, t_max)
        }

        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $watertight(
            block: &TriangleBlock<f32>,
            ray: &TriangleRay<Vec3>,
            t_min: f32,
            t_max: f32,
        ) -> [f32; 4] {
            watertight4::<__m128>(block, ray, t_min, t_max)
        }

        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $watertight64(
            block: &TriangleBlock<f64>,
            ray: &TriangleRay<DVec3>,
            t_min: f64,
            t_max: f64,
        ) -> [f64; 4] {
            watertight4::<__m256d>(block, ray, t_min, t_max)
        }

        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $box_against_rays(
            lanes: &PacketLanes<f32>,
            lower: [f32; 3],
            upper: [f32; 3],
            first: usize,
            dims: usize,
            active: u32,
        ) -> BoxAgainstRays<f32> {
            box_in_lanes::<__m256>(lanes, lower, upper, first, dims, active)
        }

        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $box_against_rays64(
            lanes: &PacketLanes<f64>,
            lower: [f64; 3],
            upper: [f64; 3],
            first: usize,
            dims: usize,
            active: u32,
        ) -> BoxAgainstRays<f64> {
            box_in_lanes::<__m256d>(lanes, lower, upper, first, dims, active)
        }

        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $triangle_against_rays(
            block: &TriangleBlock<f32>,
            lane: usize,
            lanes: &PacketLanes<f32>,
            first: usize,
        ) -> ([f32; LANES], u32) {
            moller_trumbore_rays::<__m256>(block, lane, lanes, first)
        }

        #[inline]
        #[target_feature(enable = $features)]
        pub(super) fn $triangle_against_rays64(
            block: &TriangleBlock<f64>,
            lane: usize,
            lanes: &PacketLanes<f64>,
            first: usize,
        ) -> ([f64; LANES], u32) {
            moller_trumbore_rays::<__m256d>(block, lane, lanes, first)
        }
    };
}

kernels!(
    children_avx2,
    children64_avx2,
    moller_trumbore_avx2,
    moller_trumbore64_avx2,
    watertight_avx2,
    watertight64_avx2,
    box_against_rays_avx2,
    box_against_rays64_avx2,
    triangle_against_rays_avx2,
    triangle_against_rays64_avx2,
    "avx2,fma"
);
kernels!(
    children_avx512,
    children64_avx512,
    moller_trumbore_avx512,
    moller_trumbore64_avx512,
    watertight_avx512,
    watertight64_avx512,
    box_against_rays_avx512,
    box_against_rays64_avx512,
    triangle_against_rays_avx512,
    triangle_against_rays64_avx512,
    "avx2,fma,avx512f,avx512vl"
);

// SAFETY, for every intrinsic in the three implementations below: SSE is part of every
// x86-64 processor, and the AVX lanes are used only by the kernels above, which are
// compiled for AVX2 and run only when `Isa::active` names AVX2 or AVX-512. Loads and
// stores index their slice first, so they stay inside it.

/// SSE's four lanes.
impl Register for __m128 {
    type Scalar = f32;
    const COUNT: usize = 4;
    #[inline(always)]
    fn splat(value: f32) -> Self {
        unsafe { _mm_set1_ps(value) }
    }
    #[inline(always)]
    fn from_slice(values: &[f32]) -> Self {
        unsafe { _mm_loadu_ps(values[..4].as_ptr()) }
    }
    #[inline(always)]
    fn write_to(self, out: &mut [f32]) {
        unsafe { _mm_storeu_ps(out[..4].as_mut_ptr(), self) }
    }
    #[inline(always)]
    fn add(self, other: Self) -> Self {
        unsafe { _mm_add_ps(self, other) }
    }
    #[inline(always)]
    fn sub(self, other: Self) -> Self {
        unsafe { _mm_sub_ps(self, other) }
    }
    #[inline(always)]
    fn mul(self, other: Self) -> Self {
        unsafe { _mm_mul_ps(self, other) }
    }
    #[inline(always)]
    fn div(self, other: Self) -> Self {
        unsafe { _mm_div_ps(self, other) }
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Self {
        unsafe { _mm_cmplt_ps(self, other) }
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Self {
        unsafe { _mm_cmpgt_ps(self, other) }
    }
    #[inline(always)]
    fn le(self, other: Self) -> Self {
        unsafe { _mm_cmple_ps(self, other) }
    }
    #[inline(always)]
    fn ge(self, other: Self) -> Self {
        unsafe { _mm_cmpge_ps(self, other) }
    }
    #[inline(always)]
    fn ne(self, other: Self) -> Self {
        unsafe { _mm_cmpneq_ps(self, other) }
    }
    #[inline(always)]
    fn or(self, other: Self) -> Self {
        unsafe { _mm_or_ps(self, other) }
    }
    #[inline(always)]
    fn and(self, other: Self) -> Self {
        unsafe { _mm_and_ps(self, other) }
    }
    #[inline(always)]
    fn and_not(self, other: Self) -> Self {
        // `_mm_andnot_ps(a, b)` is `!a & b`.
        unsafe { _mm_andnot_ps(other, self) }
    }
    #[inline(always)]
    fn select(self, other: Self, mask: Self) -> Self {
        unsafe { _mm_or_ps(_mm_and_ps(mask, self), _mm_andnot_ps(mask, other)) }
    }
    #[inline(always)]
    fn later(self, other: Self) -> Self {
        // MAXPS is `a > b ? a : b`.
        unsafe { _mm_max_ps(self, other) }
    }
    #[inline(always)]
    fn earlier(self, other: Self) -> Self {
        // MINPS is `a < b ? a : b`.
        unsafe { _mm_min_ps(self, other) }
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        unsafe { _mm_movemask_ps(self) as u32 }
    }
    #[inline(always)]
    fn from_bits(bits: u32) -> Self {
        unsafe {
            let lanes = _mm_setr_epi32(1, 2, 4, 8);
            let set = _mm_and_si128(_mm_set1_epi32(bits as i32), lanes);
            _mm_castsi128_ps(_mm_cmpeq_epi32(set, lanes))
        }
    }
}

/// AVX's eight lanes.
impl Register for __m256 {
    type Scalar = f32;
    const COUNT: usize = 8;
    #[inline(always)]
    fn splat(value: f32) -> Self {
        unsafe { _mm256_set1_ps(value) }
    }
    #[inline(always)]
    fn from_slice(values: &[f32]) -> Self {
        unsafe { _mm256_loadu_ps(values[..8].as_ptr()) }
    }
    #[inline(always)]
    fn write_to(self, out: &mut [f32]) {
        unsafe { _mm256_storeu_ps(out[..8].as_mut_ptr(), self) }
    }
    #[inline(always)]
    fn add(self, other: Self) -> Self {
        unsafe { _mm256_add_ps(self, other) }
    }
    #[inline(always)]
    fn sub(self, other: Self) -> Self {
        unsafe { _mm256_sub_ps(self, other) }
    }
    #[inline(always)]
    fn mul(self, other: Self) -> Self {
        unsafe { _mm256_mul_ps(self, other) }
    }
    #[inline(always)]
    fn div(self, other: Self) -> Self {
        unsafe { _mm256_div_ps(self, other) }
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Self {
        unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self, other) }
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Self {
        unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self, other) }
    }
    #[inline(always)]
    fn le(self, other: Self) -> Self {
        unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self, other) }
    }
    #[inline(always)]
    fn ge(self, other: Self) -> Self {
        unsafe { _mm256_cmp_ps::<_CMP_GE_OQ>(self, other) }
    }
    #[inline(always)]
    fn ne(self, other: Self) -> Self {
        // Unordered: a NaN lane is "not equal", as `!=` says.
        unsafe { _mm256_cmp_ps::<_CMP_NEQ_UQ>(self, other) }
    }
    #[inline(always)]
    fn or(self, other: Self) -> Self {
        unsafe { _mm256_or_ps(self, other) }
    }
    #[inline(always)]
    fn and(self, other: Self) -> Self {
        unsafe { _mm256_and_ps(self, other) }
    }
    #[inline(always)]
    fn and_not(self, other: Self) -> Self {
        unsafe { _mm256_andnot_ps(other, self) }
    }
    #[inline(always)]
    fn select(self, other: Self, mask: Self) -> Self {
        unsafe { _mm256_blendv_ps(other, self, mask) }
    }
    #[inline(always)]
    fn later(self, other: Self) -> Self {
        unsafe { _mm256_max_ps(self, other) }
    }
    #[inline(always)]
    fn earlier(self, other: Self) -> Self {
        unsafe { _mm256_min_ps(self, other) }
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        unsafe { _mm256_movemask_ps(self) as u32 }
    }
    #[inline(always)]
    fn from_bits(bits: u32) -> Self {
        unsafe {
            let lanes = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let set = _mm256_and_si256(_mm256_set1_epi32(bits as i32), lanes);
            _mm256_castsi256_ps(_mm256_cmpeq_epi32(set, lanes))
        }
    }
}

/// AVX's four lanes of f64.
impl Register for __m256d {
    type Scalar = f64;
    const COUNT: usize = 4;
    #[inline(always)]
    fn splat(value: f64) -> Self {
        unsafe { _mm256_set1_pd(value) }
    }
    #[inline(always)]
    fn from_slice(values: &[f64]) -> Self {
        unsafe { _mm256_loadu_pd(values[..4].as_ptr()) }
    }
    #[inline(always)]
    fn write_to(self, out: &mut [f64]) {
        unsafe { _mm256_storeu_pd(out[..4].as_mut_ptr(), self) }
    }
    #[inline(always)]
    fn add(self, other: Self) -> Self {
        unsafe { _mm256_add_pd(self, other) }
    }
    #[inline(always)]
    fn sub(self, other: Self) -> Self {
        unsafe { _mm256_sub_pd(self, other) }
    }
    #[inline(always)]
    fn mul(self, other: Self) -> Self {
        unsafe { _mm256_mul_pd(self, other) }
    }
    #[inline(always)]
    fn div(self, other: Self) -> Self {
        unsafe { _mm256_div_pd(self, other) }
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Self {
        unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self, other) }
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Self {
        unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self, other) }
    }
    #[inline(always)]
    fn le(self, other: Self) -> Self {
        unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(self, other) }
    }
    #[inline(always)]
    fn ge(self, other: Self) -> Self {
        unsafe { _mm256_cmp_pd::<_CMP_GE_OQ>(self, other) }
    }
    #[inline(always)]
    fn ne(self, other: Self) -> Self {
        unsafe { _mm256_cmp_pd::<_CMP_NEQ_UQ>(self, other) }
    }
    #[inline(always)]
    fn or(self, other: Self) -> Self {
        unsafe { _mm256_or_pd(self, other) }
    }
    #[inline(always)]
    fn and(self, other: Self) -> Self {
        unsafe { _mm256_and_pd(self, other) }
    }
    #[inline(always)]
    fn and_not(self, other: Self) -> Self {
        unsafe { _mm256_andnot_pd(other, self) }
    }
    #[inline(always)]
    fn select(self, other: Self, mask: Self) -> Self {
        unsafe { _mm256_blendv_pd(other, self, mask) }
    }
    #[inline(always)]
    fn later(self, other: Self) -> Self {
        unsafe { _mm256_max_pd(self, other) }
    }
    #[inline(always)]
    fn earlier(self, other: Self) -> Self {
        unsafe { _mm256_min_pd(self, other) }
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        unsafe { _mm256_movemask_pd(self) as u32 }
    }
    #[inline(always)]
    fn from_bits(bits: u32) -> Self {
        unsafe {
            let lanes = _mm256_setr_epi64x(1, 2, 4, 8);
            let set = _mm256_and_si256(_mm256_set1_epi64x(i64::from(bits)), lanes);
            _mm256_castsi256_pd(_mm256_cmpeq_epi64(set, lanes))
        }
    }
}
