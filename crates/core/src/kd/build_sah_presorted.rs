//! The SAH kD-tree in O(n log n): the lecture's second way to build, sorting once.
//!
//! Wald & Havran 2006, "On building fast kd-trees for ray tracing, and on doing that in
//! O(N log N)": sort each axis's events once at the root, then keep every node's lists sorted
//! while dividing them: a stable split of each list by the side each primitive goes to. Only a
//! primitive cut by the plane changes on the split axis (its box clipped to each child cell
//! ends, or starts, at the plane), and those new events all lie at the plane, so they drop in
//! at one place without sorting. Every node sees exactly the events [`KdSah`](crate::kd::KdSah)
//! would sort for it, so both build the same tree.
//!
//! With perfect splits ([`KdSahPresorted::build_with_perfect_splits`]) a cut primitive's box
//! shrinks on every axis, so its events are replaced on every list: the new ones are sorted
//! (they are few) and merged in (WH 2006 §5.3).

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReason, NoBuildObserver};
use crate::kd::build::{CellSplitter, Cut, KdBuilder, build_top_down};
use crate::kd::events::{Event, EventKind, cheapest_cut, event_order, push_events, sort_events};
use crate::kd::tree::KdTree;
use crate::math::{Real, Vector};
use crate::params::BuildParams;
use crate::primitive::PrimitiveSet;
use crate::sah::SahCost;

/// The SAH kD builder that sorts the events once (O(n log n)).
#[derive(Clone, Copy, Debug, Default)]
pub struct KdSahPresorted;

/// What perfect splits need of the primitives: the box of each one's part inside a cell.
trait Clipper<V: Vector> {
    fn clipped_bounds(&self, index: usize, cell: &Aabb<V>) -> Option<Aabb<V>>;
}

impl<V: Vector, P: PrimitiveSet<V>> Clipper<V> for P {
    fn clipped_bounds(&self, index: usize, cell: &Aabb<V>) -> Option<Aabb<V>> {
        PrimitiveSet::clipped_bounds(self, index, cell)
    }
}

/// Each axis's events of a node, sorted.
type EventLists<S> = Vec<Vec<Event<S>>>;

/// A primitive cut by the plane, with the boxes of its parts below and above (if any).
type ClippedPrimitive<V> = (u32, Option<Aabb<V>>, Option<Aabb<V>>);

/// The root's events are sorted on several threads from this many primitives.
const PARALLEL_SORT: usize = 4096;

/// A `side` flag: the primitive's events are replaced by those of its clipped parts.
const CLIPPED: u8 = 4;

struct Splitter<'a, V: Vector> {
    bounds: &'a [Aabb<V>],
    cost: SahCost,
    /// The primitives, for perfect splits.
    clip: Option<&'a (dyn Clipper<V> + Sync)>,
    /// Scratch, by primitive: which sides of the current cut it reaches (bit 0 below, bit 1
    /// above), and [`CLIPPED`].
    side: Vec<u8>,
    /// Scratch, perfect splits: each cut primitive with the boxes of its parts below and above.
    clipped: Vec<ClippedPrimitive<V>>,
    /// Scratch: the start events of the primitives the current cut goes through.
    cut_starts: Vec<Event<V::Scalar>>,
    /// Event lists no node needs any more, kept for reuse: a build makes a few lists per node,
    /// and the allocator would otherwise be a good share of the time.
    pool: Vec<Vec<Event<V::Scalar>>>,
}

impl<V: Vector> Splitter<'_, V> {
    /// `kept` and the (sorted) `new` events merged into one sorted list.
    fn merge(
        &mut self,
        kept: Vec<Event<V::Scalar>>,
        new: &[Event<V::Scalar>],
    ) -> Vec<Event<V::Scalar>> {
        if new.is_empty() {
            return kept;
        }
        let mut merged = self.list(kept.len() + new.len());
        let (mut i, mut j) = (0, 0);
        while i < kept.len() && j < new.len() {
            if event_order(&new[j], &kept[i]).is_lt() {
                merged.push(new[j]);
                j += 1;
            } else {
                merged.push(kept[i]);
                i += 1;
            }
        }
        merged.extend_from_slice(&kept[i..]);
        merged.extend_from_slice(&new[j..]);
        self.pool.push(kept);
        merged
    }

    /// `divide` with perfect splits (Wald & Havran 2006, §5.3): on every axis, the events of
    /// primitives on one side keep their order; each cut primitive's events are replaced by
    /// those of its clipped parts, which are sorted and merged in.
    fn divide_clipped(
        &mut self,
        events: EventLists<V::Scalar>,
        below: &Aabb<V>,
        above: &Aabb<V>,
    ) -> (EventLists<V::Scalar>, EventLists<V::Scalar>) {
        let clipped = std::mem::take(&mut self.clipped);
        let mut scratch = Vec::new();
        let mut below_lists = Vec::with_capacity(V::DIM);
        let mut above_lists = Vec::with_capacity(V::DIM);
        for (axis, list) in events.into_iter().enumerate() {
            let mut below_list = self.list(list.len());
            let mut above_list = self.list(list.len());
            for event in &list {
                match self.side[event.primitive() as usize] {
                    1 => below_list.push(*event),
                    2 => above_list.push(*event),
                    3 => {
                        below_list.push(*event);
                        above_list.push(*event);
                    }
                    _ => {} // Clipped: replaced below.
                }
            }
            let mut new_below = self.list(2 * clipped.len());
            let mut new_above = self.list(2 * clipped.len());
            for &(primitive, below_part, above_part) in &clipped {
                if let Some(part) = below_part {
                    push_events(&mut new_below, primitive, &part, below, axis);
                }
                if let Some(part) = above_part {
                    push_events(&mut new_above, primitive, &part, above, axis);
                }
            }
            sort_events(&mut new_below, &mut scratch);
            sort_events(&mut new_above, &mut scratch);
            below_list = self.merge(below_list, &new_below);
            above_list = self.merge(above_list, &new_above);
            self.pool.extend([new_below, new_above, list]);
            below_lists.push(below_list);
            above_lists.push(above_list);
        }
        self.clipped = clipped;
        (below_lists, above_lists)
    }

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
    type NodeData = EventLists<V::Scalar>;

    fn root_data<O: BuildObserver>(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        observer: &mut O,
    ) -> Self::NodeData {
        // Sort once per axis.
        let sorted = |axis: usize, scratch: &mut Vec<Event<V::Scalar>>| {
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
            sort_events(&mut events, scratch);
            events
        };
        if !O::ACTIVE && primitives.len() >= PARALLEL_SORT && crate::parallel::has_threads() {
            // The axes at once: the one part of the build no fork shares.
            use rayon::prelude::*;
            return (0..V::DIM)
                .into_par_iter()
                .map(|axis| sorted(axis, &mut Vec::new()))
                .collect();
        }
        let mut scratch = Vec::new();
        (0..V::DIM)
            .map(|axis| {
                let events = sorted(axis, &mut scratch);
                observer.sorted(axis);
                events
            })
            .collect()
    }

    fn choose<O: BuildObserver>(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        events: &Self::NodeData,
        observer: &mut O,
    ) -> Result<(Cut<V::Scalar>, Option<f64>), LeafReason> {
        let leaf_cost = self.cost.leaf_cost(primitives.len());
        if self.cost.kd_leaf_beats_any_split(primitives.len()) {
            return Err(LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: None,
            });
        }
        // One sweep per axis over the lists, already sorted, costs every candidate plane.
        let cheapest = cheapest_cut(cell, events, primitives.len(), &self.cost);
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

    fn classify(
        &mut self,
        events: &Self::NodeData,
        cut: &Cut<V::Scalar>,
        below: &Aabb<V>,
        above: &Aabb<V>,
    ) {
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
        // Perfect splits: a primitive the plane goes through is clipped to each child cell; it
        // goes only where some part of it is, with the box of that part.
        if let Some(clip) = self.clip {
            self.clipped.clear();
            for event in &events[cut.axis] {
                let primitive = event.primitive();
                if event.kind() != EventKind::Start || self.side[primitive as usize] != 3 {
                    continue;
                }
                let below_part = clip.clipped_bounds(primitive as usize, below);
                let above_part = clip.clipped_bounds(primitive as usize, above);
                self.side[primitive as usize] =
                    CLIPPED | below_part.is_some() as u8 | (above_part.is_some() as u8) << 1;
                self.clipped.push((primitive, below_part, above_part));
            }
        }
    }

    fn sides_of(&self, primitive: u32, _cut: &Cut<V::Scalar>, _bounds: &Aabb<V>) -> (bool, bool) {
        let side = self.side[primitive as usize];
        (side & 1 != 0, side & 2 != 0)
    }

    fn divide<O: BuildObserver>(
        &mut self,
        events: Self::NodeData,
        cut: &Cut<V::Scalar>,
        below: &Aabb<V>,
        above: &Aabb<V>,
        observer: &mut O,
    ) -> (Self::NodeData, Self::NodeData) {
        observer.lists_divided();
        let mut below_lists = Vec::with_capacity(V::DIM);
        let mut above_lists = Vec::with_capacity(V::DIM);
        if self.clip.is_some() {
            return self.divide_clipped(events, below, above);
        }
        for (axis, list) in events.into_iter().enumerate() {
            // Events of primitives on one side keep their order in that side's list.
            let (mut below_list, mut above_list);
            if axis != cut.axis {
                // Without branches: each event is written to both lists, and each list's end
                // moves past it only on the sides its primitive reaches.
                below_list = self.scratch_list(list.len());
                above_list = self.scratch_list(list.len());
                let (mut below_end, mut above_end) = (0, 0);
                // Slices, so the loop keeps their addresses in registers.
                let (below_slots, above_slots) = (&mut below_list[..], &mut above_list[..]);
                let sides = &self.side[..];
                for event in &list {
                    let side = sides[event.primitive() as usize];
                    below_slots[below_end] = *event;
                    above_slots[above_end] = *event;
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

    fn fork(&self) -> Self {
        Splitter::with_cost(self.bounds, self.cost, self.clip)
    }
}

impl KdBuilder for KdSahPresorted {
    fn name(&self) -> String {
        "sah-presorted".into()
    }

    /// Leaves end where no cut is cheaper than the leaf (or at the depth limit);
    /// `params.max_leaf_size` is not used.
    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> KdTree<V> {
        build_top_down(primitive_bounds, params, 1, observer, || {
            Splitter::new(primitive_bounds, params, None)
        })
    }
}

impl KdSahPresorted {
    /// Builds with perfect splits: a primitive cut by a plane is clipped to each child cell
    /// (a triangle as a polygon, Sutherland & Hodgman 1974), so each child sees the box of the
    /// part in it, or nothing if no part is (Havran 2000, §4.5; Wald & Havran 2006, §4.3).
    /// Tighter events make cheaper trees, at the price of clipping during the build.
    pub fn build_with_perfect_splits<V: Vector, P: PrimitiveSet<V>>(
        &self,
        primitives: &P,
        params: &BuildParams,
    ) -> KdTree<V> {
        self.build_with_perfect_splits_observed(primitives, params, &mut NoBuildObserver)
    }

    /// [`build_with_perfect_splits`](Self::build_with_perfect_splits), telling `observer`
    /// about each node.
    pub fn build_with_perfect_splits_observed<V: Vector, P: PrimitiveSet<V>, O: BuildObserver>(
        &self,
        primitives: &P,
        params: &BuildParams,
        observer: &mut O,
    ) -> KdTree<V> {
        let bounds = primitives.all_bounds();
        build_top_down(&bounds, params, 1, observer, || {
            Splitter::new(&bounds, params, Some(primitives))
        })
    }
}

impl<'a, V: Vector> Splitter<'a, V> {
    fn new(
        bounds: &'a [Aabb<V>],
        params: &BuildParams,
        clip: Option<&'a (dyn Clipper<V> + Sync)>,
    ) -> Self {
        Self::with_cost(bounds, params.cost, clip)
    }

    /// A splitter with empty scratch (a new build's, or a fork's).
    fn with_cost(
        bounds: &'a [Aabb<V>],
        cost: SahCost,
        clip: Option<&'a (dyn Clipper<V> + Sync)>,
    ) -> Self {
        Self {
            bounds,
            cost,
            clip,
            side: vec![0; bounds.len()],
            clipped: Vec::new(),
            cut_starts: Vec::new(),
            pool: Vec::new(),
        }
    }
}
