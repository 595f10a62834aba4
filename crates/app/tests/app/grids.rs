//! The grid, hashing and quadtree lessons (18 to 20): the walk they show is the core's, its
//! table holds the numbers each step needs before it is taken, the cell size is the user's or
//! the density rule's, the cost curve is measured, and the views match their snapshots.

use accelviz_app::lesson::Lesson;
use accelviz_app::lessons::grid::GridLesson;
use accelviz_app::views::grid_walk::{MOST_ALONG, rule_along};
use accelviz_core::Step;

use crate::common::{lesson_harness_3d, lesson_text};

/// Updates `lesson` until what it builds aside is in.
fn settle(lesson: &mut impl Lesson) {
    for _ in 0..400 {
        lesson.update();
        if lesson.building().is_none() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    panic!("still building after 4 s");
}

/// The walk the lesson shows is the core's: one cell after the next, each across the line of
/// the axis whose `t` in the table was the smaller (so the table answers every step before it
/// is taken), ending where the caption says, for the lesson's scene and both presets.
#[test]
fn the_grid_walk_steps_across_the_nearer_line_its_table_shows() {
    let mut lesson = GridLesson::new(lesson_text("18-uniform-grid.ron"));
    for preset in [None, Some("teapot in a stadium"), Some("evenly spread")] {
        if let Some(preset) = preset {
            assert!(lesson.show_named(preset), "{preset}");
        }
        settle(&mut lesson);
        let rows = lesson.rows().to_vec();
        assert!(rows.len() >= 5, "{preset:?}: {} cells", rows.len());
        for pair in rows.windows(2) {
            let (row, next) = (&pair[0], &pair[1]);
            let t_next = row.t_next.expect("a cell the walk leaves has its table");
            let axis = row.crossed.expect("and the line it crosses");
            let other = 1 - axis;
            assert!(t_next[axis] <= t_next[other], "{preset:?}: {row:?}");
            // The next cell is across that line, one step along its axis.
            assert_eq!(
                next.cell[other], row.cell[other],
                "{preset:?}: {row:?} -> {next:?}"
            );
            assert_eq!(
                next.cell[axis].abs_diff(row.cell[axis]),
                1,
                "{preset:?}: {row:?} -> {next:?}"
            );
            assert_eq!(next.t_near, t_next[axis]);
        }
        // Stepped to the end, the caption says where and why it stopped.
        let frames = lesson.stage().timeline.len;
        lesson.stage_mut().timeline.shown = frames;
        lesson.update();
        let caption = lesson.caption().expect("a caption");
        let last = rows.last().expect("cells");
        assert!(
            caption.contains(&format!(
                "cells passed ({} empty)",
                rows.iter().filter(|row| row.listed == 0).count()
            )) && caption.contains(&format!("inside cell ({}, {})", last.cell[0], last.cell[1])),
            "{preset:?}: {caption}"
        );
    }
}

/// The lesson's own ray makes its points: a primitive hit beyond its cell does not stop the
/// walk, the mailbox saves its second test, and it stops in the cell holding the hit.
#[test]
fn the_lessons_ray_is_hit_beyond_its_cell_and_then_in_the_next() {
    let mut lesson = GridLesson::new(lesson_text("18-uniform-grid.ron"));
    settle(&mut lesson);
    let trace = lesson.trace().expect("traced").clone();
    let hit = trace.hit.expect("the ray hits the long segment");
    assert_eq!(hit.primitive, 12);
    let rows = lesson.rows();
    let tested_in = rows
        .iter()
        .find(|row| {
            trace.steps[row.entered_at..]
                .iter()
                .take_while(|step| !matches!(step, Step::GridStepped { .. }))
                .any(|step| matches!(step, Step::PrimitiveTested { primitive: 12, .. }))
        })
        .expect("tested");
    assert!(
        hit.t > tested_in.t_far,
        "hit beyond the cell it was tested in"
    );
    let last = rows.last().expect("cells");
    assert!(last.t_near <= hit.t && hit.t <= last.t_far);
    assert!(
        trace
            .steps
            .iter()
            .any(|step| matches!(step, Step::PrimitiveSkipped { primitive: 12 }))
    );
    assert!(rows.iter().filter(|row| row.listed == 0).count() >= 2);
}

/// The slider sets the cells along the longer side (1 to the most); the density rule's button
/// gives the rule's; the curve is measured at every size, and is dearest with one cell
/// (every primitive tested) and at the most cells (every cell stepped).
#[test]
fn the_cell_size_is_chosen_and_the_cost_is_measured_at_every_size() {
    let mut lesson = GridLesson::new(lesson_text("18-uniform-grid.ron"));
    settle(&mut lesson);
    let shapes = lesson
        .stage()
        .scene
        .flat()
        .expect("2D")
        .scene
        .shapes
        .clone();
    let along = |lesson: &GridLesson| {
        let cells = lesson
            .tree()
            .expect("built")
            .built
            .grid_cells()
            .expect("a grid")
            .resolution;
        cells[0].max(cells[1])
    };
    assert_eq!(along(&lesson), rule_along(&shapes));
    for asked in [1, 9, MOST_ALONG] {
        lesson.set_cells_along(Some(asked));
        settle(&mut lesson);
        assert_eq!(along(&lesson), asked);
        assert!(lesson.trace().is_some_and(|trace| trace.frames() > 0));
    }
    lesson.set_cells_along(None);
    settle(&mut lesson);
    assert_eq!(along(&lesson), rule_along(&shapes));
    let curve = lesson.curve().expect("measured").clone();
    assert_eq!(curve.points.len(), MOST_ALONG as usize);
    let first = curve.points[0];
    assert_eq!(first.cells_per_ray, 1.0);
    assert_eq!(first.tests_per_ray, shapes.shapes.len() as f64);
    let cheapest = curve.cheapest().expect("points");
    let last = curve.points.last().expect("points");
    assert!(
        cheapest.cost_per_ray < first.cost_per_ray && cheapest.cost_per_ray < last.cost_per_ray
    );
    assert!(
        last.cells_per_ray > 5.0 * cheapest.cells_per_ray,
        "{last:?} {cheapest:?}"
    );
}

/// Lesson 18 at work, on its scene and in the stadium.
#[test]
fn the_grid_lesson_matches_its_snapshots() {
    let mut harness = lesson_harness_3d(GridLesson::new(lesson_text("18-uniform-grid.ron")));
    harness.run();
    settle(harness.state_mut());
    harness.state_mut().stage_mut().timeline.shown = 11;
    harness.run();
    let mut failures = Vec::new();
    if let Err(error) = harness.try_snapshot("grid_walk") {
        failures.push(error.to_string());
    }
    assert!(harness.state_mut().show_named("teapot in a stadium"));
    settle(harness.state_mut());
    let frames = harness.state().stage().timeline.len;
    harness.state_mut().stage_mut().timeline.shown = frames / 2;
    harness.run();
    if let Err(error) = harness.try_snapshot("grid_walk_stadium") {
        failures.push(error.to_string());
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Lesson 19's walk is lesson 18's, cell for cell (the same cells, parts and tests), each
/// cell looked up first; a lookup's reads, drawn in the table, run from the cell's home place
/// to where it is found or to an empty place.
#[test]
fn the_hashed_walk_is_the_dense_walk_with_a_lookup_a_cell() {
    use accelviz_app::lessons::hashing::{HashLesson, START_ALONG};
    use accelviz_app::views::grid_walk::CellChoice;
    let mut hashed = HashLesson::new(lesson_text("19-hashing.ron"));
    settle(&mut hashed);
    let mut dense = GridLesson::new(lesson_text("19-hashing.ron"));
    dense.set_cells_along(Some(START_ALONG));
    settle(&mut dense);
    let cells = |rows: &[accelviz_app::views::grid_walk::WalkRow]| {
        rows.iter()
            .map(|row| (row.cell, row.t_near, row.t_far, row.tests))
            .collect::<Vec<_>>()
    };
    assert_eq!(cells(hashed.rows()), cells(dense.rows()));
    assert!(
        hashed
            .rows()
            .iter()
            .all(|row| row.probes.is_some_and(|probes| probes >= 1))
    );
    // Most of the ray's cells are empty: looked up and not found.
    assert!(hashed.rows().iter().filter(|row| row.listed == 0).count() >= 3);
    // Every lookup, frame by frame.
    let frames = hashed.stage().timeline.len;
    let mut lookups = 0;
    for frame in 1..=frames {
        hashed.stage_mut().timeline.shown = frame;
        hashed.update();
        let Some(lookup) = hashed.lookup() else {
            continue;
        };
        lookups += 1;
        let tree = hashed.tree().expect("built");
        let table = tree.built.hashed_cells().expect("hashed");
        assert_eq!(lookup.found, table.place_of(lookup.cell).is_some());
        let caption = hashed.caption().expect("caption");
        assert!(
            caption.contains(&format!("hashes to place {}", lookup.home)),
            "{caption}"
        );
    }
    assert_eq!(lookups, hashed.rows().len());
    // A table at its fullest collides more, and reads more a lookup, than the default.
    let roomy = hashed
        .tree()
        .expect("built")
        .built
        .hashed_cells()
        .expect("hashed")
        .clone();
    hashed.choose(CellChoice {
        along: Some(START_ALONG),
        places: Some(roomy.occupied() + 1),
    });
    settle(&mut hashed);
    let full = hashed
        .tree()
        .expect("built")
        .built
        .hashed_cells()
        .expect("hashed")
        .clone();
    assert_eq!(full.buckets.len(), roomy.occupied() + 1);
    assert!(full.collisions > roomy.collisions);
    let reads = |lesson: &HashLesson| {
        lesson
            .rows()
            .iter()
            .filter_map(|row| row.probes)
            .sum::<u32>()
    };
    assert!(reads(&hashed) > hashed.rows().len() as u32);
}

/// Memory is weighed at every cell size: the dense grid grows with the cells, the table with
/// the cells that hold something, so it pays only from some size on, in the stadium sooner
/// than in the lesson's scene.
#[test]
fn the_table_is_smaller_than_the_dense_grid_only_once_most_cells_are_empty() {
    use accelviz_app::lessons::hashing::HashLesson;
    let mut lesson = HashLesson::new(lesson_text("19-hashing.ron"));
    settle(&mut lesson);
    let scene = lesson.memory().expect("weighed").clone();
    assert_eq!(scene.points.len(), MOST_ALONG as usize);
    let first = scene.points[0];
    assert!(first.hashed_bytes > first.dense_bytes, "{first:?}");
    let from = scene.hashing_pays_from().expect("pays at some size");
    let point = *scene
        .points
        .iter()
        .find(|point| point.along == from)
        .expect("measured");
    assert!(point.hashed_bytes < point.dense_bytes);
    assert!(point.occupied * 4 < point.cells, "{point:?}");
    assert!(lesson.show_named("teapot in a stadium"));
    settle(&mut lesson);
    let stadium = lesson.memory().expect("weighed").clone();
    let stadium_from = stadium.hashing_pays_from().expect("pays at some size");
    assert!(stadium_from > 1, "{stadium_from}");
}

/// Lesson 19 at work: a lookup part-way through the walk, and the stadium.
#[test]
fn the_hashing_lesson_matches_its_snapshots() {
    use accelviz_app::lessons::hashing::HashLesson;
    let mut harness = lesson_harness_3d(HashLesson::new(lesson_text("19-hashing.ron")));
    harness.run();
    settle(harness.state_mut());
    // The lookup of the fourth cell the walk passes.
    let at = harness.state().rows()[3].entered_at;
    let frame = (1..=harness.state().stage().timeline.len)
        .find(|&frame| harness.state().trace().expect("traced").shown(frame).len() >= at)
        .expect("a frame");
    harness.state_mut().stage_mut().timeline.shown = frame;
    harness.run();
    assert!(
        harness.state().lookup().is_some(),
        "frame {frame} is a lookup"
    );
    let mut failures = Vec::new();
    if let Err(error) = harness.try_snapshot("hash_lookup") {
        failures.push(error.to_string());
    }
    assert!(harness.state_mut().show_named("teapot in a stadium"));
    settle(harness.state_mut());
    harness.run();
    if let Err(error) = harness.try_snapshot("hash_stadium") {
        failures.push(error.to_string());
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Lesson 20's build steps are the builder's own: every node started, then cut into four or
/// made a leaf, each cut at its cell's middle; the tree at the end is the one traced.
#[test]
fn the_quadtree_build_is_stepped_from_the_builders_report() {
    use accelviz_app::lessons::quadtree::{Mode, QuadtreeLesson, quadrant_path};
    use accelviz_core::BuildStep;
    let mut lesson = QuadtreeLesson::new(lesson_text("20-quadtree.ron"));
    settle(&mut lesson);
    let recorded = lesson.recorded().expect("built").clone();
    let facts = &recorded.tree().built.facts;
    assert_eq!(lesson.stage().timeline.len, recorded.steps.len());
    let (mut started, mut cut, mut leaves) = (0, 0, 0);
    for step in &recorded.steps {
        match *step {
            BuildStep::NodeStarted { .. } => started += 1,
            BuildStep::Split { node, children, .. } => {
                cut += 1;
                assert_eq!(children.len(), 4);
                let cell = facts.bounds[node as usize];
                for (axis, position) in recorded.tree().built.cuts(node) {
                    let middle = 0.5 * (cell.min[axis] + cell.max[axis]);
                    assert!((position - middle).abs() < 1e-9);
                }
            }
            BuildStep::Leaf { .. } => leaves += 1,
            _ => {}
        }
    }
    assert_eq!(started, facts.node_count());
    assert_eq!(cut + leaves, started);
    assert!(cut >= 2, "the lesson's scene is cut more than once");
    // Names follow the quadrants: the root's children are SW, SE, NW, NE.
    let first = facts.children[0].expect("the root is cut").first;
    let names: Vec<String> = (first..first + 4)
        .map(|node| quadrant_path(facts, node))
        .collect();
    assert_eq!(names, ["SW", "SE", "NW", "NE"]);
    // Every build caption names its cell; the traversal steps through the core's trace.
    for frame in 1..=recorded.steps.len() {
        lesson.stage_mut().timeline.shown = frame;
        lesson.update();
        assert!(
            lesson
                .caption()
                .expect("caption")
                .to_lowercase()
                .contains("cell")
        );
    }
    lesson.set_mode(Mode::Traverse);
    settle(&mut lesson);
    let trace = lesson.trace().expect("traced").clone();
    assert_eq!(lesson.stage().timeline.len, trace.frames());
    assert!(
        trace
            .steps
            .iter()
            .any(|step| matches!(step, Step::ChildrenOrdered { tested: 0, .. }))
    );
    let comparison = &lesson.recorded().expect("built").comparison;
    assert_eq!(comparison.trees.len(), 2);
    assert!(comparison.trees[1].built.tree.family() == accelviz_core::Family::Kd);
}

/// Lesson 20 at work: the build part-way, the traversal at an ordering step.
#[test]
fn the_quadtree_lesson_matches_its_snapshots() {
    use accelviz_app::lessons::quadtree::{Mode, QuadtreeLesson};
    let mut harness = lesson_harness_3d(QuadtreeLesson::new(lesson_text("20-quadtree.ron")));
    harness.run();
    settle(harness.state_mut());
    let steps = harness.state().stage().timeline.len;
    harness.state_mut().stage_mut().timeline.shown = steps / 2;
    harness.run();
    let mut failures = Vec::new();
    if let Err(error) = harness.try_snapshot("quadtree_build") {
        failures.push(error.to_string());
    }
    harness.state_mut().set_mode(Mode::Traverse);
    settle(harness.state_mut());
    let trace = harness.state().trace().expect("traced").clone();
    let ordering = (1..=trace.frames())
        .filter(|&frame| {
            matches!(
                trace.frame(frame).last(),
                Some(Step::ChildrenOrdered { .. })
            )
        })
        .nth(1)
        .expect("a second ordering step");
    harness.state_mut().stage_mut().timeline.shown = ordering;
    harness.run();
    if let Err(error) = harness.try_snapshot("quadtree_traversal") {
        failures.push(error.to_string());
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Lessons 12 and 14 offer the grid and the octree: a grid shown by the cells that hold
/// something (a voxel teapot), then the cells its walk passes; an octree by its three middle
/// planes a node; heat maps of both; node names that say what they are.
#[test]
fn grids_and_octrees_in_3d_match_their_snapshots() {
    use accelviz_app::lessons::heat::HeatLesson;
    use accelviz_app::lessons::mesh_tree::MeshTreeLesson;
    let mut failures = Vec::new();
    for (name, structure) in [("grid_3d", "grid:uniform"), ("octree_3d", "octree")] {
        let mut harness = lesson_harness_3d(MeshTreeLesson::new(lesson_text("12-mesh-bvh.ron")));
        harness
            .state_mut()
            .restore("structure", structure)
            .expect("a structure");
        harness.run();
        settle(harness.state_mut());
        harness.run();
        let lesson = harness.state();
        let grid = structure.starts_with("grid");
        assert_eq!(
            (lesson.show_inner, lesson.show_leaves, lesson.show_planes),
            (false, grid, !grid),
            "{structure}: a grid by its cells, an octree by its planes"
        );
        if let Err(error) = harness.try_snapshot(format!("{name}_cells")) {
            failures.push(error.to_string());
        }
        // A ray across the top of the teapot to its lid, stepped to its end.
        harness.state_mut().pick(
            glam::DVec3::new(-3.0, 1.5, 0.05),
            glam::DVec3::new(1.0, 0.0, 0.0),
        );
        harness.run();
        settle(harness.state_mut());
        let frames = harness.state().stage().timeline.len;
        harness.state_mut().stage_mut().timeline.shown = frames;
        harness.run();
        let caption = harness.state().caption().expect("a caption");
        let named = if grid { "cell (" } else { "octant " };
        assert!(
            (1..=frames).any(|frame| {
                harness.state_mut().stage_mut().timeline.shown = frame;
                harness
                    .state()
                    .caption()
                    .is_some_and(|caption| caption.contains(named))
            }),
            "{structure}: {caption}"
        );
        harness.state_mut().stage_mut().timeline.shown = frames;
        harness.run();
        if let Err(error) = harness.try_snapshot(format!("{name}_ray")) {
            failures.push(error.to_string());
        }
    }
    for (name, structure) in [
        ("heat_3d_grid", "grid:uniform"),
        ("heat_3d_octree", "octree"),
    ] {
        let mut harness = lesson_harness_3d(HeatLesson::new(lesson_text("14-heat-maps.ron")));
        harness
            .state_mut()
            .restore("structure", structure)
            .expect("a structure");
        for _ in 0..400 {
            harness.run();
            if harness.state().building().is_none() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        harness.run();
        if let Err(error) = harness.try_snapshot(name) {
            failures.push(error.to_string());
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The shapes the text names are numbered on the canvas: lessons 18 to 20 say "the closest
/// hit is primitive 12", and the canvas now writes 12 beside it (it numbered none).
#[test]
fn the_primitive_a_grid_lesson_names_is_numbered_on_its_canvas() {
    use accelviz_app::lessons::hashing::HashLesson;
    use accelviz_app::lessons::quadtree::QuadtreeLesson;
    fn check<L: Lesson + 'static>(lesson: L, name: &str) {
        let mut harness = lesson_harness_3d(lesson);
        for _ in 0..4 {
            harness.run();
        }
        let len = harness.state().stage().timeline.len;
        harness.state_mut().stage_mut().timeline.shown = len;
        harness.run();
        harness.run();
        let caption = harness.state().caption().unwrap_or_default();
        let named: Vec<String> = caption
            .split("primitive ")
            .skip(1)
            .filter_map(|rest| {
                let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
                (!digits.is_empty()).then_some(digits)
            })
            .collect();
        assert!(
            !named.is_empty(),
            "{name}: the last step names a primitive: {caption}"
        );
        let drawn = drawn_texts(&harness);
        for number in named {
            assert!(
                drawn.contains(&number),
                "{name}: '{caption}' names primitive {number}, not numbered on the canvas"
            );
        }
    }
    check(
        GridLesson::new(lesson_text("18-uniform-grid.ron")),
        "lesson 18",
    );
    check(HashLesson::new(lesson_text("19-hashing.ron")), "lesson 19");
    let mut quadtree = QuadtreeLesson::new(lesson_text("20-quadtree.ron"));
    quadtree.set_mode(accelviz_app::lessons::quadtree::Mode::Traverse);
    check(quadtree, "lesson 20");
}

/// The texts the last frame drew.
fn drawn_texts<S>(harness: &egui_kittest::Harness<'_, S>) -> Vec<String> {
    fn walk(shape: &egui::Shape, found: &mut Vec<String>) {
        match shape {
            egui::Shape::Text(text) => found.push(text.galley.job.text.clone()),
            egui::Shape::Vec(shapes) => shapes.iter().for_each(|shape| walk(shape, found)),
            _ => {}
        }
    }
    let mut found = Vec::new();
    for clipped in &harness.output().shapes {
        walk(&clipped.shape, &mut found);
    }
    found
}
