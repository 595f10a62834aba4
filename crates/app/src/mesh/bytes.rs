//! Bytes for what a Web Worker sends back (its memory is its own): little-endian fields
//! written one after another ([`Writer`]) and read back in the same order ([`Reader`]), a
//! short or corrupt input an error, never a panic or a huge allocation.

use accelviz_core::Aabb;
use glam::DVec3;

/// Bytes written little-endian, field after field.
#[derive(Default)]
pub(crate) struct Writer {
    /// What is written so far.
    pub(crate) bytes: Vec<u8>,
}

impl Writer {
    pub(crate) fn u32(&mut self, value: u32) {
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    pub(crate) fn u64(&mut self, value: u64) {
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    pub(crate) fn f64(&mut self, value: f64) {
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    pub(crate) fn aabb(&mut self, bounds: &Aabb<DVec3>) {
        for value in bounds
            .min
            .to_array()
            .into_iter()
            .chain(bounds.max.to_array())
        {
            self.f64(value);
        }
    }

    pub(crate) fn string(&mut self, value: &str) {
        self.u64(value.len() as u64);
        self.bytes.extend_from_slice(value.as_bytes());
    }

    pub(crate) fn u32s(&mut self, values: &[u32]) {
        self.u64(values.len() as u64);
        self.bytes.reserve(values.len() * 4);
        for &value in values {
            self.u32(value);
        }
    }
}

/// Bytes read back in the order [`Writer`] wrote them; a read past the end is an error.
pub(crate) struct Reader<'a> {
    /// What is left to read.
    pub(crate) rest: &'a [u8],
}

impl<'a> Reader<'a> {
    pub(crate) fn u32(&mut self) -> Result<u32, String> {
        let bytes = self.take(4)?;
        Ok(u32_at(bytes, 0))
    }

    pub(crate) fn take(&mut self, count: usize) -> Result<&'a [u8], String> {
        if self.rest.len() < count {
            return Err("the packed structure ends early".to_owned());
        }
        let (taken, rest) = self.rest.split_at(count);
        self.rest = rest;
        Ok(taken)
    }

    pub(crate) fn array<const N: usize>(&mut self) -> Result<[u8; N], String> {
        let mut array = [0; N];
        array.copy_from_slice(self.take(N)?);
        Ok(array)
    }

    pub(crate) fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.array()?))
    }

    pub(crate) fn usize(&mut self) -> Result<usize, String> {
        usize::try_from(self.u64()?).map_err(|_| "a count too large".to_owned())
    }

    /// A count of items of `item_bytes` each, checked against the bytes left (so a corrupt
    /// count cannot ask for a huge allocation).
    pub(crate) fn count(&mut self, item_bytes: usize) -> Result<usize, String> {
        let count = self.usize()?;
        if count.saturating_mul(item_bytes) > self.rest.len() {
            return Err("the packed structure ends early".to_owned());
        }
        Ok(count)
    }

    pub(crate) fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.array()?))
    }

    pub(crate) fn aabb(&mut self) -> Result<Aabb<DVec3>, String> {
        let mut values = [0.0; 6];
        for value in &mut values {
            *value = self.f64()?;
        }
        Ok(Aabb::new(
            DVec3::new(values[0], values[1], values[2]),
            DVec3::new(values[3], values[4], values[5]),
        ))
    }

    pub(crate) fn string(&mut self) -> Result<String, String> {
        let length = self.count(1)?;
        String::from_utf8(self.take(length)?.to_vec())
            .map_err(|_| "a name that is not UTF-8".to_owned())
    }

    /// Whether every byte was read.
    pub(crate) fn is_done(&self) -> bool {
        self.rest.is_empty()
    }

    pub(crate) fn u32s(&mut self) -> Result<Vec<u32>, String> {
        self.items(|bytes: &[u8; 4]| u32::from_le_bytes(*bytes))
    }

    /// A counted run of items of `N` bytes each, each made by `item` (in one pass over the
    /// bytes: a million-node tree is read in the browser's page, where time is frames).
    pub(crate) fn items<const N: usize, T>(
        &mut self,
        item: impl Fn(&[u8; N]) -> T,
    ) -> Result<Vec<T>, String> {
        let count = self.count(N)?;
        let bytes = self.take(count * N)?;
        Ok(bytes
            .chunks_exact(N)
            .map(|chunk| item(chunk.try_into().unwrap_or(&[0; N])))
            .collect())
    }
}

/// The little-endian `u32` at `at`.
pub(crate) fn u32_at(bytes: &[u8], at: usize) -> u32 {
    let mut array = [0; 4];
    array.copy_from_slice(&bytes[at..at + 4]);
    u32::from_le_bytes(array)
}

/// The little-endian `f32` at `at`.
pub(crate) fn f32_at(bytes: &[u8], at: usize) -> f32 {
    let mut array = [0; 4];
    array.copy_from_slice(&bytes[at..at + 4]);
    f32::from_le_bytes(array)
}

/// The little-endian `f64` at `at`.
pub(crate) fn f64_at(bytes: &[u8], at: usize) -> f64 {
    let mut array = [0; 8];
    array.copy_from_slice(&bytes[at..at + 8]);
    f64::from_le_bytes(array)
}

/// The box (six `f64`) at `at`.
pub(crate) fn aabb_at(bytes: &[u8], at: usize) -> Aabb<DVec3> {
    let corner = |at: usize| {
        DVec3::new(
            f64_at(bytes, at),
            f64_at(bytes, at + 8),
            f64_at(bytes, at + 16),
        )
    };
    Aabb::new(corner(at), corner(at + 24))
}
