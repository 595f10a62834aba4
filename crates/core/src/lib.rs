//! # accelviz-core
//!
//! The algorithms of accelviz, for teaching and measuring ray-tracing acceleration structures.
//! One implementation serves 2D and 3D, f32 and f64, through the narrow [`Vector`] trait
//! implemented for glam's `Vec2`, `Vec3`, `DVec2` and `DVec3`.
//!
//! The pipeline:
//!
//! ```text
//! primitives ──bounds──▶ boxes ──builder──▶ Bvh (flat nodes) ──traverse + Observer──▶ hits, counts, steps
//!     └──────────────────────────── brute_force (the reference) ───────────────────────────┘
//! ```
//!
//! - [`slab`]: the slab test, with the record a lesson shows and the hot path traversal runs.
//! - [`bounding`]: bounding box and sphere of an object, their reject tests and void.
//! - [`kd`]: kD-trees (middle and median cuts), the lecture's near-side-first traversal, a
//!   validator.
//! - [`grid`]: uniform grids, in a dense table or a hash table, walked cell by cell
//!   (Amanatides & Woo 1987); [`octree`]: octrees (quadtrees in 2D), walked front to back
//!   (Revelles et al. 2000).
//! - [`bvh`]: four builders ([`bvh::MiddleSplit`], [`bvh::MedianSplit`], [`bvh::BinnedSah`],
//!   [`bvh::SweepSah`]) sharing one [`SahCost`], one traversal, a validator and statistics.
//! - [`observer`]: how traversal reports each step (nothing, counts, or a full record).
//! - [`structure`]: the catalogue of every structure (`bvh:middle` … `octree`), built
//!   into a [`Tree`]; [`build_observer`]: how a builder reports each node and why it made each
//!   leaf; [`facts`]: what views show about a tree (boxes, cells, paths, depths), computed once.
//! - [`bytes`]: a built tree as bytes and back (each family writes its own; `Built::to_bytes`),
//!   for memory that is not shared: a Web Worker's build, a GPU's layout.
//! - [`break_even`]: which structure is fastest overall for N rays (build + N × trace).
//! - [`crack`]: the cases behind the trade: a ray at a shared edge, far from the origin, through
//!   a box's corner; decided by the core's own tests.
//! - [`quality`]: what a tree is worth beyond its SAH cost (end-point overlap).
//! - [`outcome`]: a traced ray's answer against a reference that is sure of itself on the
//!   same rounded inputs: agree, tie, graze, leak, false hit or wrong.
//! - [`compiled`]: a triangle mesh's builds and traversals compiled in this crate, for the
//!   callers compiled for size (the browser app).
//! - [`camera`]: which ray goes through which pixel (the benchmark's camera rays, the app's
//!   3D view and clicks); [`heatmap`]: every pixel's traversal cost, counted by the one
//!   traversal.
//!
//! No file IO, no UI: this crate builds for `wasm32-unknown-unknown`.

pub mod aabb;
pub mod bounding;
pub mod break_even;
pub mod brute;
pub mod build_observer;
pub mod built;
mod built_bytes;
pub mod bvh;
pub mod bytes;
pub mod camera;
pub mod compiled;
pub mod crack;
pub mod curve;
pub mod facts;
pub mod format;
pub mod grid;
pub mod heatmap;
pub mod kd;
pub mod math;
pub mod observer;
pub mod octree;
pub mod outcome;
mod parallel;
pub mod params;
pub mod primitive;
pub mod quality;
pub mod query;
pub mod ray;
pub mod sah;
mod search;
pub mod simd;
pub mod slab;
pub mod stats;
pub mod structure;
pub mod trade;
mod trade_bytes;
pub mod trade_lab;
pub mod trade_summary;

pub use aabb::{Aabb, Aabb2, Aabb3};
pub use brute::brute_force;
pub use build_observer::{BuildObserver, BuildRecorder, BuildStep, LeafReason, NoBuildObserver};
pub use built::Built;
pub use facts::{Children, Hierarchy, TreeFacts};
pub use math::{Real, Vector, Vector3};
pub use observer::{Counters, MaxStack, NoObserver, Observer, Recorder, Step, counters_of};
pub use params::{BuildParams, GridParams, KdBudget};
pub use primitive::{
    HitTest, LeafOrdered, LeafPrimitives, PrimitiveSet, Shape, ShapeSet, Sphere, TriangleSet,
};
pub use query::{Hit, Order, Query, QueryNameError, TraceOptions};
pub use ray::{Ray, Ray2, Ray3, RayError};
pub use sah::SahCost;
pub use slab::{SlabRay, SlabRecord, slab_clip, slab_record};
pub use stats::TreeStats;
pub use structure::{CATALOGUE, Family, SplitRule, Structure, TraversalStacks, Tree, Width};
