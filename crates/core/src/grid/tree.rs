//! A grid's memory: its cells ([`GridCells`]) and where each cell's primitives are listed,
//! either in a dense table with a place for every cell ([`DenseCells`]) or in a hash table
//! with places only for the cells that hold something ([`HashedCells`]).

use crate::aabb::Aabb;
use crate::facts::{Children, Hierarchy};
use crate::grid::cells::GridCells;
use crate::math::{Real, Vector};
use crate::primitive::{LeafOrdered, PrimitiveSet};
use crate::sah::SahCost;
use crate::stats::TreeStats;

/// Where a grid keeps each cell's list of primitives.
pub trait CellStore: Clone + std::fmt::Debug + PartialEq + Send + Sync + 'static {
    /// Whether a lookup can take more than one read (a hash table's probes), which the walk
    /// then reports to its observer.
    const HASHED: bool;

    /// Cell `cell`'s primitives (a slice of the references) and where they start in them,
    /// with how many table places the lookup read.
    fn lookup(&self, cell: u32) -> CellLookup<'_>;

    /// [`lookup`](Self::lookup) of the cell at `coordinates` (number `cell`), for a walk that
    /// knows both (a hash table hashes the coordinates, and need not work them out again).
    #[inline(always)]
    fn lookup_at(&self, cell: u32, _coordinates: [u32; 3]) -> CellLookup<'_> {
        self.lookup(cell)
    }

    /// Every cell's primitives, cell after cell (a primitive once in each cell it reaches).
    fn references(&self) -> &[u32];

    /// Bytes the store takes: its table and its references.
    fn bytes(&self) -> usize;

    /// Checks the table itself for a grid of `cell_count` cells (what the validator asks
    /// before it looks every cell up).
    fn check(&self, cell_count: usize) -> Result<(), String>;
}

/// What a lookup of one cell found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellLookup<'a> {
    /// The cell's primitives, in increasing order.
    pub primitives: &'a [u32],
    /// Where they start in [`CellStore::references`].
    pub first: u32,
    /// Table places read to find them (1 for a dense table; a hash table's probes).
    pub probes: u32,
}

/// The compact dense layout of Lagae & Dutré 2008 ("Compact, fast and robust grids for ray
/// tracing"): exactly one index per cell, where its run of primitives starts, and exactly
/// one per reference: the literal "indexing in a table".
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DenseCells {
    /// Per cell, where its primitives start in `references`, and one more entry at the end:
    /// cell `c`'s are `references[cell_start[c]..cell_start[c + 1]]`.
    pub cell_start: Vec<u32>,
    /// Every cell's primitives, cell after cell.
    pub references: Vec<u32>,
}

impl CellStore for DenseCells {
    const HASHED: bool = false;

    #[inline(always)]
    fn lookup(&self, cell: u32) -> CellLookup<'_> {
        let first = self.cell_start[cell as usize];
        let end = self.cell_start[cell as usize + 1];
        CellLookup {
            primitives: &self.references[first as usize..end as usize],
            first,
            probes: 1,
        }
    }

    fn references(&self) -> &[u32] {
        &self.references
    }

    fn bytes(&self) -> usize {
        4 * (self.cell_start.len() + self.references.len())
    }

    /// One start per cell and one more, from 0 to the last reference, never decreasing.
    fn check(&self, cell_count: usize) -> Result<(), String> {
        if self.cell_start.len() != cell_count + 1 {
            return Err(format!(
                "{} cell starts for {cell_count} cells",
                self.cell_start.len()
            ));
        }
        let ends = (self.cell_start[0], self.cell_start[cell_count]);
        if ends != (0, self.references.len() as u32) {
            return Err(format!("the cell starts run from {} to {}", ends.0, ends.1));
        }
        if self.cell_start.windows(2).any(|pair| pair[0] > pair[1]) {
            return Err("the cell starts decrease".into());
        }
        Ok(())
    }
}

/// One place of a [`HashedCells`] table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bucket {
    /// The cell stored here, or [`Bucket::EMPTY`].
    pub cell: u32,
    /// Where its primitives start in the references.
    pub first: u32,
    /// How many.
    pub count: u32,
}

impl Bucket {
    /// The `cell` of an empty place.
    pub const EMPTY: u32 = u32::MAX;
}

/// The grid's cells kept in a hash table of a chosen number of places (Teschner, Heidelberger,
/// Müller, Pomeranets & Gross 2003, "Optimized spatial hashing for collision detection of
/// deformable objects"): only cells that hold a primitive are stored, so memory follows the
/// occupied cells, not the box. A cell `(i, j, k)` hashes to
/// `(i·73856093 ⊕ j·19349663 ⊕ k·83492791) mod m`; a place already taken sends it on to the
/// next free one (linear probing), and a lookup reads places from the cell's own until it
/// finds the cell or an empty place. The lists are the dense grid's, so a walk tests the
/// same primitives in the same cells.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HashedCells {
    /// The table's places.
    pub buckets: Vec<Bucket>,
    /// Every occupied cell's primitives, cell after cell.
    pub references: Vec<u32>,
    /// The cells per axis, which the hash reads a cell's number back into.
    resolution: [u32; 3],
    /// Occupied cells that found their own place taken (each takes more than one probe).
    pub collisions: usize,
}

/// Teschner et al.'s three large primes.
const HASH_PRIMES: [u32; 3] = [73_856_093, 19_349_663, 83_492_791];

impl HashedCells {
    /// The cells of `dense` (a grid of `resolution`) that hold something, in a table of
    /// `places` places (at least one more than the occupied cells, so a lookup always ends).
    pub fn from_dense(dense: &DenseCells, resolution: [u32; 3], places: usize) -> Self {
        let occupied: Vec<u32> = (0..dense.cell_start.len().saturating_sub(1) as u32)
            .filter(|&cell| dense.cell_start[cell as usize] < dense.cell_start[cell as usize + 1])
            .collect();
        let places = places.max(occupied.len() + 1);
        let mut table = Self {
            buckets: vec![
                Bucket {
                    cell: Bucket::EMPTY,
                    first: 0,
                    count: 0,
                };
                places
            ],
            references: dense.references.clone(),
            resolution,
            collisions: 0,
        };
        for cell in occupied {
            let (first, end) = (
                dense.cell_start[cell as usize],
                dense.cell_start[cell as usize + 1],
            );
            let mut place = table.home(cell);
            if table.buckets[place].cell != Bucket::EMPTY {
                table.collisions += 1;
            }
            while table.buckets[place].cell != Bucket::EMPTY {
                place = table.next_place(place);
            }
            table.buckets[place] = Bucket {
                cell,
                first,
                count: end - first,
            };
        }
        table
    }

    /// The table size a grid gets unless asked for another: the smallest power of two at
    /// least twice the occupied cells (a load of at most one half, where linear probing
    /// averages under 1.5 probes for a cell found and 2.5 for one absent; Knuth 1998, §6.4).
    pub fn default_places(occupied: usize) -> usize {
        (2 * occupied.max(1)).next_power_of_two()
    }

    /// The place cell `cell` hashes to.
    pub fn home(&self, cell: u32) -> usize {
        let [nx, ny, _] = self.resolution;
        self.home_of([cell % nx, (cell / nx) % ny, cell / (nx * ny)])
    }

    /// The place the cell at `coordinates` hashes to.
    #[inline(always)]
    pub fn home_of(&self, coordinates: [u32; 3]) -> usize {
        let hash = (0..3).fold(0u32, |hash, axis| {
            hash ^ coordinates[axis].wrapping_mul(HASH_PRIMES[axis])
        }) as usize;
        let places = self.buckets.len();
        // A power of two (the default size) takes a mask, where `%` is a division.
        if places.is_power_of_two() {
            hash & (places - 1)
        } else {
            hash % places
        }
    }

    /// The place after `place`, wrapping round.
    #[inline(always)]
    fn next_place(&self, place: usize) -> usize {
        if place + 1 == self.buckets.len() {
            0
        } else {
            place + 1
        }
    }

    /// The same lists in a dense table for a grid of `cell_count` cells (what
    /// [`HashedCells::from_dense`] was given).
    pub fn to_dense(&self, cell_count: usize) -> DenseCells {
        let mut cell_start = vec![0u32; cell_count + 1];
        for bucket in self
            .buckets
            .iter()
            .filter(|bucket| bucket.cell != Bucket::EMPTY)
        {
            cell_start[bucket.cell as usize + 1] = bucket.count;
        }
        for cell in 0..cell_count {
            cell_start[cell + 1] += cell_start[cell];
        }
        DenseCells {
            cell_start,
            references: self.references.clone(),
        }
    }

    /// How many cells the table holds.
    pub fn occupied(&self) -> usize {
        self.buckets
            .iter()
            .filter(|bucket| bucket.cell != Bucket::EMPTY)
            .count()
    }

    /// The share of places taken.
    pub fn load(&self) -> f64 {
        self.occupied() as f64 / self.buckets.len().max(1) as f64
    }

    /// The places a lookup reads, on average over every cell of a grid of `cell_count`
    /// cells: (for the cells stored, for the cells not stored). Linear probing's cost
    /// (Knuth 1998, §6.4): about `(1 + 1/(1 − α)) / 2` and `(1 + 1/(1 − α)²) / 2` at load α.
    pub fn probes_per_lookup(&self, cell_count: usize) -> (f64, f64) {
        let mut sums = [(0u64, 0u64); 2];
        for cell in 0..cell_count as u32 {
            let lookup = self.lookup(cell);
            let found = usize::from(self.place_of(cell).is_none());
            sums[found].0 += u64::from(lookup.probes);
            sums[found].1 += 1;
        }
        let mean = |(probes, lookups): (u64, u64)| probes as f64 / lookups.max(1) as f64;
        (mean(sums[0]), mean(sums[1]))
    }

    /// The place where cell `cell` is stored, if it holds anything.
    pub fn place_of(&self, cell: u32) -> Option<usize> {
        let mut place = self.home(cell);
        loop {
            match self.buckets[place].cell {
                stored if stored == cell => return Some(place),
                Bucket::EMPTY => return None,
                _ => place = self.next_place(place),
            }
        }
    }
}

impl CellStore for HashedCells {
    const HASHED: bool = true;

    fn lookup(&self, cell: u32) -> CellLookup<'_> {
        let [nx, ny, _] = self.resolution;
        self.lookup_at(cell, [cell % nx, (cell / nx) % ny, cell / (nx * ny)])
    }

    #[inline(always)]
    fn lookup_at(&self, cell: u32, coordinates: [u32; 3]) -> CellLookup<'_> {
        let mut place = self.home_of(coordinates);
        let mut probes = 1;
        loop {
            let bucket = &self.buckets[place];
            if bucket.cell == cell {
                return CellLookup {
                    primitives: &self.references[bucket.first as usize..][..bucket.count as usize],
                    first: bucket.first,
                    probes,
                };
            }
            if bucket.cell == Bucket::EMPTY {
                return CellLookup {
                    primitives: &[],
                    first: 0,
                    probes,
                };
            }
            place = self.next_place(place);
            probes += 1;
        }
    }

    fn references(&self) -> &[u32] {
        &self.references
    }

    fn bytes(&self) -> usize {
        std::mem::size_of::<Bucket>() * self.buckets.len() + 4 * self.references.len()
    }

    /// Every stored cell is found from its own place, its run lies in the references, and an
    /// empty place is left (so a lookup of an absent cell ends).
    fn check(&self, cell_count: usize) -> Result<(), String> {
        if !self
            .buckets
            .iter()
            .any(|bucket| bucket.cell == Bucket::EMPTY)
        {
            return Err("the hash table has no empty place".into());
        }
        for (place, bucket) in self.buckets.iter().enumerate() {
            if bucket.cell == Bucket::EMPTY {
                continue;
            }
            if bucket.cell as usize >= cell_count {
                return Err(format!("place {place} holds cell {}", bucket.cell));
            }
            if bucket.first as usize + bucket.count as usize > self.references.len() {
                return Err(format!("place {place}'s run passes the references"));
            }
            if self.place_of(bucket.cell) != Some(place) {
                return Err(format!(
                    "cell {} at place {place} is not found from its own place",
                    bucket.cell
                ));
            }
        }
        Ok(())
    }
}

/// A grid over primitives numbered `0..n`: its cells and their lists. Cell `c` is node `c + 1`
/// to observers and views; node 0 is the grid's box.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid<V: Vector, C: CellStore = DenseCells> {
    /// The cells.
    pub cells: GridCells<V>,
    /// Each cell's primitives.
    pub store: C,
    /// The density the grid was asked for and the one it was built with.
    pub limits: GridLimits,
}

/// A uniform grid in a dense table (see [`DenseCells`]).
pub type UniformGrid<V> = Grid<V, DenseCells>;
/// A uniform grid in a hash table (see [`HashedCells`]).
pub type HashedGrid<V> = Grid<V, HashedCells>;

/// The density a grid was asked for and the one it was built with: lower when the cells or
/// the references would have passed the build's budget
/// ([`KdBudget`](crate::params::KdBudget), which bounds every structure that lists a
/// primitive in several places).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridLimits {
    /// Cells per primitive asked for.
    pub density_asked: f64,
    /// Cells per primitive used.
    pub density_used: f64,
}

impl<V: Vector, C: CellStore> Grid<V, C> {
    /// The same grid in another precision `W`, cell for cell (exact from f32 to f64; see
    /// [`Vector::converted`]).
    pub fn converted<W: Vector>(&self) -> Grid<W, C>
    where
        C: Clone,
    {
        Grid {
            cells: self.cells.converted(),
            store: self.store.clone(),
            limits: self.limits,
        }
    }

    /// The node observers hear for cell `cell`.
    #[inline(always)]
    pub fn node_of_cell(cell: u32) -> u32 {
        cell + 1
    }

    /// The grid's box.
    pub fn bounds(&self) -> Aabb<V> {
        self.cells.bounds
    }

    /// The primitives listed in cell `cell`.
    pub fn cell_primitives(&self, cell: u32) -> &[u32] {
        self.store.lookup(cell).primitives
    }

    /// The bytes the same lists take in a dense table ([`DenseCells`]: a start for every
    /// cell and one more, then the references): what a hashed grid is weighed against.
    pub fn dense_bytes(&self) -> usize {
        std::mem::size_of::<u32>() * (self.cells.cell_count() + 1 + self.store.references().len())
    }

    /// A copy of `primitives` stored in the grid's reference order (a primitive once for every
    /// cell that lists it), so a cell's primitives are read from consecutive memory.
    pub fn leaf_ordered<P: PrimitiveSet<V>>(&self, primitives: &P) -> LeafOrdered<P> {
        LeafOrdered::new(primitives.permuted(self.store.references()))
    }
}

impl<V: Vector, C: CellStore> Grid<V, C> {
    /// The grid's shape and predicted cost, in the cost model of Ize, Shirley & Parker 2007:
    /// a ray through the box passes each cell with the chance `A(cell) / A(box)` (its area
    /// over the box's, as the SAH assumes), and each cell passed costs a step (`C_trav`) and a
    /// test of each primitive it lists (`C_isect`): `C_trav + Σ_cells (C_trav + N·C_isect) ·
    /// A(cell) / A(box)` (the first `C_trav` the box's own test). Cells count as leaves below
    /// the box (depth 1); empty cells as empty leaves.
    pub fn stats(&self, cost: &SahCost) -> TreeStats {
        let cell_count = self.cells.cell_count();
        if self.store.references().is_empty() && self.cells.bounds.is_empty() {
            return TreeStats::default();
        }
        let (box_area, box_measure) = (
            self.cells.bounds.area().to_f64(),
            self.cells.bounds.measure().to_f64(),
        );
        let mut stats = TreeStats {
            node_count: cell_count + 1,
            leaf_count: cell_count,
            max_depth: 1,
            min_leaf_size: usize::MAX,
            primitive_references: self.store.references().len(),
            sah_cost: cost.traversal_cost,
            ..TreeStats::default()
        };
        for cell in 0..cell_count as u32 {
            let size = self.store.lookup(cell).primitives.len();
            let bounds = self.cells.cell_bounds(self.cells.coordinates(cell));
            let chance = if box_area > 0.0 {
                bounds.area().to_f64() / box_area
            } else {
                1.0
            };
            stats.sah_cost += chance * (cost.traversal_cost + cost.leaf_cost(size));
            stats.min_leaf_size = stats.min_leaf_size.min(size);
            stats.max_leaf_size = stats.max_leaf_size.max(size);
            if size == 0 {
                stats.empty_leaf_count += 1;
                if box_measure > 0.0 {
                    stats.empty_leaf_share += bounds.measure().to_f64() / box_measure;
                }
            }
        }
        stats.mean_leaf_size = stats.primitive_references as f64 / cell_count.max(1) as f64;
        stats
    }
}

/// A grid as a tree of two levels: node 0 its box, nodes `1..=cells` its cells (cell `c` is
/// node `c + 1`), each a leaf.
impl<V: Vector, C: CellStore> Hierarchy<V> for Grid<V, C> {
    fn node_count(&self) -> usize {
        self.cells.cell_count() + 1
    }

    fn children(&self, node: u32) -> Option<Children> {
        (node == 0).then(|| Children {
            first: 1,
            count: self.cells.cell_count() as u32,
        })
    }

    fn leaf_primitives(&self, node: u32) -> &[u32] {
        match node {
            0 => &[],
            _ => self.store.lookup(node - 1).primitives,
        }
    }

    fn node_bounds(&self) -> Vec<Aabb<V>> {
        let cells = (0..self.cells.cell_count() as u32)
            .map(|cell| self.cells.cell_bounds(self.cells.coordinates(cell)));
        std::iter::once(self.cells.bounds).chain(cells).collect()
    }
}
