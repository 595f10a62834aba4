//! The question kinds: each listed once in [`KINDS`], with the generator in its own file.

mod build_yourself;
mod first_hit;
mod grid_walk;
mod kd_traversal;
mod leaf_or_split;
mod leak;
mod lecture;
mod near_vs_file;
mod octree_order;
mod sah_split;
mod slab;
mod visit_order;

use accelviz_core::{Built, Order, Query, Ray, ShapeSet, Step};
use glam::DVec2;
use serde_json::{Map, Value, json};

use crate::generate::{Gen, Level, entered, final_hit, traversal_question};
use crate::question::{Ask, Figure, Question, TreeFigure};

/// One kind of question.
pub struct KindEntry {
    /// Its name, as the CLI's `--kind` and the JSON's `kind` spell it.
    pub name: &'static str,
    /// A short title for the app's list.
    pub title: &'static str,
    /// What it asks, in a sentence.
    pub about: &'static str,
    /// Makes one question from the generator, or `None` when the draw is unfit (a near tie, a
    /// ray that teaches nothing); the caller draws again from where the generator stands.
    generate: fn(&mut Gen) -> Option<Draft>,
}

/// Every kind of question, in the order a mixed quiz cycles through them.
pub const KINDS: &[KindEntry] = &[
    KindEntry {
        name: "slab",
        title: "The slab test",
        about: "Does the ray hit the box? Which axis gives t_enter, and what is it?",
        generate: slab::generate,
    },
    KindEntry {
        name: "first-hit",
        title: "The first hit",
        about: "Which shape does the ray hit first, and where?",
        generate: first_hit::generate,
    },
    KindEntry {
        name: "visit-order",
        title: "BVH traversal, step by step",
        about: "Which node does the traversal enter next?",
        generate: visit_order::generate,
    },
    KindEntry {
        name: "near-vs-file",
        title: "Near first against file order",
        about: "How many nodes does each order enter, and what does near first skip?",
        generate: near_vs_file::generate,
    },
    KindEntry {
        name: "kd-traversal",
        title: "kD-tree traversal",
        about: "Which child is near, and is the far child visited?",
        generate: kd_traversal::generate,
    },
    KindEntry {
        name: "sah-split",
        title: "Choosing a split",
        about: "Which split does SAH choose, which do middle and median choose, what does one cost?",
        generate: sah_split::generate,
    },
    KindEntry {
        name: "leaf-or-split",
        title: "Leaf or split?",
        about: "Does the SAH builder keep this node a leaf?",
        generate: leaf_or_split::generate,
    },
    KindEntry {
        name: "lecture",
        title: "The lecture's quiz",
        about: "Why visit the near side first? What happens in file order?",
        generate: lecture::generate,
    },
    KindEntry {
        name: "leak",
        title: "Does the ray slip through?",
        about: "A ray through the edge two triangles share: does this test, in this precision, hit either?",
        generate: leak::generate,
    },
    KindEntry {
        name: "octree-order",
        title: "Quadtree traversal, front to back",
        about: "Which child does the ray visit first, and which next?",
        generate: octree_order::generate,
    },
    KindEntry {
        name: "grid-walk",
        title: "Walking a grid",
        about: "Which cells does the ray pass through, in order? Which line does it reach first?",
        generate: grid_walk::generate,
    },
    KindEntry {
        name: "build",
        title: "Build the tree yourself",
        about: "Pick each node's split or keep a leaf; scored on SAH cost against the builder.",
        generate: build_yourself::generate,
    },
];

/// What a kind's generator makes; [`generate`] adds the kind, seed and level.
pub(crate) struct Draft {
    pub(crate) prompt: String,
    pub(crate) figure: Figure,
    pub(crate) asks: Vec<Ask>,
    pub(crate) fields: Map<String, Value>,
    pub(crate) answer: Value,
}

impl Draft {
    /// A question on a near-first traversal of `built` over `shapes` by `ray` under `query`:
    /// the figure shows the recorded `steps`; the answer holds the nodes entered, the shape
    /// hit, and the steps' own answers under `key`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn near_first_traversal(
        prompt: &str,
        (shapes, ray): (ShapeSet<DVec2>, Ray<DVec2>),
        built: Built<DVec2>,
        query: Query,
        steps: Vec<Step<f64>>,
        asks: Vec<Ask>,
        (key, per_step): (&str, Value),
    ) -> Self {
        let visited = entered(&steps);
        let hit = final_hit(&steps);
        let (fields, scene) = traversal_question(
            shapes,
            ray,
            TreeFigure {
                built,
                order: Order::NearFirst,
                query,
                steps,
                reveal_as_reached: false,
            },
        );
        let mut answer = Map::new();
        answer.insert("visited".into(), json!(visited));
        answer.insert("shape".into(), json!(hit.map(|(shape, _)| shape)));
        answer.insert(key.into(), per_step);
        Self {
            prompt: prompt.into(),
            figure: Figure::Scene(Box::new(scene)),
            asks,
            fields,
            answer: Value::Object(answer),
        }
    }
}

/// A kind that does not exist, or a seed no question could be made from.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum KindError {
    /// The name is not in [`KINDS`].
    #[error("unknown question kind '{0}'; the kinds are: {names}", names = kind_names().join(", "))]
    Unknown(String),
    /// Every draw was unfit (it should not happen: the tests draw hundreds of seeds).
    #[error("no {kind} question could be made from seed {seed}")]
    NoQuestion {
        /// The kind.
        kind: &'static str,
        /// The seed.
        seed: u64,
    },
}

/// The names of every kind.
pub fn kind_names() -> Vec<&'static str> {
    KINDS.iter().map(|entry| entry.name).collect()
}

/// The kind of a name.
pub fn entry(name: &str) -> Result<&'static KindEntry, KindError> {
    KINDS
        .iter()
        .find(|entry| entry.name == name)
        .ok_or_else(|| KindError::Unknown(name.to_owned()))
}

/// The question of kind `kind` made from `seed` at `level`: the same on every machine.
pub fn generate(kind: &str, seed: u64, level: Level) -> Result<Question, KindError> {
    let entry = entry(kind)?;
    let mut generator = Gen::new(seed, level);
    for _ in 0..1000 {
        if let Some(draft) = (entry.generate)(&mut generator) {
            return Ok(Question {
                kind: entry.name,
                seed,
                level,
                prompt: draft.prompt,
                figure: draft.figure,
                asks: draft.asks,
                fields: draft.fields,
                answer: draft.answer,
            });
        }
    }
    Err(KindError::NoQuestion {
        kind: entry.name,
        seed,
    })
}

/// The yes/no options, in that order.
pub(crate) fn yes_no() -> Vec<crate::Choice> {
    vec![crate::Choice::text("yes"), crate::Choice::text("no")]
}

/// The tolerance a typed number is graded with: two decimals' worth, or 1 % of large values.
pub(crate) fn tolerance(value: f64) -> f64 {
    (0.01 * value.abs()).max(0.02)
}
