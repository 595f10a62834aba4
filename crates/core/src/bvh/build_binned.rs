//! Binned SAH: Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"
//! (IEEE Symposium on Interactive Ray Tracing).
//!
//! Instead of costing a split at every primitive, drop the centroids into B equal bins along
//! the longest axis of the node's centroid box and cost only the B − 1 planes between bins.
//! Each node is O(n + B) and the tree is nearly as good as the exact sweep (which tries every
//! axis and every primitive) for B ≈ 16; fewer bins build faster and cost more to trace. The
//! trade is measured by `accelviz-cli bench`. Binning one axis follows pbrt-v3 §4.3.2.
//!
//! Unobserved, it builds on every thread of the current rayon pool, in the two ways Wald's
//! paper sets out: the top nodes' binning split between threads (data parallel), and below
//! them each big node's two sides at once (task parallel, `build.rs`). The tree is the one a
//! single thread builds.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReason};
use crate::bvh::build::{
    Builder, ForkingSplitter, RangeSplitter, Split, build_top_down, build_top_down_parallel,
};
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

    /// Adds another bin's primitives (binned apart) to this one.
    fn merge(&mut self, other: &Self) {
        self.bounds = self.bounds.union(other.bounds);
        self.centroid_bounds = self.centroid_bounds.union(other.centroid_bounds);
        self.count += other.count;
    }
}

/// Drops each primitive of `refs` into its bin of `bins` by its centroid's coordinate on
/// `axis`, and notes the bin in `bin_of` (for the partition).
#[inline(always)]
fn bin_into<V: Vector>(
    bins: &mut [Bin<V>],
    refs: &[PrimitiveRef<V>],
    bin_of: &mut [u16],
    binning: &Binning<V::Scalar>,
    axis: usize,
) {
    for (primitive, bin_of) in refs.iter().zip(bin_of) {
        let centroid = primitive.bounds.center();
        let index = binning.bin(centroid[axis]);
        *bin_of = index as u16;
        bins[index].add(primitive.bounds, centroid);
    }
}

/// A node of at least this many primitives is binned in chunks on every thread.
const PARALLEL_BINNING: usize = 32_768;

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

/// The binned splitter over a part of the primitives' order: the whole of it, or (in a
/// parallel build) the range of one subtree, `offset..offset + refs.len()`.
struct Splitter<'a, V: Vector> {
    refs: &'a mut [PrimitiveRef<V>],
    /// The bin of each primitive of the node being split, by position in `refs`.
    bin_of: &'a mut [u16],
    /// Where `refs[0]` sits in the whole order (node ranges are given in it).
    offset: usize,
    bin_count: usize,
    max_leaf_size: usize,
    cost: SahCost,
    /// The bins of the node being split.
    bins: Vec<Bin<V>>,
    /// For each plane of the axis being costed: its right side's count and half area.
    right_sides: Vec<(u32, V::Scalar)>,
}

impl<'a, V: Vector> Splitter<'a, V> {
    /// A splitter over the whole order (`refs` and its bins' scratch `bin_of`).
    fn new(
        refs: &'a mut [PrimitiveRef<V>],
        bin_of: &'a mut [u16],
        bin_count: usize,
        params: &BuildParams,
    ) -> Self {
        Self {
            refs,
            bin_of,
            offset: 0,
            bin_count,
            max_leaf_size: params.max_leaf_size.max(1),
            cost: params.cost,
            bins: vec![Bin::EMPTY(); bin_count],
            right_sides: vec![(0, V::Scalar::ZERO); bin_count],
        }
    }
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

impl<V: Vector> RangeSplitter<V> for Splitter<'_, V> {
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
        // Positions in this part's storage.
        let (begin, end) = (begin - self.offset, end - self.offset);
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
                mid: mid + self.offset,
                cost: None,
                left: (half(&self.refs[begin..mid]), *centroid_bounds),
                right: (half(&self.refs[mid..end]), *centroid_bounds),
            });
        };
        // Drop every centroid into its bin, remembering the bin for the partition.
        self.bins.fill(Bin::EMPTY());
        let refs = &self.refs[begin..end];
        let bin_of = &mut self.bin_of[begin..end];
        if count < PARALLEL_BINNING || !crate::parallel::has_threads() {
            bin_into(&mut self.bins, refs, bin_of, &binning, axis);
        } else {
            // The top nodes' binning in chunks on the current rayon pool, their bins merged:
            // a bin's box, centroid box and count are the same in any grouping.
            use rayon::prelude::*;
            let chunks: Vec<Vec<Bin<V>>> = refs
                .par_chunks(PARALLEL_BINNING / 4)
                .zip(bin_of.par_chunks_mut(PARALLEL_BINNING / 4))
                .map(|(refs, bin_of)| {
                    let mut bins = vec![Bin::EMPTY(); bin_count];
                    bin_into(&mut bins, refs, bin_of, &binning, axis);
                    bins
                })
                .collect();
            for chunk in &chunks {
                for (bin, part) in self.bins.iter_mut().zip(chunk) {
                    bin.merge(part);
                }
            }
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
            mid: self.offset + begin + left_end,
            cost: Some(best_cost),
            left: side(&self.bins[..plane]),
            right: side(&self.bins[plane..]),
        })
    }

    fn into_order(self) -> Vec<u32> {
        self.refs.iter().map(|r| r.index).collect()
    }
}

impl<V: Vector> ForkingSplitter<V> for Splitter<'_, V> {
    fn fork(self, mid: usize) -> (Self, Self) {
        let Splitter {
            refs,
            bin_of,
            offset,
            bin_count,
            max_leaf_size,
            cost,
            bins,
            right_sides,
        } = self;
        let (left_refs, right_refs) = refs.split_at_mut(mid - offset);
        let (left_bins, right_bins) = bin_of.split_at_mut(mid - offset);
        let part = |refs, bin_of, offset, bins, right_sides| Splitter {
            refs,
            bin_of,
            offset,
            bin_count,
            max_leaf_size,
            cost,
            bins,
            right_sides,
        };
        (
            part(left_refs, left_bins, offset, bins, right_sides),
            part(
                right_refs,
                right_bins,
                mid,
                vec![Bin::EMPTY(); bin_count],
                vec![(0, V::Scalar::ZERO); bin_count],
            ),
        )
    }
}

/// Each primitive's box with its number, in input order: the binned builder's working order.
/// On the current rayon pool, in order.
fn primitive_refs<V: Vector>(primitive_bounds: &[Aabb<V>]) -> Vec<PrimitiveRef<V>> {
    use rayon::prelude::*;
    primitive_bounds
        .par_iter()
        .with_min_len(PARALLEL_BINNING / 4)
        .enumerate()
        .map(|(index, &bounds)| PrimitiveRef {
            bounds,
            index: index as u32,
        })
        .collect()
}

/// The primitives' numbers in the order the build left them (on the current rayon pool).
fn order_of<V: Vector>(refs: &[PrimitiveRef<V>]) -> Vec<u32> {
    use rayon::prelude::*;
    refs.par_iter()
        .with_min_len(PARALLEL_BINNING / 4)
        .map(|r| r.index)
        .collect()
}

impl Builder for BinnedSah {
    fn name(&self) -> String {
        format!("sah-binned:{}", self.bins)
    }

    /// Unobserved, on every thread of the current rayon pool (`build_top_down_parallel`:
    /// the same tree on any number of threads); observed, or on one thread, one node after
    /// another (in the order the observer hears them).
    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> Bvh<V> {
        let mut refs = primitive_refs(primitive_bounds);
        let mut bin_of = vec![0; primitive_bounds.len()];
        let splitter = Splitter::new(&mut refs, &mut bin_of, self.bin_count(), params);
        let max_leaf_size = params.max_leaf_size.max(1);
        if O::ACTIVE || !crate::parallel::has_threads() {
            return build_top_down(splitter, primitive_bounds.len(), max_leaf_size, observer);
        }
        let nodes = build_top_down_parallel(splitter, primitive_bounds.len(), max_leaf_size);
        Bvh {
            nodes,
            primitive_indices: order_of(&refs),
        }
    }
}

impl BinnedSah {
    /// The bins per axis used: bin indices are kept in 16 bits.
    fn bin_count(&self) -> usize {
        self.bins.clamp(2, u16::MAX as usize)
    }
}
