//! Bounding volumes around a whole object, for the reject test the lecture starts with, and
//! the "void" that makes the choice of volume a trade-off.

use crate::aabb::Aabb;
use crate::math::{Real, Vector};
use crate::primitive::{Shape, ShapeSet, Sphere};
use crate::ray::Ray;
use crate::slab::slab_record;

/// A near-minimal sphere around points: Ritter 1990, "An Efficient Bounding Sphere"
/// (Graphics Gems). Within about 5% of the optimal radius, in two passes.
pub fn bounding_sphere<V: Vector>(points: &[V]) -> Sphere<V> {
    let Some(&first) = points.first() else {
        return Sphere {
            center: V::splat(V::Scalar::ZERO),
            radius: V::Scalar::ZERO,
        };
    };
    let farthest_from = |from: V| {
        points.iter().copied().fold(from, |best, point| {
            if (point - from).length() > (best - from).length() {
                point
            } else {
                best
            }
        })
    };
    // Start with the sphere on a far-apart pair of points.
    let a = farthest_from(first);
    let b = farthest_from(a);
    let half = V::Scalar::ONE / V::Scalar::TWO;
    let mut center = (a + b) * half;
    let mut radius = (b - a).length() * half;
    // Grow it just enough to take in every point that lies outside.
    for &point in points {
        let distance = (point - center).length();
        if distance > radius {
            let new_radius = (radius + distance) * half;
            center = center + (point - center) * ((new_radius - radius) / distance);
            radius = new_radius;
        }
    }
    // Rounding can leave a point a hair outside; make the sphere conservative.
    let slack = points
        .iter()
        .map(|&point| (point - center).length())
        .fold(radius, V::Scalar::max);
    Sphere {
        center,
        radius: slack,
    }
}

/// The two bounding volumes of the lecture around the same object, with their void.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingVolumes<V: Vector> {
    /// The axis-aligned bounding box.
    pub aabb: Aabb<V>,
    /// The bounding sphere (disc in 2D).
    pub sphere: Sphere<V>,
    /// Share of the box's area (2D) or volume (3D) the object does not fill, in [0, 1].
    pub aabb_void: f64,
    /// Share of the sphere's the object does not fill, in [0, 1].
    pub sphere_void: f64,
}

impl<V: Vector> BoundingVolumes<V> {
    /// The volumes around `points`, for an object whose own area (2D) or volume (3D) is
    /// `object_measure`: the void is what a ray can hit in the volume and miss in the object.
    pub fn new(points: &[V], object_measure: f64) -> Self {
        let aabb = Aabb::from_points(points.iter().copied());
        let sphere = bounding_sphere(points);
        Self {
            aabb,
            sphere,
            aabb_void: void_fraction(aabb.measure().to_f64(), object_measure),
            sphere_void: void_fraction(sphere.measure().to_f64(), object_measure),
        }
    }

    /// The volumes around a set of solid shapes taken as one object: its void is measured
    /// against what the shapes cover together (overlaps once, on a 400² grid in 2D).
    pub fn around_shapes(shapes: &ShapeSet<V>) -> Self {
        let points: Vec<V> = shapes.shapes.iter().flat_map(Shape::hull_points).collect();
        let samples = if V::DIM == 2 { 400 } else { 60 };
        Self::new(&points, shapes.covered_measure(samples))
    }

    /// The reject tests: whether `ray` hits the box and the sphere. A ray that misses a
    /// volume cannot hit the object inside, so its primitives need no test.
    pub fn reject_tests(&self, ray: &Ray<V>) -> (bool, bool) {
        let box_hit = slab_record(&self.aabb, ray, false).hit;
        let sphere_hit = self
            .sphere
            .interval(ray)
            .is_some_and(|(t0, t1)| t0.max(ray.t_min) <= t1.min(ray.t_max));
        (box_hit, sphere_hit)
    }
}

/// `1 − object / volume`, clamped to [0, 1] (0 for an empty volume).
pub fn void_fraction(volume_measure: f64, object_measure: f64) -> f64 {
    if volume_measure <= 0.0 {
        return 0.0;
    }
    (1.0 - object_measure / volume_measure).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn square_in_its_box_and_circle() {
        let corners = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        let volumes = BoundingVolumes::new(&corners, 4.0);
        assert_eq!(volumes.aabb_void, 0.0);
        // The circle through the corners has radius √2: void = 1 − 4 / 2π.
        assert!((volumes.sphere.radius - 2f64.sqrt()).abs() < 1e-12);
        assert!((volumes.sphere_void - (1.0 - 4.0 / (2.0 * std::f64::consts::PI))).abs() < 1e-12);
        // A ray passing the corner: inside the circle, outside the box.
        let ray = Ray::try_new(DVec2::new(-1.0, 2.2), DVec2::new(1.0, 0.0)).unwrap();
        assert_eq!(volumes.reject_tests(&ray), (false, true));
    }

    /// Two overlapping unit squares cover 1.75, not 2; a disc's covered area is πr² within the
    /// grid's error, and its hull points enclose it.
    #[test]
    fn shapes_covered_together_count_overlaps_once() {
        let square =
            |x: f64, y: f64| Shape::Box(Aabb::new(DVec2::new(x, y), DVec2::new(x + 1.0, y + 1.0)));
        let squares = ShapeSet {
            shapes: vec![square(0.0, 0.0), square(0.5, 0.5)],
        };
        assert!((squares.covered_measure(400) - 1.75).abs() < 0.01);
        let disc = ShapeSet {
            shapes: vec![Shape::Sphere(Sphere {
                center: DVec2::new(3.0, 4.0),
                radius: 2.0,
            })],
        };
        let area = disc.covered_measure(400);
        assert!((area - 4.0 * std::f64::consts::PI).abs() < 0.05, "{area}");
        let volumes = BoundingVolumes::around_shapes(&disc);
        assert!(volumes.sphere.radius >= 2.0 && volumes.sphere.radius < 2.01);
        assert!((volumes.aabb_void - (1.0 - std::f64::consts::PI / 4.0)).abs() < 0.01);
    }
}
