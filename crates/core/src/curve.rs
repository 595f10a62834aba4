//! SAH cost curves: for one node of a BVH or a kD-tree, the cost of every candidate split along
//! each axis, with its parts, next to the cost of keeping the node a leaf and to where the
//! middle, median and SAH rules would cut.
//!
//! The curves come from the builders' own code: the kD sweep over sorted events
//! ([`KdSah`](crate::kd::KdSah)), the BVH sweep over sorted centroids
//! ([`SweepSah`](crate::bvh::SweepSah)) and the BVH's bins ([`BinnedSah`](crate::bvh::BinnedSah)),
//! all costed by one [`SahCost`], so the curve's minimum is the split the SAH builder makes.
//!
//! Positions: a kD candidate is its plane. A BVH candidate separates primitives by centroid,
//! so its position is the middle between the two neighbouring centroids (exact) or the plane
//! between two bins (binned).

use crate::aabb::Aabb;
use crate::built::Built;
use crate::bvh::{build_binned, build_sweep};
use crate::kd;
use crate::math::{Real, Vector};
use crate::sah::SahCost;
use crate::structure::Family;

/// One candidate split with the parts of its cost:
/// `cost = C_trav + P(L)·N_L·C_isect + P(R)·N_R·C_isect` (kD: discounted by the empty bonus
/// when a side is empty), with `P(side) = area(side) / area(node)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    /// The axis (0 = x, 1 = y, 2 = z).
    pub axis: usize,
    /// Where the split lies on that axis.
    pub position: f64,
    /// The SAH cost of making it.
    pub cost: f64,
    /// `N_L`: primitives on the left (below the plane).
    pub count_left: usize,
    /// `N_R`: primitives on the right (above the plane).
    pub count_right: usize,
    /// The left child's surface area (2D: perimeter): its box (BVH) or cell (kD).
    pub area_left: f64,
    /// The right child's surface area (2D: perimeter).
    pub area_right: f64,
    /// `P(L)`: the chance that a ray through the node passes through the left child.
    pub p_left: f64,
    /// `P(R)`.
    pub p_right: f64,
}

/// Where one rule cuts the node, and what that costs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mark {
    /// The axis.
    pub axis: usize,
    /// The position on it.
    pub position: f64,
    /// The cost of the cut.
    pub cost: f64,
}

impl From<&Candidate> for Mark {
    fn from(candidate: &Candidate) -> Self {
        Self {
            axis: candidate.axis,
            position: candidate.position,
            cost: candidate.cost,
        }
    }
}

/// The candidates at the planes between `bins` equal bins.
#[derive(Clone, Debug, PartialEq)]
pub struct BinnedCurve {
    /// Bins per axis.
    pub bins: usize,
    /// The candidates of each axis, by position.
    pub axes: Vec<Vec<Candidate>>,
    /// The cheapest binned candidate (on any axis).
    pub best: Option<Mark>,
}

/// Every candidate split of one node, and the alternatives to compare it with.
#[derive(Clone, Debug, PartialEq)]
pub struct CostCurve {
    /// The cost model used.
    pub cost_model: SahCost,
    /// The node's box (BVH) or cell (kD).
    pub bounds: [[f64; 2]; 3],
    /// The node's surface area (2D: perimeter).
    pub area: f64,
    /// How many primitives the node holds.
    pub count: usize,
    /// The cost of keeping the node a leaf: `N·C_isect`.
    pub leaf_cost: f64,
    /// The exact candidates of each axis, by position (every primitive's bound for kD, every
    /// gap between sorted centroids for a BVH).
    pub axes: Vec<Vec<Candidate>>,
    /// Where the middle rule cuts.
    pub middle: Option<Mark>,
    /// Where the median rule cuts.
    pub median: Option<Mark>,
    /// The cheapest exact candidate: the SAH builder's choice (the earliest axis, then the
    /// lowest position, at a tie). The builder keeps a leaf when this is not below
    /// `leaf_cost`.
    pub best: Option<Mark>,
    /// The candidates between bins, when asked for.
    pub binned: Option<BinnedCurve>,
}

fn bounds_array<V: Vector>(bounds: &Aabb<V>) -> [[f64; 2]; 3] {
    let (min, max) = (bounds.min.to_f64_array(), bounds.max.to_f64_array());
    [[min[0], max[0]], [min[1], max[1]], [min[2], max[2]]]
}

/// The cost curve of `node` of a built structure: [`bvh_curve`] or [`kd_curve`] with the
/// node's primitives (and cell), with binned candidates when `bins` is given. A grid's or an
/// octree's cell is space, as a kD cell is: its curve is the kD cuts of it.
pub fn node_curve<V: Vector>(
    built: &Built<V>,
    node: u32,
    primitive_bounds: &[Aabb<V>],
    cost: &SahCost,
    bins: Option<usize>,
) -> CostCurve {
    let primitives = built.primitives_below(node);
    match built.tree.family() {
        Family::Bvh => bvh_curve(primitive_bounds, &primitives, cost, bins),
        Family::Kd | Family::Grid | Family::HashedGrid | Family::Octree => kd_curve(
            primitive_bounds,
            &primitives,
            &built.facts.bounds[node as usize],
            cost,
            bins,
        ),
    }
}

fn best_of(axes: &[Vec<Candidate>]) -> Option<Mark> {
    let mut best: Option<&Candidate> = None;
    for candidate in axes.iter().flatten() {
        if best.is_none_or(|best| candidate.cost < best.cost) {
            best = Some(candidate);
        }
    }
    best.map(Mark::from)
}

/// The cost curve of a BVH node holding `primitives` (numbers into `primitive_bounds`), with
/// binned candidates when `bins` is given. Exact candidates are those of
/// [`SweepSah`](crate::bvh::SweepSah); binned ones those of
/// [`BinnedSah`](crate::bvh::BinnedSah), which bins only the longest axis of the centroids'
/// box (here every axis is shown).
pub fn bvh_curve<V: Vector>(
    primitive_bounds: &[Aabb<V>],
    primitives: &[u32],
    cost: &SahCost,
    bins: Option<usize>,
) -> CostCurve {
    let bounds = primitives.iter().fold(Aabb::empty(), |acc, &primitive| {
        acc.union(primitive_bounds[primitive as usize])
    });
    let area = bounds.area().to_f64();
    let count = primitives.len();
    let centroids: Vec<V> = primitive_bounds.iter().map(Aabb::center).collect();
    let centroid_bounds = Aabb::from_points(primitives.iter().map(|&p| centroids[p as usize]));
    let mut right_areas = vec![0.0; count.max(1)];
    let mut sorted_axes = Vec::with_capacity(V::DIM);
    let axes: Vec<Vec<Candidate>> = (0..V::DIM)
        .map(|axis| {
            let mut list = primitives.to_vec();
            build_sweep::sort_by_centroid(&mut list, &centroids, axis);
            let mut candidates = Vec::with_capacity(count.saturating_sub(1));
            build_sweep::sweep_sorted(
                &list,
                primitive_bounds,
                area,
                cost,
                &mut right_areas,
                |split, area_left, area_right, split_cost| {
                    let before = centroids[list[split - 1] as usize][axis].to_f64();
                    let after = centroids[list[split] as usize][axis].to_f64();
                    candidates.push(Candidate {
                        axis,
                        position: 0.5 * (before + after),
                        cost: split_cost,
                        count_left: split,
                        count_right: count - split,
                        area_left,
                        area_right,
                        p_left: area_left / area,
                        p_right: area_right / area,
                    });
                },
            );
            sorted_axes.push(list);
            candidates
        })
        .collect();
    // The middle and median rules cut the longest axis of the centroids' box; each cut is one
    // of that axis's exact candidates.
    let rule_axis = centroid_bounds.largest_axis();
    let candidate_at = |split: usize| {
        (1..count)
            .contains(&split)
            .then(|| axes[rule_axis][split - 1])
    };
    let median = candidate_at(count / 2).map(|candidate| Mark::from(&candidate));
    let middle = if count > 1 {
        let middle = centroid_bounds.center()[rule_axis];
        let left = sorted_axes[rule_axis]
            .iter()
            .take_while(|&&p| centroids[p as usize][rule_axis] < middle)
            .count();
        // With every centroid on one side the middle rule falls back to the median.
        candidate_at(left).map_or(median, |candidate| {
            Some(Mark {
                position: middle.to_f64(),
                ..Mark::from(&candidate)
            })
        })
    } else {
        None
    };
    let binned = bins.map(|bin_count| {
        let bin_count = bin_count.max(2);
        let half_area = bounds.half_area_nonempty().to_f64();
        let mut right = vec![(0, V::Scalar::ZERO); bin_count];
        let axes: Vec<Vec<Candidate>> = (0..V::DIM)
            .map(|axis| {
                let Some(binning) = build_binned::Binning::new(&centroid_bounds, axis, bin_count)
                else {
                    return Vec::new();
                };
                let mut bins = vec![build_binned::Bin::EMPTY(); bin_count];
                for &primitive in primitives {
                    let centroid = centroids[primitive as usize];
                    bins[binning.bin(centroid[axis])]
                        .add(primitive_bounds[primitive as usize], centroid);
                }
                let mut candidates = Vec::new();
                build_binned::sweep_bins(
                    &bins,
                    &mut right,
                    |plane, left_count, left_area, right_count, right_area| {
                        // As the builder computes it, in the scene's precision.
                        let weighted = left_area * V::Scalar::from_u32(left_count)
                            + right_area * V::Scalar::from_u32(right_count);
                        let split_cost =
                            cost.split_cost_weighted(half_area, weighted.to_f64(), count);
                        let (left_area, right_area) = (left_area.to_f64(), right_area.to_f64());
                        candidates.push(Candidate {
                            axis,
                            position: binning.plane_position(plane).to_f64(),
                            cost: split_cost,
                            count_left: left_count as usize,
                            count_right: right_count as usize,
                            area_left: 2.0 * left_area,
                            area_right: 2.0 * right_area,
                            p_left: left_area / half_area,
                            p_right: right_area / half_area,
                        });
                    },
                );
                candidates
            })
            .collect();
        BinnedCurve {
            bins: bin_count,
            best: best_of(&axes),
            axes,
        }
    });
    CostCurve {
        cost_model: *cost,
        bounds: bounds_array(&bounds),
        area,
        count,
        leaf_cost: cost.leaf_cost(count),
        best: best_of(&axes),
        axes,
        middle,
        median,
        binned,
    }
}

fn kd_candidate<S: Real>(candidate: &kd::events::KdCandidate<S>) -> Candidate {
    let [parent, below, above] = candidate.half_areas;
    Candidate {
        axis: candidate.cut.axis,
        position: candidate.cut.position.to_f64(),
        cost: candidate.cost(),
        count_left: candidate.count_below,
        count_right: candidate.count_above,
        area_left: 2.0 * below,
        area_right: 2.0 * above,
        p_left: below / parent,
        p_right: above / parent,
    }
}

/// The cost curve of a kD cell holding `primitives`, with binned candidates (planes at `bins`
/// equal steps across the cell) when `bins` is given. Exact candidates are those the SAH kD
/// builders sweep.
pub fn kd_curve<V: Vector>(
    primitive_bounds: &[Aabb<V>],
    primitives: &[u32],
    cell: &Aabb<V>,
    cost: &SahCost,
    bins: Option<usize>,
) -> CostCurve {
    use kd::events::{cost_of_cut, push_events, sort_events, sweep_candidates};
    let count = primitives.len();
    let mut scratch = Vec::new();
    let events: Vec<Vec<_>> = (0..V::DIM)
        .map(|axis| {
            let mut events = Vec::with_capacity(2 * count);
            for &primitive in primitives {
                let bounds = &primitive_bounds[primitive as usize];
                push_events(&mut events, primitive, bounds, cell, axis);
            }
            sort_events(&mut events, &mut scratch);
            events
        })
        .collect();
    let mut axes = vec![Vec::new(); V::DIM];
    // The best as the builder picks it: by the scaled cost, first at a tie.
    let mut best: Option<kd::events::KdCandidate<V::Scalar>> = None;
    if count > 0 {
        sweep_candidates(cell, &events, count, cost, |candidate| {
            axes[candidate.cut.axis].push(kd_candidate(candidate));
            if best.is_none_or(|best| candidate.scaled_cost < best.scaled_cost) {
                best = Some(*candidate);
            }
        });
    }
    let rule_mark = |cut: kd::build::Cut<V::Scalar>| {
        let inside = cell.min[cut.axis] < cut.position && cut.position < cell.max[cut.axis];
        inside.then(|| {
            let candidate = cost_of_cut(
                cell,
                primitive_bounds,
                primitives,
                cut.axis,
                cut.position,
                cost,
                false,
            );
            Mark::from(&kd_candidate(&candidate))
        })
    };
    let middle = rule_mark(kd::build_middle::middle_cut(cell));
    let median = (count > 0)
        .then(|| {
            rule_mark(kd::build_median::median_cut(
                cell,
                primitives,
                primitive_bounds,
                &mut Vec::new(),
            ))
        })
        .flatten();
    let binned = bins.map(|bin_count| {
        let bin_count = bin_count.max(2);
        let axes: Vec<Vec<Candidate>> = (0..V::DIM)
            .map(|axis| {
                let (low, high) = (cell.min[axis], cell.max[axis]);
                let step = (high - low) / V::Scalar::from_usize(bin_count);
                (1..bin_count)
                    .map(|plane| low + step * V::Scalar::from_usize(plane))
                    .filter(|&position| low < position && position < high)
                    .map(|position| {
                        let candidate = cost_of_cut(
                            cell,
                            primitive_bounds,
                            primitives,
                            axis,
                            position,
                            cost,
                            true,
                        );
                        kd_candidate(&candidate)
                    })
                    .collect()
            })
            .collect();
        BinnedCurve {
            bins: bin_count,
            best: best_of(&axes),
            axes,
        }
    });
    CostCurve {
        cost_model: *cost,
        bounds: bounds_array(cell),
        area: cell.area().to_f64(),
        count,
        leaf_cost: cost.leaf_cost(count),
        best: best.map(|best| Mark::from(&kd_candidate(&best))),
        axes,
        middle,
        median,
        binned,
    }
}
