//! The scene's shapes and ray on a canvas, coloured by what a traversal did to them.

use accelviz_core::{Ray, ShapeSet, Step};
use egui::{Color32, Stroke};
use glam::DVec2;

use crate::canvas::{BATCH_ABOVE, Canvas, faded, palette};

/// The fill of a shape nobody is looking at, readable on either theme.
pub fn shape_fill(ui: &egui::Ui) -> Color32 {
    if ui.visuals().dark_mode {
        Color32::from_gray(150)
    } else {
        Color32::from_gray(110)
    }
}

/// Draws every shape; `color_of` picks a colour for shapes that stand out.
pub fn draw_shapes(
    ui: &egui::Ui,
    canvas: &Canvas,
    shapes: &ShapeSet<DVec2>,
    color_of: impl Fn(usize) -> Option<Color32>,
) {
    let plain = shape_fill(ui);
    let color_of = |index| canvas.ink(color_of(index).unwrap_or(plain));
    if shapes.shapes.len() > BATCH_ABOVE {
        // Kept between frames while the shapes and their colours are the same (hashing them
        // takes a fraction of what drawing them again does).
        let colors: Vec<Color32> = (0..shapes.shapes.len()).map(color_of).collect();
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        for shape in &shapes.shapes {
            let bounds = shape.bounds();
            std::hash::Hash::hash(
                &[bounds.min, bounds.max].map(|corner| corner.to_array().map(f64::to_bits)),
                &mut hasher,
            );
        }
        let key = (std::hash::Hasher::finish(&hasher), &colors);
        canvas.cached_batch("shapes", key, |batch| {
            // A disc takes up to 41 vertices; boxes and segments 4.
            batch.reserve(shapes.shapes.len() * 16, shapes.shapes.len() * 14);
            for (shape, color) in shapes.shapes.iter().zip(&colors) {
                canvas.batch_shape(batch, shape, *color);
            }
        });
        return;
    }
    for (index, shape) in shapes.shapes.iter().enumerate() {
        let color = color_of(index);
        canvas.shape(
            shape,
            canvas.ink(faded(color, 200)),
            Stroke::new(1.0, color),
        );
    }
}

/// How each primitive fared in the steps shown: `Some(true)` hit, `Some(false)` missed by its
/// last test, `None` not tested.
pub fn tested_primitives(steps: &[Step<f64>], count: usize) -> Vec<Option<bool>> {
    let mut tested = vec![None; count];
    for step in steps {
        if let Step::PrimitiveTested { primitive, t_hit } = step
            && let Some(entry) = tested.get_mut(*primitive as usize)
        {
            *entry = Some(t_hit.is_some());
        }
    }
    tested
}

/// Draws every shape, coloured by its last test in `steps` (green hit, red missed), `current`
/// in the "now" colour.
pub fn draw_tested_shapes(
    ui: &egui::Ui,
    canvas: &Canvas,
    shapes: &ShapeSet<DVec2>,
    steps: &[Step<f64>],
    current: Option<u32>,
) {
    let tested = tested_primitives(steps, shapes.shapes.len());
    draw_shapes(ui, canvas, shapes, |index| {
        if Some(index as u32) == current {
            return Some(palette::CURRENT);
        }
        tested[index].map(|hit| if hit { palette::HIT } else { palette::MISS })
    });
}

/// Draws the ray: solid up to `t_solid` (the closest hit so far), faded beyond it.
pub fn draw_ray(canvas: &Canvas, ray: &Ray<DVec2>, t_solid: Option<f64>) {
    draw_ray_colored(canvas, ray, t_solid, palette::RAY, "closest");
}

/// [`draw_ray`] in another colour, with `hit_label` at the closest hit.
pub fn draw_ray_colored(
    canvas: &Canvas,
    ray: &Ray<DVec2>,
    t_solid: Option<f64>,
    color: Color32,
    hit_label: &str,
) {
    let t_end = canvas.clip_t(ray.origin, ray.direction, f64::INFINITY);
    let color = canvas.ink(color);
    if let Some(t) = t_solid.filter(|t| *t < t_end) {
        let cut = ray.origin + ray.direction * t;
        canvas.painter.line_segment(
            [
                canvas.to_screen(cut),
                canvas.to_screen(ray.origin + ray.direction * t_end),
            ],
            Stroke::new(1.5, canvas.ink(faded(color, 70))),
        );
        canvas.ray(ray.origin, ray.direction, t, Stroke::new(2.5, color));
        // Beside the ray on a dark plate, not on the hit shape (green on green).
        canvas.ray_mark_labeled(ray.origin, ray.direction, t, palette::HIT, hit_label, 1.0);
    } else {
        canvas.ray(ray.origin, ray.direction, t_end, Stroke::new(2.5, color));
    }
}

/// A name for primitive `index`: a letter in small scenes (as on the slides), else a number.
pub fn primitive_name(index: u32, count: usize) -> String {
    if count <= 26 {
        char::from(b'A' + index as u8).to_string()
    } else {
        index.to_string()
    }
}

/// Writes each shape's name beside it in small scenes (letters, as on the slides), laid out
/// so that none covers another or leaves the canvas.
pub fn label_shapes(ui: &egui::Ui, canvas: &Canvas, shapes: &ShapeSet<DVec2>) {
    let count = shapes.shapes.len();
    if count > 26 {
        return;
    }
    for (index, shape) in shapes.shapes.iter().enumerate() {
        let bounds = shape.bounds();
        canvas.label(
            DVec2::new(bounds.max.x, bounds.max.y),
            &primitive_name(index as u32, count),
            ui.visuals().strong_text_color(),
        );
    }
}

/// The most shapes numbered on a canvas: beyond it the numbers are a carpet, and a lesson
/// names no primitive a person could find among them.
pub const NUMBERED_SHAPES: usize = 60;

/// Writes each shape's number beside it (the number a lesson's text and status line name:
/// "primitive 12"), laid out so that none covers another; not in scenes of more than
/// [`NUMBERED_SHAPES`].
pub fn number_shapes(ui: &egui::Ui, canvas: &Canvas, shapes: &ShapeSet<DVec2>) {
    if shapes.shapes.len() > NUMBERED_SHAPES {
        return;
    }
    for (index, shape) in shapes.shapes.iter().enumerate() {
        let bounds = shape.bounds();
        canvas.label(
            DVec2::new(bounds.max.x, bounds.max.y),
            &index.to_string(),
            ui.visuals().weak_text_color(),
        );
    }
}

/// The hint every lesson that shows `t` gives once, under its numbers.
pub fn t_hint_ui(ui: &mut egui::Ui) {
    ui.label(
        egui::RichText::new(
            "t is measured in arrow lengths: the ray is r(t) = p + t·d, with t = 1 at the arrow's head. Drag the head to change d, and every t changes with it.",
        )
        .small()
        .weak(),
    );
}

/// Says on the canvas that a newer build is being made (what is drawn is the last one) and
/// keeps the frames coming until it is done.
pub fn building_note(
    ui: &egui::Ui,
    canvas: &Canvas,
    working_for: Option<std::time::Duration>,
    what: &str,
) {
    if let Some(working) = working_for {
        canvas.note(&format!(
            "Building {what}… {:.1} s (the last build is shown until then)",
            working.as_secs_f64()
        ));
        ui.ctx().request_repaint();
    }
}

/// Grid lines at every power of ten of a log10 axis (and none between), so each is labelled.
pub fn powers_of_ten(input: egui_plot::GridInput) -> Vec<egui_plot::GridMark> {
    let (low, high) = input.bounds;
    (low.ceil() as i32..=high.floor() as i32)
        .map(|power| egui_plot::GridMark {
            value: power as f64,
            step_size: 1.0,
        })
        .collect()
}

/// The tick label of a log axis at `mark` (a power of ten): `1`, `10`, `1 000`, `0.01`, one
/// way on every axis (the trade lab mixed `1.000`, `100.0` and `1e6`); between powers, none.
pub fn power_of_ten_label(mark: egui_plot::GridMark, _: &std::ops::RangeInclusive<f64>) -> String {
    let power = mark.value.round();
    if (mark.value - power).abs() > 1e-9 {
        return String::new();
    }
    if power >= 0.0 {
        accelviz_core::format::count(10f64.powf(power).round() as usize)
    } else {
        format!("{:.*}", (-power) as usize, 10f64.powf(power))
    }
}

/// A plot's x axis labelled `label`, whose tick numbers show even in a narrow panel (egui_plot
/// hides x numbers closer than 60 points apart, which in the inspector can hide them all).
pub fn narrow_x_axis<'a>(label: &str) -> egui_plot::AxisHints<'a> {
    egui_plot::AxisHints::new_x()
        .label(label.to_owned())
        .label_spacing(28.0..=40.0)
}
