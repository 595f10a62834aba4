//! What a generated question holds: its figure, its steps with their answers and
//! explanations, and its JSON for the CLI.

use accelviz_core::{Aabb, Built, Order, Query, Ray, ShapeSet, Step};
use glam::DVec2;
use serde_json::{Map, Value};

use crate::generate::Level;

/// One generated question.
#[derive(Clone, Debug)]
pub struct Question {
    /// The kind's name (`slab`, `visit-order`, …).
    pub kind: &'static str,
    /// The seed it was generated from: the same seed and level give the same question.
    pub seed: u64,
    /// How hard.
    pub level: Level,
    /// What the question is about, in a sentence or two.
    pub prompt: String,
    /// What the canvas shows.
    pub figure: Figure,
    /// The steps, asked and graded in order.
    pub asks: Vec<Ask>,
    /// The kind's fixed JSON fields (the box, the ray, the shapes, the nodes, …).
    pub fields: Map<String, Value>,
    /// The kind's answer, as JSON.
    pub answer: Value,
}

impl Question {
    /// One line of JSON: `kind`, `seed`, `level`, `prompt`, the kind's fields and `answer`.
    pub fn to_json(&self) -> String {
        let mut object = Map::new();
        object.insert("kind".into(), Value::from(self.kind));
        object.insert("seed".into(), Value::from(self.seed));
        object.insert("level".into(), Value::from(self.level.name()));
        object.insert("prompt".into(), Value::from(self.prompt.clone()));
        for (key, value) in &self.fields {
            object.insert(key.clone(), value.clone());
        }
        object.insert("answer".into(), self.answer.clone());
        Value::Object(object).to_string()
    }

    /// The figure's numbers as they stand while step `step` is asked (before its answer): see
    /// [`Figure::numbers`].
    pub fn numbers(&self, step: usize) -> Vec<String> {
        self.figure
            .numbers(Some(self.asks.get(step).map_or(0, |ask| ask.frame)))
    }

    /// The figure's numbers while step `step` is asked, in two parts: those the step names
    /// (the shapes and nodes its prompt or options name, and the ray, the box, the node being
    /// split: every line that is not one shape's or one node's), then the rest. A lecture
    /// shows the first part where it stays on screen; a node list of a dozen lines used to
    /// push the node the step asks about below it.
    pub fn numbers_named_by(&self, step: usize) -> (Vec<String>, Vec<String>) {
        let Some(ask) = self.asks.get(step) else {
            return (self.numbers(step), Vec::new());
        };
        let mut text = ask.prompt.clone();
        for option in ask.expected.options() {
            text.push('\n');
            text.push_str(&option.label);
        }
        self.numbers(step)
            .into_iter()
            .partition(|line| line_is_named(line, &text))
    }

    /// The question for print: the prompt, the figure's numbers, each step with its answer
    /// and explanation.
    pub fn to_text(&self) -> String {
        let mut text = format!(
            "[{} · seed {} · {}]\n{}\n",
            self.kind,
            self.seed,
            self.level.name(),
            self.prompt
        );
        text.push_str(&self.figure.describe());
        for (number, ask) in self.asks.iter().enumerate() {
            text.push_str(&format!("\n{}. {}\n", number + 1, ask.prompt));
            {
                for (index, option) in ask.expected.options().iter().enumerate() {
                    text.push_str(&format!("   ({}) {}\n", option_letter(index), option.label));
                }
            }
            text.push_str(&format!("   Answer: {}\n", ask.expected.model_answer()));
            text.push_str(&format!("   Why: {}\n", ask.explanation));
        }
        text
    }
}

/// Whether a line of the numbers is one `text` needs: a line about one shape (`shape 3: …`)
/// or one node (`node RL: …`) when `text` names it, every other line (the ray, a box, the
/// node being split) always.
fn line_is_named(line: &str, text: &str) -> bool {
    let subject = line.split(": ").next().unwrap_or_default();
    let (noun, name) = match subject.split_once(' ') {
        Some((noun @ ("shape" | "node"), name)) if !name.contains(' ') => (noun, name),
        _ => return true,
    };
    // A name of digits alone is named only with its noun (`shape 2`, `node 2`, `child 2`,
    // `cell 2`): a bare `2` is as likely a coordinate. A path of L and R, or `root`, is named
    // wherever it stands as a word.
    let nouns: &[&str] = match (noun, name.bytes().all(|b| b.is_ascii_digit())) {
        ("shape", _) => &["shape ", "shapes "],
        (_, true) => &["node ", "child ", "cell "],
        (_, false) => &[""],
    };
    nouns.iter().any(|noun| {
        let wanted = format!("{noun}{name}");
        text.match_indices(&wanted).any(|(at, _)| {
            let before = text[..at].chars().next_back();
            let after = text[at + wanted.len()..].chars().next();
            let apart = |c: Option<char>| c.is_none_or(|c| !c.is_alphanumeric());
            apart(before) && apart(after)
        })
    })
}

/// The letter of a choice: `a`, `b`, … (the keys that pick it in the app).
pub fn option_letter(index: usize) -> char {
    char::from(b'a' + (index % 26) as u8)
}

/// What the canvas draws for a question.
#[derive(Clone, Debug)]
pub enum Figure {
    /// A box and a ray (the slab test), in 2D or 3D.
    Slab {
        /// The box's smallest corner (2 or 3 coordinates).
        min: Vec<f64>,
        /// The box's largest corner.
        max: Vec<f64>,
        /// The ray's origin.
        origin: Vec<f64>,
        /// The ray's direction (no zero component).
        direction: Vec<f64>,
    },
    /// A 2D scene of shapes, maybe with a ray, a tree and a node's candidate splits.
    Scene(Box<SceneFigure>),
    /// A tree for the student to build, as it starts.
    Build(Box<crate::build::BuildExercise>),
    /// Two triangles sharing an edge and a ray aimed at it, seen along the ray.
    Crack(Box<CrackFigure>),
    /// A uniform grid and a ray walking through its cells, in 2D or 3D.
    Grid(Box<GridFigure>),
}

/// A uniform grid and a ray, with the cells the ray passes (the grid-walk question). A
/// highlight's `nodes` are cell numbers (`x + n_x·(y + n_y·z)`), and a step's frame is how
/// many of the walked cells are shown.
#[derive(Clone, Debug)]
pub struct GridFigure {
    /// The grid's smallest corner (2 or 3 coordinates).
    pub min: Vec<f64>,
    /// Its largest corner.
    pub max: Vec<f64>,
    /// Cells along each axis.
    pub cells: Vec<u32>,
    /// The ray's origin.
    pub origin: Vec<f64>,
    /// The ray's direction.
    pub direction: Vec<f64>,
    /// The cells the ray passes, in order (padded to three coordinates).
    pub walked: Vec<[u32; 3]>,
    /// The ray's part of each, `[t_near, t_far]`.
    pub parts: Vec<(f64, f64)>,
}

impl GridFigure {
    /// One cell's size along each axis.
    pub fn cell_size(&self) -> Vec<f64> {
        (0..self.min.len())
            .map(|axis| (self.max[axis] - self.min[axis]) / f64::from(self.cells[axis]))
            .collect()
    }

    /// The number of the cell at `coordinates`.
    pub fn cell_number(&self, coordinates: [u32; 3]) -> u32 {
        let ny = self.cells.get(1).copied().unwrap_or(1);
        coordinates[0] + self.cells[0] * (coordinates[1] + ny * coordinates[2])
    }

    /// The coordinates of cell number `cell`.
    pub fn coordinates(&self, cell: u32) -> [u32; 3] {
        let (nx, ny) = (self.cells[0], self.cells.get(1).copied().unwrap_or(1));
        [cell % nx, (cell / nx) % ny, cell / (nx * ny)]
    }

    /// A cell's smallest and largest corners (2 or 3 coordinates).
    pub fn cell_box(&self, coordinates: [u32; 3]) -> (Vec<f64>, Vec<f64>) {
        let size = self.cell_size();
        let low: Vec<f64> = (0..self.min.len())
            .map(|axis| self.min[axis] + f64::from(coordinates[axis]) * size[axis])
            .collect();
        let high = low
            .iter()
            .zip(&size)
            .map(|(low, size)| low + size)
            .collect();
        (low, high)
    }

    /// The cells as a student writes them: `(1, 2)` or `(1, 2, 0)`.
    pub fn describe_cell(&self, coordinates: [u32; 3]) -> String {
        let values: Vec<String> = coordinates[..self.min.len()]
            .iter()
            .map(|value| value.to_string())
            .collect();
        format!("({})", values.join(", "))
    }
}

/// Two triangles, A and B, that share an edge, and a ray aimed at a point of it, with what a
/// ray/triangle test in one precision computed for each (the leak question).
#[derive(Clone, Debug)]
pub struct CrackFigure {
    /// A and B seen along the ray: their corners in a plane across it, the point aimed at
    /// in the middle of the figure's world and the triangles scaled to fill it.
    pub seen: [[DVec2; 3]; 2],
    /// Where the ray is in the figure (the point aimed at).
    pub ray_at: DVec2,
    /// A's and B's corners as the test stores them (in its precision).
    pub corners: [[[f64; 3]; 3]; 2],
    /// The ray's origin and direction as the test sees them.
    pub origin: [f64; 3],
    /// The ray's direction.
    pub direction: [f64; 3],
    /// `f32` or `f64`.
    pub precision: &'static str,
    /// The test.
    pub test: accelviz_core::HitTest,
    /// What the test computed for A and for B: `u`, `v` and `w = 1 − u − v` (fast), or the
    /// edge functions `U`, `V`, `W` (watertight). `None` where the test stopped before it.
    pub computed: [[Option<f64>; 3]; 2],
}

impl CrackFigure {
    /// The names of what it computed: `u`, `v`, `w` or `U`, `V`, `W`.
    pub fn value_names(&self) -> [&'static str; 3] {
        match self.test {
            accelviz_core::HitTest::Fast => ["u", "v", "w = 1 − u − v"],
            accelviz_core::HitTest::Watertight => ["U", "V", "W"],
        }
    }
}

/// A 2D scene for a question.
#[derive(Clone, Debug)]
pub struct SceneFigure {
    /// The shapes, numbered from 0.
    pub shapes: ShapeSet<DVec2>,
    /// The ray (from t = 0, no end), if the question has one.
    pub ray: Option<Ray<DVec2>>,
    /// The tree and its recorded traversal, if the question has one.
    pub tree: Option<TreeFigure>,
    /// The node the question is about: its box and shapes (the others are drawn faint).
    pub node: Option<(Aabb<DVec2>, Vec<u32>)>,
    /// Candidate splits (axis, position), labelled `a`, `b`, … in the canvas as in the choices.
    pub candidates: Vec<(usize, f64)>,
    /// Each candidate's two children's boxes (left, right): what its cost is made of.
    pub candidate_boxes: Vec<[Aabb<DVec2>; 2]>,
    /// Whether the candidates are drawn before the step is answered (not when where the best
    /// split lies is part of the answer).
    pub candidates_before_answer: bool,
}

impl SceneFigure {
    /// A scene of shapes with nothing else yet.
    pub fn of(shapes: ShapeSet<DVec2>) -> Self {
        Self {
            shapes,
            ray: None,
            tree: None,
            node: None,
            candidates: Vec::new(),
            candidate_boxes: Vec::new(),
            candidates_before_answer: true,
        }
    }

    /// The side (0 left, 1 right) shape `member` goes to at a split at `position` on `axis`:
    /// left when its box's centre is below the position.
    fn side_of(&self, member: u32, axis: usize, position: f64) -> usize {
        usize::from(self.shapes.shapes[member as usize].bounds().center()[axis] >= position)
    }

    /// How many of the node's shapes go to each side of candidate `index`.
    pub fn candidate_counts(&self, index: usize) -> [usize; 2] {
        let mut counts = [0, 0];
        if let (Some((axis, position)), Some((_, members))) =
            (self.candidates.get(index), &self.node)
        {
            for member in members {
                counts[self.side_of(*member, *axis, *position)] += 1;
            }
        }
        counts
    }

    /// Sets the candidate splits of the node's shapes, with each one's children's boxes (a
    /// shape goes left when its box's centre is below the position).
    pub fn with_candidates(mut self, candidates: Vec<(usize, f64)>) -> Self {
        let members = self
            .node
            .as_ref()
            .map(|(_, members)| members.clone())
            .unwrap_or_default();
        self.candidate_boxes = candidates
            .iter()
            .map(|(axis, position)| {
                let mut sides = [Aabb::empty(), Aabb::empty()];
                for member in &members {
                    let side = self.side_of(*member, *axis, *position);
                    sides[side] = sides[side].union(self.shapes.shapes[*member as usize].bounds());
                }
                sides
            })
            .collect();
        self.candidates = candidates;
        self
    }
}

/// A tree in a question, with the traversal the question steps through.
#[derive(Clone, Debug)]
pub struct TreeFigure {
    /// The tree and its facts, built by the core's catalogue.
    pub built: Built<DVec2>,
    /// The order the recorded traversal used.
    pub order: Order,
    /// What it searched for: the closest hit, or by the lecture's pseudo-code's rule.
    pub query: Query,
    /// The traversal's steps, as the core's `Recorder` recorded them.
    pub steps: Vec<Step<f64>>,
    /// Whether nodes are shown only once the traversal has reached them (their parent was
    /// entered), as in OpenDSA's search exercises.
    pub reveal_as_reached: bool,
}

impl TreeFigure {
    /// The nodes a student has seen after the first `frame` recorded steps: every node, or
    /// with [`reveal_as_reached`](Self::reveal_as_reached) the root and the children of every
    /// node entered so far.
    pub fn visible(&self, frame: usize) -> Vec<u32> {
        let facts = &self.built.facts;
        if !self.reveal_as_reached {
            return (0..facts.node_count() as u32).collect();
        }
        let mut seen = vec![0];
        for step in &self.steps[..frame.min(self.steps.len())] {
            if let Step::NodeEntered { node } | Step::CellEntered { node, .. } = step
                && let Some(children) = facts.children[*node as usize]
            {
                seen.extend(children);
            }
        }
        seen
    }
}

impl Figure {
    /// The figure's numbers as a student sees them after the first `frame` recorded steps
    /// (`None`: all of them), one line each: the box and the ray; the shapes, the ray and the
    /// nodes seen so far; the node asked about and its candidate splits with their boxes,
    /// perimeters and counts. What the student works an answer out from.
    pub fn numbers(&self, frame: Option<usize>) -> Vec<String> {
        use crate::generate::{AXES, describe_box, describe_node, describe_shape, num};
        let list = |values: &[f64]| {
            values
                .iter()
                .map(|v| num(*v))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut lines = Vec::new();
        match self {
            Figure::Slab {
                min,
                max,
                origin,
                direction,
            } => {
                lines.push(format!("box from ({}) to ({})", list(min), list(max)));
                lines.push(format!(
                    "ray from ({}) in direction ({})",
                    list(origin),
                    list(direction)
                ));
            }
            Figure::Crack(crack) => {
                let point = |corner: &[f64; 3]| {
                    let written: Vec<String> = corner
                        .iter()
                        // Every digit the precision holds: the test's inputs exactly.
                        .map(|value| {
                            if crack.precision == "f32" {
                                format!("{}", *value as f32)
                            } else {
                                format!("{value}")
                            }
                        })
                        .collect();
                    format!("({})", written.join(", "))
                };
                for (name, corners) in ["A", "B"].iter().zip(&crack.corners) {
                    let written: Vec<String> = corners.iter().map(point).collect();
                    lines.push(format!("triangle {name}: {}", written.join(" ")));
                }
                lines.push(format!(
                    "ray from {} in direction {}",
                    point(&crack.origin),
                    point(&crack.direction)
                ));
                lines.push(match crack.test {
                    accelviz_core::HitTest::Fast => format!(
                        "the fast test (Möller–Trumbore) in {}: a hit needs u, v and w all ≥ 0",
                        crack.precision
                    ),
                    accelviz_core::HitTest::Watertight => format!(
                        "the watertight test (Woop et al.) in {}: a hit needs U, V, W not of opposite signs (a zero goes with either)",
                        crack.precision
                    ),
                });
                let names = crack.value_names();
                for (name, values) in ["A", "B"].iter().zip(&crack.computed) {
                    let written: Vec<String> = names
                        .iter()
                        .zip(values)
                        .map(|(label, value)| match value {
                            Some(value) => format!("{label} = {}", num(*value)),
                            None => format!("{label}: not computed (the test had its answer)"),
                        })
                        .collect();
                    lines.push(format!("{name}: {}", written.join(", ")));
                }
            }
            Figure::Scene(scene) => {
                for (index, shape) in scene.shapes.shapes.iter().enumerate() {
                    lines.push(format!("shape {index}: {}", describe_shape(shape)));
                }
                if let Some(ray) = &scene.ray {
                    lines.push(format!(
                        "ray from ({}) in direction ({})",
                        list(&ray.origin.to_array()),
                        list(&ray.direction.to_array())
                    ));
                }
                if let Some(tree) = &scene.tree {
                    let facts = &tree.built.facts;
                    for node in tree.visible(frame.unwrap_or(usize::MAX)) {
                        lines.push(format!(
                            "node {}: {}",
                            node_label(facts, node),
                            describe_node(&tree.built, node)
                        ));
                    }
                }
                if let Some((bounds, members)) = &scene.node {
                    lines.push(format!(
                        "the node: {}, box {}, perimeter {}",
                        accelviz_core::format::counted(members.len(), "shape", "shapes"),
                        describe_box(bounds),
                        num(bounds.area())
                    ));
                }
                if scene.candidates_before_answer {
                    for (index, ((axis, position), sides)) in scene
                        .candidates
                        .iter()
                        .zip(&scene.candidate_boxes)
                        .enumerate()
                    {
                        let counts = scene.candidate_counts(index);
                        let side = |bounds: &Aabb<DVec2>, count: usize| {
                            format!(
                                "{}, box {}, perimeter {}",
                                accelviz_core::format::counted(count, "shape", "shapes"),
                                describe_box(bounds),
                                num(bounds.area())
                            )
                        };
                        lines.push(format!(
                            "({}) {} = {}: left {}; right {}",
                            option_letter(index),
                            AXES[*axis],
                            num(*position),
                            side(&sides[0], counts[0]),
                            side(&sides[1], counts[1])
                        ));
                    }
                }
            }
            Figure::Build(exercise) => {
                for (index, shape) in exercise.shapes().shapes.iter().enumerate() {
                    lines.push(format!("shape {index}: {}", describe_shape(shape)));
                }
            }
            Figure::Grid(grid) => {
                let counts: Vec<String> = grid.cells.iter().map(|n| n.to_string()).collect();
                let sizes: Vec<String> = grid.cell_size().iter().map(|s| num(*s)).collect();
                lines.push(format!(
                    "grid from ({}) to ({}): {} cells of {}, numbered from 0 at the smallest corner",
                    list(&grid.min),
                    list(&grid.max),
                    counts.join(" × "),
                    sizes.join(" × ")
                ));
                lines.push(format!(
                    "ray from ({}) in direction ({})",
                    list(&grid.origin),
                    list(&grid.direction)
                ));
                let shown = frame.unwrap_or(grid.walked.len()).min(grid.walked.len());
                if shown > 0 {
                    let passed: Vec<String> = grid.walked[..shown]
                        .iter()
                        .map(|cell| grid.describe_cell(*cell))
                        .collect();
                    lines.push(format!("cells passed so far: {}", passed.join(", ")));
                }
            }
        }
        lines
    }

    fn describe(&self) -> String {
        let mut text: String = self
            .numbers(None)
            .iter()
            .map(|line| format!("  {line}\n"))
            .collect();
        if let Figure::Build(exercise) = self {
            // The model answer for print: the builder's pick at every node.
            let mut model = (**exercise).clone();
            while let Some(choice) = model.next_choice() {
                model.pick(choice.builder);
            }
            text.push_str(&format!(
                "  The SAH builder's tree (SAH cost {}):\n",
                crate::generate::num(model.score().builder_cost)
            ));
            for (choice, index) in model.decided() {
                let node = if choice.path.is_empty() {
                    "root"
                } else {
                    &choice.path
                };
                let pick = match choice.picks[*index] {
                    crate::build::Pick::Leaf => format!("leaf {:?}", choice.shapes),
                    crate::build::Pick::Split { axis, position } => format!(
                        "split at {} = {}",
                        crate::generate::AXES[axis],
                        crate::generate::num(position)
                    ),
                };
                text.push_str(&format!("    {node}: {pick}\n"));
            }
        }
        text
    }
}

/// A node's name as students see it: `root`, or its path from the root (`L`, `LR`, …).
pub fn node_label(facts: &accelviz_core::TreeFacts<DVec2>, node: u32) -> String {
    let path = facts.path_to(node);
    if path.is_empty() { "root".into() } else { path }
}

/// One graded step of a question.
#[derive(Clone, Debug)]
pub struct Ask {
    /// The question asked at this step.
    pub prompt: String,
    /// The right answer.
    pub expected: Expected,
    /// Why it is right, shown once the step is answered.
    pub explanation: String,
    /// What the canvas marks with the explanation.
    pub highlight: Highlight,
    /// How many of the traversal's recorded steps the canvas shows while asking (0 without a
    /// traversal): the animation pauses just before the step asked about.
    pub frame: usize,
    /// The numbers the answer is worked out from (coordinates, costs): each is shown before
    /// the step is asked, in the prompt or in [`Question::numbers`] (tested for every kind).
    pub needs: Vec<f64>,
}

/// What an answer must be.
#[derive(Clone, Debug, PartialEq)]
pub enum Expected {
    /// One of several options.
    Choice {
        /// The options, in the order shown.
        options: Vec<Choice>,
        /// The right one.
        correct: usize,
    },
    /// One of several options, each with a cost: any option as cheap as the cheapest is
    /// right (the build exercise's picks, graded by their SAH cost).
    Costed {
        /// The options, in the order shown.
        options: Vec<Choice>,
        /// Each option's cost.
        costs: Vec<f64>,
    },
    /// A number, right within a tolerance.
    Number {
        /// The value.
        value: f64,
        /// How far from it an answer may be.
        tolerance: f64,
    },
}

impl Expected {
    /// Whether `response` is right.
    pub fn accepts(&self, response: &Response) -> bool {
        match (self, response) {
            (Expected::Choice { correct, .. }, Response::Choice(chosen)) => chosen == correct,
            (Expected::Costed { costs, .. }, Response::Choice(chosen)) => {
                let cheapest = costs.iter().copied().fold(f64::INFINITY, f64::min);
                costs
                    .get(*chosen)
                    .is_some_and(|cost| *cost <= cheapest + 1e-9 * (1.0 + cheapest.abs()))
            }
            (Expected::Number { value, tolerance }, Response::Number(given)) => {
                given.is_finite() && (given - value).abs() <= *tolerance
            }
            _ => false,
        }
    }

    /// The right answer, as text.
    pub fn model_answer(&self) -> String {
        match self {
            Expected::Choice { options, correct } => {
                format!("({}) {}", option_letter(*correct), options[*correct].label)
            }
            Expected::Costed { options, .. } => {
                let best = self.correct_option().unwrap_or(0);
                format!("({}) {}", option_letter(best), options[best].label)
            }
            Expected::Number { value, .. } => crate::generate::num(*value),
        }
    }

    /// The options of a choice (none for a number).
    pub fn options(&self) -> &[Choice] {
        match self {
            Expected::Choice { options, .. } | Expected::Costed { options, .. } => options,
            Expected::Number { .. } => &[],
        }
    }

    /// The right option of a choice (the first cheapest of a costed one).
    pub fn correct_option(&self) -> Option<usize> {
        match self {
            Expected::Choice { correct, .. } => Some(*correct),
            Expected::Costed { costs, .. } => {
                (0..costs.len()).min_by(|a, b| costs[*a].total_cmp(&costs[*b]))
            }
            Expected::Number { .. } => None,
        }
    }

    /// A response as text, for the review of mistakes.
    pub fn describe(&self, response: &Response) -> String {
        match (self, response) {
            (
                Expected::Choice { options, .. } | Expected::Costed { options, .. },
                Response::Choice(chosen),
            ) => options
                .get(*chosen)
                .map_or_else(|| "?".into(), |option| option.label.clone()),
            (_, Response::Number(value)) => crate::generate::num(*value),
            (_, Response::Choice(chosen)) => format!("option {chosen}"),
        }
    }
}

/// One option of a choice.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// What the option says.
    pub label: String,
    /// The tree node it names, so a click on that node in the canvas picks it.
    pub node: Option<u32>,
    /// The shape it names, so a click on that shape picks it.
    pub shape: Option<u32>,
}

impl Choice {
    /// An option that names nothing in the canvas.
    pub fn text(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            node: None,
            shape: None,
        }
    }
}

/// A student's answer to one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Response {
    /// The option chosen.
    Choice(usize),
    /// The number given.
    Number(f64),
}

/// What the canvas marks when a step's answer is revealed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Highlight {
    /// Tree nodes to mark.
    pub nodes: Vec<u32>,
    /// Shapes to mark.
    pub shapes: Vec<u32>,
    /// The slab test's axis to mark.
    pub axis: Option<usize>,
    /// A point on the ray, by its `t`.
    pub t: Option<f64>,
    /// What that point is, as the figure labels it (`plane, t = 1.125`; empty: `t = …`).
    pub t_label: String,
    /// A candidate split to mark (its index in [`SceneFigure::candidates`]).
    pub candidate: Option<usize>,
    /// How many traversal steps to show with the explanation (the step just asked about
    /// included).
    pub frame: Option<usize>,
    /// Points on the ray to mark, by their `t` (the slab test's crossings found so far).
    pub marks: Vec<f64>,
    /// Whether the slab test's intervals are drawn on number lines (once every one is known).
    pub intervals: bool,
}

#[cfg(test)]
mod tests {
    use super::line_is_named;

    #[test]
    fn a_line_is_named_by_its_shape_or_node_as_a_word() {
        let text = "The ray is in cell R for t in [0.625, 1.05]; which child is near?\nnode RL (y < 7.5)\nnode RR";
        for (line, named) in [
            ("node R: (12.25, 1.5)–(19, 13.5), cut at y = 7.5", true),
            ("node RL: (12.25, 1.5)–(19, 7.5)", true),
            ("node RLL: (12.25, 1.5)–(15.625, 7.5), leaf", false),
            ("node L: (5.5, 1.5)–(12.25, 13.5)", false),
            ("shape 1: box (12.5, 7.5)–(14.5, 8.5)", false),
            ("ray from (8.5, 21) in direction (10, −12)", true),
            ("the node: 5 shapes, box (3, 1.5)–(18.5, 13.5)", true),
        ] {
            assert_eq!(line_is_named(line, text), named, "{line}");
        }
        let text = "After child 2, which child of root does the ray pass into next?\nnode 3 (x > 13)\nshape 12";
        for (line, named) in [
            ("node 2: (7.5, 8.5)–(13, 15.5)", true),
            ("node 3: (13, 8.5)–(18.5, 15.5)", true),
            ("node 1: (13, 1.5)–(18.5, 8.5)", false),
            ("node root: (7.5, 1.5)–(18.5, 15.5)", true),
            ("shape 1: box", false),
            ("shape 12: disc", true),
        ] {
            assert_eq!(line_is_named(line, text), named, "{line}");
        }
    }
}
