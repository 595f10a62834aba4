//! What every traversal does in a leaf, written once: test the listed primitives, keep the
//! closest hit (ties to the lower number), shrink the interval, stop an any-hit query at the
//! first hit, and end a [`Query::FirstInCell`] search after the first leaf with a hit.

use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::{LeafPrimitives, PrimitiveSet};
use crate::query::{Hit, Query};

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
            if self
                .closest
                .is_none_or(|hit| hit.is_beaten_by(primitive, t))
            {
                self.closest = Some(Hit { primitive, t });
                self.t_closest = t;
                observer.closest_hit_updated(primitive, t);
                if self.ends_search(&mut leaf_done) {
                    return true;
                }
            }
        }
        leaf_done
    }
}
