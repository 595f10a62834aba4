//! Split in the middle of the cell: the lecture's first strategy. The two children are equally
//! likely to be entered; what they contain is ignored.

use crate::aabb::Aabb;
use crate::build_observer::BuildObserver;
use crate::kd::build::{Cut, KdBuilder, build_by_rule};
use crate::kd::tree::KdTree;
use crate::math::{Real, Vector};
use crate::params::BuildParams;

/// Cuts each cell in half across its longest axis.
#[derive(Clone, Copy, Debug, Default)]
pub struct KdMiddleSplit;

impl KdBuilder for KdMiddleSplit {
    fn name(&self) -> String {
        "middle".into()
    }

    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> KdTree<V> {
        build_by_rule(primitive_bounds, params, observer, |cell, _, _, _| {
            middle_cut(cell)
        })
    }
}

/// The middle rule's cut of `cell`. Shared with the cost curves.
pub(crate) fn middle_cut<V: Vector>(cell: &Aabb<V>) -> Cut<V::Scalar> {
    let axis = cell.largest_axis();
    let half = V::Scalar::ONE / V::Scalar::TWO;
    Cut::new(axis, (cell.min[axis] + cell.max[axis]) * half)
}
