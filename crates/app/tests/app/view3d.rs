//! The 3D lessons drawn on the software adapter (snapshots named `*_3d*`), and what they
//! trace: a clicked pixel's recorded hit is brute force's.

use crate::common;

use accelviz_app::lesson::Lesson;
use accelviz_app::lessons::heat::HeatLesson;
use accelviz_app::lessons::mesh_tree::MeshTreeLesson;
use accelviz_app::lessons::slab3d::Slab3dLesson;
use accelviz_app::view3d::HiddenEdges;
use accelviz_core::heatmap::Counter;
use accelviz_core::{Counters, Order, Ray, TraceOptions, TraversalStacks, brute_force};
use accelviz_scene::rays::{RayKind, pixel_secondary_rays};
use common::{lesson_harness_3d, lesson_text};
use glam::DVec3;

fn mesh_lesson() -> MeshTreeLesson {
    MeshTreeLesson::new(lesson_text("12-mesh-bvh.ron"))
}

#[test]
fn the_mesh_and_its_boxes_at_two_depth_ranges_with_and_without_xray() {
    let mut harness = lesson_harness_3d(mesh_lesson());
    harness.run();
    let mut failures = Vec::new();
    let mut check = |harness: &mut egui_kittest::Harness<'_, MeshTreeLesson>, name: &str| {
        harness.run();
        if let Err(error) = harness.try_snapshot(name) {
            failures.push(error.to_string());
        }
    };
    // A big tree opens on its first two levels; every depth is asked for.
    assert_eq!(harness.state().depth_range, (0, 1));
    harness.state_mut().depth_range = (0, usize::MAX);
    check(&mut harness, "mesh_3d_all_depths_xray");
    harness.state_mut().depth_range = (3, 4);
    check(&mut harness, "mesh_3d_depths_3_4_xray");
    harness.state_mut().hidden_edges = HiddenEdges::Hidden;
    check(&mut harness, "mesh_3d_depths_3_4_hidden");
    // The triangles' edges, without boxes.
    harness.state_mut().show_inner = false;
    harness.state_mut().show_leaves = false;
    harness.state_mut().wireframe = true;
    check(&mut harness, "mesh_3d_wireframe");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_clicked_pixels_traversal_half_way() {
    let mut harness = lesson_harness_3d(mesh_lesson());
    harness.run();
    let (center, _) = harness.state().tree().expect("built").build.sphere;
    // A ray from the upper left front into the teapot's body.
    let origin = center + DVec3::new(-2.0, 2.5, 4.0);
    harness.state_mut().pick(origin, center - origin);
    harness.run();
    let trace = harness.state().trace().expect("traced");
    let frames = trace.frames();
    assert!(trace.hit.is_some(), "the ray hits the teapot");
    harness.state_mut().stage_mut().timeline.shown = frames / 2;
    // Orbit a quarter turn so the ray is seen from the side.
    harness.state_mut().view.orbit.yaw += 70.0;
    harness.run();
    harness.snapshot("mesh_3d_traversal_half_way");
}

#[test]
fn a_click_traces_through_its_pixels_centre() {
    let mut harness = lesson_harness_3d(mesh_lesson());
    harness.run();
    let rect = harness.state().view.rect().expect("drawn");
    // Where a pointer lands: on a pixel's corner (the harness has one pixel a point).
    let at = egui::pos2(rect.min.x + 301.0, rect.min.y + 207.0);
    for event in [
        egui::Event::PointerMoved(at),
        egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed: true,
            modifiers: egui::Modifiers::NONE,
        },
        egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed: false,
            modifiers: egui::Modifiers::NONE,
        },
    ] {
        harness.event(event);
        harness.run();
    }
    let (pixel, ray) = harness.state().picked().expect("a click picks a ray");
    let pixel = pixel.expect("a clicked pixel");
    assert_eq!((pixel.column, pixel.row), (301, 207));
    assert_eq!(
        (pixel.width, pixel.height),
        (rect.width().round() as u32, rect.height().round() as u32)
    );
    let tree = harness.state().tree().expect("built").clone();
    let camera = harness
        .state()
        .view
        .orbit
        .camera(tree.build.sphere.0, tree.build.sphere.1);
    // The very ray the heat maps and `bench --camera` trace for that pixel.
    let expected: Ray<DVec3> = camera
        .pixel_ray(301, 207, pixel.width as usize, pixel.height as usize)
        .expect("a ray");
    assert_eq!(
        (ray.origin, ray.direction),
        (expected.origin, expected.direction)
    );
    // Its link opens the same: the ray, and the node the click selected (lit orange), which
    // a link left at the root.
    let selected = harness.state().selected;
    assert_ne!(selected, Some(0), "the click selects the box under it");
    let values = harness.state().share();
    let mut shared = lesson_harness_3d(mesh_lesson());
    for (key, value) in &values {
        shared.state_mut().restore(key, value).expect("restores");
    }
    shared.run();
    assert_eq!(shared.state().selected, selected);
    let (_, shared_ray) = shared.state().picked().expect("the ray");
    assert_eq!(
        (shared_ray.origin, shared_ray.direction),
        (ray.origin, ray.direction)
    );
}

#[test]
fn a_clicked_pixels_recorded_hit_is_brute_forces() {
    let mut harness = lesson_harness_3d(mesh_lesson());
    harness.run();
    let tree = harness.state().tree().expect("built").clone();
    let (center, radius) = tree.build.sphere;
    let camera = harness.state().view.orbit.camera(center, radius);
    let (width, height) = (24, 18);
    let mut hits = 0;
    for order in [Order::NearFirst, Order::FileOrder] {
        harness.state_mut().order = order;
        for row in 0..height {
            for column in 0..width {
                let (origin, direction) =
                    camera.ray_through(column as f64 + 0.5, row as f64 + 0.5, width, height);
                harness.state_mut().pick(origin, direction);
                // What a frame does first; drawing is not needed here.
                harness.state_mut().update();
                let trace = harness.state().trace().expect("traced");
                let ray = Ray::try_new(origin, direction).expect("a ray");
                let expected = brute_force(
                    &tree.triangles,
                    &ray,
                    &TraceOptions::default(),
                    &mut accelviz_core::NoObserver,
                );
                assert_eq!(
                    trace.hit.map(|hit| hit.primitive),
                    expected.map(|hit| hit.primitive),
                    "pixel ({column}, {row}), {order:?}"
                );
                hits += usize::from(expected.is_some());
            }
        }
    }
    assert!(hits > 50, "{hits} pixels hit the teapot");
}

fn heat_lesson() -> HeatLesson {
    HeatLesson::new(lesson_text("14-heat-maps.ron"))
}

/// Runs frames until the heat maps are whole.
fn finish_heat_maps(harness: &mut egui_kittest::Harness<'_, HeatLesson>) {
    harness.run_steps(2);
    harness.state().job().expect("a job started").finish();
    harness.run_steps(2);
    let maps = harness.state().maps().expect("maps");
    assert_eq!(maps.progress, 1.0);
}

#[test]
fn heat_maps_near_first_file_order_and_their_difference() {
    let mut harness = lesson_harness_3d(heat_lesson());
    finish_heat_maps(&mut harness);
    harness.snapshot("heat_3d_nodes");
    harness.state_mut().counter = Counter::Prims;
    harness.run_steps(2);
    harness.snapshot("heat_3d_prims");
}

#[test]
fn heat_maps_of_packets_on_an_eight_wide_tree() {
    let mut harness = lesson_harness_3d(heat_lesson());
    let structure = harness
        .state()
        .structure
        .with_width(accelviz_core::Width::Eight);
    harness.state_mut().structure = structure;
    harness.state_mut().packets = true;
    harness.state_mut().counter = Counter::Boxes;
    finish_heat_maps(&mut harness);
    let key = *harness.state().job().expect("job").key();
    assert_eq!(key.tile, 8);
    harness.snapshot("heat_3d_packets_bvh8");
}

#[test]
fn heat_maps_of_shadow_rays_count_the_clis_rays_from_each_pixels_hit() {
    let mut harness = lesson_harness_3d(heat_lesson());
    harness.state_mut().ray_kind = RayKind::Shadow;
    harness.state_mut().packets = true;
    finish_heat_maps(&mut harness);
    let tree = harness.state().tree().expect("built").clone();
    let key = *harness.state().job().expect("job").key();
    assert_eq!(
        (key.ray_kind, key.tile),
        (RayKind::Shadow, 1),
        "one ray at a time"
    );
    let maps = harness.state().maps().expect("maps");
    let bounds = tree.mesh.bounds();
    for (order, map) in [Order::NearFirst, Order::FileOrder]
        .into_iter()
        .zip(&maps.maps)
    {
        // Each pixel: its camera ray's hit, then the shadow ray from there traced any-hit, as
        // the CLI's `heatmap --ray-kind shadow` does.
        let options = TraceOptions {
            order,
            query: RayKind::Shadow.default_query(),
            ..TraceOptions::default()
        };
        let mut stacks = TraversalStacks::default();
        let mut missed_pixels_cost = 0;
        for row in 0..key.height {
            for column in 0..key.width {
                let ray = key
                    .camera
                    .pixel_ray::<DVec3>(column, row, key.width, key.height)
                    .expect("a ray");
                let cost = map.at(column, row).expect("a pixel");
                // The camera ray's hit by the tree (brute force over 20k triangles for every
                // pixel took a minute; other tests hold the tree to brute force).
                let Some(hit) = tree.build.built.tree.trace(
                    &tree.triangles,
                    &ray,
                    &TraceOptions::default(),
                    &mut stacks,
                    &mut accelviz_core::NoObserver,
                ) else {
                    missed_pixels_cost += cost.nodes;
                    continue;
                };
                let mut counters = Counters::default();
                for shadow in pixel_secondary_rays(RayKind::Shadow, &tree.mesh, &bounds, &ray, hit)
                {
                    tree.build.built.tree.trace(
                        &tree.triangles,
                        &shadow,
                        &options,
                        &mut stacks,
                        &mut counters,
                    );
                }
                assert_eq!(
                    cost.nodes, counters.nodes_visited as u32,
                    "{order:?} {column},{row}"
                );
                assert_eq!(
                    cost.prims, counters.primitive_tests as u32,
                    "{order:?} {column},{row}"
                );
            }
        }
        assert_eq!(
            missed_pixels_cost, 0,
            "a pixel that sees nothing casts no shadow ray"
        );
        assert!(map.summary(Counter::Nodes).total > 0);
    }
    harness.snapshot("heat_3d_shadow");
}

#[test]
fn heat_map_totals_are_the_counters_of_the_same_rays() {
    let mut harness = lesson_harness_3d(heat_lesson());
    finish_heat_maps(&mut harness);
    let tree = harness.state().tree().expect("built").clone();
    let key = *harness.state().job().expect("job").key();
    let maps = harness.state().maps().expect("maps");
    assert!(
        key.width > 100 && key.height > 100,
        "{}x{}",
        key.width,
        key.height
    );
    for (order, map) in [Order::NearFirst, Order::FileOrder]
        .into_iter()
        .zip(&maps.maps)
    {
        let options = TraceOptions {
            order,
            ..TraceOptions::default()
        };
        let mut summed = Counters::default();
        let mut stacks = TraversalStacks::default();
        for row in 0..key.height {
            for column in 0..key.width {
                let ray = key
                    .camera
                    .pixel_ray::<DVec3>(column, row, key.width, key.height)
                    .expect("a ray");
                // The triangles in file order: the leaf-ordered copy the maps use must not
                // change what is counted.
                tree.build.built.tree.trace(
                    &tree.triangles,
                    &ray,
                    &options,
                    &mut stacks,
                    &mut summed,
                );
            }
        }
        assert_eq!(
            map.summary(Counter::Nodes).total,
            summed.nodes_visited,
            "{order:?}"
        );
        assert_eq!(
            map.summary(Counter::Boxes).total,
            summed.box_tests,
            "{order:?}"
        );
        assert_eq!(
            map.summary(Counter::Prims).total,
            summed.primitive_tests,
            "{order:?}"
        );
    }
    // Clicking a pixel traces its ray: the recorded hit is brute force's.
    let (x, y) = (key.width / 2, key.height / 2);
    harness.state_mut().pick_pixel(x, y, Order::FileOrder);
    harness.state_mut().update();
    let ray = key
        .camera
        .pixel_ray::<DVec3>(x, y, key.width, key.height)
        .expect("ray");
    let expected = brute_force(
        &tree.triangles,
        &ray,
        &TraceOptions::default(),
        &mut accelviz_core::NoObserver,
    );
    let trace = harness.state().trace().expect("traced");
    assert!(expected.is_some(), "the centre pixel sees the mesh");
    assert_eq!(
        trace.hit.map(|hit| hit.primitive),
        expected.map(|hit| hit.primitive)
    );
}

fn slab_lesson() -> Slab3dLesson {
    Slab3dLesson::new(lesson_text("11-slab-3d.ron"))
}

#[test]
fn the_slab_test_in_3d_step_by_step_and_its_edge_cases() {
    let mut harness = lesson_harness_3d(slab_lesson());
    harness.run();
    let mut failures = Vec::new();
    for (shown, name) in [(3, "slab_3d_three_slabs"), (6, "slab_3d_verdict")] {
        harness.state_mut().stage_mut().timeline.shown = shown;
        harness.run();
        if let Err(error) = harness.try_snapshot(name) {
            failures.push(error.to_string());
        }
    }
    // The parallel case: one slab's interval is everything.
    harness.state_mut().use_case(1);
    harness.run();
    let record = harness.state().scene().record().expect("a ray");
    assert_eq!(
        (record.t_near.y, record.t_far.y),
        (f64::NEG_INFINITY, f64::INFINITY)
    );
    assert!(record.hit);
    if let Err(error) = harness.try_snapshot("slab_3d_parallel") {
        failures.push(error.to_string());
    }
    harness.state_mut().use_case(2);
    harness.run();
    let record = harness.state().scene().record().expect("a ray");
    assert!(!record.hit, "parallel outside the y slab misses");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn dragging_the_rays_start_moves_it_and_not_the_camera() {
    let mut harness = lesson_harness_3d(slab_lesson());
    harness.run_steps(2);
    let before = harness.state().scene().origin;
    let orbit = harness.state().view.orbit;
    // Where the last frame drew the ray's start.
    let start = harness
        .state()
        .handle_on_screen(0)
        .expect("the start is drawn");
    let end = start + egui::vec2(40.0, -25.0);
    common::drag(&mut harness, start, end);
    let after = harness.state().scene().origin;
    assert!((after - before).length() > 0.05, "{before} -> {after}");
    assert_eq!(harness.state().view.orbit, orbit, "the camera stayed");
}

#[test]
fn kd_split_planes_clipped_to_their_cells_and_a_selected_cell() {
    let mut harness = lesson_harness_3d(MeshTreeLesson::new(lesson_text("13-kd-3d.ron")));
    harness.run();
    let tree = harness.state().tree().expect("built").clone();
    assert_eq!(
        tree.build.built.structure.family(),
        accelviz_core::Family::Kd
    );
    harness.state_mut().depth_range = (0, 3);
    harness.run();
    let mut failures = Vec::new();
    if let Err(error) = harness.try_snapshot("kd_3d_planes") {
        failures.push(error.to_string());
    }
    // A deeper node selected: its plane lit, its triangles drawn over the mesh.
    let node = tree.build.built.facts.by_depth[5];
    harness.state_mut().selected = Some(node);
    harness.run();
    if let Err(error) = harness.try_snapshot("kd_3d_selected_cell") {
        failures.push(error.to_string());
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A harness's picture (pixels per point 1), as RGBA rows.
#[derive(Clone)]
struct Picture {
    width: u32,
    height: u32,
    rgba: Vec<u8>,
}

impl Picture {
    fn of<State>(harness: &mut egui_kittest::Harness<'_, State>) -> Self {
        let image = harness.render().expect("renders");
        Self {
            width: image.width(),
            height: image.height(),
            rgba: image.into_raw(),
        }
    }

    fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let at = ((y * self.width + x) * 4) as usize;
        [0, 1, 2, 3].map(|c| self.rgba[at + c])
    }

    /// The pixels inside `rect`: (x, y, RGBA).
    fn inside(&self, rect: egui::Rect) -> impl Iterator<Item = (u32, u32, [u8; 4])> + '_ {
        let (x0, y0) = (rect.min.x.ceil() as u32, rect.min.y.ceil() as u32);
        let (x1, y1) = (
            (rect.max.x.floor() as u32).min(self.width),
            (rect.max.y.floor() as u32).min(self.height),
        );
        (y0..y1).flat_map(move |y| (x0..x1).map(move |x| (x, y, self.pixel(x, y))))
    }
}

/// Relative luminance (WCAG) of a picture's pixel, as the contrast test computes it.
fn luminance([r, g, b, _]: [u8; 4]) -> f64 {
    f64::from(accelviz_app::canvas::luminance(egui::Color32::from_rgb(
        r, g, b,
    )))
}

#[test]
fn the_3d_view_is_dark_in_the_dark_theme_and_light_in_the_light_ones() {
    use accelviz_app::lecture::Theme;
    for theme in Theme::ALL {
        let mut harness = lesson_harness_3d(MeshTreeLesson::new(lesson_text("13-kd-3d.ron")));
        harness.ctx.set_visuals(theme.visuals());
        harness.run();
        let rect = harness.state().view.rect().expect("drawn");
        let image = Picture::of(&mut harness);
        // The view's background: its outermost pixels (the teapot sits in the middle).
        let border: Vec<f64> = image
            .inside(rect.shrink(2.0))
            .filter(|&(x, y, _)| {
                let (x, y) = (x as f32, y as f32);
                x < rect.min.x + 8.0
                    || x > rect.max.x - 9.0
                    || y < rect.min.y + 8.0
                    || y > rect.max.y - 9.0
            })
            .map(|(_, _, pixel)| luminance(pixel))
            .collect();
        let background = border.iter().sum::<f64>() / border.len() as f64;
        let all: Vec<f64> = image.inside(rect).map(|(_, _, p)| luminance(p)).collect();
        let mean = all.iter().sum::<f64>() / all.len() as f64;
        eprintln!(
            "{}: background {background:.3}, mean {mean:.3}",
            theme.name()
        );
        if theme == Theme::Dark {
            assert!(
                background < 0.01,
                "dark theme: background luminance {background}"
            );
            assert!(mean < 0.12, "dark theme: the view's mean luminance {mean}");
            harness.snapshot("kd_3d_dark");
        } else {
            assert!(
                background > 0.8,
                "{}: background {background}",
                theme.name()
            );
        }
    }
}

#[test]
fn a_selected_kd_cell_lights_its_triangles_and_its_plane() {
    let mut harness = lesson_harness_3d(MeshTreeLesson::new(lesson_text("13-kd-3d.ron")));
    harness.run();
    let tree = harness.state().tree().expect("built").clone();
    let rect = harness.state().view.rect().expect("drawn");
    let before = Picture::of(&mut harness);
    // Every inner node two levels down (the findings' LL among them), with planes shown and not.
    let facts = &tree.build.built.facts;
    let nodes: Vec<u32> = facts
        .by_depth
        .iter()
        .copied()
        .filter(|&node| facts.depth[node as usize] == 2 && tree.build.built.plane(node).is_some())
        .collect();
    assert!(!nodes.is_empty());
    for show_planes in [true, false] {
        harness.state_mut().show_planes = show_planes;
        harness.state_mut().selected = Some(0);
        harness.run();
        let before = if show_planes {
            before.clone()
        } else {
            Picture::of(&mut harness)
        };
        for &node in &nodes {
            harness.state_mut().selected = Some(node);
            harness.run();
            let after = Picture::of(&mut harness);
            let (axis, _) = tree.build.built.plane(node).expect("inner");
            let axis_color = accelviz_app::canvas::palette::AXES[axis];
            let (mut bluer, mut in_axis_color) = (0, 0);
            for (x, y, pixel) in after.inside(rect) {
                let old = before.pixel(x, y);
                let blueness = |[r, _, b, _]: [u8; 4]| i32::from(b) - i32::from(r);
                // The highlight's blue, lit or seen through the surface.
                if blueness(pixel) - blueness(old) > 30 {
                    bluer += 1;
                }
                let near = |p: [u8; 4]| {
                    (0..3)
                        .map(|c| (i32::from(p[c]) - i32::from(axis_color.to_array()[c])).abs())
                        .max()
                        .unwrap_or(0)
                        < 24
                };
                if near(pixel) && !near(old) {
                    in_axis_color += 1;
                }
            }
            let label = tree.node_name(node);
            eprintln!(
                "node {label} (planes {show_planes}): {bluer} pixels bluer, {in_axis_color} in the plane's colour"
            );
            assert!(
                bluer > 400,
                "node {label}: {bluer} pixels lit by its triangles"
            );
            assert!(
                in_axis_color > 100,
                "node {label}: {in_axis_color} pixels of its plane's outline"
            );
        }
    }
}

/// A file dropped onto the window, as eframe hands it over on the desktop.
#[derive(Debug)]
struct DroppedPath(std::path::PathBuf);

impl egui::DroppedFile for DroppedPath {
    fn path(&self) -> &std::path::Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|error| error.to_string())
    }
}

#[test]
fn a_malformed_obj_leaves_the_app_running_with_the_message_and_the_mesh_kept() {
    let mut harness = common::app_harness();
    let titles = harness.state().titles();
    harness.state_mut().selected = titles
        .iter()
        .position(|title| title.contains("real mesh"))
        .expect("lesson 12");
    harness.run();
    let broken = "v 0 0 0\nv 1 0 0\nvn 0 1\nf 1 2 3\n";
    assert!(!harness.state_mut().open_scene_text("broken.obj", broken));
    harness.run();
    use egui_kittest::kittest::Queryable;
    assert!(
        harness
            .query_by_label_contains("broken.obj:3: a normal needs 3 numbers, found 2")
            .is_some(),
        "the message names the file and the line"
    );
    assert!(
        harness.query_by_label_contains("teapot: ").is_some(),
        "the teapot stays"
    );

    // A good OBJ dropped onto the window opens.
    let dir = std::env::temp_dir().join(format!("accelviz-drop-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("tetrahedron.obj");
    std::fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .expect("written");
    harness
        .input_mut()
        .dropped_files
        .push(std::sync::Arc::new(DroppedPath(path)));
    harness.run_steps(3);
    assert!(
        harness
            .query_by_label_contains("opened tetrahedron.obj")
            .is_some(),
        "the dropped file opened"
    );
    assert!(
        harness
            .query_by_label_contains("tetrahedron.obj: 4 triangles")
            .is_some()
    );
    std::fs::remove_dir_all(&dir).expect("removed");
}

/// A PNG's size and how many colours it has.
fn decode_png(bytes: &[u8]) -> (u32, u32, usize) {
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut pixels = vec![0; reader.output_buffer_size().expect("a size")];
    let info = reader.next_frame(&mut pixels).expect("a frame");
    let colours: std::collections::HashSet<&[u8]> = pixels[..info.buffer_size()]
        .chunks_exact(info.color_type.samples())
        .collect();
    (info.width, info.height, colours.len())
}

#[test]
fn the_view_and_a_heat_map_save_as_png() {
    use egui_kittest::kittest::Queryable;
    let mut harness = lesson_harness_3d(mesh_lesson());
    harness.run();
    harness.get_by_label("save view as PNG").click();
    harness.run_steps(2);
    let (name, bytes) = harness
        .state_mut()
        .take_export()
        .expect("an export")
        .expect("a picture");
    assert_eq!(name, "view.png");
    let (width, height, colours) = decode_png(&bytes);
    assert!(width > 500 && height > 400, "{width}x{height}");
    assert!(
        colours > 50,
        "the picture has the mesh and its boxes: {colours} colours"
    );

    let mut harness = lesson_harness_3d(heat_lesson());
    finish_heat_maps(&mut harness);
    harness
        .get_all_by_label("save PNG")
        .next()
        .expect("a map's button")
        .click();
    harness.run_steps(2);
    let (name, bytes) = harness
        .state_mut()
        .take_export()
        .expect("an export")
        .expect("a picture");
    assert_eq!(name, "heat-near-first-nodes.png");
    let key = *harness.state().job().expect("job").key();
    let (width, height, colours) = decode_png(&bytes);
    assert_eq!((width as usize, height as usize), (key.width, key.height));
    assert!(colours > 10, "{colours} colours");
}

/// Lesson 14: a clicked map pixel is marked on the view (a white ring on black around it),
/// and stepping its ray draws the boxes it met, the step's own in the current step's blue.
#[test]
fn a_clicked_heat_map_pixel_is_marked_and_its_steps_draw_boxes() {
    let mut harness = lesson_harness_3d(heat_lesson());
    finish_heat_maps(&mut harness);
    let key = *harness.state().job().expect("job").key();
    let (x, y) = (key.width / 2, key.height / 2);
    harness.state_mut().pick_pixel(x, y, Order::NearFirst);
    harness.run();
    let rect = harness.state().view.rect().expect("drawn");
    let before = Picture::of(&mut harness);
    // The ring (radius 7 points around the pixel's centre: one point a pixel here).
    let at = rect.min
        + egui::vec2(
            (x as f32 + 0.5) / key.width as f32 * rect.width(),
            (y as f32 + 0.5) / key.height as f32 * rect.height(),
        );
    let ring_white = (0..16)
        .filter(|&k| {
            let angle = k as f32 / 16.0 * std::f32::consts::TAU;
            // The ring is 2 points wide: a white pixel within a point of its radius.
            [6.0, 6.5, 7.0, 7.5, 8.0].iter().any(|radius| {
                let p = at + *radius * egui::vec2(angle.cos(), angle.sin());
                let [r, g, b, _] = before.pixel(p.x.round() as u32, p.y.round() as u32);
                r > 200 && g > 200 && b > 200
            })
        })
        .count();
    assert!(
        ring_white >= 12,
        "{ring_white} of 16 points of the marker's ring are white"
    );
    // At the first step that tests a box: that box drawn in the current step's blue.
    let trace = harness.state().trace().expect("traced");
    let frame = (1..=trace.frames())
        .find(|&frame| {
            trace
                .state(frame)
                .current
                .and_then(|step| accelviz_app::trace::step_node(&step))
                .is_some()
        })
        .expect("a step at a node");
    harness.state_mut().stage_mut().timeline.shown = frame;
    harness.run();
    let after = Picture::of(&mut harness);
    let current = accelviz_app::canvas::palette::CURRENT;
    let near = |[r, g, b, _]: [u8; 4]| {
        (i32::from(r) - i32::from(current.r())).abs() < 30
            && (i32::from(g) - i32::from(current.g())).abs() < 30
            && (i32::from(b) - i32::from(current.b())).abs() < 30
    };
    let blue_now = after
        .inside(rect)
        .filter(|&(x, y, pixel)| near(pixel) && !near(before.pixel(x, y)))
        .count();
    assert!(blue_now > 50, "{blue_now} pixels of the current step's box");
}
