//! A tree's bytes: what carries a built structure to where its memory is not shared (a Web
//! Worker builds a large mesh's tree and sends it back to the page; a GPU will read a tree's
//! layout). Fields are written little-endian one after another ([`ByteWriter`]) and read back
//! in the same order ([`ByteReader`]); short or corrupt bytes are an error ([`BytesError`]),
//! never a panic or a huge allocation. Numbers of either precision are written as `f64`,
//! which holds an `f32` exactly, so a tree comes back bit for bit. No IO: the caller moves
//! the bytes.
//!
//! Each family writes and reads its own tree beside it (`bvh/bytes.rs`, `kd/bytes.rs`,
//! `grid/bytes.rs`, `octree/bytes.rs`); [`crate::Built::to_bytes`] puts one together with
//! its structure's name and its leaves' reasons.

use crate::aabb::Aabb;
use crate::math::{Real, Vector};

/// Why bytes are not what was asked for.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BytesError {
    /// They stop before what they say they hold.
    #[error("the bytes end early")]
    EndsEarly,
    /// Bytes are left over after the last field.
    #[error("{0} bytes too many")]
    TooMany(usize),
    /// They do not start as a tree written by this version does.
    #[error("not a tree written by this version of accelviz")]
    NotATree,
    /// A field names something this version does not know.
    #[error("unknown {what} {tag}")]
    Unknown {
        /// What the field says.
        what: &'static str,
        /// The value found.
        tag: u64,
    },
    /// A field's value cannot be what it says (a count larger than memory, a name that is
    /// not text, a table that does not fit its cells).
    #[error("{0}")]
    Invalid(String),
}

/// Bytes written little-endian, field after field.
#[derive(Clone, Debug, Default)]
pub struct ByteWriter {
    bytes: Vec<u8>,
}

impl ByteWriter {
    /// An empty writer.
    pub fn new() -> Self {
        Self::default()
    }

    /// What was written.
    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }

    /// Room for `additional` more bytes (for a caller about to write many).
    pub fn reserve(&mut self, additional: usize) {
        self.bytes.reserve(additional);
    }

    /// Bytes as they are.
    pub fn raw(&mut self, bytes: &[u8]) {
        self.bytes.extend_from_slice(bytes);
    }

    /// One byte.
    pub fn u8(&mut self, value: u8) {
        self.bytes.push(value);
    }

    /// A `u32`.
    pub fn u32(&mut self, value: u32) {
        self.raw(&value.to_le_bytes());
    }

    /// A `u64`.
    pub fn u64(&mut self, value: u64) {
        self.raw(&value.to_le_bytes());
    }

    /// A count or size, as a `u64`.
    pub fn usize(&mut self, value: usize) {
        self.u64(value as u64);
    }

    /// An `f32`.
    pub fn f32(&mut self, value: f32) {
        self.raw(&value.to_le_bytes());
    }

    /// An `f64`.
    pub fn f64(&mut self, value: f64) {
        self.raw(&value.to_le_bytes());
    }

    /// A number of either precision, as an `f64` (exact for an `f32`).
    pub fn real<S: Real>(&mut self, value: S) {
        self.f64(value.to_f64());
    }

    /// A vector's `V::DIM` components.
    pub fn vector<V: Vector>(&mut self, value: V) {
        for component in &value.to_array3()[..V::DIM] {
            self.real(*component);
        }
    }

    /// A box: its minimum corner, then its maximum.
    pub fn aabb<V: Vector>(&mut self, bounds: &Aabb<V>) {
        self.vector(bounds.min);
        self.vector(bounds.max);
    }

    /// Text, after its length.
    pub fn string(&mut self, value: &str) {
        self.usize(value.len());
        self.raw(value.as_bytes());
    }

    /// `u32`s, after their count.
    pub fn u32s(&mut self, values: &[u32]) {
        self.usize(values.len());
        self.reserve(values.len() * 4);
        for &value in values {
            self.u32(value);
        }
    }
}

/// Bytes read back in the order [`ByteWriter`] wrote them; a read past the end is an error.
#[derive(Clone, Debug)]
pub struct ByteReader<'a> {
    rest: &'a [u8],
}

impl<'a> ByteReader<'a> {
    /// Reads `bytes` from their start.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { rest: bytes }
    }

    /// The next `count` bytes.
    pub fn take(&mut self, count: usize) -> Result<&'a [u8], BytesError> {
        if self.rest.len() < count {
            return Err(BytesError::EndsEarly);
        }
        let (taken, rest) = self.rest.split_at(count);
        self.rest = rest;
        Ok(taken)
    }

    /// The next `N` bytes.
    pub fn array<const N: usize>(&mut self) -> Result<[u8; N], BytesError> {
        let mut array = [0; N];
        array.copy_from_slice(self.take(N)?);
        Ok(array)
    }

    /// One byte.
    pub fn u8(&mut self) -> Result<u8, BytesError> {
        Ok(self.array::<1>()?[0])
    }

    /// A `u32`.
    pub fn u32(&mut self) -> Result<u32, BytesError> {
        Ok(u32::from_le_bytes(self.array()?))
    }

    /// A `u64`.
    pub fn u64(&mut self) -> Result<u64, BytesError> {
        Ok(u64::from_le_bytes(self.array()?))
    }

    /// A count or size written by [`ByteWriter::usize`].
    pub fn usize(&mut self) -> Result<usize, BytesError> {
        usize::try_from(self.u64()?).map_err(|_| BytesError::Invalid("a count too large".into()))
    }

    /// A count of items of `item_bytes` each, checked against the bytes left, so that a
    /// corrupt count cannot ask for a huge allocation.
    pub fn count(&mut self, item_bytes: usize) -> Result<usize, BytesError> {
        let count = self.usize()?;
        if count.saturating_mul(item_bytes) > self.rest.len() {
            return Err(BytesError::EndsEarly);
        }
        Ok(count)
    }

    /// An `f32`.
    pub fn f32(&mut self) -> Result<f32, BytesError> {
        Ok(f32::from_le_bytes(self.array()?))
    }

    /// An `f64`.
    pub fn f64(&mut self) -> Result<f64, BytesError> {
        Ok(f64::from_le_bytes(self.array()?))
    }

    /// A number written by [`ByteWriter::real`], in the precision `S`.
    pub fn real<S: Real>(&mut self) -> Result<S, BytesError> {
        Ok(S::from_f64(self.f64()?))
    }

    /// A vector written by [`ByteWriter::vector`].
    pub fn vector<V: Vector>(&mut self) -> Result<V, BytesError> {
        let mut values = [0.0; 3];
        for value in &mut values[..V::DIM] {
            *value = self.f64()?;
        }
        Ok(V::from_f64_slice(&values[..V::DIM]))
    }

    /// A box written by [`ByteWriter::aabb`].
    pub fn aabb<V: Vector>(&mut self) -> Result<Aabb<V>, BytesError> {
        Ok(Aabb::new(self.vector()?, self.vector()?))
    }

    /// Text written by [`ByteWriter::string`].
    pub fn string(&mut self) -> Result<String, BytesError> {
        let length = self.count(1)?;
        String::from_utf8(self.take(length)?.to_vec())
            .map_err(|_| BytesError::Invalid("a name that is not text".into()))
    }

    /// `u32`s written by [`ByteWriter::u32s`].
    pub fn u32s(&mut self) -> Result<Vec<u32>, BytesError> {
        let count = self.count(4)?;
        Ok(self
            .take(count * 4)?
            .chunks_exact(4)
            .map(|chunk| u32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]))
            .collect())
    }

    /// `count` items, each read by `item`, after checking that `count` items of
    /// `item_bytes` each fit in what is left.
    pub fn items<T>(
        &mut self,
        item_bytes: usize,
        mut item: impl FnMut(&mut Self) -> Result<T, BytesError>,
    ) -> Result<Vec<T>, BytesError> {
        let count = self.count(item_bytes)?;
        let mut items = Vec::with_capacity(count);
        for _ in 0..count {
            items.push(item(self)?);
        }
        Ok(items)
    }

    /// Ok when every byte was read; else how many are left over.
    pub fn finish(&self) -> Result<(), BytesError> {
        match self.rest.len() {
            0 => Ok(()),
            left => Err(BytesError::TooMany(left)),
        }
    }
}

/// What a node of a flat tree read from bytes links to ([`check_links`]).
pub(crate) enum Link {
    /// An interior node: `children` nodes from `first`.
    Interior {
        /// Its first child.
        first: usize,
        /// How many children follow from there.
        children: usize,
    },
    /// A leaf: `count` primitive references from `first`.
    Leaf {
        /// Its first reference.
        first: usize,
        /// How many.
        count: usize,
    },
}

impl Link {
    /// A node that is a leaf of `count` references from `first`, or else an interior node
    /// whose `children` children start at `first` (as BVH, kD and octree nodes are laid out).
    pub(crate) fn of(leaf: bool, first: u32, count: u32, children: usize) -> Self {
        match leaf {
            true => Link::Leaf {
                first: first as usize,
                count: count as usize,
            },
            false => Link::Interior {
                first: first as usize,
                children,
            },
        }
    }
}

/// Checks that a flat tree read from bytes can be walked as its traversal and facts walk it:
/// from the root, every child lies in the node array and every node is reached exactly once
/// (no cycle, none shared, none left over), and every leaf's run lies in the `references`.
/// Well-formed but wrong bytes are an error here, not an index out of bounds later.
pub(crate) fn check_links(
    node_count: usize,
    references: usize,
    link: impl Fn(usize) -> Result<Link, BytesError>,
) -> Result<(), BytesError> {
    if node_count == 0 {
        return Ok(());
    }
    let broken = |node: usize, what: &str| BytesError::Invalid(format!("node {node}: {what}"));
    let mut reached = vec![false; node_count];
    let mut pending = vec![0usize];
    reached[0] = true;
    while let Some(node) = pending.pop() {
        match link(node)? {
            Link::Interior { first, children } => {
                let end = first
                    .checked_add(children)
                    .filter(|&end| end <= node_count && first > 0)
                    .ok_or_else(|| broken(node, "children outside the tree"))?;
                for (child, seen) in reached[first..end].iter_mut().enumerate() {
                    if std::mem::replace(seen, true) {
                        return Err(broken(first + child, "reached twice"));
                    }
                    pending.push(first + child);
                }
            }
            Link::Leaf { first, count } => {
                if first.checked_add(count).is_none_or(|end| end > references) {
                    return Err(broken(node, "primitives outside the list"));
                }
            }
        }
    }
    match reached.iter().position(|&reached| !reached) {
        Some(node) => Err(broken(node, "not reached from the root")),
        None => Ok(()),
    }
}

/// The bytes of one component of a vector or a number of either precision.
pub const REAL_BYTES: usize = 8;

/// The bytes of a box of `V`.
pub fn aabb_bytes<V: Vector>() -> usize {
    2 * V::DIM * REAL_BYTES
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, Vec3};

    #[test]
    fn fields_come_back_in_order_and_a_short_read_is_an_error() {
        let mut out = ByteWriter::new();
        out.u8(7);
        out.u32(0xdead_beef);
        out.usize(12);
        out.real(0.1f32);
        out.aabb(&Aabb::new(Vec3::new(-1.5, 0.25, 3.0), Vec3::splat(4.0)));
        out.vector(DVec2::new(0.1, -0.2));
        out.string("kd:sah");
        out.u32s(&[1, 2, 3]);
        let bytes = out.into_bytes();
        let mut input = ByteReader::new(&bytes);
        assert_eq!(input.u8(), Ok(7));
        assert_eq!(input.u32(), Ok(0xdead_beef));
        assert_eq!(input.usize(), Ok(12));
        assert_eq!(input.real::<f32>(), Ok(0.1f32), "an f32 comes back exactly");
        assert_eq!(
            input.aabb::<Vec3>(),
            Ok(Aabb::new(Vec3::new(-1.5, 0.25, 3.0), Vec3::splat(4.0)))
        );
        assert_eq!(input.vector::<DVec2>(), Ok(DVec2::new(0.1, -0.2)));
        assert_eq!(input.string().as_deref(), Ok("kd:sah"));
        assert_eq!(input.u32s(), Ok(vec![1, 2, 3]));
        assert_eq!(input.finish(), Ok(()));
        assert_eq!(input.u8(), Err(BytesError::EndsEarly));
        // A count larger than the bytes left asks for nothing, and one larger than a `usize`
        // (as on wasm32) is refused.
        let mut out = ByteWriter::new();
        out.u64(1 << 30);
        let bytes = out.into_bytes();
        assert_eq!(ByteReader::new(&bytes).u32s(), Err(BytesError::EndsEarly));
        let mut out = ByteWriter::new();
        out.u64(u64::MAX);
        assert!(ByteReader::new(&out.into_bytes()).u32s().is_err());
    }
}
