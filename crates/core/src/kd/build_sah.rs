//! The SAH kD-tree, built the lecture's first way: sort the split candidates at every node.
//!
//! At each cell, every primitive's box clipped to the cell gives events on each axis (where it
//! starts, ends, or lies flat); sorted, one sweep costs every candidate plane by the SAH, and the
//! cheapest cut is made unless keeping the leaf is cheaper (MacDonald & Booth 1990; Wald &
//! Havran 2006, "On building fast kd-trees for ray tracing, and on doing that in O(N log N)",
//! whose O(N log² N) variant this is). Sorting at each node costs O(n log n) per level.

use crate::aabb::Aabb;
use crate::bvh::BuildParams;
use crate::kd::build::{KdBuilder, build_by_rule};
use crate::kd::events::{Event, cheapest_cut, event_order, push_events};
use crate::kd::tree::KdTree;
use crate::math::Vector;

/// The SAH kD builder that sorts the events at each node.
#[derive(Clone, Copy, Debug, Default)]
pub struct KdSah;

impl KdBuilder for KdSah {
    fn name(&self) -> String {
        "sah".into()
    }

    /// Leaves end where no cut is cheaper than the leaf (or at the depth limit);
    /// `params.max_leaf_size` is not used.
    fn build<V: Vector>(&self, primitive_bounds: &[Aabb<V>], params: &BuildParams) -> KdTree<V> {
        let cost = params.cost;
        let mut events_per_axis: Vec<Vec<Event<V::Scalar>>> = vec![Vec::new(); V::DIM];
        let params = BuildParams {
            max_leaf_size: 1,
            ..*params
        };
        build_by_rule(primitive_bounds, &params, |cell, primitives, bounds| {
            // Make and sort each axis's events, then sweep them for the cheapest cut.
            for (axis, events) in events_per_axis.iter_mut().enumerate() {
                events.clear();
                for &primitive in primitives {
                    push_events(events, primitive, &bounds[primitive as usize], cell, axis);
                }
                events.sort_unstable_by(event_order);
            }
            let (split_cost, cut) = cheapest_cut(cell, &events_per_axis, primitives.len(), &cost)?;
            // Keep the leaf if no cut is cheaper.
            (split_cost < cost.leaf_cost(primitives.len())).then_some(cut)
        })
    }
}
