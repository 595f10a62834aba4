//! Split at the median: the lecture's second strategy, which gives the two children equal
//! primitive counts (equal cost) and pays no attention to how likely they are to be hit.

use crate::aabb::Aabb;
use crate::bvh::build::{BuildParams, Builder, IndexedBoxes, RangeSplitter, Split, build_top_down};
use crate::bvh::tree::Bvh;
use crate::math::Vector;

/// Splits each node at the median centroid (object median) along the longest axis of the
/// centroids' box. Always balanced: depth ⌈log₂(n / leaf size)⌉.
#[derive(Clone, Copy, Debug, Default)]
pub struct MedianSplit;

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
        // Partial sort (quickselect) puts the lower half first in linear time.
        let axis = self.boxes.centroid_bounds(begin, end).largest_axis();
        let median = self.boxes.median_split(begin, end, axis);
        Some(self.boxes.split_at(begin, median, end))
    }

    fn into_order(self) -> Vec<u32> {
        self.boxes.order
    }
}

impl Builder for MedianSplit {
    fn name(&self) -> String {
        "median".into()
    }

    fn build<V: Vector>(&self, primitive_bounds: &[Aabb<V>], params: &BuildParams) -> Bvh<V> {
        let splitter = Splitter {
            boxes: IndexedBoxes::new(primitive_bounds),
            max_leaf_size: params.max_leaf_size.max(1),
        };
        build_top_down(splitter, primitive_bounds.len())
    }
}
