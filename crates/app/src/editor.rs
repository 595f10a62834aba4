//! Scene editing on the canvas: drag the ray's origin and head, move, add and delete shapes,
//! resize the selected one, and regenerate the scene from a seeded generator. Every change
//! bumps `revision`, which is how lessons know to rebuild their structures.

use accelviz_core::{Aabb, Ray, RayError, Shape, Sphere};
use accelviz_scene::document::{GeneratorEntry, LayoutEntry, Scene2d};
use accelviz_scene::scene2d::generate;
use egui::{Color32, Key, Stroke, Ui};
use glam::DVec2;

use crate::canvas::{Canvas, View2d, palette};

/// What a primary-button drag on the canvas does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Move shapes (or pan on empty space); click selects.
    Move,
    /// Drag out a new disc.
    AddDisc,
    /// Drag out a new box.
    AddBox,
    /// Drag out a new segment.
    AddSegment,
    /// Click a shape to delete it.
    Delete,
}

/// What is being dragged.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Drag {
    RayOrigin,
    RayHead,
    /// A whole shape, grabbed at `grab` (world offset from where it was).
    Shape {
        index: usize,
        last: DVec2,
    },
    /// One end of a segment, one corner of a box or a disc's centre or rim; `anchor` is the
    /// other corner, which stays put while a box is resized.
    Handle {
        index: usize,
        handle: usize,
        anchor: DVec2,
    },
    /// The view.
    Pan,
}

/// Which parts of the scene a lesson lets the user edit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Editing {
    /// The ray's origin and head can be dragged.
    pub ray: bool,
    /// Shapes can be moved, added and deleted.
    pub shapes: bool,
    /// The scene can be replaced by a generated one.
    pub generator: bool,
}

impl Editing {
    /// Everything: the ray, the shapes, the generator.
    pub const ALL: Self = Self {
        ray: true,
        shapes: true,
        generator: true,
    };
    /// The ray and the shapes by hand (the scene is a fixed exhibit, not a generated one).
    pub const BY_HAND: Self = Self {
        ray: true,
        shapes: true,
        generator: false,
    };
    /// The shapes and the generator (lessons about building, with no ray).
    pub const SHAPES: Self = Self {
        ray: false,
        shapes: true,
        generator: true,
    };
}

/// Where a scene's shapes came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneOrigin {
    /// The lesson file.
    Lesson,
    /// A scene file the user opened.
    File,
    /// The generator.
    Generated,
    /// Changed by hand since.
    Edited,
}

/// A scene being looked at and edited.
#[derive(Clone, Debug)]
pub struct EditableScene {
    /// The scene.
    pub scene: Scene2d,
    /// Bumped on every change.
    pub revision: u64,
    /// Bumped when the shapes or the settings change (not when only the ray moves): what
    /// structures are rebuilt for.
    pub shapes_revision: u64,
    /// Where the shapes came from, for the toolbar: the lesson, a file, the generator, edits.
    pub origin: SceneOrigin,
    /// Set when the generator made new shapes, until the lesson places its ray.
    generated: bool,
    /// The current tool.
    pub tool: Tool,
    /// The selected shape.
    pub selected: Option<usize>,
    /// The canvas view.
    pub view: View2d,
    /// What may be edited.
    pub editing: Editing,
    drag: Option<Drag>,
    /// The canvas rectangle and view of the last frame, to place world points on screen.
    last_canvas: Option<(egui::Rect, View2d)>,
    /// The generator's controls (kept when the shapes are edited by hand).
    pub generator: GeneratorEntry,
}

/// The most shapes the generator makes: the largest scene every lesson is tested with.
pub const MAX_GENERATED: usize = 100_000;

/// Pick distance in screen points.
const PICK_POINTS: f32 = 10.0;

impl EditableScene {
    /// A scene with the given editing rights.
    pub fn new(scene: Scene2d, editing: Editing) -> Self {
        // A scene written out shape by shape offers to generate as many shapes as it has.
        let generator = scene.generator.unwrap_or(GeneratorEntry {
            layout: LayoutEntry::Uniform,
            count: scene.shapes.shapes.len().max(1),
            seed: 1,
        });
        let origin = if scene.is_generated() {
            SceneOrigin::Generated
        } else {
            SceneOrigin::Lesson
        };
        Self {
            scene,
            revision: 1,
            shapes_revision: 1,
            origin,
            generated: false,
            tool: Tool::Move,
            selected: None,
            view: View2d::default(),
            editing,
            drag: None,
            last_canvas: None,
            generator,
        }
    }

    /// Replaces the scene (opened from a file or a preset) and refits the view.
    pub fn replace(&mut self, scene: Scene2d) {
        // A scene written out shape by shape offers to generate as many shapes, uniformly, as
        // a new one does: the bar must not name the generator of the scene before it (the
        // recap's dust in a room showed the teapot in a stadium's).
        self.generator = scene.generator.unwrap_or(GeneratorEntry {
            layout: LayoutEntry::Uniform,
            count: scene.shapes.shapes.len().max(1),
            seed: 1,
        });
        self.scene = scene;
        self.selected = None;
        self.drag = None;
        self.view.placed = false;
        self.touch();
    }

    /// Marks a change of the shapes or settings made from outside (a slider).
    pub fn touch(&mut self) {
        self.revision += 1;
        self.shapes_revision += 1;
    }

    /// Marks a change of the ray made from outside (a preset ray).
    pub fn touch_ray(&mut self) {
        self.revision += 1;
    }

    /// Whether the generator made new shapes since the last call: the lesson then places the
    /// ray where it shows what the lesson is about.
    pub fn take_generated(&mut self) -> bool {
        std::mem::take(&mut self.generated)
    }

    /// Where the scene's shapes came from, in words ("from the lesson", "generated: …").
    pub fn origin_text(&self) -> String {
        match self.origin {
            SceneOrigin::Lesson => "the lesson's scene".to_owned(),
            SceneOrigin::File => "opened from a file".to_owned(),
            SceneOrigin::Generated => {
                let generator = self.scene.generator.unwrap_or(self.generator);
                format!(
                    "generated: {}, seed {}",
                    layout_name(generator.layout),
                    generator.seed
                )
            }
            SceneOrigin::Edited => "edited by hand".to_owned(),
        }
    }

    /// The ray, or why there is none (its head sits on its origin).
    pub fn ray(&self) -> Result<Ray<DVec2>, RayError> {
        Ray::try_new(
            self.scene.ray_origin,
            self.scene.ray_toward - self.scene.ray_origin,
        )
    }

    /// Where the canvas was on screen in the last frame.
    pub fn last_canvas_rect(&self) -> Option<egui::Rect> {
        self.last_canvas.map(|(rect, _)| rect)
    }

    /// Where a world point was on screen in the last frame (for tests and tooltips).
    pub fn screen_position(&self, world: DVec2) -> Option<egui::Pos2> {
        let (rect, view) = self.last_canvas?;
        let offset = (world - view.center) * view.points_per_unit;
        Some(rect.center() + egui::Vec2::new(offset.x as f32, -offset.y as f32))
    }

    /// The box around every shape, and the ray's origin and head when the lesson has a ray:
    /// what "fit" shows.
    pub fn bounds(&self) -> Aabb<DVec2> {
        let shapes = self.scene.shapes.bounding_box();
        if self.editing.ray {
            shapes
                .grown(self.scene.ray_origin)
                .grown(self.scene.ray_toward)
        } else {
            shapes
        }
    }

    /// The toolbar above the canvas: tools, generator, fit. One line at the app's default size
    /// (the shape count is written on the canvas, [`draw_footer`](Self::draw_footer)); it wraps
    /// rather than widen the canvas's panel past the window when the app is scaled up.
    pub fn toolbar_ui(&mut self, ui: &mut Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.spacing_mut().item_spacing.x = 6.0;
            if self.editing.shapes {
                for (tool, label, hint) in [
                    (
                        Tool::Move,
                        "move",
                        "Drag shapes; drag empty space to pan; click to select",
                    ),
                    (Tool::AddDisc, "+ disc", "Drag to add a disc"),
                    (Tool::AddBox, "+ box", "Drag to add a box"),
                    (Tool::AddSegment, "+ segment", "Drag to add a segment"),
                    (
                        Tool::Delete,
                        "delete",
                        "Click a shape to delete it (or select it and press Delete)",
                    ),
                ] {
                    ui.selectable_value(&mut self.tool, tool, label)
                        .on_hover_text(hint);
                }
                ui.separator();
            }
            if self.editing.generator {
                self.generator_ui(ui);
                ui.separator();
            }
            if ui
                .button("fit")
                .on_hover_text("Fit the view to the scene")
                .clicked()
            {
                self.view.placed = false;
            }
        });
    }

    fn generator_ui(&mut self, ui: &mut Ui) {
        egui::ComboBox::from_id_salt("layout")
            .selected_text(layout_name(self.generator.layout))
            .width(84.0)
            .show_ui(ui, |ui| {
                for layout in [
                    LayoutEntry::Uniform,
                    LayoutEntry::Clustered,
                    LayoutEntry::Teapot,
                ] {
                    ui.selectable_value(&mut self.generator.layout, layout, layout_name(layout));
                }
            })
            .response
            .on_hover_text("Where the generated shapes go");
        ui.add(
            egui::DragValue::new(&mut self.generator.count)
                .range(1..=MAX_GENERATED)
                .prefix("n "),
        )
        .on_hover_text("How many shapes to generate (the scene now has its own count, below)");
        ui.add(egui::DragValue::new(&mut self.generator.seed).prefix("seed "))
            .on_hover_text("The same seed gives the same scene");
        if ui
            .button("generate")
            .on_hover_text("Replace the shapes with n generated ones")
            .clicked()
        {
            self.generate();
        }
    }

    /// Replaces the shapes with the generator's; the ray goes from outside the lower left
    /// across the scene until the lesson places it (see [`take_generated`](Self::take_generated)).
    pub fn generate(&mut self) {
        self.scene.shapes = generate(
            self.generator.layout.into(),
            self.generator.count,
            self.generator.seed,
        );
        self.scene.generator = Some(self.generator);
        let bounds = self.bounds();
        self.scene.ray_origin = bounds.min - bounds.extent() * 0.05;
        self.scene.ray_toward = self.scene.ray_origin + bounds.extent() * 0.2;
        self.selected = None;
        self.view.placed = false;
        self.origin = SceneOrigin::Generated;
        self.generated = true;
        self.touch();
    }

    /// The scene's shape count and where it came from, at the canvas's bottom right.
    pub fn draw_footer(&self, canvas: &Canvas) {
        canvas.note_right(&format!(
            "{} · {}",
            accelviz_core::format::counted(self.scene.shapes.shapes.len(), "shape", "shapes"),
            self.origin_text()
        ));
    }

    /// The toolbar, then a canvas filling the space left (fitted to the scene and `extra`
    /// the first time), with the user's edits applied. What most lessons start their canvas
    /// with; they rebuild afterwards if the revision moved.
    pub fn canvas_ui(&mut self, ui: &mut Ui, extra: Option<Aabb<DVec2>>) -> Canvas {
        self.toolbar_ui(ui);
        let bounds = extra.map_or(self.bounds(), |extra| self.bounds().union(extra));
        let canvas = Canvas::allocate(ui, ui.available_size(), &mut self.view, &bounds, false);
        self.interact(ui, &canvas);
        canvas
    }

    /// Handles the user's clicks and drags on `canvas`; returns whether the scene changed.
    pub fn interact(&mut self, ui: &Ui, canvas: &Canvas) -> bool {
        self.last_canvas = Some((canvas.rect, canvas.view));
        let response = &canvas.response;
        let before = self.revision;
        let pick = canvas.world_length(PICK_POINTS);
        if response.drag_started_by(egui::PointerButton::Primary)
            && let Some(pos) = response.interact_pointer_pos()
        {
            let press = ui
                .input(|input| input.pointer.press_origin())
                .unwrap_or(pos);
            let at = canvas.to_world(press);
            self.drag = Some(self.start_drag(at, pick));
            if let Some(Drag::Handle { index, .. }) = self.drag {
                self.selected = Some(index);
            }
        }
        if let (Some(drag), Some(pos)) = (self.drag, response.interact_pointer_pos())
            && response.dragged_by(egui::PointerButton::Primary)
        {
            let at = canvas.to_world(pos);
            self.continue_drag(drag, at, canvas);
        }
        if response.drag_stopped() {
            self.drag = None;
        }
        if response.clicked()
            && let Some(pos) = response.interact_pointer_pos()
        {
            let hit = self.shape_at(canvas.to_world(pos), pick);
            match self.tool {
                Tool::Delete if self.editing.shapes => {
                    if let Some(index) = hit {
                        self.delete(index);
                    }
                }
                _ => self.selected = hit,
            }
        }
        let delete_pressed = !ui.ctx().egui_wants_keyboard_input()
            && ui.input(|input| input.key_pressed(Key::Delete));
        if delete_pressed
            && self.editing.shapes
            && let Some(index) = self.selected
        {
            self.delete(index);
        }
        self.revision != before
    }

    fn delete(&mut self, index: usize) {
        if index < self.scene.shapes.shapes.len() && self.scene.shapes.shapes.len() > 1 {
            self.scene.shapes.shapes.remove(index);
            self.selected = None;
            self.edited();
        }
    }

    fn start_drag(&mut self, at: DVec2, pick: f64) -> Drag {
        if self.editing.ray {
            if at.distance(self.scene.ray_toward) <= pick {
                return Drag::RayHead;
            }
            if at.distance(self.scene.ray_origin) <= pick {
                return Drag::RayOrigin;
            }
        }
        if !self.editing.shapes {
            return Drag::Pan;
        }
        if let Some(index) = self.selected
            && let Some(handle) = self
                .handles(index)
                .iter()
                .position(|h| h.distance(at) <= pick)
        {
            let anchor = self.handles(index)[1 - handle.min(1)];
            return Drag::Handle {
                index,
                handle,
                anchor,
            };
        }
        let new_shape = match self.tool {
            Tool::Move | Tool::Delete => {
                return match self.shape_at(at, pick) {
                    Some(index) if self.tool == Tool::Move => {
                        self.selected = Some(index);
                        Drag::Shape { index, last: at }
                    }
                    _ => Drag::Pan,
                };
            }
            Tool::AddDisc => Shape::Sphere(Sphere {
                center: at,
                radius: pick * 0.5,
            }),
            Tool::AddBox => Shape::Box(Aabb::new(at, at)),
            Tool::AddSegment => Shape::Segment([at, at]),
        };
        self.scene.shapes.shapes.push(new_shape);
        let index = self.scene.shapes.shapes.len() - 1;
        self.selected = Some(index);
        self.edited();
        Drag::Handle {
            index,
            handle: 1,
            anchor: at,
        }
    }

    fn continue_drag(&mut self, drag: Drag, at: DVec2, canvas: &Canvas) {
        match drag {
            Drag::RayOrigin => {
                // Move the whole ray, so its direction stays as it was.
                let offset = at - self.scene.ray_origin;
                self.scene.ray_origin = at;
                self.scene.ray_toward += offset;
                self.touch_ray();
                return;
            }
            Drag::RayHead => {
                self.scene.ray_toward = at;
                self.touch_ray();
                return;
            }
            Drag::Shape { index, last } => {
                let offset = at - last;
                if let Some(shape) = self.scene.shapes.shapes.get_mut(index) {
                    *shape = moved(shape, offset);
                }
                self.drag = Some(Drag::Shape { index, last: at });
            }
            Drag::Handle {
                index,
                handle,
                anchor,
            } => {
                if let Some(shape) = self.scene.shapes.shapes.get_mut(index) {
                    *shape = with_handle(shape, handle, at, anchor);
                }
            }
            Drag::Pan => {
                let delta = canvas.response.drag_delta();
                self.view.fitted_size = None;
                self.view.center -=
                    DVec2::new(delta.x as f64, -delta.y as f64) / self.view.points_per_unit;
                return;
            }
        }
        self.edited();
    }

    /// The shapes were changed by hand.
    fn edited(&mut self) {
        self.origin = SceneOrigin::Edited;
        self.scene.generator = None;
        self.touch();
    }

    /// The topmost shape under a world point.
    pub fn shape_at(&self, at: DVec2, pick: f64) -> Option<usize> {
        self.scene
            .shapes
            .shapes
            .iter()
            .rposition(|shape| distance_to_shape(shape, at) <= pick * 0.5)
    }

    /// Handles of a shape: a box's corners (min, max), a segment's ends, a disc's rim point.
    fn handles(&self, index: usize) -> Vec<DVec2> {
        match self.scene.shapes.shapes.get(index) {
            Some(Shape::Box(bounds)) => vec![bounds.min, bounds.max],
            Some(Shape::Segment(ends)) => ends.to_vec(),
            Some(Shape::Sphere(sphere)) => {
                vec![
                    sphere.center,
                    sphere.center + DVec2::new(sphere.radius, 0.0),
                ]
            }
            None => Vec::new(),
        }
    }

    /// Draws the selection and its handles, and the ray's handles.
    pub fn draw_handles(&self, canvas: &Canvas) {
        if let Some(index) = self.selected {
            if let Some(shape) = self.scene.shapes.shapes.get(index) {
                canvas.box_outline(&shape.bounds(), Stroke::new(1.5, palette::CURRENT), None);
            }
            if self.editing.shapes {
                for handle in self.handles(index) {
                    canvas.painter.circle_stroke(
                        canvas.to_screen(handle),
                        5.0,
                        Stroke::new(2.0, palette::CURRENT),
                    );
                }
            }
        }
        if self.editing.ray {
            canvas.painter.circle_stroke(
                canvas.to_screen(self.scene.ray_origin),
                8.0,
                Stroke::new(1.5, Color32::from_white_alpha(120)),
            );
        }
    }
}

fn layout_name(layout: LayoutEntry) -> &'static str {
    match layout {
        LayoutEntry::Uniform => "uniform",
        LayoutEntry::Clustered => "clustered",
        LayoutEntry::Teapot => "teapot in a stadium",
    }
}

fn moved(shape: &Shape<DVec2>, offset: DVec2) -> Shape<DVec2> {
    match *shape {
        Shape::Sphere(sphere) => Shape::Sphere(Sphere {
            center: sphere.center + offset,
            radius: sphere.radius,
        }),
        Shape::Box(bounds) => Shape::Box(Aabb::new(bounds.min + offset, bounds.max + offset)),
        Shape::Segment([from, to]) => Shape::Segment([from + offset, to + offset]),
    }
}

/// The shape with one handle moved to `at` (a box spans `anchor` to `at`, a disc keeps a
/// radius).
fn with_handle(shape: &Shape<DVec2>, handle: usize, at: DVec2, anchor: DVec2) -> Shape<DVec2> {
    match *shape {
        Shape::Sphere(sphere) if handle == 0 => Shape::Sphere(Sphere {
            center: at,
            radius: sphere.radius,
        }),
        Shape::Sphere(sphere) => Shape::Sphere(Sphere {
            center: sphere.center,
            radius: sphere.center.distance(at).max(1e-6),
        }),
        Shape::Box(_) => Shape::Box(Aabb::new(anchor.min(at), anchor.max(at))),
        Shape::Segment(mut ends) => {
            ends[handle.min(1)] = at;
            Shape::Segment(ends)
        }
    }
}

/// Distance from a point to a shape (0 inside).
pub fn distance_to_shape(shape: &Shape<DVec2>, at: DVec2) -> f64 {
    match shape {
        Shape::Sphere(sphere) => (at.distance(sphere.center) - sphere.radius).max(0.0),
        Shape::Box(bounds) => (at.clamp(bounds.min, bounds.max) - at).length(),
        Shape::Segment([from, to]) => {
            let edge = *to - *from;
            let along = if edge == DVec2::ZERO {
                0.0
            } else {
                ((at - *from).dot(edge) / edge.length_squared()).clamp(0.0, 1.0)
            };
            at.distance(*from + edge * along)
        }
    }
}
