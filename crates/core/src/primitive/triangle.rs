//! Triangles in 3D and the two ray/triangle tests users trade between.

use crate::aabb::Aabb;
use crate::math::{Real, Vector3};
use crate::primitive::{HitTest, PrimitiveSet};
use crate::ray::Ray;

/// Copies of at least this many triangles are split between the threads of the current rayon
/// pool (a leaf-ordered copy of a big mesh, its blocks of four).
const PARALLEL_COPY_GRAIN: usize = 8192;

/// A triangle mesh as a flat list of triangles, numbered in order.
///
/// A degenerate (zero-area) triangle keeps its number and its box but is stored collapsed to
/// one point, so neither test can ever report a hit on it.
#[derive(Clone, Debug, Default)]
pub struct TriangleSet<V: Vector3> {
    triangles: Vec<[V; 3]>,
    degenerate_count: usize,
    /// The same triangles four to a block, when packed ([`PrimitiveSet::with_blocks`]).
    blocks: Option<Vec<TriangleBlock<V::Scalar>>>,
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
            blocks: None,
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

    /// The test of triangle `index` against `ray` (prepared for its test), with what it
    /// computed on the way: the same computation as [`PrimitiveSet::intersect`], which gives
    /// the same answer.
    pub fn explain(
        &self,
        ray: &TriangleRay<V>,
        index: usize,
        t_min: V::Scalar,
        t_max: V::Scalar,
    ) -> TriangleTestValues<V::Scalar> {
        let mut values = TriangleTestValues::default();
        let corners = &self.triangles[index];
        match ray.test {
            HitTest::Fast => moller_trumbore(&ray.ray, corners, t_min, t_max, Some(&mut values)),
            HitTest::Watertight => watertight(ray, corners, t_min, t_max, Some(&mut values)),
        };
        values
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

/// What a ray/triangle test computed on its way to its answer: the numbers a lesson on cracks
/// shows and a question on leaks asks about. The tests fill it in as they go, in the same
/// computation (the traversal's calls pass `None`, and that code is compiled away).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriangleTestValues<S> {
    /// Which test.
    pub test: HitTest,
    /// Möller–Trumbore: the determinant `e1 · (d × e2)`; watertight: `U + V + W`.
    pub det: Option<S>,
    /// Möller–Trumbore: the barycentric coordinates `u`, `v` and `u + v` (the hit needs
    /// `u ≥ 0`, `v ≥ 0`, `u + v ≤ 1`); watertight: the edge functions `U`, `V`, `W` (the hit
    /// needs no two of opposite signs). `None` where the test stopped before computing it.
    pub coordinates: [Option<S>; 3],
    /// Watertight: an edge function was zero, so all three were computed again in f64.
    pub recomputed: bool,
    /// Where the ray meets the triangle's plane, when the test got that far.
    pub t: Option<S>,
    /// The answer: a hit within the interval.
    pub hit: bool,
}

impl<S: Real> TriangleTestValues<S> {
    /// The same values, exactly, in f64 (to show an f32 test beside an f64 one).
    pub fn widened(&self) -> TriangleTestValues<f64> {
        let wide = |value: Option<S>| value.map(Real::to_f64);
        TriangleTestValues {
            test: self.test,
            det: wide(self.det),
            coordinates: self.coordinates.map(wide),
            recomputed: self.recomputed,
            t: wide(self.t),
            hit: self.hit,
        }
    }

    /// The weight of corner `corner` (0, 1 or 2) that puts the ray's point where the test
    /// computed it: the three add up to one, and all are ≥ 0 inside the triangle.
    /// Möller–Trumbore's are `(1 − u − v, u, v)`, the watertight test's `(U, V, W) / (U + V +
    /// W)`. `None` where the test stopped before computing what it needs (Möller–Trumbore stops
    /// after `u` when `u` is outside [0, 1], so corner 1's weight is always there).
    pub fn weight(&self, corner: usize) -> Option<f64> {
        let [first, second, third] = self.coordinates.map(|value| value.map(Real::to_f64));
        match (self.test, corner) {
            (HitTest::Fast, 0) => Some(1.0 - (first? + second?)),
            (HitTest::Fast, 1) => first,
            (HitTest::Fast, _) => second,
            (HitTest::Watertight, _) => {
                let sum = first? + second? + third?;
                let own = [first, second, third][corner.min(2)]?;
                (sum != 0.0).then(|| own / sum)
            }
        }
    }
}

/// Möller & Trumbore 1997, "Fast, Minimum Storage Ray/Triangle Intersection". `values`, if
/// given, is told what was computed.
#[inline(always)]
fn moller_trumbore<V: Vector3>(
    ray: &Ray<V>,
    [v0, v1, v2]: &[V; 3],
    t_min: V::Scalar,
    t_max: V::Scalar,
    mut values: Option<&mut TriangleTestValues<V::Scalar>>,
) -> Option<V::Scalar> {
    let zero = V::Scalar::ZERO;
    let edge1 = *v1 - *v0;
    let edge2 = *v2 - *v0;
    let p = ray.direction.cross(edge2);
    let det = edge1.dot(p);
    if let Some(values) = values.as_deref_mut() {
        values.test = HitTest::Fast;
        values.det = Some(det);
    }
    // A zero determinant: the ray is parallel to the plane, or the triangle is degenerate.
    if det == zero {
        return None;
    }
    let inv_det = V::Scalar::ONE / det;
    let s = ray.origin - *v0;
    let u = s.dot(p) * inv_det;
    if let Some(values) = values.as_deref_mut() {
        values.coordinates[0] = Some(u);
    }
    if u < zero || u > V::Scalar::ONE {
        return None;
    }
    let q = s.cross(edge1);
    let v = ray.direction.dot(q) * inv_det;
    if let Some(values) = values.as_deref_mut() {
        values.coordinates[1] = Some(v);
        values.coordinates[2] = Some(u + v);
    }
    if v < zero || u + v > V::Scalar::ONE {
        return None;
    }
    let t = edge2.dot(q) * inv_det;
    let hit = t >= t_min && t <= t_max;
    if let Some(values) = values {
        values.t = Some(t);
        values.hit = hit;
    }
    hit.then_some(t)
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
        use rayon::prelude::*;
        // On the current rayon pool, in order (a copy: the same blocks on any threads).
        triangles
            .par_chunks(4)
            .with_min_len(PARALLEL_COPY_GRAIN / 4)
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
            HitTest::Fast => moller_trumbore(&ray.ray, &triangle, t_min, t_max, None),
            HitTest::Watertight => watertight(ray, &triangle, t_min, t_max, None),
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
    mut values: Option<&mut TriangleTestValues<V::Scalar>>,
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
    let recompute = u == zero || v == zero || w == zero;
    if recompute {
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
    if let Some(values) = values.as_deref_mut() {
        values.test = HitTest::Watertight;
        values.coordinates = [Some(u), Some(v), Some(w)];
        values.recomputed = recompute;
        values.det = Some(u + v + w);
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
    if let Some(values) = values {
        values.t = Some(t_scaled / det);
        values.hit = if det < zero {
            !(t_scaled > t_min * det || t_scaled < t_max * det)
        } else {
            !(t_scaled < t_min * det || t_scaled > t_max * det)
        };
    }
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

    /// On the current rayon pool, in order.
    fn all_bounds(&self) -> Vec<Aabb<V>> {
        use rayon::prelude::*;
        self.triangles
            .par_iter()
            .with_min_len(PARALLEL_COPY_GRAIN)
            .map(|&corners| Aabb::from_points(corners))
            .collect()
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

    fn overlaps(&self, index: usize, cell: &Aabb<V>) -> bool {
        super::overlap::triangle_overlaps_box(&self.triangles[index], cell)
    }

    fn permuted(&self, order: &[u32]) -> Self {
        use rayon::prelude::*;
        Self {
            // On the current rayon pool, in order (a copy: the same on any threads).
            triangles: order
                .par_iter()
                .with_min_len(PARALLEL_COPY_GRAIN)
                .map(|&index| self.triangles[index as usize])
                .collect(),
            degenerate_count: self.degenerate_count,
            blocks: None,
        }
    }

    fn with_blocks(self) -> Self {
        Self {
            blocks: Some(TriangleBlock::pack(&self.triangles)),
            ..self
        }
    }

    #[inline(always)]
    fn blocks(&self) -> Option<&[TriangleBlock<V::Scalar>]> {
        self.blocks.as_deref()
    }

    #[inline(always)]
    fn block_ray(ray: &TriangleRay<V>) -> Option<&TriangleRay<V>> {
        Some(ray)
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
            HitTest::Fast => moller_trumbore(&ray.ray, corners, t_min, t_max, None),
            HitTest::Watertight => watertight(ray, corners, t_min, t_max, None),
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
    fn an_explained_test_gives_the_tests_answer_and_its_numbers() {
        // Random triangles near the unit square and rays aimed near them, both tests, both
        // precisions' worth of f32: the explanation's answer is the test's.
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let mut corner = || [next() * 2.0 - 1.0, next() * 2.0 - 1.0, next() * 0.5];
            let triangle = [corner(), corner(), corner()];
            let set = TriangleSet::<Vec3>::from_f64(&[triangle]);
            let origin = Vec3::new(next() as f32 - 0.5, next() as f32 - 0.5, 3.0);
            let target = Vec3::new(next() as f32 * 2.0 - 1.0, next() as f32 * 2.0 - 1.0, 0.2);
            let ray = Ray::try_new(origin, target - origin).unwrap();
            for test in [HitTest::Fast, HitTest::Watertight] {
                let prepared = set.prepare(&ray, test);
                let hit = set.intersect(&prepared, 0, 0.0, f32::INFINITY);
                let values = set.explain(&prepared, 0, 0.0, f32::INFINITY);
                assert_eq!(values.test, test);
                assert_eq!(values.hit, hit.is_some(), "{values:?}");
                if let Some(t) = hit {
                    assert_eq!(values.t, Some(t));
                }
                if test == HitTest::Fast && values.hit {
                    let [u, v, sum] = values.coordinates.map(Option::unwrap);
                    assert!(u >= 0.0 && v >= 0.0 && sum <= 1.0);
                }
            }
        }
        // Inside the unit triangle at (0.25, 0.25): u = 0.25, v = 0.25 (and so 0.5).
        let set = TriangleSet::<Vec3>::from_f64(&[unit_triangle()]);
        let ray = Ray::try_new(Vec3::new(0.25, 0.25, 2.0), Vec3::new(0.0, 0.0, -1.0)).unwrap();
        let values = set.explain(&set.prepare(&ray, HitTest::Fast), 0, 0.0, f32::INFINITY);
        assert_eq!(values.coordinates, [Some(0.25), Some(0.25), Some(0.5)]);
        assert_eq!(values.t, Some(2.0));
        // The watertight test's edge functions: all of one sign inside.
        let values = set.explain(
            &set.prepare(&ray, HitTest::Watertight),
            0,
            0.0,
            f32::INFINITY,
        );
        let [a, b, c] = values.coordinates.map(Option::unwrap);
        assert!(values.hit && (a > 0.0) == (b > 0.0) && (b > 0.0) == (c > 0.0));
        assert!(!values.recomputed);
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
