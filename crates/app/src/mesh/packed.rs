//! What crosses between the page and a Web Worker, which shares no memory with it: a mesh as
//! its corners, nine numbers a triangle ([`flat_triangles`]), and a built structure as the
//! core's bytes of it followed by what the builder's thread measured and the triangles as the
//! 3D view draws them ([`pack`], [`unpack`]: tested equal field for field).

use accelviz_core::bytes::{ByteReader, ByteWriter, BytesError};
use accelviz_core::{Built, TreeStats};

use super::tree::MeshBuild;
use crate::view3d::DrawTriangle;

/// `built` as bytes: the core's bytes of the structure ([`Built::write_bytes`]), then what the
/// builder's thread measured of it and the triangles as the 3D view draws them.
pub fn pack(built: &MeshBuild) -> Vec<u8> {
    let mut out = ByteWriter::new();
    built.built.write_bytes(&mut out);
    built.stats.write_bytes(&mut out);
    out.f64(built.build_millis);
    out.usize(built.root_triangles);
    let (center, radius) = built.sphere;
    out.vector(center);
    out.f64(radius);
    out.usize(built.drawn.len());
    out.reserve(built.drawn.len() * DRAWN_TRIANGLE_BYTES);
    for triangle in &built.drawn {
        for &value in triangle.corners.iter().flatten() {
            out.f32(value);
        }
        out.raw(&triangle.color);
    }
    out.into_bytes()
}

/// A drawn triangle's bytes: nine `f32` corners and four colour bytes.
const DRAWN_TRIANGLE_BYTES: usize = 9 * 4 + 4;

/// What [`pack`] made, back; or why the bytes are not that.
pub fn unpack(bytes: &[u8]) -> Result<MeshBuild, String> {
    let read = || -> Result<MeshBuild, BytesError> {
        let mut input = ByteReader::new(bytes);
        let built = Built::read_bytes(&mut input)?;
        let stats = TreeStats::read_bytes(&mut input)?;
        let build_millis = input.f64()?;
        let root_triangles = input.usize()?;
        let sphere = (input.vector()?, input.f64()?);
        let drawn = input.items(DRAWN_TRIANGLE_BYTES, |input| {
            let mut corner = || -> Result<[f32; 3], BytesError> {
                Ok([input.f32()?, input.f32()?, input.f32()?])
            };
            let corners = [corner()?, corner()?, corner()?];
            Ok(DrawTriangle {
                corners,
                color: input.array()?,
            })
        })?;
        input.finish()?;
        Ok(MeshBuild {
            built,
            stats,
            root_triangles,
            build_millis,
            sphere,
            drawn,
        })
    };
    read().map_err(|error| format!("the structure sent back: {error}"))
}

/// A mesh's triangles as nine numbers each (the corners in order), to send to a worker.
pub fn flat_triangles(triangles: &[[[f64; 3]; 3]]) -> &[f64] {
    triangles.as_flattened().as_flattened()
}

/// Triangles from [`flat_triangles`]' numbers (a partial triangle at the end is dropped).
pub fn triangles_of(numbers: &[f64]) -> Vec<[[f64; 3]; 3]> {
    numbers
        .chunks_exact(9)
        .map(|n| [[n[0], n[1], n[2]], [n[3], n[4], n[5]], [n[6], n[7], n[8]]])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::MeshTree;
    use std::sync::Arc;

    #[test]
    fn every_structure_comes_back_equal() {
        let mesh = Arc::new(accelviz_scene::builtin::teapot());
        let wide = [accelviz_core::Width::Four, accelviz_core::Width::Eight]
            .map(|width| accelviz_core::CATALOGUE[3].structure.with_width(width));
        let structures = accelviz_core::CATALOGUE.iter().map(|entry| entry.structure);
        for structure in structures.chain(wide) {
            let tree = MeshTree::build(mesh.clone(), structure);
            let bytes = pack(&tree.build);
            assert_eq!(
                unpack(&bytes).as_ref(),
                Ok(&tree.build),
                "{}",
                structure.name()
            );
            // Cut short or padded: an error, never a panic.
            for cut in [0, 7, 8, 40, bytes.len() / 2, bytes.len() - 1] {
                assert!(unpack(&bytes[..cut]).is_err(), "cut at {cut}");
            }
            let mut padded = bytes.clone();
            padded.push(0);
            assert!(unpack(&padded).is_err());
        }
        let flat = flat_triangles(&mesh.triangles);
        assert_eq!(triangles_of(flat), mesh.triangles);
    }
}
