//! Build the tree yourself: the student picks each node's split (or a leaf); the score is the
//! SAH builder's tree cost over the student's. The exercise is [`BuildExercise`]; this draws
//! its scene and writes the builder's own tree as the model answer.

use accelviz_core::SahCost;
use serde_json::{Map, Value, json};

use super::Draft;
use crate::build::{BuildExercise, Pick};
use crate::generate::{Gen, Level, shapes_json};
use crate::question::Figure;

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let count = match generator.level {
        Level::Easy => 4,
        Level::Medium => 6,
        Level::Hard => 8,
    };
    let shapes = generator.shapes(count);
    let cost = SahCost {
        traversal_cost: 1.0,
        intersection_cost: 1.0,
        ..SahCost::default()
    };
    let exercise = BuildExercise::new(shapes.clone(), cost);
    let first = exercise.next_ask()?;
    // The model answer: the builder's pick at every node, which makes the builder's tree.
    let mut model = exercise.clone();
    while let Some(choice) = model.next_choice() {
        model.pick(choice.builder);
    }
    let score = model.score();
    // No node of the model may hinge on a near tie (a split as dear as the leaf, two splits
    // as cheap): the builder's tree would then be one of several, and a student who picks the
    // other would be told a different story.
    let clear = model.decided().iter().all(|(choice, _)| {
        let mut costs = choice.costs.clone();
        costs.sort_by(f64::total_cmp);
        costs.len() < 2 || costs[1] - costs[0] > 1e-3
    });
    if !clear || (score.ratio - 1.0).abs() > 1e-9 {
        return None;
    }
    let nodes: Vec<Value> = model
        .decided()
        .iter()
        .map(|(choice, index)| match choice.picks[*index] {
            Pick::Leaf => json!({"path": choice.path, "shapes": choice.shapes, "leaf": true}),
            Pick::Split { axis, position } => json!({
                "path": choice.path,
                "shapes": choice.shapes,
                "axis": axis,
                "position": position,
                "cost": choice.costs[*index],
            }),
        })
        .collect();
    let mut fields = Map::new();
    fields.insert("shapes".into(), shapes_json(&shapes));
    fields.insert(
        "cost".into(),
        json!({"c_trav": cost.traversal_cost, "c_isect": cost.intersection_cost}),
    );
    Some(Draft {
        prompt: format!(
            "Build a BVH over these {count} shapes yourself: at each node pick a split (shapes whose box centre lies below it go left) or keep a leaf. You are scored on your tree's SAH cost against the SAH builder's (C_trav = 1, C_isect = 1)."
        ),
        figure: Figure::Build(Box::new(exercise)),
        asks: vec![first],
        fields,
        answer: json!({"sah_cost": score.builder_cost, "nodes": nodes}),
    })
}
