//! Uniform grids: the box around the primitives cut into equal cells, each listing the
//! primitives that reach into it, walked cell by cell along the ray (Amanatides & Woo 1987).
//! The lecture's "hashing & indexing in tables": a cell's list is found by indexing a table
//! with the cell's number ([`DenseCells`]), or by hashing it into a smaller table that holds
//! only the cells with something in them ([`HashedCells`]).
//!
//! Primitives → [`build_uniform`] or [`build_hashed`] → [`Grid`] ([`GridCells`] and a
//! [`CellStore`]) → [`traverse`] told about each cell by an
//! [`Observer`](crate::observer::Observer). [`validate`] checks any grid.

mod build;
mod bytes;
mod cells;
mod traverse;
mod tree;
mod validate;

pub use build::{DEFAULT_DENSITY, build_hashed, build_uniform, build_with_cells};
pub use cells::{GridCells, MAX_CELLS};
pub use traverse::traverse;
pub use tree::{
    Bucket, CellLookup, CellStore, DenseCells, Grid, GridLimits, HashedCells, HashedGrid,
    UniformGrid,
};
pub use validate::{GridValidationError, validate};
