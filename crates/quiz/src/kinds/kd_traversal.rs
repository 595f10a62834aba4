//! kD-tree traversal, the lecture's pseudo-code: at a cell, which child is near, and is the
//! far child visited? The pseudo-code searches the far child only `If(no intersection)` in
//! the near one, and then only if the ray's far part is not empty (`if empty(ray) return`):
//! the reason asked for is the one it acts on, decided when it comes to it, once the near
//! subtree is done. The steps are the core's kD traversal under that rule
//! ([`Query::FirstInCell`]), recorded.

use accelviz_core::{Order, Query, Step, Structure};
use serde_json::json;

use super::Draft;
use super::first_hit::{scene_and_ray, shape_name};
use crate::generate::{
    AXES, Gen, Level, build, clear_cell_hits, clear_steps, final_hit, grazes_a_corner, num,
    ray_numbers, record_query,
};
use crate::question::{Ask, Choice, Expected, Highlight, node_label};

/// The most cells a question asks about.
const MOST_ASKED: usize = 3;

/// What happens to the far child, and why: the pseudo-code's three cases and a distractor.
/// Each of the three says what the near child gave, so exactly one is true.
const OUTCOMES: [&str; 4] = [
    "yes: the near child gave no hit, and the far part is not empty",
    "no: the near child gave no hit, but the ray's far part is empty",
    "no: the near child gave a hit, so the far side is never clipped",
    "no: near first never searches a far child, only file order does",
];

/// What became of a far child, as [`OUTCOMES`] indexes it and the JSON names it.
const FATES: [&str; 3] = ["searched", "empty", "not searched"];

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let (shapes, ray) = scene_and_ray(generator)?;
    let structure = if generator.index(2) == 0 {
        Structure::KdMiddle
    } else {
        Structure::KdSah
    };
    let leaf_size = if generator.level == Level::Easy { 1 } else { 2 };
    let built = build(structure, &shapes, leaf_size);
    let steps = record_query(&built, &shapes, &ray, Order::NearFirst, Query::FirstInCell);
    if !clear_steps(&steps) || !clear_cell_hits(&steps) || grazes_a_corner(&built, &ray) {
        return None;
    }
    let facts = &built.facts;
    let direction = ray.direction.to_array();
    let origin = ray.origin.to_array();
    // Each ask with the order it is asked in: by frame, and among the far children that the
    // near child's hit leaves unsearched (all decided at the end), innermost first, as the
    // recursion returns.
    let mut asks = Vec::new();
    let mut answers = Vec::new();
    for (at, step) in steps.iter().enumerate() {
        let Step::CellEntered {
            node,
            t_near,
            t_far,
        } = *step
        else {
            continue;
        };
        let (Some([below, above]), Some((axis, split))) = (
            facts.children[node as usize].and_then(|children| children.as_pair()),
            built.plane(node),
        ) else {
            continue;
        };
        if origin[axis] == split {
            continue;
        }
        let (near, far) = if direction[axis] < 0.0 {
            (above, below)
        } else {
            (below, above)
        };
        let later = &steps[at + 1..];
        let missed = |cell: u32| {
            later
                .first()
                .is_some_and(|step| *step == Step::CellMissed { node: cell })
        };
        if missed(near) {
            // The ray is past the plane already: no near side to ask about.
            continue;
        }
        let t_plane = (split - origin[axis]) / direction[axis];
        // The far child's fate, decided once the near subtree is done: entered, dropped as
        // empty, or never come to (the near child gave a hit, and the search ended).
        let fate = later.iter().position(|step| {
            matches!(step, Step::CellEntered { node, .. } | Step::CellMissed { node } if *node == far)
        });
        let (outcome, decided_at) = match fate.map(|offset| (later[offset], at + 1 + offset)) {
            Some((Step::CellEntered { .. }, decided)) => (0, decided + 1),
            Some((_, decided)) => (1, decided + 1),
            None => (2, steps.len()),
        };
        let mut answer = json!({"node": node, "near": near, "far": FATES[outcome]});
        if asks.len() / 2 >= MOST_ASKED {
            answers.push(answer);
            continue;
        }
        answer["reason"] = json!(OUTCOMES[outcome]);
        answers.push(answer);
        let label = node_label(facts, node);
        let side = |child: u32| {
            let relation = if child == below { "<" } else { ">" };
            format!(
                "node {} ({} {relation} {})",
                node_label(facts, child),
                AXES[axis],
                num(split)
            )
        };
        let moving = if direction[axis] < 0.0 {
            "decreasing"
        } else {
            "increasing"
        };
        asks.push(((at + 1, at), Ask {
            prompt: format!(
                "The ray is in cell {label} for t in [{}, {}]; the cell is cut at {} = {}. Which child is near?",
                num(t_near),
                num(t_far),
                AXES[axis],
                num(split)
            ),
            expected: Expected::Choice {
                options: vec![
                    Choice {
                        label: side(below),
                        node: Some(below),
                        shape: None,
                    },
                    Choice {
                        label: side(above),
                        node: Some(above),
                        shape: None,
                    },
                ],
                correct: usize::from(near == above),
            },
            explanation: format!(
                "The ray's direction along {axis_name} is {d}: it moves towards {moving} {axis_name}, so inside the cell it meets the side {which} the plane first. That is the near child, {near_label}.",
                axis_name = AXES[axis],
                d = num(direction[axis]),
                which = if near == below { "below" } else { "above" },
                near_label = node_label(facts, near)
            ),
            highlight: Highlight {
                nodes: vec![near],
                frame: Some(at + 1),
                ..Highlight::default()
            },
            frame: at + 1,
            needs: Vec::new(),
        }));
        let mut order = [0, 1, 2, 3];
        generator.shuffle(&mut order);
        let why = match outcome {
            0 => format!(
                "The near child gave no hit, so `If(no intersection)` holds and the ray is clipped to the far side: it crosses the plane at t = {} inside the cell's [{}, {}], and the far child is searched with [{}, {}].",
                num(t_plane),
                num(t_near),
                num(t_far),
                num(t_plane.max(t_near)),
                num(t_far)
            ),
            1 => format!(
                "The near child gave no hit, so the ray is clipped to the far side: it would cross the plane at t = {}, after it leaves the cell at t = {}, so its far part is empty and the far call returns at once (the lecture's `if empty(ray) return`).",
                num(t_plane),
                num(t_far)
            ),
            _ => {
                let (shape, t_hit) = final_hit(&steps)?;
                format!(
                    "The near child, {}, gave a hit: {} at t = {}, inside the part of the ray of the leaf that found it. So `If(no intersection)` is false: the far side is never clipped or searched, and the search ends with that hit.",
                    node_label(facts, near),
                    shape_name(&shapes, shape),
                    num(t_hit)
                )
            }
        };
        // Asked when the traversal comes to decide it, as the lecture's recursion does: once
        // the near subtree is done, just before the far child's fate is shown (or, when the
        // near child's hit ends the search, once it has).
        let (frame, order_key) = if outcome == 2 {
            (decided_at, usize::MAX - at)
        } else {
            (decided_at - 1, at)
        };
        asks.push((
            (frame, order_key),
            Ask {
                prompt: format!(
                    "Is the far child of {label}, node {}, visited, and why?",
                    node_label(facts, far)
                ),
                expected: Expected::Choice {
                    options: order.iter().map(|at| Choice::text(OUTCOMES[*at])).collect(),
                    correct: order.iter().position(|at| *at == outcome)?,
                },
                explanation: why,
                highlight: Highlight {
                    nodes: vec![far],
                    t: Some(t_plane),
                    t_label: format!("plane, t = {}", num(t_plane)),
                    frame: Some(decided_at),
                    ..Highlight::default()
                },
                frame,
                needs: [ray_numbers(&ray), vec![split, t_near, t_far]].concat(),
            },
        ));
    }
    if asks.is_empty() {
        return None;
    }
    // In traversal order: a cell's near child, its near subtree's questions, then its far
    // child.
    asks.sort_by_key(|(order, _)| *order);
    let asks: Vec<Ask> = asks.into_iter().map(|(_, ask)| ask).collect();
    Some(Draft::near_first_traversal(
        "A kD-tree over the shapes, traversed as the lecture's pseudo-code does: the near child first, each leaf's shapes tested against the ray clipped to its cell, and the far child only `If(no intersection)` in the near one (and only if the ray reaches it).",
        (shapes, ray),
        built,
        Query::FirstInCell,
        steps,
        asks,
        ("cells", json!(answers)),
    ))
}
