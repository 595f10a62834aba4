//! Acceleration-structure specs: `brute`, or any structure of the core's catalogue
//! (`bvh:sah-binned:16`, `kd:sah`, ...), and what they build.

use std::time::Instant;

use accelviz_core::params::BuildParams;
use accelviz_core::structure::valid_names;
use accelviz_core::{
    Hit, LeafOrdered, NoObserver, Observer, PrimitiveSet, Ray, SahCost, Structure, TraceOptions,
    TraversalStacks, Tree, TreeStats, Vector, brute_force,
};
use anyhow::{Result, bail};

use crate::parallel::Workers;

/// A parsed spec: brute force, or a structure of the catalogue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccelSpec {
    /// Test every triangle.
    Brute,
    /// Build a structure.
    Tree(Structure),
}

impl AccelSpec {
    /// Parses one spec.
    pub fn parse(text: &str) -> Result<Self> {
        if text == "brute" {
            return Ok(Self::Brute);
        }
        match Structure::parse(text) {
            Ok(structure) => Ok(Self::Tree(structure)),
            Err(accelviz_core::structure::StructureError::Unknown { .. }) => bail!(
                "unknown accelerator '{text}'; valid ones are: brute, {}",
                valid_names()
            ),
            Err(error) => bail!("{error}"),
        }
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
            Self::Tree(structure) => structure.name(),
        }
    }

    /// Builds the structure over `primitives`, timing the build: the boxes, the tree, and the
    /// copy of the primitives in the tree's leaf order that traversal reads.
    pub fn build<'a, V: Vector, P: PrimitiveSet<V> + 'static>(
        &self,
        primitives: &'a P,
        params: &BuildParams,
    ) -> (Accel<'a, V, P>, f64) {
        let start = Instant::now();
        let accel = match self {
            Self::Brute => Accel::Brute(primitives),
            Self::Tree(structure) => {
                let tree = structure.build(primitives, params);
                let leaf_ordered = tree.leaf_ordered(primitives);
                Accel::Tree(tree, leaf_ordered)
            }
        };
        (accel, start.elapsed().as_secs_f64() * 1e3)
    }
}

/// A built structure with the primitives it traces.
pub enum Accel<'a, V: Vector, P> {
    /// No structure: brute force over the primitives in their own order.
    Brute(&'a P),
    /// A tree and the primitives in its leaf order.
    Tree(Tree<V>, LeafOrdered<P>),
}

impl<V: Vector, P: PrimitiveSet<V>> Accel<'_, V, P> {
    /// Traces one ray.
    #[inline]
    pub fn trace<O: Observer<V::Scalar>>(
        &self,
        ray: &Ray<V>,
        options: &TraceOptions,
        stacks: &mut TraversalStacks<V::Scalar>,
        observer: &mut O,
    ) -> Option<Hit<V::Scalar>> {
        match self {
            Accel::Brute(primitives) => brute_force(*primitives, ray, options, observer),
            Accel::Tree(tree, primitives) => tree.trace(primitives, ray, options, stacks, observer),
        }
    }

    /// Traces up to 64 rays as a packet (see [`Tree::trace_packet`]; brute force takes them
    /// one by one), writing each ray's hit to `hits`.
    pub fn trace_packet<O: Observer<V::Scalar>>(
        &self,
        rays: &[Ray<V>],
        options: &TraceOptions,
        stacks: &mut TraversalStacks<V::Scalar>,
        observers: &mut [O],
        hits: &mut [Option<Hit<V::Scalar>>],
    ) {
        match self {
            Accel::Brute(primitives) => {
                for ((ray, observer), hit) in rays.iter().zip(observers).zip(hits) {
                    *hit = brute_force(*primitives, ray, options, observer);
                }
            }
            Accel::Tree(tree, primitives) => {
                tree.trace_packet(primitives, rays, options, stacks, observers, hits)
            }
        }
    }

    /// The tree's statistics with these cost constants (for brute force: one leaf holding
    /// everything).
    pub fn stats(&self, primitive_count: usize, cost: &SahCost) -> TreeStats {
        match self {
            Accel::Brute(_) => TreeStats {
                min_leaf_size: primitive_count,
                max_leaf_size: primitive_count,
                mean_leaf_size: primitive_count as f64,
                primitive_references: primitive_count,
                sah_cost: cost.leaf_cost(primitive_count),
                ..TreeStats::default()
            },
            Accel::Tree(tree, _) => tree.stats(cost),
        }
    }
}

impl<V: Vector, P: PrimitiveSet<V>> Accel<'_, V, P> {
    /// The tree's memory and fill rate, and its leaves' sizes (brute force: nothing, and one
    /// leaf of everything is not counted).
    pub fn footprint(&self) -> (accelviz_core::quality::Footprint, Vec<u64>) {
        match self {
            Accel::Brute(_) => (
                accelviz_core::quality::Footprint {
                    bytes: 0,
                    fill_rate: None,
                },
                Vec::new(),
            ),
            Accel::Tree(tree, _) => (
                accelviz_core::quality::Footprint::of(tree),
                accelviz_core::quality::leaf_size_histogram(tree),
            ),
        }
    }
}

impl<V: Vector, P: PrimitiveSet<V>> Accel<'_, V, P> {
    /// The facts of a binary tree (a BVH of two children a node, or a kD-tree), whose every
    /// node a traversal enters: what the SAH's chances are checked on. `None` for a wide BVH
    /// (its traversal skips the binary nodes it collapsed) and for brute force.
    pub fn binary_facts(&self) -> Option<accelviz_core::TreeFacts<V>> {
        match self {
            Accel::Tree(tree @ (Tree::Bvh(_) | Tree::Kd(_)), _) => {
                Some(accelviz_core::TreeFacts::of(tree))
            }
            _ => None,
        }
    }
}

impl<V: accelviz_core::Vector3, P: PrimitiveSet<V>> Accel<'_, V, P> {
    /// The tree's end-point overlap over `triangles` (in their own numbering), for a BVH (a
    /// wide one's is the binary tree's it was collapsed from); `None` for a kD-tree, whose
    /// cells do not overlap, and for brute force.
    pub fn epo(&self, triangles: &[[V; 3]], cost: &SahCost) -> Option<f64> {
        match self {
            Accel::Tree(tree @ (Tree::Bvh(_) | Tree::Bvh4(_) | Tree::Bvh8(_)), _) => {
                Some(accelviz_core::quality::epo(tree, triangles, cost))
            }
            _ => None,
        }
    }
}

impl<V: Vector, P: PrimitiveSet<V> + Sync> Accel<'_, V, P> {
    /// Traces every ray on `workers` with the observer that does nothing (what benchmarks
    /// time); returns the number of hits. (Kept out of line so profiles can single it out.)
    #[inline(never)]
    pub fn count_hits(&self, rays: &[Ray<V>], options: &TraceOptions, workers: &Workers) -> usize {
        workers.count(rays, TraversalStacks::default, |stacks, ray| {
            self.trace(ray, options, stacks, &mut NoObserver).is_some()
        })
    }
}
