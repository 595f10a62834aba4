//! The 2D canvas: a view (where the world sits on screen, zoom and pan) and the drawing of
//! the core's geometry: boxes, shapes, rays, points along a ray.

use accelviz_core::{Aabb, Shape};
use egui::{Align2, Color32, FontId, Pos2, Rect, Response, Sense, Stroke, StrokeKind, Vec2};
use glam::DVec2;

/// Where the world sits on screen: the world point at the canvas's centre and the zoom.
/// World y points up, screen y down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View2d {
    /// The world point shown at the centre of the canvas.
    pub center: DVec2,
    /// Screen points per world unit.
    pub points_per_unit: f64,
    /// Whether the view was set (fitted to a scene or moved by the user).
    pub placed: bool,
}

impl Default for View2d {
    fn default() -> Self {
        Self {
            center: DVec2::splat(50.0),
            points_per_unit: 4.0,
            placed: false,
        }
    }
}

impl View2d {
    /// A view showing all of `bounds` in `rect` with a margin.
    pub fn fitted(bounds: &Aabb<DVec2>, rect: Rect) -> Self {
        if bounds.is_empty() || !bounds.is_finite() {
            return Self {
                placed: true,
                ..Self::default()
            };
        }
        let extent = bounds.extent().max(DVec2::splat(1e-9));
        let usable = (rect.size() - Vec2::splat(48.0)).max(Vec2::splat(16.0));
        let points_per_unit = (usable.x as f64 / extent.x).min(usable.y as f64 / extent.y);
        Self {
            center: bounds.center(),
            points_per_unit,
            placed: true,
        }
    }
}

/// One frame of a canvas: the painter clipped to its rectangle, the view, and the response
/// that lessons read clicks and drags from.
pub struct Canvas {
    /// Paints inside the canvas only.
    pub painter: egui::Painter,
    /// The canvas on screen.
    pub rect: Rect,
    /// The view this frame.
    pub view: View2d,
    /// Clicks, drags and hovering on the canvas.
    pub response: Response,
}

/// Colours shared by every lesson, readable on the dark and the light theme.
pub mod palette {
    use egui::Color32;
    /// The ray.
    pub const RAY: Color32 = Color32::from_rgb(255, 170, 30);
    /// A hit point.
    pub const HIT: Color32 = Color32::from_rgb(60, 220, 90);
    /// Something rejected or missed.
    pub const MISS: Color32 = Color32::from_rgb(235, 70, 70);
    /// The thing being looked at now.
    pub const CURRENT: Color32 = Color32::from_rgb(80, 170, 255);
    /// A bounding box.
    pub const BOX: Color32 = Color32::from_rgb(120, 200, 255);
    /// A bounding sphere.
    pub const SPHERE: Color32 = Color32::from_rgb(230, 120, 255);
    /// Horizontal (x) quantities.
    pub const X_AXIS: Color32 = Color32::from_rgb(240, 90, 90);
    /// Vertical (y) quantities.
    pub const Y_AXIS: Color32 = Color32::from_rgb(90, 200, 110);
}

/// A colour per tree depth, cycling through hues so neighbouring depths differ.
pub fn depth_color(depth: usize) -> Color32 {
    let hue = (depth as f32 * 0.137 + 0.55).fract();
    egui::ecolor::Hsva::new(hue, 0.75, 0.95, 1.0).into()
}

impl Canvas {
    /// Allocates a canvas of `size`, lets the user zoom (scroll, pinch) and pan (drag with the
    /// secondary or middle button, or with the primary button when `pan_with_primary`), and
    /// fits the view to `fit_bounds` the first time.
    pub fn allocate(
        ui: &mut egui::Ui,
        size: Vec2,
        view: &mut View2d,
        fit_bounds: &Aabb<DVec2>,
        pan_with_primary: bool,
    ) -> Self {
        let (response, painter) = ui.allocate_painter(size, Sense::click_and_drag());
        let rect = response.rect;
        if !view.placed {
            *view = View2d::fitted(fit_bounds, rect);
        }
        painter.rect_filled(rect, 0.0, ui.visuals().extreme_bg_color);

        // Zoom about the pointer, so the point under it stays put.
        if let Some(hover) = response.hover_pos() {
            let (scroll, zoom) =
                ui.input(|input| (input.smooth_scroll_delta.y, input.zoom_delta()));
            let factor = (scroll as f64 * 0.002).exp() * zoom as f64;
            if factor != 1.0 {
                let before = to_world(view, rect, hover);
                view.points_per_unit = (view.points_per_unit * factor).clamp(1e-6, 1e9);
                let after = to_world(view, rect, hover);
                view.center += before - after;
            }
        }
        let panning = response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
            || (pan_with_primary && response.dragged_by(egui::PointerButton::Primary));
        if panning {
            let delta = response.drag_delta();
            view.center -= DVec2::new(delta.x as f64, -delta.y as f64) / view.points_per_unit;
        }
        Self {
            painter: painter.with_clip_rect(rect),
            rect,
            view: *view,
            response,
        }
    }

    /// Screen position of a world point.
    pub fn to_screen(&self, point: DVec2) -> Pos2 {
        to_screen(&self.view, self.rect, point)
    }

    /// World position of a screen point.
    pub fn to_world(&self, pos: Pos2) -> DVec2 {
        to_world(&self.view, self.rect, pos)
    }

    /// Screen rectangle of a world box.
    pub fn screen_rect(&self, bounds: &Aabb<DVec2>) -> Rect {
        Rect::from_two_pos(self.to_screen(bounds.min), self.to_screen(bounds.max))
    }

    /// World length of `points` screen points (for pick distances).
    pub fn world_length(&self, points: f32) -> f64 {
        points as f64 / self.view.points_per_unit
    }

    /// Whether a screen rectangle can be seen on the canvas (drawing what cannot is skipped,
    /// which keeps a frame of a 10k-shape scene cheap when zoomed in).
    fn visible(&self, rect: Rect) -> bool {
        self.rect.intersects(rect.expand(2.0))
    }

    /// Outlines a box, optionally filled.
    pub fn box_outline(&self, bounds: &Aabb<DVec2>, stroke: Stroke, fill: Option<Color32>) {
        if bounds.is_empty() || !self.visible(self.screen_rect(bounds)) {
            return;
        }
        // A flat box still shows: at least one point wide on screen.
        let rect =
            self.screen_rect(bounds)
                .expand2(Vec2::new(0.0, 0.0))
                .union(Rect::from_center_size(
                    self.to_screen(bounds.center()),
                    Vec2::splat(1.0),
                ));
        if let Some(fill) = fill {
            self.painter.rect_filled(rect, 0.0, fill);
        }
        self.painter
            .rect_stroke(rect, 0.0, stroke, StrokeKind::Middle);
    }

    /// A split: the line `axis = position` across `cell` (a kD plane, or a candidate split).
    pub fn split_line(&self, cell: &Aabb<DVec2>, axis: usize, position: f64, stroke: Stroke) {
        let [from, to] = self.split_ends(cell, axis, position);
        self.painter.line_segment([from, to], stroke);
    }

    fn split_ends(&self, cell: &Aabb<DVec2>, axis: usize, position: f64) -> [Pos2; 2] {
        let (from, to) = if axis == 0 {
            (
                DVec2::new(position, cell.min.y),
                DVec2::new(position, cell.max.y),
            )
        } else {
            (
                DVec2::new(cell.min.x, position),
                DVec2::new(cell.max.x, position),
            )
        };
        [self.to_screen(from), self.to_screen(to)]
    }

    /// Many box outlines: one by one when few, as one batched mesh when many.
    pub fn box_outlines(&self, boxes: impl ExactSizeIterator<Item = (Aabb<DVec2>, Stroke)>) {
        if boxes.len() <= BATCH_ABOVE {
            for (bounds, stroke) in boxes {
                self.box_outline(&bounds, stroke, None);
            }
            return;
        }
        let mut batch = Batch::default();
        batch.reserve(boxes.len() * 8, boxes.len() * 8);
        for (bounds, stroke) in boxes {
            self.batch_box(&mut batch, &bounds, stroke.width, stroke.color);
        }
        self.draw_batch(batch);
    }

    /// Many split lines (`cell`, `axis`, `position`): one by one when few, batched when many.
    pub fn split_lines(
        &self,
        lines: impl ExactSizeIterator<Item = (Aabb<DVec2>, usize, f64, Stroke)>,
    ) {
        if lines.len() <= BATCH_ABOVE {
            for (cell, axis, position, stroke) in lines {
                self.split_line(&cell, axis, position, stroke);
            }
            return;
        }
        let mut batch = Batch::default();
        batch.reserve(lines.len() * 4, lines.len() * 2);
        for (cell, axis, position, stroke) in lines {
            let [from, to] = self.split_ends(&cell, axis, position);
            if self.visible(Rect::from_two_pos(from, to)) {
                batch.line(from, to, stroke.width, stroke.color);
            }
        }
        self.draw_batch(batch);
    }

    /// Draws a shape: filled disc or box, or a thick segment. A shape a few points across is
    /// drawn as a filled square: it looks the same, with a fraction of the triangles.
    pub fn shape(&self, shape: &Shape<DVec2>, fill: Color32, stroke: Stroke) {
        let screen = self.screen_rect(&shape.bounds());
        if !self.visible(screen) {
            return;
        }
        if screen.width().max(screen.height()) < 4.0 && !matches!(shape, Shape::Segment(_)) {
            let dot = Rect::from_center_size(screen.center(), screen.size().max(Vec2::splat(1.5)));
            self.painter.rect_filled(dot, 0.0, stroke.color);
            return;
        }
        match shape {
            Shape::Sphere(sphere) => {
                let center = self.to_screen(sphere.center);
                let radius = (sphere.radius * self.view.points_per_unit) as f32;
                self.painter.circle_filled(center, radius.max(1.0), fill);
                self.painter.circle_stroke(center, radius.max(1.0), stroke);
            }
            Shape::Box(bounds) => self.box_outline(bounds, stroke, Some(fill)),
            Shape::Segment([from, to]) => {
                let thick = Stroke::new(stroke.width.max(2.5), fill);
                self.painter
                    .line_segment([self.to_screen(*from), self.to_screen(*to)], thick);
            }
        }
    }

    /// Draws a ray from its origin to `t_end` (clipped to the canvas), with an arrow head at
    /// `origin + direction` that the user can drag.
    pub fn ray(&self, origin: DVec2, direction: DVec2, t_end: f64, stroke: Stroke) {
        let start = self.to_screen(origin);
        let end = self.to_screen(origin + direction * self.clip_t(origin, direction, t_end));
        self.painter.line_segment([start, end], stroke);
        self.painter.circle_filled(start, 5.0, stroke.color);
        let head = self.to_screen(origin + direction);
        let back = (start - head).normalized() * 12.0;
        let side = Vec2::new(-back.y, back.x) * 0.5;
        self.painter.add(egui::Shape::convex_polygon(
            vec![head, head + back + side, head + back - side],
            stroke.color,
            Stroke::NONE,
        ));
    }

    /// The largest `t ≤ t_end` that still lies near the visible canvas (so an infinite ray
    /// draws as a finite line).
    pub fn clip_t(&self, origin: DVec2, direction: DVec2, t_end: f64) -> f64 {
        let visible = Aabb::new(
            self.to_world(self.rect.left_bottom()),
            self.to_world(self.rect.right_top()),
        );
        let reach = (visible.extent().length() + (origin - visible.center()).length()) * 2.0;
        t_end.min(reach / direction.length().max(1e-300))
    }

    /// A tick across the ray at parameter `t` with a label `label_offset` tick-lengths to its
    /// left (negative: to its right), so labels at nearby `t` can sit on opposite sides.
    pub fn ray_mark(
        &self,
        origin: DVec2,
        direction: DVec2,
        t: f64,
        color: Color32,
        label: &str,
        label_offset: f32,
    ) {
        if !t.is_finite() {
            return;
        }
        let point = self.to_screen(origin + direction * t);
        let along = self.to_screen(origin + direction) - self.to_screen(origin);
        let normal = Vec2::new(-along.y, along.x).normalized() * 7.0;
        self.painter
            .line_segment([point - normal, point + normal], Stroke::new(2.5, color));
        if !label.is_empty() {
            self.painter.text(
                point + normal * label_offset,
                Align2::CENTER_CENTER,
                label,
                FontId::proportional(13.0),
                color,
            );
        }
    }

    /// A label at a world point.
    pub fn label(&self, at: DVec2, text: &str, color: Color32) {
        self.painter.text(
            self.to_screen(at),
            Align2::LEFT_BOTTOM,
            text,
            FontId::proportional(13.0),
            color,
        );
    }

    /// A caption in the canvas's top-left corner, one line per entry.
    pub fn caption(&self, lines: &[(String, Color32)]) {
        let mut pos = self.rect.left_top() + Vec2::new(10.0, 8.0);
        for (text, color) in lines {
            let galley =
                self.painter
                    .layout_no_wrap(text.clone(), FontId::proportional(14.0), *color);
            let backing = Rect::from_min_size(pos, galley.size()).expand(3.0);
            self.painter
                .rect_filled(backing, 3.0, Color32::from_black_alpha(140));
            self.painter.galley(pos, galley, *color);
            pos.y += 20.0;
        }
    }
}

/// Above this many shapes, boxes or lines, a lesson draws them as one batched mesh.
pub const BATCH_ABOVE: usize = 300;

/// Many simple shapes in one mesh, drawn with one paint call: what a frame with thousands of
/// primitives and boxes can afford (egui would otherwise tessellate each with anti-aliased
/// edges). Lessons use it above a few hundred shapes; below that, each shape is drawn on its own.
#[derive(Default)]
pub struct Batch {
    mesh: egui::Mesh,
}

impl Batch {
    /// A filled rectangle.
    pub fn rect(&mut self, rect: Rect, color: Color32) {
        self.mesh.add_colored_rect(rect, color);
    }

    /// A line of `width` points as one quad.
    pub fn line(&mut self, from: Pos2, to: Pos2, width: f32, color: Color32) {
        let along = to - from;
        let across = Vec2::new(-along.y, along.x).normalized() * (width * 0.5);
        let first = self.mesh.vertices.len() as u32;
        for pos in [from - across, from + across, to + across, to - across] {
            self.mesh.colored_vertex(pos, color);
        }
        self.mesh.add_triangle(first, first + 1, first + 2);
        self.mesh.add_triangle(first, first + 2, first + 3);
    }

    /// Room for `vertices` more vertices and `triangles` more triangles, so a large batch is
    /// allocated once rather than grown (growing dominated a 10k-shape frame).
    pub fn reserve(&mut self, vertices: usize, triangles: usize) {
        self.mesh.vertices.reserve(vertices);
        self.mesh.indices.reserve(triangles * 3);
    }

    /// A rectangle's outline of `width` points: a frame of eight vertices, the outer corners
    /// and the inner ones, and eight triangles.
    pub fn rect_outline(&mut self, rect: Rect, width: f32, color: Color32) {
        let half = width * 0.5;
        let outer = rect.expand(half);
        let inner = rect.shrink(half.min(rect.width() * 0.5).min(rect.height() * 0.5));
        let first = self.mesh.vertices.len() as u32;
        for frame in [outer, inner] {
            for corner in [
                frame.left_top(),
                frame.right_top(),
                frame.right_bottom(),
                frame.left_bottom(),
            ] {
                self.mesh.colored_vertex(corner, color);
            }
        }
        for side in 0..4 {
            let (outer_a, outer_b) = (first + side, first + (side + 1) % 4);
            let (inner_a, inner_b) = (outer_a + 4, outer_b + 4);
            self.mesh.add_triangle(outer_a, outer_b, inner_b);
            self.mesh.add_triangle(outer_a, inner_b, inner_a);
        }
    }

    /// A filled disc as a fan, with more sides the larger it is.
    pub fn disc(&mut self, center: Pos2, radius: f32, color: Color32) {
        let sides = (radius * 1.5).clamp(6.0, 40.0) as u32;
        let first = self.mesh.vertices.len() as u32;
        self.mesh.colored_vertex(center, color);
        for side in 0..sides {
            let angle = side as f32 / sides as f32 * std::f32::consts::TAU;
            self.mesh
                .colored_vertex(center + Vec2::new(angle.cos(), angle.sin()) * radius, color);
        }
        for side in 0..sides {
            self.mesh
                .add_triangle(first, first + 1 + side, first + 1 + (side + 1) % sides);
        }
    }
}

impl Canvas {
    /// Adds a shape to a batch (culled when off the canvas).
    pub fn batch_shape(&self, batch: &mut Batch, shape: &Shape<DVec2>, color: Color32) {
        let screen = self.screen_rect(&shape.bounds());
        if !self.visible(screen) {
            return;
        }
        match shape {
            Shape::Sphere(sphere) if screen.width() >= 4.0 => batch.disc(
                self.to_screen(sphere.center),
                (sphere.radius * self.view.points_per_unit) as f32,
                color,
            ),
            Shape::Segment([from, to]) => {
                batch.line(self.to_screen(*from), self.to_screen(*to), 2.0, color)
            }
            _ => batch.rect(
                screen.union(Rect::from_center_size(screen.center(), Vec2::splat(1.5))),
                color,
            ),
        }
    }

    /// Adds a box outline to a batch (culled when off the canvas or under a point across).
    pub fn batch_box(&self, batch: &mut Batch, bounds: &Aabb<DVec2>, width: f32, color: Color32) {
        let screen = self.screen_rect(bounds);
        if bounds.is_empty() || !self.visible(screen) || screen.width().max(screen.height()) < 1.0 {
            return;
        }
        batch.rect_outline(screen, width, color);
    }

    /// Paints a batch.
    pub fn draw_batch(&self, batch: Batch) {
        if !batch.mesh.is_empty() {
            self.painter.add(egui::Shape::mesh(batch.mesh));
        }
    }
}

fn to_screen(view: &View2d, rect: Rect, point: DVec2) -> Pos2 {
    let offset = (point - view.center) * view.points_per_unit;
    let pos = rect.center() + Vec2::new(offset.x as f32, -offset.y as f32);
    // Keep far-away points representable (egui works in f32 screen points).
    Pos2::new(pos.x.clamp(-1e6, 1e6), pos.y.clamp(-1e6, 1e6))
}

fn to_world(view: &View2d, rect: Rect, pos: Pos2) -> DVec2 {
    let offset = pos - rect.center();
    view.center + DVec2::new(offset.x as f64, -offset.y as f64) / view.points_per_unit
}

/// A semi-transparent version of a colour.
pub fn faded(color: Color32, alpha: u8) -> Color32 {
    Color32::from_rgba_unmultiplied(color.r(), color.g(), color.b(), alpha)
}
