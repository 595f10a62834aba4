//! Lesson 11, "The slab test in 3D": the slide's "three pairs of parallel planes". A box, its
//! three slabs drawn as translucent plane pairs (x red, y green, z blue), the ray, and each
//! slab's [t_near, t_far] on the ray and on a number line; then the max of the nears and the
//! min of the fars. The numbers are the core's `slab_record`, the arithmetic the traversal
//! runs. Drag the ray's start or its aim point in the view; the edge cases are one click away.

use accelviz_core::format::{number, point};
use accelviz_core::{Aabb, Ray, SlabRecord, slab_record};
use egui::{Color32, Vec2};
use glam::DVec3;

use crate::canvas::palette;
use crate::files::FileFilter;
use crate::lesson::Lesson;
use crate::lesson_file::{LessonText, SlabFile};
use crate::stage::{SceneFile, Stage};
use crate::view3d::{Content, HiddenEdges, Instance, View3d, relative, revision_of};
use crate::views::number_lines::{IntervalRow, number_lines_height, number_lines_ui};

/// The three slabs: name and colour, by axis.
const AXES: [(&str, Color32); 3] = [
    ("x slab", palette::X_AXIS),
    ("y slab", palette::Y_AXIS),
    ("z slab", palette::Z_AXIS),
];

/// The steps, in the slide's order.
const STEP_CAPTIONS: [&str; 7] = [
    "A box is three pairs of parallel planes, one pair per axis: three slabs. The ray is r(t) = p + t·d.",
    "x slab, between the planes x = min.x and x = max.x: where the ray crosses them gives [t_near, t_far].",
    "y slab, between y = min.y and y = max.y: its [t_near, t_far].",
    "z slab, between z = min.z and z = max.z: its [t_near, t_far].",
    "The max of the t_near: only after it is the ray inside all three slabs.",
    "The min of the t_far: after it the ray has left some slab.",
    "If max t_near > min t_far the box is missed (also when min t_far < 0: it is behind the ray).",
];

/// The edge cases one click away: name, what it shows, and the ray (origin, aim point) for
/// the box [-1, 1] × [-0.6, 0.6] × [-0.8, 0.8].
const GALLERY: [(&str, &str, [f64; 3], [f64; 3]); 5] = [
    (
        "crossing",
        "a plain hit through the box",
        [-3.0, 1.6, 2.5],
        [0.3, 0.1, -0.2],
    ),
    (
        "parallel inside a slab",
        "d.y = 0 within the y slab: its t_near = −∞, t_far = +∞",
        [-3.0, 0.2, 1.8],
        [0.0, 0.2, 0.0],
    ),
    (
        "parallel outside",
        "d.y = 0 above the y slab: that slab's interval is empty, a miss",
        [-3.0, 1.0, 1.8],
        [0.0, 1.0, 0.0],
    ),
    (
        "origin inside",
        "p inside the box: max t_near < 0 < min t_far, still a hit",
        [0.2, 0.1, 0.3],
        [1.0, 0.5, 0.8],
    ),
    (
        "missing",
        "the slabs' intervals do not overlap: max t_near > min t_far",
        [-3.0, 2.0, 2.5],
        [0.0, 1.2, 1.2],
    ),
];

/// The box and the ray.
pub struct SlabScene {
    /// The box.
    pub bounds: Aabb<DVec3>,
    /// Where the ray starts.
    pub origin: DVec3,
    /// The point the ray passes at t = 1.
    pub toward: DVec3,
}

impl SlabScene {
    /// The scene a lesson file gives (or the gallery's first case).
    fn of_lesson(text: &LessonText) -> Self {
        let slab: Option<SlabFile> = text.file.view3d.as_ref().and_then(|view| view.slab);
        let v = |(x, y, z): (f64, f64, f64)| DVec3::new(x, y, z);
        match slab {
            Some(slab) => Self {
                bounds: Aabb::new(v(slab.min), v(slab.max)),
                origin: v(slab.origin),
                toward: v(slab.toward),
            },
            None => Self {
                bounds: Aabb::new(DVec3::new(-1.0, -0.6, -0.8), DVec3::new(1.0, 0.6, 0.8)),
                origin: DVec3::from_array(GALLERY[0].2),
                toward: DVec3::from_array(GALLERY[0].3),
            },
        }
    }

    /// The ray, unless it has no direction.
    pub fn ray(&self) -> Option<Ray<DVec3>> {
        Ray::try_new(self.origin, self.toward - self.origin).ok()
    }

    /// The slab test of the ray and the box.
    pub fn record(&self) -> Option<SlabRecord<DVec3>> {
        Some(slab_record(&self.bounds, &self.ray()?, false))
    }

    /// A sphere holding the box and both of the ray's points.
    fn sphere(&self) -> (DVec3, f64) {
        let all = self.bounds.grown(self.origin).grown(self.toward);
        accelviz_core::camera::bounding_sphere_of_box(&all)
    }
}

impl SceneFile for SlabScene {
    fn noun(&self) -> &'static str {
        "ray"
    }

    fn filter(&self) -> Option<FileFilter> {
        None
    }

    fn open(&mut self, _name: &str, _text: &str) -> Result<(), String> {
        Err("this lesson opens no files: drag the ray, or pick an edge case".to_owned())
    }

    fn save(&self) -> Option<(String, String)> {
        None
    }

    fn can_save(&self) -> bool {
        false
    }

    fn reset(&mut self, text: &LessonText) {
        *self = Self::of_lesson(text);
    }
}

/// Which end of the ray is being dragged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Handle {
    Origin,
    Toward,
}

/// The lesson.
pub struct Slab3dLesson {
    stage: Stage<SlabScene>,
    /// The view and its camera.
    pub view: View3d,
    dragging: Option<Handle>,
    /// Where the handles were drawn last frame (origin, aim point).
    handles_on_screen: [Option<egui::Pos2>; 2],
}

/// Colour as the GPU takes it.
fn rgba(color: Color32, alpha: u8) -> [u8; 4] {
    [color.r(), color.g(), color.b(), alpha]
}

impl Slab3dLesson {
    /// The lesson with its file's box and ray.
    pub fn new(text: LessonText) -> Self {
        let scene = SlabScene::of_lesson(&text);
        let mut stage = Stage::with_scene(text, scene);
        stage.timeline.set_len(STEP_CAPTIONS.len() - 1);
        Self {
            stage,
            view: View3d::default(),
            dragging: None,
            handles_on_screen: [None; 2],
        }
    }

    /// The box and the ray.
    pub fn scene(&self) -> &SlabScene {
        &self.stage.scene
    }

    /// Where the last frame drew the ray's start (0) or aim point (1).
    pub fn handle_on_screen(&self, handle: usize) -> Option<egui::Pos2> {
        self.handles_on_screen.get(handle).copied().flatten()
    }

    /// Puts the ray on one of the gallery's cases, and shows every step.
    pub fn use_case(&mut self, index: usize) {
        if let Some((_, _, origin, toward)) = GALLERY.get(index) {
            self.stage.scene.origin = DVec3::from_array(*origin);
            self.stage.scene.toward = DVec3::from_array(*toward);
            self.stage.timeline.shown = self.stage.timeline.len;
        }
    }

    /// The planes of the slabs shown so far (two per axis), as translucent quads reaching a
    /// little beyond the box, sorted back to front for `eye`.
    fn planes(&self, shown: usize, eye: DVec3, sphere: (DVec3, f64)) -> Vec<Instance> {
        let bounds = self.stage.scene.bounds;
        let margin = bounds.extent() * 0.35;
        let mut planes: Vec<(f64, Instance)> = Vec::new();
        for (axis, (_, color)) in AXES.iter().enumerate() {
            if shown <= axis {
                continue;
            }
            for value in [bounds.min[axis], bounds.max[axis]] {
                let (mut low, mut high) = (bounds.min - margin, bounds.max + margin);
                low[axis] = value;
                high[axis] = value;
                let distance = ((low + high) / 2.0 - eye).length();
                planes.push((
                    distance,
                    Instance {
                        a: relative(low, sphere),
                        b: relative(high, sphere),
                        color: rgba(*color, 46),
                    },
                ));
            }
        }
        planes.sort_by(|a, b| b.0.total_cmp(&a.0));
        planes.into_iter().map(|(_, plane)| plane).collect()
    }

    /// The ray, each shown slab's interval on it, and the markers of the steps shown.
    fn ray_marks(
        &self,
        record: &SlabRecord<DVec3>,
        shown: usize,
        sphere: (DVec3, f64),
    ) -> (Vec<Instance>, Vec<Instance>) {
        let scene = &self.stage.scene;
        let Some(ray) = scene.ray() else {
            return (Vec::new(), Vec::new());
        };
        // The part of the ray drawn: from its start to past the box.
        let reach = ((scene.origin - sphere.0).length() + 2.0 * sphere.1) / ray.direction.length();
        let clamp = |t: f64| t.clamp(-reach, reach);
        let point = |t: f64| relative(ray.at(clamp(t)), sphere);
        let mut segments = vec![Instance {
            a: point(0.0),
            b: point(reach),
            color: rgba(palette::RAY, 255),
        }];
        let mut markers = Vec::new();
        let marker = |t: f64, color: Color32, size: f64| {
            let at = ray.at(clamp(t));
            let half = DVec3::splat(sphere.1 * size);
            Instance {
                a: relative(at - half, sphere),
                b: relative(at + half, sphere),
                color: rgba(color, 255),
            }
        };
        for (axis, (_, color)) in AXES.iter().enumerate() {
            if shown <= axis {
                continue;
            }
            let (t_near, t_far) = (record.t_near[axis], record.t_far[axis]);
            if t_near <= t_far {
                segments.push(Instance {
                    a: point(t_near),
                    b: point(t_far),
                    color: rgba(*color, 255),
                });
            }
            for t in [t_near, t_far] {
                if t.is_finite() {
                    markers.push(marker(t, *color, 0.015));
                }
            }
        }
        if shown >= 4 {
            markers.push(marker(record.t_enter, palette::CURRENT, 0.03));
        }
        if shown >= 5 {
            markers.push(marker(record.t_exit, palette::CURRENT, 0.03));
        }
        if shown >= 6 && record.hit {
            segments.push(Instance {
                a: point(record.t_enter.max(0.0)),
                b: point(record.t_exit),
                color: rgba(palette::HIT, 255),
            });
        }
        // The handles: the ray's start and its aim point.
        for (at, color) in [(scene.origin, palette::RAY), (scene.toward, Color32::WHITE)] {
            let half = DVec3::splat(sphere.1 * 0.025);
            markers.push(Instance {
                a: relative(at - half, sphere),
                b: relative(at + half, sphere),
                color: rgba(color, 255),
            });
        }
        (segments, markers)
    }

    /// Starts, continues or ends a drag of the ray's start or aim point.
    fn drag(&mut self, ui: &egui::Ui, response: &crate::view3d::ViewResponse) {
        let (pressed, press_origin, down) = ui.input(|input| {
            (
                input.pointer.primary_pressed(),
                input.pointer.press_origin(),
                input.pointer.primary_down(),
            )
        });
        if pressed && let Some(press) = press_origin {
            let near =
                |handle: Option<egui::Pos2>| handle.is_some_and(|at| at.distance(press) < 14.0);
            self.dragging = if near(self.handles_on_screen[1]) {
                Some(Handle::Toward)
            } else if near(self.handles_on_screen[0]) {
                Some(Handle::Origin)
            } else {
                None
            };
        }
        if !down {
            self.dragging = None;
        }
        self.view.locked = self.dragging.is_some();
        if let (Some(handle), Some((origin, direction))) = (self.dragging, response.hovered) {
            // Move the handle in the plane through it facing the camera.
            let scene = &mut self.stage.scene;
            let current = match handle {
                Handle::Origin => scene.origin,
                Handle::Toward => scene.toward,
            };
            let normal = response.camera.basis().forward;
            let denominator = direction.dot(normal);
            if denominator.abs() > 1e-12 {
                let t = (current - origin).dot(normal) / denominator;
                let moved = origin + direction * t;
                let other = match handle {
                    Handle::Origin => scene.toward,
                    Handle::Toward => scene.origin,
                };
                // Never let the ray's two points meet: it would have no direction.
                if (moved - other).length() > 1e-6 * (1.0 + other.length()) {
                    match handle {
                        Handle::Origin => scene.origin = moved,
                        Handle::Toward => scene.toward = moved,
                    }
                }
            }
        }
        self.handles_on_screen = [
            response.to_screen(self.stage.scene.origin),
            response.to_screen(self.stage.scene.toward),
        ];
    }
}

impl Lesson for Slab3dLesson {
    crate::staged!();

    fn share(&self) -> Vec<(String, String)> {
        vec![crate::share::camera_value(&self.view.orbit)]
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        match key {
            "camera" => self.view.orbit = crate::share::parse_camera(value)?,
            _ => return Err(format!("this lesson keeps no '{key}'")),
        }
        Ok(())
    }

    fn take_export(&mut self) -> Option<crate::view3d::Export> {
        self.view.take_export()
    }

    fn caption(&self) -> Option<String> {
        let shown = self.stage.timeline.shown.min(STEP_CAPTIONS.len() - 1);
        let record = self.stage.scene.record()?;
        let mut caption = STEP_CAPTIONS[shown].to_owned();
        if shown >= 6 {
            caption.push_str(&format!(
                " Here: max t_near = {}, min t_far = {}: {}.",
                number(record.t_enter),
                number(record.t_exit),
                if record.hit { "hit" } else { "miss" }
            ));
        }
        Some(caption)
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        self.view.save_button(ui);
        ui.label(egui::RichText::new("Edge cases").strong());
        ui.horizontal_wrapped(|ui| {
            for (index, (name, about, _, _)) in GALLERY.iter().enumerate() {
                if ui.button(*name).on_hover_text(*about).clicked() {
                    self.use_case(index);
                }
            }
        });
        ui.separator();
        let scene = &self.stage.scene;
        ui.label(format!(
            "box from {} to {}",
            point(&scene.bounds.min.to_array()),
            point(&scene.bounds.max.to_array())
        ));
        ui.label(format!(
            "ray p = {}, d = {}",
            point(&scene.origin.to_array()),
            point(&(scene.toward - scene.origin).to_array())
        ));
        let Some(record) = scene.record() else {
            ui.colored_label(
                crate::canvas::readable(ui, palette::MISS),
                "The ray's two points meet: it has no direction.",
            );
            return;
        };
        let shown = self.stage.timeline.shown;
        // A table keeps its columns: in a narrow panel (the app scaled up) it scrolls
        // sideways rather than widen the panel.
        egui::ScrollArea::horizontal()
            .id_salt("slab3d table columns")
            .show(ui, |ui| {
                egui::Grid::new("slab3d table")
                    .striped(true)
                    .min_col_width(56.0)
                    .show(ui, |ui| {
                        ui.label("");
                        ui.strong("t near");
                        ui.strong("t far");
                        ui.end_row();
                        for (axis, (name, color)) in AXES.iter().enumerate() {
                            ui.colored_label(crate::canvas::readable(ui, *color), *name);
                            let known = shown > axis;
                            let cell =
                                |value: f64| if known { number(value) } else { "?".to_owned() };
                            ui.monospace(cell(record.t_near[axis]));
                            ui.monospace(cell(record.t_far[axis]));
                            ui.end_row();
                        }
                        ui.strong("max / min");
                        ui.monospace(if shown >= 4 {
                            number(record.t_enter)
                        } else {
                            "?".into()
                        });
                        ui.monospace(if shown >= 5 {
                            number(record.t_exit)
                        } else {
                            "?".into()
                        });
                        ui.end_row();
                    });
            });
        if shown >= 6 {
            let (text, color) = if record.hit {
                (
                    "hit: max t_near ≤ min t_far, and min t_far ≥ 0",
                    palette::HIT,
                )
            } else {
                ("miss", palette::MISS)
            };
            ui.colored_label(crate::canvas::readable(ui, color), text);
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let shown = self.stage.timeline.shown;
        let lines_height = number_lines_height(4);
        let size = ui.available_size() - Vec2::new(0.0, lines_height + 6.0);
        let scene = &self.stage.scene;
        let sphere = scene.sphere();
        let camera = self.view.orbit.camera(sphere.0, sphere.1);
        let record = scene.record();
        let boxes = [Instance {
            a: relative(scene.bounds.min, sphere),
            b: relative(scene.bounds.max, sphere),
            color: [70, 70, 70, 255],
        }];
        let planes = self.planes(shown, camera.eye, sphere);
        let (segments, markers) = match &record {
            Some(record) => self.ray_marks(record, shown, sphere),
            None => (Vec::new(), Vec::new()),
        };
        let all_boxes: Vec<Instance> = boxes.iter().copied().chain(markers).collect();
        let key = revision_of((
            shown,
            [
                scene.origin,
                scene.toward,
                scene.bounds.min,
                scene.bounds.max,
            ]
            .map(|v| v.to_array().map(f64::to_bits)),
            camera.eye.to_array().map(f64::to_bits),
        ));
        let response = self.view.ui(
            ui,
            size.max(Vec2::splat(60.0)),
            &Content {
                sphere,
                mesh: (0, &[]),
                highlights: (0, &[]),
                boxes: (key, &all_boxes),
                segments: (key, &segments),
                quads: (key, &planes),
                hidden_edges: HiddenEdges::Dimmed,
                wireframe: false,
            },
        );
        self.drag(ui, &response);
        // The handles as discs over the picture, outlined so they show on every background.
        let painter = ui.painter_at(response.response.rect);
        for (at, fill) in self
            .handles_on_screen
            .iter()
            .zip([palette::RAY, Color32::WHITE])
        {
            if let Some(at) = at {
                painter.circle(*at, 7.0, fill, egui::Stroke::new(2.0, Color32::BLACK));
            }
        }
        if let Some(record) = record {
            let mut rows: Vec<IntervalRow<'_>> = AXES
                .iter()
                .enumerate()
                .map(|(axis, (name, color))| IntervalRow {
                    name,
                    color: *color,
                    interval: (record.t_near[axis], record.t_far[axis]),
                    visible: shown > axis,
                })
                .collect();
            rows.push(IntervalRow {
                name: "all three",
                color: palette::CURRENT,
                interval: (record.t_enter, record.t_exit),
                visible: shown >= 5,
            });
            number_lines_ui(ui, &rows, lines_height);
        }
    }
}
