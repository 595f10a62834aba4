//! Split at the median: the lecture's second strategy. The plane goes through the median of
//! the primitives' bounds, so both children hold about as many primitives; how likely each is
//! to be entered is ignored.

use crate::aabb::Aabb;
use crate::build_observer::BuildObserver;
use crate::kd::build::{Cut, KdBuilder, build_by_rule};
use crate::kd::tree::KdTree;
use crate::math::{Real, Vector};
use crate::params::BuildParams;

/// Cuts each cell across its longest axis at the median of its primitives' box ends (each
/// primitive's lower and upper bound on that axis, clipped to the cell); if that falls on the
/// cell's boundary, in the middle instead.
#[derive(Clone, Copy, Debug, Default)]
pub struct KdMedianSplit;

impl KdBuilder for KdMedianSplit {
    fn name(&self) -> String {
        "median".into()
    }

    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> KdTree<V> {
        build_by_rule(primitive_bounds, params, observer, median_cut)
    }
}

/// The median rule's cut of `cell` (`ends` is scratch space). Shared with the cost curves.
pub(crate) fn median_cut<V: Vector>(
    cell: &Aabb<V>,
    primitives: &[u32],
    bounds: &[Aabb<V>],
    ends: &mut Vec<V::Scalar>,
) -> Cut<V::Scalar> {
    let axis = cell.largest_axis();
    let (low, high) = (cell.min[axis], cell.max[axis]);
    // Gather both ends of every box, clipped to the cell, and take the middle one.
    ends.clear();
    for &primitive in primitives {
        let bounds = &bounds[primitive as usize];
        ends.push(bounds.min[axis].max(low));
        ends.push(bounds.max[axis].min(high));
    }
    let half = ends.len() / 2;
    let split = if ends.is_empty() {
        None
    } else {
        let (_, &mut median, _) = ends.select_nth_unstable_by(half, |a, b| {
            a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal)
        });
        (low < median && median < high).then_some(median)
    };
    let split = split.unwrap_or_else(|| (low + high) * (V::Scalar::ONE / V::Scalar::TWO));
    Cut::new(axis, split)
}
