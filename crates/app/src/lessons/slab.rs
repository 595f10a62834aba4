//! Lesson 3, "Fast BV Tests (AABB)": the slab test, step by step. Per axis the ray's
//! [t_near, t_far] is drawn on the ray and on a number line; the max of the nears and the min
//! of the fars are marked; the slide's Near/Far table fills in live. The numbers are the
//! core's `slab_record`, the same arithmetic the traversals run.

use accelviz_core::{Aabb, Shape, SlabRecord, slab_record};
use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, Vec2};
use glam::DVec2;

use super::common::{self, number};
use super::{Lesson, LessonText};
use crate::canvas::{Canvas, faded, palette};
use crate::editor::{EditableScene, Editing};
use crate::timeline::Timeline;

/// The lesson's steps, in the slide's order.
const STEP_CAPTIONS: [&str; 6] = [
    "A box is pairs of parallel planes (lines in 2D), each pair across one axis. The ray is r(t) = p + t·d.",
    "Horizontal: where the ray crosses x = min.x and x = max.x gives [t_near, t_far] on x.",
    "Vertical: where it crosses y = min.y and y = max.y gives [t_near, t_far] on y.",
    "Find the max of the t_near: the ray is inside every slab only after it.",
    "Find the min of the t_far: the ray has left some slab after it.",
    "If max t_near > min t_far the box is not intersected (also missed when min t_far < 0: behind).",
];

/// The edge cases one click away: a name, and where the ray goes relative to the box.
const GALLERY: [(&str, &str); 6] = [
    (
        "crossing",
        "a plain hit, entering through one slab and leaving through the other",
    ),
    (
        "parallel to a slab",
        "d.y = 0 inside the y slab: t_near.y = −∞, t_far.y = +∞",
    ),
    (
        "parallel, outside",
        "d.y = 0 outside the y slab: that axis's interval is empty",
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
    text: LessonText,
    scene: EditableScene,
    timeline: Timeline,
    robust: bool,
}

impl SlabLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let scene = EditableScene::new(text.scene.clone(), Editing::BY_HAND);
        let mut timeline = Timeline::default();
        timeline.set_len(STEP_CAPTIONS.len() - 1);
        timeline.shown = timeline.len;
        Self {
            text,
            scene,
            timeline,
            robust: false,
        }
    }

    /// The first box of the scene: the one tested.
    fn tested_box(&self) -> Option<Aabb<DVec2>> {
        self.scene
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
        let ray = self.scene.ray().ok()?;
        Some((bounds, slab_record(&bounds, &ray, self.robust)))
    }

    /// Puts the ray where an edge case happens.
    fn apply_case(&mut self, case: usize) {
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
        self.scene.scene.ray_origin = origin;
        self.scene.scene.ray_toward = origin + direction.normalize() * length;
        self.scene.touch();
    }
}

impl Lesson for SlabLesson {
    fn text(&self) -> &LessonText {
        &self.text
    }

    fn scene_mut(&mut self) -> Option<&mut EditableScene> {
        Some(&mut self.scene)
    }

    fn timeline(&mut self) -> Option<(&mut Timeline, String)> {
        let caption = STEP_CAPTIONS[self.timeline.shown.min(STEP_CAPTIONS.len() - 1)].to_owned();
        Some((&mut self.timeline, caption))
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Edge cases");
        ui.horizontal_wrapped(|ui| {
            for (index, (name, explanation)) in GALLERY.iter().enumerate() {
                if ui.button(*name).on_hover_text(*explanation).clicked() {
                    self.apply_case(index);
                }
            }
        });
        ui.checkbox(
            &mut self.robust,
            "conservative test (t_far widened by 1 + 2γ₃, Ize 2013)",
        );
        ui.separator();
        let Some((_, record)) = self.record() else {
            ui.label("The scene needs a box and a ray with a direction.");
            return;
        };
        let shown = self.timeline.shown;
        ui.heading("Near and far, per slab");
        let enter_axis = (record.t_near.y > record.t_near.x) as usize;
        let exit_axis = (record.t_far.y < record.t_far.x) as usize;
        egui::Grid::new("slab table")
            .striped(true)
            .min_col_width(70.0)
            .show(ui, |ui| {
                ui.label("");
                ui.strong("Near");
                ui.strong("Far");
                ui.end_row();
                for (axis, name, color) in [
                    (0, "Horizontal (x)", palette::X_AXIS),
                    (1, "Vertical (y)", palette::Y_AXIS),
                ] {
                    ui.colored_label(color, name);
                    let known = shown > axis;
                    let cell = |ui: &mut egui::Ui, value: f64, chosen: bool| {
                        let text = if known { number(value) } else { "?".to_owned() };
                        let rich = egui::RichText::new(text).monospace();
                        ui.label(if chosen {
                            rich.strong().color(palette::CURRENT)
                        } else {
                            rich
                        });
                    };
                    cell(ui, record.t_near[axis], shown >= 3 && axis == enter_axis);
                    cell(ui, record.t_far[axis], shown >= 4 && axis == exit_axis);
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
                if record.hit {
                    palette::HIT
                } else {
                    palette::MISS
                },
                verdict,
            );
        }
        if let Ok(ray) = self.scene.ray() {
            ui.label(format!(
                "p = ({}, {}), d = ({}, {})",
                number(ray.origin.x),
                number(ray.origin.y),
                number(ray.direction.x),
                number(ray.direction.y)
            ));
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.scene.toolbar_ui(ui);
        // Room around the box for the slab lines and the ray beyond it.
        let bounds = match self.tested_box() {
            Some(tested) => Aabb::new(tested.min - tested.extent(), tested.max + tested.extent())
                .union(self.scene.bounds()),
            None => self.scene.bounds(),
        };
        let number_lines_height = 120.0;
        let size = ui.available_size() - Vec2::new(0.0, number_lines_height + 6.0);
        let canvas = Canvas::allocate(
            ui,
            size.max(Vec2::splat(50.0)),
            &mut self.scene.view,
            &bounds,
            false,
        );
        self.scene.interact(ui, &canvas);
        common::draw_shapes(ui, &canvas, &self.scene.scene.shapes, |_| None);
        let record = self.record();
        let shown = self.timeline.shown;
        let ray = self.scene.ray();
        if let (Some((bounds, record)), Ok(ray)) = (record, &ray) {
            // The slab planes, as lines across the canvas.
            let visible = canvas.rect;
            for (axis, color) in [(0, palette::X_AXIS), (1, palette::Y_AXIS)] {
                if shown <= axis {
                    continue;
                }
                for value in [bounds.min[axis], bounds.max[axis]] {
                    let on_screen = canvas.to_screen(DVec2::splat(value));
                    let line = if axis == 0 {
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
                        .line_segment(line, Stroke::new(1.0, faded(color, 160)));
                }
            }
            common::draw_ray(&canvas, ray, None);
            // Each axis's interval along the ray, drawn beside it.
            let along = (canvas.to_screen(ray.origin + ray.direction)
                - canvas.to_screen(ray.origin))
            .normalized();
            let side = Vec2::new(-along.y, along.x);
            for (axis, color) in [(0, palette::X_AXIS), (1, palette::Y_AXIS)] {
                if shown <= axis {
                    continue;
                }
                let (t_near, t_far) = (record.t_near[axis], record.t_far[axis]);
                if t_near <= t_far {
                    let t_start =
                        t_near.max(-canvas.clip_t(ray.origin, -ray.direction, f64::INFINITY));
                    let t_end = canvas.clip_t(ray.origin, ray.direction, t_far);
                    let offset = side * (8.0 + 7.0 * axis as f32);
                    canvas.painter.line_segment(
                        [
                            canvas.to_screen(ray.at(t_start)) + offset,
                            canvas.to_screen(ray.at(t_end)) + offset,
                        ],
                        Stroke::new(4.0, faded(color, 200)),
                    );
                }
                let name = if axis == 0 { "x" } else { "y" };
                canvas.ray_mark(
                    ray.origin,
                    ray.direction,
                    t_near,
                    color,
                    &format!("near {name}"),
                    2.2 + 1.8 * axis as f32,
                );
                canvas.ray_mark(
                    ray.origin,
                    ray.direction,
                    t_far,
                    color,
                    &format!("far {name}"),
                    -2.2 - 1.8 * axis as f32,
                );
            }
            if shown >= 3 {
                canvas.ray_mark(
                    ray.origin,
                    ray.direction,
                    record.t_enter,
                    palette::CURRENT,
                    "max near",
                    6.0,
                );
            }
            if shown >= 4 {
                canvas.ray_mark(
                    ray.origin,
                    ray.direction,
                    record.t_exit,
                    palette::CURRENT,
                    "min far",
                    -6.0,
                );
            }
            canvas.box_outline(
                &bounds,
                Stroke::new(
                    2.5,
                    if shown >= 5 {
                        if record.hit {
                            palette::HIT
                        } else {
                            palette::MISS
                        }
                    } else {
                        palette::BOX
                    },
                ),
                None,
            );
        } else if let Err(error) = &ray {
            canvas.caption(&[(format!("No ray: {error}"), palette::MISS)]);
        }
        self.scene.draw_handles(&canvas);
        if let Some((_, record)) = record {
            number_lines_ui(ui, &record, shown, number_lines_height);
        }
    }
}

/// One number line per axis and one for the result, sharing a t scale.
fn number_lines_ui(ui: &mut egui::Ui, record: &SlabRecord<DVec2>, shown: usize, height: f32) {
    let (rect, _) = ui.allocate_exact_size(Vec2::new(ui.available_width(), height), Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 4.0, ui.visuals().faint_bg_color);
    let text_color = ui.visuals().text_color();
    // The t range: every finite value and 0, with a margin.
    let finite: Vec<f64> = [
        record.t_near.x,
        record.t_near.y,
        record.t_far.x,
        record.t_far.y,
        0.0,
    ]
    .into_iter()
    .filter(|value| value.is_finite())
    .collect();
    let low = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let high = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let margin = ((high - low) * 0.15).max(0.5);
    let (low, high) = (low - margin, high + margin);
    let left = rect.left() + 110.0;
    let right = rect.right() - 20.0;
    let x_of = |t: f64| -> f32 {
        if t == f64::INFINITY {
            right + 10.0
        } else if t == f64::NEG_INFINITY {
            left - 10.0
        } else {
            left + ((t - low) / (high - low)) as f32 * (right - left)
        }
    };
    let rows = [
        (
            "x slab",
            palette::X_AXIS,
            Some((record.t_near.x, record.t_far.x)),
            shown >= 1,
        ),
        (
            "y slab",
            palette::Y_AXIS,
            Some((record.t_near.y, record.t_far.y)),
            shown >= 2,
        ),
        (
            "both",
            palette::CURRENT,
            Some((record.t_enter, record.t_exit)),
            shown >= 4,
        ),
    ];
    for (row, (name, color, interval, visible)) in rows.into_iter().enumerate() {
        let y = rect.top() + 22.0 + row as f32 * 32.0;
        painter.text(
            Pos2::new(rect.left() + 10.0, y),
            Align2::LEFT_CENTER,
            name,
            FontId::proportional(13.0),
            color,
        );
        painter.line_segment(
            [Pos2::new(left - 10.0, y), Pos2::new(right + 10.0, y)],
            Stroke::new(1.0, faded(text_color, 90)),
        );
        if !visible {
            continue;
        }
        let Some((t_near, t_far)) = interval else {
            continue;
        };
        if t_near <= t_far {
            let span = Rect::from_x_y_ranges(x_of(t_near)..=x_of(t_far), (y - 5.0)..=(y + 5.0));
            painter.rect_filled(span, 2.0, faded(color, 170));
        } else {
            painter.text(
                Pos2::new((x_of(t_far) + x_of(t_near)) * 0.5, y - 10.0),
                Align2::CENTER_CENTER,
                "empty: near > far",
                FontId::proportional(12.0),
                palette::MISS,
            );
        }
        for (t, label) in [(t_near, "near"), (t_far, "far")] {
            let x = x_of(t);
            painter.line_segment(
                [Pos2::new(x, y - 8.0), Pos2::new(x, y + 8.0)],
                Stroke::new(2.0, color),
            );
            painter.text(
                Pos2::new(x, y + 14.0),
                Align2::CENTER_CENTER,
                format!("{label} {}", number(t)),
                FontId::proportional(11.0),
                text_color,
            );
        }
    }
    // t = 0, where the ray starts: hits behind it do not count.
    let zero = x_of(0.0);
    painter.line_segment(
        [
            Pos2::new(zero, rect.top() + 6.0),
            Pos2::new(zero, rect.bottom() - 6.0),
        ],
        Stroke::new(1.0, Color32::from_gray(160)),
    );
    painter.text(
        Pos2::new(zero + 3.0, rect.top() + 8.0),
        Align2::LEFT_TOP,
        "t = 0",
        FontId::proportional(11.0),
        text_color,
    );
}
