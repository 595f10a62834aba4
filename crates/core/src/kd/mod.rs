//! kD-trees: space cut by axis-aligned planes, straddling primitives listed on both sides.
//! Three ways to place the planes: the cell's middle, the primitives' median, and the SAH.
//!
//! Boxes → a builder (`build_*`) → [`KdTree`] (flat nodes, index children) → [`traverse`]
//! (the lecture's near-side-first recursion, with an explicit stack) told about each step by an
//! [`Observer`](crate::observer::Observer). [`validate`] checks any tree.

pub(crate) mod build;
pub(crate) mod build_median;
pub(crate) mod build_middle;
mod build_sah;
mod build_sah_presorted;
mod bytes;
pub(crate) mod events;
mod traverse;
mod tree;
mod validate;

pub use build::KdBuilder;
pub use build_median::KdMedianSplit;
pub use build_middle::KdMiddleSplit;
pub use build_sah::KdSah;
pub use build_sah_presorted::KdSahPresorted;
pub use traverse::{KdTraversalStack, traverse};
pub use tree::{KdBudgetExceeded, KdLimits, KdNode, KdTree};
pub use validate::{KdValidationError, validate, validate_clipped};
