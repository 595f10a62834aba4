//! Number lines of t: the slab test's intervals, one line per slab and one for their
//! intersection, on one scale (lessons 3 and 11).

use accelviz_core::format::number;
use egui::{Color32, Pos2, Rect, Sense, Stroke, Vec2};

use crate::canvas::{Labels, faded, palette};

/// One line: its name and colour, the interval [t_near, t_far], and whether it is shown yet.
#[derive(Clone, Copy, Debug)]
pub struct IntervalRow<'a> {
    /// Its name, left of the line.
    pub name: &'a str,
    /// Its colour.
    pub color: Color32,
    /// (t_near, t_far); may be infinite, and empty (near > far).
    pub interval: (f64, f64),
    /// Whether its interval is drawn (steps reveal them one by one).
    pub visible: bool,
}

/// The height [`number_lines_ui`] needs for `rows` rows.
pub fn number_lines_height(rows: usize) -> f32 {
    26.0 + rows as f32 * 36.0
}

/// One number line per row, sharing a t scale, with t = 0 marked; a row's interval is a bar
/// with its ends labelled, or "empty" when near > far; infinite ends sit just past the line's
/// ends. Returns where its labels went (none overlap).
pub fn number_lines_ui(ui: &mut egui::Ui, rows: &[IntervalRow<'_>], height: f32) -> Vec<Rect> {
    let (rect, _) = ui.allocate_exact_size(Vec2::new(ui.available_width(), height), Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 4.0, ui.visuals().faint_bg_color);
    let text_color = ui.visuals().text_color();
    // The t range: every finite value and 0, with a margin.
    let finite: Vec<f64> = rows
        .iter()
        .filter(|row| row.visible)
        .flat_map(|row| [row.interval.0, row.interval.1])
        .chain([0.0])
        .filter(|value| value.is_finite())
        .collect();
    let low = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let high = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let margin = ((high - low) * 0.15).max(0.5);
    let (low, high) = (low - margin, high + margin);
    let left = rect.left() + 150.0;
    let right = rect.right() - 30.0;
    let x_of = |t: f64| -> f32 {
        if t == f64::INFINITY {
            right + 16.0
        } else if t == f64::NEG_INFINITY {
            left - 16.0
        } else {
            left + ((t - low) / (high - low)) as f32 * (right - left)
        }
    };
    let mut labels = Labels::new(rect.shrink(2.0));
    // t = 0, where the ray starts: hits behind it do not count.
    let zero = x_of(0.0);
    painter.line_segment(
        [
            Pos2::new(zero, rect.top() + 6.0),
            Pos2::new(zero, rect.bottom() - 6.0),
        ],
        Stroke::new(1.0, Color32::from_gray(160)),
    );
    labels.place(
        &painter,
        "t = 0",
        crate::canvas::font(painter.ctx(), 11.0),
        text_color,
        Pos2::new(zero, rect.top() + 9.0),
        &[Vec2::new(18.0, 0.0), Vec2::new(-18.0, 0.0)],
        None,
    );
    for (index, row) in rows.iter().enumerate() {
        let IntervalRow {
            name,
            color,
            interval: (t_near, t_far),
            visible,
        } = *row;
        let y = rect.top() + 26.0 + index as f32 * 36.0;
        labels.place(
            &painter,
            name,
            crate::canvas::font(painter.ctx(), 13.0),
            color,
            Pos2::new(rect.left() + 70.0, y),
            &[Vec2::ZERO],
            None,
        );
        painter.line_segment(
            [Pos2::new(left - 16.0, y), Pos2::new(right + 16.0, y)],
            Stroke::new(1.0, faded(text_color, 90)),
        );
        if !visible {
            continue;
        }
        if t_near <= t_far {
            let span = Rect::from_x_y_ranges(x_of(t_near)..=x_of(t_far), (y - 5.0)..=(y + 5.0));
            painter.rect_filled(span, 2.0, faded(color, 170));
        } else {
            labels.place(
                &painter,
                "empty: near > far",
                crate::canvas::font(painter.ctx(), 12.0),
                palette::MISS,
                Pos2::new((x_of(t_far) + x_of(t_near)) * 0.5, y),
                &[Vec2::new(0.0, -11.0), Vec2::new(0.0, 11.0)],
                None,
            );
        }
        for (t, label, below) in [(t_near, "near", 1.0), (t_far, "far", -1.0)] {
            let x = x_of(t);
            painter.line_segment(
                [Pos2::new(x, y - 8.0), Pos2::new(x, y + 8.0)],
                Stroke::new(2.0, color),
            );
            labels.place(
                &painter,
                &format!("{label} {}", number(t)),
                crate::canvas::font(painter.ctx(), 11.0),
                text_color,
                Pos2::new(x, y),
                &[
                    Vec2::new(0.0, 13.0 * below),
                    Vec2::new(0.0, -13.0 * below),
                    Vec2::new(34.0 * below, 13.0 * below),
                    Vec2::new(-34.0 * below, 13.0 * below),
                ],
                None,
            );
        }
    }
    labels.placed().to_vec()
}
