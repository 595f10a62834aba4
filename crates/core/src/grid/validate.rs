//! The grid validator: the cells tile the box around every primitive, every cell's list is
//! found where it is stored, each primitive is listed in every cell it reaches (the overlap
//! test, [`PrimitiveSet::overlaps`], asked again of every cell its box touches; the test
//! itself is held to clipping in its own property test) and in none its box does not touch.

use crate::grid::tree::{CellStore, Grid};
use crate::math::Vector;
use crate::primitive::PrimitiveSet;

/// What is wrong with a grid.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GridValidationError {
    /// The cells or their planes are malformed.
    #[error("grid cells: {what}")]
    Cells {
        /// What is wrong.
        what: String,
    },
    /// A primitive's box reaches outside the grid's box.
    #[error("primitive {primitive} reaches outside the grid's box")]
    Outside {
        /// The primitive.
        primitive: u32,
    },
    /// A cell's list is malformed (out of range, unsorted, repeated).
    #[error("cell {cell}: {what}")]
    List {
        /// The cell.
        cell: u32,
        /// What is wrong.
        what: String,
    },
    /// A primitive reaches a cell that does not list it.
    #[error("primitive {primitive} reaches cell {cell}, which does not list it")]
    Missing {
        /// The primitive.
        primitive: u32,
        /// The cell.
        cell: u32,
    },
    /// A cell lists a primitive whose box does not even touch it.
    #[error("cell {cell} lists primitive {primitive}, whose box does not touch it")]
    Stray {
        /// The primitive.
        primitive: u32,
        /// The cell.
        cell: u32,
    },
}

/// Checks `grid`, built over `primitives`.
pub fn validate<V: Vector, C: CellStore, P: PrimitiveSet<V>>(
    grid: &Grid<V, C>,
    primitives: &P,
) -> Result<(), GridValidationError> {
    let cells = &grid.cells;
    let cells_error = |what: String| GridValidationError::Cells { what };
    // No primitives: an empty box, one cell, nothing listed.
    if cells.bounds.is_empty() {
        return match (primitives.len(), grid.store.references().len()) {
            (0, 0) => Ok(()),
            (count, listed) => Err(cells_error(format!(
                "an empty box for {count} primitives, {listed} listed"
            ))),
        };
    }
    // The planes: n + 1 per axis, from the box's minimum to its maximum, never decreasing.
    for axis in 0..V::DIM {
        let planes = &cells.planes[axis];
        let count = cells.resolution[axis] as usize;
        if count == 0 || planes.len() != count + 1 {
            return Err(cells_error(format!(
                "axis {axis}: {} planes for {count} cells",
                planes.len()
            )));
        }
        if planes[0] != cells.bounds.min[axis] || planes[count] != cells.bounds.max[axis] {
            return Err(cells_error(format!(
                "axis {axis}: the planes do not end at the box's sides"
            )));
        }
        if planes.windows(2).any(|pair| {
            pair[0]
                .partial_cmp(&pair[1])
                .is_none_or(|order| order.is_gt())
        }) {
            return Err(cells_error(format!("axis {axis}: the planes decrease")));
        }
    }
    if (V::DIM..3).any(|axis| cells.resolution[axis] != 1) {
        return Err(cells_error(
            "cells along an axis the grid does not have".into(),
        ));
    }
    grid.store.check(cells.cell_count()).map_err(cells_error)?;
    let count = primitives.len();
    for primitive in 0..count {
        if !cells.bounds.contains(&primitives.bounds(primitive)) {
            return Err(GridValidationError::Outside {
                primitive: primitive as u32,
            });
        }
    }
    // Every cell's list: in range, increasing; and every reference found through a lookup.
    let mut listed_count = 0usize;
    for cell in 0..cells.cell_count() as u32 {
        let listed = grid.store.lookup(cell).primitives;
        listed_count += listed.len();
        let list_error = |what: String| GridValidationError::List { cell, what };
        if let Some(&beyond) = listed
            .iter()
            .find(|&&primitive| primitive as usize >= count)
        {
            return Err(list_error(format!("primitive {beyond} of {count}")));
        }
        if listed.windows(2).any(|pair| pair[0] >= pair[1]) {
            return Err(list_error("its list is not increasing".into()));
        }
        let coordinates = cells.coordinates(cell);
        let cell_bounds = cells.cell_bounds(coordinates);
        for &primitive in listed {
            if cell_bounds
                .intersection(&primitives.bounds(primitive as usize))
                .is_none()
            {
                return Err(GridValidationError::Stray { primitive, cell });
            }
        }
    }
    if listed_count != grid.store.references().len() {
        return Err(cells_error(format!(
            "{} references stored, {listed_count} found by looking every cell up",
            grid.store.references().len()
        )));
    }
    // Every cell a primitive reaches lists it.
    for primitive in 0..count {
        let (first, last) = cells.cells_touching(&primitives.bounds(primitive));
        for z in first[2]..=last[2] {
            for y in first[1]..=last[1] {
                for x in first[0]..=last[0] {
                    let coordinates = [x, y, z];
                    let reaches = primitives.overlaps(primitive, &cells.cell_bounds(coordinates));
                    let cell = cells.index(coordinates);
                    if reaches
                        && grid
                            .store
                            .lookup(cell)
                            .primitives
                            .binary_search(&(primitive as u32))
                            .is_err()
                    {
                        return Err(GridValidationError::Missing {
                            primitive: primitive as u32,
                            cell,
                        });
                    }
                }
            }
        }
    }
    Ok(())
}
