//! Building a uniform grid (Cleary & Wyvill 1988, "Analysis of an algorithm for fast ray
//! tracing using uniform space subdivision"): choose the cells from the primitive count and
//! the box's shape, list every primitive in every cell it reaches, and store the lists as
//! Lagae & Dutré 2008's compact grid, with one counting sort.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReason};
use crate::facts::Children;
use crate::grid::cells::GridCells;
use crate::grid::tree::{DenseCells, GridLimits, HashedCells, HashedGrid, UniformGrid};
use crate::math::Vector;
use crate::params::BuildParams;
use crate::primitive::PrimitiveSet;

/// Cells per primitive when none is asked for. Measured with `accelviz-cli bench --mailbox`
/// (5 interleaved rounds, one thread, AMD EPYC with AVX-512) on the bunny, the rocker arm,
/// suzanne and the teapot in a stadium, 100,000 random rays and 256² camera rays each: one
/// cell per primitive traced 6 to 18 % slower than two on every mesh and ray kind; 2, 3 and
/// 4 stayed within 10 % of each other (the rounds moved by 5 to 15 %), and 8 was slower again.
/// Two is the least memory and build time among the best (Ize et al. 2007 found 2 to 8).
pub const DEFAULT_DENSITY: f64 = 2.0;

/// Builds a uniform grid over `primitives` with about `density` cells per primitive (see
/// [`GridCells::for_primitives`]), telling `observer` about its box and its cells (and a restart
/// for each lowering of the density); or, where `params.grid` chooses the cells along the
/// longest side, with those ([`GridCells::along_longest`]), whatever the budget.
///
/// Each primitive is listed in every cell its box touches that it really reaches (an exact
/// overlap test, [`PrimitiveSet::overlaps`]: Akenine-Möller 2001 for triangles), each cell's
/// list in increasing order. Past the build's budget (`params.kd_budget`: cells and
/// references per primitive) the density is halved until the grid fits, and the grid says so
/// ([`GridLimits`]).
pub fn build_uniform<V: Vector, P: PrimitiveSet<V>, O: BuildObserver>(
    primitives: &P,
    density: f64,
    params: &BuildParams,
    observer: &mut O,
) -> UniformGrid<V> {
    let count = primitives.len();
    let bounds = (0..count).fold(Aabb::empty(), |acc, index| {
        acc.union(primitives.bounds(index))
    });
    if let Some(along_longest) = params.grid.cells_along_longest {
        observer.node_started(0, 0, count);
        let grid = build_with_cells(primitives, GridCells::along_longest(bounds, along_longest));
        report_cells(&grid.cells, observer);
        return grid;
    }
    let node_budget = params.kd_budget.nodes_for(count);
    let reference_budget = params.kd_budget.references_for(count);
    let mut density_used = density;
    loop {
        observer.node_started(0, 0, count);
        let cells = GridCells::for_primitives(bounds, count, density_used);
        // The smallest grid always fits: one cell lists every primitive once.
        let budget = match cells.cell_count() {
            1 => usize::MAX,
            cell_count if cell_count > node_budget => 0,
            _ => reference_budget,
        };
        if let Some(store) = list_primitives(primitives, &cells, budget) {
            report_cells(&cells, observer);
            return UniformGrid {
                cells,
                store,
                limits: GridLimits {
                    density_asked: density,
                    density_used,
                },
            };
        }
        density_used /= 2.0;
        observer.restarted();
    }
}

/// The uniform grid of [`build_uniform`], its occupied cells moved into a hash table of
/// `params.grid.hash_places` places (the default for `None`: [`HashedCells::default_places`]).
pub fn build_hashed<V: Vector, P: PrimitiveSet<V>, O: BuildObserver>(
    primitives: &P,
    density: f64,
    params: &BuildParams,
    observer: &mut O,
) -> HashedGrid<V> {
    let dense = build_uniform(primitives, density, params, observer);
    let occupied = dense
        .store
        .cell_start
        .windows(2)
        .filter(|run| run[0] < run[1])
        .count();
    let places = params
        .grid
        .hash_places
        .unwrap_or_else(|| HashedCells::default_places(occupied));
    HashedGrid {
        store: HashedCells::from_dense(&dense.store, dense.cells.resolution, places),
        cells: dense.cells,
        limits: dense.limits,
    }
}

/// A uniform grid over `primitives` with the cells `cells` (their box should hold every
/// primitive: one outside is listed in the cells nearest it), whatever the budget: what a
/// lesson builds to show cells of a chosen size.
pub fn build_with_cells<V: Vector, P: PrimitiveSet<V>>(
    primitives: &P,
    cells: GridCells<V>,
) -> UniformGrid<V> {
    let store = list_primitives(primitives, &cells, usize::MAX)
        .unwrap_or_else(|| unreachable!("no budget to pass"));
    // The density these cells amount to.
    let density = cells.cell_count() as f64 / primitives.len().max(1) as f64;
    UniformGrid {
        cells,
        store,
        limits: GridLimits {
            density_asked: density,
            density_used: density,
        },
    }
}

/// Every primitive in every cell it reaches, as a compact grid; `None` past `budget`
/// references (at once for a budget of 0).
fn list_primitives<V: Vector, P: PrimitiveSet<V>>(
    primitives: &P,
    cells: &GridCells<V>,
    budget: usize,
) -> Option<DenseCells> {
    if budget == 0 {
        return None;
    }
    // (cell, primitive) pairs, primitives in increasing order.
    let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(primitives.len());
    for primitive in 0..primitives.len() {
        let bounds = primitives.bounds(primitive);
        let (first, last) = cells.cells_touching(&bounds);
        let one_cell = first == last;
        for z in first[2]..=last[2] {
            for y in first[1]..=last[1] {
                for x in first[0]..=last[0] {
                    let coordinates = [x, y, z];
                    // A box inside one cell needs no test: the primitive is in it.
                    if one_cell || primitives.overlaps(primitive, &cells.cell_bounds(coordinates)) {
                        pairs.push((cells.index(coordinates), primitive as u32));
                        if pairs.len() > budget {
                            return None;
                        }
                    }
                }
            }
        }
    }
    // A counting sort by cell keeps each cell's primitives in increasing order.
    let cell_count = cells.cell_count();
    let mut cell_start = vec![0u32; cell_count + 1];
    for &(cell, _) in &pairs {
        cell_start[cell as usize + 1] += 1;
    }
    for cell in 0..cell_count {
        cell_start[cell + 1] += cell_start[cell];
    }
    let mut next = cell_start.clone();
    let mut references = vec![0u32; pairs.len()];
    for (cell, primitive) in pairs {
        let slot = &mut next[cell as usize];
        references[*slot as usize] = primitive;
        *slot += 1;
    }
    Some(DenseCells {
        cell_start,
        references,
    })
}

/// Tells `observer` that the grid's box (node 0) holds its cells (nodes `1..=cells`), each a
/// leaf.
fn report_cells<V: Vector, O: BuildObserver>(cells: &GridCells<V>, observer: &mut O) {
    let count = cells.cell_count() as u32;
    observer.split(0, Children { first: 1, count }, None);
    for cell in 1..=count {
        observer.leaf(cell, LeafReason::GridCell);
    }
}
