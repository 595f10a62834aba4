//! Rays `r(t) = p + t d` restricted to an interval `[t_min, t_max]`.

use crate::math::{Real, Vector};

/// Why a ray could not be made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RayError {
    /// Every direction component is zero (±0): the ray goes nowhere.
    #[error("the direction is zero")]
    ZeroDirection,
    /// The origin has a NaN or infinite component.
    #[error("the origin is not finite (NaN or infinity)")]
    NonFiniteOrigin,
    /// The direction has a NaN or infinite component.
    #[error("the direction is not finite (NaN or infinity)")]
    NonFiniteDirection,
    /// `t_min` is NaN, `t_max` is NaN, or `t_min > t_max`.
    #[error("the interval [t_min, t_max] is empty or NaN")]
    BadInterval,
}

/// A ray `r(t) = origin + t · direction` for `t` in `[t_min, t_max]`.
///
/// The direction need not be normalised; `t` is measured in units of its length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray<V: Vector> {
    /// `p`, where the ray starts.
    pub origin: V,
    /// `d`, never all zeros.
    pub direction: V,
    /// The smallest `t` that counts as a hit.
    pub t_min: V::Scalar,
    /// The largest `t` that counts as a hit (may be +∞).
    pub t_max: V::Scalar,
}

/// A 2D ray in f32.
pub type Ray2 = Ray<glam::Vec2>;
/// A 3D ray in f32.
pub type Ray3 = Ray<glam::Vec3>;

impl<V: Vector> Ray<V> {
    /// A ray over `[0, +∞)`, checked like [`Ray::try_with_interval`].
    pub fn try_new(origin: V, direction: V) -> Result<Self, RayError> {
        Self::try_with_interval(origin, direction, V::Scalar::ZERO, V::Scalar::INFINITY)
    }

    /// A ray over `[t_min, t_max]`. Fails on a zero or non-finite direction, a non-finite
    /// origin, or an empty or NaN interval (`t_max` may be +∞).
    pub fn try_with_interval(
        origin: V,
        direction: V,
        t_min: V::Scalar,
        t_max: V::Scalar,
    ) -> Result<Self, RayError> {
        if !origin.is_finite() {
            return Err(RayError::NonFiniteOrigin);
        }
        if !direction.is_finite() {
            return Err(RayError::NonFiniteDirection);
        }
        if (0..V::DIM).all(|axis| direction[axis] == V::Scalar::ZERO) {
            return Err(RayError::ZeroDirection);
        }
        // `!(a <= b)` rather than `a > b` so that a NaN bound is rejected too.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(t_min <= t_max) || t_min.is_nan() {
            return Err(RayError::BadInterval);
        }
        Ok(Self {
            origin,
            direction,
            t_min,
            t_max,
        })
    }

    /// The point `p + t d`.
    #[inline]
    pub fn at(&self, t: V::Scalar) -> V {
        self.origin + self.direction * t
    }

    /// Converts between precisions of the same dimension.
    pub fn cast<W: Vector>(&self) -> Ray<W> {
        Ray {
            origin: W::from_f64_slice(&self.origin.to_f64_array()),
            direction: W::from_f64_slice(&self.direction.to_f64_array()),
            t_min: W::Scalar::from_f64(self.t_min.to_f64()),
            t_max: W::Scalar::from_f64(self.t_max.to_f64()),
        }
    }
}
