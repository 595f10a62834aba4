//! Split at the median: the lecture's second strategy, which gives the two children equal
//! primitive counts (equal cost) and pays no attention to how likely they are to be hit.

use crate::aabb::Aabb;
use crate::build_observer::BuildObserver;
use crate::bvh::build::{Builder, build_by_rule};
use crate::bvh::tree::Bvh;
use crate::math::Vector;
use crate::params::BuildParams;

/// Splits each node at the median centroid (object median) along the longest axis of the
/// centroids' box. Always balanced: depth ⌈log₂(n / leaf size)⌉.
#[derive(Clone, Copy, Debug, Default)]
pub struct MedianSplit;

impl Builder for MedianSplit {
    fn name(&self) -> String {
        "median".into()
    }

    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> Bvh<V> {
        build_by_rule(
            primitive_bounds,
            params.max_leaf_size,
            observer,
            |boxes, begin, end| {
                // Partial sort (quickselect) puts the lower half first in linear time.
                let axis = boxes.centroid_bounds(begin, end).largest_axis();
                boxes.median_split(begin, end, axis)
            },
        )
    }
}
