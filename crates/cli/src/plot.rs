//! Plots as standalone SVG: scatter plots of labelled points, a colour for each family, with
//! round-number ticks and an optional `y = x` line, and lines on log-log axes with marks.
//! Sized and lettered to be read on a projected slide.

use std::fmt::Write;

/// One labelled point.
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub label: String,
    /// Which family (and colour): an index into [`Scatter::families`].
    pub family: usize,
}

/// A scatter plot.
pub struct Scatter {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// The families' names, for the legend, in the order of their colours.
    pub families: Vec<String>,
    pub points: Vec<Point>,
    /// Draw the line `y = x` (for predicted against measured).
    pub diagonal: bool,
    /// A logarithmic x axis (for times spanning decades).
    pub log_x: bool,
}

const WIDTH: f64 = 960.0;
const HEIGHT: f64 = 600.0;
const LEFT: f64 = 100.0;
const RIGHT: f64 = 40.0;
const TOP: f64 = 70.0;
const BOTTOM: f64 = 80.0;

/// Ticks of a logarithmic axis over `[low, high]` (both positive): 1, 2 and 5 times powers of
/// ten.
fn log_ticks(low: f64, high: f64) -> Vec<f64> {
    let mut ticks = Vec::new();
    let mut power = 10f64.powf(low.log10().floor());
    while power <= high {
        for factor in [1.0, 2.0, 5.0] {
            let tick = factor * power;
            if (low..=high).contains(&tick) {
                ticks.push(tick);
            }
        }
        power *= 10.0;
    }
    ticks
}

/// Where labels go: beside their point if there is room, else a little further with a leader
/// line; never over another label. `boxes` are the labels placed so far.
fn place_label(
    point: (f64, f64),
    width: f64,
    boxes: &mut Vec<[f64; 4]>,
    bounds: [f64; 4],
) -> (f64, f64, &'static str) {
    let height = 16.0;
    let overlaps = |b: &[f64; 4]| {
        boxes
            .iter()
            .any(|o| b[0] < o[2] && o[0] < b[2] && b[1] < o[3] && o[1] < b[3])
    };
    let inside = |b: &[f64; 4]| {
        b[0] >= bounds[0] && b[2] <= bounds[2] && b[1] >= bounds[1] && b[3] <= bounds[3]
    };
    let mut first = None;
    for distance in [10.0, 24.0, 40.0, 58.0, 78.0, 100.0] {
        for (dx, dy) in [
            (1.0, -0.5),
            (-1.0, -0.5),
            (1.0, 0.6),
            (-1.0, 0.6),
            (0.0, -1.3),
            (0.0, 1.5),
        ] {
            let (x, y) = (point.0 + dx * distance, point.1 + dy * distance);
            let (left, anchor) = if dx > 0.0 {
                (x, "start")
            } else if dx < 0.0 {
                (x - width, "end")
            } else {
                (x - width / 2.0, "middle")
            };
            let label_box = [left, y - height + 4.0, left + width, y + 4.0];
            first.get_or_insert((x, y, anchor, label_box));
            if inside(&label_box) && !overlaps(&label_box) {
                boxes.push(label_box);
                return (x, y, anchor);
            }
        }
    }
    let (x, y, anchor, label_box) = first.unwrap_or((point.0, point.1, "start", [0.0; 4]));
    boxes.push(label_box);
    (x, y, anchor)
}

/// Round tick values covering `[low, high]`: steps of 1, 2 or 5 times a power of ten.
fn ticks(low: f64, high: f64) -> Vec<f64> {
    let span = (high - low).max(f64::MIN_POSITIVE);
    let rough = span / 6.0;
    let power = 10f64.powf(rough.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|factor| factor * power)
        .find(|step| span / step <= 7.0)
        .unwrap_or(10.0 * power);
    let first = (low / step).ceil() as i64;
    let last = (high / step).floor() as i64;
    // Dividing by a whole number keeps 0.3 from printing as 0.30000000000000004.
    let inverse = (1.0 / step).round();
    (first..=last)
        .map(|index| {
            if step < 1.0 {
                index as f64 / inverse
            } else {
                index as f64 * step
            }
        })
        .collect()
}

fn tick_text(value: f64) -> String {
    if value == 0.0 {
        "0".into()
    } else if value.abs() >= 1e4 || value.abs() < 1e-2 {
        format!("{value:.0e}")
    } else {
        let text = format!("{value:.3}");
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    }
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// What both kinds of plot draw around their data: the document's start with the title, the
/// grid with its ticks (`x_ticks` and `y_ticks` as values and where they are drawn), the plot's
/// frame, and the axes' titles. The caller adds its data and closes the document.
struct Frame<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    plot_width: f64,
    plot_height: f64,
}

impl Frame<'_> {
    fn draw(&self, x_ticks: &[(f64, f64)], y_ticks: &[(f64, f64)]) -> String {
        let (plot_width, plot_height) = (self.plot_width, self.plot_height);
        let mut svg = String::new();
        let _ = writeln!(
            svg,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" viewBox="0 0 {WIDTH} {HEIGHT}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">"#
        );
        let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
        let _ = writeln!(
            svg,
            r#"<text x="{}" y="38" font-size="24" text-anchor="middle" font-weight="bold">{}</text>"#,
            WIDTH / 2.0,
            escape(self.title)
        );
        for &(x, px) in x_ticks {
            let _ = writeln!(
                svg,
                r##"<line x1="{px:.1}" y1="{TOP}" x2="{px:.1}" y2="{:.1}" stroke="#e4e4e4"/><text x="{px:.1}" y="{:.1}" font-size="16" text-anchor="middle">{}</text>"##,
                TOP + plot_height,
                TOP + plot_height + 24.0,
                tick_text(x)
            );
        }
        for &(y, py) in y_ticks {
            let _ = writeln!(
                svg,
                r##"<line x1="{LEFT}" y1="{py:.1}" x2="{:.1}" y2="{py:.1}" stroke="#e4e4e4"/><text x="{:.1}" y="{:.1}" font-size="16" text-anchor="end">{}</text>"##,
                LEFT + plot_width,
                LEFT - 10.0,
                py + 5.0,
                tick_text(y)
            );
        }
        let _ = writeln!(
            svg,
            r##"<rect x="{LEFT}" y="{TOP}" width="{plot_width}" height="{plot_height}" fill="none" stroke="#444"/>"##
        );
        let _ = writeln!(
            svg,
            r#"<text x="{:.1}" y="{:.1}" font-size="18" text-anchor="middle">{}</text>"#,
            LEFT + plot_width / 2.0,
            HEIGHT - 24.0,
            escape(self.x_label)
        );
        let _ = writeln!(
            svg,
            r#"<text transform="translate(28 {:.1}) rotate(-90)" font-size="18" text-anchor="middle">{}</text>"#,
            TOP + plot_height / 2.0,
            escape(self.y_label)
        );
        svg
    }
}

impl Scatter {
    /// The plot as an SVG document.
    pub fn to_svg(&self) -> String {
        let finite: Vec<&Point> = self
            .points
            .iter()
            .filter(|p| p.x.is_finite() && p.y.is_finite())
            .collect();
        let range = |value: fn(&Point) -> f64| {
            let (low, high) = finite
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |acc, p| {
                    (acc.0.min(value(p)), acc.1.max(value(p)))
                });
            if low > high {
                (0.0, 1.0)
            } else {
                // Start at zero when that costs little room, and leave a margin.
                let low = if low > 0.0 && low < 0.5 * high {
                    0.0
                } else {
                    low
                };
                let pad = 0.08 * (high - low).max(high.abs() * 0.05).max(1e-9);
                (low - if low == 0.0 { 0.0 } else { pad }, high + pad)
            }
        };
        let (mut x_low, mut x_high) = if self.log_x {
            let (low, high) = finite
                .iter()
                .filter(|p| p.x > 0.0)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |acc, p| {
                    (acc.0.min(p.x), acc.1.max(p.x))
                });
            if low > high {
                (1.0, 10.0)
            } else {
                (low / 1.6, high * 1.6)
            }
        } else {
            range(|p| p.x)
        };
        let (mut y_low, mut y_high) = range(|p| p.y);
        if self.diagonal {
            // Same range on both axes, so the diagonal is at 45 degrees.
            x_low = x_low.min(y_low);
            y_low = x_low;
            x_high = x_high.max(y_high);
            y_high = x_high;
        }
        let plot_width = WIDTH - LEFT - RIGHT;
        let plot_height = HEIGHT - TOP - BOTTOM;
        let log_x = self.log_x;
        let to_x = |x: f64| {
            let fraction = if log_x {
                (x.max(f64::MIN_POSITIVE) / x_low).ln() / (x_high / x_low).ln()
            } else {
                (x - x_low) / (x_high - x_low)
            };
            LEFT + fraction * plot_width
        };
        let to_y = |y: f64| TOP + plot_height - (y - y_low) / (y_high - y_low) * plot_height;

        // Grid and ticks.
        let x_ticks = if log_x {
            log_ticks(x_low, x_high)
        } else {
            ticks(x_low, x_high)
        };
        let frame = Frame {
            title: &self.title,
            x_label: &self.x_label,
            y_label: &self.y_label,
            plot_width,
            plot_height,
        };
        let mut svg = frame.draw(
            &x_ticks.iter().map(|&x| (x, to_x(x))).collect::<Vec<_>>(),
            &ticks(y_low, y_high)
                .iter()
                .map(|&y| (y, to_y(y)))
                .collect::<Vec<_>>(),
        );
        if self.diagonal {
            let _ = writeln!(
                svg,
                r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#888" stroke-dasharray="6 5"/><text x="{:.1}" y="{:.1}" font-size="15" fill="#666" text-anchor="end">measured = predicted</text>"##,
                to_x(x_low),
                to_y(x_low),
                to_x(x_high),
                to_y(x_high),
                to_x(x_high) - 8.0,
                to_y(x_high) + 22.0,
            );
        }
        // Points, then their labels placed clear of each other (and of the legend).
        let legend_width = self
            .families
            .iter()
            .map(|family| 8.6 * family.chars().count() as f64)
            .fold(0.0, f64::max);
        let mut boxes = vec![[
            LEFT,
            TOP,
            LEFT + 44.0 + legend_width,
            TOP + 14.0 + 26.0 * self.families.len() as f64,
        ]];
        let plot_bounds = [
            LEFT + 2.0,
            TOP + 2.0,
            LEFT + plot_width - 2.0,
            TOP + plot_height - 2.0,
        ];
        for point in &finite {
            let (px, py) = (to_x(point.x), to_y(point.y));
            boxes.push([px - 7.0, py - 7.0, px + 7.0, py + 7.0]);
            let colour = series_colour(point.family);
            let _ = writeln!(
                svg,
                r#"<circle cx="{px:.1}" cy="{py:.1}" r="7" fill="{colour}" fill-opacity="0.85"/>"#
            );
        }
        for point in &finite {
            let (px, py) = (to_x(point.x), to_y(point.y));
            let colour = series_colour(point.family);
            let width = 8.6 * point.label.chars().count() as f64;
            let (x, y, anchor) = place_label((px, py), width, &mut boxes, plot_bounds);
            if (x - px).abs() + (y - py).abs() > 20.0 {
                let _ = writeln!(
                    svg,
                    r#"<line x1="{px:.1}" y1="{py:.1}" x2="{x:.1}" y2="{:.1}" stroke="{colour}" stroke-opacity="0.6"/>"#,
                    y - 5.0
                );
            }
            let _ = writeln!(
                svg,
                r#"<text x="{x:.1}" y="{y:.1}" font-size="15" text-anchor="{anchor}" fill="{colour}">{}</text>"#,
                escape(&point.label)
            );
        }
        // Legend.
        for (index, family) in self.families.iter().enumerate() {
            let y = TOP + 22.0 + 26.0 * index as f64;
            let _ = writeln!(
                svg,
                r#"<circle cx="{:.1}" cy="{y:.1}" r="7" fill="{}"/><text x="{:.1}" y="{:.1}" font-size="16">{}</text>"#,
                LEFT + 20.0,
                series_colour(index),
                LEFT + 34.0,
                y + 5.0,
                escape(family)
            );
        }
        svg.push_str("</svg>\n");
        svg
    }
}

/// Lines on log-log axes (total time against rays) or linear ones, each named at its right
/// end, with vertical marks (the crossovers) labelled at the top.
pub struct Lines {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// Each line: its name and its points, left to right (positive coordinates).
    pub lines: Vec<(String, Vec<(f64, f64)>)>,
    /// Vertical marks: where, and what to write there.
    pub marks: Vec<(f64, String)>,
    /// Logarithmic axes (else linear ones from zero).
    pub log: bool,
}

/// Colours of a [`Scatter`]'s families and of [`Lines`], told apart on a projector and by
/// most colour-blind readers.
const SERIES_COLOURS: [&str; 8] = [
    "#1f6fb4", "#d1542b", "#2a9d3c", "#8e44ad", "#b8860b", "#17a2b8", "#555555", "#e83e8c",
];

/// The colour of series `index` (repeating after eight).
fn series_colour(index: usize) -> &'static str {
    SERIES_COLOURS[index % SERIES_COLOURS.len()]
}

impl Lines {
    /// The plot as an SVG document.
    pub fn to_svg(&self) -> String {
        let points = self.lines.iter().flat_map(|(_, points)| points.iter());
        let positive: Vec<&(f64, f64)> = points
            .filter(|(x, y)| {
                x.is_finite() && y.is_finite() && (!self.log || (*x > 0.0 && *y > 0.0))
            })
            .collect();
        let range = |value: fn(&(f64, f64)) -> f64| {
            let (low, high) = positive
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |acc, p| {
                    (acc.0.min(value(p)), acc.1.max(value(p)))
                });
            if low > high { (1.0, 10.0) } else { (low, high) }
        };
        let log = self.log;
        let (x_low, x_high) = range(|p| p.0);
        let (y_low, y_high) = range(|p| p.1);
        let (x_low, y_low, y_high) = if log {
            (x_low, y_low / 1.5, y_high * 1.5)
        } else {
            (x_low.min(0.0), 0.0, y_high * 1.1)
        };
        // Room on the right for the lines' names.
        let right = 190.0;
        let plot_width = WIDTH - LEFT - right;
        let plot_height = HEIGHT - TOP - BOTTOM;
        let fraction = |value: f64, low: f64, high: f64| {
            if log {
                (value / low).ln() / (high / low).ln().max(1e-12)
            } else {
                (value - low) / (high - low).max(1e-12)
            }
        };
        let to_x = |x: f64| LEFT + fraction(x, x_low, x_high) * plot_width;
        let to_y = |y: f64| TOP + plot_height - fraction(y, y_low, y_high) * plot_height;
        // Decades only: a log-log plot over six decades has room for no more.
        let decades = |low: f64, high: f64| {
            if !log {
                return ticks(low, high);
            }
            log_ticks(low, high)
                .into_iter()
                .filter(|tick| (tick.log10() - tick.log10().round()).abs() < 1e-9)
                .collect::<Vec<_>>()
        };
        let frame = Frame {
            title: &self.title,
            x_label: &self.x_label,
            y_label: &self.y_label,
            plot_width,
            plot_height,
        };
        let mut svg = frame.draw(
            &decades(x_low, x_high)
                .iter()
                .map(|&x| (x, to_x(x)))
                .collect::<Vec<_>>(),
            &decades(y_low, y_high)
                .iter()
                .map(|&y| (y, to_y(y)))
                .collect::<Vec<_>>(),
        );
        for (x, label) in &self.marks {
            if !(x_low..=x_high).contains(x) {
                continue;
            }
            let px = to_x(*x);
            let _ = writeln!(
                svg,
                r##"<line x1="{px:.1}" y1="{TOP}" x2="{px:.1}" y2="{:.1}" stroke="#888" stroke-dasharray="6 5"/><text x="{:.1}" y="{:.1}" font-size="14" fill="#444" transform="rotate(-90 {:.1} {:.1})" text-anchor="end">{}</text>"##,
                TOP + plot_height,
                px - 6.0,
                TOP + 8.0,
                px - 6.0,
                TOP + 8.0,
                escape(label)
            );
        }
        // The lines, then their names at their right ends, kept apart.
        let mut ends: Vec<(f64, usize)> = Vec::new();
        for (index, (_, points)) in self.lines.iter().enumerate() {
            let colour = series_colour(index);
            let path: Vec<String> = points
                .iter()
                .filter(|(x, y)| !log || (*x > 0.0 && *y > 0.0))
                .map(|&(x, y)| format!("{:.1},{:.1}", to_x(x), to_y(y)))
                .collect();
            let _ = writeln!(
                svg,
                r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="3"/>"#,
                path.join(" ")
            );
            // Log-log lines (totals) part at their right ends; linear ones (profiles that
            // fall back to zero) are named in a column from the top.
            if !log {
                ends.push((TOP + 10.0 + 22.0 * index as f64, index));
            } else if let Some(&(_, y)) = points.last() {
                ends.push((to_y(y), index));
            }
        }
        ends.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut last = f64::NEG_INFINITY;
        for (y, index) in ends {
            let y = y.max(last + 18.0);
            last = y;
            let colour = series_colour(index);
            let _ = writeln!(
                svg,
                r#"<text x="{:.1}" y="{:.1}" font-size="15" fill="{colour}">{}</text>"#,
                LEFT + plot_width + 8.0,
                y + 5.0,
                escape(&self.lines[index].0)
            );
        }
        svg.push_str("</svg>\n");
        svg
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(ticks(0.0, 10.0), [0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(ticks(0.13, 0.52), [0.2, 0.3, 0.4, 0.5]);
        assert_eq!(tick_text(0.30000000000000004), "0.3");
        assert_eq!(tick_text(250000.0), "2e5");
        assert_eq!(log_ticks(3.0, 70.0), [5.0, 10.0, 20.0, 50.0]);
    }

    #[test]
    fn the_svg_has_every_point_and_label() {
        let plot = Scatter {
            title: "t <1>".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            families: vec!["BVH".into(), "kD".into()],
            points: vec![
                Point {
                    x: 1.0,
                    y: 2.0,
                    label: "a".into(),
                    family: 0,
                },
                Point {
                    x: 3.0,
                    y: f64::NAN,
                    label: "skipped".into(),
                    family: 1,
                },
                Point {
                    x: 2.0,
                    y: 1.0,
                    label: "b&c".into(),
                    family: 1,
                },
            ],
            diagonal: true,
            log_x: false,
        };
        let svg = plot.to_svg();
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>\n"));
        assert_eq!(
            svg.matches("<circle").count(),
            2 + 2,
            "two points and two legend dots"
        );
        assert!(svg.contains("t &lt;1&gt;") && svg.contains("b&amp;c"));
        assert!(!svg.contains("skipped") && !svg.contains("NaN"));
    }

    #[test]
    fn every_family_has_its_own_colour_and_legend_entry() {
        let names = ["BVH", "kD-tree", "uniform grid", "hashed grid", "octree"];
        let plot = Scatter {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            families: names.iter().map(|name| name.to_string()).collect(),
            points: (0..names.len())
                .map(|family| Point {
                    x: family as f64,
                    y: 1.0 + family as f64,
                    label: format!("p{family}"),
                    family,
                })
                .collect(),
            diagonal: false,
            log_x: false,
        };
        let svg = plot.to_svg();
        for (family, name) in names.iter().enumerate() {
            let colour = series_colour(family);
            assert!(svg.contains(&format!(">{name}</text>")), "{name}: {svg}");
            // Its point, its label and its legend dot in its colour, and no other family's.
            assert_eq!(svg.matches(colour).count(), 3, "{name} in {colour}: {svg}");
        }
    }

    #[test]
    fn lines_draw_every_line_its_name_and_the_marks_in_range() {
        let plot = Lines {
            title: "total".into(),
            x_label: "rays".into(),
            y_label: "ms".into(),
            lines: vec![
                ("quick".into(), vec![(1e3, 11.0), (1e9, 1e6)]),
                ("good".into(), vec![(1e3, 100.0), (1e9, 5e5)]),
            ],
            marks: vec![(1.8e5, "1.8e5: good".into()), (1e12, "outside".into())],
            log: true,
        };
        let svg = plot.to_svg();
        assert_eq!(svg.matches("<polyline").count(), 2);
        assert!(svg.contains(">quick</text>") && svg.contains(">good</text>"));
        assert!(svg.contains("1.8e5: good") && !svg.contains("outside"));
        assert!(svg.contains(">1e6</text>"), "decade ticks");
    }
}
