//! Spheres (discs in 2D), boxes and segments: the solid shapes of 2D lessons and scenes.
//!
//! Shapes are solid: a ray hits a shape at the first `t` of its interval where it is inside
//! (so a ray starting inside a disc hits it at `t_min`).

use crate::aabb::Aabb;
use crate::math::{Real, Vector};
use crate::primitive::{HitTest, PrimitiveSet};
use crate::ray::Ray;
use crate::slab::{SlabRay, slab_clip};

/// A sphere in 3D, a disc in 2D.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere<V: Vector> {
    /// The centre.
    pub center: V,
    /// The radius (≥ 0).
    pub radius: V::Scalar,
}

impl<V: Vector> Sphere<V> {
    /// The bounding box.
    pub fn bounds(&self) -> Aabb<V> {
        let reach = V::splat(self.radius);
        Aabb::new(self.center - reach, self.center + reach)
    }

    /// The area in 2D (πr²), the volume in 3D (4/3 πr³).
    pub fn measure(&self) -> V::Scalar {
        let r = self.radius;
        let pi = V::Scalar::from_f64(std::f64::consts::PI);
        if V::DIM == 2 {
            pi * r * r
        } else {
            V::Scalar::from_f64(4.0 / 3.0) * pi * r * r * r
        }
    }

    /// Where the ray is inside the closed sphere, `[t_0, t_1]`, if anywhere on its line.
    pub fn interval(&self, ray: &Ray<V>) -> Option<(V::Scalar, V::Scalar)> {
        // Solve |o + t d − c|² = r² in the numerically stable form of pbrt-v3 §3.2.2.
        let to_origin = ray.origin - self.center;
        let a = ray.direction.dot(ray.direction);
        let half_b = to_origin.dot(ray.direction);
        let c = to_origin.dot(to_origin) - self.radius * self.radius;
        let discriminant = half_b * half_b - a * c;
        if discriminant < V::Scalar::ZERO {
            return None;
        }
        let root = discriminant.sqrt();
        let q = if half_b < V::Scalar::ZERO {
            -half_b + root
        } else {
            -half_b - root
        };
        if q == V::Scalar::ZERO {
            // Origin at the centre of a zero sphere, or a tangent through the origin.
            return Some((V::Scalar::ZERO, V::Scalar::ZERO));
        }
        let (t0, t1) = (q / a, c / q);
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }
}

/// One solid shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape<V: Vector> {
    /// A disc (2D) or ball (3D).
    Sphere(Sphere<V>),
    /// A solid axis-aligned box.
    Box(Aabb<V>),
    /// A line segment between two points. Only a 2D segment can be hit; in 3D it has no area.
    Segment([V; 2]),
}

impl<V: Vector> Shape<V> {
    /// The bounding box.
    pub fn bounds(&self) -> Aabb<V> {
        match self {
            Shape::Sphere(sphere) => sphere.bounds(),
            Shape::Box(bounds) => *bounds,
            Shape::Segment(ends) => Aabb::from_points(*ends),
        }
    }

    /// The first `t` in `[t_min, t_max]` where the ray is inside the shape.
    pub fn intersect(&self, ray: &Ray<V>, t_min: V::Scalar, t_max: V::Scalar) -> Option<V::Scalar> {
        let (t_enter, t_exit) = match self {
            Shape::Sphere(sphere) => sphere.interval(ray)?,
            Shape::Box(bounds) => {
                let slab_ray = SlabRay::new(&Ray { t_min, ..*ray }, false);
                slab_clip(bounds, &slab_ray, t_max)
            }
            Shape::Segment(ends) => segment_interval(ray, ends)?,
        };
        let first = t_enter.max(t_min);
        (first <= t_exit.min(t_max)).then_some(first)
    }
}

impl<V: Vector> Shape<V> {
    /// Whether `point` lies in the solid shape (a segment has no inside).
    pub fn contains(&self, point: V) -> bool {
        match self {
            Shape::Sphere(sphere) => {
                let offset = point - sphere.center;
                offset.dot(offset) <= sphere.radius * sphere.radius
            }
            Shape::Box(bounds) => bounds.contains_point(point),
            Shape::Segment(_) => false,
        }
    }

    /// Points whose hull holds the whole shape, for a bounding sphere around it: a box's
    /// corners, a segment's ends, and around a disc a 64-gon pushed out just enough to enclose
    /// it (in 3D, the corners of a ball's box).
    pub fn hull_points(&self) -> Vec<V> {
        match *self {
            Shape::Sphere(sphere) if V::DIM == 2 => {
                const SIDES: usize = 64;
                let reach = sphere.radius.to_f64() / (std::f64::consts::PI / SIDES as f64).cos();
                let center = sphere.center.to_f64_array();
                (0..SIDES)
                    .map(|index| {
                        let angle = index as f64 / SIDES as f64 * std::f64::consts::TAU;
                        V::from_f64_slice(&[
                            center[0] + angle.cos() * reach,
                            center[1] + angle.sin() * reach,
                        ])
                    })
                    .collect()
            }
            Shape::Sphere(sphere) => box_corners(&sphere.bounds()),
            Shape::Box(bounds) => box_corners(&bounds),
            Shape::Segment(ends) => ends.to_vec(),
        }
    }
}

/// The 2^DIM corners of a box.
fn box_corners<V: Vector>(bounds: &Aabb<V>) -> Vec<V> {
    let (min, max) = (bounds.min.to_f64_array(), bounds.max.to_f64_array());
    (0..1usize << V::DIM)
        .map(|corner| {
            let pick = |axis: usize| {
                if corner >> axis & 1 == 1 {
                    max[axis]
                } else {
                    min[axis]
                }
            };
            V::from_f64_slice(&(0..V::DIM).map(pick).collect::<Vec<_>>())
        })
        .collect()
}

/// Where a 2D ray meets a segment: one `t`, or a range when the ray runs along it.
fn segment_interval<V: Vector>(ray: &Ray<V>, [a, b]: &[V; 2]) -> Option<(V::Scalar, V::Scalar)> {
    if V::DIM != 2 {
        return None;
    }
    let perp = |p: V, q: V| p[0] * q[1] - p[1] * q[0];
    let zero = V::Scalar::ZERO;
    let edge = *b - *a;
    let to_a = *a - ray.origin;
    let denominator = perp(ray.direction, edge);
    if denominator == zero {
        // Parallel: a hit only when the ray runs along the segment's line.
        if perp(to_a, ray.direction) != zero {
            return None;
        }
        let length_squared = ray.direction.dot(ray.direction);
        let t_a = to_a.dot(ray.direction) / length_squared;
        let t_b = (*b - ray.origin).dot(ray.direction) / length_squared;
        return Some((t_a.min(t_b), t_a.max(t_b)));
    }
    let t = perp(to_a, edge) / denominator;
    let s = perp(to_a, ray.direction) / denominator;
    (s >= zero && s <= V::Scalar::ONE).then_some((t, t))
}

/// A list of shapes, numbered in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShapeSet<V: Vector> {
    /// The shapes.
    pub shapes: Vec<Shape<V>>,
}

impl<V: Vector> ShapeSet<V> {
    /// The box around every shape (empty for no shapes).
    pub fn bounding_box(&self) -> Aabb<V> {
        self.shapes
            .iter()
            .fold(Aabb::empty(), |bounds, shape| bounds.union(shape.bounds()))
    }

    /// The area (2D) or volume (3D) the shapes cover together, overlaps counted once: the
    /// share of a grid of `samples` points per axis over their box (each at its cell's centre)
    /// that lies in some shape, times the box's measure. The error shrinks as 1/`samples`.
    /// Each shape marks the grid points inside its own box, so the work grows with the
    /// shapes' size on the grid, not with shapes × points.
    pub fn covered_measure(&self, samples: usize) -> f64 {
        let bounds = self.bounding_box();
        let samples = samples.max(1);
        if bounds.is_empty() || self.shapes.is_empty() {
            return 0.0;
        }
        let (min, max) = (bounds.min.to_f64_array(), bounds.max.to_f64_array());
        let step: Vec<f64> = (0..V::DIM)
            .map(|axis| (max[axis] - min[axis]) / samples as f64)
            .collect();
        let total = samples.pow(V::DIM as u32);
        let mut covered = vec![false; total];
        let mut coordinates = vec![0.0; V::DIM];
        for shape in &self.shapes {
            // The grid points inside the shape's box, axis by axis.
            let shape_bounds = shape.bounds();
            let (low, high) = (
                shape_bounds.min.to_f64_array(),
                shape_bounds.max.to_f64_array(),
            );
            let range: Vec<(usize, usize)> = (0..V::DIM)
                .map(|axis| {
                    if step[axis] <= 0.0 {
                        return (0, samples);
                    }
                    let first = ((low[axis] - min[axis]) / step[axis] - 0.5).ceil().max(0.0);
                    let last = ((high[axis] - min[axis]) / step[axis] - 0.5).floor();
                    (
                        first as usize,
                        (last + 1.0).clamp(0.0, samples as f64) as usize,
                    )
                })
                .collect();
            if range.iter().any(|(first, end)| first >= end) {
                continue;
            }
            let cells: usize = range.iter().map(|(first, end)| end - first).product();
            for offset in 0..cells {
                let mut rest = offset;
                let mut index = 0;
                let mut stride = 1;
                for (axis, coordinate) in coordinates.iter_mut().enumerate() {
                    let (first, end) = range[axis];
                    let cell = first + rest % (end - first);
                    rest /= end - first;
                    *coordinate = min[axis] + step[axis] * (cell as f64 + 0.5);
                    index += cell * stride;
                    stride *= samples;
                }
                if !covered[index] && shape.contains(V::from_f64_slice(&coordinates)) {
                    covered[index] = true;
                }
            }
        }
        let inside = covered.iter().filter(|&&point| point).count();
        bounds.measure().to_f64() * inside as f64 / total as f64
    }
}

impl<V: Vector> PrimitiveSet<V> for ShapeSet<V> {
    type RayData = Ray<V>;

    fn len(&self) -> usize {
        self.shapes.len()
    }

    fn bounds(&self, index: usize) -> Aabb<V> {
        self.shapes[index].bounds()
    }

    fn prepare(&self, ray: &Ray<V>, _test: HitTest) -> Ray<V> {
        *ray
    }

    fn clipped_bounds(&self, index: usize, cell: &Aabb<V>) -> Option<Aabb<V>> {
        match &self.shapes[index] {
            Shape::Segment(ends) => super::clip::clipped_bounds(ends, cell),
            // A disc's or box's own box clipped to the cell (exact for boxes).
            _ => self.bounds(index).intersection(cell),
        }
    }

    fn overlaps(&self, index: usize, cell: &Aabb<V>) -> bool {
        match &self.shapes[index] {
            Shape::Sphere(sphere) => {
                super::overlap::sphere_overlaps_box(sphere.center, sphere.radius, cell)
            }
            _ => self.clipped_bounds(index, cell).is_some(),
        }
    }

    fn permuted(&self, order: &[u32]) -> Self {
        Self {
            shapes: order
                .iter()
                .map(|&index| self.shapes[index as usize])
                .collect(),
        }
    }

    fn intersect(
        &self,
        ray: &Ray<V>,
        index: usize,
        t_min: V::Scalar,
        t_max: V::Scalar,
    ) -> Option<V::Scalar> {
        self.shapes[index].intersect(ray, t_min, t_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn disc_segment_and_box_in_2d() {
        let ray = Ray::try_new(DVec2::new(-2.0, 0.0), DVec2::X).unwrap();
        let disc = Shape::Sphere(Sphere {
            center: DVec2::ZERO,
            radius: 1.0,
        });
        assert_eq!(disc.intersect(&ray, 0.0, f64::INFINITY), Some(1.0));
        let wall = Shape::Segment([DVec2::new(3.0, -1.0), DVec2::new(3.0, 1.0)]);
        assert_eq!(wall.intersect(&ray, 0.0, f64::INFINITY), Some(5.0));
        assert_eq!(wall.intersect(&ray, 0.0, 4.0), None);
        let along = Shape::Segment([DVec2::new(4.0, 0.0), DVec2::new(6.0, 0.0)]);
        assert_eq!(along.intersect(&ray, 0.0, f64::INFINITY), Some(6.0));
        let solid = Shape::Box(Aabb::new(DVec2::new(-3.0, -1.0), DVec2::new(-1.0, 1.0)));
        // The origin is inside the box: the first inside point is t_min.
        assert_eq!(solid.intersect(&ray, 0.0, f64::INFINITY), Some(0.0));
    }
}
