//! Split events and the SAH sweep over them, shared by both SAH kD builders and by the cost
//! curves, so that what a curve shows is what the builders minimise.
//!
//! For each axis, every primitive's box clipped to the cell gives events: where it starts and
//! where it ends (or one "planar" event if it is flat on that axis). Sorted, one sweep over
//! them knows at each candidate plane how many primitives each side gets, and the cost model
//! `cost = C_trav + P(L)·N_L·C_isect + P(R)·N_R·C_isect` (P by surface area; perimeter in 2D),
//! discounted for a side left empty, costs the cut (MacDonald & Booth 1990; Wald & Havran
//! 2006, "On building fast kd-trees for ray tracing, and on doing that in O(N log N)", §4).

use crate::aabb::Aabb;
use crate::kd::build::Cut;
use crate::math::{Real, Vector};
use crate::sah::SahCost;

/// What an event says about one primitive at one position on one axis. At equal positions,
/// events sort in this order; counts are taken per position, so the order only has to group.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
#[repr(u32)]
pub(crate) enum EventKind {
    /// The clipped box ends here.
    End = 0,
    /// The clipped box is flat here.
    Planar = 1,
    /// The clipped box starts here.
    Start = 2,
}

/// One event: a primitive's clipped box starts, ends, or lies flat at `position`. The kind and
/// the primitive share one word (8 bytes an event in f32), as the sweep streams millions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Event<S> {
    pub(crate) position: S,
    /// `primitive << 2 | kind`.
    tagged: u32,
}

/// The largest primitive number an event can carry.
pub(crate) const MAX_EVENT_PRIMITIVE: u32 = u32::MAX >> 2;

impl<S: Real> Event<S> {
    #[inline(always)]
    pub(crate) fn new(position: S, kind: EventKind, primitive: u32) -> Self {
        debug_assert!(primitive <= MAX_EVENT_PRIMITIVE);
        Self {
            position,
            tagged: primitive << 2 | kind as u32,
        }
    }

    /// The primitive the event belongs to.
    #[inline(always)]
    pub(crate) fn primitive(&self) -> u32 {
        self.tagged >> 2
    }

    /// Which of its three kinds it is.
    #[inline(always)]
    pub(crate) fn kind(&self) -> EventKind {
        match self.tagged & 3 {
            0 => EventKind::End,
            1 => EventKind::Planar,
            _ => EventKind::Start,
        }
    }

    /// Which of its three kinds it is, as `EventKind as usize`.
    #[inline(always)]
    fn kind_index(&self) -> usize {
        (self.tagged & 3) as usize
    }
}

/// The order events are swept in: by position, then ends before flats before starts.
#[inline]
pub(crate) fn event_order<S: Real>(a: &Event<S>, b: &Event<S>) -> std::cmp::Ordering {
    a.position
        .partial_cmp(&b.position)
        .unwrap_or(std::cmp::Ordering::Equal)
        .then((a.tagged & 3).cmp(&(b.tagged & 3)))
}

/// Sorts events by [`event_order`]: by radix (least significant digit first, a byte a pass, the
/// kind first), linear in the count, as the root's lists hold two events per primitive.
/// `scratch` is working space.
pub(crate) fn sort_events<S: Real>(events: &mut Vec<Event<S>>, scratch: &mut Vec<Event<S>>) {
    if events.len() < 512 {
        events.sort_unstable_by(event_order);
        return;
    }
    let kind_pass = |event: &Event<S>| event.kind_index();
    radix_pass(events, scratch, kind_pass);
    for byte in 0..S::KEY_BYTES {
        let digit = |event: &Event<S>| (event.position.order_key() >> (8 * byte)) as usize & 0xff;
        // A byte all keys share (the high ones, often) leaves the order as it is.
        let first = digit(&events[0]);
        if events.iter().all(|event| digit(event) == first) {
            continue;
        }
        radix_pass(events, scratch, digit);
    }
}

/// One stable counting-sort pass by a digit below 256.
fn radix_pass<S: Real>(
    events: &mut Vec<Event<S>>,
    scratch: &mut Vec<Event<S>>,
    digit: impl Fn(&Event<S>) -> usize,
) {
    let mut starts = [0usize; 256];
    for event in events.iter() {
        starts[digit(event)] += 1;
    }
    let mut total = 0;
    for start in starts.iter_mut() {
        let count = *start;
        *start = total;
        total += count;
    }
    scratch.clear();
    scratch.resize(events.len(), events[0]);
    for event in events.iter() {
        let slot = &mut starts[digit(event)];
        scratch[*slot] = *event;
        *slot += 1;
    }
    std::mem::swap(events, scratch);
}

/// The events of primitive `primitive`'s box on one axis, clipped to the cell.
#[inline]
pub(crate) fn push_events<V: Vector>(
    events: &mut Vec<Event<V::Scalar>>,
    primitive: u32,
    bounds: &Aabb<V>,
    cell: &Aabb<V>,
    axis: usize,
) {
    // Adding zero turns −0 into +0, so equal positions have equal sort keys.
    let low = bounds.min[axis].max(cell.min[axis]) + V::Scalar::ZERO;
    let high = bounds.max[axis].min(cell.max[axis]) + V::Scalar::ZERO;
    if low == high {
        events.push(Event::new(low, EventKind::Planar, primitive));
    } else {
        events.push(Event::new(low, EventKind::Start, primitive));
        events.push(Event::new(high, EventKind::End, primitive));
    }
}

/// One candidate cut, costed: what the sweep weighs at each event position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct KdCandidate<S> {
    /// The plane, with the side that primitives lying in it go to (the cheaper one).
    pub(crate) cut: Cut<S>,
    /// Primitives the cell below the plane would hold.
    pub(crate) count_below: usize,
    /// Primitives the cell above the plane would hold.
    pub(crate) count_above: usize,
    /// Half the surface area (2D: the perimeter) of the parent cell and of the cells below and
    /// above the plane.
    pub(crate) half_areas: [f64; 3],
    /// The cost of the cut by the SAH, with the empty-space bonus, times the parent's half
    /// area ([`SahCost::kd_split_cost_scaled`]): what the sweep compares.
    pub(crate) scaled_cost: f64,
}

impl<S> KdCandidate<S> {
    /// The cost of the cut by the SAH, with the empty-space bonus.
    pub(crate) fn cost(&self) -> f64 {
        SahCost::unscale(self.scaled_cost, self.half_areas[0])
    }
}

/// The half area of a cell as a function of its extent on one axis: `slope · length + base`
/// (in 3D `x(y + z) + yz`; in 2D `x + y`), in f64.
#[derive(Clone, Copy)]
struct HalfAreaAlong {
    slope: f64,
    base: f64,
}

impl HalfAreaAlong {
    fn new<V: Vector>(cell: &Aabb<V>, axis: usize) -> Self {
        let extent = |other: usize| (cell.max[other] - cell.min[other]).to_f64();
        let others = (0..V::DIM).filter(|&other| other != axis);
        if V::DIM == 2 {
            Self {
                slope: 1.0,
                base: others.map(extent).sum(),
            }
        } else {
            let [a, b]: [f64; 2] = {
                let mut pair = [0.0; 2];
                for (slot, other) in pair.iter_mut().zip(others) {
                    *slot = extent(other);
                }
                pair
            };
            Self {
                slope: a + b,
                base: a * b,
            }
        }
    }

    #[inline(always)]
    fn at(&self, length: f64) -> f64 {
        self.slope * length + self.base
    }
}

/// Costs a cut of `cell` at every event position strictly inside it, in sweep order (axis by
/// axis, positions ascending), handing each to `visit`. `events_per_axis[axis]` must be sorted
/// by [`event_order`]. Counts follow [`Cut::sides`]: at a plane `p`, the primitives that end at
/// `p` count below only, those starting at `p` above only, and those lying in `p` on whichever
/// side makes the cut cheaper (Wald & Havran 2006, §4.2; ties go below).
#[inline]
pub(crate) fn sweep_candidates<V: Vector>(
    cell: &Aabb<V>,
    events_per_axis: &[Vec<Event<V::Scalar>>],
    primitive_count: usize,
    cost: &SahCost,
    mut visit: impl FnMut(&KdCandidate<V::Scalar>),
) {
    let parent_area = cell.half_area_nonempty().to_f64();
    for (axis, events) in events_per_axis.iter().enumerate().take(V::DIM) {
        let (low, high) = (cell.min[axis], cell.max[axis]);
        let (low_f64, high_f64) = (low.to_f64(), high.to_f64());
        let half_area = HalfAreaAlong::new(cell, axis);
        // Primitives that start (or lie) strictly before the current position, and those that
        // have not ended (or lain) before it.
        let (mut count_below, mut count_above) = (0, primitive_count);
        let mut index = 0;
        while index < events.len() {
            // Count every event at this position by kind.
            let position = events[index].position;
            let mut counts = [0usize; 3];
            while index < events.len() && events[index].position == position {
                counts[events[index].kind_index()] += 1;
                index += 1;
            }
            let [ends, planars, starts] = counts;
            count_above -= planars + ends;
            if low < position && position < high {
                let candidate = costed_cut(
                    &CutSite {
                        axis,
                        low: low_f64,
                        high: high_f64,
                        parent_area,
                        half_area,
                    },
                    position,
                    [count_below, count_above, planars],
                    true,
                    cost,
                );
                visit(&candidate);
            }
            count_below += starts + planars;
        }
    }
}

/// Costs one cut of `cell` at `position` on `axis` by counting the primitives each side gets
/// (the cost curves' binned candidates and middle and median marks), with the same formulas
/// as [`sweep_candidates`], so a plane costed both ways costs the same. With
/// `cheaper_planar_side`, primitives lying in the plane go to the cheaper side as in the
/// sweep; otherwise below, as the middle and median rules put them.
pub(crate) fn cost_of_cut<V: Vector>(
    cell: &Aabb<V>,
    primitive_bounds: &[Aabb<V>],
    primitives: &[u32],
    axis: usize,
    position: V::Scalar,
    cost: &SahCost,
    cheaper_planar_side: bool,
) -> KdCandidate<V::Scalar> {
    let (mut only_below, mut only_above, mut both, mut planars) = (0, 0, 0, 0);
    for &primitive in primitives {
        let bounds = &primitive_bounds[primitive as usize];
        let (low, high) = (bounds.min[axis], bounds.max[axis]);
        if low == position && high == position {
            planars += 1;
        } else if low < position && high > position {
            both += 1;
        } else if low < position {
            only_below += 1;
        } else {
            only_above += 1;
        }
    }
    let site = CutSite {
        axis,
        low: cell.min[axis].to_f64(),
        high: cell.max[axis].to_f64(),
        parent_area: cell.half_area_nonempty().to_f64(),
        half_area: HalfAreaAlong::new(cell, axis),
    };
    costed_cut(
        &site,
        position,
        [only_below + both, only_above + both, planars],
        cheaper_planar_side,
        cost,
    )
}

/// What a cut's cost needs of its cell and axis.
struct CutSite {
    axis: usize,
    low: f64,
    high: f64,
    parent_area: f64,
    half_area: HalfAreaAlong,
}

/// A cut at `position` costed, with `[below, above, planar]` the primitives only below or
/// across, only above or across, and lying in the plane: the one formula of the sweep, the
/// binned candidates and the rule marks. Primitives in the plane go below, or to the cheaper
/// side with `cheaper_planar_side` (ties below).
#[inline(always)]
fn costed_cut<S: Real>(
    site: &CutSite,
    position: S,
    [below, above, planars]: [usize; 3],
    cheaper_planar_side: bool,
    cost: &SahCost,
) -> KdCandidate<S> {
    let at = position.to_f64();
    let half_areas = [
        site.parent_area,
        site.half_area.at(at - site.low),
        site.half_area.at(site.high - at),
    ];
    let cost_of = |count_below, count_above| {
        cost.kd_split_cost_scaled(
            site.parent_area,
            half_areas[1],
            count_below,
            half_areas[2],
            count_above,
        )
    };
    let mut candidate = KdCandidate {
        cut: Cut {
            axis: site.axis,
            position,
            planar_below: true,
        },
        count_below: below + planars,
        count_above: above,
        half_areas,
        scaled_cost: cost_of(below + planars, above),
    };
    if cheaper_planar_side && planars > 0 {
        let planar_above_cost = cost_of(below, above + planars);
        if planar_above_cost < candidate.scaled_cost {
            candidate.cut.planar_below = false;
            candidate.count_below = below;
            candidate.count_above = above + planars;
            candidate.scaled_cost = planar_above_cost;
        }
    }
    candidate
}

/// The cheapest cut of `cell` by a plane through an event position strictly inside it, if any:
/// `(cost, cut)`. Ties go to the lower axis, then the lower position.
pub(crate) fn cheapest_cut<V: Vector>(
    cell: &Aabb<V>,
    events_per_axis: &[Vec<Event<V::Scalar>>],
    primitive_count: usize,
    cost: &SahCost,
) -> Option<(f64, Cut<V::Scalar>)> {
    let mut best: Option<KdCandidate<V::Scalar>> = None;
    sweep_candidates(cell, events_per_axis, primitive_count, cost, |candidate| {
        if best.is_none_or(|best| candidate.scaled_cost < best.scaled_cost) {
            best = Some(*candidate);
        }
    });
    best.map(|best| (best.cost(), best.cut))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngSeed};

    /// Every candidate costed directly: count the boxes each side of the plane gets, with the
    /// boxes lying in the plane put below, then above.
    fn brute_force_cut(cell: &Aabb<DVec3>, boxes: &[Aabb<DVec3>], cost: &SahCost) -> Option<f64> {
        let mut best: Option<f64> = None;
        for axis in 0..3 {
            for bounds in boxes {
                for position in [bounds.min[axis], bounds.max[axis]] {
                    let position = position.clamp(cell.min[axis], cell.max[axis]);
                    if !(cell.min[axis] < position && position < cell.max[axis]) {
                        continue;
                    }
                    for planar_below in [true, false] {
                        let cut = Cut {
                            axis,
                            position,
                            planar_below,
                        };
                        let (mut left, mut right) = (0, 0);
                        for other in boxes {
                            let (below, above) = cut.sides(other);
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

        /// The sweep's cheapest cut costs what the cheapest of all candidates costs.
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
            let swept = cheapest_cut(&cell, &events, boxes.len(), &cost).map(|(c, _)| c);
            let brute = brute_force_cut(&cell, &boxes, &cost);
            prop_assert_eq!(swept.is_some(), brute.is_some());
            if let (Some(swept), Some(brute)) = (swept, brute) {
                prop_assert!((swept - brute).abs() <= 1e-12 * brute, "{swept} vs {brute}");
            }
        }
    }

    proptest! {
        #![proptest_config(Config {
            cases: 200,
            rng_seed: RngSeed::Fixed(0x5047),
            failure_persistence: None,
            ..Config::default()
        })]

        /// The radix sort orders events as the comparison sort does (negative numbers, ±0,
        /// repeats and ties of kind included), and keeps every event.
        #[test]
        fn radix_sort_matches_the_comparison_sort(
            raw in prop::collection::vec((-6i32..6, 0u32..3, prop::bool::ANY), 0..1500),
            scale in prop_oneof![Just(1.0f32), Just(1e-30f32), Just(3e30f32)],
        ) {
            let kinds = [EventKind::End, EventKind::Planar, EventKind::Start];
            let events: Vec<Event<f32>> = raw
                .iter()
                .enumerate()
                .map(|(primitive, &(value, kind, negative_zero))| {
                    let position = if value == 0 && negative_zero { -0.0 } else { value as f32 * scale };
                    Event::new(position + 0.0, kinds[kind as usize], primitive as u32)
                })
                .collect();
            let mut by_radix = events.clone();
            sort_events(&mut by_radix, &mut Vec::new());
            let mut by_comparison = events.clone();
            by_comparison.sort_by(event_order);
            let key = |e: &Event<f32>| (e.position, e.kind_index());
            prop_assert_eq!(
                by_radix.iter().map(key).collect::<Vec<_>>(),
                by_comparison.iter().map(key).collect::<Vec<_>>()
            );
            let mut primitives: Vec<u32> = by_radix.iter().map(Event::primitive).collect();
            primitives.sort_unstable();
            prop_assert_eq!(primitives, (0..events.len() as u32).collect::<Vec<_>>());
        }
    }
}
