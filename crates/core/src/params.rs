//! What every builder takes: how large a leaf may be, the SAH constants, how far a
//! structure that lists a primitive in every cell it reaches (kD-trees) may grow, and a
//! grid's cells when they are chosen rather than ruled.

use crate::sah::SahCost;

/// Parameters shared by every builder, whatever the structure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildParams {
    /// Nodes with more primitives than this are always split. Middle and median splits make a
    /// leaf at or below it; the SAH builders make one there only when no split is cheaper.
    pub max_leaf_size: usize,
    /// The SAH constants (also used to report a tree's cost).
    pub cost: SahCost,
    /// How large a kD build may grow (a BVH never has more than `2n − 1` nodes).
    pub kd_budget: KdBudget,
    /// A grid's cells and hash table, where a lesson chooses them.
    pub grid: GridParams,
}

/// At most 8 primitives a leaf (what one cache line of indices and a few triangle tests
/// amortise), the default [`SahCost`] and [`KdBudget`].
impl Default for BuildParams {
    fn default() -> Self {
        Self {
            max_leaf_size: 8,
            cost: SahCost::default(),
            kd_budget: KdBudget::default(),
            grid: GridParams::default(),
        }
    }
}

/// How large a kD build may grow. A kD-tree lists a primitive in every cell it reaches, so
/// overlapping primitives cut by rules that ignore cost (middle, median, small leaves) can
/// multiply nodes and references far beyond the primitive count before the usual depth limit
/// (`8 + 1.3 log₂ n`, pbrt-v3 §4.4.2) stops them: 20,000 overlapping discs cut in the middle
/// down to two per leaf make 1.6 million nodes. Past either budget the builder lowers its
/// depth limit until the tree fits, so the tree stays whole and even, only shallower, and
/// the tree says so ([`KdTree::limits`](crate::kd::KdTree::limits)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KdBudget {
    /// The most nodes; `None` for [`KdBudget::DEFAULT_NODES_PER_PRIMITIVE`] per primitive.
    pub max_nodes: Option<usize>,
    /// The most primitive references in leaves (a primitive counts once in each leaf that
    /// lists it); `None` for [`KdBudget::DEFAULT_REFERENCES_PER_PRIMITIVE`] per primitive.
    pub max_references: Option<usize>,
}

impl KdBudget {
    /// Nodes per primitive allowed by default: far above what cost-driven builds of real
    /// meshes make (the SAH builds of the shared meshes make 2 to 4), so only runaway builds
    /// are bounded.
    pub const DEFAULT_NODES_PER_PRIMITIVE: usize = 32;
    /// References per primitive allowed by default.
    pub const DEFAULT_REFERENCES_PER_PRIMITIVE: usize = 32;
    /// The budget's room for small inputs, whatever their size.
    const FLOOR: usize = 1 << 16;

    /// The node budget for `primitive_count` primitives.
    pub fn nodes_for(&self, primitive_count: usize) -> usize {
        self.max_nodes
            .unwrap_or_else(|| {
                primitive_count.saturating_mul(Self::DEFAULT_NODES_PER_PRIMITIVE) + Self::FLOOR
            })
            .max(1)
    }

    /// The reference budget for `primitive_count` primitives (never below the count: a single
    /// leaf holding everything must fit).
    pub fn references_for(&self, primitive_count: usize) -> usize {
        self.max_references
            .unwrap_or_else(|| {
                primitive_count.saturating_mul(Self::DEFAULT_REFERENCES_PER_PRIMITIVE) + Self::FLOOR
            })
            .max(primitive_count)
    }
}

/// A grid's cells and table as chosen by hand, for a lesson that lets the user size them
/// (the catalogue's grids leave both to their rules).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GridParams {
    /// Cells along the box's longest side, the other sides cut into cells as near square
    /// (cube) as whole numbers allow; `None`: the density rule
    /// ([`GridCells::for_primitives`](crate::grid::GridCells::for_primitives)). Chosen cells
    /// are built whatever the budget.
    pub cells_along_longest: Option<u32>,
    /// Places in a hashed grid's table (at least one more than the occupied cells); `None`:
    /// [`HashedCells::default_places`](crate::grid::HashedCells::default_places).
    pub hash_places: Option<usize>,
}
