//! The 3D view: a camera the user orbits, pans and zooms, drawn by [`gpu`] into the view's own
//! textures; a click gives the ray through that pixel (the core's [`Camera`], the same one
//! the heat maps and `bench --camera` use), so what is picked is what is traced.

pub mod gpu;

use accelviz_core::camera::{Camera, Projection};
use egui::{Color32, Rect, Sense, Vec2};
use glam::{DVec3, Mat4};

pub use gpu::{DrawTriangle, Gpu, HiddenEdges, Instance, Scene3d, ViewGpu};

/// A file a lesson hands the app to save: (suggested name, bytes), or why it could not make it.
pub type Export = Result<(String, Vec<u8>), String>;

/// Where the camera is: angles around the target and a distance in scene radii.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Degrees around the vertical axis (0: looking along −z).
    pub yaw: f64,
    /// Degrees above the horizon.
    pub pitch: f64,
    /// Distance from the target in scene radii (at 45°, 2.6 fits the scene's sphere).
    pub distance: f64,
    /// The target's offset from the scene's centre, in scene radii.
    pub pan: DVec3,
    /// Perspective or orthographic.
    pub orthographic: bool,
}

impl Default for Orbit {
    fn default() -> Self {
        Self {
            yaw: 20.0,
            pitch: 22.0,
            distance: 2.8,
            pan: DVec3::ZERO,
            orthographic: false,
        }
    }
}

/// The perspective camera's field of view, across the view's shorter side.
const FIELD_OF_VIEW_DEGREES: f64 = 45.0;

impl Orbit {
    /// The camera for a scene whose bounding sphere is (`center`, `radius`).
    pub fn camera(&self, center: DVec3, radius: f64) -> Camera {
        let (yaw, pitch) = (self.yaw.to_radians(), self.pitch.to_radians());
        let toward_eye = DVec3::new(
            yaw.sin() * pitch.cos(),
            pitch.sin(),
            yaw.cos() * pitch.cos(),
        );
        let target = center + self.pan * radius;
        let distance = self.distance * radius;
        let projection = if self.orthographic {
            // As much of the scene as the perspective camera shows at the target's distance.
            Projection::Orthographic {
                half_size: distance * (FIELD_OF_VIEW_DEGREES.to_radians() / 2.0).tan(),
            }
        } else {
            Projection::Perspective {
                fov: FIELD_OF_VIEW_DEGREES.to_radians(),
            }
        };
        Camera {
            eye: target + toward_eye * distance,
            target,
            up: DVec3::Y,
            projection,
        }
    }

    /// Orbits by a drag of `delta` points, pans by a drag with the secondary button, zooms
    /// by scrolling.
    fn control(&mut self, response: &egui::Response, ui: &egui::Ui) {
        let delta = response.drag_delta();
        let panning = response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
            || (response.dragged_by(egui::PointerButton::Primary)
                && ui.input(|i| i.modifiers.shift));
        if panning {
            let (yaw, pitch) = (self.yaw.to_radians(), self.pitch.to_radians());
            let right = DVec3::new(yaw.cos(), 0.0, -yaw.sin());
            let up = DVec3::new(
                -yaw.sin() * pitch.sin(),
                pitch.cos(),
                -yaw.cos() * pitch.sin(),
            );
            let scale = self.distance / response.rect.height().max(1.0) as f64;
            self.pan += (-right * delta.x as f64 + up * delta.y as f64) * scale;
        } else if response.dragged_by(egui::PointerButton::Primary) {
            self.yaw -= delta.x as f64 * 0.4;
            self.pitch = (self.pitch + delta.y as f64 * 0.4).clamp(-89.0, 89.0);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y) as f64;
            if scroll != 0.0 {
                self.distance = (self.distance * (-scroll * 0.002).exp()).clamp(0.05, 50.0);
            }
        }
    }
}

/// A 3D view: its camera and what it drew last.
#[derive(Default)]
pub struct View3d {
    /// The camera.
    pub orbit: Orbit,
    /// Set while a lesson drags something in the view: drags then do not move the camera.
    pub locked: bool,
    gpu: ViewGpu,
    /// Where the view was drawn last frame.
    rect: Option<Rect>,
}

/// What happened in the view this frame.
pub struct ViewResponse {
    /// The view's response.
    pub response: egui::Response,
    /// The camera used.
    pub camera: Camera,
    /// The pixel clicked this frame.
    pub clicked: Option<Pixel>,
    /// The ray through the centre of the pixel under the pointer, in world space: (origin,
    /// direction).
    pub hovered: Option<(DVec3, DVec3)>,
    /// World to screen (points), for the bounding sphere the view was drawn for.
    to_screen: Box<dyn Fn(DVec3) -> Option<egui::Pos2>>,
}

impl ViewResponse {
    /// Where `point` is drawn, if it is in front of the camera.
    pub fn to_screen(&self, point: DVec3) -> Option<egui::Pos2> {
        (self.to_screen)(point)
    }
}

/// A pixel of the view's picture: its column and row in a picture `width` × `height` pixels.
/// With the camera it names one ray (through its centre), whatever the window's size later.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Pixel {
    /// From the left, from 0.
    pub column: u32,
    /// From the top, from 0.
    pub row: u32,
    /// The picture's width in pixels.
    pub width: u32,
    /// The picture's height in pixels.
    pub height: u32,
}

impl Pixel {
    /// The ray through the pixel's centre, in world space: (origin, direction); the same
    /// ray the heat maps and `accelviz-cli bench --camera` trace for it
    /// ([`Camera::pixel_ray`]).
    pub fn ray(&self, camera: &Camera) -> (DVec3, DVec3) {
        camera.ray_through(
            f64::from(self.column) + 0.5,
            f64::from(self.row) + 0.5,
            self.width as usize,
            self.height as usize,
        )
    }

    /// The pixel as shared in a link: `column,row,width,height`.
    pub fn to_text(&self) -> String {
        format!(
            "{},{},{},{}",
            self.column, self.row, self.width, self.height
        )
    }

    /// Reads [`Pixel::to_text`]'s form.
    pub fn parse(text: &str) -> Result<Self, String> {
        let numbers: Vec<u32> = text
            .split(',')
            .map(|part| part.trim().parse::<u32>())
            .collect::<Result<_, _>>()
            .map_err(|_| {
                format!("pixel '{text}' is not four whole numbers: column,row,width,height")
            })?;
        let &[column, row, width, height] = numbers.as_slice() else {
            return Err(format!(
                "pixel '{text}' is not four numbers: column,row,width,height"
            ));
        };
        if column >= width || row >= height {
            return Err(format!(
                "pixel {column},{row} is outside a {width}×{height} picture"
            ));
        }
        Ok(Self {
            column,
            row,
            width,
            height,
        })
    }
}

/// World to screen for `camera` drawing into `rect`.
fn projector(
    camera: Camera,
    rect: Rect,
    sphere: (DVec3, f64),
) -> Box<dyn Fn(DVec3) -> Option<egui::Pos2>> {
    let (near, far) = camera.depth_range(sphere.0, sphere.1 * 1.5);
    let matrix = camera.view_projection(
        f64::from(rect.width().max(1.0)) / f64::from(rect.height().max(1.0)),
        near,
        far,
    );
    Box::new(move |point| {
        let clip = matrix * point.extend(1.0);
        (clip.w > 1e-12).then(|| {
            let ndc = clip.truncate() / clip.w;
            egui::pos2(
                rect.min.x + (ndc.x as f32 + 1.0) / 2.0 * rect.width(),
                rect.min.y + (1.0 - ndc.y as f32) / 2.0 * rect.height(),
            )
        })
    })
}

/// What a lesson gives the view to draw, and the layers' revisions. Geometry is given
/// relative to the sphere (see [`relative`]).
pub struct Content<'a> {
    /// The bounding sphere of everything shown: (centre, radius).
    pub sphere: (DVec3, f64),
    /// The mesh and its revision.
    pub mesh: (u64, &'a [DrawTriangle]),
    /// Highlighted triangles and their revision.
    pub highlights: (u64, &'a [DrawTriangle]),
    /// Boxes and their revision.
    pub boxes: (u64, &'a [Instance]),
    /// Segments and their revision.
    pub segments: (u64, &'a [Instance]),
    /// Quads (back to front) and their revision.
    pub quads: (u64, &'a [Instance]),
    /// How box edges behind surfaces are drawn.
    pub hidden_edges: HiddenEdges,
    /// Whether the mesh's triangle edges are drawn over it.
    pub wireframe: bool,
}

/// Line width in points: readable on a projector (3.6 pixels at lecture mode's 1.5 zoom), and
/// wider again in a theme with heavier strokes (high contrast).
const LINE_WIDTH_POINTS: f32 = 2.4;

/// How the view looks in the theme of `visuals`: the background of the app's other canvases
/// (dark in the dark theme: no glaring rectangle in a dark hall), and the line width in pixels
/// at `pixels_per_point`, scaled as the theme's strokes are.
pub fn look(visuals: &egui::Visuals, pixels_per_point: f32) -> ([u8; 3], f32) {
    let background = visuals.extreme_bg_color;
    let stroke_scale = visuals
        .widgets
        .noninteractive
        .fg_stroke
        .width
        .clamp(1.0, 1.5);
    (
        [background.r(), background.g(), background.b()],
        LINE_WIDTH_POINTS * stroke_scale * pixels_per_point,
    )
}

impl View3d {
    /// Draws the view filling `size` and handles its camera controls. Coordinates sent to
    /// the GPU are relative to the scene's centre, so f32 keeps the detail of a mesh far from
    /// the origin.
    pub fn ui(&mut self, ui: &mut egui::Ui, size: Vec2, content: &Content<'_>) -> ViewResponse {
        let (rect, response) = ui.allocate_exact_size(size, Sense::click_and_drag());
        self.rect = Some(rect);
        if !self.locked {
            self.orbit.control(&response, ui);
        }
        let (center, radius) = content.sphere;
        let radius = radius.max(1e-9);
        let camera = self.orbit.camera(center, radius);
        let pixels_per_point = ui.ctx().pixels_per_point();
        let pixels = [
            (rect.width() * pixels_per_point).round().max(1.0) as u32,
            (rect.height() * pixels_per_point).round().max(1.0) as u32,
        ];
        // The pixel under a point: a click traces through that pixel's centre, as the heat
        // maps' rays do, not through the corner the pointer's position falls on.
        let pixel_at = |position: egui::Pos2| {
            let x = ((position.x - rect.min.x) * pixels_per_point).floor();
            let y = ((position.y - rect.min.y) * pixels_per_point).floor();
            Pixel {
                column: (x.max(0.0) as u32).min(pixels[0] - 1),
                row: (y.max(0.0) as u32).min(pixels[1] - 1),
                width: pixels[0],
                height: pixels[1],
            }
        };
        let clicked = response
            .clicked()
            .then(|| response.interact_pointer_pos())
            .flatten()
            .map(pixel_at);
        let hovered = response
            .hover_pos()
            .map(|position| pixel_at(position).ray(&camera));

        match Gpu::of(ui.ctx()) {
            Some(gpu) => {
                // The camera in the units the geometry is sent in (see `relative`).
                let relative = Camera {
                    eye: (camera.eye - center) / radius,
                    target: (camera.target - center) / radius,
                    projection: match camera.projection {
                        Projection::Orthographic { half_size } => Projection::Orthographic {
                            half_size: half_size / radius,
                        },
                        perspective => perspective,
                    },
                    ..camera
                };
                let (near, far) = relative.depth_range(DVec3::ZERO, 1.5);
                let view_proj: Mat4 = relative
                    .view_projection(pixels[0] as f64 / pixels[1] as f64, near, far)
                    .as_mat4();
                let (background, line_width) = look(ui.visuals(), pixels_per_point);
                let scene = Scene3d {
                    view_proj,
                    light: camera.eye - camera.target,
                    mesh: content.mesh,
                    highlights: content.highlights,
                    boxes: content.boxes,
                    segments: content.segments,
                    quads: content.quads,
                    line_width,
                    hidden_edges: content.hidden_edges,
                    wireframe: content.wireframe,
                    background,
                };
                let texture = self.gpu.draw(&gpu, pixels, &scene);
                if !self.gpu.uploaded() {
                    ui.ctx().request_repaint();
                }
                ui.painter().image(
                    texture,
                    rect,
                    Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                    Color32::WHITE,
                );
            }
            None => {
                ui.painter()
                    .rect_filled(rect, 0.0, ui.visuals().extreme_bg_color);
                ui.painter().text(
                    rect.center(),
                    egui::Align2::CENTER_CENTER,
                    "The 3D view needs the wgpu renderer (WebGPU, WebGL2, Vulkan, Metal or DirectX).",
                    crate::canvas::font(ui.ctx(), 15.0),
                    ui.visuals().text_color(),
                );
            }
        }
        ViewResponse {
            response,
            camera,
            clicked,
            hovered,
            to_screen: projector(camera, rect, (center, radius)),
        }
    }

    /// A button that saves the view as a PNG (a download in the browser), for slides; the
    /// file comes out of [`View3d::take_export`] once the GPU has handed the picture back.
    pub fn save_button(&mut self, ui: &mut egui::Ui) {
        let pending = self.gpu.picture_pending();
        // While a mesh is on its way to the GPU the view shows the picture before it.
        let ready = self.gpu.uploaded();
        if ui
            .add_enabled(!pending && ready, egui::Button::new("save view as PNG"))
            .on_hover_text("The view as it is drawn now, for slides")
            .clicked()
            && let Some(gpu) = Gpu::of(ui.ctx())
        {
            self.gpu.request_picture(&gpu);
        }
        if pending {
            ui.ctx().request_repaint();
        }
    }

    /// The view's picture as a PNG file (`view.png`), once asked for and read back.
    pub fn take_export(&mut self) -> Option<Export> {
        let picture = self.gpu.take_picture()?;
        Some(picture.and_then(|(width, height, pixels)| {
            let bytes = accelviz_scene::output::encode_png(width, height, &pixels)?;
            Ok(("view.png".to_owned(), bytes))
        }))
    }

    /// Where the view was drawn last frame (points), if it was drawn.
    pub fn rect(&self) -> Option<Rect> {
        self.rect
    }

    /// Puts the camera back where it started.
    pub fn reset(&mut self) {
        self.orbit = Orbit::default();
    }
}

/// A point as the GPU gets it: relative to the scene's bounding sphere (`center`, `radius`)
/// in units of its radius, so f32 keeps a mesh's detail at any size and distance from the
/// origin (a mesh at 1e300 included).
pub fn relative(point: DVec3, (center, radius): (DVec3, f64)) -> [f32; 3] {
    ((point - center) / radius.max(f64::MIN_POSITIVE))
        .as_vec3()
        .to_array()
}

/// A layer's revision: a hash of what it was made from.
pub fn revision_of(key: impl std::hash::Hash) -> u64 {
    use std::hash::Hasher;
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    key.hash(&mut hasher);
    hasher.finish()
}
