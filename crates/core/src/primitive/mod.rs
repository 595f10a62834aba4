//! Primitives and the trait through which traversal and brute force test them.
//!
//! Builders never see primitives: they get one box per primitive. Traversal and brute force
//! test primitives only through [`PrimitiveSet`], so a triangle mesh and a 2D scene of
//! segments and discs run the same code.

mod shape;
mod triangle;

pub use shape::{Shape, ShapeSet, Sphere};
pub use triangle::{TriangleRay, TriangleSet};

use crate::aabb::Aabb;
use crate::math::Vector;
use crate::ray::Ray;

/// Which ray/primitive test to run where there is a choice (triangles).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum HitTest {
    /// Möller & Trumbore 1997: fast, but a ray through a shared edge or vertex can slip
    /// between the two triangles.
    #[default]
    Fast,
    /// Woop, Benthin & Wald 2013, "Watertight Ray/Triangle Intersection": never misses
    /// through a shared edge or vertex of a closed mesh.
    Watertight,
}

/// An indexed set of primitives that a ray can be tested against.
pub trait PrimitiveSet<V: Vector> {
    /// What a ray precomputes once before testing many primitives.
    type RayData;

    /// The number of primitives; they are numbered `0..len()`.
    fn len(&self) -> usize;

    /// True when there are no primitives.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The bounding box of primitive `index`.
    fn bounds(&self, index: usize) -> Aabb<V>;

    /// Precomputes what the tests of `ray` share.
    fn prepare(&self, ray: &Ray<V>, test: HitTest) -> Self::RayData;

    /// The smallest `t` in `[t_min, t_max]` where the ray meets primitive `index`, if any.
    fn intersect(
        &self,
        ray: &Self::RayData,
        index: usize,
        t_min: V::Scalar,
        t_max: V::Scalar,
    ) -> Option<V::Scalar>;

    /// Every primitive's box, in order: what a builder takes.
    fn all_bounds(&self) -> Vec<Aabb<V>> {
        (0..self.len()).map(|index| self.bounds(index)).collect()
    }
}
