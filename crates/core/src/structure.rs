//! The catalogue: every acceleration structure the core builds, named once, with its builder
//! and parameters. The CLI parses its structure names here, the app offers these choices, and
//! the tests and benches build every entry; adding a structure is one entry in [`CATALOGUE`]
//! and one arm in [`Structure::build_observed`].
//!
//! A built structure is a [`Tree`]: a BVH or a kD-tree, traced by the one traversal of its
//! kind and measured by the same [`TreeFacts`](crate::facts::TreeFacts) and [`TreeStats`] whatever it is.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, NoBuildObserver};
use crate::bvh::{
    self, BinnedSah, Builder, Bvh, MedianSplit, MiddleSplit, PacketStack, SweepSah, TraversalStack,
    WideBvh, WideStack,
};
use crate::facts::{Children, Hierarchy};
use crate::grid::{self, HashedGrid, UniformGrid};
use crate::kd::{
    self, KdBuilder, KdMedianSplit, KdMiddleSplit, KdSah, KdSahPresorted, KdTraversalStack, KdTree,
};
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::octree::{self, Octree, OctreeStack};
use crate::params::BuildParams;
use crate::primitive::{LeafOrdered, LeafPrimitives, PrimitiveSet};
use crate::query::{Hit, TraceOptions};
use crate::ray::Ray;
use crate::stats::TreeStats;

/// The kinds of structure.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// Bounding volume hierarchies: boxes of boxes; each primitive in one leaf.
    Bvh,
    /// kD-trees: space cut by planes; a primitive in every cell it reaches.
    Kd,
    /// Uniform grids: space cut into equal cells, walked along the ray; a primitive in every
    /// cell it reaches, each cell's list found by indexing a table.
    Grid,
    /// The same grids with their occupied cells in a hash table.
    HashedGrid,
    /// Octrees (quadtrees in 2D): cells cut at their middle on every axis at once, down to
    /// few primitives; a primitive in every cell it reaches.
    Octree,
}

impl Family {
    /// Every family.
    pub const ALL: [Family; 5] = [
        Family::Bvh,
        Family::Kd,
        Family::Grid,
        Family::HashedGrid,
        Family::Octree,
    ];

    /// A short name for share links (`bvh`, `kd`, `grid`, `hashed-grid`).
    pub fn name(self) -> &'static str {
        match self {
            Family::Bvh => "bvh",
            Family::Kd => "kd",
            Family::Grid => "grid",
            Family::HashedGrid => "hashed-grid",
            Family::Octree => "octree",
        }
    }

    /// The family of that [`Family::name`].
    pub fn from_name(name: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|family| family.name() == name)
    }

    /// The name for people: "BVH", "kD-tree", "uniform grid", "hashed grid", "octree".
    pub fn label(self) -> &'static str {
        match self {
            Family::Bvh => "BVH",
            Family::Kd => "kD-tree",
            Family::Grid => "uniform grid",
            Family::HashedGrid => "hashed grid",
            Family::Octree => "octree",
        }
    }

    /// Whether the lecture's three rules build it (BVHs, kD-trees): where a split goes is
    /// chosen, not fixed (a grid's cells, an octree's middles).
    pub fn has_rules(self) -> bool {
        matches!(self, Family::Bvh | Family::Kd)
    }
}

/// How a structure places its splits: the lecture's three rules, or none at all.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SplitRule {
    /// In the middle of the node: equal chances for the children, their costs ignored.
    Middle,
    /// At the median primitive: equal costs, the chances ignored.
    Median,
    /// Where the surface area heuristic's cost is lowest.
    Sah,
    /// Nowhere chosen: equal cells, as many as the primitive count asks for (a grid).
    Uniform,
}

impl SplitRule {
    /// The name for people.
    pub fn label(self) -> &'static str {
        match self {
            SplitRule::Middle => "middle",
            SplitRule::Median => "median",
            SplitRule::Sah => "SAH",
            SplitRule::Uniform => "uniform",
        }
    }
}

/// How many children a BVH node has: binary as built, or a binary BVH collapsed into 4 or 8
/// children per node ([`bvh::collapse`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Width {
    /// Two children per node: the tree the builders make.
    #[default]
    Binary,
    /// Four: [`bvh::WideBvh`] with `W = 4`.
    Four,
    /// Eight: [`bvh::WideBvh`] with `W = 8`.
    Eight,
}

impl Width {
    /// Every width, narrowest first.
    pub const ALL: [Width; 3] = [Width::Binary, Width::Four, Width::Eight];

    /// Children per node.
    pub fn children(self) -> usize {
        match self {
            Width::Binary => 2,
            Width::Four => 4,
            Width::Eight => 8,
        }
    }

    /// The family part of a structure's name: `bvh`, `bvh4`, `bvh8`.
    pub fn prefix(self) -> &'static str {
        match self {
            Width::Binary => "bvh",
            Width::Four => "bvh4",
            Width::Eight => "bvh8",
        }
    }
}

/// A structure with its parameters, as the CLI names it: `bvh:sah-binned:16`,
/// `bvh8:sah-binned`, `kd:sah`. Every BVH rule comes in every [`Width`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Structure {
    /// [`MiddleSplit`].
    BvhMiddle {
        /// Children per node.
        width: Width,
    },
    /// [`MedianSplit`].
    BvhMedian {
        /// Children per node.
        width: Width,
    },
    /// [`SweepSah`]: every candidate.
    BvhSahSweep {
        /// Children per node.
        width: Width,
    },
    /// [`BinnedSah`] with this many bins.
    BvhSahBinned {
        /// Bins per axis.
        bins: u16,
        /// Children per node.
        width: Width,
    },
    /// [`KdMiddleSplit`].
    KdMiddle,
    /// [`KdMedianSplit`].
    KdMedian,
    /// [`KdSahPresorted`]: events sorted once, O(n log n).
    KdSah,
    /// [`KdSah`]: events sorted at every node, O(n log² n); the same tree as `kd:sah`.
    KdSahPerNode,
    /// [`KdSahPresorted::build_with_perfect_splits`]: straddlers clipped to each cell.
    KdSahPerfect,
    /// [`grid::build_uniform`] with this many cells per primitive.
    GridUniform {
        /// Cells per primitive.
        density: u16,
    },
    /// [`grid::build_hashed`] with this many cells per primitive.
    GridHashed {
        /// Cells per primitive.
        density: u16,
    },
    /// [`octree::build`] with leaves of at most this many primitives.
    Octree {
        /// Primitives a leaf may hold.
        leaf: u16,
    },
}

/// A whole-number parameter of a structure (the bins of the binned SAH, a grid's density).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parameter {
    /// Its name.
    pub name: &'static str,
    /// The value when none is given.
    pub default: u16,
    /// The smallest value.
    pub min: u16,
    /// The largest value.
    pub max: u16,
    /// The values a comparison of every structure measures.
    pub compared: &'static [u16],
}

/// One entry of the catalogue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry {
    /// The structure, with its parameter at its default.
    pub structure: Structure,
    /// Its name without a parameter: `bvh:sah-binned`.
    pub name: &'static str,
    /// BVH or kD-tree.
    pub family: Family,
    /// Which of the lecture's rules it follows.
    pub rule: SplitRule,
    /// A short name for a button: "binned SAH".
    pub label: &'static str,
    /// One line on what it does.
    pub about: &'static str,
    /// Its parameter, if it has one (`name:VALUE`).
    pub parameter: Option<Parameter>,
}

/// The bins of the binned SAH.
const BINS: Parameter = Parameter {
    name: "bins",
    default: 16,
    min: 2,
    max: 4096,
    compared: &[4, 8, 16, 32],
};

/// A grid's cells per primitive (Ize et al. 2007's `K`).
const DENSITY: Parameter = Parameter {
    name: "density",
    default: grid::DEFAULT_DENSITY as u16,
    min: 1,
    max: 64,
    compared: &[grid::DEFAULT_DENSITY as u16],
};

/// An octree's leaf size.
const LEAF: Parameter = Parameter {
    name: "leaf size",
    default: octree::DEFAULT_LEAF_SIZE as u16,
    min: 1,
    max: 1024,
    compared: &[octree::DEFAULT_LEAF_SIZE as u16],
};

/// Every structure, in the lecture's order within each family: the first entry of each rule
/// is the one the lessons compare (the exact SAH before its approximations).
pub const CATALOGUE: [Entry; 12] = [
    Entry {
        structure: Structure::BvhMiddle {
            width: Width::Binary,
        },
        name: "bvh:middle",
        family: Family::Bvh,
        rule: SplitRule::Middle,
        label: "middle",
        about: "split each node in the middle of its centroids' longest axis",
        parameter: None,
    },
    Entry {
        structure: Structure::BvhMedian {
            width: Width::Binary,
        },
        name: "bvh:median",
        family: Family::Bvh,
        rule: SplitRule::Median,
        label: "median",
        about: "split each node at its median centroid (object median)",
        parameter: None,
    },
    Entry {
        structure: Structure::BvhSahSweep {
            width: Width::Binary,
        },
        name: "bvh:sah-sweep",
        family: Family::Bvh,
        rule: SplitRule::Sah,
        label: "SAH",
        about: "the SAH over every candidate, lists sorted once (MacDonald & Booth 1990)",
        parameter: None,
    },
    Entry {
        structure: Structure::BvhSahBinned {
            bins: BINS.default,
            width: Width::Binary,
        },
        name: "bvh:sah-binned",
        family: Family::Bvh,
        rule: SplitRule::Sah,
        label: "binned SAH",
        about: "the SAH over the planes between a few bins (Wald 2007)",
        parameter: Some(BINS),
    },
    Entry {
        structure: Structure::KdMiddle,
        name: "kd:middle",
        family: Family::Kd,
        rule: SplitRule::Middle,
        label: "middle",
        about: "cut each cell in half across its longest axis",
        parameter: None,
    },
    Entry {
        structure: Structure::KdMedian,
        name: "kd:median",
        family: Family::Kd,
        rule: SplitRule::Median,
        label: "median",
        about: "cut each cell at the median of its primitives' bounds",
        parameter: None,
    },
    Entry {
        structure: Structure::KdSah,
        name: "kd:sah",
        family: Family::Kd,
        rule: SplitRule::Sah,
        label: "SAH",
        about: "the SAH with an empty-space bonus, events sorted once: O(n log n) (Wald & Havran 2006)",
        parameter: None,
    },
    Entry {
        structure: Structure::KdSahPerNode,
        name: "kd:sah-per-node",
        family: Family::Kd,
        rule: SplitRule::Sah,
        label: "SAH, sorting at each node",
        about: "the same tree as kd:sah, events sorted at every node: O(n log² n)",
        parameter: None,
    },
    Entry {
        structure: Structure::KdSahPerfect,
        name: "kd:sah-perfect",
        family: Family::Kd,
        rule: SplitRule::Sah,
        label: "SAH, perfect splits",
        about: "kd:sah with straddling primitives clipped to each cell (Havran 2000)",
        parameter: None,
    },
    Entry {
        structure: Structure::GridUniform {
            density: DENSITY.default,
        },
        name: "grid:uniform",
        family: Family::Grid,
        rule: SplitRule::Uniform,
        label: "uniform grid",
        about: "equal cells, about K per primitive, walked along the ray (Cleary & Wyvill 1988; Amanatides & Woo 1987)",
        parameter: Some(DENSITY),
    },
    Entry {
        structure: Structure::GridHashed {
            density: DENSITY.default,
        },
        name: "grid:hashed",
        family: Family::HashedGrid,
        rule: SplitRule::Uniform,
        label: "hashed grid",
        about: "the uniform grid's occupied cells in a hash table (Teschner et al. 2003)",
        parameter: Some(DENSITY),
    },
    Entry {
        structure: Structure::Octree { leaf: LEAF.default },
        name: "octree",
        family: Family::Octree,
        rule: SplitRule::Middle,
        label: "octree",
        about: "each cell cut at its middle on every axis at once, down to a few primitives; walked front to back (Revelles et al. 2000)",
        parameter: Some(LEAF),
    },
];

/// A structure name that is not in the catalogue, or a parameter out of range.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum StructureError {
    /// No such name.
    #[error("unknown structure '{name}'; valid ones are: {}", valid_names())]
    Unknown {
        /// What was given.
        name: String,
    },
    /// A parameter that is not a whole number in range, or one given to a structure without.
    #[error("'{name}': {problem}")]
    Parameter {
        /// What was given.
        name: String,
        /// What is wrong with it.
        problem: String,
    },
}

/// Every name the catalogue accepts, for messages: `bvh:middle, …, bvh:sah-binned[:BINS]
/// (default 16), …`.
pub fn valid_names() -> String {
    CATALOGUE
        .iter()
        .map(|entry| match entry.parameter {
            Some(parameter) => format!(
                "{}[:{}] (default {})",
                entry.name,
                parameter.name.to_uppercase(),
                parameter.default
            ),
            None => entry.name.to_owned(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

impl Structure {
    /// Parses a name from the catalogue, with its parameter if it takes one
    /// (`bvh:sah-binned:8`), and for a BVH its width (`bvh4:sah-binned:8`, `bvh8:middle`).
    pub fn parse(text: &str) -> Result<Self, StructureError> {
        let wide = Width::ALL[1..].iter().find_map(|&width| {
            let rest = text.strip_prefix(width.prefix())?.strip_prefix(':')?;
            Some((width, format!("{}:{rest}", Width::Binary.prefix())))
        });
        let (width, binary_name) = match &wide {
            Some((width, name)) => (*width, name.as_str()),
            None => (Width::Binary, text),
        };
        Self::parse_binary(binary_name, text).map(|structure| structure.with_width(width))
    }

    /// Parses a catalogue name with its parameter; errors quote `text`, as given.
    fn parse_binary(name_and_value: &str, text: &str) -> Result<Self, StructureError> {
        let (name, value) = match CATALOGUE.iter().find(|entry| entry.name == name_and_value) {
            Some(entry) => return Ok(entry.structure),
            None => name_and_value
                .rsplit_once(':')
                .unwrap_or((name_and_value, "")),
        };
        let unknown = || StructureError::Unknown {
            name: text.to_owned(),
        };
        let entry = CATALOGUE
            .iter()
            .find(|entry| entry.name == name)
            .ok_or_else(unknown)?;
        let problem = |problem: String| StructureError::Parameter {
            name: text.to_owned(),
            problem,
        };
        let Some(parameter) = entry.parameter else {
            return Err(problem(format!("{name} takes no parameter")));
        };
        match value.parse::<u16>() {
            Ok(value) if (parameter.min..=parameter.max).contains(&value) => {
                Ok(entry.structure.with_parameter(value))
            }
            _ => Err(problem(format!(
                "the {} must be a whole number from {} to {}",
                parameter.name, parameter.min, parameter.max
            ))),
        }
    }

    /// Its catalogue entry (the binary one for a wide BVH).
    pub fn entry(&self) -> &'static Entry {
        let plain = self.with_parameter(0).with_width(Width::Binary);
        CATALOGUE
            .iter()
            .find(|entry| entry.structure.with_parameter(0) == plain)
            .unwrap_or_else(|| unreachable!("every structure has an entry"))
    }

    /// Its parameter's value, if it has one.
    pub fn parameter(&self) -> Option<u16> {
        match *self {
            Structure::BvhSahBinned { bins, .. } => Some(bins),
            Structure::GridUniform { density } | Structure::GridHashed { density } => Some(density),
            Structure::Octree { leaf } => Some(leaf),
            _ => None,
        }
    }

    /// The same structure with its parameter set to `value` (unchanged if it has none).
    pub fn with_parameter(self, value: u16) -> Self {
        match self {
            Structure::BvhSahBinned { width, .. } => Structure::BvhSahBinned { bins: value, width },
            Structure::GridUniform { .. } => Structure::GridUniform { density: value },
            Structure::GridHashed { .. } => Structure::GridHashed { density: value },
            Structure::Octree { .. } => Structure::Octree { leaf: value },
            other => other,
        }
    }

    /// Children per node: [`Width::Binary`] for every kD-tree.
    pub fn width(&self) -> Width {
        match *self {
            Structure::BvhMiddle { width }
            | Structure::BvhMedian { width }
            | Structure::BvhSahSweep { width }
            | Structure::BvhSahBinned { width, .. } => width,
            _ => Width::Binary,
        }
    }

    /// The same BVH with `width` children per node (a kD-tree is unchanged: it is binary).
    pub fn with_width(self, width: Width) -> Self {
        match self {
            Structure::BvhMiddle { .. } => Structure::BvhMiddle { width },
            Structure::BvhMedian { .. } => Structure::BvhMedian { width },
            Structure::BvhSahSweep { .. } => Structure::BvhSahSweep { width },
            Structure::BvhSahBinned { bins, .. } => Structure::BvhSahBinned { bins, width },
            other => other,
        }
    }

    /// The canonical name: `bvh:sah-binned:16`, `bvh8:sah-binned:16`, `kd:sah`.
    pub fn name(&self) -> String {
        let entry = self.entry();
        let name = match self.width() {
            Width::Binary => entry.name.to_owned(),
            width => entry
                .name
                .replacen(Width::Binary.prefix(), width.prefix(), 1),
        };
        match self.parameter() {
            Some(value) => format!("{name}:{value}"),
            None => name,
        }
    }

    /// Its family: BVH, kD-tree, grid.
    pub fn family(&self) -> Family {
        self.entry().family
    }

    /// A short name for people: the entry's label, with the width of a wide BVH ("binned
    /// SAH, 8 wide").
    pub fn label(&self) -> String {
        match self.width() {
            Width::Binary => self.entry().label.to_owned(),
            width => format!("{}, {} wide", self.entry().label, width.children()),
        }
    }

    /// Its label with its family where the label does not already name it: "SAH kD-tree",
    /// "binned SAH, 8 wide BVH", but "uniform grid".
    pub fn title(&self) -> String {
        let (label, family) = (self.label(), self.family().label());
        if label.contains(family) {
            label
        } else {
            format!("{label} {family}")
        }
    }

    /// Which of the lecture's rules it follows.
    pub fn rule(&self) -> SplitRule {
        self.entry().rule
    }

    /// The first structure of `family` that follows `rule`: the one the lessons compare (for
    /// a family that does not follow the rule, a grid, its first structure).
    pub fn lecture(family: Family, rule: SplitRule) -> Self {
        let of_family = || CATALOGUE.iter().filter(|entry| entry.family == family);
        of_family()
            .find(|entry| entry.rule == rule)
            .or_else(|| of_family().next())
            .map(|entry| entry.structure)
            .unwrap_or_else(|| unreachable!("every family has an entry"))
    }

    /// Every structure as a comparison measures it: each entry, a parameterised one at each
    /// of its compared values, and the SAH BVHs (at their default parameter) 4 and 8 wide.
    pub fn compared() -> Vec<Self> {
        let entries = CATALOGUE.iter().flat_map(|entry| match entry.parameter {
            Some(parameter) => parameter
                .compared
                .iter()
                .map(|&value| entry.structure.with_parameter(value))
                .collect(),
            None => vec![entry.structure],
        });
        let wide = CATALOGUE
            .iter()
            .filter(|entry| entry.family == Family::Bvh && entry.rule == SplitRule::Sah)
            .flat_map(|entry| {
                [Width::Four, Width::Eight].map(|width| entry.structure.with_width(width))
            });
        entries.chain(wide).collect()
    }

    /// Builds the structure over `primitives`.
    pub fn build<V: Vector, P: PrimitiveSet<V>>(
        &self,
        primitives: &P,
        params: &BuildParams,
    ) -> Tree<V> {
        self.build_observed(primitives, params, &mut NoBuildObserver)
    }

    /// Builds the structure over `primitives`, telling `observer` about each node.
    pub fn build_observed<V: Vector, P: PrimitiveSet<V>, O: BuildObserver>(
        &self,
        primitives: &P,
        params: &BuildParams,
        observer: &mut O,
    ) -> Tree<V> {
        let bounds = primitives.all_bounds();
        let bvh = |binary: Bvh<V>| Tree::from_binary(binary, self.width(), &params.cost);
        match *self {
            Structure::BvhMiddle { .. } => {
                bvh(MiddleSplit.build_observed(&bounds, params, observer))
            }
            Structure::BvhMedian { .. } => {
                bvh(MedianSplit.build_observed(&bounds, params, observer))
            }
            Structure::BvhSahSweep { .. } => {
                bvh(SweepSah.build_observed(&bounds, params, observer))
            }
            Structure::BvhSahBinned { bins, .. } => bvh(BinnedSah {
                bins: bins as usize,
            }
            .build_observed(&bounds, params, observer)),
            Structure::KdMiddle => {
                Tree::Kd(KdMiddleSplit.build_observed(&bounds, params, observer))
            }
            Structure::KdMedian => {
                Tree::Kd(KdMedianSplit.build_observed(&bounds, params, observer))
            }
            Structure::KdSah => Tree::Kd(KdSahPresorted.build_observed(&bounds, params, observer)),
            Structure::KdSahPerNode => Tree::Kd(KdSah.build_observed(&bounds, params, observer)),
            Structure::KdSahPerfect => Tree::Kd(
                KdSahPresorted.build_with_perfect_splits_observed(primitives, params, observer),
            ),
            Structure::GridUniform { density } => Tree::Grid(grid::build_uniform(
                primitives,
                f64::from(density),
                params,
                observer,
            )),
            Structure::GridHashed { density } => Tree::HashedGrid(grid::build_hashed(
                primitives,
                f64::from(density),
                params,
                observer,
            )),
            Structure::Octree { leaf } => Tree::Octree(octree::build(
                primitives,
                usize::from(leaf),
                params,
                observer,
            )),
        }
    }
}

/// A built structure: a BVH (binary or wide), a kD-tree or a grid.
#[derive(Clone, Debug, PartialEq)]
pub enum Tree<V: Vector> {
    /// A bounding volume hierarchy.
    Bvh(Bvh<V>),
    /// A BVH of 4 children per node, with the binary tree it was collapsed from.
    Bvh4(WideBvh<V, 4>),
    /// A BVH of 8 children per node, with the binary tree it was collapsed from.
    Bvh8(WideBvh<V, 8>),
    /// A kD-tree.
    Kd(KdTree<V>),
    /// A uniform grid in a dense table.
    Grid(UniformGrid<V>),
    /// A uniform grid in a hash table.
    HashedGrid(HashedGrid<V>),
    /// An octree (a quadtree in 2D).
    Octree(Octree<V>),
}

/// One traversal stack per kind of tree, kept per thread so tracing allocates nothing per ray.
#[derive(Clone, Debug, Default)]
pub struct TraversalStacks<S: Real> {
    bvh: TraversalStack<S>,
    wide: WideStack<S>,
    packet: PacketStack<S>,
    kd: KdTraversalStack<S>,
    octree: OctreeStack<S>,
}

impl<V: Vector> Tree<V> {
    /// The same tree in another precision `W`, node for node (exact from f32 to f64; see
    /// [`Vector::converted`]).
    pub fn converted<W: Vector>(&self) -> Tree<W> {
        match self {
            Tree::Bvh(bvh) => Tree::Bvh(bvh.converted()),
            Tree::Bvh4(wide) => Tree::Bvh4(wide.converted()),
            Tree::Bvh8(wide) => Tree::Bvh8(wide.converted()),
            Tree::Kd(tree) => Tree::Kd(tree.converted()),
            Tree::Grid(grid) => Tree::Grid(grid.converted()),
            Tree::HashedGrid(grid) => Tree::HashedGrid(grid.converted()),
            Tree::Octree(tree) => Tree::Octree(tree.converted()),
        }
    }

    /// A binary BVH as it is, or collapsed to `width` children per node.
    pub fn from_binary(binary: Bvh<V>, width: Width, cost: &crate::sah::SahCost) -> Self {
        match width {
            Width::Binary => Tree::Bvh(binary),
            Width::Four => Tree::Bvh4(bvh::collapse(binary, cost)),
            Width::Eight => Tree::Bvh8(bvh::collapse(binary, cost)),
        }
    }

    /// Its family.
    pub fn family(&self) -> Family {
        match self {
            Tree::Bvh(_) | Tree::Bvh4(_) | Tree::Bvh8(_) => Family::Bvh,
            Tree::Kd(_) => Family::Kd,
            Tree::Grid(_) => Family::Grid,
            Tree::HashedGrid(_) => Family::HashedGrid,
            Tree::Octree(_) => Family::Octree,
        }
    }

    /// Traces one ray with the traversal of its kind (see [`bvh::traverse`] and
    /// [`kd::traverse`]).
    #[inline]
    pub fn trace<P: LeafPrimitives<V>, O: Observer<V::Scalar>>(
        &self,
        primitives: &P,
        ray: &Ray<V>,
        options: &TraceOptions,
        stacks: &mut TraversalStacks<V::Scalar>,
        observer: &mut O,
    ) -> Option<Hit<V::Scalar>> {
        match self {
            Tree::Bvh(bvh) => {
                bvh::traverse(bvh, primitives, ray, options, &mut stacks.bvh, observer)
            }
            Tree::Bvh4(wide) => {
                bvh::traverse_wide(wide, primitives, ray, options, &mut stacks.wide, observer)
            }
            Tree::Bvh8(wide) => {
                bvh::traverse_wide(wide, primitives, ray, options, &mut stacks.wide, observer)
            }
            Tree::Kd(tree) => {
                kd::traverse(tree, primitives, ray, options, &mut stacks.kd, observer)
            }
            Tree::Grid(grid) => grid::traverse(grid, primitives, ray, options, observer),
            Tree::HashedGrid(grid) => grid::traverse(grid, primitives, ray, options, observer),
            Tree::Octree(tree) => {
                octree::traverse(tree, primitives, ray, options, &mut stacks.octree, observer)
            }
        }
    }

    /// Traces up to [`bvh::MAX_PACKET`] rays together (a wide BVH's packet traversal,
    /// [`bvh::traverse_packet`]; other trees, and a packet of one, trace rays one by one),
    /// writing each ray's hit to `hits`: the answers [`Tree::trace`] gives each ray.
    /// `observers[i]` hears ray `i`.
    pub fn trace_packet<P: LeafPrimitives<V>, O: Observer<V::Scalar>>(
        &self,
        primitives: &P,
        rays: &[Ray<V>],
        options: &TraceOptions,
        stacks: &mut TraversalStacks<V::Scalar>,
        observers: &mut [O],
        hits: &mut [Option<Hit<V::Scalar>>],
    ) {
        match self {
            // A packet of one is a single ray (the same steps, without a packet's set-up).
            Tree::Bvh4(wide) if rays.len() > 1 => bvh::traverse_packet(
                wide,
                primitives,
                rays,
                options,
                &mut stacks.packet,
                observers,
                hits,
            ),
            Tree::Bvh8(wide) if rays.len() > 1 => bvh::traverse_packet(
                wide,
                primitives,
                rays,
                options,
                &mut stacks.packet,
                observers,
                hits,
            ),
            _ => {
                for ((ray, observer), hit) in rays.iter().zip(observers).zip(hits) {
                    *hit = self.trace(primitives, ray, options, stacks, observer);
                }
            }
        }
    }

    /// A copy of `primitives` in this tree's leaf order, for faster traversal.
    pub fn leaf_ordered<P: PrimitiveSet<V>>(&self, primitives: &P) -> LeafOrdered<P> {
        match self {
            Tree::Bvh(bvh) => bvh.leaf_ordered(primitives),
            Tree::Bvh4(wide) => wide.leaf_ordered(primitives),
            Tree::Bvh8(wide) => wide.leaf_ordered(primitives),
            Tree::Kd(tree) => tree.leaf_ordered(primitives),
            Tree::Grid(grid) => grid.leaf_ordered(primitives),
            Tree::HashedGrid(grid) => grid.leaf_ordered(primitives),
            Tree::Octree(tree) => tree.leaf_ordered(primitives),
        }
    }

    /// The tree's statistics with these cost constants (a wide BVH's count its wide nodes
    /// and leaves, see [`WideBvh::stats`]; a grid's cost is its walk's, see
    /// [`Grid::stats`](grid::Grid::stats)).
    pub fn stats(&self, cost: &crate::sah::SahCost) -> TreeStats {
        match self {
            Tree::Bvh4(wide) => wide.stats(cost),
            Tree::Bvh8(wide) => wide.stats(cost),
            Tree::Grid(grid) => grid.stats(cost),
            Tree::HashedGrid(grid) => grid.stats(cost),
            _ => TreeStats::of(self, cost),
        }
    }

    /// The kD build's limits, for a kD-tree.
    pub fn kd_limits(&self) -> Option<&kd::KdLimits> {
        match self {
            Tree::Kd(tree) => Some(&tree.limits),
            _ => None,
        }
    }
}

impl<V: Vector> Tree<V> {
    /// The tree whose nodes facts are about: a kD-tree, or a BVH's binary tree (for a wide
    /// BVH, the numbering its traversal reports).
    fn hierarchy(&self) -> &dyn Hierarchy<V> {
        match self {
            Tree::Bvh(bvh) => bvh,
            Tree::Bvh4(wide) => &wide.binary,
            Tree::Bvh8(wide) => &wide.binary,
            Tree::Kd(tree) => tree,
            Tree::Grid(grid) => grid,
            Tree::HashedGrid(grid) => grid,
            Tree::Octree(tree) => tree,
        }
    }
}

impl<V: Vector> Hierarchy<V> for Tree<V> {
    fn node_count(&self) -> usize {
        self.hierarchy().node_count()
    }

    fn children(&self, node: u32) -> Option<Children> {
        self.hierarchy().children(node)
    }

    fn leaf_primitives(&self, node: u32) -> &[u32] {
        self.hierarchy().leaf_primitives(node)
    }

    fn node_bounds(&self) -> Vec<Aabb<V>> {
        self.hierarchy().node_bounds()
    }
}

/// What is wrong with a built tree: what [`bvh::validate`], [`kd::validate`] or
/// [`kd::validate_clipped`] found.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TreeValidationError {
    /// A BVH's problem.
    #[error(transparent)]
    Bvh(#[from] bvh::ValidationError),
    /// A kD-tree's problem.
    #[error(transparent)]
    Kd(#[from] kd::KdValidationError),
    /// A grid's problem.
    #[error(transparent)]
    Grid(#[from] grid::GridValidationError),
    /// An octree's problem.
    #[error(transparent)]
    Octree(#[from] octree::OctreeValidationError),
}

impl Structure {
    /// Checks a tree this structure built over `primitives` with its kind's validator (the
    /// clipped one for perfect splits, whose cells hold clipped parts).
    pub fn validate<V: Vector, P: PrimitiveSet<V>>(
        &self,
        tree: &Tree<V>,
        primitives: &P,
    ) -> Result<(), TreeValidationError> {
        match tree {
            Tree::Bvh(bvh) => bvh::validate(bvh, &primitives.all_bounds())?,
            Tree::Bvh4(wide) => bvh::validate_wide(wide, &primitives.all_bounds())?,
            Tree::Bvh8(wide) => bvh::validate_wide(wide, &primitives.all_bounds())?,
            Tree::Kd(tree) if *self == Structure::KdSahPerfect => {
                kd::validate_clipped(tree, primitives)?
            }
            Tree::Kd(tree) => kd::validate(tree, &primitives.all_bounds())?,
            Tree::Grid(grid) => grid::validate(grid, primitives)?,
            Tree::HashedGrid(grid) => grid::validate(grid, primitives)?,
            Tree::Octree(tree) => octree::validate(tree, primitives)?,
        }
        Ok(())
    }
}
