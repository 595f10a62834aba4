//! Split in the middle: the lecture's first strategy, which makes the two children equally
//! likely to be hit and pays no attention to what they cost.

use crate::aabb::Aabb;
use crate::bvh::build::{BuildParams, Builder, IndexedBoxes, RangeSplitter, Split, build_top_down};
use crate::bvh::tree::Bvh;
use crate::math::Vector;

/// Splits each node at the middle of its centroids' box, along that box's longest axis.
///
/// Fast to build, blind to where the primitives are: with clustered geometry it makes deep,
/// unbalanced trees. When every centroid lies on one side (they coincide) it falls back to
/// the object median.
#[derive(Clone, Copy, Debug, Default)]
pub struct MiddleSplit;

struct Splitter<'a, V: Vector> {
    boxes: IndexedBoxes<'a, V>,
    max_leaf_size: usize,
}

impl<V: Vector> RangeSplitter<V> for Splitter<'_, V> {
    type NodeInfo = ();

    fn root(&self) -> (Aabb<V>, ()) {
        (self.boxes.range_bounds(0, self.boxes.order.len()), ())
    }

    fn split(
        &mut self,
        begin: usize,
        end: usize,
        _node_bounds: &Aabb<V>,
        _info: &(),
    ) -> Option<Split<V, ()>> {
        if end - begin <= self.max_leaf_size {
            return None;
        }
        // Bound the centroids and cut their longest axis in half.
        let centroid_bounds = self.boxes.centroid_bounds(begin, end);
        let axis = centroid_bounds.largest_axis();
        let middle = centroid_bounds.center()[axis];
        let mid = self
            .boxes
            .partition(begin, end, |centroid| centroid[axis] < middle);
        if mid == begin || mid == end {
            // Every centroid is on one side of the middle: they coincide on this axis.
            let median = self.boxes.median_split(begin, end, axis);
            return Some(self.boxes.split_at(begin, median, end));
        }
        Some(self.boxes.split_at(begin, mid, end))
    }

    fn into_order(self) -> Vec<u32> {
        self.boxes.order
    }
}

impl Builder for MiddleSplit {
    fn name(&self) -> String {
        "middle".into()
    }

    fn build<V: Vector>(&self, primitive_bounds: &[Aabb<V>], params: &BuildParams) -> Bvh<V> {
        let splitter = Splitter {
            boxes: IndexedBoxes::new(primitive_bounds),
            max_leaf_size: params.max_leaf_size.max(1),
        };
        build_top_down(splitter, primitive_bounds.len())
    }
}
