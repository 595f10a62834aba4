//! The narrow numeric interface that lets one implementation serve 2D and 3D, f32 and f64.
//!
//! [`Real`] is the scalar (f32 or f64); [`Vector`] is a glam point/vector of dimension
//! [`Vector::DIM`] over that scalar (`Vec2`, `Vec3`, `DVec2`, `DVec3`). Everything in the core is
//! written against these two traits, in the spirit of bevy_math's bounding traits: "area" is
//! the perimeter in 2D and the surface area in 3D.

use std::fmt::{Debug, Display};
use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, Neg, Sub, SubAssign};

use glam::{BVec2, BVec3, BVec3A, DVec2, DVec3, Vec2, Vec3, Vec3A};

/// A floating-point scalar: `f32` or `f64`.
pub trait Real:
    Copy
    + Debug
    + Display
    + Default
    + PartialEq
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 2.
    const TWO: Self;
    /// +∞.
    const INFINITY: Self;
    /// −∞.
    const NEG_INFINITY: Self;
    /// The unit roundoff ε/2 of the format (pbrt's `MachineEpsilon`).
    const UNIT_ROUNDOFF: Self;
    /// The largest finite value.
    const MAX: Self;
    /// Not a number.
    const NAN: Self;
    /// The 3D vector over this scalar (`Vec3` or `DVec3`): what a triangle block's lanes
    /// are tested with, one lane at a time, by the portable code.
    type Vec3: Vector3<Scalar = Self>;
    /// Converts from f64, rounding to nearest.
    fn from_f64(value: f64) -> Self;
    /// Widens to f64 (exact).
    fn to_f64(self) -> f64;
    /// Converts from f32 (exact).
    fn from_f32(value: f32) -> Self;
    /// Converts a count.
    fn from_usize(value: usize) -> Self;
    /// Converts a 32-bit count (one instruction, where a 64-bit unsigned one takes several).
    fn from_u32(value: u32) -> Self;
    /// Truncates towards zero to a small count: negative and NaN give 0, and values beyond
    /// `i32::MAX` saturate there (a 32-bit conversion is a single instruction; bin indices
    /// need no more).
    fn to_small_usize(self) -> usize;
    /// |x|.
    fn abs(self) -> Self;
    /// √x.
    fn sqrt(self) -> Self;
    /// Neither NaN nor ±∞.
    fn is_finite(self) -> bool;
    /// NaN.
    fn is_nan(self) -> bool;
    /// The smaller of two numbers; if one is NaN, the other.
    fn min(self, other: Self) -> Self;
    /// The larger of two numbers; if one is NaN, the other.
    fn max(self, other: Self) -> Self;
    /// How many of the low bytes of [`order_key`](Self::order_key) can be non-zero.
    const KEY_BYTES: usize;
    /// An integer in the same order as the number (for radix sorting; not for NaN): the sign
    /// bit flipped for positive numbers, every bit for negative ones.
    fn order_key(self) -> u64;

    /// The gap between `|self|` and the next number of this precision above it: the unit in
    /// the last place, how far apart the numbers near `self` are.
    fn ulp(self) -> Self;

    /// Hands `value` to `f32_case` or `f64_case`, whichever is this precision's, and returns
    /// what it returns: how code written for both precisions calls code written for one of
    /// them (the SIMD kernels, whose registers differ). The choice is made when the code is
    /// compiled, and the value is passed as it is: no test at run time, no copy.
    fn by_precision<In: OverScalar, Out: OverScalar>(
        value: In::Of<Self>,
        f32_case: impl FnOnce(In::Of<f32>) -> Out::Of<f32>,
        f64_case: impl FnOnce(In::Of<f64>) -> Out::Of<f64>,
    ) -> Out::Of<Self>;

    /// pbrt's γ(n) = nε/(1 − nε): the relative error bound of n chained roundings
    /// (Pharr, Jakob, Humphreys, "Physically Based Rendering", 3rd ed., §3.9).
    #[inline]
    fn gamma(n: u32) -> Self {
        let n_eps = Self::from_usize(n as usize) * Self::UNIT_ROUNDOFF;
        n_eps / (Self::ONE - n_eps)
    }
}

/// A type made over a scalar (`[S; 4]`, a triangle block of `S`, a tuple of references to
/// them): what [`Real::by_precision`] hands to code written for one precision. `Of<S>` is the
/// type over `S`; the implementing type is only its name.
pub trait OverScalar {
    /// The type over the scalar `S`.
    type Of<S: Real>;
}

macro_rules! impl_real {
    ($t:ty, $vec3:ty, $case:tt) => {
        impl Real for $t {
            type Vec3 = $vec3;
            #[inline(always)]
            fn by_precision<In: OverScalar, Out: OverScalar>(
                value: In::Of<Self>,
                f32_case: impl FnOnce(In::Of<f32>) -> Out::Of<f32>,
                f64_case: impl FnOnce(In::Of<f64>) -> Out::Of<f64>,
            ) -> Out::Of<Self> {
                let cases = (f32_case, f64_case);
                (cases.$case)(value)
            }
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const TWO: Self = 2.0;
            const INFINITY: Self = <$t>::INFINITY;
            const NEG_INFINITY: Self = <$t>::NEG_INFINITY;
            const UNIT_ROUNDOFF: Self = <$t>::EPSILON * 0.5;
            const MAX: Self = <$t>::MAX;
            const NAN: Self = <$t>::NAN;
            const KEY_BYTES: usize = std::mem::size_of::<$t>();
            #[inline(always)]
            fn order_key(self) -> u64 {
                let bits = self.to_bits();
                let sign = 1 << (8 * Self::KEY_BYTES - 1);
                (if bits & sign != 0 { !bits } else { bits | sign }) as u64
            }
            #[inline]
            fn ulp(self) -> Self {
                let magnitude = <$t>::abs(self);
                magnitude.next_up() - magnitude
            }
            #[inline(always)]
            fn from_f64(value: f64) -> Self {
                value as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn from_f32(value: f32) -> Self {
                value as $t
            }
            #[inline(always)]
            fn from_usize(value: usize) -> Self {
                value as $t
            }
            #[inline(always)]
            fn from_u32(value: u32) -> Self {
                value as $t
            }
            #[inline(always)]
            fn to_small_usize(self) -> usize {
                (self as i32).max(0) as usize
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn is_nan(self) -> bool {
                <$t>::is_nan(self)
            }
            #[inline(always)]
            fn min(self, other: Self) -> Self {
                <$t>::min(self, other)
            }
            #[inline(always)]
            fn max(self, other: Self) -> Self {
                <$t>::max(self, other)
            }
        }
    };
}
impl_real!(f32, Vec3, 0);
impl_real!(f64, DVec3, 1);

/// A point or vector of dimension [`Vector::DIM`] over [`Vector::Scalar`].
///
/// Implemented for glam's `Vec2`, `Vec3`, `DVec2` and `DVec3`. Component `i` is `v[i]`.
pub trait Vector:
    Copy
    + Debug
    + Default
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Mul<<Self as Vector>::Scalar, Output = Self>
    + Div<<Self as Vector>::Scalar, Output = Self>
    + Neg<Output = Self>
    + Index<usize, Output = <Self as Vector>::Scalar>
    + IndexMut<usize>
{
    /// The component type.
    type Scalar: Real;
    /// 2 or 3.
    const DIM: usize;
    /// Every component set to `value`.
    fn splat(value: Self::Scalar) -> Self;
    /// Component-wise minimum (unspecified where a component is NaN: one compare and select,
    /// the inner loop of every box union).
    fn min(self, other: Self) -> Self;
    /// Component-wise maximum (unspecified where a component is NaN).
    fn max(self, other: Self) -> Self;
    /// Dot product.
    fn dot(self, other: Self) -> Self::Scalar;
    /// Builds a vector from the first `DIM` values of `values` (f64, rounded to the scalar).
    fn from_f64_slice(values: &[f64]) -> Self;
    /// Every component finite.
    fn is_finite(self) -> bool;

    /// The vector's lanes form (see [`Lanes`]).
    type Lanes: Lanes<Scalar = Self::Scalar>;
    /// The vector in its lanes form.
    fn to_lanes(self) -> Self::Lanes;

    /// Euclidean length.
    #[inline]
    fn length(self) -> Self::Scalar {
        self.dot(self).sqrt()
    }
    /// The components, padded with zeros to three: indexing an array by a run-time axis is a
    /// load, where glam's `v[axis]` is a match (hot loops pick components by axis).
    #[inline(always)]
    fn to_array3(self) -> [Self::Scalar; 3] {
        let mut out = [Self::Scalar::ZERO; 3];
        for (axis, slot) in out.iter_mut().enumerate().take(Self::DIM) {
            *slot = self[axis];
        }
        out
    }

    /// The same point in another precision `W` of the same dimension: exact when `W`'s
    /// scalar holds every value of this one's (f32 to f64), rounded to nearest otherwise.
    #[inline]
    fn converted<W: Vector>(self) -> W {
        W::from_f64_slice(&self.to_f64_array()[..Self::DIM])
    }

    /// The components as f64, padded with zeros to three (for printing and JSON).
    #[inline]
    fn to_f64_array(self) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (axis, slot) in out.iter_mut().enumerate().take(Self::DIM) {
            *slot = self[axis].to_f64();
        }
        out
    }
}

macro_rules! impl_vector {
    ($v:ty, $s:ty, $dim:expr, $lanes:ty) => {
        impl Vector for $v {
            type Scalar = $s;
            type Lanes = $lanes;
            #[inline(always)]
            fn to_lanes(self) -> $lanes {
                <$lanes>::from(self)
            }
            const DIM: usize = $dim;
            #[inline(always)]
            fn splat(value: $s) -> Self {
                <$v>::splat(value)
            }
            #[inline(always)]
            fn min(self, other: Self) -> Self {
                <$v>::select(self.cmplt(other), self, other)
            }
            #[inline(always)]
            fn max(self, other: Self) -> Self {
                <$v>::select(self.cmpgt(other), self, other)
            }
            #[inline(always)]
            fn dot(self, other: Self) -> $s {
                <$v>::dot(self, other)
            }
            #[inline]
            fn from_f64_slice(values: &[f64]) -> Self {
                let mut out = Self::ZERO;
                for axis in 0..$dim {
                    out[axis] = values[axis] as $s;
                }
                out
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$v>::is_finite(self)
            }
        }
    };
}
impl_vector!(Vec2, f32, 2, Vec2);
impl_vector!(Vec3, f32, 3, Vec3A);
impl_vector!(DVec2, f64, 2, DVec2);
impl_vector!(DVec3, f64, 3, DVec3);

/// A vector in the form its arithmetic runs fastest in, with the few operations the slab test
/// needs lane by lane: 3D f32 is glam's `Vec3A`, the three axes in one 16-byte SIMD register;
/// the other types are their own form. The slab test's hot path
/// ([`slab_clip`](crate::slab::slab_clip)) runs in lanes where they are a register
/// ([`Lanes::IN_REGISTER`]) and axis by axis elsewhere.
pub trait Lanes:
    Copy + Debug + Send + Sync + 'static + Sub<Output = Self> + Mul<Output = Self>
{
    /// The component type.
    type Scalar: Real;
    /// Whether the lanes are one SIMD register (3D f32). Where they are not, arithmetic on
    /// them is component by component anyway, and code written axis by axis ran faster (the
    /// f64 slab test on glam's `DVec3` took 1.6 times the instructions of the axis loop).
    const IN_REGISTER: bool;
    /// A mask: one flag per lane.
    type Mask: Copy + Debug + Send + Sync + 'static;
    /// The lanes below zero (−0 is not).
    fn negative(self) -> Self::Mask;
    /// `if_true` where `mask` is set, `if_false` elsewhere.
    fn select(mask: Self::Mask, if_true: Self, if_false: Self) -> Self;
    /// The largest lane, a NaN lane read as −∞.
    fn greatest(self) -> Self::Scalar;
    /// The smallest lane, a NaN lane read as +∞.
    fn least(self) -> Self::Scalar;
}

macro_rules! impl_lanes {
    ($lanes:ty, $s:ty, $mask:ty, $in_register:expr) => {
        impl Lanes for $lanes {
            type Scalar = $s;
            const IN_REGISTER: bool = $in_register;
            type Mask = $mask;
            #[inline(always)]
            fn negative(self) -> $mask {
                self.cmplt(<$lanes>::ZERO)
            }
            #[inline(always)]
            fn select(mask: $mask, if_true: Self, if_false: Self) -> Self {
                <$lanes>::select(mask, if_true, if_false)
            }
            #[inline(always)]
            fn greatest(self) -> $s {
                // `x.max(−∞)` keeps x and turns NaN into −∞ on every glam backend (SSE's
                // `maxps(a, b)` gives `b` for a NaN `a`; the scalar one is `f32::max`).
                self.max(<$lanes>::NEG_INFINITY).max_element()
            }
            #[inline(always)]
            fn least(self) -> $s {
                self.min(<$lanes>::INFINITY).min_element()
            }
        }
    };
}
impl_lanes!(Vec2, f32, BVec2, false);
impl_lanes!(Vec3A, f32, BVec3A, true);
impl_lanes!(DVec2, f64, BVec2, false);
impl_lanes!(DVec3, f64, BVec3, false);

/// A three-dimensional [`Vector`]: adds the cross product that triangles need. It is its
/// scalar's 3D vector ([`Real::Vec3`]), which code generic over it may rely on.
pub trait Vector3: Vector<Scalar: Real<Vec3 = Self>> {
    /// Cross product.
    fn cross(self, other: Self) -> Self;
    /// The vector `(x, y, z)`.
    fn new(x: Self::Scalar, y: Self::Scalar, z: Self::Scalar) -> Self;
}

impl Vector3 for Vec3 {
    #[inline(always)]
    fn cross(self, other: Self) -> Self {
        Vec3::cross(self, other)
    }
    #[inline(always)]
    fn new(x: f32, y: f32, z: f32) -> Self {
        Vec3::new(x, y, z)
    }
}

impl Vector3 for DVec3 {
    #[inline(always)]
    fn cross(self, other: Self) -> Self {
        DVec3::cross(self, other)
    }
    #[inline(always)]
    fn new(x: f64, y: f64, z: f64) -> Self {
        DVec3::new(x, y, z)
    }
}
