//! The grid walk at its extremes, with the cells written down: along an axis, through cell
//! corners, lying in a grid plane, starting inside, from very far away; fast and robust.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::grid::{self, GridCells, UniformGrid};
use accelviz_core::{
    Aabb, Query, Ray, Recorder, Shape, ShapeSet, Step, TraceOptions, TraversalStacks, Tree, Vector,
};
use glam::{DVec2, Vec2};

/// A grid of 4 × 4 unit cells over [0, 4]² (two specks in the top left and bottom right
/// corners make the box, off the rays' ways).
fn grid<V: Vector>() -> (ShapeSet<V>, UniformGrid<V>) {
    let speck = |x: f64, y: f64| {
        Shape::Box(Aabb::new(
            V::from_f64_slice(&[x, y]),
            V::from_f64_slice(&[x + 0.01, y + 0.01]),
        ))
    };
    let shapes = ShapeSet {
        shapes: vec![speck(0.0, 3.99), speck(3.99, 0.0)],
    };
    let bounds = Aabb::new(
        V::from_f64_slice(&[0.0, 0.0]),
        V::from_f64_slice(&[4.0, 4.0]),
    );
    let cells = GridCells::with_resolution(bounds, [4, 4, 1]);
    let built = grid::build_with_cells(&shapes, cells);
    (shapes, built)
}

/// The cells the walk passes, in order, as (x, y) with their parts of the ray.
fn walk<V: Vector>(
    origin: [f64; 2],
    direction: [f64; 2],
    robust: bool,
) -> Vec<([u32; 2], f64, f64)> {
    let (shapes, grid) = grid::<V>();
    let ray = Ray::try_new(V::from_f64_slice(&origin), V::from_f64_slice(&direction)).unwrap();
    let options = TraceOptions {
        // Nothing is hit: the walk goes on to the end.
        query: Query::Closest,
        ..TraceOptions::default()
    }
    .with_robust(robust);
    let mut recorder = Recorder::default();
    let tree = Tree::Grid(grid.clone());
    tree.trace(
        &shapes,
        &ray,
        &options,
        &mut TraversalStacks::default(),
        &mut recorder,
    );
    recorder
        .steps
        .iter()
        .filter_map(|step| match *step {
            Step::CellEntered {
                node,
                t_near,
                t_far,
            }
            | Step::CellSkipped {
                node,
                t_near,
                t_far,
            } => {
                let [x, y, _] = grid.cells.coordinates(node - 1);
                Some(([x, y], t_near.to_f64(), t_far.to_f64()))
            }
            _ => None,
        })
        .collect()
}

fn cells_of(walked: &[([u32; 2], f64, f64)]) -> Vec<[u32; 2]> {
    walked.iter().map(|(cell, _, _)| *cell).collect()
}

use accelviz_core::Real;

#[test]
fn along_an_axis_the_walk_passes_one_row_with_each_cells_part() {
    for robust in [false, true] {
        let walked = walk::<DVec2>([-1.0, 0.5], [1.0, 0.0], robust);
        assert_eq!(
            walked,
            vec![
                ([0, 0], 1.0, 2.0),
                ([1, 0], 2.0, 3.0),
                ([2, 0], 3.0, 4.0),
                ([3, 0], 4.0, 5.0)
            ]
        );
        // Backwards, from the other side.
        let back = walk::<Vec2>([9.0, 3.5], [-2.0, -0.0], robust);
        assert_eq!(cells_of(&back), vec![[3, 3], [2, 3], [1, 3], [0, 3]]);
    }
}

#[test]
fn through_cell_corners_the_plain_walk_steps_x_first_and_the_robust_one_visits_both() {
    let fast = walk::<DVec2>([-1.0, -1.0], [1.0, 1.0], false);
    assert_eq!(
        fast,
        vec![
            ([0, 0], 1.0, 2.0),
            ([1, 0], 2.0, 2.0),
            ([1, 1], 2.0, 3.0),
            ([2, 1], 3.0, 3.0),
            ([2, 2], 3.0, 4.0),
            ([3, 2], 4.0, 4.0),
            ([3, 3], 4.0, 5.0),
        ]
    );
    let robust = walk::<DVec2>([-1.0, -1.0], [1.0, 1.0], true);
    assert_eq!(
        cells_of(&robust),
        vec![
            [0, 0],
            [1, 0],
            [0, 1],
            [1, 1],
            [2, 1],
            [1, 2],
            [2, 2],
            [3, 2],
            [2, 3],
            [3, 3]
        ]
    );
}

#[test]
fn lying_in_a_grid_plane_the_robust_walk_runs_along_both_sides() {
    // y = 2 is the plane between rows 1 and 2; a point on it belongs to the row above.
    let fast = walk::<DVec2>([-1.0, 2.0], [1.0, 0.0], false);
    assert_eq!(cells_of(&fast), vec![[0, 2], [1, 2], [2, 2], [3, 2]]);
    let robust = walk::<DVec2>([-1.0, 2.0], [1.0, 0.0], true);
    assert_eq!(
        cells_of(&robust),
        vec![
            [0, 2],
            [0, 1],
            [1, 2],
            [1, 1],
            [2, 2],
            [2, 1],
            [3, 2],
            [3, 1]
        ]
    );
    // Along the box's own side: one row inside, in either mode.
    let side = walk::<DVec2>([-1.0, 0.0], [1.0, 0.0], true);
    assert_eq!(cells_of(&side), vec![[0, 0], [1, 0], [2, 0], [3, 0]]);
}

#[test]
fn starting_inside_the_walk_begins_in_the_origins_cell() {
    let walked = walk::<DVec2>([1.5, 2.5], [1.0, 0.5], false);
    assert_eq!(
        walked,
        vec![
            ([1, 2], 0.0, 0.5),
            ([2, 2], 0.5, 1.0),
            ([2, 3], 1.0, 1.5),
            ([3, 3], 1.5, 2.5),
        ]
    );
}

#[test]
fn from_far_away_every_cell_on_the_way_is_passed_even_where_their_t_coincide() {
    // From 10⁶ the cells' planes are a unit apart in t: told apart exactly.
    let near_enough = walk::<DVec2>([-1e6, 0.5], [1.0, 0.0], false);
    assert_eq!(cells_of(&near_enough), vec![[0, 0], [1, 0], [2, 0], [3, 0]]);
    // From 10³⁰ in f32 every plane is at the same t: each cell is passed, with an empty part.
    let far = walk::<Vec2>([-1e30, 0.5], [1.0, 0.0], false);
    assert_eq!(cells_of(&far), vec![[0, 0], [1, 0], [2, 0], [3, 0]]);
    let far_t = f64::from(1e30f32);
    assert!(
        far.iter()
            .all(|&(_, t_near, t_far)| t_near == far_t && t_far == t_near)
    );
}

#[test]
fn a_ray_that_misses_the_box_or_starts_beyond_it_passes_no_cell() {
    assert!(walk::<DVec2>([-1.0, 5.0], [1.0, 0.0], false).is_empty());
    assert!(walk::<DVec2>([5.0, 0.5], [1.0, 0.0], true).is_empty());
}

#[test]
fn every_cells_path_leads_back_to_it_in_a_grid_and_an_octree() {
    use accelviz_core::params::BuildParams;
    use accelviz_core::{Built, NoBuildObserver, Sphere, Structure};
    let discs = ShapeSet {
        shapes: (0..40)
            .map(|index| {
                let x = f64::from(index % 8);
                let y = f64::from(index / 8) * 1.3;
                Shape::Sphere(Sphere {
                    center: DVec2::new(x, y),
                    radius: 0.3,
                })
            })
            .collect(),
    };
    for name in ["grid:uniform:2", "grid:hashed:1", "octree:2"] {
        let structure = Structure::parse(name).unwrap();
        let built = Built::new(
            structure,
            &discs,
            &BuildParams::default(),
            &mut NoBuildObserver,
        );
        assert!(built.facts.node_count() > 9, "{name}");
        for node in 0..built.facts.node_count() as u32 {
            let path = built.facts.path_to(node);
            assert_eq!(built.facts.node_at(&path), Ok(node), "{name}: {path}");
        }
    }
}

/// A lesson's chosen cells and table: `BuildParams::grid` overrides the density rule and the
/// table's default size, and the grids built are whole (they validate, and the hashed one
/// walks like the dense one).
#[test]
fn chosen_cells_and_table_size_are_built_as_asked() {
    use accelviz_core::{BuildParams, GridParams, NoBuildObserver, Structure};
    let shapes: ShapeSet<DVec2> =
        accelviz_scene::scene2d::generate(accelviz_scene::scene2d::Layout::Uniform, 60, 3);
    let params = BuildParams {
        grid: GridParams {
            cells_along_longest: Some(12),
            hash_places: Some(97),
        },
        ..BuildParams::default()
    };
    let bounds = shapes
        .shapes
        .iter()
        .fold(Aabb::empty(), |bounds, shape| bounds.union(shape.bounds()));
    let expected = GridCells::along_longest(bounds, 12).resolution;
    for density in [1, 8] {
        let dense = Structure::GridUniform { density }.build_observed(
            &shapes,
            &params,
            &mut NoBuildObserver,
        );
        let hashed = Structure::GridHashed { density }.build_observed(
            &shapes,
            &params,
            &mut NoBuildObserver,
        );
        let (Tree::Grid(dense), Tree::HashedGrid(hashed)) = (dense, hashed) else {
            panic!("grids built");
        };
        assert_eq!(
            dense.cells.resolution, expected,
            "density {density} is not asked"
        );
        assert_eq!(hashed.cells.resolution, expected);
        assert_eq!(hashed.store.buckets.len(), 97);
        grid::validate(&dense, &shapes).unwrap();
        grid::validate(&hashed, &shapes).unwrap();
        // The dense table's bytes, as the hashed grid weighs itself against them.
        use accelviz_core::grid::CellStore;
        assert_eq!(hashed.dense_bytes(), dense.store.bytes());
        assert_eq!(dense.dense_bytes(), dense.store.bytes());
    }
}

/// A fuller table reads more places a lookup: at its fullest (one place free) more than at
/// the default load of at most a half; a stored cell is found in at least one read, and the
/// means are those of looking every cell up.
#[test]
fn a_fuller_hash_table_reads_more_places_a_lookup() {
    use accelviz_core::grid::CellStore;
    use accelviz_core::{BuildParams, GridParams, NoBuildObserver, Structure};
    let shapes: ShapeSet<DVec2> =
        accelviz_scene::scene2d::generate(accelviz_scene::scene2d::Layout::Uniform, 200, 5);
    let table = |places: Option<usize>| {
        let params = BuildParams {
            grid: GridParams {
                cells_along_longest: None,
                hash_places: places,
            },
            ..BuildParams::default()
        };
        let structure = Structure::GridHashed { density: 2 };
        match structure.build_observed(&shapes, &params, &mut NoBuildObserver) {
            Tree::HashedGrid(grid) => grid,
            _ => panic!("a hashed grid"),
        }
    };
    let roomy = table(None);
    let occupied = roomy.store.occupied();
    assert!(roomy.store.load() <= 0.5);
    let full = table(Some(occupied + 1));
    assert_eq!(full.store.buckets.len(), occupied + 1);
    let cell_count = roomy.cells.cell_count();
    let (roomy_found, roomy_absent) = roomy.store.probes_per_lookup(cell_count);
    let (full_found, full_absent) = full.store.probes_per_lookup(cell_count);
    assert!(roomy_found >= 1.0 && roomy_absent >= 1.0);
    assert!(full_found > roomy_found, "{full_found} vs {roomy_found}");
    assert!(
        full_absent > roomy_absent,
        "{full_absent} vs {roomy_absent}"
    );
    assert!(full.store.collisions > roomy.store.collisions);
    // The mean for stored cells is the mean of their lookups.
    let stored: Vec<u32> = (0..cell_count as u32)
        .filter(|&cell| full.store.place_of(cell).is_some())
        .collect();
    let mean = stored
        .iter()
        .map(|&cell| f64::from(full.store.lookup(cell).probes))
        .sum::<f64>()
        / stored.len() as f64;
    assert!((mean - full_found).abs() < 1e-12);
}
