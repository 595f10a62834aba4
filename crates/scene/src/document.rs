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

/// One shape as written in a document. Checked as it is read, so that a wrong number is
/// reported at its line, naming the field: every coordinate finite, radii positive, a box's
/// corners in order.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawShape")]
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

/// A shape as parsed, before its numbers are checked.
#[derive(Deserialize)]
enum RawShape {
    Disc { center: (f64, f64), radius: f64 },
    Box { min: (f64, f64), max: (f64, f64) },
    Segment { from: (f64, f64), to: (f64, f64) },
}

/// `value` if it is finite; otherwise why not, naming `field`.
fn finite(field: &str, value: f64) -> Result<f64, String> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("{field} is {value}: every number must be finite"))
    }
}

/// A point whose coordinates are finite, or which one is not.
fn finite_point(field: &str, (x, y): (f64, f64)) -> Result<(f64, f64), String> {
    Ok((
        finite(&format!("{field} x"), x)?,
        finite(&format!("{field} y"), y)?,
    ))
}

impl TryFrom<RawShape> for ShapeEntry {
    type Error = String;

    fn try_from(raw: RawShape) -> Result<Self, String> {
        Ok(match raw {
            RawShape::Disc { center, radius } => {
                let center = finite_point("a disc's centre", center)?;
                let radius = finite("a disc's radius", radius)?;
                if radius <= 0.0 {
                    return Err(format!(
                        "a disc's radius is {radius}: it must be a positive number"
                    ));
                }
                ShapeEntry::Disc { center, radius }
            }
            RawShape::Box { min, max } => {
                let min = finite_point("a box's min", min)?;
                let max = finite_point("a box's max", max)?;
                for (axis, low, high) in [("x", min.0, max.0), ("y", min.1, max.1)] {
                    if low > high {
                        return Err(format!(
                            "a box's min {axis} ({low}) is above its max {axis} ({high}): min ≤ max is needed"
                        ));
                    }
                }
                ShapeEntry::Box { min, max }
            }
            RawShape::Segment { from, to } => ShapeEntry::Segment {
                from: finite_point("a segment's from", from)?,
                to: finite_point("a segment's to", to)?,
            },
        })
    }
}

/// The ray: from `origin` towards `toward` (its direction is `toward − origin`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, try_from = "RawRay")]
pub struct RayEntry {
    /// Where it starts.
    pub origin: (f64, f64),
    /// A point it passes at t = 1.
    pub toward: (f64, f64),
}

/// The ray as parsed, before its numbers are checked.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRay {
    origin: (f64, f64),
    toward: (f64, f64),
}

impl TryFrom<RawRay> for RayEntry {
    type Error = String;

    fn try_from(raw: RawRay) -> Result<Self, String> {
        let origin = finite_point("the ray's origin", raw.origin)?;
        let toward = finite_point("the ray's toward point", raw.toward)?;
        if origin == toward {
            return Err(format!(
                "the ray's toward point equals its origin {origin:?}: the ray has no direction"
            ));
        }
        Ok(Self { origin, toward })
    }
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
#[serde(deny_unknown_fields, try_from = "RawGenerator")]
pub struct GeneratorEntry {
    /// Where shapes go.
    pub layout: LayoutEntry,
    /// How many (1 to [`MAX_SHAPES`]).
    pub count: usize,
    /// The seed.
    pub seed: u64,
}

/// The generator as parsed, before its count is checked.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGenerator {
    layout: LayoutEntry,
    count: usize,
    seed: u64,
}

impl TryFrom<RawGenerator> for GeneratorEntry {
    type Error = String;

    fn try_from(raw: RawGenerator) -> Result<Self, String> {
        if !(1..=MAX_SHAPES).contains(&raw.count) {
            return Err(format!(
                "the generator's count {} is not from 1 to {MAX_SHAPES}",
                raw.count
            ));
        }
        Ok(Self {
            layout: raw.layout,
            count: raw.count,
            seed: raw.seed,
        })
    }
}

/// How structures over the scene are built and costed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawSettings")]
pub struct SceneSettings {
    /// A node with this many primitives or fewer becomes a leaf (1 to 64).
    pub max_leaf_size: usize,
    /// C_trav of the SAH (0 or more).
    pub traversal_cost: f64,
    /// C_isect of the SAH (above 0).
    pub intersection_cost: f64,
    /// The kD empty-space bonus (0 to below 1).
    pub empty_bonus: f64,
    /// Bins of the binned SAH (2 to 256).
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

/// The settings as parsed, before they are checked; unset ones take their defaults.
#[derive(Deserialize)]
#[serde(default, deny_unknown_fields)]
struct RawSettings {
    max_leaf_size: usize,
    traversal_cost: f64,
    intersection_cost: f64,
    empty_bonus: f64,
    bins: usize,
}

impl Default for RawSettings {
    fn default() -> Self {
        let settings = SceneSettings::default();
        Self {
            max_leaf_size: settings.max_leaf_size,
            traversal_cost: settings.traversal_cost,
            intersection_cost: settings.intersection_cost,
            empty_bonus: settings.empty_bonus,
            bins: settings.bins,
        }
    }
}

impl TryFrom<RawSettings> for SceneSettings {
    type Error = String;

    fn try_from(raw: RawSettings) -> Result<Self, String> {
        let out_of_range = |field: &str, value: String, range: &str| {
            format!("{field} is {value}: it must be {range}")
        };
        if !(1..=64).contains(&raw.max_leaf_size) {
            return Err(out_of_range(
                "max_leaf_size",
                raw.max_leaf_size.to_string(),
                "from 1 to 64",
            ));
        }
        if !(2..=256).contains(&raw.bins) {
            return Err(out_of_range("bins", raw.bins.to_string(), "from 2 to 256"));
        }
        let traversal_cost = finite("traversal_cost", raw.traversal_cost)?;
        if traversal_cost < 0.0 {
            return Err(out_of_range(
                "traversal_cost",
                traversal_cost.to_string(),
                "0 or more",
            ));
        }
        let intersection_cost = finite("intersection_cost", raw.intersection_cost)?;
        if intersection_cost <= 0.0 {
            return Err(out_of_range(
                "intersection_cost",
                intersection_cost.to_string(),
                "above 0",
            ));
        }
        let empty_bonus = finite("empty_bonus", raw.empty_bonus)?;
        if !(0.0..1.0).contains(&empty_bonus) {
            return Err(out_of_range(
                "empty_bonus",
                empty_bonus.to_string(),
                "from 0 to below 1",
            ));
        }
        Ok(Self {
            max_leaf_size: raw.max_leaf_size,
            traversal_cost,
            intersection_cost,
            empty_bonus,
            bins: raw.bins,
        })
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
    /// The generator the scene names (for the generator controls): it made the shapes when
    /// the document listed none, or when they are listed as it makes them (a generated scene
    /// saved); beside other shapes it is only the controls' preset ([`Scene2d::is_generated`]).
    pub generator: Option<GeneratorEntry>,
}

impl Scene2d {
    /// Whether the shapes are exactly what the scene's generator makes: only then was the
    /// scene generated (a lesson may list its own shapes and name a generator as the
    /// controls' preset).
    pub fn is_generated(&self) -> bool {
        self.generator.is_some_and(|generator| {
            generator.count == self.shapes.shapes.len()
                && generate(generator.layout.into(), generator.count, generator.seed) == self.shapes
        })
    }
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
            // RON names the Rust types it expected; a reader knows the file's own words.
            let problem = match &error.code {
                ron::Error::ExpectedDifferentStructName {
                    expected: "SceneDocument",
                    found,
                } => format!(
                    "this is not an accelviz scene: a scene file starts with `SceneDocument(` or `(`, not `{found}`"
                ),
                ron::Error::ExpectedNamedStructLike("SceneDocument") => {
                    "this is not an accelviz scene: a scene file starts with `SceneDocument(` or `(`".to_owned()
                }
                code => code.to_string(),
            };
            LoadError::at_line(
                path,
                error.span.start.line,
                format!("column {}: {problem}", error.span.start.col),
            )
        })?;
        Self::from_document(document, path)
    }

    /// Reads and parses a RON document from a file.
    pub fn load(path: &str) -> Result<Self, LoadError> {
        Self::parse(&read_text(path)?, path)
    }

    /// Makes the scene of a parsed document (whose shapes, ray and settings were checked as
    /// they were read): its shapes, or the generator's, at most [`MAX_SHAPES`].
    pub fn from_document(document: SceneDocument, path: &str) -> Result<Self, LoadError> {
        let fail = |problem: String| LoadError::in_file(path, problem);
        if document.shapes.len() > MAX_SHAPES {
            return Err(fail(format!(
                "{} shapes; scenes are limited to {MAX_SHAPES}",
                document.shapes.len()
            )));
        }
        let mut shapes: Vec<Shape<DVec2>> = document
            .shapes
            .iter()
            .map(|entry| match *entry {
                ShapeEntry::Disc { center, radius } => Shape::Sphere(Sphere {
                    center: point(center),
                    radius,
                }),
                ShapeEntry::Box { min, max } => Shape::Box(Aabb::new(point(min), point(max))),
                ShapeEntry::Segment { from, to } => Shape::Segment([point(from), point(to)]),
            })
            .collect();
        if shapes.is_empty() {
            let Some(generator) = document.generator else {
                return Err(fail("the scene has no shapes and no generator".into()));
            };
            shapes = generate(generator.layout.into(), generator.count, generator.seed).shapes;
        }
        let RayEntry { origin, toward } = document.ray;
        Ok(Self {
            shapes: ShapeSet { shapes },
            ray_origin: point(origin),
            ray_toward: point(toward),
            settings: document.settings,
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
    fn a_file_that_is_not_a_scene_is_named_so_without_rust_type_names() {
        for text in ["v 0 0 0\nv 1 0 0\nf 1 2 3\n", "Mesh(shapes: [])"] {
            let message = Scene2d::parse(text, "planar.obj").unwrap_err().to_string();
            assert!(
                message.starts_with("planar.obj:1: column 1: this is not an accelviz scene"),
                "{message}"
            );
            assert!(!message.contains("struct"), "{message}");
        }
    }

    #[test]
    fn a_generator_stands_in_for_shapes() {
        let text = "(generator: Some((layout: Teapot, count: 50, seed: 3)), ray: (origin: (0, 0), toward: (1, 1)))";
        let scene = Scene2d::parse(text, "gen.ron").unwrap();
        assert_eq!(scene.shapes, generate(Layout::TeapotInStadium, 50, 3));
        assert!(scene.is_generated());
        // Saved and read again, every shape listed: still the generator's.
        let saved = ron::to_string(&scene.to_document()).unwrap();
        assert!(Scene2d::parse(&saved, "saved.ron").unwrap().is_generated());
        // Listed shapes beside a generator that does not make them: a preset, not generated.
        let listed = "(shapes: [Disc(center: (1, 2), radius: 1)], generator: Some((layout: Teapot, count: 50, seed: 3)), ray: (origin: (0, 0), toward: (1, 1)))";
        let scene = Scene2d::parse(listed, "listed.ron").unwrap();
        assert_eq!(scene.shapes.shapes.len(), 1);
        assert!(!scene.is_generated());
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
            radius.starts_with("bad.ron:1: ") && radius.contains("a disc's radius is -1"),
            "{radius}"
        );
        let zero_direction = message(
            "(shapes: [Disc(center: (1, 2), radius: 1)], ray: (origin: (2,2), toward: (2,2)))",
        );
        assert!(zero_direction.contains("no direction"), "{zero_direction}");
        let flipped = message(
            "(shapes: [Box(min: (5, 5), max: (1, 9))], ray: (origin: (0,0), toward: (1,1)))",
        );
        assert!(
            flipped.contains("min x (5) is above its max x (1)"),
            "{flipped}"
        );
        let empty = message("(ray: (origin: (0,0), toward: (1,1)))");
        assert!(empty.contains("no shapes"), "{empty}");
        let huge = message(
            "(generator: Some((layout: Uniform, count: 100000000, seed: 1)), ray: (origin: (0,0), toward: (1,1)))",
        );
        assert!(huge.contains("count 100000000"), "{huge}");
        let settings = message(
            "(shapes: [Disc(center: (1, 2), radius: 1)], ray: (origin: (0,0), toward: (1,1)), settings: (bins: 0))",
        );
        assert!(
            settings.contains("bins is 0: it must be from 2 to 256"),
            "{settings}"
        );
    }

    /// A number that is not finite is named with its field and line, whatever spells it.
    #[test]
    fn a_number_that_is_not_finite_is_named_at_its_line() {
        for (spelled, shown) in [
            ("NaN", "NaN"),
            ("inf", "inf"),
            ("-inf", "-inf"),
            ("1e999", "inf"),
        ] {
            let text = format!(
                "(\n shapes: [\n  Disc(center: (1, 2), radius: 1),\n  Disc(center: ({spelled}, 2), radius: 5),\n ],\n ray: (origin: (0, 0), toward: (1, 1)),\n)"
            );
            let message = Scene2d::parse(&text, "scene.ron").unwrap_err().to_string();
            assert!(message.starts_with("scene.ron:4: "), "{spelled}: {message}");
            assert!(
                message.contains(&format!(
                    "a disc's centre x is {shown}: every number must be finite"
                )),
                "{spelled}: {message}"
            );
        }
        let far = "(shapes: [Segment(from: (0, 0), to: (1e300, -1e300))], ray: (origin: (0, 0), toward: (1, 1)))";
        assert!(
            Scene2d::parse(far, "far.ron").is_ok(),
            "huge but finite is allowed"
        );
    }
}
