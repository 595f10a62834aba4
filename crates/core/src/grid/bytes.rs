//! A grid's bytes ([`crate::bytes`]): its box and resolution (the cells are made again from
//! them), the density it was built for, and its dense table; a hashed grid also writes its
//! table's size and is hashed again from the dense table when read (deterministic).

use crate::bytes::{ByteReader, ByteWriter, BytesError};
use crate::math::Vector;

use super::cells::GridCells;
use super::tree::{DenseCells, Grid, GridLimits, HashedCells, HashedGrid, UniformGrid};

/// Writes the part every grid shares: box, resolution, limits; then the dense table.
fn write_grid<V: Vector>(
    cells: &GridCells<V>,
    limits: &GridLimits,
    dense: &DenseCells,
    out: &mut ByteWriter,
) {
    out.aabb(&cells.bounds);
    for count in cells.resolution {
        out.u32(count);
    }
    out.f64(limits.density_asked);
    out.f64(limits.density_used);
    out.u32s(&dense.cell_start);
    out.u32s(&dense.references);
}

/// Reads what [`write_grid`] wrote, checking that the table fits the cells.
fn read_grid<V: Vector>(
    input: &mut ByteReader<'_>,
) -> Result<(GridCells<V>, GridLimits, DenseCells), BytesError> {
    let bounds = input.aabb()?;
    let resolution = [input.u32()?, input.u32()?, input.u32()?];
    let limits = GridLimits {
        density_asked: input.f64()?,
        density_used: input.f64()?,
    };
    let dense = DenseCells {
        cell_start: input.u32s()?,
        references: input.u32s()?,
    };
    let cell_count = resolution
        .iter()
        .try_fold(1u64, |product, &count| product.checked_mul(count.into()))
        .filter(|&count| count <= super::MAX_CELLS)
        .ok_or_else(|| BytesError::Invalid(format!("a grid of {resolution:?} cells")))?;
    // Every cell's run lies in the references, one after another: what a lookup slices.
    let fits = dense.cell_start.len() as u64 == cell_count + 1
        && dense.cell_start.first() == Some(&0)
        && dense.cell_start.windows(2).all(|pair| pair[0] <= pair[1])
        && dense.cell_start.last().map(|&end| end as usize) == Some(dense.references.len());
    if !fits {
        return Err(BytesError::Invalid(
            "the grid's table does not fit its cells".into(),
        ));
    }
    Ok((
        GridCells::with_resolution(bounds, resolution),
        limits,
        dense,
    ))
}

impl<V: Vector> UniformGrid<V> {
    /// Writes the grid.
    pub fn write_bytes(&self, out: &mut ByteWriter) {
        write_grid(&self.cells, &self.limits, &self.store, out);
    }

    /// The grid [`UniformGrid::write_bytes`] wrote.
    pub fn read_bytes(input: &mut ByteReader<'_>) -> Result<Self, BytesError> {
        let (cells, limits, store) = read_grid(input)?;
        Ok(Grid {
            cells,
            store,
            limits,
        })
    }
}

impl<V: Vector> HashedGrid<V> {
    /// Writes the grid: as a dense table, and how many places its hash table has.
    pub fn write_bytes(&self, out: &mut ByteWriter) {
        let dense = self.store.to_dense(self.cells.cell_count());
        write_grid(&self.cells, &self.limits, &dense, out);
        out.usize(self.store.buckets.len());
    }

    /// The grid [`HashedGrid::write_bytes`] wrote, hashed again.
    pub fn read_bytes(input: &mut ByteReader<'_>) -> Result<Self, BytesError> {
        let (cells, limits, dense) = read_grid(input)?;
        let places = input.usize()?;
        if places as u64 > super::MAX_CELLS {
            return Err(BytesError::Invalid(format!(
                "a hash table of {places} places"
            )));
        }
        Ok(Grid {
            store: HashedCells::from_dense(&dense, cells.resolution, places),
            cells,
            limits,
        })
    }
}
