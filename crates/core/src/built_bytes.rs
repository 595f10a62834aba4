//! A built structure's bytes ([`crate::bytes`]): a mark with the format's version, the
//! vector's dimension and precision, the structure's name, its tree as its family writes it
//! (`bvh/bytes.rs`, `kd/bytes.rs`, `grid/bytes.rs`, `octree/bytes.rs`) and why each leaf is a
//! leaf; the facts are made again from the tree. What a Web Worker's build sends back to the
//! page, and what a caller adds its own fields after ([`Built::write_bytes`]).

use crate::build_observer::LeafReason;
use crate::built::Built;
use crate::bvh::Bvh;
use crate::bytes::{ByteReader, ByteWriter, BytesError, REAL_BYTES};
use crate::facts::TreeFacts;
use crate::grid::{HashedGrid, UniformGrid};
use crate::kd::KdTree;
use crate::math::Vector;
use crate::octree::Octree;
use crate::sah::SahCost;
use crate::structure::{Family, Structure, Tree};

/// Marks a built structure's bytes, and the version of their layout.
const MAGIC: &[u8; 8] = b"accelvz2";

impl<V: Vector> Built<V> {
    /// The structure as bytes, alone.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = ByteWriter::new();
        self.write_bytes(&mut out);
        out.into_bytes()
    }

    /// The structure [`Built::to_bytes`] wrote; an error for any other bytes, and for bytes
    /// left over.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, BytesError> {
        let mut input = ByteReader::new(bytes);
        let built = Self::read_bytes(&mut input)?;
        input.finish()?;
        Ok(built)
    }

    /// Writes the structure; a caller may write its own fields after it.
    pub fn write_bytes(&self, out: &mut ByteWriter) {
        out.raw(MAGIC);
        out.u8(V::DIM as u8);
        out.u8(std::mem::size_of::<V::Scalar>() as u8);
        out.string(&self.structure.name());
        match &self.tree {
            Tree::Bvh(bvh)
            | Tree::Bvh4(crate::bvh::WideBvh { binary: bvh, .. })
            | Tree::Bvh8(crate::bvh::WideBvh { binary: bvh, .. }) => bvh.write_bytes(out),
            Tree::Kd(tree) => tree.write_bytes(out),
            Tree::Grid(grid) => grid.write_bytes(out),
            Tree::HashedGrid(grid) => grid.write_bytes(out),
            Tree::Octree(tree) => tree.write_bytes(out),
        }
        let reasons = &self.facts.leaf_reasons;
        out.usize(reasons.len());
        out.reserve(reasons.len() * LEAF_REASON_BYTES);
        for reason in reasons {
            write_leaf_reason(*reason, out);
        }
    }

    /// Reads what [`Built::write_bytes`] wrote, leaving what follows it.
    pub fn read_bytes(input: &mut ByteReader<'_>) -> Result<Self, BytesError> {
        if input.take(MAGIC.len())? != MAGIC {
            return Err(BytesError::NotATree);
        }
        let (dimension, real_bytes) = (input.u8()?, input.u8()?);
        let expected = (V::DIM as u8, std::mem::size_of::<V::Scalar>() as u8);
        if (dimension, real_bytes) != expected {
            return Err(BytesError::Invalid(format!(
                "a tree in {dimension}D with {real_bytes}-byte numbers, read as one in {}D with {}-byte numbers",
                expected.0, expected.1
            )));
        }
        let name = input.string()?;
        let structure =
            Structure::parse(&name).map_err(|error| BytesError::Invalid(error.to_string()))?;
        let tree = match structure.family() {
            Family::Bvh => Tree::from_binary(
                Bvh::read_bytes(input)?,
                structure.width(),
                &SahCost::default(),
            ),
            Family::Kd => Tree::Kd(KdTree::read_bytes(input)?),
            Family::Grid => Tree::Grid(UniformGrid::read_bytes(input)?),
            Family::HashedGrid => Tree::HashedGrid(HashedGrid::read_bytes(input)?),
            Family::Octree => Tree::Octree(Octree::read_bytes(input)?),
        };
        let reasons = input.items(LEAF_REASON_BYTES, read_leaf_reason)?;
        let facts = TreeFacts::with_leaf_reasons(&tree, reasons);
        Ok(Self {
            structure,
            tree,
            facts,
        })
    }
}

/// A leaf reason's bytes: a tag and two numbers.
const LEAF_REASON_BYTES: usize = 1 + 2 * REAL_BYTES;

fn write_leaf_reason(reason: Option<LeafReason>, out: &mut ByteWriter) {
    let (tag, a, b) = match reason {
        None => (0, 0.0, 0.0),
        Some(LeafReason::SmallEnough {
            count,
            max_leaf_size,
        }) => (1, count as f64, max_leaf_size as f64),
        Some(LeafReason::LeafCheaper {
            leaf_cost,
            split_cost: None,
        }) => (2, leaf_cost, 0.0),
        Some(LeafReason::LeafCheaper {
            leaf_cost,
            split_cost: Some(split_cost),
        }) => (3, leaf_cost, split_cost),
        Some(LeafReason::Inseparable { count }) => (4, count as f64, 0.0),
        Some(LeafReason::DepthLimit { limit }) => (5, limit as f64, 0.0),
        Some(LeafReason::GridCell) => (6, 0.0, 0.0),
    };
    out.u8(tag);
    out.f64(a);
    out.f64(b);
}

fn read_leaf_reason(input: &mut ByteReader<'_>) -> Result<Option<LeafReason>, BytesError> {
    let (tag, a, b) = (input.u8()?, input.f64()?, input.f64()?);
    Ok(match tag {
        0 => None,
        1 => Some(LeafReason::SmallEnough {
            count: a as usize,
            max_leaf_size: b as usize,
        }),
        2 => Some(LeafReason::LeafCheaper {
            leaf_cost: a,
            split_cost: None,
        }),
        3 => Some(LeafReason::LeafCheaper {
            leaf_cost: a,
            split_cost: Some(b),
        }),
        4 => Some(LeafReason::Inseparable { count: a as usize }),
        5 => Some(LeafReason::DepthLimit { limit: a as usize }),
        6 => Some(LeafReason::GridCell),
        _ => {
            return Err(BytesError::Unknown {
                what: "leaf reason",
                tag: tag.into(),
            });
        }
    })
}
