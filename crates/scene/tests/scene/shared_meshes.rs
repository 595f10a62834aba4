//! The shared test meshes (`../shared/meshes/`, beside the repository) load with the expected
//! triangle counts, and a structure of every family agrees with brute force on a few thousand
//! random rays.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::params::BuildParams;
use accelviz_core::{
    NoObserver, Structure, TraceOptions, TraversalStacks, Tree, TriangleSet, Vector3, Width,
    brute_force,
};
use accelviz_scene::Mesh;
use accelviz_scene::obj::load_obj;
use accelviz_scene::rays::random_rays;
use glam::{DVec3, Vec3};

pub fn shared_mesh(name: &str) -> Mesh {
    let path = format!(
        "{}/../../../shared/meshes/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    load_obj(&path)
        .unwrap_or_else(|error| panic!("the shared meshes sit beside the repository: {error}"))
}

fn agree<V: Vector3>(mesh: &Mesh, ray_count: usize, options: TraceOptions) -> usize {
    let triangles = TriangleSet::<V>::from_f64(&mesh.triangles);
    let params = BuildParams::default();
    let trees: Vec<(Structure, Tree<V>)> = [
        Structure::BvhSahBinned {
            bins: 16,
            width: Width::Binary,
        },
        Structure::BvhSahSweep {
            width: Width::Binary,
        },
        Structure::KdMiddle,
        Structure::KdMedian,
        Structure::GridUniform { density: 2 },
        Structure::GridHashed { density: 1 },
        Structure::Octree { leaf: 8 },
    ]
    .into_iter()
    .map(|structure| (structure, structure.build(&triangles, &params)))
    .collect();
    for (structure, tree) in &trees {
        // The kD validator is O(leaves × primitives): the property tests run it everywhere,
        // here only on the smaller meshes.
        if !matches!(tree, Tree::Kd(_)) || mesh.triangles.len() <= 25_000 {
            structure.validate(tree, &triangles).unwrap();
        }
        // Real meshes stay far inside the default kD budget: it bounds runaway builds only.
        assert!(
            tree.kd_limits()
                .is_none_or(|limits| limits.lowered_from.is_none()),
            "{} {}: {:?}",
            mesh.name,
            structure.name(),
            tree.kd_limits()
        );
    }
    let mut stacks = TraversalStacks::default();
    let mut hits = 0;
    for spec in random_rays(&mesh.bounds(), ray_count, 3) {
        let ray = spec.to_ray::<V>().unwrap();
        let expected = brute_force(&triangles, &ray, &options, &mut NoObserver);
        hits += expected.is_some() as usize;
        for (structure, tree) in &trees {
            let got = tree.trace(&triangles, &ray, &options, &mut stacks, &mut NoObserver);
            assert_eq!(got, expected, "{} {}: {ray:?}", mesh.name, structure.name());
        }
    }
    hits
}

/// `name` loads with `triangle_count` triangles, and every tree agrees with brute force on
/// `rays` random rays, in f32 and in f64 with the robust tests.
fn loads_and_agrees(name: &str, triangle_count: usize, rays: usize) -> Mesh {
    let mesh = shared_mesh(name);
    assert_eq!(mesh.triangles.len(), triangle_count, "{name}");
    let fast = agree::<Vec3>(&mesh, rays, TraceOptions::default());
    let robust = agree::<DVec3>(&mesh, rays, TraceOptions::default().with_robust(true));
    // Random rays aim inside the box: a good share hit the mesh.
    assert!(
        fast > rays / 10 && robust > rays / 10,
        "{name}: {fast} and {robust} hits"
    );
    mesh
}

// One test a mesh, so the test runner spreads them over the cores: brute force on the larger
// meshes is most of this binary's time.

#[test]
fn suzanne_loads_and_agrees_with_brute_force() {
    loads_and_agrees("suzanne.obj", 968, 4000);
}

#[test]
fn the_rocker_arm_loads_and_agrees_with_brute_force() {
    loads_and_agrees("rocker-arm.obj", 20_088, 2000);
}

#[test]
fn the_bunny_loads_and_agrees_with_brute_force() {
    loads_and_agrees("stanford-bunny.obj", 69_451, 2000);
}

#[test]
fn the_ogre_loads_and_agrees_with_brute_force() {
    let ogre = loads_and_agrees("ogre.obj", 124_008, 2000);
    let ogre = TriangleSet::<Vec3>::from_f64(&ogre.triangles);
    assert_eq!(
        ogre.degenerate_count(),
        4,
        "the ogre's README lists 4 zero-area triangles"
    );
}

#[test]
fn a_file_over_the_size_limit_is_refused_before_reading() {
    // A sparse file: it takes no disk space, but its length is over the limit.
    let path = std::env::temp_dir().join(format!("accelviz-huge-{}.obj", std::process::id()));
    let file = std::fs::File::create(&path).unwrap();
    file.set_len(accelviz_scene::error::MAX_FILE_BYTES + 1)
        .unwrap();
    let path_text = path.to_string_lossy().into_owned();
    let message = load_obj(&path_text).unwrap_err().to_string();
    std::fs::remove_file(&path).unwrap();
    assert!(message.starts_with(&path_text), "{message}");
    assert!(message.contains("the limit is 1073741824"), "{message}");
}
