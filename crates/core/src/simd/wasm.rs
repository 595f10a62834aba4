//! The WebAssembly `simd128` kernels: four lanes of f32 (eight children are two groups of
//! four); f64, two lanes a register, runs the portable code.

use std::arch::wasm32::*;

use glam::{DVec3, Vec3};

use crate::primitive::{TriangleBlock, TriangleRay};
use crate::simd::kernel::{
    BoxAgainstRays, ChildTests, Kernel, LANES, NodeLanes, PacketLanes, Planes, Portable,
    impl_kernel,
};
use crate::simd::lanes::{
    Register, box_in_lanes, children_in_lanes, moller_trumbore_rays, moller_trumbore4, watertight4,
};

/// WebAssembly `simd128` kernels: four lanes; eight children are two groups of four.
pub(crate) struct Simd128;

impl_kernel!(
    Simd128,
    children_simd128,
    children64_simd128,
    moller_trumbore_simd128,
    moller_trumbore64_simd128,
    watertight_simd128,
    watertight64_simd128,
    box_against_rays_simd128,
    box_against_rays64_simd128,
    triangle_against_rays_simd128,
    triangle_against_rays64_simd128
);

pub(super) fn children_simd128<const W: usize>(
    planes: &Planes<f32, W>,
    ray: &NodeLanes<f32, W>,
    t_max: f32,
) -> ChildTests<f32, W> {
    children_in_lanes::<v128, W>(planes, ray, t_max)
}

pub(super) fn moller_trumbore_simd128(
    block: &TriangleBlock<f32>,
    origin: Vec3,
    direction: Vec3,
    t_min: f32,
    t_max: f32,
) -> [f32; 4] {
    moller_trumbore4::<v128>(block, origin, direction, t_min, t_max)
}

pub(super) fn watertight_simd128(
    block: &TriangleBlock<f32>,
    ray: &TriangleRay<Vec3>,
    t_min: f32,
    t_max: f32,
) -> [f32; 4] {
    watertight4::<v128>(block, ray, t_min, t_max)
}

pub(super) fn box_against_rays_simd128(
    lanes: &PacketLanes<f32>,
    lower: [f32; 3],
    upper: [f32; 3],
    first: usize,
    dims: usize,
    active: u32,
) -> BoxAgainstRays<f32> {
    box_in_lanes::<v128>(lanes, lower, upper, first, dims, active)
}

pub(super) fn triangle_against_rays_simd128(
    block: &TriangleBlock<f32>,
    lane: usize,
    lanes: &PacketLanes<f32>,
    first: usize,
) -> ([f32; LANES], u32) {
    moller_trumbore_rays::<v128>(block, lane, lanes, first)
}

// f64 has no lanes of its own here (two per `simd128` register): the portable code.

pub(super) fn triangle_against_rays64_simd128(
    block: &TriangleBlock<f64>,
    lane: usize,
    lanes: &PacketLanes<f64>,
    first: usize,
) -> ([f64; LANES], u32) {
    Portable::triangle_against_rays(block, lane, lanes, first)
}

pub(super) fn box_against_rays64_simd128(
    lanes: &PacketLanes<f64>,
    lower: [f64; 3],
    upper: [f64; 3],
    first: usize,
    dims: usize,
    active: u32,
) -> BoxAgainstRays<f64> {
    Portable::box_against_rays(lanes, lower, upper, first, dims, active)
}

pub(super) fn children64_simd128<const W: usize>(
    planes: &Planes<f64, W>,
    ray: &NodeLanes<f64, W>,
    t_max: f64,
) -> ChildTests<f64, W> {
    Portable::test_children(planes, ray, 3, t_max)
}

pub(super) fn moller_trumbore64_simd128(
    block: &TriangleBlock<f64>,
    origin: DVec3,
    direction: DVec3,
    t_min: f64,
    t_max: f64,
) -> [f64; 4] {
    Portable::moller_trumbore(block, origin, direction, t_min, t_max)
}

pub(super) fn watertight64_simd128(
    block: &TriangleBlock<f64>,
    ray: &TriangleRay<DVec3>,
    t_min: f64,
    t_max: f64,
) -> [f64; 4] {
    Portable::watertight(block, ray, t_min, t_max)
}

/// WebAssembly's four lanes.
impl Register for v128 {
    type Scalar = f32;
    const COUNT: usize = 4;
    #[inline(always)]
    fn splat(value: f32) -> Self {
        f32x4_splat(value)
    }
    #[inline(always)]
    fn from_slice(values: &[f32]) -> Self {
        // One 16-byte load (unaligned loads are allowed in WebAssembly); building the
        // vector lane by lane costs four loads and three lane replacements.
        unsafe { v128_load(values[..4].as_ptr().cast::<v128>()) }
    }
    #[inline(always)]
    fn write_to(self, out: &mut [f32]) {
        unsafe { v128_store(out[..4].as_mut_ptr().cast::<v128>(), self) }
    }
    #[inline(always)]
    fn add(self, other: Self) -> Self {
        f32x4_add(self, other)
    }
    #[inline(always)]
    fn sub(self, other: Self) -> Self {
        f32x4_sub(self, other)
    }
    #[inline(always)]
    fn mul(self, other: Self) -> Self {
        f32x4_mul(self, other)
    }
    #[inline(always)]
    fn div(self, other: Self) -> Self {
        f32x4_div(self, other)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Self {
        f32x4_lt(self, other)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Self {
        f32x4_gt(self, other)
    }
    #[inline(always)]
    fn le(self, other: Self) -> Self {
        f32x4_le(self, other)
    }
    #[inline(always)]
    fn ge(self, other: Self) -> Self {
        f32x4_ge(self, other)
    }
    #[inline(always)]
    fn ne(self, other: Self) -> Self {
        f32x4_ne(self, other)
    }
    #[inline(always)]
    fn or(self, other: Self) -> Self {
        v128_or(self, other)
    }
    #[inline(always)]
    fn and(self, other: Self) -> Self {
        v128_and(self, other)
    }
    #[inline(always)]
    fn and_not(self, other: Self) -> Self {
        // `v128_andnot(a, b)` is `a & !b`.
        v128_andnot(self, other)
    }
    #[inline(always)]
    fn select(self, other: Self, mask: Self) -> Self {
        v128_bitselect(self, other, mask)
    }
    #[inline(always)]
    fn later(self, other: Self) -> Self {
        // `pmax(a, b)` is `a < b ? b : a`: with `a = other`, `self > other ? self : other`.
        f32x4_pmax(other, self)
    }
    #[inline(always)]
    fn earlier(self, other: Self) -> Self {
        // `pmin(a, b)` is `b < a ? b : a`.
        f32x4_pmin(other, self)
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        u32::from(i32x4_bitmask(self))
    }
    #[inline(always)]
    fn from_bits(bits: u32) -> Self {
        let lanes = i32x4(1, 2, 4, 8);
        i32x4_eq(v128_and(i32x4_splat(bits as i32), lanes), lanes)
    }
}
