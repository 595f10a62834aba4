//! Seeded 2D scenes of segments, discs and boxes.

use accelviz_core::{Aabb, Shape, ShapeSet, Sphere};
use glam::DVec2;

use crate::error::{LoadError, read_text};
use crate::rng::SplitMix64;

/// How the shapes of a generated scene are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// Uniformly over the square `[0, 100]²`.
    Uniform,
    /// In a few tight clusters.
    Clustered,
    /// "Teapot in a stadium": a dense cluster in a corner of a large, nearly empty scene,
    /// where middle splits waste levels and SAH cuts the empty space off.
    TeapotInStadium,
}

/// `count` shapes (segments, discs and boxes in turn) placed by `layout`.
pub fn generate(layout: Layout, count: usize, seed: u64) -> ShapeSet<DVec2> {
    let mut rng = SplitMix64::new(seed);
    let clusters: Vec<DVec2> = (0..4)
        .map(|_| DVec2::new(rng.range(10.0, 90.0), rng.range(10.0, 90.0)))
        .collect();
    let mut shapes = Vec::with_capacity(count);
    for index in 0..count {
        let (center, size) = match layout {
            Layout::Uniform => (
                DVec2::new(rng.range(0.0, 100.0), rng.range(0.0, 100.0)),
                2.0,
            ),
            Layout::Clustered => {
                let cluster = clusters[index % clusters.len()];
                (
                    cluster + DVec2::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)),
                    0.8,
                )
            }
            Layout::TeapotInStadium => {
                if index < 4 {
                    // The stadium's walls, far apart.
                    let corner = [
                        DVec2::ZERO,
                        DVec2::new(100.0, 0.0),
                        DVec2::new(100.0, 100.0),
                        DVec2::new(0.0, 100.0),
                    ];
                    shapes.push(Shape::Segment([corner[index], corner[(index + 1) % 4]]));
                    continue;
                }
                (
                    DVec2::new(rng.range(80.0, 86.0), rng.range(10.0, 16.0)),
                    0.3,
                )
            }
        };
        let radius = rng.range(0.2, 1.0) * size;
        shapes.push(match index % 3 {
            0 => {
                let angle = rng.range(0.0, std::f64::consts::TAU);
                let half = DVec2::new(angle.cos(), angle.sin()) * radius;
                Shape::Segment([center - half, center + half])
            }
            1 => Shape::Sphere(Sphere { center, radius }),
            _ => {
                let half = DVec2::new(rng.range(0.3, 1.0), rng.range(0.3, 1.0)) * radius;
                Shape::Box(Aabb::new(center - half, center + half))
            }
        });
    }
    ShapeSet { shapes }
}

/// The built-in 2D scene layouts by name, for `builtin:NAME[:COUNT[:SEED]]`.
pub const LAYOUT_NAMES: [&str; 3] = ["uniform", "clustered", "teapot"];

/// Loads a 2D scene: `builtin:LAYOUT[:COUNT[:SEED]]` (a [`generate`]d scene; 200 shapes and
/// seed 1 unless given) or a scene file read by [`parse_scene2d`].
pub fn load_scene2d(spec: &str) -> Result<ShapeSet<DVec2>, LoadError> {
    let Some(builtin) = spec.strip_prefix("builtin:") else {
        let text = read_text(spec)?;
        return parse_scene2d(&text, spec);
    };
    let fail = |problem: String| LoadError::in_file(spec, problem);
    let mut parts = builtin.split(':');
    let layout = match parts.next().unwrap_or_default() {
        "uniform" => Layout::Uniform,
        "clustered" => Layout::Clustered,
        "teapot" => Layout::TeapotInStadium,
        other => {
            return Err(fail(format!(
                "unknown built-in 2D scene '{other}'; built-in scenes are: {}",
                LAYOUT_NAMES.join(", ")
            )));
        }
    };
    let count = match parts.next() {
        None => 200,
        Some(word) => word
            .parse::<usize>()
            .ok()
            .filter(|count| (1..=10_000_000).contains(count))
            .ok_or_else(|| fail(format!("'{word}' is not a shape count from 1 to 10000000")))?,
    };
    let seed = match parts.next() {
        None => 1,
        Some(word) => word
            .parse::<u64>()
            .map_err(|_| fail(format!("'{word}' is not a seed (a whole number)")))?,
    };
    if let Some(extra) = parts.next() {
        return Err(fail(format!(
            "unexpected ':{extra}'; use builtin:LAYOUT[:COUNT[:SEED]]"
        )));
    }
    Ok(generate(layout, count, seed))
}

/// Parses a 2D scene file: one shape per line, `#` starts a comment.
///
/// ```text
/// disc    CX CY RADIUS
/// box     MINX MINY MAXX MAXY
/// segment AX AY BX BY
/// ```
///
/// Errors name the line: an unknown shape, a wrong number of values, a value that is not a
/// finite number, a radius that is not positive, a box whose min exceeds its max.
pub fn parse_scene2d(text: &str, path: &str) -> Result<ShapeSet<DVec2>, LoadError> {
    let mut shapes = Vec::new();
    for (line_index, line) in text.lines().enumerate() {
        let line_number = line_index + 1;
        let content = line.split('#').next().unwrap_or_default().trim();
        if content.is_empty() {
            continue;
        }
        let fail = |problem: String| LoadError::at_line(path, line_number, problem);
        let mut words = content.split_whitespace();
        let kind = words.next().unwrap_or_default();
        let values: Vec<f64> = words
            .map(|word| {
                word.parse::<f64>()
                    .ok()
                    .filter(|value| value.is_finite())
                    .ok_or_else(|| fail(format!("'{word}' is not a finite number")))
            })
            .collect::<Result<_, _>>()?;
        let expected = match kind {
            "disc" => 3,
            "box" | "segment" => 4,
            other => {
                return Err(fail(format!(
                    "unknown shape '{other}'; use disc, box or segment"
                )));
            }
        };
        if values.len() != expected {
            return Err(fail(format!(
                "a {kind} takes {expected} numbers, found {}",
                values.len()
            )));
        }
        let point = |index: usize| DVec2::new(values[index], values[index + 1]);
        shapes.push(match kind {
            "disc" => {
                if values[2] <= 0.0 {
                    return Err(fail(format!("the radius {} is not positive", values[2])));
                }
                Shape::Sphere(Sphere {
                    center: point(0),
                    radius: values[2],
                })
            }
            "box" => {
                let (min, max) = (point(0), point(2));
                if min.x > max.x || min.y > max.y {
                    return Err(fail(format!(
                        "the box's min ({}, {}) exceeds its max ({}, {})",
                        min.x, min.y, max.x, max.y
                    )));
                }
                Shape::Box(Aabb::new(min, max))
            }
            _ => Shape::Segment([point(0), point(2)]),
        });
    }
    if shapes.is_empty() {
        return Err(LoadError::in_file(path, "the scene holds no shapes"));
    }
    Ok(ShapeSet { shapes })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_files_parse_and_errors_name_the_line() {
        let scene = parse_scene2d(
            "# two shapes\ndisc 1 2 0.5\n\nbox 0 0 1 1  # a unit box\nsegment 0 0 3 4\n",
            "s.txt",
        )
        .unwrap();
        assert_eq!(scene.shapes.len(), 3);
        assert_eq!(
            scene.shapes[0],
            Shape::Sphere(Sphere {
                center: DVec2::new(1.0, 2.0),
                radius: 0.5
            })
        );
        let error = |text: &str| parse_scene2d(text, "s.txt").unwrap_err().to_string();
        assert_eq!(
            error("disc 1 2 0.5\ntriangle 0 0 1"),
            "s.txt:2: unknown shape 'triangle'; use disc, box or segment"
        );
        assert_eq!(
            error("box 0 0 1"),
            "s.txt:1: a box takes 4 numbers, found 3"
        );
        assert_eq!(
            error("disc 0 nan 1"),
            "s.txt:1: 'nan' is not a finite number"
        );
        assert_eq!(
            error("disc 0 0 -1"),
            "s.txt:1: the radius -1 is not positive"
        );
        assert_eq!(
            error("box 2 0 1 1"),
            "s.txt:1: the box's min (2, 0) exceeds its max (1, 1)"
        );
        assert_eq!(error("# nothing\n"), "s.txt: the scene holds no shapes");
    }

    #[test]
    fn builtin_specs() {
        assert_eq!(load_scene2d("builtin:uniform").unwrap().shapes.len(), 200);
        assert_eq!(
            load_scene2d("builtin:teapot:50:7").unwrap(),
            generate(Layout::TeapotInStadium, 50, 7)
        );
        for bad in [
            "builtin:square",
            "builtin:uniform:0",
            "builtin:uniform:5:x",
            "builtin:uniform:5:1:2",
        ] {
            assert!(load_scene2d(bad).is_err(), "{bad}");
        }
    }
}
