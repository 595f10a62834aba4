//! Primitives and the trait through which traversal and brute force test them.
//!
//! Builders never see primitives: they get one box per primitive. Traversal and brute force
//! test primitives only through [`PrimitiveSet`], so a triangle mesh and a 2D scene of
//! segments and discs run the same code.

pub(crate) mod clip;
pub use clip::clipped_polygon;
mod shape;
mod triangle;

pub use shape::{Shape, ShapeSet, Sphere};
pub use triangle::{TriangleBlock, TriangleRay, TriangleSet, TriangleTestValues};

use std::any::Any;

use crate::aabb::Aabb;
use crate::math::{Vector, Vector3};
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

/// An indexed set of primitives that a ray can be tested against.
pub trait PrimitiveSet<V: Vector> {
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

    /// Every primitive's box, in order: what a builder takes.
    fn all_bounds(&self) -> Vec<Aabb<V>> {
        (0..self.len()).map(|index| self.bounds(index)).collect()
    }

    /// The same primitives stored in another order: element `k` of the result is primitive
    /// `order[k]` of this set.
    fn permuted(&self, order: &[u32]) -> Self
    where
        Self: Sized;
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
    stored: P,
    /// For 3D triangles in a wide BVH's leaf order: the same triangles in blocks of four.
    blocks: Option<Blocks>,
}

/// Triangle blocks in their precision.
#[derive(Clone, Debug)]
enum Blocks {
    F32(Vec<TriangleBlock<f32>>),
    F64(Vec<TriangleBlock<f64>>),
}

impl<P> LeafOrdered<P> {
    /// Wraps `stored`, which must hold the primitives in the leaf order of the tree it is
    /// traversed with.
    pub(crate) fn new(stored: P) -> Self {
        Self {
            stored,
            blocks: None,
        }
    }

    /// Wraps `stored`, in the leaf order of a wide BVH (each leaf starting at a multiple of
    /// four), and when it is a set of 3D triangles packs them in blocks of four too.
    pub(crate) fn with_blocks(stored: P) -> Self
    where
        P: 'static,
    {
        let any = &stored as &dyn Any;
        let blocks = match (
            any.downcast_ref::<TriangleSet<glam::Vec3>>(),
            any.downcast_ref::<TriangleSet<glam::DVec3>>(),
        ) {
            (Some(triangles), _) => Some(Blocks::F32(TriangleBlock::pack(triangles.triangles()))),
            (_, Some(triangles)) => Some(Blocks::F64(TriangleBlock::pack(triangles.triangles()))),
            _ => None,
        };
        Self { stored, blocks }
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
        // Concrete types on both sides: the test is resolved when the code is compiled.
        match self.blocks.as_ref()? {
            Blocks::F32(blocks) => {
                (blocks as &dyn Any).downcast_ref::<Vec<TriangleBlock<V::Scalar>>>()
            }
            Blocks::F64(blocks) => {
                (blocks as &dyn Any).downcast_ref::<Vec<TriangleBlock<V::Scalar>>>()
            }
        }
        .map(Vec::as_slice)
    }
}
