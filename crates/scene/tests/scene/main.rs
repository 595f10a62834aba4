//! The scene crate's integration tests on the shared meshes, one module a subject, in one
//! test binary.

mod outcomes;
mod ray_kinds;
mod shared_meshes;
mod trade_lab;
mod watertight;
