//! The 2D canvas: a view (where the world sits on screen, zoom and pan) and the drawing of
//! the core's geometry: boxes, shapes, rays, points along a ray.

use std::sync::Arc;

use accelviz_core::{Aabb, Shape};
use egui::{Align2, Color32, FontId, Pos2, Rect, Response, Sense, Stroke, StrokeKind, Vec2};
use glam::DVec2;

/// The plate under canvas text: dark enough that a label's colour reads at 4.5:1 or better
/// whatever is drawn below, white included (a green label over a green hit shape, a red one
/// on the light theme's white canvas): the contrast test composites it over white.
pub const PLATE: Color32 = Color32::from_black_alpha(235);

/// WCAG's relative luminance of an sRGB colour (its alpha ignored).
pub fn luminance(color: Color32) -> f32 {
    let linear = |channel: u8| {
        let c = f32::from(channel) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    0.2126 * linear(color.r()) + 0.7152 * linear(color.g()) + 0.0722 * linear(color.b())
}

/// WCAG's contrast ratio of two opaque colours: 1 (the same) to 21 (black on white); text
/// wants 4.5 or more.
pub fn contrast_ratio(a: Color32, b: Color32) -> f32 {
    let (la, lb) = (luminance(a), luminance(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

/// `color`, made lighter (on a dark `background`) or darker (on a light one) just enough
/// for text in it to read at 4.5:1: the palette's colours as panel text in every theme (red
/// on the light theme's white is 3.7:1 as it is).
pub fn readable_on(color: Color32, background: Color32) -> Color32 {
    let toward = if luminance(background) < 0.18 {
        Color32::WHITE
    } else {
        Color32::BLACK
    };
    let color = Color32::from_rgb(color.r(), color.g(), color.b());
    (0..=20)
        .map(|step| color.lerp_to_gamma(toward, step as f32 / 20.0))
        .find(|candidate| contrast_ratio(*candidate, background) >= 4.5)
        .unwrap_or(toward)
}

/// [`readable_on`] the panel `ui` draws on.
pub fn readable(ui: &egui::Ui, color: Color32) -> Color32 {
    readable_on(color, ui.visuals().panel_fill)
}

/// [`readable`] in a striped table: on its stripes, the darker of its rows in the light
/// themes and the lighter in the dark one, so on both (the red leak counts of lesson 16 were
/// 3.2:1 on the light theme's stripes).
pub fn readable_in_table(ui: &egui::Ui, color: Color32) -> Color32 {
    let visuals = ui.visuals();
    readable_on(color, over(visuals.faint_bg_color, visuals.panel_fill))
}

/// A message on one line of a bar (the top bar's status, the lecture bar's notes): a problem in
/// the palette's red made [`readable`], anything else in the weak text colour; cut to the room
/// there is, the whole of it on hover.
pub fn message_line(ui: &mut egui::Ui, message: &str, problem: bool) {
    let color = if problem {
        readable(ui, palette::MISS)
    } else {
        ui.visuals().weak_text_color()
    };
    ui.add(egui::Label::new(egui::RichText::new(message).color(color)).truncate())
        .on_hover_text(message);
}

/// The least contrast a line or a shape must have with what it is drawn on: WCAG's 3:1 for
/// graphical objects.
pub const LINE_CONTRAST: f32 = 3.0;

/// `color` (premultiplied, maybe translucent, as egui keeps colours) as drawn on `background`:
/// made darker (on a light background) or lighter (on a dark one), and more opaque if that is
/// not enough, just so far that painted over the background it stands out at
/// [`LINE_CONTRAST`]. The palette's colours were chosen on the dark canvas: on the light and
/// high-contrast themes' white, the ray's orange was 1.9:1, the hit's green 1.6:1, and the
/// ray beyond the hit, faded, 1.2:1.
pub fn ink_on(color: Color32, background: Color32) -> Color32 {
    let [r, g, b, a] = color.to_srgba_unmultiplied();
    let base = Color32::from_rgb(r, g, b);
    let toward = if luminance(background) < 0.18 {
        Color32::WHITE
    } else {
        Color32::BLACK
    };
    let stands_out = |candidate: Color32, alpha: u8| {
        let [r, g, b, _] = candidate.to_array();
        let drawn = Color32::from_rgba_unmultiplied(r, g, b, alpha);
        contrast_ratio(over(drawn, background), background) >= LINE_CONTRAST
    };
    for alpha in (u32::from(a)..=255).step_by(15).chain([255]) {
        let alpha = alpha as u8;
        if let Some(found) = (0..=20)
            .map(|step| base.lerp_to_gamma(toward, step as f32 / 20.0))
            .find(|candidate| stands_out(*candidate, alpha))
        {
            let [r, g, b, _] = found.to_array();
            return Color32::from_rgba_unmultiplied(r, g, b, alpha);
        }
    }
    toward
}

/// `top` (premultiplied, as egui keeps colours) painted over the opaque `bottom`.
pub fn over(top: Color32, bottom: Color32) -> Color32 {
    let keep = 1.0 - f32::from(top.a()) / 255.0;
    let mix = |t: u8, b: u8| (f32::from(t) + f32::from(b) * keep).round().min(255.0) as u8;
    Color32::from_rgb(
        mix(top.r(), bottom.r()),
        mix(top.g(), bottom.g()),
        mix(top.b(), bottom.b()),
    )
}

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
    /// The canvas size the view was fitted to, while the user has not moved it: a canvas of
    /// another size (a window resized, a lecture slide opened at another scale) fits again.
    pub fitted_size: Option<Vec2>,
    /// The caption's size (width, height) when the view was fitted, the scene kept clear of
    /// it (below it, or beside it where that shows the scene larger): a caption that grows
    /// (lecture mode's larger text, more lines) fits the view again.
    pub fitted_caption: Vec2,
    /// The same at the bottom, for the notes there (the scene's shape count and source): a
    /// ray whose origin sat in the corner was hidden under it.
    pub fitted_bottom: f32,
}

impl Default for View2d {
    fn default() -> Self {
        Self {
            center: DVec2::splat(50.0),
            points_per_unit: 4.0,
            placed: false,
            fitted_size: None,
            fitted_caption: Vec2::ZERO,
            fitted_bottom: 0.0,
        }
    }
}

impl View2d {
    /// A view showing all of `bounds` in `rect` with a margin.
    pub fn fitted(bounds: &Aabb<DVec2>, rect: Rect) -> Self {
        Self::fitted_between(bounds, rect, Vec2::ZERO, 0.0)
    }

    /// A view showing all of `bounds` in `rect`, with a margin, clear of the caption at its
    /// top left (`caption` its size) and of the bottom `bottom` points (kept for the notes
    /// there). The scene goes below the caption or beside it, whichever shows it larger: a
    /// short, wide pane (the recap's five, a lecture's row of three) has room beside it.
    pub fn fitted_between(bounds: &Aabb<DVec2>, rect: Rect, caption: Vec2, bottom: f32) -> Self {
        if bounds.is_empty() || !bounds.is_finite() {
            return Self {
                placed: true,
                ..Self::default()
            };
        }
        // No more than half the canvas goes to a caption, a quarter to the notes.
        let caption = Vec2::new(
            caption.x.clamp(0.0, rect.width() / 2.0),
            caption.y.clamp(0.0, rect.height() / 2.0),
        );
        let bottom = bottom.clamp(0.0, rect.height() / 4.0);
        let (points_per_unit, beside) =
            Self::fitted_scale(bounds.extent(), rect.size(), caption, bottom);
        // The offset of the free area's centre from the canvas's, in points (screen y down).
        let shift = if beside {
            Vec2::new(caption.x / 2.0, -bottom / 2.0)
        } else {
            Vec2::new(0.0, (caption.y - bottom) / 2.0)
        };
        // The bounds' centre sits in the middle of what is free of caption and notes.
        let center =
            bounds.center() + DVec2::new(-f64::from(shift.x), f64::from(shift.y)) / points_per_unit;
        Self {
            center,
            points_per_unit,
            placed: true,
            fitted_size: Some(rect.size()),
            fitted_caption: caption,
            fitted_bottom: bottom,
        }
    }
}

impl View2d {
    /// The zoom (points per unit) at which a scene of `extent` fits a canvas of `size` with
    /// the margins of [`View2d::fitted_between`], clear of a caption of size `caption` and
    /// the bottom `bottom` points, and whether the scene goes beside the caption (true) or
    /// below it.
    pub fn fitted_scale(extent: DVec2, size: Vec2, caption: Vec2, bottom: f32) -> (f64, bool) {
        let caption = Vec2::new(
            caption.x.clamp(0.0, size.x / 2.0),
            caption.y.clamp(0.0, size.y / 2.0),
        );
        let bottom = bottom.clamp(0.0, size.y / 4.0);
        let extent = extent.max(DVec2::splat(1e-9));
        let scale_in = |usable: Vec2| {
            let usable = usable.max(Vec2::splat(16.0));
            (usable.x as f64 / extent.x).min(usable.y as f64 / extent.y)
        };
        let margin = Vec2::splat(48.0);
        let below = scale_in(size - margin - Vec2::new(0.0, caption.y + bottom));
        let beside = scale_in(size - margin - Vec2::new(caption.x, bottom));
        if beside > below * 1.05 {
            (beside, true)
        } else {
            (below, false)
        }
    }
}

/// Where the smallest whole scene of a pass is kept ([`smallest_scene`]).
fn smallest_scene_id() -> egui::Id {
    egui::Id::unique("smallest scene shown whole")
}

/// Notes that a canvas showed its whole scene `points` across (its longer side).
fn note_scene_shown(ctx: &egui::Context, points: f32) {
    let pass = ctx.cumulative_pass_nr();
    ctx.data_mut(|data| {
        let kept = data.get_temp_mut_or(smallest_scene_id(), (pass, points));
        if kept.0 != pass {
            *kept = (pass, points);
        } else {
            kept.1 = kept.1.min(points);
        }
    });
}

/// The smallest of the whole scenes the canvases of the last pass showed, in points across
/// (the longer side; a view the user zoomed or panned is not counted): how large what
/// carries a slide's point is drawn, which the lecture's layout test holds up.
pub fn smallest_scene(ctx: &egui::Context) -> Option<f32> {
    let pass = ctx.cumulative_pass_nr();
    ctx.data(|data| data.get_temp::<(u64, f32)>(smallest_scene_id()))
        .filter(|(kept, _)| *kept + 1 >= pass)
        .map(|(_, points)| points)
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
    /// Vertices the canvas's batches may still take this frame (see [`VERTEX_BUDGET`]).
    budget: std::cell::Cell<usize>,
    /// Shapes, boxes or lines left out this frame because the budget ran out.
    left_out: std::cell::Cell<usize>,
    /// The labels written on the canvas this frame, laid out so none covers another.
    labels: std::cell::RefCell<Labels>,
    /// Whether it is drawn on the dark theme's background (read once: a tree of 100,000
    /// nodes asks per node).
    dark_mode: bool,
    /// The colour the canvas is painted on.
    background: Color32,
}

/// The most vertices one canvas draws in a frame: about as many as a pane has pixels (a box
/// smaller than [`SMALLEST_DRAWN`] is not drawn at all), and few enough that egui hands three
/// canvases of them to the GPU in a frame of lesson 7 at 100,000 shapes near 100 ms: the frame
/// that first tessellates three new meshes of 400,000 took 180–220 ms (of it 130–160 ms
/// tessellating), of 200,000 85–115 ms; later frames 10–20 ms (at a million each, frames
/// took up to 400 ms). What does not fit is left out and the canvas says so
/// ([`Canvas::finish`]).
pub const VERTEX_BUDGET: usize = 200_000;

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
    /// The z axis (3D): apart from x, y and the current step's blue.
    pub const Z_AXIS: Color32 = Color32::from_rgb(165, 105, 235);
    /// The axes in order, x, y, z.
    pub const AXES: [Color32; 3] = [X_AXIS, Y_AXIS, Z_AXIS];
}

/// A colour per tree depth, cycling through hues so neighbouring depths differ; saturated and
/// bright on a dark background, saturated and darker on a light one (pastels vanish on white).
pub fn depth_color(depth: usize, dark_mode: bool) -> Color32 {
    // Converting a hue to sRGB takes a few `powf`s: a fifth of a frame that draws every node
    // of three 20k-shape trees, so the depths a tree reaches are converted once.
    static TABLES: std::sync::LazyLock<[Vec<Color32>; 2]> = std::sync::LazyLock::new(|| {
        [false, true].map(|dark_mode| {
            (0..DEPTH_COLORS)
                .map(|depth| hue_of_depth(depth, dark_mode))
                .collect()
        })
    });
    match TABLES[usize::from(dark_mode)].get(depth) {
        Some(&color) => color,
        None => hue_of_depth(depth, dark_mode),
    }
}

/// The body text size egui starts with; a larger one (lecture mode's) scales canvas text.
const DEFAULT_BODY_POINTS: f32 = 13.0;

/// A proportional font of `points` at the app's text scale: when lecture mode makes text
/// larger, text drawn on canvases grows with it, never below the style's small text.
pub fn font(ctx: &egui::Context, points: f32) -> FontId {
    let style = ctx.global_style();
    let size = |text_style: egui::TextStyle, default: f32| {
        style
            .text_styles
            .get(&text_style)
            .map_or(default, |font| font.size)
    };
    let factor = (size(egui::TextStyle::Body, DEFAULT_BODY_POINTS) / DEFAULT_BODY_POINTS).max(1.0);
    FontId::proportional((points * factor).max(size(egui::TextStyle::Small, 9.0)))
}

/// How many depths `depth_color` keeps converted: deeper than any kD-tree's depth limit.
const DEPTH_COLORS: usize = 64;

fn hue_of_depth(depth: usize, dark_mode: bool) -> Color32 {
    let hue = (depth as f32 * 0.137 + 0.55).fract();
    if dark_mode {
        return egui::ecolor::Hsva::new(hue, 0.75, 0.95, 1.0).into();
    }
    // On white, as dark as the hue needs to stand out at 3.2:1 (WCAG asks 3 of lines): a
    // yellow-green must be darker than a blue of the same value.
    (0..=16)
        .map(|step| {
            let value = 0.6 - 0.03 * step as f32;
            Color32::from(egui::ecolor::Hsva::new(hue, 0.95, value, 1.0))
        })
        .find(|color| contrast_ratio(*color, Color32::WHITE) >= 3.2)
        .unwrap_or(Color32::from_gray(90))
}

impl Canvas {
    /// [`depth_color`] for this canvas's background.
    pub fn depth_color(&self, depth: usize) -> Color32 {
        depth_color(depth, self.dark_mode)
    }

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
        // The caption's and the bottom notes' heights last frame ([`Canvas::caption`],
        // [`Canvas::note_right`]).
        let (caption, notes): (Vec2, f32) = ui.ctx().data(|data| {
            (
                data.get_temp(caption_id(&response)).unwrap_or(Vec2::ZERO),
                data.get_temp(notes_id(&response)).unwrap_or(0.0),
            )
        });
        // Fitted again when the canvas changes size or its caption or notes grow past the
        // room kept (not when they shrink: a view that jumped at every step would be worse).
        let resized = view.fitted_size.is_some_and(|size| {
            let kept = view.fitted_caption;
            (size - rect.size()).length() > 0.5
                || caption.x.clamp(0.0, rect.width() / 2.0) > kept.x + 0.5
                || caption.y.clamp(0.0, rect.height() / 2.0) > kept.y + 0.5
                || notes.clamp(0.0, rect.height() / 4.0) > view.fitted_bottom + 0.5
        });
        if !view.placed || resized {
            *view = View2d::fitted_between(fit_bounds, rect, caption, notes);
        }
        painter.rect_filled(rect, 0.0, ui.visuals().extreme_bg_color);
        if view.fitted_size.is_some() && !fit_bounds.is_empty() && fit_bounds.is_finite() {
            note_scene_shown(
                ui.ctx(),
                (fit_bounds.extent() * view.points_per_unit).max_element() as f32,
            );
        }

        // Zoom about the pointer, so the point under it stays put.
        if let Some(hover) = response.hover_pos() {
            let (scroll, zoom) =
                ui.input(|input| (input.smooth_scroll_delta.y, input.zoom_delta()));
            let factor = (scroll as f64 * 0.002).exp() * zoom as f64;
            if factor != 1.0 {
                view.fitted_size = None;
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
            if delta != Vec2::ZERO {
                view.fitted_size = None;
            }
            view.center -= DVec2::new(delta.x as f64, -delta.y as f64) / view.points_per_unit;
        }
        Self {
            painter: painter.with_clip_rect(rect),
            rect,
            view: *view,
            response,
            budget: std::cell::Cell::new(VERTEX_BUDGET),
            left_out: std::cell::Cell::new(0),
            labels: std::cell::RefCell::new(Labels::new(rect.shrink(2.0))),
            dark_mode: ui.visuals().dark_mode,
            background: ui.visuals().extreme_bg_color,
        }
    }

    /// Shows the world through `view` from now on (a lesson that sets its own zoom).
    pub fn set_view(&mut self, view: View2d) {
        self.view = view;
    }

    /// The colour the canvas is painted on (what a label's plate hides lines with).
    pub fn background(&self) -> Color32 {
        self.background
    }

    /// `color` as a line or a shape on this canvas: [`ink_on`] its background, so it stands
    /// out at 3:1 in every theme.
    pub fn ink(&self, color: Color32) -> Color32 {
        ink_on(color, self.background)
    }

    /// Where this frame's labels went on the canvas (for tests).
    pub fn placed_labels(&self) -> Vec<Rect> {
        self.labels.borrow().placed().to_vec()
    }

    /// How many things were left out this frame because the canvas's budget ran out.
    pub fn left_out(&self) -> usize {
        self.left_out.get()
    }

    /// Says what the budget left out, at the canvas's bottom edge. Call after drawing.
    pub fn finish(&self) {
        let left_out = self.left_out.get();
        if left_out > 0 {
            self.note(&format!(
                "{} boxes, lines or shapes are not drawn: too many for one frame. Zoom in to see them.",
                accelviz_core::format::count(left_out)
            ));
        }
    }

    /// A short note at the bottom right of the canvas, on a dark plate.
    pub fn note_right(&self, text: &str) {
        // Wrapped to the canvas: a narrow pane (three side by side, with the panels on) cut
        // a one-line note at its left edge.
        let galley = self.painter.layout(
            text.to_owned(),
            font(self.painter.ctx(), 12.0),
            Color32::from_gray(220),
            (self.rect.width() - 20.0).max(40.0),
        );
        let pos = self.rect.right_bottom() - Vec2::new(10.0, 8.0) - galley.size();
        let backing = Rect::from_min_size(pos, galley.size()).expand(3.0);
        self.keep_notes_room(self.rect.bottom() - backing.top());
        self.painter.rect_filled(backing, 3.0, PLATE);
        self.painter.galley(pos, galley, Color32::from_gray(220));
    }

    /// Keeps `height` at the canvas's bottom for its notes in the next frame's fit (what a
    /// caption's height does at the top).
    fn keep_notes_room(&self, height: f32) {
        let id = notes_id(&self.response);
        self.painter.ctx().data_mut(|data| {
            let kept: f32 = data.get_temp(id).unwrap_or(0.0);
            data.insert_temp(id, kept.max(height));
        });
    }

    /// A one-line note at the bottom left of the canvas, on a dark plate.
    pub fn note(&self, text: &str) {
        let galley = self.painter.layout(
            text.to_owned(),
            font(self.painter.ctx(), 13.0),
            Color32::WHITE,
            (self.rect.width() - 20.0).max(40.0),
        );
        let pos = self.rect.left_bottom() + Vec2::new(10.0, -10.0 - galley.size().y);
        let backing = Rect::from_min_size(pos, galley.size()).expand(3.0);
        self.keep_notes_room(self.rect.bottom() - backing.top());
        self.painter.rect_filled(backing, 3.0, PLATE);
        self.painter.galley(pos, galley, Color32::WHITE);
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
        let mut batch = self.batch();
        batch.reserve(boxes.len() * 8, boxes.len() * 8);
        for (bounds, stroke) in boxes {
            self.batch_box(&mut batch, &bounds, stroke.width, stroke.color);
        }
        self.draw_batch(batch);
    }

    /// Many split lines (`cell`, `axis`, `position`): one by one when few, batched when many.
    pub fn split_lines(&self, lines: impl IntoIterator<Item = (Aabb<DVec2>, usize, f64, Stroke)>) {
        let lines: Vec<_> = lines.into_iter().collect();
        if lines.len() <= BATCH_ABOVE {
            for (cell, axis, position, stroke) in lines {
                self.split_line(&cell, axis, position, stroke);
            }
            return;
        }
        let mut batch = self.batch();
        self.batch_split_lines(&mut batch, lines);
        self.draw_batch(batch);
    }

    /// [`Canvas::split_lines`] of many lines into `batch`.
    pub fn batch_split_lines(
        &self,
        batch: &mut Batch,
        lines: impl IntoIterator<Item = (Aabb<DVec2>, usize, f64, Stroke)>,
    ) {
        for (cell, axis, position, stroke) in lines {
            let [from, to] = self.split_ends(&cell, axis, position);
            // A line shorter than that cannot be told from its neighbours: a cell too small.
            if self.visible(Rect::from_two_pos(from, to)) && from.distance(to) >= SMALLEST_DRAWN {
                batch.line(from, to, stroke.width, stroke.color);
            }
        }
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
        self.reserve_ray(origin, direction);
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

    /// Keeps labels off a ray's origin dot and arrow head (where [`ray`](Self::ray) draws
    /// them): a name under the head could not be read, nor the head dragged.
    pub fn reserve_ray(&self, origin: DVec2, direction: DVec2) {
        let mut labels = self.labels.borrow_mut();
        for point in [origin, origin + direction] {
            labels.reserve(Rect::from_center_size(
                self.to_screen(point),
                Vec2::splat(18.0),
            ));
        }
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
                font(self.painter.ctx(), 13.0),
                color,
            );
        }
    }

    /// A tick across the ray at parameter `t`, labelled beside it (on the side `side` says
    /// first: 1 left of the ray, −1 right) where no other label is, so marks at nearby `t`
    /// never write over each other. Returns where the label went.
    pub fn ray_mark_labeled(
        &self,
        origin: DVec2,
        direction: DVec2,
        t: f64,
        color: Color32,
        label: &str,
        side: f32,
    ) -> Option<Rect> {
        if !t.is_finite() {
            return None;
        }
        let point = self.to_screen(origin + direction * t);
        let along = self.to_screen(origin + direction) - self.to_screen(origin);
        let normal = Vec2::new(-along.y, along.x).normalized();
        let tangent = along.normalized();
        self.painter.line_segment(
            [point - normal * 7.0, point + normal * 7.0],
            Stroke::new(2.5, color),
        );
        let first = normal * side * 18.0;
        self.labels.borrow_mut().place(
            &self.painter,
            label,
            font(self.painter.ctx(), 13.0),
            color,
            point,
            &[
                first,
                -first,
                first + tangent * 30.0,
                first - tangent * 30.0,
                -first + tangent * 30.0,
                -first - tangent * 30.0,
            ],
            Some(PLATE),
        )
    }

    /// A label beside a world point (above right of it, or where there is room), never over
    /// another label of this canvas.
    pub fn label(&self, at: DVec2, text: &str, color: Color32) {
        let anchor = self.to_screen(at);
        self.labels.borrow_mut().place(
            &self.painter,
            text,
            font(self.painter.ctx(), 13.0),
            // On the canvas itself: at 4.5:1 on its background, in every theme.
            readable_on(color, self.background),
            anchor,
            &[
                Vec2::new(10.0, -9.0),
                Vec2::new(-10.0, -9.0),
                Vec2::new(10.0, 9.0),
                Vec2::new(-10.0, 9.0),
            ],
            None,
        );
    }

    /// Labels the mark at `at` (a ring, a dot) by `text`, its nearest edge `clear` points from
    /// the mark's centre: right of it, left, above or below, whichever is free. [`Canvas::label`]
    /// sets a label's centre a few points off its anchor, which suits a shape's number on the
    /// shape but puts a long label over a small mark.
    pub fn label_beside(&self, at: DVec2, text: &str, color: Color32, clear: f32) {
        let font = font(self.painter.ctx(), 13.0);
        let size = self
            .painter
            .layout_no_wrap(text.to_owned(), font.clone(), color)
            .size();
        let (x, y) = (size.x / 2.0 + clear, size.y / 2.0 + clear);
        self.labels.borrow_mut().place(
            &self.painter,
            text,
            font,
            readable_on(color, self.background),
            self.to_screen(at),
            &[
                Vec2::new(x, 0.0),
                Vec2::new(-x, 0.0),
                Vec2::new(0.0, -y),
                Vec2::new(0.0, y),
            ],
            None,
        );
    }

    /// Keeps `rect` (on screen) free of the labels placed after: a mark they must not cover.
    pub fn keep_clear(&self, rect: Rect) {
        self.labels.borrow_mut().reserve(rect);
    }

    /// Names the box drawn at `rect` (on screen) by `text`: inside it, or just outside when
    /// `has_named_inside` (boxes named inside it), on a plate of the canvas's background so
    /// shapes and lines under it do not hide it ([`Labels::place_for_box`]).
    pub fn box_label(&self, rect: Rect, has_named_inside: bool, text: &str, color: Color32) {
        let plate = faded(self.background, 220);
        self.labels.borrow_mut().place_for_box(
            &self.painter,
            text,
            font(self.painter.ctx(), 13.0),
            readable_on(color, self.background),
            rect,
            has_named_inside,
            Some(plate),
        );
    }

    /// A caption in the canvas's top-left corner, one entry a line (wrapped to the canvas).
    /// A fitted view keeps clear of it: its height is kept for the next frame's fit.
    pub fn caption(&self, lines: &[(String, Color32)]) {
        let top = self.rect.top();
        let mut pos = self.rect.left_top() + Vec2::new(10.0, 8.0);
        let width = (self.rect.width() - 20.0).max(40.0);
        let mut widest: f32 = 0.0;
        for (text, color) in lines {
            let galley =
                self.painter
                    .layout(text.clone(), font(self.painter.ctx(), 14.0), *color, width);
            let backing = Rect::from_min_size(pos, galley.size()).expand(3.0);
            self.painter.rect_filled(backing, 3.0, PLATE);
            let height = galley.size().y;
            widest = widest.max(galley.size().x);
            self.painter.galley(pos, galley, *color);
            pos.y += height + 6.0;
        }
        let size = Vec2::new(widest + 16.0, pos.y - top);
        self.painter
            .ctx()
            .data_mut(|data| data.insert_temp(caption_id(&self.response), size));
    }
}

/// A slot's last batch ([`Canvas::cached_batch`]): what it was made from, and the view and
/// canvas it was laid out for.
#[derive(Clone)]
struct KeptBatch {
    key: u64,
    mesh: Arc<egui::Mesh>,
    left_out: usize,
    view: View2d,
    rect: Rect,
    /// The frame since which it has been shown moved, waiting to be made again.
    waiting_since: Option<u64>,
}

/// Where the app keeps the frame (pass) in which a batch was last made.
fn batch_pass_id() -> egui::Id {
    egui::Id::unique("canvas batch made in pass")
}

/// `mesh`, laid out for `view` on `rect`, moved and scaled to `to_view` on `to_rect`: a
/// world point's screen position is affine in it, axis by axis.
fn moved_to(
    mesh: &egui::Mesh,
    view: View2d,
    rect: Rect,
    to_view: View2d,
    to_rect: Rect,
) -> egui::Mesh {
    let scale = (to_view.points_per_unit / view.points_per_unit) as f32;
    let shift = (view.center - to_view.center) * to_view.points_per_unit;
    let (from, to) = (rect.center(), to_rect.center());
    let mut moved = mesh.clone();
    for vertex in &mut moved.vertices {
        vertex.pos = Pos2::new(
            to.x + shift.x as f32 + (vertex.pos.x - from.x) * scale,
            to.y - shift.y as f32 + (vertex.pos.y - from.y) * scale,
        );
    }
    moved
}

/// Where a canvas keeps the height of its bottom notes between frames.
fn notes_id(response: &Response) -> egui::Id {
    response.id.with("notes height")
}

/// Where a canvas keeps its caption's height between frames.
fn caption_id(response: &Response) -> egui::Id {
    response.id.with("caption height")
}

/// Boxes and split lines smaller than this (points) are not drawn in a batch: at that size a
/// tree's neighbouring boxes merge into one smear, and three trees of 100,000 shapes drew a
/// million of them a frame (200 ms) to show nothing more.
pub const SMALLEST_DRAWN: f32 = 2.0;

/// Above this many shapes, boxes or lines, a lesson draws them as one batched mesh.
pub const BATCH_ABOVE: usize = 300;

/// Many simple shapes in one mesh, drawn with one paint call: what a frame with thousands of
/// primitives and boxes can afford (egui would otherwise tessellate each with anti-aliased
/// edges). Lessons use it above a few hundred shapes; below that, each shape is drawn on its own.
pub struct Batch {
    mesh: egui::Mesh,
    /// The most vertices it takes; past them it counts what it leaves out.
    limit: usize,
    left_out: usize,
}

impl Batch {
    /// Whether `vertices` more fit; if not, the thing is counted as left out.
    fn room_for(&mut self, vertices: usize) -> bool {
        let fits = self.mesh.vertices.len() + vertices <= self.limit;
        if !fits {
            self.left_out += 1;
        }
        fits
    }

    /// A filled rectangle.
    pub fn rect(&mut self, rect: Rect, color: Color32) {
        if self.room_for(4) {
            self.mesh.add_colored_rect(rect, color);
        }
    }

    /// A line of `width` points as one quad.
    pub fn line(&mut self, from: Pos2, to: Pos2, width: f32, color: Color32) {
        if !self.room_for(4) {
            return;
        }
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
        let vertices = vertices.min(self.limit);
        let triangles = triangles.min(self.limit);
        self.mesh.vertices.reserve(vertices);
        self.mesh.indices.reserve(triangles * 3);
    }

    /// A rectangle's outline of `width` points: a frame of eight vertices, the outer corners
    /// and the inner ones, and eight triangles.
    pub fn rect_outline(&mut self, rect: Rect, width: f32, color: Color32) {
        if !self.room_for(8) {
            return;
        }
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
        if !self.room_for(sides as usize + 1) {
            return;
        }
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

    /// A batch that may take what is left of the canvas's budget.
    pub fn batch(&self) -> Batch {
        Batch {
            mesh: egui::Mesh::default(),
            limit: self.budget.get(),
            left_out: 0,
        }
    }

    /// Paints the batch `fill` makes, or the one it made last for the same `slot` of this
    /// canvas and the same `key` (what it is drawn from: a tree's id, colours, the view and
    /// canvas are added here). Three trees of 100,000 shapes took 50 to 100 ms a frame to
    /// batch again, unchanged; kept, a frame hands egui the same mesh.
    ///
    /// At most one batch is made a frame while another slot has one to show: three new trees
    /// arriving at once (lesson 7 switching from kD-trees to BVHs at 100,000 shapes) made a
    /// frame of 200 ms. A slot that waits shows its last mesh, moved and scaled to this
    /// frame's view (exact while only the view changed: a pan, a zoom), and asks for the
    /// next frame, which makes it.
    pub fn cached_batch(
        &self,
        slot: &str,
        key: impl std::hash::Hash,
        fill: impl FnOnce(&mut Batch),
    ) {
        use std::hash::{Hash, Hasher};
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        key.hash(&mut hasher);
        (
            self.view.center.to_array().map(f64::to_bits),
            self.view.points_per_unit.to_bits(),
        )
            .hash(&mut hasher);
        [
            self.rect.min.x,
            self.rect.min.y,
            self.rect.max.x,
            self.rect.max.y,
        ]
        .map(f32::to_bits)
        .hash(&mut hasher);
        (self.dark_mode, self.budget.get()).hash(&mut hasher);
        let key = hasher.finish();
        let ctx = self.painter.ctx();
        let id = self.response.id.with(("batch", slot));
        let kept: Option<KeptBatch> = ctx.data(|data| data.get_temp(id));
        let pass = ctx.cumulative_pass_nr();
        let made_this_pass = ctx.data(|data| data.get_temp::<u64>(batch_pass_id()) == Some(pass));
        let (mesh, left_out) = match kept {
            Some(kept) if kept.key == key => (kept.mesh, kept.left_out),
            // A slot waits two frames at most, so none starves while others change.
            Some(mut kept)
                if made_this_pass
                    && kept
                        .waiting_since
                        .is_none_or(|since| pass.saturating_sub(since) < 2) =>
            {
                ctx.request_repaint();
                let shown = (
                    Arc::new(moved_to(
                        &kept.mesh, kept.view, kept.rect, self.view, self.rect,
                    )),
                    kept.left_out,
                );
                kept.waiting_since.get_or_insert(pass);
                ctx.data_mut(|data| data.insert_temp(id, kept));
                shown
            }
            _ => {
                let mut batch = self.batch();
                fill(&mut batch);
                let made = KeptBatch {
                    key,
                    mesh: Arc::new(batch.mesh),
                    left_out: batch.left_out,
                    view: self.view,
                    rect: self.rect,
                    waiting_since: None,
                };
                let shown = (made.mesh.clone(), made.left_out);
                ctx.data_mut(|data| {
                    data.insert_temp(id, made);
                    data.insert_temp(batch_pass_id(), pass);
                });
                shown
            }
        };
        self.budget
            .set(self.budget.get().saturating_sub(mesh.vertices.len()));
        self.left_out.set(self.left_out.get() + left_out);
        if !mesh.is_empty() {
            self.painter.add(egui::Shape::Mesh(mesh));
        }
    }

    /// Paints a batch, and counts what it left out.
    pub fn draw_batch(&self, batch: Batch) {
        self.budget
            .set(self.budget.get().saturating_sub(batch.mesh.vertices.len()));
        self.left_out.set(self.left_out.get() + batch.left_out);
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

/// Labels laid out so that none overlaps another or leaves its area: each label tries the
/// spots it is offered, nearest first, then the same directions further out, and takes the
/// first free one. A label with no free spot is left out rather than drawn over another.
pub struct Labels {
    area: Rect,
    placed: Vec<Rect>,
}

impl Labels {
    /// No labels yet, to be kept inside `area`.
    pub fn new(area: Rect) -> Self {
        Self {
            area,
            placed: Vec::new(),
        }
    }

    /// Keeps `rect` free: a later label will not overlap it (a drawn legend, a caption).
    pub fn reserve(&mut self, rect: Rect) {
        self.placed.push(rect);
    }

    /// Places `text` beside `anchor`: the label's centre goes to `anchor + offset` for the
    /// first free `offset` of `offsets`, or of the same offsets lengthened step by step. With
    /// `plate`, a rounded plate of that colour is drawn under the text, so lines behind it do
    /// not cross it. Returns where the label went.
    #[allow(clippy::too_many_arguments)]
    pub fn place(
        &mut self,
        painter: &egui::Painter,
        text: &str,
        font: FontId,
        color: Color32,
        anchor: Pos2,
        offsets: &[Vec2],
        plate: Option<Color32>,
    ) -> Option<Rect> {
        let galley = painter.layout_no_wrap(text.to_owned(), font, color);
        let size = galley.size();
        if size.x > self.area.width() || size.y > self.area.height() {
            return None;
        }
        let spot = (0..6).flat_map(|step| {
            let stretch = 1.0 + step as f32 * 0.75;
            offsets.iter().map(move |offset| *offset * stretch)
        });
        for offset in spot {
            let rect = Rect::from_center_size(anchor + offset, size);
            // Inside the area: shifted in, as long as that keeps it near its anchor.
            let shift = Vec2::new(
                (self.area.left() - rect.left()).max(0.0)
                    + (self.area.right() - rect.right()).min(0.0),
                (self.area.top() - rect.top()).max(0.0)
                    + (self.area.bottom() - rect.bottom()).min(0.0),
            );
            let rect = rect.translate(shift);
            if self.is_free(rect, 2.0) {
                return Some(self.put(painter, galley, color, rect, plate));
            }
        }
        None
    }

    /// Whether `rect` keeps `gap` from every label placed.
    fn is_free(&self, rect: Rect, gap: f32) -> bool {
        !self
            .placed
            .iter()
            .any(|other| other.intersects(rect.expand(gap)))
    }

    /// Draws `galley` at `rect` (on its plate) and keeps the spot taken.
    fn put(
        &mut self,
        painter: &egui::Painter,
        galley: std::sync::Arc<egui::Galley>,
        color: Color32,
        rect: Rect,
        plate: Option<Color32>,
    ) -> Rect {
        if let Some(plate) = plate {
            painter.rect_filled(rect.expand(2.0), 3.0, plate);
        }
        painter.galley(rect.min, galley, color);
        self.placed.push(rect);
        rect
    }

    /// Names the box drawn at `boxed` (on screen) by `text`, so that the name reads as that
    /// box's and no other's. A box with named boxes inside it (a parent whose children are
    /// named too) is named just outside, above its top edge, or else below its bottom edge,
    /// left-aligned, where no child's name can sit; any other box inside, at its top-left
    /// corner, or along its top edge, then row by row down. The first spot free of other
    /// labels is taken; with none, no name rather than one that could be read as a
    /// neighbour's.
    #[allow(clippy::too_many_arguments)]
    pub fn place_for_box(
        &mut self,
        painter: &egui::Painter,
        text: &str,
        font: FontId,
        color: Color32,
        boxed: Rect,
        outside: bool,
        plate: Option<Color32>,
    ) -> Option<Rect> {
        let galley = painter.layout_no_wrap(text.to_owned(), font, color);
        let size = galley.size();
        let mut spots = Vec::new();
        if outside {
            // Above the top edge's left corner, or below the bottom edge's; then along the
            // rows there, sliding right. Outside, a name keeps a wider gap from the others:
            // "root" and "R" side by side above one edge read as one name.
            let rows = [boxed.top() - 4.0 - size.y, boxed.bottom() + 4.0].map(|y| {
                spots_in(
                    Rect::from_min_size(
                        Pos2::new(boxed.left() + 3.0, y),
                        Vec2::new(boxed.width() - 3.0, size.y),
                    ),
                    size,
                )
            });
            spots.extend(rows.iter().filter_map(|row| row.first().copied()));
            spots.extend(rows.iter().flat_map(|row| row.iter().skip(1).copied()));
        }
        let outside_count = spots.len();
        // The plate's margin stays inside the box too.
        spots.extend(spots_in(boxed.shrink(3.0), size));
        for (index, rect) in spots.into_iter().enumerate() {
            let gap = if index < outside_count { 10.0 } else { 2.0 };
            if self.area.contains_rect(rect) && self.is_free(rect, gap) {
                return Some(self.put(painter, galley, color, rect, plate));
            }
        }
        None
    }

    /// Where the labels went (and what was reserved), for tests.
    pub fn placed(&self) -> &[Rect] {
        &self.placed
    }
}

/// The spots a label of `size` can take inside `room`, row by row from its top-left corner
/// in half-label steps (at most 41 × 41 of them); none when it does not fit.
fn spots_in(room: Rect, size: Vec2) -> Vec<Rect> {
    if size.x > room.width() || size.y > room.height() {
        return Vec::new();
    }
    let step = Vec2::new((size.x * 0.5).max(4.0), (size.y * 0.5).max(4.0));
    let columns = (((room.width() - size.x) / step.x).floor() as usize).min(40);
    let rows = (((room.height() - size.y) / step.y).floor() as usize).min(40);
    (0..=rows)
        .flat_map(|row| {
            (0..=columns).map(move |column| {
                Rect::from_min_size(
                    room.min + Vec2::new(column as f32 * step.x, row as f32 * step.y),
                    size,
                )
            })
        })
        .collect()
}

/// Whether any two of `rects` overlap: what a label layout must never allow.
pub fn any_overlap(rects: &[Rect]) -> bool {
    rects.iter().enumerate().any(|(index, rect)| {
        rects[index + 1..]
            .iter()
            .any(|other| rect.intersect(*other).area() > 0.0)
    })
}
