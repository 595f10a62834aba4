//! The work a Web Worker does, called by `web/worker.js` through the exports in
//! `crates/web/src/main.rs`: read an OBJ file, build a structure over a mesh; what it makes
//! goes back as bytes ([`super::packed`]).

use super::packed::{flat_triangles, pack, triangles_of};
use crate::mesh::MeshTree;
use accelviz_core::{Structure, TriangleSet};
use accelviz_scene::Mesh;

/// Reads OBJ `bytes` named `name`, telling `progress` how far it got (per mille, only
/// when that changes); the triangles' corners, nine numbers a triangle.
pub fn read_obj(name: &str, bytes: &[u8], progress: &dyn Fn(u32)) -> Result<Vec<f64>, String> {
    let text = std::str::from_utf8(bytes)
        .map_err(|_| format!("{name}: not a text file (it is not UTF-8)"))?;
    let last = std::cell::Cell::new(u32::MAX);
    let mesh = accelviz_scene::obj::parse_obj_with_progress(text, name, &|permille| {
        if last.replace(permille) != permille {
            progress(permille);
        }
    })
    .map_err(|error| error.to_string())?;
    Ok(flat_triangles(&mesh.triangles).to_vec())
}

/// Builds the structure named `structure` over `triangles` (nine numbers each), packed.
pub fn build(triangles: &[f64], structure: &str) -> Result<Vec<u8>, String> {
    let structure = Structure::parse(structure).map_err(|error| error.to_string())?;
    let mesh = Mesh {
        name: String::new(),
        triangles: triangles_of(triangles),
    };
    let triangles = TriangleSet::from_f64(&mesh.triangles);
    Ok(pack(&MeshTree::build_structure(
        &mesh, &triangles, structure,
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::packed::unpack;
    use crate::mesh::work;
    use std::sync::Arc;

    #[test]
    fn the_workers_read_and_build_are_the_apps() {
        let mesh = accelviz_scene::builtin::teapot();
        let text = accelviz_scene::obj::obj_text(&mesh);
        let heard = std::cell::RefCell::new(Vec::new());
        let numbers = work::read_obj("teapot.obj", text.as_bytes(), &|permille| {
            heard.borrow_mut().push(permille)
        })
        .expect("reads");
        assert_eq!(triangles_of(&numbers), mesh.triangles);
        let heard = heard.into_inner();
        assert!(heard.windows(2).all(|pair| pair[0] < pair[1]), "{heard:?}");

        let structure = Structure::parse("kd:sah").expect("in the catalogue");
        let mut from_worker =
            unpack(&work::build(&numbers, &structure.name()).expect("builds")).expect("unpacks");
        let on_page = MeshTree::build(Arc::new(mesh), structure).build;
        from_worker.build_millis = on_page.build_millis;
        assert_eq!(from_worker, on_page);

        // Bad input: a message naming the file and line, or the structure.
        let problem = work::read_obj("bad.obj", b"v 0 0 0\nv 1 x 0\n", &|_| {}).unwrap_err();
        assert!(problem.contains("bad.obj:2"), "{problem}");
        let problem = work::read_obj("binary.obj", &[0xff, 0xfe, 0], &|_| {}).unwrap_err();
        assert!(problem.contains("binary.obj: not a text file"), "{problem}");
        assert!(work::build(&numbers, "bvh:nonsense").is_err());
    }
}
