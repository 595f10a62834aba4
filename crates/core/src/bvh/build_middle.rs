//! Split in the middle: the lecture's first strategy, which makes the two children equally
//! likely to be hit and pays no attention to what they cost.

use crate::aabb::Aabb;
use crate::build_observer::BuildObserver;
use crate::bvh::build::{Builder, build_by_rule};
use crate::bvh::tree::Bvh;
use crate::math::Vector;
use crate::params::BuildParams;

/// Splits each node at the middle of its centroids' box, along that box's longest axis.
///
/// Fast to build, blind to where the primitives are: with clustered geometry it makes deep,
/// unbalanced trees. When every centroid lies on one side (they coincide) it falls back to
/// the object median.
#[derive(Clone, Copy, Debug, Default)]
pub struct MiddleSplit;

impl Builder for MiddleSplit {
    fn name(&self) -> String {
        "middle".into()
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
                // Bound the centroids and cut their longest axis in half.
                let centroid_bounds = boxes.centroid_bounds(begin, end);
                let axis = centroid_bounds.largest_axis();
                let middle = centroid_bounds.center()[axis];
                let mid = boxes.partition(begin, end, |centroid| centroid[axis] < middle);
                if mid == begin || mid == end {
                    // Every centroid is on one side of the middle: they coincide on this axis.
                    boxes.median_split(begin, end, axis)
                } else {
                    mid
                }
            },
        )
    }
}
