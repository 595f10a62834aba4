//! How a traced ray's answer compares with a reference that is sure of itself: the six
//! outcomes in which the speed/accuracy trade is reported.
//!
//! A configuration under test sees the mesh and the ray rounded to its precision. The
//! reference ([`ReferenceScene`]) takes exactly those values, widened to f64 (which is exact),
//! and decides for every triangle near the ray whether the ray meets it *inside*, on its
//! *boundary*, or not at all. It evaluates the watertight test's three edge functions (Woop,
//! Benthin & Wald 2013) and keeps a margin around each zero: `K · ε · bound`, where `ε` is
//! the unit roundoff of the precision *tested* and `bound` the first-order error bound of
//! that edge function, in the watertight formulation and in Möller–Trumbore's (relative to
//! the first corner, which loses digits when the ray starts far away). This is a forward
//! error filter in the manner of Shewchuk 1997 ("Adaptive precision floating-point arithmetic
//! and fast robust geometric predicates"): outside the margin no test in that precision can
//! decide otherwise, so the reference is decisive there; inside it, the ray passes through an
//! edge or a vertex, where rounding decides which triangle is hit, and what counts is the
//! surface: does it go through there, or only touch it? The ray's neighbourhood says: moved
//! sideways four ways, by a few times the margins' width so that each moved ray is decided,
//! does it meet one of the triangles touched there every time?
//!
//! - A point inside a triangle is an *interior* point of the surface.
//! - An edge or a vertex where the surface covers the ray's neighbourhood (two triangles of a
//!   shared edge, a fan round a vertex, a saddle too) is a *crossing*: the surface goes on
//!   through it, so a ray that misses it has found a crack.
//! - A point on a boundary edge (no neighbour), on a silhouette or a fold (the moved rays miss
//!   on one side), or at the very end of the ray's interval, is a *graze*: rounding decides,
//!   and either answer is right.
//!
//! A ray's [`Outcome`] follows from that and from the primitive the traversal returned.

use glam::DVec3;

use crate::aabb::Aabb;
use crate::bvh::{BinnedSah, Builder, Bvh, TraversalStack, traverse};
use crate::math::{Real, Vector3};
use crate::observer::Observer;
use crate::params::BuildParams;
use crate::primitive::{HitTest, LeafPrimitives, PrimitiveSet, TriangleSet};
use crate::query::{Query, TraceOptions};
use crate::ray::Ray;

/// What a traced ray's answer was, against the reference on the same rounded inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Outcome {
    /// The reference's answer: the same primitive (or none, where it has none).
    Agree,
    /// Another primitive at the same point (the other triangle of a shared edge, a duplicate
    /// face): both answers are right.
    Tie,
    /// The closest point lies on a silhouette or boundary edge or vertex, or at the end of the
    /// ray's interval, and the answer missed it: rounding decides there, so it is no error.
    Graze,
    /// The surface goes through the closest point (a triangle's inside, or an edge or vertex
    /// where the surface covers the ray's neighbourhood), and the ray slipped past it: no hit, or one
    /// beyond it on a shared edge or vertex. A crack.
    Leak,
    /// A hit where the reference has none.
    FalseHit,
    /// A hit on a triangle the ray does not meet, or beyond a triangle's inside (the closest
    /// hit skipped).
    Wrong,
}

impl Outcome {
    /// Every outcome, the right answers first.
    pub const ALL: [Outcome; 6] = [
        Outcome::Agree,
        Outcome::Tie,
        Outcome::Graze,
        Outcome::Leak,
        Outcome::FalseHit,
        Outcome::Wrong,
    ];

    /// The name tables, JSON and ray files use: `agree`, `tie`, `graze`, `leak`,
    /// `false_hit`, `wrong`.
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Agree => "agree",
            Outcome::Tie => "tie",
            Outcome::Graze => "graze",
            Outcome::Leak => "leak",
            Outcome::FalseHit => "false_hit",
            Outcome::Wrong => "wrong",
        }
    }

    /// One line on what it means.
    pub fn about(self) -> &'static str {
        match self {
            Outcome::Agree => "the reference's answer",
            Outcome::Tie => "another triangle at the same point (a shared edge): also right",
            Outcome::Graze => {
                "missed a silhouette or boundary point: rounding decides, not an error"
            }
            Outcome::Leak => "slipped through the surface where it goes on: a crack",
            Outcome::FalseHit => "a hit where the ray meets nothing",
            Outcome::Wrong => "a hit on a triangle the ray does not meet, or beyond the closest",
        }
    }

    /// Leak, false hit and wrong: the answers that are errors.
    pub fn is_error(self) -> bool {
        matches!(self, Outcome::Leak | Outcome::FalseHit | Outcome::Wrong)
    }

    /// Its place in [`Outcome::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// How many rays had each outcome.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OutcomeCounts {
    counts: [u64; 6],
}

impl OutcomeCounts {
    /// Counts one ray.
    pub fn add(&mut self, outcome: Outcome) {
        self.counts[outcome.index()] += 1;
    }

    /// The counts of [`Outcome::ALL`], in its order.
    pub fn from_counts(counts: [u64; 6]) -> Self {
        Self { counts }
    }

    /// Each outcome's count, in [`Outcome::ALL`]'s order.
    pub fn counts(&self) -> [u64; 6] {
        self.counts
    }

    /// Rays with `outcome`.
    pub fn count(&self, outcome: Outcome) -> u64 {
        self.counts[outcome.index()]
    }

    /// Rays counted.
    pub fn total(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// Rays with `outcome` per million rays counted (the six add up to a million; 0 when
    /// nothing was counted).
    pub fn per_million(&self, outcome: Outcome) -> f64 {
        let total = self.total();
        if total == 0 {
            return 0.0;
        }
        self.count(outcome) as f64 * 1e6 / total as f64
    }
}

impl std::ops::AddAssign for OutcomeCounts {
    fn add_assign(&mut self, other: Self) {
        for (count, more) in self.counts.iter_mut().zip(other.counts) {
            *count += more;
        }
    }
}

/// How the ray meets one triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Contact {
    /// Inside it, beyond every margin.
    Inside,
    /// Within a margin of an edge or a corner (or of the interval's end): rounding decides.
    Boundary,
}

/// One triangle the ray meets, inside or on its boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Touch {
    /// The triangle.
    pub primitive: u32,
    /// Where along the ray.
    pub t: f64,
    /// Inside or on the boundary.
    pub contact: Contact,
    /// Within rounding of `t_min` or `t_max`.
    pub at_interval_end: bool,
    /// How far `t` can move by rounding.
    t_tolerance: f64,
    /// How wide the margins around its edges are, sideways to the ray.
    band: f64,
    /// The edges the ray passes within a margin of: bit `i` for the edge opposite corner `i`
    /// (two bits: near the corner between them).
    near_edges: u8,
}

/// What the surface is at the reference's closest point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfacePoint {
    /// Inside a triangle.
    Interior,
    /// An edge or vertex where the surface covers the ray's neighbourhood: it goes on.
    Crossing,
    /// A boundary or silhouette edge or vertex, or the interval's end: rounding decides.
    Graze,
}

/// The reference's answer for one ray that meets the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// The triangles met at the closest point, the reference's answer first. At an interior
    /// point: the triangles met there (a duplicate face ties), the lowest-numbered one met
    /// inside first. At an edge or vertex: every triangle touched in front of the first
    /// interior point, where rounding decides, closest first.
    pub at_closest: Vec<u32>,
    /// Where the closest point is along the ray.
    pub t: f64,
    /// What the surface is there.
    pub point: SurfacePoint,
    /// Beyond an edge or vertex, the triangles at the first interior point (answer first),
    /// if there is one: what a ray that missed a graze hits next.
    pub behind: Vec<u32>,
    /// Some triangle is met inside somewhere in the interval (what an any-hit query must
    /// find).
    pub inside_anywhere: bool,
}

impl Reference {
    /// The reference's own answer.
    pub fn primitive(&self) -> u32 {
        self.at_closest[0]
    }
}

/// The margins' factor over the first-order error bounds: the bounds leave out constants
/// (a handful of roundings each) and second-order terms.
const MARGIN_FACTOR: f64 = 8.0;

/// How much the candidate boxes are widened, in units of the tested precision's unit
/// roundoff times the scene's extent: enough for a margin band around an edge for rays starting
/// up to some fifty scene sizes away.
const BOX_PAD_FACTOR: f64 = 4096.0;

/// A mesh as the reference sees it: the triangles of one precision widened to f64, and a BVH
/// over their boxes (widened by the margins) that finds every triangle a ray may touch.
#[derive(Clone, Debug)]
pub struct ReferenceScene {
    triangles: Margins,
    bvh: Bvh<DVec3>,
    /// How far the boxes were widened.
    box_pad: f64,
    /// Per triangle, where the mesh is open: its edges no other triangle shares (bit `i`:
    /// the edge opposite corner `i`), and its corners on such an edge of any triangle (bit
    /// `3 + j`: corner `j`). A ray through those points grazes the surface's rim.
    open: Vec<u8>,
}

/// The triangles, tested with margins.
#[derive(Clone, Debug)]
struct Margins {
    triangles: Vec<[DVec3; 3]>,
    /// The tested precision's unit roundoff.
    unit_roundoff: f64,
}

impl ReferenceScene {
    /// The reference for configurations that see `triangles` (in their precision).
    pub fn new<V: Vector3>(triangles: &TriangleSet<V>) -> Self {
        let unit_roundoff = V::Scalar::UNIT_ROUNDOFF.to_f64();
        let triangles: Vec<[DVec3; 3]> = triangles
            .triangles()
            .iter()
            .map(|corners| corners.map(|corner| DVec3::from_array(corner.to_f64_array())))
            .collect();
        let scene = Aabb::from_points(triangles.iter().flatten().copied());
        // The margins scale with distances within the scene (the tested arithmetic works on
        // differences of coordinates), and in f64 also with the coordinates themselves.
        let box_pad = if scene.is_empty() {
            0.0
        } else {
            let magnitude = scene.min.abs().max(scene.max.abs()).max_element();
            BOX_PAD_FACTOR * unit_roundoff * scene.extent().max_element()
                + 64.0 * f64::EPSILON * magnitude
        };
        let bounds: Vec<Aabb<DVec3>> = triangles
            .iter()
            .map(|corners| {
                let tight = Aabb::from_points(*corners);
                Aabb::new(
                    tight.min - DVec3::splat(box_pad),
                    tight.max + DVec3::splat(box_pad),
                )
            })
            .collect();
        let bvh = BinnedSah::default().build(&bounds, &BuildParams::default());
        let open = open_features(&triangles);
        Self {
            triangles: Margins {
                triangles,
                unit_roundoff,
            },
            bvh,
            box_pad,
            open,
        }
    }

    /// Whether `touch` lies on the mesh's rim: within a margin of an edge no other triangle
    /// shares, or of a corner on such an edge.
    fn on_rim(&self, touch: &Touch) -> bool {
        let open = self.open[touch.primitive as usize];
        match touch.near_edges.count_ones() {
            0 => false,
            // On one edge.
            1 => open & touch.near_edges != 0,
            // Near a corner: the one the two edges share (the corner no near edge is
            // opposite), or every corner where all three are near (a sliver).
            _ => (0..3).any(|corner| {
                let others = 0b111 & !(1 << corner);
                touch.near_edges & others == others && open & (1 << (3 + corner)) != 0
            }),
        }
    }

    /// How many triangles.
    pub fn len(&self) -> usize {
        self.triangles.triangles.len()
    }

    /// True without triangles.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every triangle `ray` (in the tested precision) meets, inside or on its boundary,
    /// within its interval (up to rounding), in no particular order.
    pub fn touches<V: Vector3>(&self, ray: &Ray<V>) -> Vec<Touch> {
        self.touches_of(&widen(ray))
    }

    fn touches_of(&self, ray: &Ray<DVec3>) -> Vec<Touch> {
        let ray = *ray;
        // The search interval reaches past the ray's by the boxes' padding, so that a
        // triangle touched right at the interval's end is not cut off by its box.
        let pad = self.box_pad / ray.direction.abs().max_element();
        let search = Ray {
            t_min: ray.t_min - pad,
            t_max: ray.t_max + pad,
            ..ray
        };
        let options = TraceOptions {
            query: Query::Closest,
            ..TraceOptions::default()
        }
        .with_robust(true);
        let mut found = Found(Vec::new());
        let mut stack = TraversalStack::new();
        traverse(
            &self.bvh,
            &self.triangles,
            &search,
            &options,
            &mut stack,
            &mut found,
        );
        let prepared = ContactRay::new(&ray);
        let mut touches: Vec<Touch> = found
            .0
            .into_iter()
            .filter_map(|primitive| {
                self.triangles
                    .touch(&prepared, primitive as usize, ray.t_min, ray.t_max)
            })
            .collect();
        touches.sort_by_key(|touch| touch.primitive);
        touches.dedup_by_key(|touch| touch.primitive);
        touches
    }

    /// The reference's answer for `ray`, or `None` when it meets nothing.
    ///
    /// Touches in front of the first interior point are an edge or vertex region, where
    /// rounding decides which triangle, if any, is hit. Whether the surface goes through
    /// there is asked of the ray's neighbourhood: the ray moved sideways, four ways, by a
    /// few times the margins' width (so the moved rays are decided), must meet one of those
    /// triangles every time for a crossing; a ray beside a silhouette misses them on one side.
    pub fn reference<V: Vector3>(&self, ray: &Ray<V>) -> Option<Reference> {
        let ray = widen(ray);
        let mut touches = self.touches_of(&ray);
        touches.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.primitive.cmp(&b.primitive)));
        let closest = *touches.first()?;
        let decided = |touch: &Touch| touch.contact == Contact::Inside && !touch.at_interval_end;
        let first_inside = touches.iter().find(|touch| decided(touch)).copied();
        // The triangles at the first interior point: those within rounding of its t.
        let at_inside: Vec<u32> = first_inside.map_or_else(Vec::new, |inside| {
            let mut group: Vec<&Touch> = touches
                .iter()
                .filter(|touch| {
                    (touch.t - inside.t).abs() <= touch.t_tolerance.max(inside.t_tolerance)
                })
                .collect();
            group.sort_by_key(|touch| (!decided(touch), touch.primitive));
            group.iter().map(|touch| touch.primitive).collect()
        });
        let in_front: Vec<&Touch> = touches
            .iter()
            .filter(|touch| {
                first_inside.is_none_or(|inside| {
                    touch.t < inside.t - touch.t_tolerance.max(inside.t_tolerance)
                })
            })
            .collect();
        let inside_anywhere = first_inside.is_some();
        if in_front.is_empty() {
            return Some(Reference {
                at_closest: at_inside,
                t: closest.t,
                point: SurfacePoint::Interior,
                behind: Vec::new(),
                inside_anywhere,
            });
        }
        let region: Vec<u32> = in_front.iter().map(|touch| touch.primitive).collect();
        let at_end = in_front.iter().any(|touch| touch.at_interval_end);
        // On the rim of an open mesh the surface does not go on, whatever the moved rays
        // meet (a vertex whose triangles cover 242° of its neighbourhood can hold all four).
        let on_rim = in_front.iter().any(|touch| self.on_rim(touch));
        let point = if !at_end && !on_rim && self.goes_through(&ray, &in_front) {
            SurfacePoint::Crossing
        } else {
            SurfacePoint::Graze
        };
        Some(Reference {
            at_closest: region,
            t: closest.t,
            point,
            behind: at_inside,
            inside_anywhere,
        })
    }

    /// Whether the surface of the triangles touched in `region` covers the ray's
    /// neighbourhood: rays moved sideways four ways each meet one of them.
    fn goes_through(&self, ray: &Ray<DVec3>, region: &[&Touch]) -> bool {
        let band = region.iter().map(|touch| touch.band).fold(0.0, f64::max);
        let scale = ray.origin.abs().max_element().max(f64::MIN_POSITIVE);
        let shift = 4.0 * band + 64.0 * f64::EPSILON * scale;
        let prepared = ContactRay::new(ray);
        let [kx, ky, _] = prepared.axes;
        // At an angle no mesh favours, so that a moved ray does not run along an edge from
        // the vertex it was aimed at.
        (0..4).all(|quarter| {
            let angle = 0.4 + f64::from(quarter) * std::f64::consts::FRAC_PI_2;
            let mut origin = ray.origin.to_array();
            origin[kx] += shift * angle.cos();
            origin[ky] += shift * angle.sin();
            let moved = ContactRay {
                origin: DVec3::from_array(origin),
                ..prepared
            };
            region.iter().any(|touch| {
                self.triangles
                    .touch(&moved, touch.primitive as usize, ray.t_min, ray.t_max)
                    .is_some()
            })
        })
    }

    /// Whether `ray` meets triangle `primitive` at all (inside or on its boundary).
    pub fn meets<V: Vector3>(&self, ray: &Ray<V>, primitive: u32) -> bool {
        let ray = widen(ray);
        (primitive as usize) < self.len()
            && self
                .triangles
                .touch(
                    &ContactRay::new(&ray),
                    primitive as usize,
                    ray.t_min,
                    ray.t_max,
                )
                .is_some()
    }

    /// The outcome of a traversal that answered `got` (the primitive hit, if any) for `ray`
    /// under `query`, given the reference's answer for it.
    pub fn classify<V: Vector3>(
        &self,
        ray: &Ray<V>,
        reference: Option<&Reference>,
        got: Option<u32>,
        query: Query,
    ) -> Outcome {
        let Some(reference) = reference else {
            return match got {
                None => Outcome::Agree,
                Some(_) => Outcome::FalseHit,
            };
        };
        match (query, got) {
            (Query::Any, None) if reference.inside_anywhere => Outcome::Leak,
            (Query::Any, None) => match reference.point {
                SurfacePoint::Crossing => Outcome::Leak,
                _ => Outcome::Graze,
            },
            (Query::Any, Some(primitive)) => {
                if self.meets(ray, primitive) {
                    Outcome::Agree
                } else {
                    Outcome::Wrong
                }
            }
            (Query::Closest | Query::FirstInCell, None) => match reference.point {
                SurfacePoint::Interior | SurfacePoint::Crossing => Outcome::Leak,
                // Past a graze into nothing, unless a triangle's inside was behind it.
                SurfacePoint::Graze if reference.behind.is_empty() => Outcome::Graze,
                SurfacePoint::Graze => Outcome::Leak,
            },
            (Query::Closest | Query::FirstInCell, Some(primitive)) => {
                if primitive == reference.primitive() {
                    Outcome::Agree
                } else if reference.at_closest.contains(&primitive) {
                    Outcome::Tie
                } else if !self.meets(ray, primitive) {
                    Outcome::Wrong
                } else {
                    match reference.point {
                        // Beyond a triangle's inside: no rounding lets a ray through there.
                        SurfacePoint::Interior => Outcome::Wrong,
                        // Through an edge or vertex the surface goes on across.
                        SurfacePoint::Crossing => Outcome::Leak,
                        // Past a graze, to what lies behind it (and no farther).
                        SurfacePoint::Graze if reference.behind.contains(&primitive) => {
                            Outcome::Graze
                        }
                        SurfacePoint::Graze if reference.behind.is_empty() => Outcome::Graze,
                        SurfacePoint::Graze => Outcome::Wrong,
                    }
                }
            }
        }
    }

    /// The reference for `ray` and the outcome of answering `got` to it.
    pub fn outcome<V: Vector3>(&self, ray: &Ray<V>, got: Option<u32>, query: Query) -> Outcome {
        self.classify(ray, self.reference(ray).as_ref(), got, query)
    }
}

/// Where each triangle lies on the mesh's rim ([`ReferenceScene::open`]): its corners welded
/// by exact position, an edge open when no other triangle has the same two corners.
fn open_features(triangles: &[[DVec3; 3]]) -> Vec<u8> {
    use std::collections::{HashMap, HashSet};
    let key = |corner: DVec3| corner.to_array().map(f64::to_bits);
    // Edge opposite corner `i`: from corner `i + 1` to corner `i + 2`.
    let edge = |corners: &[DVec3; 3], opposite: usize| {
        let (a, b) = (
            key(corners[(opposite + 1) % 3]),
            key(corners[(opposite + 2) % 3]),
        );
        if a <= b { (a, b) } else { (b, a) }
    };
    let mut uses: HashMap<([u64; 3], [u64; 3]), u32> = HashMap::new();
    for corners in triangles {
        for opposite in 0..3 {
            *uses.entry(edge(corners, opposite)).or_default() += 1;
        }
    }
    let rim_corners: HashSet<[u64; 3]> = uses
        .iter()
        .filter(|(_, count)| **count == 1)
        .flat_map(|((a, b), _)| [*a, *b])
        .collect();
    triangles
        .iter()
        .map(|corners| {
            let mut open = 0u8;
            for index in 0..3 {
                if uses[&edge(corners, index)] == 1 {
                    open |= 1 << index;
                }
                if rim_corners.contains(&key(corners[index])) {
                    open |= 1 << (3 + index);
                }
            }
            open
        })
        .collect()
}

fn widen<V: Vector3>(ray: &Ray<V>) -> Ray<DVec3> {
    Ray {
        origin: DVec3::from_array(ray.origin.to_f64_array()),
        direction: DVec3::from_array(ray.direction.to_f64_array()),
        t_min: ray.t_min.to_f64(),
        t_max: ray.t_max.to_f64(),
    }
}

/// A ray prepared for the margin test: the watertight test's permutation and shear.
#[derive(Clone, Copy, Debug)]
struct ContactRay {
    origin: DVec3,
    direction: DVec3,
    axes: [usize; 3],
    shear: [f64; 3],
}

impl ContactRay {
    fn new(ray: &Ray<DVec3>) -> Self {
        let d = ray.direction.to_array();
        let axis_z = ray.direction.abs().max_position();
        let mut axis_x = (axis_z + 1) % 3;
        let mut axis_y = (axis_x + 1) % 3;
        if d[axis_z] < 0.0 {
            std::mem::swap(&mut axis_x, &mut axis_y);
        }
        Self {
            origin: ray.origin,
            direction: ray.direction,
            axes: [axis_x, axis_y, axis_z],
            shear: [
                d[axis_x] / d[axis_z],
                d[axis_y] / d[axis_z],
                1.0 / d[axis_z],
            ],
        }
    }
}

impl Margins {
    /// How the ray meets triangle `index` within `[t_min, t_max]` (up to rounding), or
    /// `None` where it certainly does not.
    fn touch(&self, ray: &ContactRay, index: usize, t_min: f64, t_max: f64) -> Option<Touch> {
        let corners = self.triangles[index];
        let [kx, ky, kz] = ray.axes;
        let [sx, sy, sz] = ray.shear;
        // Each corner relative to the origin, sheared into ray space, with the size of the
        // terms its coordinates were computed from (their rounding is relative to that).
        let sheared = corners.map(|corner| {
            let p = (corner - ray.origin).to_array();
            let x = p[kx] - sx * p[kz];
            let y = p[ky] - sy * p[kz];
            let size_x = p[kx].abs() + (sx * p[kz]).abs();
            let size_y = p[ky].abs() + (sy * p[kz]).abs();
            (x, y, size_x, size_y, sz * p[kz])
        });
        let [a, b, c] = sheared;
        // The edge functions (the watertight test's U, V, W) and their first-order error
        // bounds: an error in a coordinate times the other factor of its product.
        let edge = |p: (f64, f64, f64, f64, f64), q: (f64, f64, f64, f64, f64)| {
            let value = p.0 * q.1 - p.1 * q.0;
            let bound = p.2 * q.1.abs() + p.0.abs() * q.3 + p.3 * q.0.abs() + p.1.abs() * q.2;
            (value, bound)
        };
        let (mut u, bound_u) = edge(c, b);
        let (mut v, bound_v) = edge(a, c);
        let (mut w, bound_w) = edge(b, a);
        // Möller–Trumbore works relative to the first corner: its triple products err by
        // about |s|·|d|·|edge| (s from the first corner to the origin), which in these units
        // (divided by d_z) is this.
        let norm = |vector: DVec3| vector.length();
        let [p0, p1, p2] = corners;
        let d = ray.direction;
        let moller = norm(ray.origin - p0) * (norm(p1 - p0) + norm(p2 - p0)) * norm(d)
            / d.to_array()[kz].abs();
        let epsilon = MARGIN_FACTOR * self.unit_roundoff;
        let margins = [
            epsilon * (bound_u + moller),
            epsilon * (bound_v + moller),
            epsilon * (bound_w + moller),
        ];
        let mut det = u + v + w;
        if det < 0.0 {
            (u, v, w, det) = (-u, -v, -w, -det);
        }
        // Zero: the ray lies in the triangle's plane (or the triangle has no area), where
        // neither test reports a hit.
        if det.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let functions = [u, v, w];
        if functions
            .iter()
            .zip(&margins)
            .any(|(value, margin)| *value < -margin)
        {
            return None;
        }
        // Each margin's width sideways to the ray: the margin over the edge's length in ray
        // space (the edge function's rate of change as the ray moves).
        let length = |p: (f64, f64, f64, f64, f64), q: (f64, f64, f64, f64, f64)| {
            (p.0 - q.0).hypot(p.1 - q.1).max(f64::MIN_POSITIVE)
        };
        let band = (margins[0] / length(c, b))
            .max(margins[1] / length(a, c))
            .max(margins[2] / length(b, a));
        let inside = functions
            .iter()
            .zip(&margins)
            .all(|(value, margin)| *value > *margin);
        // t from the same sums (the sign folded into det above cancels in the ratio).
        let t = (u * a.4 + v * b.4 + w * c.4) / det;
        let normal = (p1 - p0).cross(p2 - p0);
        let cosine = d.dot(normal).abs() / (d.length() * normal.length());
        let scale = ray.origin.abs().max_element()
            + corners
                .iter()
                .map(|corner| (*corner - ray.origin).abs().max_element())
                .fold(0.0, f64::max);
        let t_tolerance =
            epsilon * scale / (d.abs().max_element() * cosine.max(1e-2)) + f64::MIN_POSITIVE;
        if !(t >= t_min - t_tolerance && t <= t_max + t_tolerance) {
            return None;
        }
        let at_interval_end = (t - t_min).abs() <= t_tolerance || (t - t_max).abs() <= t_tolerance;
        Some(Touch {
            primitive: index as u32,
            t,
            contact: if inside {
                Contact::Inside
            } else {
                Contact::Boundary
            },
            at_interval_end,
            t_tolerance,
            band,
            near_edges: functions
                .iter()
                .zip(&margins)
                .enumerate()
                .filter(|(_, (value, margin))| value.abs() <= **margin)
                .fold(0, |mask, (edge, _)| mask | 1 << edge),
        })
    }
}

/// The triangles the candidate search reached and found touched.
struct Found(Vec<u32>);

impl Observer<f64> for Found {
    fn primitive_tested(&mut self, primitive: u32, t_hit: Option<f64>) {
        if t_hit.is_some() {
            self.0.push(primitive);
        }
    }
}

impl PrimitiveSet<DVec3> for Margins {
    type RayData = (ContactRay, f64, f64);

    fn len(&self) -> usize {
        self.triangles.len()
    }

    fn bounds(&self, index: usize) -> Aabb<DVec3> {
        Aabb::from_points(self.triangles[index])
    }

    fn prepare(&self, ray: &Ray<DVec3>, _test: HitTest) -> Self::RayData {
        (ContactRay::new(ray), ray.t_min, ray.t_max)
    }

    /// Every touched triangle answers the search interval's end, so that no hit culls the
    /// rest: the search visits every box along the ray and the observer hears of each.
    fn intersect(
        &self,
        (ray, t_min, t_max): &Self::RayData,
        index: usize,
        _t_min: f64,
        _t_max: f64,
    ) -> Option<f64> {
        self.touch(ray, index, *t_min, *t_max).map(|_| *t_max)
    }

    fn permuted(&self, order: &[u32]) -> Self {
        Self {
            triangles: order
                .iter()
                .map(|&index| self.triangles[index as usize])
                .collect(),
            unit_roundoff: self.unit_roundoff,
        }
    }
}

impl LeafPrimitives<DVec3> for Margins {
    type Set = Self;

    fn stored(&self) -> &Self {
        self
    }

    fn storage_index(&self, _slot: usize, primitive: u32) -> usize {
        primitive as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brute_force;
    use crate::observer::NoObserver;
    use crate::primitive::PrimitiveSet;
    use glam::Vec3;

    fn scene(triangles: &[[[f64; 3]; 3]]) -> (TriangleSet<Vec3>, ReferenceScene) {
        let set = TriangleSet::<Vec3>::from_f64(triangles);
        let reference = ReferenceScene::new(&set);
        (set, reference)
    }

    fn down_at(x: f32, y: f32) -> Ray<Vec3> {
        Ray::try_new(Vec3::new(x, y, 1.0), Vec3::new(0.0, 0.0, -1.0)).expect("a ray")
    }

    /// The unit square at z = 0 split along its diagonal, both halves facing +z.
    const SQUARE: [[[f64; 3]; 3]; 2] = [
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
    ];

    #[test]
    fn a_ray_through_a_shared_edge_crosses_and_either_triangle_is_right() {
        let (_, reference) = scene(&SQUARE);
        let ray = down_at(0.5, 0.5);
        let found = reference.reference(&ray).expect("a hit");
        assert_eq!(found.at_closest, vec![0, 1]);
        assert_eq!(found.point, SurfacePoint::Crossing);
        assert_eq!(found.t, 1.0);
        let outcome = |got| reference.classify(&ray, Some(&found), got, Query::Closest);
        assert_eq!(outcome(Some(0)), Outcome::Agree);
        assert_eq!(outcome(Some(1)), Outcome::Tie);
        assert_eq!(outcome(None), Outcome::Leak);
        // Well inside one half: an interior point, met by that half alone.
        let inside = reference.reference(&down_at(0.75, 0.25)).expect("a hit");
        assert_eq!(inside.at_closest, vec![0]);
        assert_eq!(inside.point, SurfacePoint::Interior);
    }

    #[test]
    fn a_ray_through_a_shared_vertex_meets_its_whole_fan() {
        // Four triangles around (0, 0, 0), all facing +z.
        let fan = [
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
            [[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]],
        ];
        let (_, reference) = scene(&fan);
        let ray = down_at(0.0, 0.0);
        let found = reference.reference(&ray).expect("a hit");
        assert_eq!(found.at_closest, vec![0, 1, 2, 3]);
        assert_eq!(found.point, SurfacePoint::Crossing);
        assert_eq!(
            reference.classify(&ray, Some(&found), Some(3), Query::Closest),
            Outcome::Tie
        );
        assert_eq!(
            reference.classify(&ray, Some(&found), None, Query::Closest),
            Outcome::Leak
        );
    }

    #[test]
    fn a_silhouette_or_a_boundary_edge_is_a_graze() {
        // A V-shaped valley along the x axis: seen from above, its bottom edge is crossed;
        // seen from the side, along y, the ray only touches that edge.
        let valley = [
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 1.0, 1.0]],
            [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.5, -1.0, 1.0]],
        ];
        let (_, reference) = scene(&valley);
        let from_above = down_at(0.5, 0.0);
        let found = reference.reference(&from_above).expect("a hit");
        assert_eq!(found.point, SurfacePoint::Crossing);
        let from_the_side =
            Ray::try_new(Vec3::new(0.5, -5.0, 0.0), Vec3::new(0.0, 1.0, 0.0)).expect("a ray");
        let found = reference.reference(&from_the_side).expect("a touch");
        assert_eq!(found.at_closest, vec![0, 1]);
        assert_eq!(found.point, SurfacePoint::Graze);
        assert_eq!(
            reference.classify(&from_the_side, Some(&found), None, Query::Closest),
            Outcome::Graze
        );
        // One triangle alone: its edges are the mesh's boundary.
        let (_, single) = scene(&SQUARE[..1]);
        let found = single.reference(&down_at(0.5, 0.5)).expect("a touch");
        assert_eq!(found.point, SurfacePoint::Graze);
        // And the end of the interval: a shadow ray that stops exactly at the surface.
        let stopping = Ray::try_with_interval(
            Vec3::new(0.75, 0.25, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
            0.0,
            1.0,
        )
        .expect("a ray");
        let found = single.reference(&stopping).expect("a touch");
        assert_eq!(found.point, SurfacePoint::Graze);
        assert!(!found.inside_anywhere);
    }

    #[test]
    fn a_duplicate_face_is_a_tie_and_a_farther_or_absent_triangle_is_wrong() {
        let below = [[0.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 1.0, -1.0]];
        let aside = [[5.0, 5.0, 0.0], [6.0, 5.0, 0.0], [6.0, 6.0, 0.0]];
        let (_, reference) = scene(&[SQUARE[0], SQUARE[0], below, aside]);
        let ray = down_at(0.75, 0.25);
        let found = reference.reference(&ray).expect("a hit");
        assert_eq!(found.at_closest, vec![0, 1]);
        assert_eq!(found.point, SurfacePoint::Interior);
        let outcome = |got| reference.classify(&ray, Some(&found), got, Query::Closest);
        assert_eq!(outcome(Some(0)), Outcome::Agree);
        assert_eq!(outcome(Some(1)), Outcome::Tie);
        // Beyond an interior point (the closest hit skipped), or a triangle not met at all.
        assert_eq!(outcome(Some(2)), Outcome::Wrong);
        assert_eq!(outcome(Some(3)), Outcome::Wrong);
        assert_eq!(outcome(None), Outcome::Leak);
        // Any hit along the ray is right for an any-hit query.
        assert_eq!(
            reference.classify(&ray, Some(&found), Some(2), Query::Any),
            Outcome::Agree
        );
        // Nothing there: a hit is false.
        let away = down_at(3.0, 3.0);
        assert_eq!(reference.reference(&away), None);
        assert_eq!(
            reference.outcome(&away, Some(3), Query::Closest),
            Outcome::FalseHit
        );
        assert_eq!(
            reference.outcome(&away, None, Query::Closest),
            Outcome::Agree
        );
    }

    /// Found by a seeded search over jittered squares (the fourth square it tried): f32
    /// values, written in full.
    const LEAK_SQUARE: [[[f64; 3]; 3]; 2] = [
        [
            [-0.9049034118652344, -0.8232514262199402, 0.1941138207912445],
            [1.0515077114105225, -1.1164028644561768, 0.18978121876716614],
            [1.0034525394439697, 1.0243618488311768, 0.1637946218252182],
        ],
        [
            [-0.9049034118652344, -0.8232514262199402, 0.1941138207912445],
            [1.0034525394439697, 1.0243618488311768, 0.1637946218252182],
            [-0.9395909309387207, 1.004438042640686, 0.10606065392494202],
        ],
    ];
    /// The ray's origin and direction (f32).
    const LEAK_RAY: [[f32; 3]; 2] = [
        [0.17927016, -0.163336, 3.8662436],
        [0.76483375, 1.1302383, -3.7015061],
    ];

    /// A square of f32 corners split along a diagonal, and a ray aimed at a point on that
    /// diagonal: the fast test's barycentric coordinates for both halves fall just outside,
    /// and the ray slips through; the watertight test hits one half.
    #[test]
    fn the_fast_f32_test_leaks_through_a_shared_edge_and_the_watertight_one_does_not() {
        let (set, reference) = scene(&LEAK_SQUARE);
        let ray = Ray::try_new(Vec3::from_array(LEAK_RAY[0]), Vec3::from_array(LEAK_RAY[1]))
            .expect("a ray");
        let found = reference.reference(&ray).expect("the ray meets the square");
        assert_eq!(found.point, SurfacePoint::Crossing);
        let answer = |test: HitTest| {
            let options = TraceOptions {
                hit_test: test,
                ..TraceOptions::default()
            };
            brute_force(&set, &ray, &options, &mut NoObserver).map(|hit| hit.primitive)
        };
        assert_eq!(answer(HitTest::Fast), None, "the fast test slips through");
        // Why: for each half, a barycentric coordinate the fast test computed falls just
        // outside [0, 1]; the watertight test's edge functions for one half share a sign.
        for index in 0..2 {
            let fast = set.explain(&set.prepare(&ray, HitTest::Fast), index, 0.0, f32::INFINITY);
            let [u, v, sum] = fast.coordinates;
            let outside = u.is_some_and(|u| !(0.0..=1.0).contains(&u))
                || v.is_some_and(|v| v < 0.0)
                || sum.is_some_and(|sum| sum > 1.0);
            assert!(!fast.hit && outside, "half {index}: {fast:?}");
        }
        let watertight_hits = (0..2)
            .filter(|&index| {
                set.explain(
                    &set.prepare(&ray, HitTest::Watertight),
                    index,
                    0.0,
                    f32::INFINITY,
                )
                .hit
            })
            .count();
        assert!(watertight_hits >= 1);
        assert_eq!(
            reference.classify(&ray, Some(&found), answer(HitTest::Fast), Query::Closest),
            Outcome::Leak
        );
        let watertight = reference.classify(
            &ray,
            Some(&found),
            answer(HitTest::Watertight),
            Query::Closest,
        );
        assert!(matches!(watertight, Outcome::Agree | Outcome::Tie));
    }

    #[test]
    fn counts_add_up_to_a_million() {
        let mut counts = OutcomeCounts::default();
        for (index, outcome) in Outcome::ALL.into_iter().enumerate() {
            for _ in 0..=index * 7 {
                counts.add(outcome);
            }
        }
        let sum: f64 = Outcome::ALL
            .into_iter()
            .map(|outcome| counts.per_million(outcome))
            .sum();
        assert!((sum - 1e6).abs() < 1e-6, "{sum}");
        assert_eq!(counts.count(Outcome::Wrong), 36);
        assert_eq!(OutcomeCounts::default().per_million(Outcome::Agree), 0.0);
    }
}
