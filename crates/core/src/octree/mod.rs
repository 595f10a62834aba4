//! Octrees (quadtrees in 2D): a cell cut at its middle into `2^D` equal children, again and
//! again, until it holds few enough primitives; "a kD-tree whose cuts are forced to the middle
//! on every axis at once". Walked front to back in the order the ray's direction sets
//! (Revelles, Ureña & Lastra 2000).
//!
//! Primitives → [`build`] → [`Octree`] (flat nodes, children side by side) → [`traverse`]
//! told about each cell by an [`Observer`](crate::observer::Observer). [`validate`] checks
//! any octree.

mod build;
mod bytes;
mod traverse;
mod tree;
mod validate;

pub use build::{DEFAULT_LEAF_SIZE, build, depth_limit};
pub use traverse::{OctreeStack, traverse};
pub use tree::{Octree, OctreeLimits, OctreeNode, child_cell, child_count, middle};
pub use validate::{OctreeValidationError, validate};

/// A quadtree: the 2D octree, in f32.
pub type Quadtree = Octree<glam::Vec2>;
