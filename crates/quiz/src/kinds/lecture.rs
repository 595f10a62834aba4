//! The lecture's own quiz ("Why first do near side? What happens if we just traverse in file
//! order?"): two multiple-choice questions, then the live demonstration on a scene where the
//! two orders differ, recorded by the core's traversal.

use accelviz_core::{Order, Step};
use serde_json::json;

use super::Draft;
use super::first_hit::scene_and_ray;
use super::visit_order::bvh_structure;
use crate::generate::{
    Gen, Level, build, clear_steps, entered, final_hit, num, record, traversal_question,
};
use crate::question::{Ask, Choice, Expected, Figure, Highlight, TreeFigure, node_label};

const WHY_NEAR: [&str; 4] = [
    "a hit on the near side lies before anything on the far side, so once one is found the far side can often be skipped",
    "the near side always holds fewer primitives",
    "in any other order the traversal could return a hit that is not the closest",
    "the near child's box test is cheaper",
];

const FILE_ORDER: [&str; 4] = [
    "the same closest hit, found with more work: nodes behind it are entered and tested before it is known",
    "a hit that may not be the closest",
    "nothing changes: the same nodes are entered in another order",
    "fewer nodes are entered, because memory is read in order",
];

fn choice(generator: &mut Gen, texts: &[&str; 4]) -> Expected {
    let mut order = [0, 1, 2, 3];
    generator.shuffle(&mut order);
    Expected::Choice {
        options: order.iter().map(|at| Choice::text(texts[*at])).collect(),
        correct: order.iter().position(|at| *at == 0).unwrap_or(0),
    }
}

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let (shapes, ray) = scene_and_ray(generator)?;
    let structure = bvh_structure(generator);
    let leaf_size = if generator.level == Level::Easy { 1 } else { 2 };
    let built = build(structure, &shapes, leaf_size);
    let near_steps = record(&built, &shapes, &ray, Order::NearFirst);
    let file_steps = record(&built, &shapes, &ray, Order::FileOrder);
    if !clear_steps(&near_steps) || !clear_steps(&file_steps) {
        return None;
    }
    let (near, file) = (entered(&near_steps), entered(&file_steps));
    let (shape, t) = final_hit(&near_steps)?;
    // The demonstration needs a ray on which the orders differ by more than a node.
    if file.len() < near.len() + 2 {
        return None;
    }
    let tests = |steps: &[Step<f64>]| {
        steps
            .iter()
            .filter(|step| matches!(step, Step::PrimitiveTested { .. }))
            .count()
    };
    let list = |nodes: &[u32]| {
        nodes
            .iter()
            .map(|node| node_label(&built.facts, *node))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let asks = vec![
        Ask {
            prompt: "Why first do the near side?".into(),
            expected: choice(generator, &WHY_NEAR),
            explanation: "Along the ray, everything in the near child comes before the far child's box. A hit found there ends the search of any node whose box starts beyond it: near first finds close hits early and culls the rest. Both orders return the closest hit; near first does less work.".into(),
            highlight: Highlight::default(),
            frame: 0,
        },
        Ask {
            prompt: "What happens if we just traverse in file order (the order nodes happen to be in memory)?".into(),
            expected: choice(generator, &FILE_ORDER),
            explanation: "Culling still keeps the answer right, but file order may spend its work on far subtrees first, before it has the hit that would have let it skip them.".into(),
            highlight: Highlight::default(),
            frame: 0,
        },
        Ask {
            prompt: format!(
                "On this scene, file order enters {} nodes. How many does near first enter?",
                file.len()
            ),
            expected: Expected::Number {
                value: near.len() as f64,
                tolerance: 0.0,
            },
            explanation: format!(
                "Near first enters {} nodes ({}) and makes {} shape tests; file order enters {} ({}) and makes {}. Both find shape {shape} at t = {}.",
                near.len(),
                list(&near),
                tests(&near_steps),
                file.len(),
                list(&file),
                tests(&file_steps),
                num(t)
            ),
            highlight: Highlight {
                nodes: near.clone(),
                shapes: vec![shape],
                t: Some(t),
                frame: Some(near_steps.len()),
                ..Highlight::default()
            },
            frame: 0,
        },
    ];
    let (fields, scene) = traversal_question(
        shapes,
        ray,
        TreeFigure {
            built,
            order: Order::NearFirst,
            steps: near_steps,
            reveal_as_reached: false,
        },
    );
    Some(Draft {
        prompt: "The lecture's quiz: why first do the near side, and what happens in file order? Then see it on a scene.".into(),
        figure: Figure::Scene(Box::new(scene)),
        asks,
        fields,
        answer: json!({
            "why_near_first": WHY_NEAR[0],
            "file_order": FILE_ORDER[0],
            "near_first_visited": near,
            "file_order_visited": file,
            "shape": shape,
        }),
    })
}
