//! The SAH kD-tree, built the lecture's first way: sort the split candidates at every node.
//!
//! At each cell, every primitive's box clipped to the cell gives events on each axis (where it
//! starts, ends, or lies flat); sorted, one sweep costs every candidate plane by the SAH, and the
//! cheapest cut is made unless keeping the leaf is cheaper (MacDonald & Booth 1990; Wald &
//! Havran 2006, "On building fast kd-trees for ray tracing, and on doing that in O(N log N)",
//! whose O(N log² N) variant this is). Sorting at each node costs O(n log n) per level.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReason};
use crate::kd::build::{CellSplitter, Cut, KdBuilder, build_top_down};
use crate::kd::events::{Event, cheapest_cut, event_order, push_events};
use crate::kd::tree::KdTree;
use crate::math::Vector;
use crate::params::BuildParams;
use crate::sah::SahCost;

/// The SAH kD builder that sorts the events at each node.
#[derive(Clone, Copy, Debug, Default)]
pub struct KdSah;

/// Sorts each node's events and sweeps them: the state is only reused scratch space.
struct Splitter<'a, V: Vector> {
    bounds: &'a [Aabb<V>],
    cost: SahCost,
    events_per_axis: Vec<Vec<Event<V::Scalar>>>,
}

impl<V: Vector> CellSplitter<V> for Splitter<'_, V> {
    type NodeData = ();

    fn root_data<O: BuildObserver>(&mut self, _: &Aabb<V>, _: &[u32], _: &mut O) {}

    fn choose<O: BuildObserver>(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        _data: &(),
        observer: &mut O,
    ) -> Result<(Cut<V::Scalar>, Option<f64>), LeafReason> {
        let leaf_cost = self.cost.leaf_cost(primitives.len());
        if self.cost.kd_leaf_beats_any_split(primitives.len()) {
            return Err(LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: None,
            });
        }
        // Make and sort each axis's events.
        for (axis, events) in self.events_per_axis.iter_mut().enumerate() {
            events.clear();
            for &primitive in primitives {
                push_events(
                    events,
                    primitive,
                    &self.bounds[primitive as usize],
                    cell,
                    axis,
                );
            }
            events.sort_unstable_by(event_order);
            observer.sorted(axis);
        }
        // One sweep per axis costs every candidate plane.
        let cheapest = cheapest_cut(cell, &self.events_per_axis, primitives.len(), &self.cost);
        (0..V::DIM).for_each(|axis| observer.swept(axis));
        match cheapest {
            // Keep the leaf if no cut is cheaper.
            Some((split_cost, cut)) if split_cost < leaf_cost => Ok((cut, Some(split_cost))),
            cheapest => Err(LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: cheapest.map(|(split_cost, _)| split_cost),
            }),
        }
    }

    fn divide<O: BuildObserver>(
        &mut self,
        _: (),
        _: &Cut<V::Scalar>,
        _: &Aabb<V>,
        _: &Aabb<V>,
        _: &mut O,
    ) -> ((), ()) {
        ((), ())
    }

    fn fork(&self) -> Self {
        Splitter {
            bounds: self.bounds,
            cost: self.cost,
            events_per_axis: vec![Vec::new(); V::DIM],
        }
    }
}

impl KdBuilder for KdSah {
    fn name(&self) -> String {
        "sah".into()
    }

    /// Leaves end where no cut is cheaper than the leaf (or at the depth limit);
    /// `params.max_leaf_size` is not used.
    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> KdTree<V> {
        build_top_down(primitive_bounds, params, 1, observer, || Splitter {
            bounds: primitive_bounds,
            cost: params.cost,
            events_per_axis: vec![Vec::new(); V::DIM],
        })
    }
}
