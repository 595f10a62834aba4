//! Primitives and the trait through which traversal and brute force test them.
//!
//! Builders never see primitives: they get one box per primitive. Traversal and brute force
//! test primitives only through [`PrimitiveSet`], so a triangle mesh and a 2D scene of
//! segments and discs run the same code.

pub(crate) mod clip;
pub use clip::clipped_polygon;
mod overlap;
mod shape;
mod triangle;

pub use shape::{Shape, ShapeSet, Sphere};
pub use triangle::{TriangleBlock, TriangleRay, TriangleSet, TriangleTestValues};

use crate::aabb::Aabb;
use crate::math::{Real, Vector, Vector3};
use crate::ray::Ray;

/// Which ray/primitive test to run where there is a choice (triangles).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum HitTest {
    /// Möller & Trumbore 1997: fast, but a ray through a shared edge or vertex can slip
    /// between the two triangles.
    #[default]
    Fast,
    /// Woop, Benthin & Wald 2013, "Watertight Ray/Triangle Intersection": never misses
    /// through a shared edge or vertex of a closed mesh.
    Watertight,
}

impl HitTest {
    /// Both tests.
    pub const ALL: [HitTest; 2] = [HitTest::Fast, HitTest::Watertight];

    /// `"fast"` or `"watertight"`, as links, JSON and the CLI spell it.
    pub fn name(self) -> &'static str {
        match self {
            HitTest::Fast => "fast",
            HitTest::Watertight => "watertight",
        }
    }

    /// The test called `name`.
    pub fn from_name(name: &str) -> Option<HitTest> {
        HitTest::ALL.into_iter().find(|test| test.name() == name)
    }
}

/// An indexed set of primitives that a ray can be tested against. It is plain data, shared by
/// the threads that build over it and trace it (`Sync`).
pub trait PrimitiveSet<V: Vector>: Sync {
    /// What a ray precomputes once before testing many primitives.
    type RayData: 'static;

    /// The number of primitives; they are numbered `0..len()`.
    fn len(&self) -> usize;

    /// True when there are no primitives.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The bounding box of primitive `index`.
    fn bounds(&self, index: usize) -> Aabb<V>;

    /// Precomputes what the tests of `ray` share.
    fn prepare(&self, ray: &Ray<V>, test: HitTest) -> Self::RayData;

    /// The smallest `t` in `[t_min, t_max]` where the ray meets primitive `index`, if any.
    fn intersect(
        &self,
        ray: &Self::RayData,
        index: usize,
        t_min: V::Scalar,
        t_max: V::Scalar,
    ) -> Option<V::Scalar>;

    /// The box around the part of primitive `index` inside the closed box `cell`, or `None`
    /// when no part of it is there: what kD "perfect splits" use. Never smaller than the exact
    /// box of that part. By default, the primitive's box clipped to the cell.
    fn clipped_bounds(&self, index: usize, cell: &Aabb<V>) -> Option<Aabb<V>> {
        self.bounds(index).intersection(cell)
    }

    /// Whether primitive `index` reaches into the closed box `cell`: what a grid lists it by.
    /// Conservative: touching counts, and where rounding cannot tell, so does nearly
    /// touching. By default, whether it has a part in the cell
    /// ([`clipped_bounds`](Self::clipped_bounds)).
    fn overlaps(&self, index: usize, cell: &Aabb<V>) -> bool {
        self.clipped_bounds(index, cell).is_some()
    }

    /// Every primitive's box, in order: what a builder takes.
    fn all_bounds(&self) -> Vec<Aabb<V>> {
        (0..self.len()).map(|index| self.bounds(index)).collect()
    }

    /// The same primitives stored in another order: element `k` of the result is primitive
    /// `order[k]` of this set (without [`blocks`](Self::blocks)).
    fn permuted(&self, order: &[u32]) -> Self
    where
        Self: Sized;

    /// The same set with its primitives also packed for SIMD tests, where it has such a form:
    /// 3D triangles four to a [`TriangleBlock`] (in the set's order: a wide BVH's leaf order
    /// when [`LeafOrdered`] asks). Other sets are returned as they are.
    fn with_blocks(self) -> Self
    where
        Self: Sized,
    {
        self
    }

    /// The blocks [`with_blocks`](Self::with_blocks) packed, if it packed any.
    #[inline(always)]
    fn blocks(&self) -> Option<&[TriangleBlock<V::Scalar>]> {
        None
    }

    /// A ray prepared for this set's tests, as the triangle blocks' kernels take it: `Some`
    /// for 3D triangles (whose preparation it is), `None` for other sets.
    #[inline(always)]
    fn block_ray(_ray: &Self::RayData) -> Option<&TriangleRay<<V::Scalar as Real>::Vec3>> {
        None
    }
}

/// How traversal reaches the primitive in a leaf slot: a plain [`PrimitiveSet`] is stored in
/// its own numbering; a [`LeafOrdered`] set is stored in the tree's leaf order, so a leaf's
/// primitives sit side by side in memory. Hits are numbered the same way either way.
pub trait LeafPrimitives<V: Vector> {
    /// The set the primitives are stored in.
    type Set: PrimitiveSet<V>;
    /// The stored set.
    fn stored(&self) -> &Self::Set;
    /// Where the primitive of leaf slot `slot`, numbered `primitive`, is stored.
    fn storage_index(&self, slot: usize, primitive: u32) -> usize;
    /// The primitives as 3D triangles four to a block, block `b` holding slots `4b..4b + 4`
    /// (a wide BVH's leaf order, see [`WideBvh::leaf_ordered`](crate::bvh::WideBvh::leaf_ordered)),
    /// when stored so.
    #[inline(always)]
    fn triangle_blocks(&self) -> Option<&[TriangleBlock<V::Scalar>]> {
        None
    }
}

/// Implements [`LeafPrimitives`] for a set stored in its own numbering. (A blanket impl over
/// every `PrimitiveSet` would collide with the one for [`LeafOrdered`].)
macro_rules! stored_in_own_order {
    ($set:ident, $bound:ident) => {
        impl<V: $bound> LeafPrimitives<V> for $set<V> {
            type Set = Self;

            #[inline(always)]
            fn stored(&self) -> &Self {
                self
            }

            #[inline(always)]
            fn storage_index(&self, _slot: usize, primitive: u32) -> usize {
                primitive as usize
            }
        }
    };
}
stored_in_own_order!(TriangleSet, Vector3);
stored_in_own_order!(ShapeSet, Vector);

/// A copy of a primitive set in one BVH's leaf order (see
/// [`Bvh::leaf_ordered`](crate::bvh::Bvh::leaf_ordered)): traversal then reads each leaf's
/// primitives from consecutive memory instead of jumping through the index list. Use it only
/// with the tree it was made for.
#[derive(Clone, Debug)]
pub struct LeafOrdered<P> {
    /// The set in leaf order; packed in blocks ([`PrimitiveSet::blocks`]) only for a wide
    /// BVH, whose leaves start at multiples of four.
    stored: P,
}

impl<P> LeafOrdered<P> {
    /// Wraps `stored`, which must hold the primitives in the leaf order of the tree it is
    /// traversed with.
    pub(crate) fn new(stored: P) -> Self {
        Self { stored }
    }

    /// Wraps `stored`, in the leaf order of a wide BVH (each leaf starting at a multiple of
    /// four), packed for SIMD tests where the set has such a form (3D triangles in blocks of
    /// four, [`PrimitiveSet::with_blocks`]).
    pub(crate) fn with_blocks<V: Vector>(stored: P) -> Self
    where
        P: PrimitiveSet<V>,
    {
        Self {
            stored: stored.with_blocks(),
        }
    }
}

impl<V: Vector, P: PrimitiveSet<V>> LeafPrimitives<V> for LeafOrdered<P> {
    type Set = P;

    #[inline(always)]
    fn stored(&self) -> &P {
        &self.stored
    }

    #[inline(always)]
    fn storage_index(&self, slot: usize, _primitive: u32) -> usize {
        slot
    }

    #[inline(always)]
    fn triangle_blocks(&self) -> Option<&[TriangleBlock<V::Scalar>]> {
        self.stored.blocks()
    }
}
