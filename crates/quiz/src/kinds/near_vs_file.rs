//! Near first against file order, on one ray: how many nodes each enters, which near first
//! skips and why. Both traversals are the core's, recorded; near first's saving is the
//! lecture's answer to "why first do the near side?".

use accelviz_core::{Order, Query, Step};
use serde_json::json;

use super::Draft;
use super::first_hit::scene_and_ray;
use super::visit_order::bvh_structure;
use crate::generate::{
    Gen, Level, box_numbers, build, clear_steps, entered, final_hit, num, ray_numbers, record,
    traversal_question,
};
use crate::question::{Ask, Choice, Expected, Figure, Highlight, TreeFigure, node_label};

/// Why near first does not enter a node that file order enters.
const REASONS: [&str; 4] = [
    "a hit found earlier lies before its box: it is culled",
    "its parent was never entered, so it was never reached",
    "the ray passes beside its box and misses it entirely",
    "near first always skips a right child when it can",
];

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
    let near = entered(&near_steps);
    let file = entered(&file_steps);
    let skipped: Vec<u32> = file
        .iter()
        .copied()
        .filter(|node| !near.contains(node))
        .collect();
    let hit = final_hit(&near_steps)?;
    if skipped.is_empty() {
        return None;
    }
    let facts = &built.facts;
    // The node asked about: the first one skipped (in file order's visit order).
    let asked = skipped[0];
    let reason = if near_steps.iter().any(|step| {
        matches!(step, Step::NodeCulled { node, .. } | Step::BoxTested { node, hit: false, .. } if *node == asked)
    }) {
        0
    } else {
        1
    };
    // The options: the skipped node among up to three nodes both orders enter (not the root).
    let mut nodes: Vec<u32> = near.iter().copied().filter(|node| *node != 0).collect();
    generator.shuffle(&mut nodes);
    nodes.truncate(3);
    nodes.push(asked);
    nodes.sort_unstable();
    let correct = nodes.iter().position(|node| *node == asked)?;
    let mut reason_order = [0, 1, 2, 3];
    generator.shuffle(&mut reason_order);
    let reason_correct = reason_order.iter().position(|at| *at == reason)?;
    let count = |steps: &[Step<f64>]| steps.len();
    let near_frames = count(&near_steps);
    let list = |nodes: &[u32]| {
        nodes
            .iter()
            .map(|node| node_label(facts, *node))
            .collect::<Vec<_>>()
            .join(", ")
    };
    // Which node is skipped, and why, before the counts: their explanations list the nodes.
    // What the counts are worked out from: the ray and every node's box.
    let needs: Vec<f64> = ray_numbers(&ray)
        .into_iter()
        .chain((0..facts.node_count()).flat_map(|node| box_numbers(&facts.bounds[node])))
        .collect();
    let asks = vec![
        Ask {
            prompt: "Which of these nodes does file order enter but near first skip?".into(),
            expected: Expected::Choice {
                options: nodes
                    .iter()
                    .map(|node| Choice {
                        label: format!("node {}", node_label(facts, *node)),
                        node: Some(*node),
                        shape: None,
                    })
                    .collect(),
                correct,
            },
            // Only the node asked about: which others each order enters is for the counts.
            explanation: format!(
                "File order enters node {label}, near first does not: why comes next.",
                label = node_label(facts, asked)
            ),
            highlight: Highlight {
                nodes: vec![asked],
                ..Highlight::default()
            },
            frame: 0,
            needs: Vec::new(),
        },
        Ask {
            prompt: format!(
                "Why does near first not enter node {}?",
                node_label(facts, asked)
            ),
            expected: Expected::Choice {
                options: reason_order
                    .iter()
                    .map(|at| Choice::text(REASONS[*at]))
                    .collect(),
                correct: reason_correct,
            },
            explanation: if reason == 0 {
                format!(
                    "Near first reaches shape {} at t = {} before it gets to node {}, whose box starts later: nothing in it can be closer, so it is not entered. File order enters it because it goes left first, before it has that hit.",
                    hit.0,
                    num(hit.1),
                    node_label(facts, asked)
                )
            } else {
                format!(
                    "An ancestor of node {} was culled by near first (its box starts beyond the hit at t = {}), so the traversal never reached it.",
                    node_label(facts, asked),
                    num(hit.1)
                )
            },
            // The hit and the node, not near first's steps: which nodes it enters is the
            // next step's question.
            highlight: Highlight {
                nodes: vec![asked],
                shapes: vec![hit.0],
                t: Some(hit.1),
                t_label: format!("closest, t = {}", num(hit.1)),
                ..Highlight::default()
            },
            frame: 0,
            needs: Vec::new(),
        },
        Ask {
            prompt: "How many nodes does near-first traversal enter (the root included)?".into(),
            expected: Expected::Number {
                value: near.len() as f64,
                tolerance: 0.0,
            },
            explanation: format!("Near first enters {}: {}.", near.len(), list(&near)),
            highlight: Highlight {
                nodes: near.clone(),
                frame: Some(near_frames),
                ..Highlight::default()
            },
            frame: 0,
            needs: needs.clone(),
        },
        Ask {
            prompt: "How many nodes does file-order traversal enter?".into(),
            expected: Expected::Number {
                value: file.len() as f64,
                tolerance: 0.0,
            },
            explanation: format!(
                "File order enters {}: {}. It finds the same hit, shape {} at t = {}, later.",
                file.len(),
                list(&file),
                hit.0,
                num(hit.1)
            ),
            highlight: Highlight {
                nodes: file.clone(),
                ..Highlight::default()
            },
            frame: 0,
            needs,
        },
    ];
    let (fields, scene) = traversal_question(
        shapes,
        ray,
        TreeFigure {
            built,
            order: Order::NearFirst,
            query: Query::Closest,
            steps: near_steps,
            reveal_as_reached: false,
        },
    );
    Some(Draft {
        prompt: "The same ray through the same BVH, traversed near first and in file order (left child first). Compare the work.".into(),
        figure: Figure::Scene(Box::new(scene)),
        asks,
        fields,
        answer: json!({
            "near_first": near,
            "file_order": file,
            "skipped": skipped,
            "shape": hit.0,
        }),
    })
}
