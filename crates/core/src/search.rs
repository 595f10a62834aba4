//! What every traversal does in a leaf, written once: test the listed primitives, keep the
//! closest hit (ties to the lower number), shrink the interval, stop an any-hit query at the
//! first hit, and end a [`Query::FirstInCell`] search after the first leaf with a hit.

use crate::aabb::Aabb;
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::{LeafPrimitives, PrimitiveSet};
use crate::query::{Hit, Query, TraceOptions};
use crate::ray::Ray;
use crate::slab::{SlabRay, slab_clip};

/// A closest- or any-hit search under way.
#[derive(Clone, Copy)]
pub(crate) struct HitSearch<S: Real> {
    /// The best hit so far.
    pub(crate) closest: Option<Hit<S>>,
    /// Where the search interval now ends: the closest hit, or the ray's `t_max`.
    pub(crate) t_closest: S,
    pub(crate) query: Query,
    /// [`Query::FirstInCell`] through cells (kD-trees, octrees): the part of the ray in the
    /// leaf being searched, `[t_near, t_far]`, widened by rounding. The lecture's pseudo-code
    /// tests a leaf's objects against the ray clipped to its cell, so a hit outside that part
    /// is no intersection there; it may be one in the cell where it lies. Everywhere else the
    /// whole line.
    part: (S, S),
    /// The closest hit found outside the part of the ray it was tested in: no answer under
    /// the pseudo-code's rule, unless no cell holds one ([`HitSearch::finish`]).
    outside: Option<Hit<S>>,
}

impl<S: Real> HitSearch<S> {
    /// A search over a ray's interval ending at `t_max`.
    pub(crate) fn new(t_max: S, query: Query) -> Self {
        Self {
            closest: None,
            t_closest: t_max,
            query,
            part: (S::NEG_INFINITY, S::INFINITY),
            outside: None,
        }
    }

    /// Clips the search to a cell's part of the ray, `[t_near, t_far]`, for the leaf tested
    /// next ([`Query::FirstInCell`] only: the pseudo-code's clipped ray). The part is widened
    /// by a few units of rounding, so that a hit at the plane between two cells, computed an
    /// ulp to the other side of it, still counts in the cell that lists its primitive.
    #[inline(always)]
    pub(crate) fn clip_to_cell(&mut self, t_near: S, t_far: S) {
        if self.query == Query::FirstInCell {
            let slack = S::UNIT_ROUNDOFF * S::from_f64(CELL_ROUNDING_UNITS);
            self.part = (t_near - slack * t_near.abs(), t_far + slack * t_far.abs());
        }
    }

    /// Whether a new closest hit ends the search: at once (true) for an any-hit query; for
    /// [`Query::FirstInCell`] once the leaf is done (`leaf_done` is set). A BVH leaf's hits
    /// all lie in its box, its part of the ray; a cell's leaf counts only hits in its own
    /// part ([`HitSearch::clip_to_cell`]).
    #[inline(always)]
    pub(crate) fn ends_search(&self, leaf_done: &mut bool) -> bool {
        match self.query {
            Query::Closest => false,
            Query::Any => true,
            Query::FirstInCell => {
                *leaf_done = true;
                false
            }
        }
    }

    /// Tests a leaf's primitives (`numbers`, stored from leaf slot `first` on), unless
    /// `memory` holds a test of one already. Returns true when the search has its answer (an
    /// any-hit query's first hit, or a [`Query::FirstInCell`] leaf with a hit).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn test_leaf<V, P, O>(
        &mut self,
        primitives: &P,
        prepared: &<P::Set as PrimitiveSet<V>>::RayData,
        t_min: S,
        first: usize,
        numbers: &[u32],
        memory: &mut impl TestMemory<S>,
        observer: &mut O,
    ) -> bool
    where
        V: Vector<Scalar = S>,
        P: LeafPrimitives<V>,
        O: Observer<S>,
    {
        let mut leaf_done = false;
        for (slot, &primitive) in (first..).zip(numbers) {
            let t_hit = if let Some(earlier) = memory.recall(primitive) {
                observer.primitive_skipped(primitive);
                // Tested in an earlier cell: under every rule but the pseudo-code's, its hit
                // (if any) was offered then. The pseudo-code's clipped ray may hold it here.
                if self.query != Query::FirstInCell {
                    continue;
                }
                earlier
            } else {
                let stored = primitives.storage_index(slot, primitive);
                let t_hit = primitives
                    .stored()
                    .intersect(prepared, stored, t_min, self.t_closest);
                observer.primitive_tested(primitive, t_hit);
                memory.keep(primitive, t_hit);
                t_hit
            };
            let Some(t) = t_hit else { continue };
            if self.offer(primitive, t, observer, &mut leaf_done) {
                return true;
            }
        }
        leaf_done
    }

    /// A hit at `t` (inside the search interval) on `primitive`: the closest from now on if it
    /// beats the one so far (the least `t`, ties to the lower number, so that every structure
    /// and every order answers alike) and lies in the part of the ray searched (see
    /// [`HitSearch::clip_to_cell`]). True when the search has its answer (see
    /// [`HitSearch::ends_search`]).
    #[inline(always)]
    pub(crate) fn offer<O: Observer<S>>(
        &mut self,
        primitive: u32,
        t: S,
        observer: &mut O,
        leaf_done: &mut bool,
    ) -> bool {
        let (part_near, part_far) = self.part;
        if !(part_near <= t && t <= part_far) {
            if self
                .outside
                .is_none_or(|hit| hit.is_beaten_by(primitive, t))
            {
                self.outside = Some(Hit { primitive, t });
            }
            return false;
        }
        if self
            .closest
            .is_none_or(|hit| hit.is_beaten_by(primitive, t))
        {
            self.closest = Some(Hit { primitive, t });
            self.t_closest = t;
            observer.closest_hit_updated(primitive, t);
            return self.ends_search(leaf_done);
        }
        false
    }

    /// The answer once every cell is searched. Under the pseudo-code's rule a hit lies in the
    /// part of the ray of some cell that lists its primitive, so one found only outside the
    /// parts it was tested in lies outside them by rounding alone (a cell of a flat box is a
    /// single point of the ray): with no other, it is the answer.
    #[inline(always)]
    pub(crate) fn finish<O: Observer<S>>(&mut self, observer: &mut O) -> Option<Hit<S>> {
        if self.closest.is_none()
            && let Some(hit) = self.outside
        {
            observer.closest_hit_updated(hit.primitive, hit.t);
            self.closest = Some(hit);
        }
        self.closest
    }
}

/// How far, in units of the scalar's roundoff, a hit may lie outside a cell's part of the ray
/// and still count there under the pseudo-code's rule: the hit's `t` (from the primitive
/// test) and the cell's ends (from the planes) are rounded apart, by a few units each. Two
/// hits nearer than that are a tie to every check (the property tests take a relative 1e-5;
/// 64 units of f32's roundoff are 3.8e-6).
const CELL_ROUNDING_UNITS: f64 = 64.0;

/// What a leaf test remembers of the primitives it tested, so that one listed in several
/// leaves or cells along a ray is tested once.
pub(crate) trait TestMemory<S: Real> {
    /// The result of an earlier test of `primitive`, if it is held: `Some(hit)`.
    fn recall(&mut self, primitive: u32) -> Option<Option<S>>;
    /// Holds the result of testing `primitive`.
    fn keep(&mut self, primitive: u32, t_hit: Option<S>);
}

/// No memory: a BVH lists each primitive in one leaf.
pub(crate) struct NoMemory;

impl<S: Real> TestMemory<S> for NoMemory {
    #[inline(always)]
    fn recall(&mut self, _primitive: u32) -> Option<Option<S>> {
        None
    }

    #[inline(always)]
    fn keep(&mut self, _primitive: u32, _t_hit: Option<S>) {}
}

/// The primitives tested most recently for one ray, with each test's result (Amanatides &
/// Woo 1987's mailbox, per ray), for structures that list a primitive in several leaves or
/// cells: a primitive listed in several leaves along the ray usually meets the ray in
/// consecutive leaves, so a few slots catch most repeats. The result is kept, not only the
/// number: under the pseudo-code's rule a hit beyond the cell it was tested in counts later,
/// in its own cell, which a mailbox of numbers alone would lose. So the mailbox saves tests
/// and changes no answer.
pub(crate) struct Mailbox<S: Real> {
    slots: [(u32, Option<S>); 8],
    used: usize,
    enabled: bool,
}

impl<S: Real> Mailbox<S> {
    /// An empty mailbox, or (`enabled` false) one that holds nothing.
    pub(crate) fn new(enabled: bool) -> Self {
        Self {
            slots: [(0, None); 8],
            used: 0,
            enabled,
        }
    }
}

impl<S: Real> TestMemory<S> for Mailbox<S> {
    #[inline(always)]
    fn recall(&mut self, primitive: u32) -> Option<Option<S>> {
        if !self.enabled {
            return None;
        }
        let filled = self.used.min(self.slots.len());
        self.slots[..filled]
            .iter()
            .find(|(held, _)| *held == primitive)
            .map(|&(_, t_hit)| t_hit)
    }

    #[inline(always)]
    fn keep(&mut self, primitive: u32, t_hit: Option<S>) {
        if self.enabled {
            self.slots[self.used % self.slots.len()] = (primitive, t_hit);
            self.used += 1;
        }
    }
}

/// A ray entering the root cell of a structure that cuts space into cells (kD-tree, grid,
/// octree): prepared for box and primitive tests, clipped to the root, and its search begun.
pub(crate) struct CellSearch<V: Vector, P: LeafPrimitives<V>> {
    /// The ray prepared for slab tests.
    pub(crate) slab_ray: SlabRay<V>,
    /// Where it enters the root cell.
    pub(crate) t_enter: V::Scalar,
    /// Where it leaves it.
    pub(crate) t_exit: V::Scalar,
    /// The ray prepared for primitive tests.
    pub(crate) primitive_ray: <P::Set as PrimitiveSet<V>>::RayData,
    /// The search: under the pseudo-code's rule ([`Query::FirstInCell`]) each leaf is clipped
    /// to its cell's part of the ray first ([`HitSearch::clip_to_cell`]).
    pub(crate) search: HitSearch<V::Scalar>,
}

impl<V: Vector, P: LeafPrimitives<V>> CellSearch<V, P> {
    /// What every such traversal does first: clip the ray to the root cell `bounds` and tell
    /// `observer` (node 0's box test); `None` when the ray misses the cell.
    #[inline(always)]
    pub(crate) fn enter<O: Observer<V::Scalar>>(
        bounds: &Aabb<V>,
        primitives: &P,
        ray: &Ray<V>,
        options: &TraceOptions,
        observer: &mut O,
    ) -> Option<Self> {
        let slab_ray = SlabRay::new(ray, options.robust_traversal);
        let (t_enter, t_exit) = slab_clip(bounds, &slab_ray, ray.t_max);
        observer.box_tested(0, t_enter, t_exit, t_enter <= t_exit);
        if t_enter > t_exit {
            return None;
        }
        Some(Self {
            slab_ray,
            t_enter,
            t_exit,
            primitive_ray: primitives.stored().prepare(ray, options.hit_test),
            search: HitSearch::new(ray.t_max, options.query),
        })
    }
}
