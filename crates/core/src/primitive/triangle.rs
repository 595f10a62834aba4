//! Triangles in 3D and the two ray/triangle tests users trade between.

use crate::aabb::Aabb;
use crate::math::{Real, Vector3};
use crate::primitive::{HitTest, PrimitiveSet};
use crate::ray::Ray;

/// A triangle mesh as a flat list of triangles, numbered in order.
///
/// A degenerate (zero-area) triangle keeps its number and its box but is stored collapsed to
/// one point, so neither test can ever report a hit on it.
#[derive(Clone, Debug, Default)]
pub struct TriangleSet<V: Vector3> {
    triangles: Vec<[V; 3]>,
    degenerate_count: usize,
}

impl<V: Vector3> TriangleSet<V> {
    /// Takes triangles given in f64 (as loaded), converting them to this precision.
    /// Zero area is judged in f64 before rounding.
    pub fn from_f64(triangles: &[[[f64; 3]; 3]]) -> Self {
        let mut degenerate_count = 0;
        let triangles = triangles
            .iter()
            .map(|corners| {
                let [a, b, c] = corners.map(glam::DVec3::from_array);
                let points = corners.map(|corner| V::from_f64_slice(&corner));
                let degenerate = (b - a).cross(c - a) == glam::DVec3::ZERO
                    || points[0] == points[1]
                    || points[1] == points[2]
                    || points[2] == points[0];
                if degenerate {
                    degenerate_count += 1;
                    [points[0]; 3]
                } else {
                    points
                }
            })
            .collect();
        Self {
            triangles,
            degenerate_count,
        }
    }

    /// The triangles' corners (a degenerate triangle appears as one repeated point).
    pub fn triangles(&self) -> &[[V; 3]] {
        &self.triangles
    }

    /// How many triangles have zero area.
    pub fn degenerate_count(&self) -> usize {
        self.degenerate_count
    }
}

/// A ray prepared for triangle tests.
#[derive(Clone, Copy, Debug)]
pub struct TriangleRay<V: Vector3> {
    /// The ray.
    pub ray: Ray<V>,
    /// Which test runs.
    pub test: HitTest,
    /// Watertight test: the axis along which the direction is largest (becomes z) ...
    pub(crate) axis_z: usize,
    /// ... and the other two, ordered to keep the winding.
    pub(crate) axis_x: usize,
    pub(crate) axis_y: usize,
    /// The shear that maps the ray onto the +z axis: `(−d_x/d_z, −d_y/d_z, 1/d_z)`.
    pub(crate) shear: [V::Scalar; 3],
}

impl<V: Vector3> TriangleRay<V> {
    /// Precomputes the ray's permutation and shear (Woop, Benthin, Wald 2013, §3) when the
    /// test is watertight.
    #[inline(always)]
    pub fn new(ray: &Ray<V>, test: HitTest) -> Self {
        if test == HitTest::Fast {
            return Self {
                ray: *ray,
                test,
                axis_z: 2,
                axis_x: 0,
                axis_y: 1,
                shear: [V::Scalar::ZERO; 3],
            };
        }
        // (An array: see `watertight`.)
        let d = ray.direction.to_array3();
        let mut axis_z = 0;
        for axis in 1..3 {
            if d[axis].abs() > d[axis_z].abs() {
                axis_z = axis;
            }
        }
        let mut axis_x = (axis_z + 1) % 3;
        let mut axis_y = (axis_x + 1) % 3;
        // Swapping x and y when d_z is negative keeps the triangle's winding.
        if d[axis_z] < V::Scalar::ZERO {
            std::mem::swap(&mut axis_x, &mut axis_y);
        }
        let inv_dz = V::Scalar::ONE / d[axis_z];
        Self {
            ray: *ray,
            test,
            axis_z,
            axis_x,
            axis_y,
            shear: [d[axis_x] * inv_dz, d[axis_y] * inv_dz, inv_dz],
        }
    }
}

/// Möller & Trumbore 1997, "Fast, Minimum Storage Ray/Triangle Intersection".
#[inline(always)]
fn moller_trumbore<V: Vector3>(
    ray: &Ray<V>,
    [v0, v1, v2]: &[V; 3],
    t_min: V::Scalar,
    t_max: V::Scalar,
) -> Option<V::Scalar> {
    let zero = V::Scalar::ZERO;
    let edge1 = *v1 - *v0;
    let edge2 = *v2 - *v0;
    let p = ray.direction.cross(edge2);
    let det = edge1.dot(p);
    // A zero determinant: the ray is parallel to the plane, or the triangle is degenerate.
    if det == zero {
        return None;
    }
    let inv_det = V::Scalar::ONE / det;
    let s = ray.origin - *v0;
    let u = s.dot(p) * inv_det;
    if u < zero || u > V::Scalar::ONE {
        return None;
    }
    let q = s.cross(edge1);
    let v = ray.direction.dot(q) * inv_det;
    if v < zero || u + v > V::Scalar::ONE {
        return None;
    }
    let t = edge2.dot(q) * inv_det;
    (t >= t_min && t <= t_max).then_some(t)
}

/// Four triangles stored lane by lane (each corner's coordinates a row of four), so that one
/// SIMD test checks them together: a wide BVH leaf's block of
/// [`LEAF_BLOCK`](crate::bvh::LEAF_BLOCK) slots, 144 bytes in f32 and 288 in f64. Blocks are
/// aligned to their rows (16 bytes), not to cache lines: padding each f32 block to three whole
/// lines made the blocks a third larger, and random rays, which miss the caches, 7 % slower.
///
/// The corners are stored, not a corner and two edges, because the watertight test needs the
/// corners themselves (`v0 + (v1 − v0)` need not round back to `v1`); Möller–Trumbore takes the
/// edges' differences when it runs, as the one-triangle test does, so both give its `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
pub struct TriangleBlock<S: Real = f32> {
    /// `corners[corner][axis][lane]`.
    pub corners: [[[S; 4]; 3]; 3],
}

impl<S: Real> Default for TriangleBlock<S> {
    fn default() -> Self {
        Self {
            corners: [[[S::ZERO; 4]; 3]; 3],
        }
    }
}

impl<S: Real> TriangleBlock<S> {
    /// Packs triangles (in slot order) four to a block; a short last block repeats its last
    /// triangle.
    pub fn pack<V: Vector3<Scalar = S>>(triangles: &[[V; 3]]) -> Vec<Self> {
        triangles
            .chunks(4)
            .map(|chunk| {
                let mut block = Self::default();
                for lane in 0..4 {
                    let triangle = chunk[lane.min(chunk.len() - 1)];
                    for (corner, point) in triangle.iter().enumerate() {
                        for axis in 0..3 {
                            block.corners[corner][axis][lane] = point[axis];
                        }
                    }
                }
                block
            })
            .collect()
    }

    /// Lane `lane`'s triangle.
    #[inline(always)]
    pub fn triangle(&self, lane: usize) -> [S::Vec3; 3] {
        self.corners
            .map(|[x, y, z]| S::Vec3::new(x[lane], y[lane], z[lane]))
    }

    /// Each lane's `t` where the ray hits its triangle within `[t_min, t_max]`, `NaN` where it
    /// does not, with the ray's test: the one-triangle test, lane by lane (the SIMD kernels
    /// compute the same).
    #[inline(always)]
    pub fn intersect(&self, ray: &TriangleRay<S::Vec3>, t_min: S, t_max: S) -> [S; 4] {
        std::array::from_fn(|lane| {
            self.intersect_lane(ray, lane, t_min, t_max)
                .unwrap_or(S::NAN)
        })
    }

    /// The one-triangle test of lane `lane`.
    #[inline(always)]
    pub fn intersect_lane(
        &self,
        ray: &TriangleRay<S::Vec3>,
        lane: usize,
        t_min: S,
        t_max: S,
    ) -> Option<S> {
        let triangle = self.triangle(lane);
        match ray.test {
            HitTest::Fast => moller_trumbore(&ray.ray, &triangle, t_min, t_max),
            HitTest::Watertight => watertight(ray, &triangle, t_min, t_max),
        }
    }
}

/// Woop, Benthin & Wald 2013, "Watertight Ray/Triangle Intersection" (JCGT 2(1)).
///
/// The triangle is moved into a space where the ray is the +z axis from the origin; the
/// 2D edge functions U, V, W are then evaluated so that a point on a shared edge gets the same
/// value from both triangles, and a zero is recomputed in higher precision for f32.
#[inline(always)]
fn watertight<V: Vector3>(
    prepared: &TriangleRay<V>,
    corners: &[V; 3],
    t_min: V::Scalar,
    t_max: V::Scalar,
) -> Option<V::Scalar> {
    let zero = V::Scalar::ZERO;
    let (kx, ky, kz) = (prepared.axis_x, prepared.axis_y, prepared.axis_z);
    let [sx, sy, sz] = prepared.shear;
    let origin = prepared.ray.origin;
    // As arrays: a glam vector indexed by a number known only when the code runs is a
    // `match`, two branches that the ray's axes make unpredictable.
    let a = (corners[0] - origin).to_array3();
    let b = (corners[1] - origin).to_array3();
    let c = (corners[2] - origin).to_array3();
    // Shear and scale the corners into ray space.
    let ax = a[kx] - sx * a[kz];
    let ay = a[ky] - sy * a[kz];
    let bx = b[kx] - sx * b[kz];
    let by = b[ky] - sy * b[kz];
    let cx = c[kx] - sx * c[kz];
    let cy = c[ky] - sy * c[kz];
    // The scaled barycentric coordinates (2D edge functions).
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    // On an edge the products can cancel; redo them in f64 so the sign is exact for f32 input.
    if u == zero || v == zero || w == zero {
        let (ax, ay, bx, by, cx, cy) = (
            ax.to_f64(),
            ay.to_f64(),
            bx.to_f64(),
            by.to_f64(),
            cx.to_f64(),
            cy.to_f64(),
        );
        u = V::Scalar::from_f64(cx * by - cy * bx);
        v = V::Scalar::from_f64(ax * cy - ay * cx);
        w = V::Scalar::from_f64(bx * ay - by * ax);
    }
    // Mixed signs: the ray passes outside an edge.
    if (u < zero || v < zero || w < zero) && (u > zero || v > zero || w > zero) {
        return None;
    }
    let det = u + v + w;
    if det == zero {
        return None;
    }
    let az = sz * a[kz];
    let bz = sz * b[kz];
    let cz = sz * c[kz];
    let t_scaled = u * az + v * bz + w * cz;
    // Compare t against the interval before dividing, with the sign of det folded in.
    if det < zero {
        if t_scaled > t_min * det || t_scaled < t_max * det {
            return None;
        }
    } else if t_scaled < t_min * det || t_scaled > t_max * det {
        return None;
    }
    Some(t_scaled / det)
}

impl<V: Vector3> PrimitiveSet<V> for TriangleSet<V> {
    type RayData = TriangleRay<V>;

    #[inline]
    fn len(&self) -> usize {
        self.triangles.len()
    }

    #[inline]
    fn bounds(&self, index: usize) -> Aabb<V> {
        Aabb::from_points(self.triangles[index])
    }

    // Inlined, so that a traversal's ray state is written in place (a copy of the prepared
    // ray right after it was written stalls on store forwarding).
    #[inline(always)]
    fn prepare(&self, ray: &Ray<V>, test: HitTest) -> TriangleRay<V> {
        TriangleRay::new(ray, test)
    }

    fn clipped_bounds(&self, index: usize, cell: &Aabb<V>) -> Option<Aabb<V>> {
        super::clip::clipped_bounds(&self.triangles[index], cell)
    }

    fn permuted(&self, order: &[u32]) -> Self {
        Self {
            triangles: order
                .iter()
                .map(|&index| self.triangles[index as usize])
                .collect(),
            degenerate_count: self.degenerate_count,
        }
    }

    #[inline(always)]
    fn intersect(
        &self,
        ray: &TriangleRay<V>,
        index: usize,
        t_min: V::Scalar,
        t_max: V::Scalar,
    ) -> Option<V::Scalar> {
        let corners = &self.triangles[index];
        match ray.test {
            HitTest::Fast => moller_trumbore(&ray.ray, corners, t_min, t_max),
            HitTest::Watertight => watertight(ray, corners, t_min, t_max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};

    fn unit_triangle() -> [[f64; 3]; 3] {
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    }

    #[test]
    fn both_tests_hit_the_interior_at_the_same_t() {
        let set = TriangleSet::<Vec3>::from_f64(&[unit_triangle()]);
        let ray = Ray::try_new(Vec3::new(0.25, 0.25, 2.0), Vec3::new(0.0, 0.0, -1.0)).unwrap();
        for test in [HitTest::Fast, HitTest::Watertight] {
            let prepared = set.prepare(&ray, test);
            assert_eq!(set.intersect(&prepared, 0, 0.0, f32::INFINITY), Some(2.0));
            // A t_max before the hit rejects it.
            assert_eq!(set.intersect(&prepared, 0, 0.0, 1.5), None);
        }
    }

    #[test]
    fn reversed_ray_misses_and_degenerate_triangle_is_never_hit() {
        let degenerate = [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 2.0, 0.0]];
        let set = TriangleSet::<DVec3>::from_f64(&[unit_triangle(), degenerate]);
        assert_eq!(set.degenerate_count(), 1);
        let away = Ray::try_new(DVec3::new(0.25, 0.25, 2.0), DVec3::Z).unwrap();
        let along = Ray::try_new(DVec3::new(1.0, 1.0, 1.0), DVec3::new(0.0, 0.0, -1.0)).unwrap();
        for test in [HitTest::Fast, HitTest::Watertight] {
            assert_eq!(
                set.intersect(&set.prepare(&away, test), 0, 0.0, f64::INFINITY),
                None
            );
            assert_eq!(
                set.intersect(&set.prepare(&along, test), 1, 0.0, f64::INFINITY),
                None
            );
        }
    }
}
