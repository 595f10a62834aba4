//! The app's integration tests, one module a subject, in one test binary: each test binary
//! links the whole GPU stack, so one binary instead of twelve saves most of a cold CI run's
//! linking.

mod background;
mod bounds;
mod common;
mod contrast;
mod cracks;
mod fonts;
mod grids;
mod interaction;
mod large_mesh;
mod layout;
mod lecture;
mod lessons;
mod quiz;
mod share;
mod start;
mod steps;
mod trade;
mod view3d;
