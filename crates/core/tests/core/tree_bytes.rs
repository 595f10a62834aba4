//! A built structure's bytes (`Built::to_bytes`, each family's `write_bytes`) come back as the
//! same structure, field for field, for every entry of the catalogue and every width, in 2D
//! and 3D, f32 and f64; cut, padded or read in the wrong precision they are an error, never a
//! panic.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::bytes::{ByteReader, ByteWriter, BytesError};
use accelviz_core::params::BuildParams;
use accelviz_core::{
    Aabb, Built, CATALOGUE, NoBuildObserver, PrimitiveSet, Shape, ShapeSet, Sphere, Structure,
    TreeStats, TriangleSet, Vector, Width,
};
use glam::{DVec2, DVec3, Vec2, Vec3};

/// Every entry of the catalogue, and the SAH BVH at every width.
fn structures() -> Vec<Structure> {
    let binned = Structure::parse("bvh:sah-binned").unwrap();
    CATALOGUE
        .iter()
        .map(|entry| Structure::parse(entry.name).unwrap())
        .chain([Width::Four, Width::Eight].map(|width| binned.with_width(width)))
        .collect()
}

fn round_trips<V: Vector, P: PrimitiveSet<V>>(primitives: &P, what: &str) {
    let params = BuildParams {
        // Small leaves and a hashed table of its own size: every field of every family set.
        max_leaf_size: 2,
        ..BuildParams::default()
    };
    for structure in structures() {
        let built = Built::new(structure, primitives, &params, &mut NoBuildObserver);
        let name = format!("{what} {}", structure.name());
        let bytes = built.to_bytes();
        assert_eq!(
            Built::<V>::from_bytes(&bytes).as_ref(),
            Ok(&built),
            "{name}"
        );
        // What a caller writes after it is left for the caller.
        let mut out = ByteWriter::new();
        built.write_bytes(&mut out);
        out.u32(7);
        let bytes_and_more = out.into_bytes();
        let mut input = ByteReader::new(&bytes_and_more);
        assert_eq!(Built::<V>::read_bytes(&mut input).as_ref(), Ok(&built));
        assert_eq!(input.u32(), Ok(7));
        input.finish().unwrap();
        // Cut anywhere or padded: an error.
        for cut in [
            0,
            7,
            8,
            9,
            20,
            bytes.len() / 3,
            bytes.len() / 2,
            bytes.len() - 1,
        ] {
            assert!(
                Built::<V>::from_bytes(&bytes[..cut]).is_err(),
                "{name}: cut at {cut}"
            );
        }
        let mut padded = bytes.clone();
        padded.push(0);
        assert_eq!(
            Built::<V>::from_bytes(&padded),
            Err(BytesError::TooMany(1)),
            "{name}"
        );
    }
}

#[test]
fn every_structure_comes_back_the_same_from_its_bytes() {
    let mesh = accelviz_scene::builtin::teapot();
    round_trips(&TriangleSet::<DVec3>::from_f64(&mesh.triangles), "3D f64");
    round_trips(&TriangleSet::<Vec3>::from_f64(&mesh.triangles), "3D f32");
    let shapes = |scale: f64| -> Vec<(usize, [f64; 2], [f64; 2])> {
        (0..300)
            .map(|index| {
                let at = |k: usize| ((index * 37 + k * 11) % 101) as f64 * scale;
                (index % 3, [at(0), at(1)], [at(2) * 0.1, at(3) * 0.1])
            })
            .collect()
    };
    fn shape_set<V: Vector>(specs: &[(usize, [f64; 2], [f64; 2])]) -> ShapeSet<V> {
        let point = |p: &[f64; 2]| V::from_f64_slice(p);
        ShapeSet {
            shapes: specs
                .iter()
                .map(|(kind, a, b)| match kind {
                    0 => Shape::Segment([point(a), point(&[a[0] + b[0], a[1] - b[1]])]),
                    1 => Shape::Sphere(Sphere {
                        center: point(a),
                        radius: <V::Scalar as accelviz_core::Real>::from_f64(b[0] + 0.1),
                    }),
                    _ => Shape::Box(Aabb::from_points([
                        point(a),
                        point(&[a[0] + b[0], a[1] + b[1]]),
                    ])),
                })
                .collect(),
        }
    }
    round_trips(&shape_set::<DVec2>(&shapes(1.0)), "2D f64");
    round_trips(&shape_set::<Vec2>(&shapes(0.01)), "2D f32");
}

#[test]
fn bytes_of_another_precision_or_dimension_or_format_are_refused() {
    let mesh = accelviz_scene::builtin::teapot();
    let triangles = TriangleSet::<DVec3>::from_f64(&mesh.triangles);
    let structure = Structure::parse("kd:sah").unwrap();
    let built = Built::new(
        structure,
        &triangles,
        &BuildParams::default(),
        &mut NoBuildObserver,
    );
    let bytes = built.to_bytes();
    assert!(matches!(
        Built::<Vec3>::from_bytes(&bytes),
        Err(BytesError::Invalid(_))
    ));
    assert!(matches!(
        Built::<DVec2>::from_bytes(&bytes),
        Err(BytesError::Invalid(_))
    ));
    let mut other = bytes.clone();
    other[7] = b'9';
    assert_eq!(
        Built::<DVec3>::from_bytes(&other),
        Err(BytesError::NotATree)
    );
    // A structure name this version does not know.
    let mut out = ByteWriter::new();
    out.raw(&bytes[..10]);
    out.string("kd:nonsense");
    assert!(matches!(
        Built::<DVec3>::from_bytes(&out.into_bytes()),
        Err(BytesError::Invalid(_))
    ));
    // The stats travel too.
    let stats = built.tree.stats(&Default::default());
    let mut out = ByteWriter::new();
    stats.write_bytes(&mut out);
    let bytes = out.into_bytes();
    let mut input = ByteReader::new(&bytes);
    assert_eq!(TreeStats::read_bytes(&mut input), Ok(stats));
    input.finish().unwrap();
}

#[test]
fn well_formed_but_wrong_bytes_are_an_error_or_another_tree_never_a_panic() {
    let mesh = accelviz_scene::builtin::teapot();
    let triangles = TriangleSet::<Vec3>::from_f64(&mesh.triangles);
    for structure in structures() {
        if structure.family() == accelviz_core::Family::HashedGrid {
            // Its table's size is read as asked (up to 2^24 places): flips there are slow.
            continue;
        }
        let built = Built::new(
            structure,
            &triangles,
            &BuildParams::default(),
            &mut NoBuildObserver,
        );
        let bytes = built.to_bytes();
        // One bit flipped at a spread of places (after the mark): whatever it becomes, a
        // tree that walks or an error.
        for step in 0..97 {
            let at = 10 + (bytes.len() - 10) * step / 97;
            for bit in [0, 3, 7] {
                let mut flipped = bytes.clone();
                flipped[at] ^= 1 << bit;
                if let Ok(read) = Built::<Vec3>::from_bytes(&flipped) {
                    // What was read can be measured: every node reached, every run in place.
                    read.tree.stats(&Default::default());
                }
            }
        }
    }
    // A BVH whose root's children point back at the root.
    let bvh = accelviz_core::bvh::Bvh {
        nodes: vec![
            accelviz_core::bvh::BvhNode {
                bounds: Aabb::new(Vec3::ZERO, Vec3::ONE),
                first: 0,
                count: 0,
            };
            2
        ],
        primitive_indices: vec![],
    };
    let mut out = ByteWriter::new();
    bvh.write_bytes(&mut out);
    let bytes = out.into_bytes();
    assert!(matches!(
        accelviz_core::bvh::Bvh::<Vec3>::read_bytes(&mut ByteReader::new(&bytes)),
        Err(BytesError::Invalid(_))
    ));
}
