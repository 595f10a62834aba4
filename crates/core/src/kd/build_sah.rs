//! The SAH kD-tree, built the lecture's first way: sort the split candidates at every node.
//!
//! For each axis, every primitive's box clipped to the cell gives events: where it starts and
//! where it ends (or one "planar" event if it is flat on that axis). Sorted, one sweep over
//! them knows at each candidate plane how many primitives reach each side, and the cost model
//! `cost = C_trav + P(L)·N_L·C_isect + P(R)·N_R·C_isect` (P by surface area; perimeter in 2D),
//! discounted for a side left empty, picks the cut; a cell stays a leaf when no cut is cheaper
//! than testing its primitives (MacDonald & Booth 1990; Wald & Havran 2006, "On building fast
//! kd-trees for ray tracing, and on doing that in O(N log N)", whose O(N log² N) variant this
//! is). Sorting at each node costs O(n log n) per level.

use crate::aabb::Aabb;
use crate::bvh::BuildParams;
use crate::kd::build::{KdBuilder, build_by_rule};
use crate::kd::tree::KdTree;
use crate::math::{Real, Vector};
use crate::sah::SahCost;

/// The SAH kD builder that sorts the events at each node.
#[derive(Clone, Copy, Debug, Default)]
pub struct KdSah;

/// What an event says about one primitive at one position on one axis. The order matters only
/// for sorting; counts are taken per position.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum EventKind {
    /// The clipped box ends here.
    End,
    /// The clipped box is flat here.
    Planar,
    /// The clipped box starts here.
    Start,
}

/// One event: a primitive's clipped box starts, ends, or lies flat at `position`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Event<S> {
    pub(crate) position: S,
    pub(crate) kind: EventKind,
    pub(crate) primitive: u32,
}

/// The order events are swept in: by position, then ends before flats before starts.
pub(crate) fn event_order<S: Real>(a: &Event<S>, b: &Event<S>) -> std::cmp::Ordering {
    a.position
        .partial_cmp(&b.position)
        .unwrap_or(std::cmp::Ordering::Equal)
        .then(a.kind.cmp(&b.kind))
}

/// The cheapest cut of `cell` by a plane through an event position, if any lies strictly
/// inside the cell: `(cost, axis, position)`. `events_per_axis[axis]` must be sorted by
/// position. A primitive touching the plane counts on both sides, as the builders place it.
/// Ties go to the lower axis, then the lower position.
pub(crate) fn cheapest_cut<V: Vector>(
    cell: &Aabb<V>,
    events_per_axis: &[Vec<Event<V::Scalar>>],
    primitive_count: usize,
    cost: &SahCost,
) -> Option<(f64, usize, V::Scalar)> {
    // Half areas: the cost needs only their ratios, and cells here are never empty.
    let parent_area = cell.half_area_nonempty().to_f64();
    let mut best: Option<(f64, usize, V::Scalar)> = None;
    for (axis, events) in events_per_axis.iter().enumerate().take(V::DIM) {
        // Counts of events strictly before the current position.
        let (mut started, mut planar_before, mut ended_before) = (0, 0, 0);
        let mut index = 0;
        while index < events.len() {
            // Gather every event at this position.
            let position = events[index].position;
            let (mut starts, mut planars, mut ends) = (0, 0, 0);
            while index < events.len() && events[index].position == position {
                match events[index].kind {
                    EventKind::Start => starts += 1,
                    EventKind::Planar => planars += 1,
                    EventKind::End => ends += 1,
                }
                index += 1;
            }
            if cell.min[axis] < position && position < cell.max[axis] {
                let left_count = started + starts + planar_before + planars;
                let right_count = primitive_count - ended_before - planar_before;
                let mut left = *cell;
                let mut right = *cell;
                left.max[axis] = position;
                right.min[axis] = position;
                let split_cost = cost.kd_split_cost(
                    parent_area,
                    left.half_area_nonempty().to_f64(),
                    left_count,
                    right.half_area_nonempty().to_f64(),
                    right_count,
                );
                if best.is_none_or(|(best_cost, _, _)| split_cost < best_cost) {
                    best = Some((split_cost, axis, position));
                }
            }
            started += starts;
            planar_before += planars;
            ended_before += ends;
        }
    }
    best
}

/// The events of primitive `primitive`'s box on one axis, clipped to the cell.
pub(crate) fn push_events<V: Vector>(
    events: &mut Vec<Event<V::Scalar>>,
    primitive: u32,
    bounds: &Aabb<V>,
    cell: &Aabb<V>,
    axis: usize,
) {
    let low = bounds.min[axis].max(cell.min[axis]);
    let high = bounds.max[axis].min(cell.max[axis]);
    let event = |position, kind| Event {
        position,
        kind,
        primitive,
    };
    if low == high {
        events.push(event(low, EventKind::Planar));
    } else {
        events.push(event(low, EventKind::Start));
        events.push(event(high, EventKind::End));
    }
}

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
            let (split_cost, axis, position) =
                cheapest_cut(cell, &events_per_axis, primitives.len(), &cost)?;
            // Keep the leaf if no cut is cheaper.
            (split_cost < cost.leaf_cost(primitives.len())).then_some((axis, position))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kd::build::sides;
    use glam::DVec3;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngSeed};

    /// Every candidate costed directly: count the boxes reaching each side of the plane.
    fn brute_force_cut(cell: &Aabb<DVec3>, boxes: &[Aabb<DVec3>], cost: &SahCost) -> Option<f64> {
        let mut best: Option<f64> = None;
        for axis in 0..3 {
            for bounds in boxes {
                for position in [bounds.min[axis], bounds.max[axis]] {
                    let position = position.clamp(cell.min[axis], cell.max[axis]);
                    if !(cell.min[axis] < position && position < cell.max[axis]) {
                        continue;
                    }
                    let (mut left, mut right) = (0, 0);
                    for other in boxes {
                        let (below, above) = sides(other, axis, position);
                        left += below as usize;
                        right += above as usize;
                    }
                    let (mut left_cell, mut right_cell) = (*cell, *cell);
                    left_cell.max[axis] = position;
                    right_cell.min[axis] = position;
                    let value = cost.kd_split_cost(
                        cell.area(),
                        left_cell.area(),
                        left,
                        right_cell.area(),
                        right,
                    );
                    best = Some(best.map_or(value, |best: f64| best.min(value)));
                }
            }
        }
        best
    }

    proptest! {
        #![proptest_config(Config {
            cases: 300,
            rng_seed: RngSeed::Fixed(0x6d5a),
            failure_persistence: None,
            ..Config::default()
        })]

        /// The sweep's cheapest cut costs exactly what the cheapest of all candidates costs.
        #[test]
        fn sweep_finds_the_cheapest_candidate(
            corners in prop::collection::vec(
                ([-4i32..4, -4i32..4, -4i32..4], [0i32..3, 0i32..3, 0i32..3]),
                1..25,
            ),
        ) {
            let boxes: Vec<Aabb<DVec3>> = corners
                .iter()
                .map(|(low, size)| {
                    let low = DVec3::new(low[0] as f64, low[1] as f64, low[2] as f64);
                    Aabb::new(low, low + DVec3::new(size[0] as f64, size[1] as f64, size[2] as f64))
                })
                .collect();
            let cell = boxes.iter().fold(Aabb::empty(), |acc, b| acc.union(*b));
            let cost = SahCost::default();
            let mut events = vec![Vec::new(); 3];
            for (axis, events) in events.iter_mut().enumerate() {
                for (primitive, bounds) in boxes.iter().enumerate() {
                    push_events(events, primitive as u32, bounds, &cell, axis);
                }
                events.sort_by(event_order);
            }
            let swept = cheapest_cut(&cell, &events, boxes.len(), &cost).map(|(c, _, _)| c);
            prop_assert_eq!(swept, brute_force_cut(&cell, &boxes, &cost));
        }
    }
}
