//! kD-tree traversal, the lecture's pseudo-code: at a cell, which child is near, and is the
//! far child visited (the ray reaches the plane inside the cell, and no hit was found before
//! it)? The steps are the core's kD traversal, recorded.

use accelviz_core::{Order, Step, Structure};
use serde_json::json;

use super::Draft;
use super::first_hit::scene_and_ray;
use crate::generate::{
    AXES, Gen, Level, build, clear_steps, grazes_a_corner, num, ray_numbers, record,
};
use crate::question::{Ask, Choice, Expected, Highlight, node_label};

/// The most cells a question asks about.
const MOST_ASKED: usize = 3;

/// What happens to the far child, and why.
const OUTCOMES: [&str; 4] = [
    "yes: nothing in the near child was hit before the plane",
    "no: the ray leaves the cell before it reaches the plane",
    "no: a hit in the near child lies before the far child begins",
    "no: the far child is only visited in file order",
];

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let (shapes, ray) = scene_and_ray(generator)?;
    let structure = if generator.index(2) == 0 {
        Structure::KdMiddle
    } else {
        Structure::KdSah
    };
    let leaf_size = if generator.level == Level::Easy { 1 } else { 2 };
    let built = build(structure, &shapes, leaf_size);
    let steps = record(&built, &shapes, &ray, Order::NearFirst);
    if !clear_steps(&steps) || grazes_a_corner(&built, &ray) {
        return None;
    }
    let facts = &built.facts;
    let direction = ray.direction.to_array();
    let origin = ray.origin.to_array();
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
        let (outcome, decided_at) = if missed(far) {
            (1, at + 2)
        } else {
            let fate = later.iter().position(|step| {
                matches!(step, Step::CellEntered { node, .. } | Step::NodeCulled { node, .. } if *node == far)
            });
            match fate.map(|offset| (later[offset], at + 1 + offset)) {
                Some((Step::CellEntered { .. }, decided)) => (0, decided + 1),
                Some((_, decided)) => (2, decided + 1),
                None => continue,
            }
        };
        answers.push(json!({"node": node, "near": near, "far_visited": outcome == 0}));
        if asks.len() / 2 >= MOST_ASKED {
            continue;
        }
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
        asks.push(Ask {
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
        });
        let mut order = [0, 1, 2, 3];
        generator.shuffle(&mut order);
        let why = match outcome {
            0 => format!(
                "The ray crosses the plane at t = {} inside the cell's [{}, {}], and the near child held no hit before it: the far child is traversed with [{}, {}].",
                num(t_plane),
                num(t_near),
                num(t_far),
                num(t_plane.max(t_near)),
                num(t_far)
            ),
            1 => format!(
                "The ray would cross the plane at t = {}, after it leaves the cell at t = {}: its far part is empty (the lecture's `if empty(ray) return`).",
                num(t_plane),
                num(t_far)
            ),
            _ => format!(
                "The near child gave a hit before t = {}, where the far part of the ray begins: nothing beyond it can be closer, so the far child is not entered.",
                num(t_plane.max(t_near))
            ),
        };
        asks.push(Ask {
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
            // Asked when the traversal comes to decide it, as the lecture's recursion does:
            // once the near subtree is done, just before the far child's fate is shown.
            frame: decided_at - 1,
            needs: [ray_numbers(&ray), vec![split, t_near, t_far]].concat(),
        });
    }
    if asks.is_empty() {
        return None;
    }
    // In traversal order: a cell's near child, its near subtree's questions, then its far
    // child (a stable sort keeps each cell's near question before its far one).
    asks.sort_by_key(|ask| ask.frame);
    Some(Draft::near_first_traversal(
        "A kD-tree over the shapes, traversed as in the lecture: near child first, the far child only if the ray reaches it and nothing nearer was hit.",
        (shapes, ray),
        built,
        steps,
        asks,
        ("cells", json!(answers)),
    ))
}
