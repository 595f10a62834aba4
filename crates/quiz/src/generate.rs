//! What every kind generates with: the level, a seeded generator, scenes of shapes with
//! round coordinates (a question on paper must be solvable with a pencil), rays aimed into
//! them, and the JSON of shapes, rays and trees.

use accelviz_core::params::BuildParams;
use accelviz_core::{
    Aabb, Built, NoBuildObserver, Order, Query, Ray, Recorder, Shape, ShapeSet, Sphere, Step,
    Structure, TraceOptions, TraversalStacks, Tree,
};
use accelviz_scene::rng::SplitMix64;
use glam::DVec2;
use serde_json::{Value, json};

/// How hard a question is: how many shapes, how round the numbers, 2D or 3D.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Level {
    /// A few shapes, coordinates on a grid of halves.
    #[default]
    Easy,
    /// More shapes, coordinates to one decimal.
    Medium,
    /// Many shapes, and the slab test in 3D.
    Hard,
}

/// An unknown level name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown level '{0}'; the levels are: easy, medium, hard")]
pub struct LevelError(pub String);

impl Level {
    /// Every level, easiest first.
    pub const ALL: [Level; 3] = [Level::Easy, Level::Medium, Level::Hard];

    /// The level's name.
    pub fn name(self) -> &'static str {
        match self {
            Level::Easy => "easy",
            Level::Medium => "medium",
            Level::Hard => "hard",
        }
    }

    /// The level of a name.
    pub fn parse(name: &str) -> Result<Self, LevelError> {
        Self::ALL
            .into_iter()
            .find(|level| level.name() == name)
            .ok_or_else(|| LevelError(name.to_owned()))
    }

    /// How many shapes a scene has.
    pub(crate) fn shape_count(self) -> usize {
        match self {
            Level::Easy => 5,
            Level::Medium => 9,
            Level::Hard => 16,
        }
    }

    /// The grid coordinates are rounded to.
    pub(crate) fn grid(self) -> f64 {
        match self {
            Level::Easy => 0.5,
            Level::Medium | Level::Hard => 0.1,
        }
    }
}

/// The generator a kind draws from.
pub(crate) struct Gen {
    pub(crate) rng: SplitMix64,
    pub(crate) level: Level,
}

/// The side of the square scenes lie in.
pub(crate) const SCENE_SIZE: f64 = 20.0;

impl Gen {
    pub(crate) fn new(seed: u64, level: Level) -> Self {
        Self {
            rng: SplitMix64::new(seed),
            level,
        }
    }

    /// A number rounded to the level's grid.
    pub(crate) fn round(&self, value: f64) -> f64 {
        round_to(value, self.level.grid())
    }

    /// A point rounded to the level's grid (a sum of round numbers may not print round).
    pub(crate) fn tidy(&self, point: DVec2) -> DVec2 {
        DVec2::new(self.round(point.x), self.round(point.y))
    }

    /// Uniform in [low, high), rounded to the level's grid.
    pub(crate) fn coordinate(&mut self, low: f64, high: f64) -> f64 {
        let value = self.rng.range(low, high);
        self.round(value)
    }

    /// Uniform in [0, 1), not rounded (for coordinates whose every digit matters).
    pub(crate) fn uniform(&mut self) -> f64 {
        self.rng.next_f64()
    }

    /// A whole number in `low..=high`.
    pub(crate) fn integer(&mut self, low: i64, high: i64) -> i64 {
        let span = (high - low + 1) as u64;
        low + (self.rng.next_u64() % span) as i64
    }

    /// An index below `count`.
    pub(crate) fn index(&mut self, count: usize) -> usize {
        (self.rng.next_u64() % count.max(1) as u64) as usize
    }

    /// `items` in a random order (Fisher–Yates).
    pub(crate) fn shuffle<T>(&mut self, items: &mut [T]) {
        for last in (1..items.len()).rev() {
            let other = self.index(last + 1);
            items.swap(last, other);
        }
    }

    /// `count` shapes (discs, boxes and segments in turn) in the scene square whose boxes do
    /// not overlap, so that each can be told apart and clicked.
    pub(crate) fn shapes(&mut self, count: usize) -> ShapeSet<DVec2> {
        let mut shapes: Vec<Shape<DVec2>> = Vec::with_capacity(count);
        let mut attempts = 0;
        while shapes.len() < count && attempts < 2000 {
            attempts += 1;
            let center = DVec2::new(
                self.coordinate(2.0, SCENE_SIZE - 2.0),
                self.coordinate(2.0, SCENE_SIZE - 2.0),
            );
            let shape = match shapes.len() % 3 {
                0 => Shape::Sphere(Sphere {
                    center,
                    radius: self.coordinate(0.5, 1.6).max(0.5),
                }),
                1 => {
                    let half = DVec2::new(self.coordinate(0.5, 1.6), self.coordinate(0.5, 1.6))
                        .max(DVec2::splat(0.5));
                    Shape::Box(Aabb::new(
                        self.tidy(center - half),
                        self.tidy(center + half),
                    ))
                }
                _ => {
                    let half = DVec2::new(self.coordinate(-1.6, 1.6), self.coordinate(-1.6, 1.6));
                    if half.length() < 0.7 {
                        continue;
                    }
                    Shape::Segment([self.tidy(center - half), self.tidy(center + half)])
                }
            };
            let grown = |bounds: Aabb<DVec2>| {
                Aabb::new(
                    bounds.min - DVec2::splat(0.4),
                    bounds.max + DVec2::splat(0.4),
                )
            };
            let bounds = grown(shape.bounds());
            let inside = Aabb::new(DVec2::ZERO, DVec2::splat(SCENE_SIZE));
            if !inside.contains(&shape.bounds())
                || shapes
                    .iter()
                    .any(|other| bounds.intersection(&grown(other.bounds())).is_some())
            {
                continue;
            }
            shapes.push(shape);
        }
        ShapeSet { shapes }
    }

    /// A ray from the scene's border towards a point near one of the shapes, with round
    /// coordinates and no zero component in its direction.
    pub(crate) fn ray_into(&mut self, shapes: &ShapeSet<DVec2>) -> Ray<DVec2> {
        loop {
            let side = self.index(4);
            let along = self.coordinate(0.0, SCENE_SIZE);
            let origin = match side {
                0 => DVec2::new(-1.0, along),
                1 => DVec2::new(SCENE_SIZE + 1.0, along),
                2 => DVec2::new(along, -1.0),
                _ => DVec2::new(along, SCENE_SIZE + 1.0),
            };
            let target = shapes.shapes[self.index(shapes.shapes.len())]
                .bounds()
                .center();
            let jitter = DVec2::new(self.coordinate(-1.5, 1.5), self.coordinate(-1.5, 1.5));
            let direction = (target + jitter - origin).round();
            if direction.x == 0.0 || direction.y == 0.0 {
                continue;
            }
            if let Ok(ray) = Ray::try_new(origin, direction) {
                return ray;
            }
        }
    }
}

/// `value` rounded to a multiple of `grid`, and tidied (`0.30000000000000004` → `0.3`, no −0).
pub(crate) fn round_to(value: f64, grid: f64) -> f64 {
    let steps = (value / grid).round();
    let tidy = (steps * grid * 1000.0).round() / 1000.0;
    if tidy == 0.0 { 0.0 } else { tidy }
}

/// Builds `structure` over `shapes` (with at most `max_leaf_size` shapes per leaf).
pub(crate) fn build(
    structure: Structure,
    shapes: &ShapeSet<DVec2>,
    max_leaf_size: usize,
) -> Built<DVec2> {
    let params = BuildParams {
        max_leaf_size,
        ..BuildParams::default()
    };
    Built::new(structure, shapes, &params, &mut NoBuildObserver)
}

/// The traversal of `ray` through `built`, recorded step by step by the core's `Recorder`.
pub(crate) fn record(
    built: &Built<DVec2>,
    shapes: &ShapeSet<DVec2>,
    ray: &Ray<DVec2>,
    order: Order,
) -> Vec<Step<f64>> {
    record_query(built, shapes, ray, order, Query::Closest)
}

/// [`record`] for a `query` (the lecture's pseudo-code's rule, [`Query::FirstInCell`]).
pub(crate) fn record_query(
    built: &Built<DVec2>,
    shapes: &ShapeSet<DVec2>,
    ray: &Ray<DVec2>,
    order: Order,
    query: Query,
) -> Vec<Step<f64>> {
    let options = TraceOptions {
        order,
        query,
        ..TraceOptions::default()
    };
    let mut recorder = Recorder::default();
    let mut stacks = TraversalStacks::default();
    built
        .tree
        .trace(shapes, ray, &options, &mut stacks, &mut recorder);
    recorder.steps
}

/// The nodes entered, in order.
pub(crate) fn entered(steps: &[Step<f64>]) -> Vec<u32> {
    steps
        .iter()
        .filter_map(|step| match step {
            Step::NodeEntered { node } | Step::CellEntered { node, .. } => Some(*node),
            _ => None,
        })
        .collect()
}

/// True when no box the traversal tests is grazed (entered and left at nearly the same `t`, as
/// at a corner) and, once a closest hit is known, no box or cell it meets starts within a
/// hair of it: whether such a node is entered would turn on the last bit of a division, which
/// is no question for a student (nor the same in every independent check).
pub(crate) fn clear_steps(steps: &[Step<f64>]) -> bool {
    let mut t_closest = f64::INFINITY;
    for step in steps {
        let t_start = match *step {
            Step::ClosestHitUpdated { t, .. } => {
                t_closest = t;
                continue;
            }
            Step::BoxTested {
                t_enter, t_exit, ..
            } => {
                if (t_exit - t_enter).abs() < 0.01 {
                    return false;
                }
                t_enter
            }
            Step::NodeCulled { t_enter, .. } => t_enter,
            Step::CellEntered { t_near, t_far, .. } => {
                if (t_far - t_closest).abs() < 0.01 || t_far - t_near < 0.01 {
                    return false;
                }
                t_near
            }
            _ => continue,
        };
        if (t_start - t_closest).abs() < 0.01 {
            return false;
        }
    }
    true
}

/// True when no hit a cell's leaf finds lies within a hair of the cell's part of the ray: under
/// the pseudo-code's rule, which tests a leaf against the ray clipped to its cell, whether
/// such a hit counts there would turn on the last bit of a division.
pub(crate) fn clear_cell_hits(steps: &[Step<f64>]) -> bool {
    let mut cell = None;
    steps.iter().all(|step| match *step {
        Step::CellEntered { t_near, t_far, .. } => {
            cell = Some((t_near, t_far));
            true
        }
        Step::PrimitiveTested {
            t_hit: Some(t_hit), ..
        } => cell.is_none_or(|(t_near, t_far): (f64, f64)| {
            (t_hit - t_near).abs() >= 0.01 && (t_hit - t_far).abs() >= 0.01
        }),
        _ => true,
    })
}

/// How near a ray may pass a kD cell's corner (where a split line ends) and still be drawn: a
/// few pixels of the quiz figure at its default size (the scene's 23 units across about
/// 700 pixels). Nearer, which child the ray enters first turns on a sliver the figure cannot
/// show.
pub(crate) const CORNER_CLEARANCE: f64 = 0.1;

/// True when `ray` (from its origin on) passes within [`CORNER_CLEARANCE`] of a corner of any
/// cell of `built` (a kD-tree's cells; a BVH's boxes).
pub(crate) fn grazes_a_corner(built: &Built<DVec2>, ray: &Ray<DVec2>) -> bool {
    let direction = ray.direction.normalize();
    built.facts.bounds.iter().any(|cell| {
        [
            cell.min,
            cell.max,
            DVec2::new(cell.min.x, cell.max.y),
            DVec2::new(cell.max.x, cell.min.y),
        ]
        .into_iter()
        .any(|corner| {
            let along = (corner - ray.origin).dot(direction).max(0.0);
            (ray.origin + direction * along).distance(corner) < CORNER_CLEARANCE
        })
    })
}

/// The closest hit at the end of the steps: (shape, t).
pub(crate) fn final_hit(steps: &[Step<f64>]) -> Option<(u32, f64)> {
    steps.iter().rev().find_map(|step| match step {
        Step::ClosestHitUpdated { primitive, t } => Some((*primitive, *t)),
        _ => None,
    })
}

/// A shape as JSON: `{"disc": [cx, cy, r]}`, `{"box": [x0, y0, x1, y1]}` or
/// `{"segment": [ax, ay, bx, by]}`.
pub(crate) fn shape_json(shape: &Shape<DVec2>) -> Value {
    match shape {
        Shape::Sphere(disc) => json!({"disc": [disc.center.x, disc.center.y, disc.radius]}),
        Shape::Box(bounds) => json!({"box": box_json(bounds)}),
        Shape::Segment([a, b]) => json!({"segment": [a.x, a.y, b.x, b.y]}),
    }
}

/// A 2D box as `[x0, y0, x1, y1]`.
pub(crate) fn box_json(bounds: &Aabb<DVec2>) -> Value {
    json!([bounds.min.x, bounds.min.y, bounds.max.x, bounds.max.y])
}

/// Every shape as JSON.
pub(crate) fn shapes_json(shapes: &ShapeSet<DVec2>) -> Value {
    Value::Array(shapes.shapes.iter().map(shape_json).collect())
}

/// A ray as `{"origin": [...], "direction": [...]}`.
pub(crate) fn ray_json(origin: &[f64], direction: &[f64]) -> Value {
    json!({"origin": origin, "direction": direction})
}

/// A BVH's nodes (any tree's, each with its box or cell) as JSON: `{"box", "children": [a,
/// b]}` or `{"box", "shapes": [...]}`, node 0 the root.
pub(crate) fn bvh_json(built: &Built<DVec2>) -> Value {
    use accelviz_core::Hierarchy;
    let facts = &built.facts;
    Value::Array(
        (0..facts.node_count() as u32)
            .map(|node| {
                let bounds = box_json(&facts.bounds[node as usize]);
                match facts.children[node as usize] {
                    None => json!({"box": bounds, "shapes": built.tree.leaf_primitives(node)}),
                    Some(children) => {
                        json!({"box": bounds, "children": children.iter().collect::<Vec<_>>()})
                    }
                }
            })
            .collect(),
    )
}

/// A kD-tree's nodes as JSON: `{"cell", "axis", "split", "children": [below, above]}` or
/// `{"cell", "shapes": [...]}`, node 0 the root.
pub(crate) fn kd_json(built: &Built<DVec2>) -> Value {
    let Tree::Kd(tree) = &built.tree else {
        return Value::Array(Vec::new());
    };
    Value::Array(
        (0..tree.nodes.len() as u32)
            .map(|index| {
                let node = &tree.nodes[index as usize];
                let cell = box_json(&built.facts.bounds[index as usize]);
                if node.is_leaf() {
                    json!({"cell": cell, "shapes": tree.leaf_primitives(node)})
                } else {
                    json!({
                        "cell": cell,
                        "axis": node.axis,
                        "split": node.split,
                        "children": node.children(),
                    })
                }
            })
            .collect(),
    )
}

/// The JSON fields and the figure of a traversal question: the shapes, the ray, the
/// structure's name and its nodes (a BVH's boxes or a kD-tree's cells), and the scene with its
/// tree and recorded steps.
pub(crate) fn traversal_question(
    shapes: ShapeSet<DVec2>,
    ray: Ray<DVec2>,
    tree: crate::question::TreeFigure,
) -> (serde_json::Map<String, Value>, crate::question::SceneFigure) {
    let mut fields = serde_json::Map::new();
    fields.insert("shapes".into(), shapes_json(&shapes));
    fields.insert(
        "ray".into(),
        ray_json(&ray.origin.to_array(), &ray.direction.to_array()),
    );
    fields.insert("structure".into(), json!(tree.built.structure.name()));
    let nodes = match tree.built.tree {
        // A grid's nodes are its box and cells, an octree's its cells: boxes, as a BVH's.
        Tree::Bvh(_)
        | Tree::Bvh4(_)
        | Tree::Bvh8(_)
        | Tree::Grid(_)
        | Tree::HashedGrid(_)
        | Tree::Octree(_) => bvh_json(&tree.built),
        Tree::Kd(_) => kd_json(&tree.built),
    };
    fields.insert("nodes".into(), nodes);
    let mut scene = crate::question::SceneFigure::of(shapes);
    scene.ray = Some(ray);
    scene.tree = Some(tree);
    (fields, scene)
}

/// A shape's numbers as [`describe_shape`] writes them: a disc's centre and radius, a box's
/// corners, a segment's ends.
pub(crate) fn shape_numbers(shape: &Shape<DVec2>) -> Vec<f64> {
    match shape {
        Shape::Sphere(disc) => vec![disc.center.x, disc.center.y, disc.radius],
        Shape::Box(bounds) => vec![bounds.min.x, bounds.min.y, bounds.max.x, bounds.max.y],
        Shape::Segment([a, b]) => vec![a.x, a.y, b.x, b.y],
    }
}

/// A ray's origin and direction.
pub(crate) fn ray_numbers(ray: &Ray<DVec2>) -> Vec<f64> {
    vec![ray.origin.x, ray.origin.y, ray.direction.x, ray.direction.y]
}

/// A box's corners.
pub(crate) fn box_numbers(bounds: &Aabb<DVec2>) -> Vec<f64> {
    vec![bounds.min.x, bounds.min.y, bounds.max.x, bounds.max.y]
}

/// A shape in words, for print.
pub(crate) fn describe_shape(shape: &Shape<DVec2>) -> String {
    let number = num;
    match shape {
        Shape::Sphere(disc) => format!(
            "disc, centre ({}, {}), radius {}",
            number(disc.center.x),
            number(disc.center.y),
            number(disc.radius)
        ),
        Shape::Box(bounds) => format!("box {}", describe_box(bounds)),
        Shape::Segment([a, b]) => format!(
            "segment from ({}, {}) to ({}, {})",
            number(a.x),
            number(a.y),
            number(b.x),
            number(b.y)
        ),
    }
}

/// A box in words: `(x0, y0)–(x1, y1)`.
pub(crate) fn describe_box(bounds: &Aabb<DVec2>) -> String {
    let number = num;
    format!(
        "({}, {})–({}, {})",
        number(bounds.min.x),
        number(bounds.min.y),
        number(bounds.max.x),
        number(bounds.max.y)
    )
}

/// A tree node in words: its box, and its shapes or its children.
pub(crate) fn describe_node(built: &Built<DVec2>, node: u32) -> String {
    let facts = &built.facts;
    let bounds = describe_box(&facts.bounds[node as usize]);
    match facts.children[node as usize] {
        Some(children) => {
            let cuts: Vec<String> = built
                .cuts(node)
                .into_iter()
                .map(|(axis, at)| format!("{} = {}", AXES[axis], num(at)))
                .collect();
            let plane = match cuts.is_empty() {
                true => String::new(),
                false => format!(", cut at {}", cuts.join(" and ")),
            };
            let labels: Vec<String> = children
                .iter()
                .map(|child| crate::question::node_label(facts, child))
                .collect();
            let (init, last) = labels.split_at(labels.len().saturating_sub(1));
            format!(
                "{bounds}{plane}, children {} and {}",
                init.join(", "),
                last.join("")
            )
        }
        None => {
            let shapes = built.primitives_below(node);
            format!("{bounds}, leaf with shapes {shapes:?}")
        }
    }
}

/// The axes' names.
pub(crate) const AXES: [&str; 3] = ["x", "y", "z"];

/// A number for prompts and explanations: up to three decimals, no trailing zeros (a
/// question's coordinates are round, and `2.5` reads better than `2.500`).
pub fn num(value: f64) -> String {
    let magnitude = value.abs();
    if !value.is_finite() || magnitude >= 1e6 || (magnitude < 1e-3 && magnitude > 0.0) {
        return accelviz_core::format::number(value);
    }
    let text = format!("{value:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    match text {
        "-0" | "" => "0".to_owned(),
        _ => text.replace('-', "−"),
    }
}
