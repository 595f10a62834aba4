//! Quadtree traversal, front to back (Revelles, Ureña & Lastra 2000): at a cell the ray
//! enters, which of its four children does it visit first, and which next? The ray starts in
//! the child holding its entry point, and each middle line it crosses inside the cell takes it
//! into the child across that line. The steps are the core's octree traversal (a quadtree in
//! 2D), recorded.

use accelviz_core::{Order, Query, Step, Structure};
use serde_json::json;

use super::Draft;
use super::first_hit::scene_and_ray;
use crate::generate::{
    AXES, Gen, Level, build, clear_steps, grazes_a_corner, num, ray_numbers, record,
};
use crate::question::{Ask, Choice, Expected, Highlight, node_label};

/// The most cells a question asks about.
const MOST_ASKED: usize = 3;

/// How far from a middle line (in scene units) the ray must enter a cell or cross the other
/// middle line: nearer, which child comes first turns on a sliver.
const CLEARANCE: f64 = 0.15;

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let (shapes, ray) = scene_and_ray(generator)?;
    let leaf_size = match generator.level {
        Level::Easy => 2,
        Level::Medium => 1,
        Level::Hard => 1,
    };
    let built = build(
        Structure::Octree { leaf: leaf_size },
        &shapes,
        usize::from(leaf_size),
    );
    let steps = record(&built, &shapes, &ray, Order::NearFirst);
    if !clear_steps(&steps) || grazes_a_corner(&built, &ray) {
        return None;
    }
    let facts = &built.facts;
    let origin = ray.origin.to_array();
    let direction = ray.direction.to_array();
    let mut asks = Vec::new();
    let mut answers = Vec::new();
    for (at, step) in steps.iter().enumerate() {
        let Step::ChildrenOrdered {
            node, order, count, ..
        } = *step
        else {
            continue;
        };
        let Some(children) = facts.children[node as usize] else {
            continue;
        };
        let order = &order[..count as usize];
        // The ray's part of the cell: the step where it was entered.
        let (t_near, t_far) = steps[..at].iter().rev().find_map(|step| match *step {
            Step::CellEntered {
                node: entered,
                t_near,
                t_far,
            } if entered == node => Some((t_near, t_far)),
            _ => None,
        })?;
        let cuts = built.cuts(node);
        let middle = [cuts[0].1, cuts[1].1];
        // Where the ray starts in the cell, and where it crosses the middle lines inside it:
        // each must be clear of the other line.
        let at_t = |t: f64| [origin[0] + t * direction[0], origin[1] + t * direction[1]];
        let entry = at_t(t_near);
        let crossings: Vec<(usize, f64)> = (0..2)
            .filter(|&axis| direction[axis] != 0.0)
            .map(|axis| (axis, (middle[axis] - origin[axis]) / direction[axis]))
            .filter(|&(_, t)| t > t_near && t < t_far)
            .collect();
        let clear = (0..2).all(|axis| (entry[axis] - middle[axis]).abs() >= CLEARANCE)
            && crossings.iter().all(|&(axis, t)| {
                let point = at_t(t);
                (point[1 - axis] - middle[1 - axis]).abs() >= CLEARANCE
                    && (t_far - t).abs() >= 0.01
                    && (t - t_near).abs() >= 0.01
            });
        if !clear {
            return None;
        }
        answers.push(json!({"node": node, "order": order}));
        if asks.len() >= MOST_ASKED || order.is_empty() {
            continue;
        }
        let label = node_label(facts, node);
        let quadrant = |child: u32| {
            let index = child - children.first;
            let sides: Vec<String> = (0..2)
                .map(|axis| {
                    let above = index & (1 << axis) != 0;
                    format!(
                        "{} {} {}",
                        AXES[axis],
                        if above { ">" } else { "<" },
                        num(middle[axis])
                    )
                })
                .collect();
            format!("node {} ({})", node_label(facts, child), sides.join(", "))
        };
        let options: Vec<Choice> = children
            .iter()
            .map(|child| Choice {
                label: quadrant(child),
                node: Some(child),
                shape: None,
            })
            .collect();
        let first = order[0];
        let entry_text = format!("({}, {})", num(entry[0]), num(entry[1]));
        asks.push(Ask {
            prompt: format!(
                "The ray enters cell {label} at t = {} and leaves it at t = {}; the cell is cut at x = {} and y = {}. Which child does it visit first?",
                num(t_near),
                num(t_far),
                num(middle[0]),
                num(middle[1])
            ),
            expected: Expected::Choice {
                options: options.clone(),
                correct: (first - children.first) as usize,
            },
            explanation: format!(
                "At t = {} the ray is at {entry_text}: {} and {}, the child {}, where it starts.",
                num(t_near),
                side_text(entry[0], middle[0], "x"),
                side_text(entry[1], middle[1], "y"),
                node_label(facts, first)
            ),
            highlight: Highlight {
                nodes: vec![first],
                t: Some(t_near),
                t_label: format!("enters, t = {}", num(t_near)),
                frame: Some(at + 1),
                ..Highlight::default()
            },
            frame: at,
            needs: [ray_numbers(&ray), vec![t_near, middle[0], middle[1]]].concat(),
        });
        // The child after the first, when the ray passes more than one: the middle line it
        // crosses first decides.
        if let (Some(&second), Some(&(axis, t_cross))) = (
            order.get(1),
            crossings.iter().min_by(|a, b| a.1.total_cmp(&b.1)),
        ) {
            let reaches: Vec<String> = crossings
                .iter()
                .map(|&(axis, t)| {
                    format!("{} = {} at t = {}", AXES[axis], num(middle[axis]), num(t))
                })
                .collect();
            asks.push(Ask {
                prompt: format!(
                    "After child {}, which child of {label} does the ray pass into next?",
                    node_label(facts, first)
                ),
                expected: Expected::Choice {
                    options,
                    correct: (second - children.first) as usize,
                },
                explanation: format!(
                    "Inside the cell the ray reaches {}: the first is {} = {}, so it crosses into {} at t = {}.",
                    reaches.join(" and "),
                    AXES[axis],
                    num(middle[axis]),
                    node_label(facts, second),
                    num(t_cross)
                ),
                highlight: Highlight {
                    nodes: vec![second],
                    t: Some(t_cross),
                    t_label: format!("{} = {}, t = {}", AXES[axis], num(middle[axis]), num(t_cross)),
                    frame: Some(at + 1),
                    ..Highlight::default()
                },
                frame: at,
                needs: [ray_numbers(&ray), vec![t_near, middle[0], middle[1]]].concat(),
            });
        }
    }
    if asks.is_empty() {
        return None;
    }
    Some(Draft::near_first_traversal(
        "A quadtree over the shapes: each cell cut at its middle into four, numbered by their sides (bit 0: x above the middle, bit 1: y above). The ray visits the children it passes front to back.",
        (shapes, ray),
        built,
        Query::Closest,
        steps,
        asks,
        ("orders", json!(answers)),
    ))
}

/// `x < 10` or `x > 10`, for an explanation.
fn side_text(value: f64, middle: f64, axis: &str) -> String {
    if value < middle {
        format!("{axis} = {} < {}", num(value), num(middle))
    } else {
        format!("{axis} = {} > {}", num(value), num(middle))
    }
}
