//! Acceleration-structure specs (`brute`, `bvh:sah-binned:16`, ...) and what they build.

use std::time::Instant;

use accelviz_core::TreeStats;
use accelviz_core::bvh::{
    BinnedSah, BuildParams, Builder, Bvh, MedianSplit, MiddleSplit, SweepSah, TraversalStack,
    traverse,
};
use accelviz_core::kd::{
    self, KdBuilder, KdMedianSplit, KdMiddleSplit, KdSah, KdSahPresorted, KdTraversalStack, KdTree,
};
use accelviz_core::{
    Aabb, Hit, LeafOrdered, Observer, PrimitiveSet, Ray, TraceOptions, Vector, brute_force,
};
use anyhow::{Result, bail};

/// The specs the CLI accepts, for messages.
pub const VALID_SPECS: &str = "brute, bvh:middle, bvh:median, bvh:sah-binned[:BINS] (default 16 bins), bvh:sah-sweep, kd:middle, kd:median, kd:sah, kd:sah-perfect, kd:sah-per-node";

/// A parsed spec.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccelSpec {
    /// Test every triangle.
    Brute,
    /// Middle split.
    Middle,
    /// Object median split.
    Median,
    /// Binned SAH with this many bins.
    Binned(usize),
    /// Full-sweep SAH.
    Sweep,
    /// kD-tree cut in the middle of each cell.
    KdMiddle,
    /// kD-tree cut at the median of the primitives' bounds.
    KdMedian,
    /// SAH kD-tree, events sorted once (O(n log n)).
    KdSah,
    /// SAH kD-tree, events sorted at every node (O(n log² n)); the same tree.
    KdSahPerNode,
    /// SAH kD-tree with perfect splits (straddling primitives clipped to each child cell).
    KdSahPerfect,
}

impl AccelSpec {
    /// Parses one spec.
    pub fn parse(text: &str) -> Result<Self> {
        let spec = match text {
            "brute" => Self::Brute,
            "bvh:middle" => Self::Middle,
            "bvh:median" => Self::Median,
            "bvh:sah-binned" => Self::Binned(16),
            "bvh:sah-sweep" => Self::Sweep,
            "kd:middle" => Self::KdMiddle,
            "kd:median" => Self::KdMedian,
            "kd:sah" => Self::KdSah,
            "kd:sah-per-node" => Self::KdSahPerNode,
            "kd:sah-perfect" => Self::KdSahPerfect,
            _ => match text.strip_prefix("bvh:sah-binned:") {
                Some(bins) => match bins.parse::<usize>() {
                    Ok(bins) if (2..=4096).contains(&bins) => Self::Binned(bins),
                    _ => bail!(
                        "unknown accelerator '{text}': the bin count must be a whole number from 2 to 4096"
                    ),
                },
                None => bail!("unknown accelerator '{text}'; valid ones are: {VALID_SPECS}"),
            },
        };
        Ok(spec)
    }

    /// Parses a comma-separated list.
    pub fn parse_list(text: &str) -> Result<Vec<Self>> {
        text.split(',')
            .map(|part| Self::parse(part.trim()))
            .collect()
    }

    /// The canonical name.
    pub fn name(&self) -> String {
        match self {
            Self::Brute => "brute".into(),
            Self::Middle => "bvh:middle".into(),
            Self::Median => "bvh:median".into(),
            Self::Binned(bins) => format!("bvh:sah-binned:{bins}"),
            Self::Sweep => "bvh:sah-sweep".into(),
            Self::KdMiddle => "kd:middle".into(),
            Self::KdMedian => "kd:median".into(),
            Self::KdSah => "kd:sah".into(),
            Self::KdSahPerNode => "kd:sah-per-node".into(),
            Self::KdSahPerfect => "kd:sah-perfect".into(),
        }
    }

    /// Builds the structure over `primitives`, timing the build: the boxes, the tree, and the
    /// copy of the primitives in the tree's leaf order that traversal reads.
    pub fn build<'a, V: Vector, P: PrimitiveSet<V>>(
        &self,
        primitives: &'a P,
        params: &BuildParams,
    ) -> (Accel<'a, V, P>, f64) {
        let start = Instant::now();
        let bvh = |builder: &dyn Fn(&[Aabb<V>]) -> Bvh<V>| {
            let bvh = builder(&primitives.all_bounds());
            let leaf_ordered = bvh.leaf_ordered(primitives);
            Accel::Bvh(bvh, leaf_ordered)
        };
        let kd = |builder: &dyn Fn(&[Aabb<V>]) -> KdTree<V>| {
            let tree = builder(&primitives.all_bounds());
            let leaf_ordered = tree.leaf_ordered(primitives);
            Accel::Kd(tree, leaf_ordered)
        };
        let accel = match self {
            Self::Brute => Accel::Brute(primitives),
            Self::KdMiddle => kd(&|bounds| KdMiddleSplit.build(bounds, params)),
            Self::KdMedian => kd(&|bounds| KdMedianSplit.build(bounds, params)),
            Self::KdSah => kd(&|bounds| KdSahPresorted.build(bounds, params)),
            Self::KdSahPerNode => kd(&|bounds| KdSah.build(bounds, params)),
            Self::KdSahPerfect => {
                kd(&|_| KdSahPresorted.build_with_perfect_splits(primitives, params))
            }
            Self::Middle => bvh(&|bounds| MiddleSplit.build(bounds, params)),
            Self::Median => bvh(&|bounds| MedianSplit.build(bounds, params)),
            Self::Binned(bins) => bvh(&|bounds| BinnedSah { bins: *bins }.build(bounds, params)),
            Self::Sweep => bvh(&|bounds| SweepSah.build(bounds, params)),
        };
        (accel, start.elapsed().as_secs_f64() * 1e3)
    }
}

/// One traversal stack per kind of tree, kept per thread.
#[derive(Default)]
pub struct Stacks<S: accelviz_core::Real> {
    bvh: TraversalStack<S>,
    kd: KdTraversalStack<S>,
}

/// A built structure with the primitives it traces.
pub enum Accel<'a, V: Vector, P> {
    /// No structure: brute force over the primitives in their own order.
    Brute(&'a P),
    /// A BVH and the primitives in its leaf order.
    Bvh(Bvh<V>, LeafOrdered<P>),
    /// A kD-tree and the primitives in its leaf order.
    Kd(KdTree<V>, LeafOrdered<P>),
}

impl<V: Vector, P: PrimitiveSet<V>> Accel<'_, V, P> {
    /// Traces one ray.
    #[inline]
    pub fn trace<O: Observer<V::Scalar>>(
        &self,
        ray: &Ray<V>,
        options: &TraceOptions,
        stacks: &mut Stacks<V::Scalar>,
        observer: &mut O,
    ) -> Option<Hit<V::Scalar>> {
        match self {
            Accel::Brute(primitives) => brute_force(*primitives, ray, options, observer),
            Accel::Bvh(bvh, primitives) => {
                traverse(bvh, primitives, ray, options, &mut stacks.bvh, observer)
            }
            Accel::Kd(tree, primitives) => {
                kd::traverse(tree, primitives, ray, options, &mut stacks.kd, observer)
            }
        }
    }

    /// The tree's statistics with these cost constants (for brute force: one leaf holding
    /// everything).
    pub fn stats(&self, primitive_count: usize, cost: &accelviz_core::SahCost) -> TreeStats {
        let cost = *cost;
        match self {
            Accel::Brute(_) => TreeStats {
                node_count: 0,
                leaf_count: 0,
                max_depth: 0,
                min_leaf_size: primitive_count,
                max_leaf_size: primitive_count,
                mean_leaf_size: primitive_count as f64,
                sah_cost: cost.leaf_cost(primitive_count),
            },
            Accel::Bvh(bvh, _) => TreeStats::of_bvh(bvh, &cost),
            Accel::Kd(tree, _) => TreeStats::of_kd(tree, &cost),
        }
    }
}
