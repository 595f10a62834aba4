//! The slab test: where a ray enters and leaves an axis-aligned box.
//!
//! A box is `DIM` pairs of parallel planes (slabs). For each axis the ray crosses the nearer
//! plane at `t_near` and the farther at `t_far`; it is inside the box between the largest
//! `t_near` (`t_enter`) and the smallest `t_far` (`t_exit`), and it hits the box when
//! `t_enter <= t_exit` within its own interval (Kay & Kajiya 1986). The lesson's record
//! ([`slab_record`]) and the axis-by-axis reference ([`slab_clip_scalar`]) share
//! [`axis_interval`] and the same NaN-ignoring reductions, so they cannot disagree.
//! Traversal's hot path, [`slab_clip`], runs the same arithmetic on the vector's [`Lanes`]
//! where they are a SIMD register (3D f32: the three axes in one); property tests hold it to
//! the reference's interval.
//!
//! # Zero direction components and origins on a plane
//! The reciprocal of a ±0 component is ±∞, so the plane distances become ±∞ (the ray never
//! reaches the plane) or, when the origin lies exactly on the plane, `0 · ∞ = NaN`. Choosing the
//! near and far planes by the sign of the reciprocal (Williams, Barrus, Morley, Shirley 2005,
//! "An efficient and robust ray-box intersection algorithm") puts such a NaN only where the
//! exact answer is −∞ (a near value) or +∞ (a far value): a ray moving inside a closed slab is
//! never constrained by it. The reductions ignore a NaN, which is exactly that.
//!
//! # Robust mode
//! Rounding can push a computed `t_far` just below the true one, so a ray grazing a box edge
//! can miss it. Multiplying `t_far` by `1 + 2γ(3)` makes the test conservative (Ize 2013,
//! "Robust BVH Ray Traversal"; pbrt-v3 §3.9.2).

use crate::aabb::Aabb;
use crate::math::{Lanes, Real, Vector};
use crate::ray::Ray;

/// A ray prepared for many box tests: reciprocal direction and its signs, computed once.
#[derive(Clone, Copy, Debug)]
pub struct SlabRay<V: Vector> {
    /// The ray's origin.
    pub origin: V,
    /// `1 / d` per component (±∞ where `d` is ±0).
    pub inv_direction: V,
    /// Per axis, whether the ray moves towards −∞ (the sign bit of `inv_direction`).
    pub negative: [bool; 3],
    /// The ray's `t_min`.
    pub t_min: V::Scalar,
    /// `1` in fast mode, `1 + 2γ(3)` in robust mode (applied to every `t_far`).
    pub far_scale: V::Scalar,
    /// The origin in lanes, for [`slab_clip`].
    origin_lanes: V::Lanes,
    /// The reciprocal direction in lanes.
    inv_direction_lanes: V::Lanes,
    /// The lanes whose direction is negative.
    negative_lanes: <V::Lanes as Lanes>::Mask,
}

impl<V: Vector> SlabRay<V> {
    /// Which side of a wide node's planes ([`LOWER`](crate::bvh::LOWER) or
    /// [`UPPER`](crate::bvh::UPPER)) the ray enters through on `axis`.
    #[inline(always)]
    pub fn near_side(&self, axis: usize) -> usize {
        usize::from(self.negative[axis])
    }

    /// The side it leaves through.
    #[inline(always)]
    pub fn far_side(&self, axis: usize) -> usize {
        usize::from(!self.negative[axis])
    }

    /// Prepares `ray`; `robust` widens every `t_far` conservatively (Ize 2013).
    #[inline]
    pub fn new(ray: &Ray<V>, robust: bool) -> Self {
        let mut inv_direction = V::splat(V::Scalar::ZERO);
        let mut negative = [false; 3];
        for axis in 0..V::DIM {
            (inv_direction[axis], negative[axis]) = reciprocal(ray.direction[axis]);
        }
        let inv_direction_lanes = inv_direction.to_lanes();
        Self {
            origin: ray.origin,
            inv_direction,
            negative,
            origin_lanes: ray.origin.to_lanes(),
            inv_direction_lanes,
            negative_lanes: inv_direction_lanes.negative(),
            t_min: ray.t_min,
            far_scale: far_scale(robust),
        }
    }
}

/// A direction component's reciprocal, and whether the ray moves towards −∞ along it.
#[inline(always)]
pub(crate) fn reciprocal<S: Real>(direction: S) -> (S, bool) {
    let inverse = S::ONE / direction;
    // 1/−0 = −∞, so the sign of the reciprocal carries the sign of a zero too.
    (inverse, inverse < S::ZERO)
}

/// The factor every `t_far` is multiplied by: `1` in fast mode, `1 + 2γ(3)` in robust mode
/// (Ize 2013).
#[inline(always)]
pub(crate) fn far_scale<S: Real>(robust: bool) -> S {
    if robust {
        S::ONE + S::TWO * S::gamma(3)
    } else {
        S::ONE
    }
}

/// `t_near` and `t_far` of one axis's slab, before robust widening. A NaN means
/// "unconstrained": −∞ for `t_near`, +∞ for `t_far` (see the module docs).
#[inline(always)]
pub fn axis_interval<V: Vector>(
    bounds: &Aabb<V>,
    ray: &SlabRay<V>,
    axis: usize,
) -> (V::Scalar, V::Scalar) {
    let (near_plane, far_plane) = if ray.negative[axis] {
        (bounds.max[axis], bounds.min[axis])
    } else {
        (bounds.min[axis], bounds.max[axis])
    };
    let origin = ray.origin[axis];
    let inverse = ray.inv_direction[axis];
    let t_near = (near_plane - origin) * inverse;
    let t_far = (far_plane - origin) * inverse;
    (t_near, t_far)
}

/// The later of two entry times; a NaN `t_near` is ignored.
#[inline(always)]
pub(crate) fn later<S: Real>(t_enter: S, t_near: S) -> S {
    if t_near > t_enter { t_near } else { t_enter }
}

/// The earlier of two exit times; a NaN `t_far` is ignored.
#[inline(always)]
pub(crate) fn earlier<S: Real>(t_exit: S, t_far: S) -> S {
    if t_far < t_exit { t_far } else { t_exit }
}

/// The hot path: the part `[t_enter, t_exit]` of `[ray.t_min, t_max]` inside `bounds`.
/// The box is hit when `t_enter <= t_exit`.
///
/// Where the vector's [`Lanes`] are a SIMD register (3D f32: the three axes in one),
/// [`slab_clip_scalar`]'s arithmetic on them, so the same interval (a zero may differ in
/// sign): NaN lanes (origin on a plane, zero direction) are read as −∞ / +∞ by the
/// reductions, which is what the scalar form's NaN-ignoring reductions amount to. Tests check
/// the two agree. Elsewhere, [`slab_clip_scalar`] itself.
#[inline(always)]
pub fn slab_clip<V: Vector>(
    bounds: &Aabb<V>,
    ray: &SlabRay<V>,
    t_max: V::Scalar,
) -> (V::Scalar, V::Scalar) {
    if !V::Lanes::IN_REGISTER {
        return slab_clip_scalar(bounds, ray, t_max);
    }
    let (origin, inverse) = (ray.origin_lanes, ray.inv_direction_lanes);
    let t_min_plane = (bounds.min.to_lanes() - origin) * inverse;
    let t_max_plane = (bounds.max.to_lanes() - origin) * inverse;
    let t_near = V::Lanes::select(ray.negative_lanes, t_max_plane, t_min_plane);
    let t_far = V::Lanes::select(ray.negative_lanes, t_min_plane, t_max_plane);
    let t_enter = later(ray.t_min, t_near.greatest());
    let t_exit = earlier(t_max, t_far.least() * ray.far_scale);
    (t_enter, t_exit)
}

/// [`slab_clip`] axis by axis: the reference form (the lesson's record computes the same).
#[inline(always)]
pub fn slab_clip_scalar<V: Vector>(
    bounds: &Aabb<V>,
    ray: &SlabRay<V>,
    t_max: V::Scalar,
) -> (V::Scalar, V::Scalar) {
    let mut t_enter = ray.t_min;
    let mut t_exit_unscaled = V::Scalar::INFINITY;
    for axis in 0..V::DIM {
        let (t_near, t_far) = axis_interval(bounds, ray, axis);
        t_enter = later(t_enter, t_near);
        t_exit_unscaled = earlier(t_exit_unscaled, t_far);
    }
    // Scaling by a positive constant commutes with the minimum (rounding is monotonic), so
    // robust mode widens once per box rather than once per axis.
    (t_enter, earlier(t_max, t_exit_unscaled * ray.far_scale))
}

/// Everything the slab test computes, as the lecture's table shows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlabRecord<V: Vector> {
    /// Per axis, where the ray crosses the nearer plane (−∞ when the axis does not constrain).
    pub t_near: V,
    /// Per axis, where the ray crosses the farther plane (+∞ when the axis does not constrain).
    pub t_far: V,
    /// The largest `t_near`: where the ray has entered every slab.
    pub t_enter: V::Scalar,
    /// The smallest `t_far`: where the ray leaves the first slab.
    pub t_exit: V::Scalar,
    /// `max(t_enter, t_min) <= min(t_exit, t_max)`: the ray meets the closed box within its
    /// interval.
    pub hit: bool,
}

/// The slab test with its record, for lessons and the CLI's `slab` command.
pub fn slab_record<V: Vector>(bounds: &Aabb<V>, ray: &Ray<V>, robust: bool) -> SlabRecord<V> {
    let slab_ray = SlabRay::new(ray, robust);
    let mut t_near_per_axis = V::splat(V::Scalar::NEG_INFINITY);
    let mut t_far_per_axis = V::splat(V::Scalar::INFINITY);
    let mut t_enter = V::Scalar::NEG_INFINITY;
    let mut t_exit = V::Scalar::INFINITY;
    for axis in 0..V::DIM {
        let (t_near, t_far) = axis_interval(bounds, &slab_ray, axis);
        let t_far = t_far * slab_ray.far_scale;
        t_near_per_axis[axis] = later(V::Scalar::NEG_INFINITY, t_near);
        t_far_per_axis[axis] = earlier(V::Scalar::INFINITY, t_far);
        t_enter = later(t_enter, t_near);
        t_exit = earlier(t_exit, t_far);
    }
    let hit = later(t_enter, ray.t_min) <= earlier(t_exit, ray.t_max);
    SlabRecord {
        t_near: t_near_per_axis,
        t_far: t_far_per_axis,
        t_enter,
        t_exit,
        hit,
    }
}
