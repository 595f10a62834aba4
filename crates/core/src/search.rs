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
}

impl<S: Real> HitSearch<S> {
    /// A search over a ray's interval ending at `t_max`.
    pub(crate) fn new(t_max: S, query: Query) -> Self {
        Self {
            closest: None,
            t_closest: t_max,
            query,
        }
    }

    /// Whether a new closest hit ends the search: at once (true) for an any-hit query; for
    /// [`Query::FirstInCell`] once the leaf is done (`leaf_done` is set). A BVH leaf's hits
    /// all lie in its box, its part of the ray; the kD traversal searches its cells itself.
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

    /// Tests a leaf's primitives (`numbers`, stored from leaf slot `first` on), unless `skip`
    /// says one was tested already. Returns true when the search has its answer (an any-hit
    /// query's first hit, or a [`Query::FirstInCell`] leaf with a hit).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn test_leaf<V, P, O>(
        &mut self,
        primitives: &P,
        prepared: &<P::Set as PrimitiveSet<V>>::RayData,
        t_min: S,
        first: usize,
        numbers: &[u32],
        mut skip: impl FnMut(u32) -> bool,
        observer: &mut O,
    ) -> bool
    where
        V: Vector<Scalar = S>,
        P: LeafPrimitives<V>,
        O: Observer<S>,
    {
        let mut leaf_done = false;
        for (slot, &primitive) in (first..).zip(numbers) {
            if skip(primitive) {
                observer.primitive_skipped(primitive);
                continue;
            }
            let stored = primitives.storage_index(slot, primitive);
            let t_hit = primitives
                .stored()
                .intersect(prepared, stored, t_min, self.t_closest);
            observer.primitive_tested(primitive, t_hit);
            let Some(t) = t_hit else { continue };
            if self.offer(primitive, t, observer, &mut leaf_done) {
                return true;
            }
        }
        leaf_done
    }

    /// A hit at `t` (inside the search interval) on `primitive`: the closest from now on if it
    /// beats the one so far (the least `t`, ties to the lower number, so that every structure
    /// and every order answers alike). True when the search has its answer (see
    /// [`HitSearch::ends_search`]).
    #[inline(always)]
    pub(crate) fn offer<O: Observer<S>>(
        &mut self,
        primitive: u32,
        t: S,
        observer: &mut O,
        leaf_done: &mut bool,
    ) -> bool {
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
}

/// The primitives tested most recently for one ray (Amanatides & Woo 1987's mailbox, per
/// ray), for structures that list a primitive in several leaves or cells: a primitive listed in several leaves along
/// the ray usually meets the ray in consecutive leaves, so a few slots catch most repeats.
#[derive(Default)]
pub(crate) struct Mailbox {
    slots: [u32; 8],
    used: usize,
}

impl Mailbox {
    /// Records `primitive`; false if it was already there (so its test can be skipped).
    #[inline(always)]
    pub(crate) fn post(&mut self, primitive: u32) -> bool {
        let filled = self.used.min(self.slots.len());
        if self.slots[..filled].contains(&primitive) {
            return false;
        }
        self.slots[self.used % self.slots.len()] = primitive;
        self.used += 1;
        true
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
    /// The search, whose leaves test for the closest hit under the pseudo-code's rule
    /// ([`Query::FirstInCell`] ends the search by cells, which the traversal does, not by
    /// leaves as in a BVH).
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
        let leaf_query = match options.query {
            Query::FirstInCell => Query::Closest,
            query => query,
        };
        Some(Self {
            slab_ray,
            t_enter,
            t_exit,
            primitive_ray: primitives.stored().prepare(ray, options.hit_test),
            search: HitSearch::new(ray.t_max, leaf_query),
        })
    }
}
