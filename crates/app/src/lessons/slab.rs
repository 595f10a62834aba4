//! Lesson 3, "Fast BV Tests (AABB)": the slab test, step by step. A 2D box is two slabs: the
//! horizontal slab between its bottom and top lines (where the ray's y is in range) and the
//! vertical slab between its left and right lines (x in range), the slide's "Horizontal" and
//! "Vertical" rows. Per slab the ray's [t_near, t_far] is drawn on the ray and on a number
//! line; the max of the nears and the min of the fars are marked; the slide's Near/Far table
//! fills in live. The numbers are the core's `slab_record`, the arithmetic traversal runs.
//! Labels are laid out so that none covers another, whatever the case.

use accelviz_core::format::{number, point};
use accelviz_core::{Aabb, Shape, SlabRecord, slab_record};
use egui::{Color32, Pos2, Rect, Stroke, Vec2};
use glam::DVec2;

use crate::canvas::{Canvas, faded, palette};
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::Stage;
use crate::views::number_lines::{IntervalRow, number_lines_ui};
use crate::views::scene_view::{draw_ray, draw_shapes, t_hint_ui};

/// The two slabs in the slide's table order: name, the axis whose interval it gives, and its
/// colour. The horizontal slab lies between two horizontal lines, so it bounds y.
pub const SLABS: [(&str, usize, Color32); 2] = [
    ("Horizontal slab", 1, palette::Y_AXIS),
    ("Vertical slab", 0, palette::X_AXIS),
];

/// The lesson's steps, in the slide's order.
const STEP_CAPTIONS: [&str; 6] = [
    "A box is pairs of parallel planes (lines in 2D), one pair per axis: a slab. The ray is r(t) = p + t·d.",
    "Horizontal slab, between the box's bottom and top lines: where the ray crosses y = min.y and y = max.y gives [t_near, t_far].",
    "Vertical slab, between its left and right lines: where the ray crosses x = min.x and x = max.x gives [t_near, t_far].",
    "Find the max of the t_near: the ray is inside every slab only after it.",
    "Find the min of the t_far: the ray has left some slab after it.",
    "If max t_near > min t_far the box is not intersected (also missed when min t_far < 0: behind).",
];

/// The edge cases one click away: a name, and where the ray goes relative to the box.
pub const GALLERY: [(&str, &str); 6] = [
    (
        "crossing",
        "a plain hit, entering through one slab and leaving through the other",
    ),
    (
        "parallel to a slab",
        "d.y = 0 inside the horizontal slab: its t_near = −∞, t_far = +∞",
    ),
    (
        "parallel, outside",
        "d.y = 0 outside the horizontal slab: that slab's interval is empty",
    ),
    (
        "origin inside",
        "p inside the box: max t_near < 0 < min t_far, still a hit",
    ),
    (
        "box behind the ray",
        "the whole interval is at t < 0: a miss",
    ),
    (
        "origin on a slab plane",
        "p.x = min.x with d.x = 0: 0 · ∞ must not become NaN",
    ),
];

/// The lesson.
pub struct SlabLesson {
    stage: Stage,
    robust: bool,
    /// Where the last frame put its labels, on the canvas and on the number lines.
    label_rects: Vec<Vec<Rect>>,
}

impl SlabLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let mut stage = Stage::new(text, Editing::BY_HAND);
        // At the first step, as every lesson (and lecture mode) opens: step and play walk it.
        stage.timeline.set_len(STEP_CAPTIONS.len() - 1);
        Self {
            stage,
            robust: false,
            label_rects: Vec::new(),
        }
    }

    /// The first box of the scene: the one tested.
    fn tested_box(&self) -> Option<Aabb<DVec2>> {
        self.stage
            .scene
            .scene
            .shapes
            .shapes
            .iter()
            .find_map(|shape| match shape {
                Shape::Box(bounds) => Some(*bounds),
                _ => None,
            })
    }

    /// The tested box and the core's slab record for the current ray.
    pub fn record(&self) -> Option<(Aabb<DVec2>, SlabRecord<DVec2>)> {
        let bounds = self.tested_box()?;
        let ray = self.stage.scene.ray().ok()?;
        Some((bounds, slab_record(&bounds, &ray, self.robust)))
    }

    /// Where the last frame's labels went: one list for the canvas, one for the number lines.
    pub fn label_rects(&self) -> &[Vec<Rect>] {
        &self.label_rects
    }

    /// Puts the ray where edge case `case` of [`GALLERY`] happens.
    pub fn show_case(&mut self, case: usize) {
        let Some(bounds) = self.tested_box() else {
            return;
        };
        let (center, extent) = (bounds.center(), bounds.extent());
        let (origin, direction) = match case {
            0 => (bounds.min - extent * 0.8, DVec2::new(1.0, 0.7)),
            1 => (
                DVec2::new(bounds.min.x - extent.x * 0.7, center.y),
                DVec2::new(1.0, 0.0),
            ),
            2 => (
                DVec2::new(bounds.min.x - extent.x * 0.7, bounds.max.y + extent.y * 0.3),
                DVec2::new(1.0, 0.0),
            ),
            3 => (center, DVec2::new(1.0, 0.4)),
            4 => (bounds.max + extent * 0.5, DVec2::new(1.0, 0.6)),
            _ => (
                DVec2::new(bounds.min.x, bounds.min.y - extent.y * 0.6),
                DVec2::new(0.0, 1.0),
            ),
        };
        let length = extent.length().max(1e-9) * 0.4;
        let scene = &mut self.stage.scene;
        scene.scene.ray_origin = origin;
        scene.scene.ray_toward = origin + direction.normalize() * length;
        scene.touch_ray();
        scene.view.placed = false;
    }

    /// The slide's table: Near and Far per slab, and the max of the nears and min of the fars.
    fn table_ui(ui: &mut egui::Ui, record: &SlabRecord<DVec2>, shown: usize) {
        let enter_axis = (record.t_near.y > record.t_near.x) as usize;
        let exit_axis = (record.t_far.y < record.t_far.x) as usize;
        // A table keeps its columns: in a narrow panel (the app scaled up) it scrolls
        // sideways rather than widen the panel.
        egui::ScrollArea::horizontal()
            .id_salt("slab table columns")
            .show(ui, |ui| {
                egui::Grid::new("slab table")
                    .striped(true)
                    .min_col_width(64.0)
                    .show(ui, |ui| {
                        ui.label("");
                        ui.strong("Near");
                        ui.strong("Far");
                        ui.end_row();
                        for (row, (name, axis, color)) in SLABS.iter().enumerate() {
                            ui.colored_label(crate::canvas::readable(ui, *color), *name).on_hover_text(match axis {
                            1 => "between the box's bottom and top lines: the ray's y is in range",
                            _ => "between the box's left and right lines: the ray's x is in range",
                        });
                            let known = shown > row;
                            let cell = |ui: &mut egui::Ui, value: f64, chosen: bool| {
                                let text = if known { number(value) } else { "?".to_owned() };
                                let rich = egui::RichText::new(text).monospace();
                                ui.label(if chosen {
                                    rich.strong()
                                        .color(crate::canvas::readable(ui, palette::CURRENT))
                                } else {
                                    rich
                                });
                            };
                            cell(ui, record.t_near[*axis], shown >= 3 && *axis == enter_axis);
                            cell(ui, record.t_far[*axis], shown >= 4 && *axis == exit_axis);
                            ui.end_row();
                        }
                        ui.strong("max / min");
                        ui.label(if shown >= 3 {
                            number(record.t_enter)
                        } else {
                            "?".into()
                        });
                        ui.label(if shown >= 4 {
                            number(record.t_exit)
                        } else {
                            "?".into()
                        });
                        ui.end_row();
                    });
            });
    }
}

impl Lesson for SlabLesson {
    crate::staged!();

    fn caption(&self) -> Option<String> {
        let step = self.stage.timeline.shown.min(STEP_CAPTIONS.len() - 1);
        let said = STEP_CAPTIONS[step];
        if step == STEP_CAPTIONS.len() - 1
            && let Some((_, record)) = self.record()
        {
            return Some(format!(
                "{said} Here: {}.",
                if record.hit { "a hit" } else { "a miss" }
            ));
        }
        Some(said.to_owned())
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        ui.heading("Edge cases");
        ui.horizontal_wrapped(|ui| {
            for (index, (name, explanation)) in GALLERY.iter().enumerate() {
                if ui.button(*name).on_hover_text(*explanation).clicked() {
                    self.show_case(index);
                }
            }
        });
        ui.checkbox(
            &mut self.robust,
            "conservative test (t_far widened by 1 + 2γ₃, Ize 2013)",
        );
        ui.separator();
        let Some((bounds, record)) = self.record() else {
            ui.label("The scene needs a box and a ray with a direction.");
            return;
        };
        let shown = self.stage.timeline.shown;
        ui.heading("Near and far, per slab");
        Self::table_ui(ui, &record, shown);
        if shown >= 5 {
            let verdict = if record.hit {
                format!(
                    "HIT: max t_near = {} ≤ min t_far = {} and min t_far ≥ 0",
                    number(record.t_enter),
                    number(record.t_exit)
                )
            } else if record.t_enter > record.t_exit {
                format!(
                    "MISS: max t_near = {} > min t_far = {}",
                    number(record.t_enter),
                    number(record.t_exit)
                )
            } else {
                format!(
                    "MISS: the box is behind the ray (min t_far = {} < 0)",
                    number(record.t_exit)
                )
            };
            ui.colored_label(
                crate::canvas::readable(
                    ui,
                    if record.hit {
                        palette::HIT
                    } else {
                        palette::MISS
                    },
                ),
                verdict,
            );
        }
        if let Ok(ray) = self.stage.scene.ray() {
            ui.label(format!(
                "p = {}, d = {}; the box runs from {} to {}",
                point(&[ray.origin.x, ray.origin.y]),
                point(&[ray.direction.x, ray.direction.y]),
                point(&[bounds.min.x, bounds.min.y]),
                point(&[bounds.max.x, bounds.max.y]),
            ));
        }
        t_hint_ui(ui);
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.stage.scene.toolbar_ui(ui);
        // Room around the box for the slab lines and the ray beyond it.
        let bounds = match self.tested_box() {
            Some(tested) => Aabb::new(tested.min - tested.extent(), tested.max + tested.extent())
                .union(self.stage.scene.bounds()),
            None => self.stage.scene.bounds(),
        };
        let number_lines_height = 130.0;
        let size = ui.available_size() - Vec2::new(0.0, number_lines_height + 6.0);
        let canvas = Canvas::allocate(
            ui,
            size.max(Vec2::splat(50.0)),
            &mut self.stage.scene.view,
            &bounds,
            false,
        );
        self.stage.scene.interact(ui, &canvas);
        draw_shapes(ui, &canvas, &self.stage.scene.scene.shapes, |_| None);
        let record = self.record();
        let shown = self.stage.timeline.shown;
        let ray = self.stage.scene.ray();
        if let (Some((bounds, record)), Ok(ray)) = (record, &ray) {
            // The slab lines across the canvas, in the order the steps reveal them.
            let visible = canvas.rect;
            for (row, (_, axis, color)) in SLABS.iter().enumerate() {
                if shown <= row {
                    continue;
                }
                for value in [bounds.min[*axis], bounds.max[*axis]] {
                    let on_screen = canvas.to_screen(DVec2::splat(value));
                    let line = if *axis == 0 {
                        [
                            Pos2::new(on_screen.x, visible.top()),
                            Pos2::new(on_screen.x, visible.bottom()),
                        ]
                    } else {
                        [
                            Pos2::new(visible.left(), on_screen.y),
                            Pos2::new(visible.right(), on_screen.y),
                        ]
                    };
                    canvas
                        .painter
                        .line_segment(line, Stroke::new(1.0, faded(*color, 160)));
                }
            }
            draw_ray(&canvas, ray, None);
            // Each slab's interval along the ray, drawn beside it.
            let along = (canvas.to_screen(ray.origin + ray.direction)
                - canvas.to_screen(ray.origin))
            .normalized();
            let side = Vec2::new(-along.y, along.x);
            for (row, (name, axis, color)) in SLABS.iter().enumerate() {
                if shown <= row {
                    continue;
                }
                let (t_near, t_far) = (record.t_near[*axis], record.t_far[*axis]);
                if t_near <= t_far {
                    let t_start =
                        t_near.max(-canvas.clip_t(ray.origin, -ray.direction, f64::INFINITY));
                    let t_end = canvas.clip_t(ray.origin, ray.direction, t_far);
                    let offset = side * (8.0 + 7.0 * row as f32);
                    canvas.painter.line_segment(
                        [
                            canvas.to_screen(ray.at(t_start)) + offset,
                            canvas.to_screen(ray.at(t_end)) + offset,
                        ],
                        Stroke::new(4.0, faded(*color, 200)),
                    );
                }
                let short = if *axis == 1 { "horizontal" } else { "vertical" };
                let _ = name;
                canvas.ray_mark_labeled(
                    ray.origin,
                    ray.direction,
                    t_near,
                    *color,
                    &format!("near, {short}"),
                    1.0,
                );
                canvas.ray_mark_labeled(
                    ray.origin,
                    ray.direction,
                    t_far,
                    *color,
                    &format!("far, {short}"),
                    -1.0,
                );
            }
            if shown >= 3 {
                canvas.ray_mark_labeled(
                    ray.origin,
                    ray.direction,
                    record.t_enter,
                    palette::CURRENT,
                    "max near",
                    1.0,
                );
            }
            if shown >= 4 {
                canvas.ray_mark_labeled(
                    ray.origin,
                    ray.direction,
                    record.t_exit,
                    palette::CURRENT,
                    "min far",
                    -1.0,
                );
            }
            let outcome = match (shown >= 5, record.hit) {
                (false, _) => palette::BOX,
                (true, true) => palette::HIT,
                (true, false) => palette::MISS,
            };
            canvas.box_outline(&bounds, Stroke::new(2.5, outcome), None);
        } else if let Err(error) = &ray {
            canvas.caption(&[(format!("No ray: {error}"), palette::MISS)]);
        }
        self.stage.scene.draw_handles(&canvas);
        canvas.finish();
        let mut rects = vec![canvas.placed_labels()];
        if let Some((_, record)) = record {
            let rows = [
                IntervalRow {
                    name: "horizontal slab",
                    color: SLABS[0].2,
                    interval: (record.t_near.y, record.t_far.y),
                    visible: shown >= 1,
                },
                IntervalRow {
                    name: "vertical slab",
                    color: SLABS[1].2,
                    interval: (record.t_near.x, record.t_far.x),
                    visible: shown >= 2,
                },
                IntervalRow {
                    name: "both",
                    color: palette::CURRENT,
                    interval: (record.t_enter, record.t_exit),
                    visible: shown >= 4,
                },
            ];
            rects.push(number_lines_ui(ui, &rows, number_lines_height));
        }
        self.label_rects = rects;
    }
}
