//! The lessons, one file each, in the lecture's order (listed in [`crate::registry`]). Each
//! draws from the core through the shared pieces ([`crate::stage`], [`crate::trace`],
//! [`crate::views`]) and never from another lesson.

pub mod bounding_volumes;
pub mod build_steps;
pub mod bvh;
pub mod cost_split;
pub mod cracks;
pub mod grid;
pub mod hashing;
pub mod heat;
pub mod kd;
pub mod mesh_tree;
pub mod near_first;
pub mod quadtree;
pub mod recap;
pub mod slab;
pub mod slab3d;
pub mod splits;
pub mod trade;
pub mod trivial;
