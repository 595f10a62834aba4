//! BVH traversal, step by step: the animation pauses before each node is entered and asks
//! which one comes next (OpenDSA's order-reproduction exercises, with child boxes revealed
//! only once the traversal reaches them). The steps are the core's traversal, recorded.

use accelviz_core::{Order, Query, Step, Structure, Width};
use serde_json::json;

use super::Draft;
use super::first_hit::{scene_and_ray, shape_options};
use crate::generate::{
    Gen, Level, box_numbers, build, clear_steps, entered, final_hit, num, ray_numbers, record,
    traversal_question,
};
use crate::question::{Ask, Choice, Expected, Figure, Highlight, TreeFigure, node_label};

/// The most nodes a question asks about: past that, it is the same step again.
const MOST_ASKED: usize = 8;

/// The structures questions are asked on.
pub(super) fn bvh_structure(generator: &mut Gen) -> Structure {
    if generator.index(2) == 0 {
        Structure::BvhMedian {
            width: Width::Binary,
        }
    } else {
        Structure::BvhSahSweep {
            width: Width::Binary,
        }
    }
}

/// Why the traversal entered `steps[at]`'s node, from the steps before it.
fn why_entered(
    figure: &TreeFigure,
    steps: &[Step<f64>],
    at: usize,
    previous: Option<u32>,
) -> String {
    let facts = &figure.built.facts;
    let Step::NodeEntered { node } = steps[at] else {
        return String::new();
    };
    let label = node_label(facts, node);
    let box_test = |wanted: u32| {
        steps[..at].iter().rev().find_map(|step| match step {
            Step::BoxTested {
                node, t_enter, hit, ..
            } if *node == wanted => Some((*t_enter, *hit)),
            _ => None,
        })
    };
    let parent = facts.parent[node as usize];
    let culled: Vec<String> = steps[..at]
        .iter()
        .rev()
        .take_while(|step| !matches!(step, Step::NodeEntered { .. }))
        .filter_map(|step| match step {
            Step::NodeCulled {
                node,
                t_enter,
                t_closest,
            } => Some(format!(
                "{} was skipped: its box starts at t = {}, beyond the closest hit at t = {}",
                node_label(facts, *node),
                num(*t_enter),
                num(*t_closest)
            )),
            _ => None,
        })
        .collect();
    let culled = if culled.is_empty() {
        String::new()
    } else {
        format!(" ({})", culled.join("; "))
    };
    if parent.is_some() && parent == previous {
        let siblings = facts.children[parent.unwrap_or(0) as usize]
            .and_then(|children| children.as_pair())
            .unwrap_or([node, node]);
        let sibling = if siblings[0] == node {
            siblings[1]
        } else {
            siblings[0]
        };
        let (t_here, _) = box_test(node).unwrap_or((0.0, true));
        match box_test(sibling) {
            Some((t_there, true)) => match figure.order {
                Order::NearFirst => format!(
                    "Both children's boxes are hit; near first enters the one the ray reaches first: {label} at t = {} before {} at t = {}. The other waits on the stack.",
                    num(t_here),
                    node_label(facts, sibling),
                    num(t_there)
                ),
                Order::FileOrder => format!(
                    "Both children's boxes are hit; file order enters the left child first, {label}, wherever the ray meets it. The other waits on the stack."
                ),
            },
            _ => format!(
                "Of the two children only {label}'s box is hit (at t = {}); the other is not entered.",
                num(t_here)
            ),
        }
    } else {
        format!(
            "The subtree before is done, so the next node comes off the stack: {label}{culled}."
        )
    }
}

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let (shapes, ray) = scene_and_ray(generator)?;
    let structure = bvh_structure(generator);
    let order = if generator.index(2) == 0 {
        Order::NearFirst
    } else {
        Order::FileOrder
    };
    let leaf_size = if generator.level == Level::Easy { 1 } else { 2 };
    let built = build(structure, &shapes, leaf_size);
    let steps = record(&built, &shapes, &ray, order);
    if !clear_steps(&steps) {
        return None;
    }
    let visited = entered(&steps);
    if visited.len() < 3 {
        return None;
    }
    let hit = final_hit(&steps);
    let figure = TreeFigure {
        built,
        order,
        query: Query::Closest,
        steps: steps.clone(),
        reveal_as_reached: true,
    };
    let facts = &figure.built.facts;
    let mut asks = Vec::new();
    let mut entered_so_far: Vec<u32> = Vec::new();
    let mut previous = None;
    for (at, step) in steps.iter().enumerate() {
        let Step::NodeEntered { node } = *step else {
            continue;
        };
        if !entered_so_far.is_empty() && asks.len() < MOST_ASKED {
            // The nodes the student can see and has not seen entered: children of nodes
            // entered so far.
            let options: Vec<u32> = (0..facts.node_count() as u32)
                .filter(|candidate| {
                    !entered_so_far.contains(candidate)
                        && facts.parent[*candidate as usize]
                            .is_some_and(|parent| entered_so_far.contains(&parent))
                })
                .collect();
            let correct = options.iter().position(|option| *option == node)?;
            if options.len() < 2 {
                // One node in sight: nothing to predict.
                entered_so_far.push(node);
                previous = Some(node);
                continue;
            }
            // The figure as it stands before this step's own tests: the box tests (and culls)
            // that decide which node comes next are not drawn, or they would paint the answer.
            let asked_at = steps[..at]
                .iter()
                .rposition(|step| !matches!(step, Step::BoxTested { .. } | Step::NodeCulled { .. }))
                .map_or(0, |before| before + 1);
            asks.push(Ask {
                prompt: format!(
                    "Which node does the traversal ({}) enter next?",
                    order.name().replace('-', " ")
                ),
                expected: Expected::Choice {
                    options: options
                        .iter()
                        .map(|option| Choice {
                            label: format!("node {}", node_label(facts, *option)),
                            node: Some(*option),
                            shape: None,
                        })
                        .collect(),
                    correct,
                },
                explanation: why_entered(&figure, &steps, at, previous),
                highlight: Highlight {
                    nodes: vec![node],
                    frame: Some(at + 1),
                    ..Highlight::default()
                },
                frame: asked_at,
                needs: ray_numbers(&ray)
                    .into_iter()
                    .chain(
                        options
                            .iter()
                            .flat_map(|option| box_numbers(&facts.bounds[*option as usize])),
                    )
                    .collect(),
            });
        }
        entered_so_far.push(node);
        previous = Some(node);
    }
    let options = shape_options(&shapes);
    let none = options.len() - 1;
    // The nodes still waiting once the hit is found: each is culled (or none is left).
    let last_hit = steps
        .iter()
        .rposition(|step| matches!(step, Step::ClosestHitUpdated { .. }))
        .unwrap_or(steps.len());
    let after = &steps[last_hit..];
    let named = |wanted: fn(&Step<f64>) -> Option<u32>| -> Vec<String> {
        after
            .iter()
            .filter_map(wanted)
            .map(|node| node_label(facts, node))
            .collect()
    };
    let culled = named(|step| match *step {
        Step::NodeCulled { node, .. } => Some(node),
        _ => None,
    });
    let entered_after = named(|step| match *step {
        Step::NodeEntered { node } => Some(node),
        _ => None,
    });
    let after_the_hit = match (entered_after.is_empty(), culled.is_empty()) {
        (true, true) => "once it is found, no node is left on the stack".to_owned(),
        (false, true) => format!(
            "the traversal then enters {}, whose boxes start before it, and finds nothing nearer",
            entered_after.join(", ")
        ),
        (true, false) => format!(
            "every node left on the stack ({}) starts beyond it and is skipped",
            culled.join(", ")
        ),
        (false, false) => format!(
            "the traversal then enters {}, whose boxes start before it, finds nothing nearer, and skips {}, which start beyond it",
            entered_after.join(", "),
            culled.join(", ")
        ),
    };
    asks.push(Ask {
        prompt: "Which shape does the traversal return as the closest hit?".into(),
        expected: Expected::Choice {
            options,
            correct: hit.map_or(none, |(shape, _)| shape as usize),
        },
        explanation: match hit {
            Some((shape, t)) => format!("Shape {shape} at t = {}: {after_the_hit}.", num(t)),
            None => "No leaf the ray reaches holds a shape it hits.".into(),
        },
        highlight: Highlight {
            shapes: hit.map(|(shape, _)| vec![shape]).unwrap_or_default(),
            t: hit.map(|(_, t)| t),
            t_label: hit.map_or_else(String::new, |(_, t)| format!("closest, t = {}", num(t))),
            frame: Some(steps.len()),
            ..Highlight::default()
        },
        // The last node entered, before its shapes are tested.
        frame: steps
            .iter()
            .rposition(|step| matches!(step, Step::NodeEntered { .. }))
            .map_or(0, |at| at + 1),
        needs: Vec::new(),
    });
    let order_value = json!(order.name());
    let (mut fields, scene) = traversal_question(shapes, ray, figure);
    fields.insert("order".into(), order_value);
    Some(Draft {
        prompt: format!(
            "A BVH over the shapes, and a ray. The traversal pauses before each node it enters: which comes next? Order: {}.",
            order.name()
        ),
        figure: Figure::Scene(Box::new(scene)),
        asks,
        fields,
        answer: json!({
            "visited": visited,
            "shape": hit.map(|(shape, _)| shape),
        }),
    })
}
