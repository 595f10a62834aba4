//! Bounding volume hierarchies: a flat array of nodes, four builders, one traversal; and wide
//! BVHs (4 or 8 children per node) collapsed from them, with their own traversal.
//!
//! Boxes → a builder (`build_*`) → [`Bvh`] (flat nodes, index children) → [`traverse`] told
//! about each step by an [`Observer`](crate::observer::Observer). [`validate`] checks any tree;
//! [`TreeStats`](crate::stats::TreeStats) measures it. A [`Bvh`] → [`collapse`] →
//! [`WideBvh`] → [`traverse_wide`] (one ray) or [`traverse_packet`] (up to [`MAX_PACKET`]
//! coherent rays), both over the kernels of [`simd`](crate::simd), checked by
//! [`validate_wide`].

mod build;
pub(crate) mod build_binned;
mod build_median;
mod build_middle;
pub(crate) mod build_sweep;
mod bytes;
mod collapse;
mod packet_traverse;
mod traverse;
mod tree;
mod validate;
mod wide;
pub(crate) mod wide_traverse;

pub use crate::simd::MAX_PACKET;
pub use build::Builder;
pub use build_binned::BinnedSah;
pub use build_median::MedianSplit;
pub use build_middle::MiddleSplit;
pub use build_sweep::SweepSah;
pub use collapse::collapse;
pub use packet_traverse::{PacketStack, traverse_packet};
pub use traverse::{TraversalStack, traverse};
pub use tree::{Bvh, BvhNode};
pub use validate::{ValidationError, validate, validate_wide};
pub use wide::{EMPTY_SLOT, LEAF_BLOCK, LOWER, Slot, UPPER, WideBvh, WideNode};
pub use wide_traverse::{WideStack, traverse_wide};

/// A 2D BVH in f32.
pub type Bvh2 = Bvh<glam::Vec2>;
/// A 3D BVH in f32.
pub type Bvh3 = Bvh<glam::Vec3>;
