//! Binned SAH: Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"
//! (IEEE Symposium on Interactive Ray Tracing).
//!
//! Instead of costing a split at every primitive, drop the centroids into B equal bins along
//! the longest axis of the node's centroid box and cost only the B − 1 planes between bins.
//! Each node is O(n + B) and the tree is nearly as good as the exact sweep (which tries every
//! axis and every primitive) for B ≈ 16; fewer bins build faster and cost more to trace. The
//! trade is measured by `accelviz-cli bench`. Binning one axis follows pbrt-v3 §4.3.2.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReason};
use crate::bvh::build::{Builder, RangeSplitter, Split, build_top_down};
use crate::bvh::tree::Bvh;
use crate::math::{Real, Vector};
use crate::params::BuildParams;
use crate::sah::SahCost;

/// The binned SAH builder with `bins` bins per axis.
#[derive(Clone, Copy, Debug)]
pub struct BinnedSah {
    /// Bins per axis (at least 2).
    pub bins: usize,
}

impl Default for BinnedSah {
    fn default() -> Self {
        Self { bins: 16 }
    }
}

/// One bin: the primitives whose centroids fall in it.
#[derive(Clone, Copy)]
pub(crate) struct Bin<V: Vector> {
    pub(crate) bounds: Aabb<V>,
    pub(crate) centroid_bounds: Aabb<V>,
    pub(crate) count: u32,
}

impl<V: Vector> Bin<V> {
    pub(crate) const EMPTY: fn() -> Self = || Self {
        bounds: Aabb::empty(),
        centroid_bounds: Aabb::empty(),
        count: 0,
    };

    /// Puts a primitive with this box and centroid in the bin.
    #[inline(always)]
    pub(crate) fn add(&mut self, bounds: Aabb<V>, centroid: V) {
        self.bounds = self.bounds.union(bounds);
        self.centroid_bounds = self.centroid_bounds.grown(centroid);
        self.count += 1;
    }
}

/// The planes between bins, each with what lies left and right of it: `visit(plane,
/// left_count, left_half_area, right_count, right_half_area)` for every plane `1..B` with
/// primitives on both sides. Shared by the builder and the cost curves, so both cost the same
/// candidates the same way. `right` is scratch space of `B` entries.
#[inline]
pub(crate) fn sweep_bins<V: Vector>(
    bins: &[Bin<V>],
    right: &mut [(u32, V::Scalar)],
    mut visit: impl FnMut(usize, u32, V::Scalar, u32, V::Scalar),
) {
    // From the right, to know each plane's right side; then from the left.
    let mut right_bounds = Aabb::empty();
    let mut right_count = 0;
    for plane in (1..bins.len()).rev() {
        right_bounds = right_bounds.union(bins[plane].bounds);
        right_count += bins[plane].count;
        right[plane] = if right_count > 0 {
            (right_count, right_bounds.half_area_nonempty())
        } else {
            (0, V::Scalar::ZERO)
        };
    }
    let mut left = Aabb::empty();
    let mut left_count = 0;
    for plane in 1..bins.len() {
        left = left.union(bins[plane - 1].bounds);
        left_count += bins[plane - 1].count;
        let (right_count, right_half_area) = right[plane];
        if left_count == 0 || right_count == 0 {
            continue;
        }
        visit(
            plane,
            left_count,
            left.half_area_nonempty(),
            right_count,
            right_half_area,
        );
    }
}

/// A primitive's box with its number, moved as one through partitioning so that every pass
/// over a node reads memory in order.
#[derive(Clone, Copy)]
struct PrimitiveRef<V: Vector> {
    bounds: Aabb<V>,
    index: u32,
}

struct Splitter<V: Vector> {
    refs: Vec<PrimitiveRef<V>>,
    bin_count: usize,
    max_leaf_size: usize,
    cost: SahCost,
    /// The bins of the node being split.
    bins: Vec<Bin<V>>,
    /// The bin of each primitive of the node being split, by position in `refs`.
    bin_of: Vec<u16>,
    /// For each plane of the axis being costed: its right side's count and half area.
    right_sides: Vec<(u32, V::Scalar)>,
}

/// Maps centroid coordinates to bins along one axis.
#[derive(Clone, Copy)]
pub(crate) struct Binning<S: Real> {
    min: S,
    bins_per_unit: S,
    last_bin: usize,
}

impl<S: Real> Binning<S> {
    /// `bin_count` equal bins across the centroid box on `axis`; `None` if the box is flat
    /// there (no plane separates the centroids).
    pub(crate) fn new<V: Vector<Scalar = S>>(
        centroid_bounds: &Aabb<V>,
        axis: usize,
        bin_count: usize,
    ) -> Option<Self> {
        let extent = centroid_bounds.max[axis] - centroid_bounds.min[axis];
        (extent > S::ZERO).then(|| Self {
            min: centroid_bounds.min[axis],
            bins_per_unit: S::from_usize(bin_count) / extent,
            last_bin: bin_count - 1,
        })
    }

    /// Where the plane before bin `plane` lies.
    pub(crate) fn plane_position(&self, plane: usize) -> S {
        self.min + S::from_usize(plane) / self.bins_per_unit
    }

    /// The bin of a centroid coordinate.
    #[inline(always)]
    pub(crate) fn bin(&self, coordinate: S) -> usize {
        let bin = ((coordinate - self.min) * self.bins_per_unit).to_small_usize();
        bin.min(self.last_bin)
    }
}

impl<V: Vector> RangeSplitter<V> for Splitter<V> {
    /// The box around the node's centroids: where the bins go.
    type NodeInfo = Aabb<V>;

    fn root(&self) -> (Aabb<V>, Aabb<V>) {
        let bounds = self
            .refs
            .iter()
            .fold(Aabb::empty(), |acc, r| acc.union(r.bounds));
        let centroid_bounds = Aabb::from_points(self.refs.iter().map(|r| r.bounds.center()));
        (bounds, centroid_bounds)
    }

    fn split(
        &mut self,
        begin: usize,
        end: usize,
        node_bounds: &Aabb<V>,
        centroid_bounds: &Aabb<V>,
    ) -> Result<Split<V, Aabb<V>>, LeafReason> {
        let count = end - begin;
        if count <= self.max_leaf_size && self.cost.leaf_beats_any_split(count) {
            return Err(LeafReason::LeafCheaper {
                leaf_cost: self.cost.leaf_cost(count),
                split_cost: None,
            });
        }
        let bin_count = self.bin_count;
        // Bin along the longest axis of the centroids' box.
        let axis = centroid_bounds.largest_axis();
        let Some(binning) = Binning::new(centroid_bounds, axis, bin_count) else {
            // All centroids coincide: no plane separates them. Halve big nodes anyway.
            if count <= self.max_leaf_size {
                return Err(LeafReason::Inseparable { count });
            }
            let mid = begin + count / 2;
            let half = |range: &[PrimitiveRef<V>]| {
                range
                    .iter()
                    .fold(Aabb::empty(), |acc, r| acc.union(r.bounds))
            };
            return Ok(Split {
                mid,
                cost: None,
                left: (half(&self.refs[begin..mid]), *centroid_bounds),
                right: (half(&self.refs[mid..end]), *centroid_bounds),
            });
        };
        // Drop every centroid into its bin, remembering the bin for the partition.
        self.bins.fill(Bin::EMPTY());
        for (primitive, bin_of) in self.refs[begin..end]
            .iter()
            .zip(&mut self.bin_of[begin..end])
        {
            let centroid = primitive.bounds.center();
            let index = binning.bin(centroid[axis]);
            *bin_of = index as u16;
            self.bins[index].add(primitive.bounds, centroid);
        }
        // Cost each plane between bins by A_L·N_L + A_R·N_R, all that varies within a node.
        let mut best: Option<(V::Scalar, usize)> = None; // (weighted, plane)
        sweep_bins(
            &self.bins,
            &mut self.right_sides,
            |plane, left_count, left_area, right_count, right_area| {
                let weighted = left_area * V::Scalar::from_u32(left_count)
                    + right_area * V::Scalar::from_u32(right_count);
                if best.is_none_or(|(best_weighted, _)| weighted < best_weighted) {
                    best = Some((weighted, plane));
                }
            },
        );
        // The lowest and highest centroids fall in the first and last bins, so some plane
        // has primitives on both sides.
        let Some((weighted, plane)) = best else {
            return Err(LeafReason::Inseparable { count });
        };
        let best_cost = self.cost.split_cost_weighted(
            node_bounds.half_area_nonempty().to_f64(),
            weighted.to_f64(),
            count,
        );
        // Keep the leaf if no split is cheaper (and the leaf is small enough).
        let leaf_cost = self.cost.leaf_cost(count);
        if count <= self.max_leaf_size && leaf_cost <= best_cost {
            return Err(LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: Some(best_cost),
            });
        }
        // Partition by bin (Hoare's two-ended scheme: only misplaced pairs move).
        let range = &mut self.refs[begin..end];
        let bin_of = &self.bin_of[begin..end];
        let plane = plane as u16;
        let (mut low, mut high) = (0, range.len());
        loop {
            while low < high && bin_of[low] < plane {
                low += 1;
            }
            while low < high && bin_of[high - 1] >= plane {
                high -= 1;
            }
            if low >= high {
                break;
            }
            // range[low] belongs right and range[high - 1] left. Their bins are not read again.
            range.swap(low, high - 1);
            low += 1;
            high -= 1;
        }
        let plane = plane as usize;
        let left_end = low;
        // Each side's box and centroid box are the unions of its bins'.
        let side = |bins: &[Bin<V>]| {
            bins.iter().fold(
                (Aabb::empty(), Aabb::empty()),
                |(bounds, centroids), bin| {
                    (
                        bounds.union(bin.bounds),
                        centroids.union(bin.centroid_bounds),
                    )
                },
            )
        };
        Ok(Split {
            mid: begin + left_end,
            cost: Some(best_cost),
            left: side(&self.bins[..plane]),
            right: side(&self.bins[plane..]),
        })
    }

    fn into_order(self) -> Vec<u32> {
        self.refs.iter().map(|r| r.index).collect()
    }
}

impl Builder for BinnedSah {
    fn name(&self) -> String {
        format!("sah-binned:{}", self.bins)
    }

    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> Bvh<V> {
        // Bin indices are kept in 16 bits.
        let bin_count = self.bins.clamp(2, u16::MAX as usize);
        let splitter = Splitter {
            refs: primitive_bounds
                .iter()
                .enumerate()
                .map(|(index, &bounds)| PrimitiveRef {
                    bounds,
                    index: index as u32,
                })
                .collect(),
            bin_count,
            max_leaf_size: params.max_leaf_size.max(1),
            cost: params.cost,
            bins: vec![Bin::EMPTY(); bin_count],
            bin_of: vec![0; primitive_bounds.len()],
            right_sides: vec![(0, V::Scalar::ZERO); bin_count],
        };
        build_top_down(
            splitter,
            primitive_bounds.len(),
            params.max_leaf_size.max(1),
            observer,
        )
    }
}
