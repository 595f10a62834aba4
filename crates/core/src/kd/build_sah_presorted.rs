//! The SAH kD-tree in O(n log n): the lecture's second way to build, sorting once.
//!
//! Wald & Havran 2006, "On building fast kd-trees for ray tracing, and on doing that in
//! O(N log N)": sort each axis's events once at the root, then keep every node's lists sorted
//! while dividing them: a stable split of each list by the side each primitive goes to. Only a
//! primitive cut by the plane changes on the split axis (its box clipped to each child cell
//! ends, or starts, at the plane), and those new events all lie at the plane, so they drop in
//! at one place without sorting. Every node sees exactly the events [`KdSah`](crate::kd::KdSah)
//! would sort for it, so both build the same tree.

use crate::aabb::Aabb;
use crate::bvh::BuildParams;
use crate::kd::build::{CellSplitter, Cut, KdBuilder, build_top_down};
use crate::kd::events::{Event, EventKind, cheapest_cut, push_events, sort_events};
use crate::kd::tree::KdTree;
use crate::math::{Real, Vector};
use crate::sah::SahCost;

/// The SAH kD builder that sorts the events once (O(n log n)).
#[derive(Clone, Copy, Debug, Default)]
pub struct KdSahPresorted;

struct Splitter<'a, V: Vector> {
    bounds: &'a [Aabb<V>],
    cost: SahCost,
    /// Scratch, by primitive: which sides of the current cut it reaches (bit 0 below, bit 1
    /// above).
    side: Vec<u8>,
    /// Scratch: the start events of the primitives the current cut goes through.
    cut_starts: Vec<Event<V::Scalar>>,
    /// Event lists no node needs any more, kept for reuse: a build makes a few lists per node,
    /// and the allocator would otherwise be a good share of the time.
    pool: Vec<Vec<Event<V::Scalar>>>,
}

impl<V: Vector> Splitter<'_, V> {
    /// An empty list with room for `capacity` events.
    fn list(&mut self, capacity: usize) -> Vec<Event<V::Scalar>> {
        let mut list = self.pool.pop().unwrap_or_default();
        list.clear();
        list.reserve(capacity);
        list
    }

    /// A list of exactly `len` events, whatever they are (to be overwritten): a reused list
    /// keeps its old contents, so only growth is filled.
    fn scratch_list(&mut self, len: usize) -> Vec<Event<V::Scalar>> {
        let mut list = self.pool.pop().unwrap_or_default();
        list.resize(len, Event::new(V::Scalar::ZERO, EventKind::End, 0));
        list
    }
}

impl<V: Vector> CellSplitter<V> for Splitter<'_, V> {
    /// Each axis's events of the node's primitives, sorted.
    type NodeData = Vec<Vec<Event<V::Scalar>>>;

    fn root_data(&mut self, cell: &Aabb<V>, primitives: &[u32]) -> Self::NodeData {
        // Sort once per axis.
        let mut scratch = Vec::new();
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
                sort_events(&mut events, &mut scratch);
                events
            })
            .collect()
    }

    fn choose(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        events: &Self::NodeData,
    ) -> Option<Cut<V::Scalar>> {
        if self.cost.kd_leaf_beats_any_split(primitives.len()) {
            return None;
        }
        let (split_cost, cut) = cheapest_cut(cell, events, primitives.len(), &self.cost)?;
        // Keep the leaf if no cut is cheaper.
        (split_cost < self.cost.leaf_cost(primitives.len())).then_some(cut)
    }

    fn divide(
        &mut self,
        events: Self::NodeData,
        cut: &Cut<V::Scalar>,
        _below: &Aabb<V>,
        _above: &Aabb<V>,
    ) -> (Self::NodeData, Self::NodeData) {
        // Classify each primitive once, from its events on the split axis (Wald & Havran 2006,
        // §5.2): a primitive ending at or before the plane is below only, one starting at or
        // after it above only, one lying in it where the cut puts it, and the rest reach both.
        for event in &events[cut.axis] {
            let side = &mut self.side[event.primitive() as usize];
            match event.kind() {
                EventKind::End if event.position <= cut.position => *side = 1,
                EventKind::Start if event.position >= cut.position => *side = 2,
                EventKind::Planar if event.position < cut.position => *side = 1,
                EventKind::Planar if event.position > cut.position => *side = 2,
                EventKind::Planar => *side = if cut.planar_below { 1 } else { 2 },
                EventKind::Start => *side = 3,
                // Its start event came first and said "both" or "above"; only "both" changes.
                EventKind::End => {}
            }
        }
        let mut below_lists = Vec::with_capacity(V::DIM);
        let mut above_lists = Vec::with_capacity(V::DIM);
        for (axis, list) in events.into_iter().enumerate() {
            // Events of primitives on one side keep their order in that side's list.
            let (mut below_list, mut above_list);
            if axis != cut.axis {
                // Without branches: each event is written to both lists, and each list's end
                // moves past it only on the sides its primitive reaches.
                below_list = self.scratch_list(list.len());
                above_list = self.scratch_list(list.len());
                let (mut below_end, mut above_end) = (0, 0);
                for event in &list {
                    let side = self.side[event.primitive() as usize];
                    below_list[below_end] = *event;
                    above_list[above_end] = *event;
                    below_end += (side & 1) as usize;
                    above_end += (side >> 1) as usize;
                }
                below_list.truncate(below_end);
                above_list.truncate(above_end);
            } else {
                below_list = self.list(list.len() + 1);
                above_list = self.list(list.len() + 1);
                // A primitive cut by the plane keeps its start in the list below and its end in
                // the list above; clipped to the child cells it gains an end and a start at the
                // plane. All of these sit at one position, so they go in without sorting: the
                // new ends before anything at the plane in the list below, the new starts after
                // anything but starts at the plane in the list above (the sweep order). Every
                // cut primitive is known by then, since its start lies before the plane.
                let (mut below_done, mut above_done) = (false, false);
                let mut cut_primitives = std::mem::take(&mut self.cut_starts);
                cut_primitives.clear();
                for event in &list {
                    if !below_done && event.position >= cut.position {
                        below_done = true;
                        below_list.extend(cut_primitives.iter().map(|cut_primitive| {
                            Event::new(cut.position, EventKind::End, cut_primitive.primitive())
                        }));
                    }
                    let past_planars = event.position > cut.position
                        || (event.position == cut.position && event.kind() == EventKind::Start);
                    if !above_done && past_planars {
                        above_done = true;
                        above_list.extend(cut_primitives.iter().map(|cut_primitive| {
                            Event::new(cut.position, EventKind::Start, cut_primitive.primitive())
                        }));
                    }
                    match self.side[event.primitive() as usize] {
                        1 => below_list.push(*event),
                        2 => above_list.push(*event),
                        _ if event.kind() == EventKind::Start => {
                            below_list.push(*event);
                            cut_primitives.push(*event);
                        }
                        _ => above_list.push(*event),
                    }
                }
                if !below_done {
                    below_list.extend(cut_primitives.iter().map(|cut_primitive| {
                        Event::new(cut.position, EventKind::End, cut_primitive.primitive())
                    }));
                }
                if !above_done {
                    above_list.extend(cut_primitives.iter().map(|cut_primitive| {
                        Event::new(cut.position, EventKind::Start, cut_primitive.primitive())
                    }));
                }
                self.cut_starts = cut_primitives;
            }
            self.pool.push(list);
            below_lists.push(below_list);
            above_lists.push(above_list);
        }
        (below_lists, above_lists)
    }

    fn discard(&mut self, events: Self::NodeData) {
        self.pool.extend(events);
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
            cut_starts: Vec::new(),
            pool: Vec::new(),
        };
        build_top_down(primitive_bounds, 1, splitter)
    }
}
