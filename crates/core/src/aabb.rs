//! Axis-aligned bounding boxes in 2D and 3D.

use crate::math::{Real, Vector};

/// An axis-aligned box `[min, max]`, closed on every side.
///
/// The empty box has `min = +∞` and `max = −∞`, so that growing it by anything gives that thing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb<V: Vector> {
    /// The corner with the smallest coordinates.
    pub min: V,
    /// The corner with the largest coordinates.
    pub max: V,
}

/// A 2D box in f32.
pub type Aabb2 = Aabb<glam::Vec2>;
/// A 3D box in f32.
pub type Aabb3 = Aabb<glam::Vec3>;

impl<V: Vector> Default for Aabb<V> {
    fn default() -> Self {
        Self::empty()
    }
}

impl<V: Vector> Aabb<V> {
    /// The box spanned by two corners.
    #[inline]
    pub fn new(min: V, max: V) -> Self {
        Self { min, max }
    }

    /// The box that contains nothing; the identity of [`Aabb::union`].
    #[inline]
    pub fn empty() -> Self {
        Self {
            min: V::splat(V::Scalar::INFINITY),
            max: V::splat(V::Scalar::NEG_INFINITY),
        }
    }

    /// The degenerate box holding one point.
    #[inline]
    pub fn from_point(point: V) -> Self {
        Self {
            min: point,
            max: point,
        }
    }

    /// The smallest box holding every point.
    pub fn from_points(points: impl IntoIterator<Item = V>) -> Self {
        points
            .into_iter()
            .fold(Self::empty(), |bounds, point| bounds.grown(point))
    }

    /// The box both boxes cover, or `None` if they do not meet (touching counts as meeting:
    /// the result may be flat).
    pub fn intersection(&self, other: &Self) -> Option<Self> {
        let common = Self::new(self.min.max(other.min), self.max.min(other.max));
        (0..V::DIM)
            .all(|axis| common.min[axis] <= common.max[axis])
            .then_some(common)
    }

    /// True when some axis has `min > max` (nothing is inside).
    #[inline]
    pub fn is_empty(&self) -> bool {
        (0..V::DIM).any(|axis| self.min[axis] > self.max[axis])
    }

    /// This box grown to hold `point`.
    #[inline]
    #[must_use]
    pub fn grown(self, point: V) -> Self {
        Self {
            min: self.min.min(point),
            max: self.max.max(point),
        }
    }

    /// The smallest box holding both.
    #[inline]
    #[must_use]
    pub fn union(self, other: Self) -> Self {
        Self {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The same box in another precision `W` (see [`Vector::converted`]).
    pub fn converted<W: Vector>(&self) -> Aabb<W> {
        Aabb::new(self.min.converted(), self.max.converted())
    }

    /// `max − min` (negative on the empty box).
    #[inline]
    pub fn extent(&self) -> V {
        self.max - self.min
    }

    /// The centre point.
    #[inline]
    pub fn center(&self) -> V {
        (self.min + self.max) * (V::Scalar::ONE / V::Scalar::TWO)
    }

    /// The axis along which the box is longest (the first one on ties).
    pub fn largest_axis(&self) -> usize {
        let extent = self.extent();
        let mut best = 0;
        for axis in 1..V::DIM {
            if extent[axis] > extent[best] {
                best = axis;
            }
        }
        best
    }

    /// The surface area in 3D, the perimeter in 2D: what a random ray's chance of hitting a
    /// convex body is proportional to (the SAH's probability, Goldsmith & Salmon 1987,
    /// MacDonald & Booth 1990). Zero for the empty box.
    #[inline]
    pub fn area(&self) -> V::Scalar {
        if self.is_empty() {
            return V::Scalar::ZERO;
        }
        let extent = self.extent();
        let two = V::Scalar::TWO;
        if V::DIM == 2 {
            two * (extent[0] + extent[1])
        } else {
            two * (extent[0] * extent[1] + extent[1] * extent[2] + extent[2] * extent[0])
        }
    }

    /// Half of [`Aabb::area`], without the check for the empty box: for the inner loops of
    /// builders, on boxes known to hold something. Ratios of half areas are ratios of areas.
    #[inline(always)]
    pub fn half_area_nonempty(&self) -> V::Scalar {
        let extent = self.extent();
        if V::DIM == 2 {
            extent[0] + extent[1]
        } else {
            extent[0] * extent[1] + extent[1] * extent[2] + extent[2] * extent[0]
        }
    }

    /// The area in 2D, the volume in 3D. Zero for the empty box.
    pub fn measure(&self) -> V::Scalar {
        if self.is_empty() {
            return V::Scalar::ZERO;
        }
        let extent = self.extent();
        (0..V::DIM).fold(V::Scalar::ONE, |product, axis| product * extent[axis])
    }

    /// True when `point` lies in the closed box.
    #[inline]
    pub fn contains_point(&self, point: V) -> bool {
        (0..V::DIM).all(|axis| self.min[axis] <= point[axis] && point[axis] <= self.max[axis])
    }

    /// True when `other` lies in the closed box (the empty box lies in every box).
    #[inline]
    pub fn contains(&self, other: &Self) -> bool {
        other.is_empty()
            || (0..V::DIM)
                .all(|axis| self.min[axis] <= other.min[axis] && other.max[axis] <= self.max[axis])
    }

    /// True when both corners are finite.
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    #[test]
    fn area_is_perimeter_in_2d_and_surface_in_3d() {
        let square = Aabb2::new(Vec2::ZERO, Vec2::new(2.0, 3.0));
        assert_eq!(square.area(), 10.0);
        assert_eq!(square.measure(), 6.0);
        let cube = Aabb3::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(cube.area(), 22.0);
        assert_eq!(cube.measure(), 6.0);
        assert_eq!(Aabb3::empty().area(), 0.0);
    }

    #[test]
    fn union_with_empty_is_identity() {
        let cube = Aabb3::new(Vec3::ZERO, Vec3::ONE);
        assert_eq!(cube.union(Aabb3::empty()), cube);
        assert!(cube.contains(&Aabb3::empty()));
        assert!(Aabb3::empty().is_empty());
        assert_eq!(cube.largest_axis(), 0);
    }
}
