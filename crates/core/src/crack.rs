//! Cracks and extremes: the cases behind the speed/accuracy trade, made here and decided by
//! the core's own tests, so that the lesson on cracks and the `leak` question show exactly
//! what a traversal computes.
//!
//! - **A shared edge** ([`SharedEdge`]): two triangles share an edge, as any two neighbours of
//!   a closed mesh do, and a ray is aimed at a point of it. Möller–Trumbore (1997) computes
//!   each triangle's barycentric coordinates on its own, and rounding can put the point just
//!   outside both: the ray slips through, a crack. The watertight test (Woop, Benthin & Wald
//!   2013, "Watertight Ray/Triangle Intersection") computes the shared edge's function alike
//!   for both triangles (one with the other's sign), so the point is inside at least one of
//!   them; an exact zero is inside both, at the same `t`, and the closest hit's tie rule (the
//!   lower primitive number, [`Hit::is_beaten_by`]) keeps one.
//! - **Far from the origin** ([`SharedEdge::moved`]): the same case moved by an offset, the ray
//!   starting as near the mesh as before. The tests work on differences (a corner minus the
//!   ray's start), which stay exact this close, so the crack keeps its width: rays aimed a
//!   little beside the edge ([`SharedEdge::aimed_aside`]) do not slip ([`slip_count`]). What
//!   grows is the spacing of the numbers themselves (their ulp): the corners snap to it, and
//!   a hit point `o + t·d` lands off the surface by up to about it
//!   ([`EdgeTest::hit_point_off`]), which is how far a secondary ray must start off it.
//! - **A ray through a box's corner** ([`corner_graze`]): exactly through it, so that the slab
//!   test's `t_enter` and `t_exit` are both 1 in exact arithmetic; rounded, `t_enter` can come
//!   out above `t_exit` and the plain test misses the box. Multiplying `t_exit` by
//!   `1 + 2γ(3)` (Ize 2013, "Robust BVH Ray Traversal") keeps it.

use glam::DVec3;

use crate::aabb::Aabb;
use crate::brute::brute_force;
use crate::math::{Real, Vector, Vector3};
use crate::observer::NoObserver;
use crate::outcome::{Outcome, ReferenceScene};
use crate::primitive::{HitTest, PrimitiveSet, TriangleSet, TriangleTestValues};
use crate::query::{Hit, Query, TraceOptions};
use crate::ray::Ray;
use crate::slab::{SlabRay, slab_clip_scalar};
use crate::trade::Precision;

/// Two triangles A = (a, b, c) and B = (a, c, d) of a square of jittered corners, split along
/// its diagonal a–c and both facing up, and a ray from above aimed at a point of the
/// diagonal. Held in f64 as drawn; each test rounds it to its precision first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SharedEdge {
    /// A's corners and B's.
    pub corners: [[DVec3; 3]; 2],
    /// Where the ray starts.
    pub origin: DVec3,
    /// Where on the shared edge, from a (0) to c (1), the ray is aimed.
    pub along: f64,
    /// How far beside the edge, into B, the ray is aimed (0: exactly at it).
    pub aside: f64,
}

/// Which of each triangle's corners is the one facing the shared edge (A's b, B's d): its
/// weight is how far inside that triangle, across the edge, a test put the ray's point.
pub const OPPOSITE: [usize; 2] = [1, 2];

impl SharedEdge {
    /// Draws a case with `uniform`, a source of numbers in [0, 1): the corners' jitter, where
    /// on the diagonal the ray is aimed (away from its ends), and where it starts.
    pub fn draw(mut uniform: impl FnMut() -> f64) -> Self {
        let mut jittered = |x: f64, y: f64| {
            DVec3::new(
                x + 0.4 * uniform() - 0.2,
                y + 0.4 * uniform() - 0.2,
                0.2 * uniform(),
            )
        };
        let [a, b, c, d] = [
            jittered(-1.0, -1.0),
            jittered(1.0, -1.0),
            jittered(1.0, 1.0),
            jittered(-1.0, 1.0),
        ];
        let along = 0.15 + 0.7 * uniform();
        let origin = DVec3::new(uniform() - 0.5, uniform() - 0.5, 3.0 + uniform());
        Self {
            corners: [[a, b, c], [a, c, d]],
            origin,
            along,
            aside: 0.0,
        }
    }

    /// The same case moved by `offset`: a mesh far from the origin, the ray starting as near
    /// it as before.
    pub fn moved(&self, offset: DVec3) -> Self {
        Self {
            corners: self
                .corners
                .map(|triangle| triangle.map(|corner| corner + offset)),
            origin: self.origin + offset,
            ..*self
        }
    }

    /// The same case with the ray aimed `aside` beside the edge, inside B: the exact ray hits
    /// B there, and a test that misses has a crack at least that wide.
    pub fn aimed_aside(&self, aside: f64) -> Self {
        Self { aside, ..*self }
    }

    /// The point of the shared edge the ray is aimed at, as drawn.
    pub fn target(&self) -> DVec3 {
        self.corners[0][0].lerp(self.corners[0][2], self.along)
    }

    /// The two triangles and the ray as precision `V` rounds them; `None` when the rounded
    /// ray has no direction.
    pub fn rounded<V: Vector3>(&self) -> Option<(TriangleSet<V>, Ray<V>)> {
        let triangles = TriangleSet::<V>::from_f64(&self.corners.map(|t| t.map(|c| c.to_array())));
        // Aimed at the edge as rounded, from the origin as rounded: far from the origin the
        // rounding of the corners moves the edge by more than any test errs, and a ray aimed
        // at the edge as drawn would pass decisively inside one triangle. The direction is
        // taken from differences (exact in f64 for corners and origin this close), so that the
        // aim does not worsen with the distance from the origin.
        let widen = |corner: V| DVec3::from_array(corner.to_f64_array());
        let [a, _, c] = triangles.triangles()[0].map(widen);
        let d = widen(triangles.triangles()[1][2]);
        let edge = c - a;
        let into_b = ((d - a) - edge * ((d - a).dot(edge) / edge.length_squared())).normalize();
        let origin = V::from_f64_slice(&self.origin.to_array());
        let direction = (a - widen(origin)) + edge * self.along + into_b * self.aside;
        let ray = Ray::try_new(origin, V::from_f64_slice(&direction.to_array())).ok()?;
        Some((triangles, ray))
    }

    /// Both triangles tested against the ray in precision `V` by `test`, with what the test
    /// computed and what the reference says; `None` when the rounded ray has no direction.
    pub fn test<V: Vector3>(&self, test: HitTest) -> Option<EdgeTest> {
        let (triangles, ray) = self.rounded::<V>()?;
        let options = TraceOptions {
            hit_test: test,
            ..TraceOptions::default()
        };
        let hit = brute_force(&triangles, &ray, &options, &mut NoObserver).map(|hit| Hit {
            primitive: hit.primitive,
            t: hit.t.to_f64(),
        });
        let prepared = triangles.prepare(&ray, test);
        let values = [0, 1].map(|index| {
            triangles
                .explain(&prepared, index, ray.t_min, ray.t_max)
                .widened()
        });
        let reference = ReferenceScene::new(&triangles);
        let judged = reference.reference(&ray);
        let outcome = reference.classify(
            &ray,
            judged.as_ref(),
            hit.map(|hit| hit.primitive),
            Query::Closest,
        );
        let widen = |corner: &V| DVec3::from_array(corner.to_f64_array());
        let stored = triangles.triangles();
        // The hit point as this precision computes it, and how far off the hit triangle's
        // plane it lands (in f64, which holds the rounded numbers exactly).
        let hit_point_off = hit.map(|hit| {
            let point = ray.at(V::Scalar::from_f64(hit.t));
            let [a, b, c] = stored[hit.primitive as usize].each_ref().map(widen);
            let normal = (b - a).cross(c - a).normalize();
            (DVec3::from_array(point.to_f64_array()) - a)
                .dot(normal)
                .abs()
        });
        Some(EdgeTest {
            test,
            precision: precision_of::<V::Scalar>(),
            corners: [
                stored[0].each_ref().map(widen),
                stored[1].each_ref().map(widen),
            ],
            origin: DVec3::from_array(ray.origin.to_f64_array()),
            direction: DVec3::from_array(ray.direction.to_f64_array()),
            values,
            hit,
            reference_t: judged.map(|judged| judged.t),
            hit_point_off,
            outcome,
            coordinate_ulp: V::Scalar::from_f64(
                self.corners
                    .iter()
                    .flatten()
                    .chain([&self.origin])
                    .fold(0.0, |largest, point| largest.max(point.abs().max_element())),
            )
            .ulp()
            .to_f64(),
        })
    }
}

/// Which precision a scalar type is.
fn precision_of<S: Real>() -> Precision {
    if std::mem::size_of::<S>() == 4 {
        Precision::F32
    } else {
        Precision::F64
    }
}

/// A [`SharedEdge`] tested in one precision by one test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeTest {
    /// Which test.
    pub test: HitTest,
    /// In which precision.
    pub precision: Precision,
    /// A's and B's corners as that precision holds them (widened to f64, which is exact).
    pub corners: [[DVec3; 3]; 2],
    /// The ray's origin, so rounded.
    pub origin: DVec3,
    /// Its direction, so rounded.
    pub direction: DVec3,
    /// What the test computed for A and for B, in its precision (widened exactly).
    pub values: [TriangleTestValues<f64>; 2],
    /// The closest hit, by the tie rule when both are hit at the same `t`; `None`: the ray
    /// slipped through.
    pub hit: Option<Hit<f64>>,
    /// Where the reference (f64 on the same rounded numbers, with margins) meets the surface.
    pub reference_t: Option<f64>,
    /// How far the hit point, `origin + t · direction` computed in this precision, lies off
    /// the hit triangle's plane: where a shadow or bounce ray from it would start.
    pub hit_point_off: Option<f64>,
    /// The answer judged against the reference: a slip is a [`Outcome::Leak`].
    pub outcome: Outcome,
    /// How far apart the numbers are in this precision near the largest coordinate of the
    /// triangles and the ray's start: how exactly a corner or a hit point can be placed.
    pub coordinate_ulp: f64,
}

impl EdgeTest {
    /// How far inside triangle `index` (0 = A, 1 = B), across the shared edge, the test put
    /// the ray's point: the weight of the corner facing the edge (≥ 0 inside; exactly, one of
    /// the two is ≥ 0 and the other ≤ 0). `None` where the test stopped before computing it.
    pub fn across(&self, index: usize) -> Option<f64> {
        self.values[index].weight(OPPOSITE[index])
    }

    /// Both triangles report a hit (an exact zero on the shared edge, or rounding's overlap).
    pub fn both_hit(&self) -> bool {
        self.values.iter().all(|values| values.hit)
    }

    /// The hit's `t`, the gap between numbers near it in this precision, and how many such
    /// gaps it lies from the reference's `t` (rounded to a whole number).
    pub fn t_error(&self) -> Option<(f64, f64, f64)> {
        let t = self.hit?.t;
        let ulp = match self.precision {
            Precision::F32 => f64::from((t as f32).ulp()),
            Precision::F64 => t.ulp(),
        };
        let reference = self.reference_t?;
        Some((t, ulp, ((t - reference) / ulp).abs().round()))
    }
}

/// How many of `cases` the ray slips through in precision `V` with `test`, out of how many
/// could be tested (a rounded ray with no direction is left out).
pub fn slip_count<V: Vector3>(cases: &[SharedEdge], test: HitTest) -> (usize, usize) {
    let options = TraceOptions {
        hit_test: test,
        ..TraceOptions::default()
    };
    let mut slipped = 0;
    let mut tested = 0;
    for case in cases {
        let Some((triangles, ray)) = case.rounded::<V>() else {
            continue;
        };
        tested += 1;
        if brute_force(&triangles, &ray, &options, &mut NoObserver).is_none() {
            slipped += 1;
        }
    }
    (slipped, tested)
}

/// A ray exactly through a corner of `bounds` that only touches the box there, found among
/// directions `(p, q) / 64` for `p`, `q` in 1..=64 in order, such that the plain slab test
/// misses the box and the conservative one hits it (Ize 2013); with the numbers of both.
/// The box's corners and the ray's origin are held exactly (the origin is the corner minus
/// a direction of few bits), so the exact answer is a touch at t = 1. `None` if no direction
/// there makes the plain test miss.
pub fn corner_graze<V: Vector>(bounds: &Aabb<V>) -> Option<CornerGraze<V::Scalar>> {
    (1..=64u32)
        .flat_map(|p| (1..=64u32).map(move |q| (p, q)))
        .filter_map(|(p, q)| corner_ray_tested(bounds, p, q))
        .find(|(graze, robust_hits)| graze.t_enter > graze.t_exit && *robust_hits)
        .map(|(graze, _)| graze)
}

/// The slab test's numbers for the ray through the corner (min x, max y) of `bounds` with
/// direction `(p, q) / 64` (through the middle of its other axes), starting one direction
/// before the corner; whether or not the plain test misses. `None` if the origin cannot be
/// held exactly. Lesson 17 gives f32 and f64 the same ray with it.
pub fn corner_ray<V: Vector>(bounds: &Aabb<V>, p: u32, q: u32) -> Option<CornerGraze<V::Scalar>> {
    corner_ray_tested(bounds, p, q).map(|(graze, _)| graze)
}

/// [`corner_ray`], and whether the conservative test hits the box.
fn corner_ray_tested<V: Vector>(
    bounds: &Aabb<V>,
    p: u32,
    q: u32,
) -> Option<(CornerGraze<V::Scalar>, bool)> {
    let sixty_fourth = V::Scalar::from_f64(1.0 / 64.0);
    // Up and right through the corner (min x, max y): left of the box before it, above the
    // box after it.
    let mut direction = V::splat(V::Scalar::ZERO);
    direction[0] = V::Scalar::from_u32(p) * sixty_fourth;
    direction[1] = V::Scalar::from_u32(q) * sixty_fourth;
    let mut corner = bounds.min;
    corner[1] = bounds.max[1];
    for axis in 2..V::DIM {
        // Through the middle of the box's other axes.
        corner[axis] = (bounds.min[axis] + bounds.max[axis]) * V::Scalar::from_f64(0.5);
    }
    let origin = corner - direction;
    // Exactly through the corner: the subtraction must not have rounded.
    if origin + direction != corner {
        return None;
    }
    let ray = Ray::try_new(origin, direction).ok()?;
    let plain = slab_clip_scalar(bounds, &SlabRay::new(&ray, false), ray.t_max);
    let robust = slab_clip_scalar(bounds, &SlabRay::new(&ray, true), ray.t_max);
    let graze = CornerGraze {
        origin: origin.to_f64_array(),
        direction: direction.to_f64_array(),
        t_enter: plain.0,
        t_exit: plain.1,
        t_exit_widened: robust.1,
    };
    Some((graze, robust.0 <= robust.1))
}

/// A ray through a box's corner that the plain slab test misses ([`corner_graze`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerGraze<S> {
    /// Where the ray starts (the corner minus its direction).
    pub origin: [f64; 3],
    /// Its direction.
    pub direction: [f64; 3],
    /// The largest `t_near`, as rounded (exactly 1 without rounding).
    pub t_enter: S,
    /// The smallest `t_far`, as rounded: below `t_enter`, so the plain test misses.
    pub t_exit: S,
    /// The same, times `1 + 2γ(3)`: at or above `t_enter`, so the conservative test hits.
    pub t_exit_widened: S,
}
