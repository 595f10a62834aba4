//! The SAH kD-tree in O(n log n): the lecture's second way to build, sorting once.
//!
//! Wald & Havran 2006, "On building fast kd-trees for ray tracing, and on doing that in
//! O(N log N)": sort each axis's events once at the root, then keep every node's lists sorted
//! while dividing them. Events of primitives that stay on one side keep their order; only a
//! primitive cut by the plane gets new events on the split axis (its box clipped to each child
//! cell), and those few are sorted and merged in. Every node sees exactly the events
//! [`KdSah`](crate::kd::KdSah) would sort for it, so both build the same tree.

use crate::aabb::Aabb;
use crate::bvh::BuildParams;
use crate::kd::build::{CellSplitter, KdBuilder, build_top_down, sides};
use crate::kd::build_sah::{Event, cheapest_cut, event_order, push_events};
use crate::kd::tree::KdTree;
use crate::math::Vector;
use crate::sah::SahCost;

/// The SAH kD builder that sorts the events once (O(n log n)).
#[derive(Clone, Copy, Debug, Default)]
pub struct KdSahPresorted;

struct Splitter<'a, V: Vector> {
    bounds: &'a [Aabb<V>],
    cost: SahCost,
    /// Scratch, by primitive: which sides of the current cut it reaches (bit 0 below, bit 1
    /// above), and whether its split-axis events were already regenerated.
    side: Vec<u8>,
    regenerated: Vec<bool>,
    new_below: Vec<Event<V::Scalar>>,
    new_above: Vec<Event<V::Scalar>>,
}

/// Merges two lists sorted by [`event_order`].
fn merge<S: crate::math::Real>(kept: Vec<Event<S>>, new: &[Event<S>]) -> Vec<Event<S>> {
    if new.is_empty() {
        return kept;
    }
    let mut merged = Vec::with_capacity(kept.len() + new.len());
    let (mut kept, mut new) = (kept.into_iter().peekable(), new.iter().copied().peekable());
    loop {
        let take_new = match (kept.peek(), new.peek()) {
            (Some(a), Some(b)) => event_order(b, a).is_lt(),
            (Some(_), None) => false,
            (None, Some(_)) => true,
            (None, None) => break,
        };
        merged.extend(if take_new { new.next() } else { kept.next() });
    }
    merged
}

impl<V: Vector> CellSplitter<V> for Splitter<'_, V> {
    /// Each axis's events of the node's primitives, sorted.
    type NodeData = Vec<Vec<Event<V::Scalar>>>;

    fn root_data(&mut self, cell: &Aabb<V>, primitives: &[u32]) -> Self::NodeData {
        // Sort once per axis.
        (0..V::DIM)
            .map(|axis| {
                let mut events = Vec::with_capacity(2 * primitives.len());
                for &primitive in primitives {
                    push_events(
                        &mut events,
                        primitive,
                        &self.bounds[primitive as usize],
                        cell,
                        axis,
                    );
                }
                events.sort_unstable_by(event_order);
                events
            })
            .collect()
    }

    fn choose(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        events: &Self::NodeData,
    ) -> Option<(usize, V::Scalar)> {
        let (split_cost, axis, position) =
            cheapest_cut(cell, events, primitives.len(), &self.cost)?;
        // Keep the leaf if no cut is cheaper.
        (split_cost < self.cost.leaf_cost(primitives.len())).then_some((axis, position))
    }

    fn divide(
        &mut self,
        events: Self::NodeData,
        split_axis: usize,
        split: V::Scalar,
        below: &Aabb<V>,
        above: &Aabb<V>,
    ) -> (Self::NodeData, Self::NodeData) {
        // Classify each primitive once (every one has an event on every axis).
        for event in &events[0] {
            let (is_below, is_above) =
                sides(&self.bounds[event.primitive as usize], split_axis, split);
            self.side[event.primitive as usize] = is_below as u8 | (is_above as u8) << 1;
        }
        let mut below_lists = Vec::with_capacity(V::DIM);
        let mut above_lists = Vec::with_capacity(V::DIM);
        for (axis, list) in events.into_iter().enumerate() {
            // Events of primitives on one side keep their order in that side's list.
            let mut below_list = Vec::with_capacity(list.len());
            let mut above_list = Vec::with_capacity(list.len());
            self.new_below.clear();
            self.new_above.clear();
            for event in &list {
                let side = self.side[event.primitive as usize];
                let (is_below, is_above) = (side & 1 != 0, side & 2 != 0);
                if axis == split_axis && is_below && is_above {
                    let bounds = &self.bounds[event.primitive as usize];
                    // Cut by the plane: new events on this axis, clipped to each child.
                    let primitive = event.primitive as usize;
                    if !self.regenerated[primitive] {
                        self.regenerated[primitive] = true;
                        push_events(&mut self.new_below, event.primitive, bounds, below, axis);
                        push_events(&mut self.new_above, event.primitive, bounds, above, axis);
                    }
                    continue;
                }
                if is_below {
                    below_list.push(*event);
                }
                if is_above {
                    above_list.push(*event);
                }
            }
            if axis == split_axis {
                for event in self.new_below.iter() {
                    self.regenerated[event.primitive as usize] = false;
                }
                // Only the cut primitives' events need sorting.
                self.new_below.sort_unstable_by(event_order);
                self.new_above.sort_unstable_by(event_order);
                below_list = merge(below_list, &self.new_below);
                above_list = merge(above_list, &self.new_above);
            }
            below_lists.push(below_list);
            above_lists.push(above_list);
        }
        (below_lists, above_lists)
    }
}

impl KdBuilder for KdSahPresorted {
    fn name(&self) -> String {
        "sah-presorted".into()
    }

    /// Leaves end where no cut is cheaper than the leaf (or at the depth limit);
    /// `params.max_leaf_size` is not used.
    fn build<V: Vector>(&self, primitive_bounds: &[Aabb<V>], params: &BuildParams) -> KdTree<V> {
        let splitter = Splitter {
            bounds: primitive_bounds,
            cost: params.cost,
            side: vec![0; primitive_bounds.len()],
            regenerated: vec![false; primitive_bounds.len()],
            new_below: Vec::new(),
            new_above: Vec::new(),
        };
        build_top_down(primitive_bounds, 1, splitter)
    }
}
