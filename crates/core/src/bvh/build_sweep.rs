//! Full-sweep SAH: exact over every candidate, built the lecture's second way, "without sort".
//!
//! Sort the primitives by centroid once per axis, then keep the `DIM` sorted lists through the
//! recursion: after choosing a split on one axis, the other lists are partitioned *stably* by
//! a per-primitive flag, which keeps them sorted in O(n). Each node then sweeps every list once
//! from each side to cost every split between neighbours (MacDonald & Booth 1990; the sorted
//! lists follow Wald 2007 §2 and Wald & Havran 2006). O(n log n) for the sort plus O(n) per
//! level.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReason};
use crate::bvh::build::{Builder, RangeSplitter, Split, build_top_down};
use crate::bvh::tree::Bvh;
use crate::math::{Real, Vector};
use crate::params::BuildParams;
use crate::sah::SahCost;

/// The exact SAH builder that sorts once per axis.
#[derive(Clone, Copy, Debug, Default)]
pub struct SweepSah;

struct Splitter<'a, V: Vector> {
    bounds: &'a [Aabb<V>],
    /// One list per axis, each sorted by centroid on that axis within every node's range.
    sorted: Vec<Vec<u32>>,
    goes_left: Vec<bool>,
    right_areas: Vec<f64>,
    scratch: Vec<u32>,
    max_leaf_size: usize,
    cost: SahCost,
}

/// Costs the split before each primitive of `list` (sorted by centroid on one axis): for each
/// `split` in `1..list.len()`, `visit(split, left_area, right_area, cost)` with the first
/// `split` primitives on the left. Shared by the builder and the cost curves. `right_areas` is
/// scratch space of at least `list.len()` entries.
pub(crate) fn sweep_sorted<V: Vector>(
    list: &[u32],
    bounds: &[Aabb<V>],
    parent_area: f64,
    cost: &SahCost,
    right_areas: &mut [f64],
    mut visit: impl FnMut(usize, f64, f64, f64),
) {
    let count = list.len();
    // Sweep from the right: the area of every suffix.
    let mut right = Aabb::empty();
    for split in (1..count).rev() {
        right = right.union(bounds[list[split] as usize]);
        right_areas[split] = right.area().to_f64();
    }
    // Sweep from the left, costing the split before each primitive.
    let mut left = Aabb::empty();
    for split in 1..count {
        left = left.union(bounds[list[split - 1] as usize]);
        let left_area = left.area().to_f64();
        let right_area = right_areas[split];
        let split_cost = cost.split_cost(parent_area, left_area, split, right_area, count - split);
        visit(split, left_area, right_area, split_cost);
    }
}

/// Sorts primitive numbers by centroid on `axis`, ties by number (so the tree does not depend
/// on the sort).
pub(crate) fn sort_by_centroid<V: Vector>(list: &mut [u32], centroids: &[V], axis: usize) {
    list.sort_unstable_by(|&a, &b| {
        let (ca, cb) = (centroids[a as usize][axis], centroids[b as usize][axis]);
        ca.partial_cmp(&cb)
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(a.cmp(&b))
    });
}

impl<V: Vector> Splitter<'_, V> {
    fn range_bounds(&self, axis: usize, begin: usize, end: usize) -> Aabb<V> {
        self.sorted[axis][begin..end]
            .iter()
            .fold(Aabb::empty(), |acc, &index| {
                acc.union(self.bounds[index as usize])
            })
    }
}

impl<V: Vector> RangeSplitter<V> for Splitter<'_, V> {
    type NodeInfo = ();

    fn root(&self) -> (Aabb<V>, ()) {
        (self.range_bounds(0, 0, self.bounds.len()), ())
    }

    fn split(
        &mut self,
        begin: usize,
        end: usize,
        node_bounds: &Aabb<V>,
        _info: &(),
    ) -> Result<Split<V, ()>, LeafReason> {
        let count = end - begin;
        if count <= self.max_leaf_size && self.cost.leaf_beats_any_split(count) {
            return Err(LeafReason::LeafCheaper {
                leaf_cost: self.cost.leaf_cost(count),
                split_cost: None,
            });
        }
        let parent_area = node_bounds.area().to_f64();
        let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, left count)
        for axis in 0..V::DIM {
            let list = &self.sorted[axis][begin..end];
            sweep_sorted(
                list,
                self.bounds,
                parent_area,
                &self.cost,
                &mut self.right_areas,
                |split, _, _, cost| {
                    if best.is_none_or(|(best_cost, _, _)| cost < best_cost) {
                        best = Some((cost, axis, split));
                    }
                },
            );
        }
        let Some((best_cost, axis, left_count)) = best else {
            return Err(LeafReason::Inseparable { count });
        };
        // Keep the leaf if no split is cheaper (and the leaf is small enough).
        let leaf_cost = self.cost.leaf_cost(count);
        if count <= self.max_leaf_size && leaf_cost <= best_cost {
            return Err(LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: Some(best_cost),
            });
        }
        let mid = begin + left_count;
        // Flag the left side, then partition the other lists stably so they stay sorted.
        for &index in &self.sorted[axis][begin..end] {
            self.goes_left[index as usize] = false;
        }
        for &index in &self.sorted[axis][begin..mid] {
            self.goes_left[index as usize] = true;
        }
        for other in (0..V::DIM).filter(|&other| other != axis) {
            let list = &mut self.sorted[other][begin..end];
            self.scratch.clear();
            let mut left_end = 0;
            for slot in 0..list.len() {
                let index = list[slot];
                if self.goes_left[index as usize] {
                    list[left_end] = index;
                    left_end += 1;
                } else {
                    self.scratch.push(index);
                }
            }
            list[left_end..].copy_from_slice(&self.scratch);
        }
        Ok(Split {
            mid,
            cost: Some(best_cost),
            left: (self.range_bounds(axis, begin, mid), ()),
            right: (self.range_bounds(axis, mid, end), ()),
        })
    }

    fn into_order(mut self) -> Vec<u32> {
        self.sorted.swap_remove(0)
    }
}

impl Builder for SweepSah {
    fn name(&self) -> String {
        "sah-sweep".into()
    }

    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> Bvh<V> {
        let count = primitive_bounds.len();
        let centroids: Vec<V> = primitive_bounds.iter().map(Aabb::center).collect();
        // Sort once per axis (ties by number, so the tree does not depend on the sort).
        let sorted = (0..V::DIM)
            .map(|axis| {
                let mut list: Vec<u32> = (0..count as u32).collect();
                sort_by_centroid(&mut list, &centroids, axis);
                list
            })
            .collect();
        let splitter = Splitter {
            bounds: primitive_bounds,
            sorted,
            goes_left: vec![false; count],
            right_areas: vec![0.0; count.max(1)],
            scratch: Vec::with_capacity(count),
            max_leaf_size: params.max_leaf_size.max(1),
            cost: params.cost,
        };
        build_top_down(splitter, count, params.max_leaf_size.max(1), observer)
    }
}
