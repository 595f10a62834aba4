//! What a wide traversal does in lanes, as the kernels take it: a node's child boxes against
//! one ray, a block of four triangles, one box against a group of a packet's rays. The
//! portable code ([`Portable`]) is the reference; each instruction set's [`Kernel`] computes
//! the same, bit for bit, in its registers where the types are theirs (3D, f32 or f64) and
//! falls back to the reference elsewhere (2D, or widths that do not fill its lanes).
//!
//! The kernels see only arrays of one scalar, never a tree: a wide node's planes, a ray in
//! lanes, a triangle block, a packet's rays in lanes.

use std::marker::PhantomData;

use crate::math::{OverScalar, Real, Vector, Vector3};
use crate::primitive::{HitTest, TriangleBlock, TriangleRay};
use crate::ray::Ray;
use crate::slab::{SlabRay, earlier, later};

/// The boxes of a wide node's `W` children, `planes[side][axis][slot]` (side 0 the lower
/// planes, 1 the upper; 2D nodes leave the z rows unused): a
/// [`WideNode`](crate::bvh::WideNode)'s planes.
pub(crate) type Planes<S, const W: usize> = [[[S; W]; 3]; 2];

/// The most lanes a kernel's registers hold (eight f32 in AVX).
pub(crate) const MAX_LANES: usize = 8;

/// The most rays a packet holds (one bit each in a `u64` mask).
pub const MAX_PACKET: usize = 64;

/// Rays whose lanes are tested together: a group of eight.
pub(crate) const LANES: usize = 8;

/// A ray prepared for the child tests of wide nodes of `W` children, once per ray: where its
/// near and far planes lie in a node, and its origin, reciprocal direction and `t_min`
/// repeated in every lane.
///
/// The planes' places are, per axis, the index of the first of their `W` values in the node's
/// planes read as one flat run of `6W` (the lower rows, then the upper ones), so that a node's
/// test reads its planes at offsets it does not recompute (choosing them at every node took 3
/// instructions a row). The lanes are stored whole and read whole: read from the slab ray, the
/// compiler loaded its fields wider than they were written, a store-forwarding stall on every
/// ray (perf: 5 % of the time).
#[derive(Clone, Copy, Debug)]
pub(crate) struct NodeLanes<S: Real, const W: usize> {
    near: [usize; 3],
    far: [usize; 3],
    pub(crate) origin: [[S; MAX_LANES]; 3],
    pub(crate) inverse: [[S; MAX_LANES]; 3],
    pub(crate) t_min: [S; MAX_LANES],
    /// The slab ray's `far_scale` (1, or Ize's widening in robust mode).
    pub(crate) far_scale: S,
}

impl<S: Real, const W: usize> NodeLanes<S, W> {
    /// Prepares `slab`.
    #[inline(always)]
    pub(crate) fn new<V: Vector<Scalar = S>>(slab: &SlabRay<V>) -> Self {
        // (A 2D ray's z lanes hold zeros: only 3D nodes are tested in lanes.)
        let lanes = |vector: V, axis: usize| {
            [if axis < V::DIM { vector[axis] } else { S::ZERO }; MAX_LANES]
        };
        Self {
            near: std::array::from_fn(|axis| (slab.near_side(axis) * 3 + axis) * W),
            far: std::array::from_fn(|axis| (slab.far_side(axis) * 3 + axis) * W),
            origin: std::array::from_fn(|axis| lanes(slab.origin, axis)),
            inverse: std::array::from_fn(|axis| lanes(slab.inv_direction, axis)),
            t_min: [slab.t_min; MAX_LANES],
            far_scale: slab.far_scale,
        }
    }

    /// The near and far planes of a node's children on `axis`.
    #[inline(always)]
    pub(crate) fn planes<'a>(&self, planes: &'a Planes<S, W>, axis: usize) -> (&'a [S], &'a [S]) {
        let flat = planes.as_flattened().as_flattened();
        let (near, far) = (self.near[axis], self.far[axis]);
        debug_assert!(near + W <= flat.len() && far + W <= flat.len());
        // SAFETY: only `new` sets the offsets, each `(side·3 + axis)·W` with a side of 0 or 1
        // and an axis below 3, so each run of `W` ends within the `6W` values.
        unsafe {
            (
                flat.get_unchecked(near..near + W),
                flat.get_unchecked(far..far + W),
            )
        }
    }
}

/// The ray/box tests of one node's children: each slot's interval and which slots are hit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ChildTests<S: Real, const W: usize> {
    /// Where the ray enters each child's box (clipped to the ray's interval).
    pub(crate) t_enter: [S; W],
    /// Where it leaves.
    pub(crate) t_exit: [S; W],
    /// Bit `s` set when slot `s` is hit (`t_enter <= t_exit`).
    pub(crate) hit_mask: u32,
}

/// A packet's rays lane by lane, for testing one box, or one triangle, against many rays at
/// once.
#[derive(Clone, Debug)]
pub(crate) struct PacketLanes<S: Real> {
    pub(crate) origin: [[S; MAX_PACKET]; 3],
    /// For the triangle tests.
    pub(crate) direction: [[S; MAX_PACKET]; 3],
    pub(crate) inv_direction: [[S; MAX_PACKET]; 3],
    pub(crate) negative: [[bool; MAX_PACKET]; 3],
    pub(crate) t_min: [S; MAX_PACKET],
    /// Each ray's closest hit so far (its search interval's end).
    pub(crate) t_closest: [S; MAX_PACKET],
    pub(crate) far_scale: S,
}

impl<S: Real> Default for PacketLanes<S> {
    /// No rays: every lane's interval is empty (it ends at −∞).
    fn default() -> Self {
        Self {
            origin: [[S::ZERO; MAX_PACKET]; 3],
            direction: [[S::ZERO; MAX_PACKET]; 3],
            inv_direction: [[S::ZERO; MAX_PACKET]; 3],
            negative: [[false; MAX_PACKET]; 3],
            t_min: [S::ZERO; MAX_PACKET],
            t_closest: [S::NEG_INFINITY; MAX_PACKET],
            far_scale: S::ONE,
        }
    }
}

/// One box against a group of [`LANES`] rays of a packet: each ray's interval, clipped to its
/// search interval (`t_exit` below `t_enter` where it misses).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BoxAgainstRays<S: Real> {
    pub(crate) t_enter: [S; LANES],
    pub(crate) t_exit: [S; LANES],
    /// Bit `lane` set where the ray is active and `t_enter <= t_exit`.
    pub(crate) hits: u32,
    /// `t_enter` where a ray hits, `+∞` elsewhere.
    pub(crate) entries: [S; LANES],
}

/// What a wide traversal needs done in lanes. [`Portable`] is the reference; an instruction
/// set's kernels compute the same in its registers where the types are theirs.
pub(crate) trait Kernel {
    /// The slab test of every child of a node (`planes`, the first `dims` axes): each slot's
    /// interval clipped to `[t_min, t_max]`, and which slots are hit: the arithmetic of
    /// [`slab_clip_scalar`](crate::slab::slab_clip_scalar) lane by lane (the same planes,
    /// products and NaN-ignoring reductions), so each child's interval is the one the binary
    /// traversal computes for its box.
    fn test_children<S: Real, const W: usize>(
        planes: &Planes<S, W>,
        ray: &NodeLanes<S, W>,
        dims: usize,
        t_max: S,
    ) -> ChildTests<S, W>;

    /// Möller–Trumbore on the four triangles of `block`: each lane's `t` where it is hit
    /// within `[t_min, t_max]`, `NaN` where not, as [`TriangleBlock::intersect`] computes it.
    fn moller_trumbore<S: Real>(
        block: &TriangleBlock<S>,
        origin: S::Vec3,
        direction: S::Vec3,
        t_min: S,
        t_max: S,
    ) -> [S; 4];

    /// The watertight test on the four triangles of `block`, as
    /// [`TriangleBlock::intersect`] computes it.
    fn watertight<S: Real>(
        block: &TriangleBlock<S>,
        ray: &TriangleRay<S::Vec3>,
        t_min: S,
        t_max: S,
    ) -> [S; 4];

    /// The slab test of the box `lower`–`upper` (the first `dims` axes) against the rays
    /// `first..first + LANES` of a packet (those whose bits are set in `active` count as
    /// hits), as [`Portable`] computes it.
    fn box_against_rays<S: Real>(
        lanes: &PacketLanes<S>,
        lower: [S; 3],
        upper: [S; 3],
        first: usize,
        dims: usize,
        active: u32,
    ) -> BoxAgainstRays<S>;

    /// Möller–Trumbore on triangle `lane` of `block` against the rays `first..first + LANES`
    /// of a packet, each in its own interval (`t_min` to `t_closest`), as the one-triangle
    /// test computes it: the hit's `t`, `NaN` where there is none, and the rays hit as bits
    /// (bit `i` for ray `first + i`). The block kernel's test turned around: one triangle in
    /// every lane and a ray in each, for a packet's leaf.
    fn triangle_against_rays<S: Real>(
        block: &TriangleBlock<S>,
        lane: usize,
        lanes: &PacketLanes<S>,
        first: usize,
    ) -> ([S; LANES], u32);
}

/// The reference kernels: plain Rust, one lane at a time.
pub(crate) struct Portable;

impl Kernel for Portable {
    #[inline(always)]
    fn test_children<S: Real, const W: usize>(
        planes: &Planes<S, W>,
        ray: &NodeLanes<S, W>,
        dims: usize,
        t_max: S,
    ) -> ChildTests<S, W> {
        let mut t_enter = [ray.t_min[0]; W];
        let mut t_exit = [S::INFINITY; W];
        for axis in 0..dims {
            let (near, far) = ray.planes(planes, axis);
            let origin = ray.origin[axis][0];
            let inverse = ray.inverse[axis][0];
            for slot in 0..W {
                let t_near = (near[slot] - origin) * inverse;
                let t_far = (far[slot] - origin) * inverse;
                t_enter[slot] = later(t_enter[slot], t_near);
                t_exit[slot] = earlier(t_exit[slot], t_far);
            }
        }
        let mut hit_mask = 0;
        for slot in 0..W {
            t_exit[slot] = earlier(t_max, t_exit[slot] * ray.far_scale);
            hit_mask |= u32::from(t_enter[slot] <= t_exit[slot]) << slot;
        }
        ChildTests {
            t_enter,
            t_exit,
            hit_mask,
        }
    }

    #[inline(always)]
    fn moller_trumbore<S: Real>(
        block: &TriangleBlock<S>,
        origin: S::Vec3,
        direction: S::Vec3,
        t_min: S,
        t_max: S,
    ) -> [S; 4] {
        block.intersect(
            &TriangleRay::new(
                &Ray {
                    origin,
                    direction,
                    t_min,
                    t_max,
                },
                HitTest::Fast,
            ),
            t_min,
            t_max,
        )
    }

    #[inline(always)]
    fn watertight<S: Real>(
        block: &TriangleBlock<S>,
        ray: &TriangleRay<S::Vec3>,
        t_min: S,
        t_max: S,
    ) -> [S; 4] {
        block.intersect(ray, t_min, t_max)
    }

    /// Each ray's near plane is chosen by the sign of its direction, as the single-ray test
    /// chooses it, so each ray's interval is the one its single-ray traversal computes for
    /// that box.
    #[inline(always)]
    fn box_against_rays<S: Real>(
        lanes: &PacketLanes<S>,
        lower: [S; 3],
        upper: [S; 3],
        first: usize,
        dims: usize,
        active: u32,
    ) -> BoxAgainstRays<S> {
        let mut t_enter: [S; LANES] = std::array::from_fn(|lane| lanes.t_min[first + lane]);
        let mut t_exit = [S::INFINITY; LANES];
        for axis in 0..dims {
            for lane in 0..LANES {
                let ray = first + lane;
                let origin = lanes.origin[axis][ray];
                let inverse = lanes.inv_direction[axis][ray];
                let t_lower = (lower[axis] - origin) * inverse;
                let t_upper = (upper[axis] - origin) * inverse;
                let negative = lanes.negative[axis][ray];
                let t_near = if negative { t_upper } else { t_lower };
                let t_far = if negative { t_lower } else { t_upper };
                t_enter[lane] = later(t_enter[lane], t_near);
                t_exit[lane] = earlier(t_exit[lane], t_far);
            }
        }
        let mut hits = 0;
        let mut entries = [S::INFINITY; LANES];
        for lane in 0..LANES {
            t_exit[lane] = earlier(
                lanes.t_closest[first + lane],
                t_exit[lane] * lanes.far_scale,
            );
            let hit = t_enter[lane] <= t_exit[lane] && (active >> lane) & 1 != 0;
            hits |= u32::from(hit) << lane;
            if hit {
                entries[lane] = t_enter[lane];
            }
        }
        BoxAgainstRays {
            t_enter,
            t_exit,
            hits,
            entries,
        }
    }

    #[inline(always)]
    fn triangle_against_rays<S: Real>(
        block: &TriangleBlock<S>,
        lane: usize,
        lanes: &PacketLanes<S>,
        first: usize,
    ) -> ([S; LANES], u32) {
        let t_hits: [S; LANES] = std::array::from_fn(|index| {
            let ray = first + index;
            let vector = |rows: &[[S; MAX_PACKET]; 3]| {
                <S::Vec3 as Vector3>::new(rows[0][ray], rows[1][ray], rows[2][ray])
            };
            let (t_min, t_max) = (lanes.t_min[ray], lanes.t_closest[ray]);
            let ray = Ray {
                origin: vector(&lanes.origin),
                direction: vector(&lanes.direction),
                t_min,
                t_max,
            };
            block
                .intersect_lane(&TriangleRay::new(&ray, HitTest::Fast), lane, t_min, t_max)
                .unwrap_or(S::NAN)
        });
        let mut hits = 0;
        for (index, t) in t_hits.iter().enumerate() {
            hits |= u32::from(!t.is_nan()) << index;
        }
        (t_hits, hits)
    }
}

/// Asks the processor to bring the `LINES` 64-byte lines from `address` on into its caches,
/// without waiting for them (x86-64's `prefetcht0`; nothing elsewhere). A hint only: it reads
/// nothing the program sees and never faults, so any address is sound.
#[inline(always)]
pub(crate) fn prefetch_lines<const LINES: usize>(address: *const u8) {
    #[cfg(target_arch = "x86_64")]
    for line in 0..LINES {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: a prefetch changes nothing but the caches (SSE, which every x86-64 processor
        // has); `wrapping_add` makes no claim on the address.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(address.wrapping_add(64 * line).cast::<i8>()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = address;
}

/// The arguments and results the kernels hand between the precisions
/// ([`Real::by_precision`]), each named by a type over the scalar.
pub(crate) struct ChildrenArgs<'a, const W: usize>(PhantomData<&'a ()>);
impl<'a, const W: usize> OverScalar for ChildrenArgs<'a, W> {
    type Of<S: Real> = (&'a Planes<S, W>, &'a NodeLanes<S, W>, S);
}
/// See [`ChildrenArgs`].
pub(crate) struct ChildTestsOf<const W: usize>;
impl<const W: usize> OverScalar for ChildTestsOf<W> {
    type Of<S: Real> = ChildTests<S, W>;
}
/// See [`ChildrenArgs`].
pub(crate) struct MollerTrumboreArgs<'a>(PhantomData<&'a ()>);
impl<'a> OverScalar for MollerTrumboreArgs<'a> {
    type Of<S: Real> = (&'a TriangleBlock<S>, S::Vec3, S::Vec3, S, S);
}
/// See [`ChildrenArgs`].
pub(crate) struct WatertightArgs<'a>(PhantomData<&'a ()>);
impl<'a> OverScalar for WatertightArgs<'a> {
    type Of<S: Real> = (&'a TriangleBlock<S>, &'a TriangleRay<S::Vec3>, S, S);
}
/// See [`ChildrenArgs`].
pub(crate) struct FourHits;
impl OverScalar for FourHits {
    type Of<S: Real> = [S; 4];
}
/// See [`ChildrenArgs`].
pub(crate) struct BoxArgs<'a>(PhantomData<&'a ()>);
impl<'a> OverScalar for BoxArgs<'a> {
    type Of<S: Real> = (&'a PacketLanes<S>, [S; 3], [S; 3]);
}
/// See [`ChildrenArgs`].
pub(crate) struct TriangleRaysArgs<'a>(PhantomData<&'a ()>);
impl<'a> OverScalar for TriangleRaysArgs<'a> {
    type Of<S: Real> = (&'a TriangleBlock<S>, &'a PacketLanes<S>);
}
/// See [`ChildrenArgs`].
pub(crate) struct LaneHits;
impl OverScalar for LaneHits {
    type Of<S: Real> = ([S; LANES], u32);
}
/// See [`ChildrenArgs`].
pub(crate) struct BoxAgainstRaysOf;
impl OverScalar for BoxAgainstRaysOf {
    type Of<S: Real> = BoxAgainstRays<S>;
}

/// An instruction set's [`Kernel`]: the functions of that set for 3D f32 and f64 (the child
/// test for any multiple of four children), chosen by precision, and the portable code for
/// everything else (2D, other widths).
macro_rules! impl_kernel {
    (
        $name:ident,
        $children:ident,
        $children64:ident,
        $moller_trumbore:ident,
        $moller_trumbore64:ident,
        $watertight:ident,
        $watertight64:ident,
        $box_against_rays:ident,
        $box_against_rays64:ident,
        $triangle_against_rays:ident,
        $triangle_against_rays64:ident
    ) => {
        // SAFETY, for every call of the set's functions below: a kernel runs only when
        // `Isa::active` says the machine has its instruction set (see `run_on`).
        // (WebAssembly's are safe: the module is compiled for its set.)
        impl $crate::simd::kernel::Kernel for $name {
            #[inline(always)]
            fn test_children<S: $crate::math::Real, const W: usize>(
                planes: &$crate::simd::kernel::Planes<S, W>,
                ray: &$crate::simd::kernel::NodeLanes<S, W>,
                dims: usize,
                t_max: S,
            ) -> $crate::simd::kernel::ChildTests<S, W> {
                use $crate::simd::kernel::{ChildTestsOf, ChildrenArgs, Portable};
                if dims != 3 || W % 4 != 0 {
                    return Portable::test_children(planes, ray, dims, t_max);
                }
                #[allow(unused_unsafe)]
                let tests = S::by_precision::<ChildrenArgs<'_, W>, ChildTestsOf<W>>(
                    (planes, ray, t_max),
                    |(planes, ray, t_max)| unsafe { $children::<W>(planes, ray, t_max) },
                    |(planes, ray, t_max)| unsafe { $children64::<W>(planes, ray, t_max) },
                );
                tests
            }

            #[inline(always)]
            fn moller_trumbore<S: $crate::math::Real>(
                block: &$crate::primitive::TriangleBlock<S>,
                origin: S::Vec3,
                direction: S::Vec3,
                t_min: S,
                t_max: S,
            ) -> [S; 4] {
                use $crate::simd::kernel::{FourHits, MollerTrumboreArgs};
                #[allow(unused_unsafe)]
                let t_hits = S::by_precision::<MollerTrumboreArgs<'_>, FourHits>(
                    (block, origin, direction, t_min, t_max),
                    |(block, origin, direction, t_min, t_max)| unsafe {
                        $moller_trumbore(block, origin, direction, t_min, t_max)
                    },
                    |(block, origin, direction, t_min, t_max)| unsafe {
                        $moller_trumbore64(block, origin, direction, t_min, t_max)
                    },
                );
                t_hits
            }

            #[inline(always)]
            fn watertight<S: $crate::math::Real>(
                block: &$crate::primitive::TriangleBlock<S>,
                ray: &$crate::primitive::TriangleRay<S::Vec3>,
                t_min: S,
                t_max: S,
            ) -> [S; 4] {
                use $crate::simd::kernel::{FourHits, WatertightArgs};
                #[allow(unused_unsafe)]
                let t_hits = S::by_precision::<WatertightArgs<'_>, FourHits>(
                    (block, ray, t_min, t_max),
                    |(block, ray, t_min, t_max)| unsafe { $watertight(block, ray, t_min, t_max) },
                    |(block, ray, t_min, t_max)| unsafe { $watertight64(block, ray, t_min, t_max) },
                );
                t_hits
            }

            #[inline(always)]
            fn box_against_rays<S: $crate::math::Real>(
                lanes: &$crate::simd::kernel::PacketLanes<S>,
                lower: [S; 3],
                upper: [S; 3],
                first: usize,
                dims: usize,
                active: u32,
            ) -> $crate::simd::kernel::BoxAgainstRays<S> {
                use $crate::simd::kernel::{BoxAgainstRaysOf, BoxArgs};
                #[allow(unused_unsafe)]
                let tests = S::by_precision::<BoxArgs<'_>, BoxAgainstRaysOf>(
                    (lanes, lower, upper),
                    |(lanes, lower, upper)| unsafe {
                        $box_against_rays(lanes, lower, upper, first, dims, active)
                    },
                    |(lanes, lower, upper)| unsafe {
                        $box_against_rays64(lanes, lower, upper, first, dims, active)
                    },
                );
                tests
            }

            #[inline(always)]
            fn triangle_against_rays<S: $crate::math::Real>(
                block: &$crate::primitive::TriangleBlock<S>,
                lane: usize,
                lanes: &$crate::simd::kernel::PacketLanes<S>,
                first: usize,
            ) -> ([S; $crate::simd::kernel::LANES], u32) {
                use $crate::simd::kernel::{LaneHits, TriangleRaysArgs};
                #[allow(unused_unsafe)]
                let t_hits = S::by_precision::<TriangleRaysArgs<'_>, LaneHits>(
                    (block, lanes),
                    |(block, lanes)| unsafe { $triangle_against_rays(block, lane, lanes, first) },
                    |(block, lanes)| unsafe { $triangle_against_rays64(block, lane, lanes, first) },
                );
                t_hits
            }
        }
    };
}
pub(crate) use impl_kernel;
