//! Lesson 14, "Where the time goes": the cost of every pixel's ray for the view's camera,
//! counted by the core's traversal (nodes visited, box tests or primitive tests), near first
//! and in file order side by side, and their difference. A colour-blind-safe palette with a
//! legend, the maximum and the mean; hover a pixel to read its counts, click it to trace its
//! ray step by step (the same recording and overlay as lesson 12).

use std::sync::Arc;

use accelviz_core::camera::Camera;
use accelviz_core::format::{count, counted, number};
use accelviz_core::heatmap::{
    Counter, HeatMap, difference_colors, difference_colors_on, diverging_on, sequential,
};
use accelviz_core::{CATALOGUE, Family, Order, Ray, Structure, Width};
use accelviz_scene::rays::{RayKind, pixel_secondary_rays};
use egui::{Color32, ColorImage, Rect, Sense, TextureHandle, TextureOptions, Vec2};
use glam::DVec3;

use crate::background::{Cached, Derived, worker_threads};
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::mesh::heat::{HeatJob, HeatKey, HeatMaps, ORDERS, PACKET_TILE};
use crate::mesh::{
    MeshScene, MeshTree, loading_ui, mesh_and_structure_ui, trace_boxes, trace_overlay,
};
use crate::stage::Stage;
use crate::trace::{Trace, options_in};
use crate::view3d::{Content, HiddenEdges, View3d, revision_of};

/// A clicked pixel's ray, in the order it is traced.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Picked {
    /// The pixel's camera ray, or the first of the secondary rays from its hit.
    ray: Ray<DVec3>,
    /// The maps' pixel it goes through.
    pixel: [usize; 2],
    order: Order,
    /// Closest or any hit, as the map traced it.
    query: accelviz_core::Query,
    revision: u64,
}

/// The maps' textures, for the job state and counter they show.
struct Textures {
    made_for: (u64, usize, Counter, bool),
    orders: [TextureHandle; 2],
    difference: TextureHandle,
    /// The sequential maps' scale (both share it) and the difference's.
    scale: u32,
    difference_scale: u64,
}

/// The lesson.
pub struct HeatLesson {
    stage: Stage<MeshScene>,
    /// The view and its camera (the heat maps use the same camera).
    pub view: View3d,
    /// The structure traced.
    pub structure: Structure,
    tree: Derived<crate::mesh::scene::TreeKey, MeshTree>,
    /// Which count the maps show.
    pub counter: Counter,
    /// Whether the camera's rays are traced in packets of 8×8 pixels.
    pub packets: bool,
    /// Whose cost a pixel shows: its camera ray's, or the shadow, AO or bounce rays' from
    /// its camera ray's hit.
    pub ray_kind: RayKind,
    job: Option<HeatJob>,
    /// Counts the jobs started, so textures know which job they show.
    job_serial: u64,
    /// How many bands of the job `maps` holds.
    maps_bands: usize,
    /// What the pixel under the pointer cost, shown above the maps.
    readout: Option<String>,
    /// The heat maps' size in pixels, from the last frame's layout.
    pane_pixels: Option<[usize; 2]>,
    maps: Option<HeatMaps>,
    textures: Option<Textures>,
    picked: Option<Picked>,
    trace: Cached<(u64, u64), Trace>,
    /// A map saved as a PNG, waiting for the app to take it.
    export: Option<crate::view3d::Export>,
}

/// The rays a heat map can show the cost of: the camera's, or the secondary rays from each
/// pixel's hit (the CLI's `heatmap --ray-kind`).
pub const HEAT_RAY_KINDS: [RayKind; 4] = [
    RayKind::Camera,
    RayKind::Shadow,
    RayKind::Ao,
    RayKind::Bounce,
];

/// What a pixel of a map of `kind` shows.
fn ray_kind_about(kind: RayKind) -> &'static str {
    match kind {
        RayKind::Shadow => {
            "the cost of each pixel's shadow ray, from its hit to the light (any hit)"
        }
        RayKind::Ao => {
            "the cost of each pixel's ambient-occlusion rays, a few short ones from its hit (any hit)"
        }
        RayKind::Bounce => {
            "the cost of each pixel's diffuse bounce from its hit (closest hit): incoherent rays"
        }
        _ => "the cost of each pixel's camera ray",
    }
}

impl HeatLesson {
    /// The lesson with its file's mesh and structure.
    pub fn new(text: LessonText) -> Self {
        let scene = MeshScene::of_lesson(&text);
        let structure = text.structure().unwrap_or(CATALOGUE[0].structure);
        Self {
            stage: Stage::with_scene(text, scene),
            view: View3d::default(),
            structure,
            tree: Derived::default(),
            counter: Counter::Nodes,
            packets: false,
            ray_kind: RayKind::Camera,
            job: None,
            job_serial: 0,
            maps_bands: 0,
            readout: None,
            pane_pixels: None,
            maps: None,
            textures: None,
            picked: None,
            trace: Cached::default(),
            export: None,
        }
    }

    /// The heat maps as far as they are made (near first, file order).
    pub fn maps(&self) -> Option<&HeatMaps> {
        self.maps.as_ref()
    }

    /// The job making the maps.
    pub fn job(&self) -> Option<&HeatJob> {
        self.job.as_ref()
    }

    /// The built tree.
    pub fn tree(&self) -> Option<&Arc<MeshTree>> {
        self.tree.get()
    }

    /// The clicked pixel's recorded traversal.
    pub fn trace(&self) -> Option<&Trace> {
        self.trace.get()
    }

    /// Traces pixel `(x, y)` of the heat maps in `order`, as a click there does.
    pub fn pick_pixel(&mut self, x: usize, y: usize, order: Order) {
        let Some(job) = &self.job else { return };
        let key = *job.key();
        let (origin, direction) =
            key.camera
                .ray_through(x as f64 + 0.5, y as f64 + 0.5, key.width, key.height);
        let Ok(camera_ray) = Ray::try_new(origin, direction) else {
            return;
        };
        // A map of secondary rays steps the pixel's first secondary ray: the one whose cost
        // it shows (the camera ray that found its start is not counted).
        let ray = match key.ray_kind {
            RayKind::Camera => Some(camera_ray),
            kind => self.tree.get().and_then(|tree| {
                let hit = tree.build.built.tree.trace(
                    &tree.triangles,
                    &camera_ray,
                    &accelviz_core::TraceOptions::default(),
                    &mut accelviz_core::TraversalStacks::default(),
                    &mut accelviz_core::NoObserver,
                )?;
                pixel_secondary_rays(kind, &tree.mesh, &tree.mesh.bounds(), &camera_ray, hit)
                    .into_iter()
                    .next()
            }),
        };
        let revision = self.picked.map_or(1, |picked| picked.revision + 1);
        self.picked = ray.map(|ray| Picked {
            ray,
            pixel: [x, y],
            order,
            query: key.ray_kind.default_query(),
            revision,
        });
        self.stage.timeline.rewind();
    }

    /// The camera the maps are made with for the current tree.
    fn camera(&self, tree: &MeshTree) -> Camera {
        self.view
            .orbit
            .camera(tree.build.sphere.0, tree.build.sphere.1)
    }

    /// Remakes the textures when the maps or the counter changed.
    fn textures(&mut self, ctx: &egui::Context) {
        let Some(maps) = &self.maps else {
            return;
        };
        let dark = ctx.global_style().visuals.dark_mode;
        let made_for = (self.job_serial, self.maps_bands, self.counter, dark);
        if self
            .textures
            .as_ref()
            .is_some_and(|textures| textures.made_for == made_for)
        {
            return;
        }
        let counter = self.counter;
        let scale = maps
            .maps
            .iter()
            .map(|map| map.summary(counter).max)
            .max()
            .unwrap_or(0)
            .max(1);
        let difference = maps.maps[0].difference(&maps.maps[1], counter);
        let difference_scale = difference
            .iter()
            .map(|d| d.unsigned_abs())
            .max()
            .unwrap_or(0)
            .max(1);
        let image = |map: &HeatMap, colors: Vec<[u8; 4]>| ColorImage {
            size: [map.width, map.height],
            source_size: Vec2::new(map.width as f32, map.height as f32),
            pixels: colors
                .into_iter()
                .map(|[r, g, b, _]| Color32::from_rgb(r, g, b))
                .collect(),
        };
        let near = image(&maps.maps[0], maps.maps[0].colors(counter, scale));
        let file = image(&maps.maps[1], maps.maps[1].colors(counter, scale));
        let diff = image(
            &maps.maps[0],
            difference_colors_on(&difference, difference_scale, dark),
        );
        match &mut self.textures {
            Some(textures) => {
                textures.orders[0].set(near, TextureOptions::NEAREST);
                textures.orders[1].set(file, TextureOptions::NEAREST);
                textures.difference.set(diff, TextureOptions::NEAREST);
                textures.made_for = made_for;
                textures.scale = scale;
                textures.difference_scale = difference_scale;
            }
            None => {
                self.textures = Some(Textures {
                    made_for,
                    orders: [
                        ctx.load_texture("heat near first", near, TextureOptions::NEAREST),
                        ctx.load_texture("heat file order", file, TextureOptions::NEAREST),
                    ],
                    difference: ctx.load_texture("heat difference", diff, TextureOptions::NEAREST),
                    scale,
                    difference_scale,
                });
            }
        }
    }

    fn controls_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            if mesh_and_structure_ui(ui, &mut self.stage.scene, &mut self.structure) {
                self.picked = None;
            }
            ui.separator();
            for counter in Counter::ALL {
                ui.selectable_value(&mut self.counter, counter, counter.label());
            }
            ui.separator();
            for kind in HEAT_RAY_KINDS {
                ui.selectable_value(&mut self.ray_kind, kind, kind.name())
                    .on_hover_text(ray_kind_about(kind));
            }
            ui.separator();
            let secondary = self.ray_kind != RayKind::Camera;
            ui.add_enabled(
                !secondary,
                egui::Checkbox::new(&mut self.packets, "8×8 packets"),
            )
            .on_disabled_hover_text(
                "Secondary rays start at scattered hits, so they are traced one at a time.",
            )
            .on_hover_text(
                "Trace the camera's rays in packets of 8×8 pixels, as renderers do: a wide BVH \
                 visits a node once for all the packet's rays that reach it, and each pixel \
                 shows what that cost its ray. Binary BVHs and kD-trees trace a packet ray by \
                 ray.",
            );
            ui.separator();
            ui.checkbox(&mut self.view.orbit.orthographic, "orthographic");
            if ui.button("reset view").clicked() {
                self.view.reset();
            }
            self.view.save_button(ui);
        });
    }

    /// One heat map pane: title, image, legend. Returns the pixel under the pointer and
    /// whether it was clicked.
    fn map_ui(
        ui: &mut egui::Ui,
        size: Vec2,
        title: &str,
        texture: &TextureHandle,
        map_size: [usize; 2],
        legend: Legend,
        marked: Option<[usize; 2]>,
    ) -> (Option<[usize; 2]>, bool, bool) {
        let mut under = None;
        let mut clicked = false;
        let mut save = false;
        ui.vertical(|ui| {
            ui.set_width(size.x);
            // Wraps (as when scaled up) rather than widen the pane.
            ui.horizontal_wrapped(|ui| {
                ui.label(egui::RichText::new(title).strong());
                save = ui
                    .small_button("save PNG")
                    .on_hover_text("This map as a PNG, one pixel a pixel, for slides")
                    .clicked();
            });
            // One pixel of the map on one pixel of the screen, like the view beside it; smaller
            // only while maps of an earlier, larger pane are shown (the app was just scaled up).
            let pixels_per_point = ui.ctx().pixels_per_point();
            let natural = Vec2::new(map_size[0] as f32, map_size[1] as f32) / pixels_per_point;
            let (fitted, response) = ui.allocate_exact_size(
                fit_within(natural, size - Vec2::new(0.0, pane_text_height(ui))),
                Sense::click(),
            );
            ui.painter().image(
                texture.id(),
                fitted,
                Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                Color32::WHITE,
            );
            if let Some(pixel) = marked {
                mark_pixel(&ui.painter_at(fitted), fitted, map_size, pixel);
            }
            if let Some(position) = response.hover_pos().filter(|p| fitted.contains(*p)) {
                let x =
                    ((position.x - fitted.min.x) / fitted.width() * map_size[0] as f32) as usize;
                let y =
                    ((position.y - fitted.min.y) / fitted.height() * map_size[1] as f32) as usize;
                under = Some([x.min(map_size[0] - 1), y.min(map_size[1] - 1)]);
                clicked = response.clicked();
            }
            legend.ui(ui, size.x);
        });
        (under, clicked, save)
    }

    /// The pane of map `which`: near first (0), file order (1) or their difference (2);
    /// what happened in it goes to `events[which]`.
    fn map_pane(
        &self,
        ui: &mut egui::Ui,
        which: usize,
        pane: Vec2,
        events: &mut [(Option<[usize; 2]>, bool, bool); 3],
    ) {
        let (Some(textures), Some(maps), Some(job)) = (&self.textures, &self.maps, &self.job)
        else {
            return;
        };
        let size = [job.key().width, job.key().height];
        let counter = self.counter;
        let (title, texture, legend) = match which {
            0 | 1 => (
                format!(
                    "{}: {} per pixel",
                    ["Near first", "File order"][which],
                    counter.label()
                ),
                &textures.orders[which],
                Legend::Sequential {
                    scale: textures.scale,
                    summary: maps.maps[which].summary(counter),
                    label: counter.label(),
                },
            ),
            _ => (
                "Near first minus file order".to_owned(),
                &textures.difference,
                Legend::Diverging {
                    scale: textures.difference_scale,
                    label: counter.label(),
                },
            ),
        };
        let marked = self.picked.map(|picked| picked.pixel);
        events[which.min(2)] = Self::map_ui(ui, pane, &title, texture, size, legend, marked);
    }

    /// One of the maps as a PNG: near first (0), file order (1) or their difference (2), in
    /// the colours shown.
    fn map_png(&self, which: usize) -> Option<crate::view3d::Export> {
        let (maps, textures) = (self.maps.as_ref()?, self.textures.as_ref()?);
        let counter = self.counter;
        let map = &maps.maps[which.min(1)];
        let colors = match which {
            0 | 1 => map.colors(counter, textures.scale),
            _ => difference_colors(
                &maps.maps[0].difference(&maps.maps[1], counter),
                textures.difference_scale,
            ),
        };
        let name = ["near-first", "file-order", "difference"][which.min(2)];
        Some(
            accelviz_scene::output::encode_png(map.width, map.height, &colors)
                .map(|bytes| (format!("heat-{name}-{}.png", counter.name()), bytes)),
        )
    }
}

/// A palette bar with its scale.
enum Legend {
    /// 0 to `scale` (both orders' maps share it), with this map's own largest value and mean.
    Sequential {
        scale: u32,
        summary: accelviz_core::heatmap::Summary,
        label: &'static str,
    },
    /// −scale to +scale.
    Diverging { scale: u64, label: &'static str },
}

impl Legend {
    fn ui(&self, ui: &mut egui::Ui, width: f32) {
        let (rect, _) =
            ui.allocate_exact_size(Vec2::new(width.min(320.0), LEGEND_BAR), Sense::hover());
        let steps = 48;
        let dark = ui.visuals().dark_mode;
        for step in 0..steps {
            let t = step as f64 / (steps - 1) as f64;
            let [r, g, b] = match self {
                Legend::Sequential { .. } => sequential(t),
                Legend::Diverging { .. } => diverging_on(t * 2.0 - 1.0, dark),
            };
            let x0 = rect.min.x + rect.width() * step as f32 / steps as f32;
            let x1 = rect.min.x + rect.width() * (step + 1) as f32 / steps as f32;
            ui.painter().rect_filled(
                Rect::from_min_max(egui::pos2(x0, rect.min.y), egui::pos2(x1, rect.max.y)),
                0.0,
                Color32::from_rgb(r, g, b),
            );
        }
        let text = match self {
            Legend::Sequential {
                scale,
                summary,
                label,
            } => {
                format!(
                    "0 … {} {label}, the scale both maps share\nthis map: max {}, mean {}",
                    count(*scale as usize),
                    count(summary.max as usize),
                    number(summary.mean)
                )
            }
            Legend::Diverging { scale, label } => format!(
                "−{} … 0 … +{} {label}\nbelow 0 near first tests fewer, above 0 more",
                count(*scale as usize),
                count(*scale as usize)
            ),
        };
        ui.label(text);
    }
}

impl Lesson for HeatLesson {
    crate::staged!(tree);

    fn share(&self) -> Vec<(String, String)> {
        let mut values =
            crate::share::mesh_view_values(&self.stage.scene, &self.structure, &self.view.orbit);
        values.push(("counter".to_owned(), self.counter.name().to_owned()));
        let packets = if self.packets {
            format!("{PACKET_TILE}x{PACKET_TILE}")
        } else {
            "none".to_owned()
        };
        values.push(("packets".to_owned(), packets));
        values.push(("rays".to_owned(), self.ray_kind.name().to_owned()));
        values
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        match key {
            "counter" => {
                self.counter = Counter::ALL
                    .into_iter()
                    .find(|counter| counter.name() == value)
                    .ok_or_else(|| format!("no counter '{value}' (nodes, boxes or prims)"))?;
            }
            "rays" => {
                self.ray_kind = HEAT_RAY_KINDS
                    .into_iter()
                    .find(|kind| kind.name() == value)
                    .ok_or_else(|| {
                        format!("no heat map rays '{value}' (camera, shadow, ao or bounce)")
                    })?;
            }
            "packets" => {
                self.packets = match value {
                    "none" => false,
                    _ if value == format!("{PACKET_TILE}x{PACKET_TILE}") => true,
                    _ => {
                        return Err(format!(
                            "packets are 'none' or '{PACKET_TILE}x{PACKET_TILE}', not '{value}'"
                        ));
                    }
                };
            }
            _ => {
                let (scene, structure) = (&mut self.stage.scene, &mut self.structure);
                crate::share::restore_mesh_view(
                    scene,
                    structure,
                    &mut self.view.orbit,
                    key,
                    value,
                )?;
            }
        }
        Ok(())
    }

    fn update(&mut self) {
        self.stage
            .scene
            .request_tree(&mut self.tree, self.structure);
        let Some(tree) = self.tree.get().cloned() else {
            return;
        };
        if let Some([width, height]) = self.pane_pixels {
            let key = HeatKey {
                tree: self.tree.generation(),
                camera: self.camera(&tree),
                width,
                height,
                tile: if self.packets && self.ray_kind == RayKind::Camera {
                    PACKET_TILE
                } else {
                    1
                },
                ray_kind: self.ray_kind,
            };
            // A layout that moves by a few pixels (a panel fitting new numbers) keeps the
            // maps: only a new tree, a new camera or a real resize starts them again.
            let close_enough = self.job.as_ref().is_some_and(|job| {
                let made = job.key();
                made.tree == key.tree
                    && made.tile == key.tile
                    && made.ray_kind == key.ray_kind
                    && made.camera == key.camera
                    && made.width.abs_diff(key.width) <= 32
                    && made.height.abs_diff(key.height) <= 32
            });
            if !close_enough {
                self.job = Some(HeatJob::start(key, tree.clone(), worker_threads()));
                self.job_serial += 1;
                self.maps = None;
            }
        }
        if let Some(job) = &self.job {
            job.advance();
            let bands = job.bands_done();
            if self.maps.is_none() || bands != self.maps_bands {
                let maps = job.snapshot();
                // Said once per job, when the last band is in (the browser test reads it).
                if let Some(ms) = maps.millis
                    && self
                        .maps
                        .as_ref()
                        .is_none_or(|before| before.millis.is_none())
                {
                    let key = job.key();
                    log::info!(
                        "accelviz: heat maps {}x{} traced in {} ms {}",
                        key.width,
                        key.height,
                        ms.round(),
                        job.traced_where()
                    );
                }
                self.maps = Some(maps);
                self.maps_bands = bands;
            }
        }
        let Some(picked) = self.picked else {
            self.trace.clear();
            self.stage.timeline.set_len(0);
            return;
        };
        let trace = self
            .trace
            .get_or_make((self.tree.generation(), picked.revision), || {
                Trace::of(
                    &tree.build.built.tree,
                    &tree.triangles,
                    &picked.ray,
                    &accelviz_core::TraceOptions {
                        query: picked.query,
                        ..options_in(picked.order)
                    },
                )
            });
        self.stage.timeline.set_len(trace.frames());
    }

    fn take_export(&mut self) -> Option<crate::view3d::Export> {
        self.view.take_export().or_else(|| self.export.take())
    }

    fn caption(&self) -> Option<String> {
        let tree = self.tree.get()?;
        Some(tree.caption(
            self.trace.get(),
            self.stage.timeline.shown,
            match self.ray_kind {
                RayKind::Camera => {
                    "Click a pixel of a heat map: its ray is traced here, step by step."
                }
                _ => "Click a pixel of a heat map: the first of the rays from its hit is traced here, step by step.",
            },
        ))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        let Some(tree) = self.tree.get().cloned() else {
            ui.label("Building…");
            return;
        };
        ui.label(format!(
            "{}: {} triangles; {}: {} nodes, SAH cost {}",
            tree.mesh.name.trim_start_matches("builtin:"),
            count(tree.mesh.triangles.len()),
            tree.build.built.structure.title(),
            count(tree.build.stats.node_count),
            number(tree.build.stats.sah_cost)
        ));
        let Some(maps) = &self.maps else { return };
        ui.separator();
        // A table keeps its columns: in a narrow panel (the app scaled up) it scrolls
        // sideways rather than widen the panel.
        egui::ScrollArea::horizontal()
            .id_salt("heat totals columns")
            .show(ui, |ui| {
                // Columns as wide as their widest text can be, so they keep their places
                // while the maps are traced and their numbers grow.
                let widest = ui
                    .painter()
                    .layout_no_wrap(
                        "mean 00.000".to_owned(),
                        egui::TextStyle::Body.resolve(ui.style()),
                        Color32::WHITE,
                    )
                    .size()
                    .x;
                egui::Grid::new("heat totals")
                    .striped(true)
                    .min_col_width(widest)
                    .show(ui, |ui| {
                        ui.label("per pixel");
                        ui.label("near first");
                        ui.label("file order");
                        ui.end_row();
                        for counter in Counter::ALL {
                            ui.label(counter.label());
                            for map in &maps.maps {
                                let summary = map.summary(counter);
                                // Two short lines: the columns fit a narrow inspector.
                                ui.label(format!(
                                    "mean {}\nmax {}",
                                    number(summary.mean),
                                    count(summary.max as usize)
                                ));
                            }
                            ui.end_row();
                        }
                    });
            });
        let how = match self.ray_kind {
            RayKind::Camera if self.packets => format!(", in {PACKET_TILE}×{PACKET_TILE} packets"),
            RayKind::Camera => ", one ray at a time".to_owned(),
            kind => format!(", {}", ray_kind_about(kind)),
        };
        let state = if maps.progress < 1.0 {
            format!("{:.0} % traced{how}", maps.progress * 100.0)
        } else {
            format!("every pixel traced{how}")
        };
        let timing = maps
            .millis
            .map(|ms| format!("both orders in {} ms", number(ms)))
            .unwrap_or_default();
        ui.label(egui::RichText::new(state).small())
            .on_hover_text(timing);
        // What a switch does where the maps cannot show it.
        let structure = tree.build.built.structure;
        if self.packets && self.ray_kind == RayKind::Camera {
            let wide = structure.family() == Family::Bvh && structure.width() != Width::Binary;
            ui.label(if wide {
                "In packets each pixel still counts its own ray's tests, and a packet's rays are tested as each would be alone: what the 64 rays share is each node's fetch from memory. So the maps match one ray at a time; packets change the speed (accelviz-cli bench --packet 1,64 times both)."
            } else {
                "This structure traces a packet ray by ray (only a wide BVH traces one together), so the maps are those of one ray at a time."
            });
        }
        if self.counter == Counter::Boxes {
            let how = match structure.family() {
                Family::Bvh => None,
                Family::Kd => {
                    Some("a kD-tree finds its cells by comparing t with each split plane")
                }
                Family::Octree => Some(
                    "an octree orders a cell's children by where the ray crosses its middle planes",
                ),
                Family::Grid | Family::HashedGrid => {
                    Some("a grid steps from cell to cell by the t of the next plane on each axis")
                }
            };
            if let Some(how) = how {
                ui.label(format!(
                    "This structure tests one box per ray, the root's: below it {how}, not by box tests. So this map is 1 at every pixel the box covers."
                ));
            }
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.controls_ui(ui);
        loading_ui(
            ui,
            &mut self.stage.scene,
            &mut self.tree,
            (
                &mut self.structure,
                &mut accelviz_core::trade::Precision::F64,
            ),
        );
        let Some(tree) = self.tree.get().cloned() else {
            ui.label("Building…");
            return;
        };
        let frame = self.stage.timeline.shown;
        let steps = self.trace.get().map_or(&[][..], |trace| trace.shown(frame));
        let (highlights, segments) = match self.picked {
            Some(picked) => trace_overlay(&tree, &picked.ray, steps),
            None => (Vec::new(), Vec::new()),
        };
        // The boxes the ray has met so far, the step's own in blue, as lesson 12 draws them.
        let current = self
            .trace
            .get()
            .and_then(|trace| trace.state(frame).current)
            .and_then(|step| crate::trace::step_node(&step));
        let boxes = if self.picked.is_some() {
            trace_boxes(&tree, steps, current)
        } else {
            Vec::new()
        };
        let overlay = revision_of((
            self.tree.generation(),
            self.picked.map(|p| p.revision),
            frame,
        ));
        // One line of fixed height: the progress while tracing, then what the pointer reads
        // (a line that came and went would resize the maps and start them again).
        let progress = self.maps.as_ref().map_or(0.0, |maps| maps.progress);
        let width = ui.available_width();
        let (line, _) = ui.allocate_exact_size(Vec2::new(width, 20.0), Sense::hover());
        if progress < 1.0 {
            ui.put(
                Rect::from_min_size(line.min, Vec2::new(width.min(420.0), 16.0)),
                egui::ProgressBar::new(progress as f32)
                    .text(format!("tracing every pixel: {:.0} %", progress * 100.0)),
            );
            ui.ctx().request_repaint();
        } else {
            let text = self
                .readout
                .clone()
                .unwrap_or_else(|| "Hover a pixel of a map to read its counts.".to_owned());
            ui.scope_builder(egui::UiBuilder::new().max_rect(line), |ui| {
                ui.add(egui::Label::new(text).truncate());
            });
        }
        self.textures(ui.ctx());
        let available = ui.available_size();
        let gap = 8.0;
        // Two panes a row with a gap between them, and the layout's spacing on each side of it.
        let spacing = ui.spacing().item_spacing;
        let pane = Vec2::new(
            (available.x - gap - 2.0 * spacing.x) / 2.0,
            (available.y - gap - 2.0 * spacing.y) / 2.0,
        )
        .max(Vec2::splat(40.0));
        // The maps have the 3D view's size in pixels, so a pixel of one is a pixel of the other.
        let pixels_per_point = ui.ctx().pixels_per_point();
        // In steps of 8 pixels, so a layout that moves by a pixel does not start the maps again.
        let quantized = |points: f32| (((points * pixels_per_point) as usize) / 8 * 8).max(8);
        let text_height = pane_text_height(ui);
        self.pane_pixels = Some([
            quantized(pane.x),
            quantized((pane.y - text_height).max(10.0)),
        ]);

        // Per map pane: the pixel under the pointer, a click on it, a click on "save PNG".
        let mut picked_pane = [(None, false, false); 3];
        let sizes = self
            .job
            .as_ref()
            .map(|job| [job.key().width, job.key().height]);
        ui.horizontal(|ui| {
            ui.vertical(|ui| {
                ui.set_width(pane.x);
                ui.label(egui::RichText::new("The view (its camera is the maps')").strong());
                // Exactly the maps' size: pixel (x, y) here is pixel (x, y) there.
                let image = match sizes.or(self.pane_pixels) {
                    Some([w, h]) => fit_within(
                        Vec2::new(w as f32, h as f32) / pixels_per_point,
                        Vec2::new(pane.x, pane.y - text_height),
                    ),
                    None => Vec2::new(pane.x, pane.y - text_height),
                };
                let response = self.view.ui(
                    ui,
                    image,
                    &Content {
                        sphere: tree.build.sphere,
                        mesh: (
                            revision_of((self.tree.generation(), "mesh")),
                            &tree.build.drawn,
                        ),
                        highlights: (overlay, &highlights),
                        boxes: (overlay, &boxes),
                        segments: (overlay, &segments),
                        quads: (0, &[]),
                        hidden_edges: HiddenEdges::Dimmed,
                        wireframe: false,
                    },
                );
                // Seen from the camera the ray is a point: mark its pixel here as on the maps.
                if let (Some(picked), Some(size)) = (self.picked, sizes) {
                    let rect = response.response.rect;
                    mark_pixel(&ui.painter_at(rect), rect, size, picked.pixel);
                }
                ui.label(
                    egui::RichText::new("Drag to orbit, right-drag to pan, scroll to zoom.")
                        .small()
                        .weak(),
                );
            });
            ui.add_space(gap);
            self.map_pane(ui, 0, pane, &mut picked_pane);
        });
        ui.add_space(gap);
        ui.horizontal(|ui| {
            self.map_pane(ui, 1, pane, &mut picked_pane);
            ui.add_space(gap);
            self.map_pane(ui, 2, pane, &mut picked_pane);
        });
        let mut hovered = None;
        let mut clicked = None;
        let mut save_which = None;
        for (which, (under, click, save)) in picked_pane.into_iter().enumerate() {
            if save {
                save_which = Some(which);
            }
            if let Some(pixel) = under {
                hovered = Some((pixel, ()));
                if click {
                    let order = if which == 1 {
                        Order::FileOrder
                    } else {
                        Order::NearFirst
                    };
                    clicked = Some((pixel, order));
                }
            }
        }
        self.readout = match (hovered, &self.maps) {
            (Some(([x, y], _)), Some(maps)) => {
                let counts: Vec<String> = ORDERS
                    .iter()
                    .zip(&maps.maps)
                    .filter_map(|(order, map)| {
                        let cost = map.at(x, y)?;
                        let name = order.name().replace('-', " ");
                        let of = |n: u32, one, many| counted(n as usize, one, many);
                        Some(format!(
                            "{name} {}, {}, {}",
                            of(cost.nodes, "node", "nodes"),
                            of(cost.boxes, "box test", "box tests"),
                            of(cost.prims, "primitive test", "primitive tests")
                        ))
                    })
                    .collect();
                Some(format!(
                    "pixel ({x}, {y}): {}; click to trace its ray",
                    counts.join(" | ")
                ))
            }
            _ => None,
        };
        if let Some(which) = save_which {
            self.export = self.map_png(which);
        }
        if let Some(([x, y], order)) = clicked {
            self.pick_pixel(x, y, order);
        }
    }
}

/// Marks `pixel` of a `size` picture drawn in `rect`: the clicked pixel, whose ray the view
/// steps through. A ring and four ticks around it, black under white, so it shows on every
/// colour of a map and of the view, and leaves the pixel itself to be seen.
fn mark_pixel(painter: &egui::Painter, rect: Rect, size: [usize; 2], [x, y]: [usize; 2]) {
    let at = rect.min
        + Vec2::new(
            (x as f32 + 0.5) / size[0].max(1) as f32 * rect.width(),
            (y as f32 + 0.5) / size[1].max(1) as f32 * rect.height(),
        );
    for (width, color) in [(4.0, Color32::BLACK), (2.0, Color32::WHITE)] {
        let stroke = egui::Stroke::new(width, color);
        painter.circle_stroke(at, 7.0, stroke);
        for direction in [Vec2::X, -Vec2::X, Vec2::Y, -Vec2::Y] {
            painter.line_segment([at + direction * 10.0, at + direction * 16.0], stroke);
        }
    }
}

/// The height a map pane keeps for its words: its title, the legend's bar and its two lines
/// (at the text size of the moment: lecture mode's is larger, and a legend cut off at the
/// bottom of a slide says nothing).
fn pane_text_height(ui: &egui::Ui) -> f32 {
    let line = ui.text_style_height(&egui::TextStyle::Body);
    let button = ui.spacing().interact_size.y;
    button + LEGEND_BAR + 2.0 * line + 5.0 * ui.spacing().item_spacing.y
}

/// The legend's colour bar, in points.
const LEGEND_BAR: f32 = 14.0;

/// `size` shrunk, keeping its shape, to fit in `room` (never grown).
fn fit_within(size: Vec2, room: Vec2) -> Vec2 {
    let scale = (room.x / size.x.max(1.0))
        .min(room.y / size.y.max(1.0))
        .clamp(0.0, 1.0);
    size * scale
}
