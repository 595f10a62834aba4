//! The SIMD kernels of the wide BVH's hot path, chosen at run time: the one module of the core
//! allowed `unsafe`.
//!
//! One binary runs on any x86-64 machine: [`Isa::detect`] asks the processor once which
//! instruction sets it has, and the wide traversal is compiled once per set (a
//! `#[target_feature]` copy of the same generic code, so the kernels inline into the loop).
//! `unsafe` is needed for three things only, all here:
//! - calling a `#[target_feature]` function, which is sound only on a processor that has the
//!   feature: every such call is behind [`Isa::active`], which only ever holds a detected set;
//! - loading and storing SIMD registers through pointers, each into a slice indexed first (so
//!   the lanes loaded are inside it); and x86 intrinsics outside `#[target_feature]`
//!   functions, in the lanes below, which run only inside such functions;
//! - the prefetch hint (`prefetch_lines`), which never faults whatever its address.
//!
//! Every kernel does the arithmetic of the portable code (`Portable`) in the same order, with
//! the same NaN rules (`max_ps(a, b)` is `a > b ? a : b`, which ignores a NaN `a`, like the
//! slab module's reductions), and no fused multiply-adds, so its results are bit for bit the
//! portable ones; the tests below hold every kernel to that on random and extreme inputs.
//!
//! In the browser the kernels are WebAssembly `simd128`, chosen when the module is compiled
//! (WebAssembly has no run-time detection; every browser of the last years has it).

#![allow(unsafe_code)]

use std::sync::atomic::{AtomicU8, Ordering};

use glam::{DVec3, Vec3};

use crate::bvh::wide_traverse::{
    BoxAgainstRays, LANES, PacketLanes, traverse_packet_with, traverse_wide_with,
};
use crate::bvh::{ChildTests, PacketStack, WideBvh, WideNode, WideStack};
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::{HitTest, LeafPrimitives, TriangleBlock, TriangleRay};
use crate::query::{Hit, TraceOptions};
use crate::ray::Ray;
use crate::slab::SlabRay;

/// An instruction set the kernels are written for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Isa {
    /// Plain Rust, one lane at a time (what the compiler makes of it): every machine.
    Portable,
    /// x86-64 with AVX2 and FMA (Intel since 2013, AMD since 2015): 8 lanes of f32.
    Avx2,
    /// x86-64 with AVX-512 F and VL: the AVX2 kernels compiled with AVX-512 enabled (its
    /// mask registers where the compiler uses them).
    Avx512,
    /// WebAssembly `simd128`: 4 lanes, fixed when the module is compiled.
    Simd128,
}

impl Isa {
    /// Every instruction set, in order of preference (best last).
    pub const ALL: [Isa; 4] = [Isa::Portable, Isa::Simd128, Isa::Avx2, Isa::Avx512];

    /// The name the CLI takes: `portable`, `avx2`, `avx512`, `simd128`.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Portable => "portable",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
            Isa::Simd128 => "simd128",
        }
    }

    /// The set named `name`.
    pub fn parse(name: &str) -> Option<Isa> {
        Isa::ALL.into_iter().find(|isa| isa.name() == name)
    }

    /// Whether this machine (or this WebAssembly module) can run the set.
    pub fn is_available(self) -> bool {
        match self {
            Isa::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => {
                Isa::Avx2.is_available()
                    && std::arch::is_x86_feature_detected!("avx512f")
                    && std::arch::is_x86_feature_detected!("avx512vl")
            }
            #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
            Isa::Simd128 => true,
            _ => false,
        }
    }

    /// The best set this machine has.
    pub fn detect() -> Isa {
        Isa::ALL
            .into_iter()
            .rev()
            .find(|isa| isa.is_available())
            .unwrap_or(Isa::Portable)
    }

    fn code(self) -> u8 {
        match self {
            Isa::Portable => 1,
            Isa::Avx2 => 2,
            Isa::Avx512 => 3,
            Isa::Simd128 => 4,
        }
    }

    /// The set traversal uses: the best one detected, unless [`Isa::set_active`] chose another.
    #[inline]
    pub fn active() -> Isa {
        match ACTIVE.load(Ordering::Relaxed) {
            1 => Isa::Portable,
            2 => Isa::Avx2,
            3 => Isa::Avx512,
            4 => Isa::Simd128,
            _ => {
                let detected = Isa::detect();
                ACTIVE.store(detected.code(), Ordering::Relaxed);
                detected
            }
        }
    }

    /// Makes traversal use `isa` from now on (to measure one set against another, or test
    /// one); refused for a set this machine cannot run.
    pub fn set_active(isa: Isa) -> Result<(), IsaError> {
        if !isa.is_available() {
            return Err(IsaError::Unavailable {
                isa,
                detected: Isa::detect(),
            });
        }
        ACTIVE.store(isa.code(), Ordering::Relaxed);
        Ok(())
    }
}

/// The instruction set in use: 0 until first asked.
static ACTIVE: AtomicU8 = AtomicU8::new(0);

/// An instruction set this machine does not have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum IsaError {
    /// Asked for a set the processor lacks.
    #[error("this machine cannot run {} kernels (the best it has is {})", isa.name(), detected.name())]
    Unavailable {
        /// What was asked for.
        isa: Isa,
        /// The best it has.
        detected: Isa,
    },
}

/// [`traverse_wide`](crate::bvh::traverse_wide) with the kernels of the active instruction
/// set.
#[inline]
pub(crate) fn traverse_wide<V, P, O, const W: usize>(
    tree: &WideBvh<V, W>,
    primitives: &P,
    ray: &Ray<V>,
    options: &TraceOptions,
    stack: &mut WideStack<V::Scalar>,
    observer: &mut O,
) -> Option<Hit<V::Scalar>>
where
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    #[cfg(target_arch = "x86_64")]
    match Isa::active() {
        // SAFETY: `Isa::active` holds only an instruction set this machine has.
        Isa::Avx512 => {
            return unsafe {
                x86::traverse_avx512(tree, primitives, ray, options, stack, observer)
            };
        }
        // SAFETY: as above.
        Isa::Avx2 => {
            return unsafe { x86::traverse_avx2(tree, primitives, ray, options, stack, observer) };
        }
        _ => {}
    }
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    if Isa::active() == Isa::Simd128 {
        return traverse_wide_with::<wasm::Simd128, V, P, O, W>(
            tree, primitives, ray, options, stack, observer,
        );
    }
    traverse_wide_with::<Portable, V, P, O, W>(tree, primitives, ray, options, stack, observer)
}

/// [`traverse_packet`](crate::bvh::traverse_packet) with the kernels of the active
/// instruction set.
#[inline]
pub(crate) fn traverse_packet<V, P, O, const W: usize>(
    tree: &WideBvh<V, W>,
    primitives: &P,
    rays: &[Ray<V>],
    options: &TraceOptions,
    stack: &mut PacketStack<V::Scalar>,
    observers: &mut [O],
    hits: &mut [Option<Hit<V::Scalar>>],
) where
    V: Vector,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    #[cfg(target_arch = "x86_64")]
    match Isa::active() {
        // SAFETY: `Isa::active` holds only an instruction set this machine has.
        Isa::Avx512 => {
            return unsafe {
                x86::packet_avx512(tree, primitives, rays, options, stack, observers, hits)
            };
        }
        // SAFETY: as above.
        Isa::Avx2 => {
            return unsafe {
                x86::packet_avx2(tree, primitives, rays, options, stack, observers, hits)
            };
        }
        _ => {}
    }
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    if Isa::active() == Isa::Simd128 {
        return traverse_packet_with::<wasm::Simd128, V, P, O, W>(
            tree, primitives, rays, options, stack, observers, hits,
        );
    }
    traverse_packet_with::<Portable, V, P, O, W>(
        tree, primitives, rays, options, stack, observers, hits,
    )
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

/// What a wide traversal needs done in lanes: a node's child boxes, a block of triangles.
/// Implemented by [`Portable`] for every vector type, and by the SIMD kernels for 3D f32 (other
/// types fall back to the portable code inside them).
pub(crate) trait Kernel {
    /// The slab test of every child of `node`, as
    /// [`test_children`](crate::bvh::test_children) computes it.
    fn test_children<V: Vector, const W: usize>(
        node: &WideNode<V::Scalar, W>,
        ray: &NodeRay<V, W>,
        t_max: V::Scalar,
    ) -> ChildTests<V::Scalar, W>;

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

    /// One box against a group of a packet's rays, as
    /// [`PacketLanes::box_against_rays`] computes it.
    fn box_against_rays<S: Real>(
        lanes: &PacketLanes<S>,
        lower: [S; 3],
        upper: [S; 3],
        first: usize,
        dims: usize,
        active: u32,
    ) -> BoxAgainstRays<S>;
}

/// The most lanes a kernel's registers hold (eight f32 in AVX).
const MAX_LANES: usize = 8;

/// A ray prepared for the child tests of wide nodes of `W` children, once per ray: the slab
/// ray, where its near and far planes lie in a node, and its origin, reciprocal direction and
/// `t_min` repeated in every lane.
///
/// The planes' places are, per axis, the index of the first of their `W` values in the node's
/// planes read as one flat run of `6W` (the lower rows, then the upper ones), so that a node's
/// test reads its planes at offsets it does not recompute (choosing them at every node took 3
/// instructions a row). The lanes are stored whole and read whole: read from the slab ray, the
/// compiler loaded its fields wider than they were written, a store-forwarding stall on every
/// ray (perf: 5 % of the time).
#[derive(Clone, Copy, Debug)]
pub(crate) struct NodeRay<V: Vector, const W: usize> {
    pub(crate) slab: SlabRay<V>,
    near: [usize; 3],
    far: [usize; 3],
    origin: [[V::Scalar; MAX_LANES]; 3],
    inverse: [[V::Scalar; MAX_LANES]; 3],
    t_min: [V::Scalar; MAX_LANES],
}

impl<V: Vector, const W: usize> NodeRay<V, W> {
    /// Prepares `slab`.
    #[inline(always)]
    pub(crate) fn new(slab: SlabRay<V>) -> Self {
        // (A 2D ray's z lanes hold zeros: only 3D nodes are tested in lanes.)
        let lanes = |vector: V, axis: usize| {
            [if axis < V::DIM {
                vector[axis]
            } else {
                V::Scalar::ZERO
            }; MAX_LANES]
        };
        Self {
            near: std::array::from_fn(|axis| (slab.near_side(axis) * 3 + axis) * W),
            far: std::array::from_fn(|axis| (slab.far_side(axis) * 3 + axis) * W),
            origin: std::array::from_fn(|axis| lanes(slab.origin, axis)),
            inverse: std::array::from_fn(|axis| lanes(slab.inv_direction, axis)),
            t_min: [slab.t_min; MAX_LANES],
            slab,
        }
    }

    /// The near and far planes of `node`'s children on `axis`.
    #[inline(always)]
    fn planes<'a>(
        &self,
        node: &'a WideNode<V::Scalar, W>,
        axis: usize,
    ) -> (&'a [V::Scalar], &'a [V::Scalar]) {
        let flat = node.planes.as_flattened().as_flattened();
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

/// The reference kernels: plain Rust.
pub(crate) struct Portable;

impl Kernel for Portable {
    #[inline(always)]
    fn test_children<V: Vector, const W: usize>(
        node: &WideNode<V::Scalar, W>,
        ray: &NodeRay<V, W>,
        t_max: V::Scalar,
    ) -> ChildTests<V::Scalar, W> {
        crate::bvh::test_children(node, &ray.slab, t_max)
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

    #[inline(always)]
    fn box_against_rays<S: Real>(
        lanes: &PacketLanes<S>,
        lower: [S; 3],
        upper: [S; 3],
        first: usize,
        dims: usize,
        active: u32,
    ) -> BoxAgainstRays<S> {
        lanes.box_against_rays(lower, upper, first, dims, active)
    }
}

/// The same generic code with the kernels of one instruction set where the types are theirs:
/// the slab test of a 3D node (`$children` for f32, `$children64` for f64, any multiple of
/// four children), a triangle block's Möller–Trumbore and watertight tests, and one box against
/// a packet's rays, each in f32 and f64. Other vector types and widths take the portable path
/// (the type tests are resolved when the code is compiled). The downcasts are written out in
/// each method: folding them into shared helpers made the compiler emit 2–4 % more
/// instructions in the traversals (callgrind).
macro_rules! kernel {
    (
        $name:ident,
        $children:ident,
        $children64:ident,
        $moller_trumbore:ident,
        $moller_trumbore64:ident,
        $watertight:ident,
        $watertight64:ident,
        $box_against_rays:ident,
        $box_against_rays64:ident
    ) => {
        impl Kernel for $name {
            #[inline(always)]
            fn test_children<V: Vector, const W: usize>(
                node: &WideNode<V::Scalar, W>,
                ray: &NodeRay<V, W>,
                t_max: V::Scalar,
            ) -> ChildTests<V::Scalar, W> {
                use std::any::Any;
                // SAFETY (both blocks): this kernel runs only when `Isa::active` says the
                // machine has its instruction set (see `traverse_wide`). (WebAssembly's kernels
                // are safe: the module is compiled for its set.)
                #[allow(unused_unsafe)]
                if W % 4 == 0
                    && let (Some(node), Some(ray), Some(&t_max)) = (
                        (node as &dyn Any).downcast_ref::<WideNode<f32, W>>(),
                        (ray as &dyn Any).downcast_ref::<NodeRay<Vec3, W>>(),
                        (&t_max as &dyn Any).downcast_ref::<f32>(),
                    )
                {
                    let tests = unsafe { $children::<W>(node, ray, t_max) };
                    if let Some(&tests) =
                        (&tests as &dyn Any).downcast_ref::<ChildTests<V::Scalar, W>>()
                    {
                        return tests;
                    }
                }
                #[allow(unused_unsafe)]
                if W % 4 == 0
                    && let (Some(node), Some(ray), Some(&t_max)) = (
                        (node as &dyn Any).downcast_ref::<WideNode<f64, W>>(),
                        (ray as &dyn Any).downcast_ref::<NodeRay<DVec3, W>>(),
                        (&t_max as &dyn Any).downcast_ref::<f64>(),
                    )
                {
                    let tests = unsafe { $children64::<W>(node, ray, t_max) };
                    if let Some(&tests) =
                        (&tests as &dyn Any).downcast_ref::<ChildTests<V::Scalar, W>>()
                    {
                        return tests;
                    }
                }
                Portable::test_children(node, ray, t_max)
            }

            #[inline(always)]
            fn moller_trumbore<S: Real>(
                block: &TriangleBlock<S>,
                origin: S::Vec3,
                direction: S::Vec3,
                t_min: S,
                t_max: S,
            ) -> [S; 4] {
                // SAFETY (both calls): as above.
                #[allow(unused_unsafe)]
                if let Some((block, [origin, direction], [t_min, t_max])) =
                    in_scalar(block, [origin, direction], [t_min, t_max])
                {
                    let t_hits =
                        unsafe { $moller_trumbore(block, origin, direction, t_min, t_max) };
                    return same_type(t_hits).unwrap_or_else(|| unreachable!());
                }
                #[allow(unused_unsafe)]
                if let Some((block, [origin, direction], [t_min, t_max])) =
                    in_scalar(block, [origin, direction], [t_min, t_max])
                {
                    let t_hits =
                        unsafe { $moller_trumbore64(block, origin, direction, t_min, t_max) };
                    return same_type(t_hits).unwrap_or_else(|| unreachable!());
                }
                Portable::moller_trumbore(block, origin, direction, t_min, t_max)
            }

            #[inline(always)]
            fn watertight<S: Real>(
                block: &TriangleBlock<S>,
                ray: &TriangleRay<S::Vec3>,
                t_min: S,
                t_max: S,
            ) -> [S; 4] {
                // SAFETY (both calls): as above.
                #[allow(unused_unsafe)]
                if let Some((block, [ray], [t_min, t_max])) =
                    in_scalar(block, [*ray], [t_min, t_max])
                {
                    let t_hits = unsafe { $watertight(block, &ray, t_min, t_max) };
                    return same_type(t_hits).unwrap_or_else(|| unreachable!());
                }
                #[allow(unused_unsafe)]
                if let Some((block, [ray], [t_min, t_max])) =
                    in_scalar(block, [*ray], [t_min, t_max])
                {
                    let t_hits = unsafe { $watertight64(block, &ray, t_min, t_max) };
                    return same_type(t_hits).unwrap_or_else(|| unreachable!());
                }
                Portable::watertight(block, ray, t_min, t_max)
            }

            #[inline(always)]
            fn box_against_rays<S: Real>(
                lanes: &PacketLanes<S>,
                lower: [S; 3],
                upper: [S; 3],
                first: usize,
                dims: usize,
                active: u32,
            ) -> BoxAgainstRays<S> {
                use std::any::Any;
                // SAFETY (both calls): as above.
                #[allow(unused_unsafe)]
                if let (Some(lanes), Some(&lower), Some(&upper)) = (
                    (lanes as &dyn Any).downcast_ref::<PacketLanes<f32>>(),
                    (&lower as &dyn Any).downcast_ref::<[f32; 3]>(),
                    (&upper as &dyn Any).downcast_ref::<[f32; 3]>(),
                ) {
                    let tests =
                        unsafe { $box_against_rays(lanes, lower, upper, first, dims, active) };
                    return same_type(tests).unwrap_or_else(|| unreachable!());
                }
                #[allow(unused_unsafe)]
                if let (Some(lanes), Some(&lower), Some(&upper)) = (
                    (lanes as &dyn Any).downcast_ref::<PacketLanes<f64>>(),
                    (&lower as &dyn Any).downcast_ref::<[f64; 3]>(),
                    (&upper as &dyn Any).downcast_ref::<[f64; 3]>(),
                ) {
                    let tests =
                        unsafe { $box_against_rays64(lanes, lower, upper, first, dims, active) };
                    return same_type(tests).unwrap_or_else(|| unreachable!());
                }
                Portable::box_against_rays(lanes, lower, upper, first, dims, active)
            }
        }
    };
}

/// A triangle block, ray data and scalars of scalar `S` seen as the types of scalar `T`, when
/// `S` is `T` (the type tests are resolved when the code is compiled); `None` otherwise.
#[inline(always)]
fn in_scalar<S: Real, T: Real, R: 'static, U: 'static + Copy, const N: usize>(
    block: &TriangleBlock<S>,
    rays: [R; N],
    scalars: [S; 2],
) -> Option<(&TriangleBlock<T>, [U; N], [T; 2])> {
    use std::any::Any;
    let block = (block as &dyn Any).downcast_ref::<TriangleBlock<T>>()?;
    let rays = *(&rays as &dyn Any).downcast_ref::<[U; N]>()?;
    let scalars = *(&scalars as &dyn Any).downcast_ref::<[T; 2]>()?;
    Some((block, rays, scalars))
}

/// `value` as type `U`, when it is one (resolved when the code is compiled).
#[inline(always)]
fn same_type<T: 'static, U: 'static + Copy>(value: T) -> Option<U> {
    (&value as &dyn std::any::Any).downcast_ref::<U>().copied()
}

/// Lanes of f32 or f64 and the operations the kernels need: one slab test of a node's
/// children ([`children_in_lanes`]), one Möller–Trumbore ([`moller_trumbore4`]) and one
/// watertight test ([`watertight4`]) serve every instruction set's registers. Masks are lanes of all ones or all zeros. An implementation
/// executes its instruction set's instructions: its methods run only inside the kernels below,
/// which run only after [`Isa::active`] named that set.
trait Lanes: Copy {
    /// What a lane holds.
    type Scalar: Real;
    /// How many lanes.
    const COUNT: usize;
    fn splat(value: Self::Scalar) -> Self;
    /// The first `COUNT` values of `values`.
    fn from_slice(values: &[Self::Scalar]) -> Self;
    /// Writes the lanes to the first `COUNT` places of `out`.
    fn write_to(self, out: &mut [Self::Scalar]);
    fn add(self, other: Self) -> Self;
    fn sub(self, other: Self) -> Self;
    fn mul(self, other: Self) -> Self;
    fn div(self, other: Self) -> Self;
    fn lt(self, other: Self) -> Self;
    fn gt(self, other: Self) -> Self;
    fn le(self, other: Self) -> Self;
    fn ge(self, other: Self) -> Self;
    fn ne(self, other: Self) -> Self;
    fn or(self, other: Self) -> Self;
    fn and(self, other: Self) -> Self;
    /// `self & !other`.
    fn and_not(self, other: Self) -> Self;
    /// `mask ? self : other`, lane by lane.
    fn select(self, other: Self, mask: Self) -> Self;
    /// `self > other ? self : other`: a NaN `self` gives `other` (the slab module's rule).
    fn later(self, other: Self) -> Self;
    /// `self < other ? self : other`: a NaN `self` gives `other`.
    fn earlier(self, other: Self) -> Self;
    /// A mask's lanes as bits, lane 0 lowest.
    fn bits(self) -> u32;
    /// The mask whose lane `i` is set where bit `i` of `bits` is (the inverse of `bits`).
    fn from_bits(bits: u32) -> Self;
}

/// The slab test of every child of `node`, `L::COUNT` children at a time: the arithmetic of
/// [`test_children`](crate::bvh::test_children) (the same planes, products and NaN-ignoring
/// reductions), so the same intervals bit for bit.
#[inline(always)]
fn children_in_lanes<L: Lanes, const W: usize>(
    node: &WideNode<L::Scalar, W>,
    ray: &NodeRay<<L::Scalar as Real>::Vec3, W>,
    t_max: L::Scalar,
) -> ChildTests<L::Scalar, W> {
    let mut tests = ChildTests {
        t_enter: [L::Scalar::ZERO; W],
        t_exit: [L::Scalar::ZERO; W],
        hit_mask: 0,
    };
    for first in (0..W).step_by(L::COUNT) {
        let mut t_enter = L::from_slice(&ray.t_min);
        let mut t_exit = L::splat(L::Scalar::INFINITY);
        for axis in 0..3 {
            // The near and far planes for this ray, chosen by the sign of its direction
            // (Williams et al. 2005), at offsets found once per ray.
            let (near, far) = ray.planes(node, axis);
            let origin = L::from_slice(&ray.origin[axis]);
            let inverse = L::from_slice(&ray.inverse[axis]);
            let t_near = L::from_slice(&near[first..]).sub(origin).mul(inverse);
            let t_far = L::from_slice(&far[first..]).sub(origin).mul(inverse);
            t_enter = t_near.later(t_enter);
            t_exit = t_far.earlier(t_exit);
        }
        // The fast mode's scale is 1, and multiplying by 1 changes nothing: it is skipped,
        // to keep a multiplication off the path from a node's planes to its next node.
        let far_scale = ray.slab.far_scale;
        let t_exit = if far_scale == L::Scalar::ONE {
            t_exit
        } else {
            t_exit.mul(L::splat(far_scale))
        };
        let t_exit = t_exit.earlier(L::splat(t_max));
        tests.hit_mask |= t_enter.le(t_exit).bits() << first;
        t_enter.write_to(&mut tests.t_enter[first..]);
        t_exit.write_to(&mut tests.t_exit[first..]);
    }
    tests
}

/// Möller–Trumbore on the four triangles of `block` in lanes: the portable code's products
/// and sums in its order (glam's cross and dot, the edges taken from the corners as it takes
/// them), so the same `t`, and its rejections written as it writes them (a NaN `u` or `v` is
/// rejected only through `t`). `NaN` where no hit. `L` has four lanes.
#[inline(always)]
fn moller_trumbore4<L: Lanes>(
    block: &TriangleBlock<L::Scalar>,
    origin: <L::Scalar as Real>::Vec3,
    direction: <L::Scalar as Real>::Vec3,
    t_min: L::Scalar,
    t_max: L::Scalar,
) -> [L::Scalar; 4] {
    // (Plain loads: `array::map` here is not always inlined.)
    let [v0, v1, v2] = &block.corners;
    let (v0x, v0y, v0z) = (
        L::from_slice(&v0[0]),
        L::from_slice(&v0[1]),
        L::from_slice(&v0[2]),
    );
    let e1x = L::from_slice(&v1[0]).sub(v0x);
    let e1y = L::from_slice(&v1[1]).sub(v0y);
    let e1z = L::from_slice(&v1[2]).sub(v0z);
    let e2x = L::from_slice(&v2[0]).sub(v0x);
    let e2y = L::from_slice(&v2[1]).sub(v0y);
    let e2z = L::from_slice(&v2[2]).sub(v0z);
    let (dx, dy, dz) = (
        L::splat(direction[0]),
        L::splat(direction[1]),
        L::splat(direction[2]),
    );
    // p = d × e2
    let px = dy.mul(e2z).sub(e2y.mul(dz));
    let py = dz.mul(e2x).sub(e2z.mul(dx));
    let pz = dx.mul(e2y).sub(e2x.mul(dy));
    let det = e1x.mul(px).add(e1y.mul(py)).add(e1z.mul(pz));
    let (zero, one) = (L::splat(L::Scalar::ZERO), L::splat(L::Scalar::ONE));
    let inv_det = one.div(det);
    let sx = L::splat(origin[0]).sub(v0x);
    let sy = L::splat(origin[1]).sub(v0y);
    let sz = L::splat(origin[2]).sub(v0z);
    let u = sx.mul(px).add(sy.mul(py)).add(sz.mul(pz)).mul(inv_det);
    // q = s × e1
    let qx = sy.mul(e1z).sub(e1y.mul(sz));
    let qy = sz.mul(e1x).sub(e1z.mul(sx));
    let qz = sx.mul(e1y).sub(e1x.mul(sy));
    let v = dx.mul(qx).add(dy.mul(qy)).add(dz.mul(qz)).mul(inv_det);
    let t = e2x.mul(qx).add(e2y.mul(qy)).add(e2z.mul(qz)).mul(inv_det);
    let rejected = u.lt(zero).or(u.gt(one)).or(v.lt(zero).or(u.add(v).gt(one)));
    let accepted = det
        .ne(zero)
        .and(t.ge(L::splat(t_min)).and(t.le(L::splat(t_max))));
    let mut out = [L::Scalar::NAN; 4];
    t.select(L::splat(L::Scalar::NAN), accepted.and_not(rejected))
        .write_to(&mut out);
    out
}

/// Woop, Benthin & Wald's watertight test (see the one-triangle `watertight` in
/// `primitive::triangle`) on the four triangles of `block` in lanes, with the portable code's
/// operations in its order, so the same `t`. Where an edge function is exactly zero in some
/// lane the portable code redoes it in f64; that is rare (a ray through an edge or a corner),
/// so the whole block then goes to the portable code. `NaN` where no hit. `L` has four lanes.
#[inline(always)]
fn watertight4<L: Lanes>(
    block: &TriangleBlock<L::Scalar>,
    ray: &TriangleRay<<L::Scalar as Real>::Vec3>,
    t_min: L::Scalar,
    t_max: L::Scalar,
) -> [L::Scalar; 4] {
    let (kx, ky, kz) = (ray.axis_x, ray.axis_y, ray.axis_z);
    let [sx, sy, sz] = ray.shear;
    let (sx, sy, sz) = (L::splat(sx), L::splat(sy), L::splat(sz));
    // (An array: a glam vector indexed by a run-time axis is a `match`, with branches.)
    let origin = ray.ray.origin.to_array3();
    let origin = [
        L::splat(origin[kx]),
        L::splat(origin[ky]),
        L::splat(origin[kz]),
    ];
    let axes = [kx, ky, kz];
    let (a, b, c) = (
        relative(&block.corners[0], axes, origin),
        relative(&block.corners[1], axes, origin),
        relative(&block.corners[2], axes, origin),
    );
    // Shear and scale the corners into ray space.
    let (ax, ay) = (a.0.sub(sx.mul(a.2)), a.1.sub(sy.mul(a.2)));
    let (bx, by) = (b.0.sub(sx.mul(b.2)), b.1.sub(sy.mul(b.2)));
    let (cx, cy) = (c.0.sub(sx.mul(c.2)), c.1.sub(sy.mul(c.2)));
    let u = cx.mul(by).sub(cy.mul(bx));
    let v = ax.mul(cy).sub(ay.mul(cx));
    let w = bx.mul(ay).sub(by.mul(ax));
    let zero = L::splat(L::Scalar::ZERO);
    if u.ne(zero).and(v.ne(zero)).and(w.ne(zero)).bits() != (1 << L::COUNT) - 1 {
        return on_an_edge(block, ray, t_min, t_max);
    }
    let mixed = u
        .lt(zero)
        .or(v.lt(zero))
        .or(w.lt(zero))
        .and(u.gt(zero).or(v.gt(zero)).or(w.gt(zero)));
    let det = u.add(v).add(w);
    let (az, bz, cz) = (sz.mul(a.2), sz.mul(b.2), sz.mul(c.2));
    let t_scaled = u.mul(az).add(v.mul(bz)).add(w.mul(cz));
    // Compare t against the interval before dividing, with the sign of det folded in.
    let (low, high) = (L::splat(t_min).mul(det), L::splat(t_max).mul(det));
    let outside_if_negative = t_scaled.gt(low).or(t_scaled.lt(high));
    let outside_if_positive = t_scaled.lt(low).or(t_scaled.gt(high));
    let outside = outside_if_negative.select(outside_if_positive, det.lt(zero));
    let accepted = det.ne(zero).and_not(mixed.or(outside));
    let mut out = [L::Scalar::NAN; 4];
    t_scaled
        .div(det)
        .select(L::splat(L::Scalar::NAN), accepted)
        .write_to(&mut out);
    out
}

/// [`watertight4`]'s rare case, out of line so that the kernel stays small enough to inline.
#[cold]
#[inline(never)]
fn on_an_edge<S: Real>(
    block: &TriangleBlock<S>,
    ray: &TriangleRay<S::Vec3>,
    t_min: S,
    t_max: S,
) -> [S; 4] {
    block.intersect(ray, t_min, t_max)
}

/// One box against a group of [`LANES`] rays of a packet, `L::COUNT` rays at a time: the
/// arithmetic of [`PacketLanes::box_against_rays`] (each ray's near plane chosen by the sign of
/// its reciprocal direction, which is its sign bit: a reciprocal is never zero or NaN), so the
/// same intervals bit for bit.
#[inline(always)]
fn box_in_lanes<L: Lanes>(
    lanes: &PacketLanes<L::Scalar>,
    lower: [L::Scalar; 3],
    upper: [L::Scalar; 3],
    first: usize,
    dims: usize,
    active: u32,
) -> BoxAgainstRays<L::Scalar> {
    let mut tests = BoxAgainstRays {
        t_enter: [L::Scalar::ZERO; LANES],
        t_exit: [L::Scalar::ZERO; LANES],
        hits: 0,
        entries: [L::Scalar::ZERO; LANES],
    };
    let infinity = L::splat(L::Scalar::INFINITY);
    let zero = L::splat(L::Scalar::ZERO);
    for start in (0..LANES).step_by(L::COUNT) {
        let at = first + start;
        let mut t_enter = L::from_slice(&lanes.t_min[at..]);
        let mut t_exit = L::splat(L::Scalar::INFINITY);
        for axis in 0..dims {
            let origin = L::from_slice(&lanes.origin[axis][at..]);
            let inverse = L::from_slice(&lanes.inv_direction[axis][at..]);
            let t_lower = L::splat(lower[axis]).sub(origin).mul(inverse);
            let t_upper = L::splat(upper[axis]).sub(origin).mul(inverse);
            let negative = inverse.lt(zero);
            t_enter = t_upper.select(t_lower, negative).later(t_enter);
            t_exit = t_lower.select(t_upper, negative).earlier(t_exit);
        }
        let t_exit = t_exit
            .mul(L::splat(lanes.far_scale))
            .earlier(L::from_slice(&lanes.t_closest[at..]));
        let hit = t_enter.le(t_exit).and(L::from_bits(active >> start));
        tests.hits |= hit.bits() << start;
        t_enter.write_to(&mut tests.t_enter[start..]);
        t_exit.write_to(&mut tests.t_exit[start..]);
        t_enter
            .select(infinity, hit)
            .write_to(&mut tests.entries[start..]);
    }
    tests
}

/// A block's corner relative to the ray's origin, its axes permuted to the ray's (a function,
/// not a closure: the compiler does not always inline closures here).
#[inline(always)]
fn relative<L: Lanes>(
    corner: &[[L::Scalar; 4]; 3],
    [kx, ky, kz]: [usize; 3],
    [ox, oy, oz]: [L; 3],
) -> (L, L, L) {
    (
        L::from_slice(&corner[kx]).sub(ox),
        L::from_slice(&corner[ky]).sub(oy),
        L::from_slice(&corner[kz]).sub(oz),
    )
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::*;

    use super::*;

    /// AVX2 + FMA kernels (FMA is not used: it would round differently from the portable
    /// code; it comes with every AVX2 processor and the compiler may use it elsewhere).
    pub(crate) struct Avx2;
    /// AVX-512 F + VL kernels (the AVX2 code, compiled for AVX-512).
    pub(crate) struct Avx512;

    kernel!(
        Avx2,
        children_avx2,
        children64_avx2,
        moller_trumbore_avx2,
        moller_trumbore64_avx2,
        watertight_avx2,
        watertight64_avx2,
        box_against_rays_avx2,
        box_against_rays64_avx2
    );
    kernel!(
        Avx512,
        children_avx512,
        children64_avx512,
        moller_trumbore_avx512,
        moller_trumbore64_avx512,
        watertight_avx512,
        watertight64_avx512,
        box_against_rays_avx512,
        box_against_rays64_avx512
    );

    /// The whole traversal compiled for one instruction set, so the kernels inline into it.
    macro_rules! traversal {
        ($name:ident, $kernel:ty, $features:literal) => {
            #[target_feature(enable = $features)]
            pub(super) fn $name<V, P, O, const W: usize>(
                tree: &WideBvh<V, W>,
                primitives: &P,
                ray: &Ray<V>,
                options: &TraceOptions,
                stack: &mut WideStack<V::Scalar>,
                observer: &mut O,
            ) -> Option<Hit<V::Scalar>>
            where
                V: Vector,
                P: LeafPrimitives<V>,
                O: Observer<V::Scalar>,
            {
                traverse_wide_with::<$kernel, V, P, O, W>(
                    tree, primitives, ray, options, stack, observer,
                )
            }
        };
    }

    traversal!(traverse_avx2, Avx2, "avx2,fma");
    traversal!(traverse_avx512, Avx512, "avx2,fma,avx512f,avx512vl");

    /// The packet traversal compiled for one instruction set (its lanes of rays are plain
    /// loops, which the compiler turns into that set's vectors).
    macro_rules! packet_traversal {
        ($name:ident, $kernel:ty, $features:literal) => {
            #[target_feature(enable = $features)]
            pub(super) fn $name<V, P, O, const W: usize>(
                tree: &WideBvh<V, W>,
                primitives: &P,
                rays: &[Ray<V>],
                options: &TraceOptions,
                stack: &mut PacketStack<V::Scalar>,
                observers: &mut [O],
                hits: &mut [Option<Hit<V::Scalar>>],
            ) where
                V: Vector,
                P: LeafPrimitives<V>,
                O: Observer<V::Scalar>,
            {
                traverse_packet_with::<$kernel, V, P, O, W>(
                    tree, primitives, rays, options, stack, observers, hits,
                )
            }
        };
    }

    packet_traversal!(packet_avx2, Avx2, "avx2,fma");
    packet_traversal!(packet_avx512, Avx512, "avx2,fma,avx512f,avx512vl");

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
            $features:literal
        ) => {
            #[inline]
            #[target_feature(enable = $features)]
            pub(super) fn $children<const W: usize>(
                node: &WideNode<f32, W>,
                ray: &NodeRay<Vec3, W>,
                t_max: f32,
            ) -> ChildTests<f32, W> {
                if W % 8 == 0 {
                    children_in_lanes::<__m256, W>(node, ray, t_max)
                } else {
                    children_in_lanes::<__m128, W>(node, ray, t_max)
                }
            }

            #[inline]
            #[target_feature(enable = $features)]
            pub(super) fn $children64<const W: usize>(
                node: &WideNode<f64, W>,
                ray: &NodeRay<DVec3, W>,
                t_max: f64,
            ) -> ChildTests<f64, W> {
                children_in_lanes::<__m256d, W>(node, ray, t_max)
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
        "avx2,fma,avx512f,avx512vl"
    );

    // SAFETY, for every intrinsic in the three implementations below: SSE is part of every
    // x86-64 processor, and the AVX lanes are used only by the kernels above, which are
    // compiled for AVX2 and run only when `Isa::active` names AVX2 or AVX-512. Loads and
    // stores index their slice first, so they stay inside it.

    /// SSE's four lanes.
    impl Lanes for __m128 {
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
    impl Lanes for __m256 {
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
    impl Lanes for __m256d {
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
}

#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod wasm {
    use std::arch::wasm32::*;

    use super::*;

    /// WebAssembly `simd128` kernels: four lanes; eight children are two groups of four.
    pub(crate) struct Simd128;

    kernel!(
        Simd128,
        children_simd128,
        children64_simd128,
        moller_trumbore_simd128,
        moller_trumbore64_simd128,
        watertight_simd128,
        watertight64_simd128,
        box_against_rays_simd128,
        box_against_rays64_simd128
    );

    pub(super) fn children_simd128<const W: usize>(
        node: &WideNode<f32, W>,
        ray: &NodeRay<Vec3, W>,
        t_max: f32,
    ) -> ChildTests<f32, W> {
        children_in_lanes::<v128, W>(node, ray, t_max)
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

    // f64 has no lanes of its own here (two per `simd128` register): the portable code.

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
        node: &WideNode<f64, W>,
        ray: &NodeRay<DVec3, W>,
        t_max: f64,
    ) -> ChildTests<f64, W> {
        Portable::test_children(node, ray, t_max)
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
    impl Lanes for v128 {
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::wide_traverse::MAX_PACKET;
    use crate::bvh::{
        BinnedSah, BuildParams, Builder, LOWER, PacketStack, UPPER, WideBvh, collapse,
    };
    use crate::observer::{Counters, NoObserver};
    use crate::primitive::{PrimitiveSet, TriangleSet};
    use crate::query::Order;
    use proptest::prelude::*;

    type Children<S, const W: usize> =
        fn(&WideNode<S, W>, &SlabRay<<S as Real>::Vec3>, S) -> ChildTests<S, W>;
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
                children4: |node, ray, t_max| K::test_children(node, &NodeRay::new(*ray), t_max),
                children8: |node, ray, t_max| K::test_children(node, &NodeRay::new(*ray), t_max),
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
            use x86::{Avx2, Avx512};
            if Isa::Avx2.is_available() {
                kernels.push(Kernels::of::<Avx2>(Isa::Avx2));
            }
            if Isa::Avx512.is_available() {
                kernels.push(Kernels::of::<Avx512>(Isa::Avx512));
            }
        }
        #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
        kernels.push(Kernels::of::<wasm::Simd128>(Isa::Simd128));
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

    /// A node with its first slots holding random (possibly flat) boxes, the rest empty.
    fn node<const W: usize>() -> impl Strategy<Value = WideNode<f32, W>> {
        (prop::collection::vec((vec3(), vec3()), W), 1..=W).prop_map(|(boxes, used)| {
            let mut node = WideNode::<f32, W>::default();
            for (slot, (a, b)) in boxes.into_iter().enumerate().take(used) {
                for axis in 0..3 {
                    node.planes[LOWER][axis][slot] = a[axis].min(b[axis]);
                    node.planes[UPPER][axis][slot] = a[axis].max(b[axis]);
                }
                node.child[slot] = slot as u32;
            }
            node
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
                origin: [[0.0; MAX_PACKET]; 3],
                inv_direction: [[0.0; MAX_PACKET]; 3],
                negative: [[false; MAX_PACKET]; 3],
                t_min: [0.0; MAX_PACKET],
                t_closest: [0.0; MAX_PACKET],
                far_scale: SlabRay::new(&rays[0].0, robust).far_scale,
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
            let want = lanes.box_against_rays(lower, upper, first, dims, active);
            for isa in Isa::ALL.into_iter().filter(|isa| isa.is_available()) {
                let got = match isa {
                    #[cfg(target_arch = "x86_64")]
                    Isa::Avx2 => <x86::Avx2 as Kernel>::box_against_rays(&lanes, lower, upper, first, dims, active),
                    #[cfg(target_arch = "x86_64")]
                    Isa::Avx512 => <x86::Avx512 as Kernel>::box_against_rays(&lanes, lower, upper, first, dims, active),
                    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
                    Isa::Simd128 => <wasm::Simd128 as Kernel>::box_against_rays(&lanes, lower, upper, first, dims, active),
                    _ => Portable::box_against_rays(&lanes, lower, upper, first, dims, active),
                };
                prop_assert_eq!(got.hits, want.hits, "{:?}", isa);
                prop_assert_eq!(bits(&got.t_enter), bits(&want.t_enter), "{:?}", isa);
                prop_assert_eq!(bits(&got.t_exit), bits(&want.t_exit), "{:?}", isa);
                prop_assert_eq!(bits(&got.entries), bits(&want.entries), "{:?}", isa);
            }
        }
    }

    /// `node` in f64 (the same boxes: f32 widens exactly).
    fn widened<const W: usize>(node: &WideNode<f32, W>) -> WideNode<f64, W> {
        WideNode {
            planes: node.planes.map(|side| side.map(|row| row.map(f64::from))),
            child: node.child,
            count: node.count,
        }
    }

    /// Every child kernel gives the portable intervals, bit for bit, for nodes of 4 and 8.
    fn same_intervals<S: Real>(
        node4: &WideNode<S, 4>,
        node8: &WideNode<S, 8>,
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
    ) -> Result<(), TestCaseError>
    where
        V::Scalar: Real<Vec3 = V>,
    {
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

    /// Packets on every instruction set: the same hits as the portable packets, and as each
    /// ray alone where no two triangles tie.
    #[test]
    fn every_instruction_set_traces_packets_alike() {
        let mut state = 11u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut point = || Vec3::new(next(), next(), next()) * 10.0;
        let corners: Vec<[[f64; 3]; 3]> = (0..2000)
            .map(|_| {
                let a = point();
                [a, a + (point() - a) * 0.08, a + (point() - a) * 0.08]
                    .map(|v| v.as_dvec3().to_array())
            })
            .collect();
        let triangles = TriangleSet::<Vec3>::from_f64(&corners);
        let binary = BinnedSah { bins: 16 }.build(&triangles.all_bounds(), &BuildParams::default());
        let eight: WideBvh<Vec3, 8> = collapse(binary, &BuildParams::default().cost);
        let ordered = eight.leaf_ordered(&triangles);
        // A camera-like fan of rays: neighbours in a packet are coherent.
        let origin = Vec3::new(5.0, 5.0, -20.0);
        let rays: Vec<Ray<Vec3>> = (0..64 * 40)
            .filter_map(|index| {
                let (x, y) = ((index % 64) as f32 / 64.0, (index / 64) as f32 / 40.0);
                Ray::try_new(origin, Vec3::new(x * 10.0 - 5.0, y * 10.0 - 5.0, 20.0)).ok()
            })
            .collect();
        let options = TraceOptions::default();
        let mut stack = PacketStack::default();
        let mut reference: Option<Vec<_>> = None;
        for isa in Isa::ALL.into_iter().filter(|isa| isa.is_available()) {
            let mut hits = vec![None; rays.len()];
            for (packet, packet_hits) in rays.chunks(64).zip(hits.chunks_mut(64)) {
                let mut observers = vec![Counters::default(); packet.len()];
                match isa {
                    #[cfg(target_arch = "x86_64")]
                    Isa::Avx2 => unsafe {
                        x86::packet_avx2(
                            &eight,
                            &ordered,
                            packet,
                            &options,
                            &mut stack,
                            &mut observers,
                            packet_hits,
                        )
                    },
                    #[cfg(target_arch = "x86_64")]
                    Isa::Avx512 => unsafe {
                        x86::packet_avx512(
                            &eight,
                            &ordered,
                            packet,
                            &options,
                            &mut stack,
                            &mut observers,
                            packet_hits,
                        )
                    },
                    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
                    Isa::Simd128 => traverse_packet_with::<wasm::Simd128, _, _, _, 8>(
                        &eight,
                        &ordered,
                        packet,
                        &options,
                        &mut stack,
                        &mut observers,
                        packet_hits,
                    ),
                    _ => traverse_packet_with::<Portable, _, _, _, 8>(
                        &eight,
                        &ordered,
                        packet,
                        &options,
                        &mut stack,
                        &mut observers,
                        packet_hits,
                    ),
                }
            }
            match &reference {
                None => {
                    let mut single = WideStack::default();
                    let alone: Vec<_> = rays
                        .iter()
                        .map(|ray| {
                            traverse_wide_with::<Portable, _, _, _, 8>(
                                &eight,
                                &ordered,
                                ray,
                                &options,
                                &mut single,
                                &mut NoObserver,
                            )
                        })
                        .collect();
                    assert_eq!(hits, alone, "packets against single rays");
                    assert!(hits.iter().filter(|hit| hit.is_some()).count() > rays.len() / 10);
                    reference = Some(hits);
                }
                Some(expected) => assert_eq!(&hits, expected, "{isa:?}"),
            }
        }
    }

    /// Whole traversals on every instruction set: the same hits and the same steps.
    #[test]
    fn every_instruction_set_traces_the_same_hits_and_steps() {
        let mut state = 3u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut point = || Vec3::new(next(), next(), next()) * 10.0;
        let corners: Vec<[[f64; 3]; 3]> = (0..3000)
            .map(|_| {
                let a = point();
                [a, a + (point() - a) * 0.05, a + (point() - a) * 0.05]
                    .map(|v| v.as_dvec3().to_array())
            })
            .collect();
        let triangles = TriangleSet::<Vec3>::from_f64(&corners);
        let binary = BinnedSah { bins: 16 }.build(&triangles.all_bounds(), &BuildParams::default());
        let cost = BuildParams::default().cost;
        let four: WideBvh<Vec3, 4> = collapse(binary.clone(), &cost);
        let eight: WideBvh<Vec3, 8> = collapse(binary, &cost);
        let (ordered4, ordered8) = (
            four.leaf_ordered(&triangles),
            eight.leaf_ordered(&triangles),
        );
        let rays: Vec<Ray<Vec3>> = (0..2000)
            .filter_map(|_| {
                let origin = point() * 3.0 - Vec3::splat(10.0);
                Ray::try_new(origin, point() - origin).ok()
            })
            .collect();
        let mut stack = WideStack::default();
        for robust in [false, true] {
            for order in [Order::NearFirst, Order::FileOrder] {
                let options = TraceOptions {
                    order,
                    ..TraceOptions::default()
                }
                .with_robust(robust);
                for ray in &rays {
                    let mut reference = None;
                    for isa in Isa::ALL.into_iter().filter(|isa| isa.is_available()) {
                        let mut trace = |tree4: bool| {
                            let mut counters = Counters::default();
                            let hit = match (tree4, isa) {
                                #[cfg(target_arch = "x86_64")]
                                (true, Isa::Avx2) => unsafe {
                                    x86::traverse_avx2(
                                        &four,
                                        &ordered4,
                                        ray,
                                        &options,
                                        &mut stack,
                                        &mut counters,
                                    )
                                },
                                #[cfg(target_arch = "x86_64")]
                                (false, Isa::Avx2) => unsafe {
                                    x86::traverse_avx2(
                                        &eight,
                                        &ordered8,
                                        ray,
                                        &options,
                                        &mut stack,
                                        &mut counters,
                                    )
                                },
                                #[cfg(target_arch = "x86_64")]
                                (true, Isa::Avx512) => unsafe {
                                    x86::traverse_avx512(
                                        &four,
                                        &ordered4,
                                        ray,
                                        &options,
                                        &mut stack,
                                        &mut counters,
                                    )
                                },
                                #[cfg(target_arch = "x86_64")]
                                (false, Isa::Avx512) => unsafe {
                                    x86::traverse_avx512(
                                        &eight,
                                        &ordered8,
                                        ray,
                                        &options,
                                        &mut stack,
                                        &mut counters,
                                    )
                                },
                                #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
                                (true, Isa::Simd128) => {
                                    traverse_wide_with::<wasm::Simd128, _, _, _, 4>(
                                        &four,
                                        &ordered4,
                                        ray,
                                        &options,
                                        &mut stack,
                                        &mut counters,
                                    )
                                }
                                #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
                                (false, Isa::Simd128) => {
                                    traverse_wide_with::<wasm::Simd128, _, _, _, 8>(
                                        &eight,
                                        &ordered8,
                                        ray,
                                        &options,
                                        &mut stack,
                                        &mut counters,
                                    )
                                }
                                (true, _) => traverse_wide_with::<Portable, _, _, _, 4>(
                                    &four,
                                    &ordered4,
                                    ray,
                                    &options,
                                    &mut stack,
                                    &mut counters,
                                ),
                                (false, _) => traverse_wide_with::<Portable, _, _, _, 8>(
                                    &eight,
                                    &ordered8,
                                    ray,
                                    &options,
                                    &mut stack,
                                    &mut counters,
                                ),
                            };
                            // The plain triangles, tested one by one, agree too.
                            let plain = if tree4 {
                                traverse_wide_with::<Portable, _, _, _, 4>(
                                    &four,
                                    &triangles,
                                    ray,
                                    &options,
                                    &mut WideStack::default(),
                                    &mut NoObserver,
                                )
                            } else {
                                traverse_wide_with::<Portable, _, _, _, 8>(
                                    &eight,
                                    &triangles,
                                    ray,
                                    &options,
                                    &mut WideStack::default(),
                                    &mut NoObserver,
                                )
                            };
                            assert_eq!(hit, plain, "{isa:?} blocks against one by one");
                            (hit, counters)
                        };
                        let got = (trace(true), trace(false));
                        match &reference {
                            None => reference = Some(got),
                            Some(expected) => assert_eq!(&got, expected, "{isa:?} {options:?}"),
                        }
                    }
                }
            }
        }
    }
}
