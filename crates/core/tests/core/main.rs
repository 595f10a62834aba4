//! The core's integration tests, one module a subject, in one test binary (one link instead
//! of eight).

mod brute_agreement;
mod common;
mod compiled;
mod cost_curves;
mod cracks;
mod grid_walk;
mod heatmap;
mod kd_budget;
mod kd_cases;
mod observer_steps;
mod octree_order;
mod parallel_build;
mod precision;
mod slab_extremes;
mod tree_bytes;
