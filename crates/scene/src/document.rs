//! 2D scene documents: shapes (or a seeded generator), one ray and the structure settings, in
//! RON, a readable text format the app saves and opens and the lessons ship as.
//!
//! ```ron
//! (
//!     shapes: [
//!         Disc(center: (30.0, 40.0), radius: 5.0),
//!         Box(min: (50.0, 10.0), max: (60.0, 25.0)),
//!         Segment(from: (10.0, 80.0), to: (40.0, 90.0)),
//!     ],
//!     ray: (origin: (0.0, 0.0), toward: (1.0, 0.5)),
//!     settings: (max_leaf_size: 2, traversal_cost: 1.0, intersection_cost: 1.0),
//! )
//! ```
//!
//! `generator: Some((layout: Teapot, count: 300, seed: 7))` stands in for `shapes` when the
//! list is empty. Every field but `shapes`/`generator` and `ray` has a default.

use accelviz_core::{Aabb, SahCost, Shape, ShapeSet, Sphere};
use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::error::{LoadError, read_text};
use crate::scene2d::{Layout, generate};

/// The largest document read (bytes); a bigger file is refused before parsing.
pub const MAX_DOCUMENT_BYTES: usize = 64 << 20;
/// The most shapes a document may hold or generate.
pub const MAX_SHAPES: usize = 1_000_000;

/// One shape as written in a document.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum ShapeEntry {
    /// A disc.
    Disc {
        /// Its centre.
        center: (f64, f64),
        /// Its radius (positive).
        radius: f64,
    },
    /// A solid axis-aligned box.
    Box {
        /// The lower corner.
        min: (f64, f64),
        /// The upper corner (not below `min` on either axis).
        max: (f64, f64),
    },
    /// A line segment.
    Segment {
        /// One end.
        from: (f64, f64),
        /// The other end.
        to: (f64, f64),
    },
}

/// The ray: from `origin` towards `toward` (its direction is `toward − origin`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RayEntry {
    /// Where it starts.
    pub origin: (f64, f64),
    /// A point it passes at t = 1.
    pub toward: (f64, f64),
}

/// Layouts a generator can make (see [`crate::scene2d::Layout`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LayoutEntry {
    /// Uniformly over [0, 100]².
    Uniform,
    /// A few tight clusters.
    Clustered,
    /// A dense cluster in a large empty scene ("teapot in a stadium").
    Teapot,
}

impl From<LayoutEntry> for Layout {
    fn from(entry: LayoutEntry) -> Self {
        match entry {
            LayoutEntry::Uniform => Layout::Uniform,
            LayoutEntry::Clustered => Layout::Clustered,
            LayoutEntry::Teapot => Layout::TeapotInStadium,
        }
    }
}

/// A seeded generator: the same three values give the same shapes on every machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeneratorEntry {
    /// Where shapes go.
    pub layout: LayoutEntry,
    /// How many.
    pub count: usize,
    /// The seed.
    pub seed: u64,
}

/// How structures over the scene are built and costed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SceneSettings {
    /// A node with this many primitives or fewer becomes a leaf.
    pub max_leaf_size: usize,
    /// C_trav of the SAH.
    pub traversal_cost: f64,
    /// C_isect of the SAH.
    pub intersection_cost: f64,
    /// The kD empty-space bonus (0 to 1).
    pub empty_bonus: f64,
    /// Bins of the binned SAH.
    pub bins: usize,
}

impl Default for SceneSettings {
    /// The lecture's cost model: one traversal costs as much as one intersection.
    fn default() -> Self {
        Self {
            max_leaf_size: 2,
            traversal_cost: 1.0,
            intersection_cost: 1.0,
            empty_bonus: 0.2,
            bins: 8,
        }
    }
}

impl SceneSettings {
    /// The SAH cost object these settings describe.
    pub fn cost(&self) -> SahCost {
        SahCost {
            traversal_cost: self.traversal_cost,
            intersection_cost: self.intersection_cost,
            empty_bonus: self.empty_bonus,
        }
    }
}

/// A scene document as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDocument {
    /// The shapes, numbered from 0 in this order.
    #[serde(default)]
    pub shapes: Vec<ShapeEntry>,
    /// Makes the shapes when `shapes` is empty.
    #[serde(default)]
    pub generator: Option<GeneratorEntry>,
    /// The ray.
    pub ray: RayEntry,
    /// Structure settings.
    #[serde(default)]
    pub settings: SceneSettings,
}

/// A checked 2D scene: shapes, a ray and settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene2d {
    /// The shapes.
    pub shapes: ShapeSet<DVec2>,
    /// The ray's origin.
    pub ray_origin: DVec2,
    /// The point the ray passes at t = 1.
    pub ray_toward: DVec2,
    /// Structure settings.
    pub settings: SceneSettings,
    /// The generator that made the shapes, if one did (for the generator controls).
    pub generator: Option<GeneratorEntry>,
}

fn point((x, y): (f64, f64)) -> DVec2 {
    DVec2::new(x, y)
}

fn pair(point: DVec2) -> (f64, f64) {
    (point.x, point.y)
}

impl Scene2d {
    /// Parses and checks a RON document; errors name `path`, the line and the problem.
    pub fn parse(text: &str, path: &str) -> Result<Self, LoadError> {
        if text.len() > MAX_DOCUMENT_BYTES {
            return Err(LoadError::in_file(
                path,
                format!(
                    "the file is {} MB; scene files are limited to {} MB",
                    text.len() >> 20,
                    MAX_DOCUMENT_BYTES >> 20
                ),
            ));
        }
        let document: SceneDocument = ron::from_str(text).map_err(|error| {
            LoadError::at_line(
                path,
                error.span.start.line,
                format!("column {}: {}", error.span.start.col, error.code),
            )
        })?;
        Self::from_document(document, path)
    }

    /// Reads and parses a RON document from a file.
    pub fn load(path: &str) -> Result<Self, LoadError> {
        Self::parse(&read_text(path)?, path)
    }

    /// Checks a parsed document: finite numbers, positive radii, ordered boxes, a ray with a
    /// direction, and at most [`MAX_SHAPES`] shapes.
    pub fn from_document(document: SceneDocument, path: &str) -> Result<Self, LoadError> {
        let fail = |problem: String| LoadError::in_file(path, problem);
        let finite = |values: &[f64]| values.iter().all(|value| value.is_finite());
        let mut shapes = Vec::with_capacity(document.shapes.len());
        for (number, entry) in document.shapes.iter().enumerate() {
            let shape = match *entry {
                ShapeEntry::Disc { center, radius } => {
                    if !finite(&[center.0, center.1, radius]) || radius <= 0.0 {
                        return Err(fail(format!(
                            "shape {number}: a disc needs a finite centre and a positive radius, found radius {radius}"
                        )));
                    }
                    Shape::Sphere(Sphere {
                        center: point(center),
                        radius,
                    })
                }
                ShapeEntry::Box { min, max } => {
                    if !finite(&[min.0, min.1, max.0, max.1]) || min.0 > max.0 || min.1 > max.1 {
                        return Err(fail(format!(
                            "shape {number}: a box needs finite corners with min ≤ max, found min {min:?} max {max:?}"
                        )));
                    }
                    Shape::Box(Aabb::new(point(min), point(max)))
                }
                ShapeEntry::Segment { from, to } => {
                    if !finite(&[from.0, from.1, to.0, to.1]) {
                        return Err(fail(format!(
                            "shape {number}: a segment needs finite ends, found {from:?} to {to:?}"
                        )));
                    }
                    Shape::Segment([point(from), point(to)])
                }
            };
            shapes.push(shape);
        }
        if shapes.is_empty() {
            match document.generator {
                Some(generator) if (1..=MAX_SHAPES).contains(&generator.count) => {
                    shapes =
                        generate(generator.layout.into(), generator.count, generator.seed).shapes;
                }
                Some(generator) => {
                    return Err(fail(format!(
                        "the generator's count {} is not from 1 to {MAX_SHAPES}",
                        generator.count
                    )));
                }
                None => return Err(fail("the scene has no shapes and no generator".into())),
            }
        }
        if shapes.len() > MAX_SHAPES {
            return Err(fail(format!(
                "{} shapes; scenes are limited to {MAX_SHAPES}",
                shapes.len()
            )));
        }
        let RayEntry { origin, toward } = document.ray;
        if !finite(&[origin.0, origin.1, toward.0, toward.1]) || origin == toward {
            return Err(fail(format!(
                "the ray needs a finite origin and a different point to head toward, found origin {origin:?} toward {toward:?}"
            )));
        }
        let settings = document.settings;
        if settings.max_leaf_size == 0
            || !(1..=256).contains(&settings.bins)
            || !finite(&[
                settings.traversal_cost,
                settings.intersection_cost,
                settings.empty_bonus,
            ])
            || settings.traversal_cost < 0.0
            || settings.intersection_cost <= 0.0
            || !(0.0..1.0).contains(&settings.empty_bonus)
        {
            return Err(fail(format!(
                "settings out of range: {settings:?} (leaf size ≥ 1, bins 1 to 256, costs ≥ 0 with C_isect > 0, empty bonus in [0, 1))"
            )));
        }
        Ok(Self {
            shapes: ShapeSet { shapes },
            ray_origin: point(origin),
            ray_toward: point(toward),
            settings,
            generator: document.generator,
        })
    }

    /// The document that writes this scene back (every shape listed).
    pub fn to_document(&self) -> SceneDocument {
        SceneDocument {
            shapes: self
                .shapes
                .shapes
                .iter()
                .map(|shape| match *shape {
                    Shape::Sphere(sphere) => ShapeEntry::Disc {
                        center: pair(sphere.center),
                        radius: sphere.radius,
                    },
                    Shape::Box(bounds) => ShapeEntry::Box {
                        min: pair(bounds.min),
                        max: pair(bounds.max),
                    },
                    Shape::Segment([from, to]) => ShapeEntry::Segment {
                        from: pair(from),
                        to: pair(to),
                    },
                })
                .collect(),
            generator: self.generator,
            ray: RayEntry {
                origin: pair(self.ray_origin),
                toward: pair(self.ray_toward),
            },
            settings: self.settings,
        }
    }

    /// The scene as RON text, one shape per line.
    pub fn to_ron(&self) -> String {
        let config = ron::ser::PrettyConfig::new()
            .depth_limit(2)
            .struct_names(false);
        // Serialising plain numbers and enums cannot fail.
        ron::ser::to_string_pretty(&self.to_document(), config).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = "(
        shapes: [
            Disc(center: (30.0, 40.0), radius: 5.0),
            Box(min: (50, 10), max: (60, 25)),
            Segment(from: (10.0, 80.0), to: (40.0, 90.0)),
        ],
        ray: (origin: (0.0, 0.0), toward: (1.0, 0.5)),
        settings: (max_leaf_size: 3),
    )";

    #[test]
    fn a_document_parses_and_round_trips() {
        let scene = Scene2d::parse(EXAMPLE, "example.ron").unwrap();
        assert_eq!(scene.shapes.shapes.len(), 3);
        assert_eq!(scene.settings.max_leaf_size, 3);
        assert_eq!(
            scene.settings.traversal_cost, 1.0,
            "unset settings keep their defaults"
        );
        assert_eq!(
            scene.shapes.shapes[1],
            Shape::Box(Aabb::new(DVec2::new(50.0, 10.0), DVec2::new(60.0, 25.0)))
        );
        let again = Scene2d::parse(&scene.to_ron(), "saved.ron").unwrap();
        assert_eq!(again, scene);
    }

    #[test]
    fn a_generator_stands_in_for_shapes() {
        let text = "(generator: Some((layout: Teapot, count: 50, seed: 3)), ray: (origin: (0, 0), toward: (1, 1)))";
        let scene = Scene2d::parse(text, "gen.ron").unwrap();
        assert_eq!(scene.shapes, generate(Layout::TeapotInStadium, 50, 3));
    }

    #[test]
    fn errors_name_the_file_line_and_problem() {
        let message = |text: &str| Scene2d::parse(text, "bad.ron").unwrap_err().to_string();
        let syntax = message(
            "(\n shapes: [\n Disk(center: (1, 2), radius: 1),\n ],\n ray: (origin: (0,0), toward: (1,1)))",
        );
        assert!(syntax.starts_with("bad.ron:3: "), "{syntax}");
        assert!(syntax.contains("Disk"), "{syntax}");
        let radius = message(
            "(shapes: [Disc(center: (1, 2), radius: -1)], ray: (origin: (0,0), toward: (1,1)))",
        );
        assert!(
            radius.contains("shape 0") && radius.contains("positive radius"),
            "{radius}"
        );
        let zero_direction = message(
            "(shapes: [Disc(center: (1, 2), radius: 1)], ray: (origin: (2,2), toward: (2,2)))",
        );
        assert!(zero_direction.contains("the ray needs"), "{zero_direction}");
        let flipped = message(
            "(shapes: [Box(min: (5, 5), max: (1, 9))], ray: (origin: (0,0), toward: (1,1)))",
        );
        assert!(flipped.contains("min ≤ max"), "{flipped}");
        let empty = message("(ray: (origin: (0,0), toward: (1,1)))");
        assert!(empty.contains("no shapes"), "{empty}");
        let huge = message(
            "(generator: Some((layout: Uniform, count: 100000000, seed: 1)), ray: (origin: (0,0), toward: (1,1)))",
        );
        assert!(huge.contains("count 100000000"), "{huge}");
        let settings = message(
            "(shapes: [Disc(center: (1, 2), radius: 1)], ray: (origin: (0,0), toward: (1,1)), settings: (bins: 0))",
        );
        assert!(settings.contains("settings out of range"), "{settings}");
    }
}
