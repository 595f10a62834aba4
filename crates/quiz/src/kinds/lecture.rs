//! The lecture's own quiz ("Why first do near side? What happens if we just traverse in file
//! order?"), asked on the algorithm of the slide it follows, "Traversing a kD-tree". That
//! pseudo-code searches the far child only `If(no intersection)` in the near one (the core's
//! [`Query::FirstInCell`]): keep the rule, take the children in file order, and the search
//! ends at the first hit it finds, which need not be the closest. The scene is drawn so that
//! here it is not, and the figure steps through that very traversal. A last step, which says
//! so, asks about the variant that culls by the closest hit instead: the same hit, more work.

use accelviz_core::{Order, Query, Step, Structure};
use serde_json::json;

use super::Draft;
use super::first_hit::{scene_and_ray, shape_name, shape_options};
use crate::generate::{
    Gen, Level, build, clear_cell_hits, clear_steps, entered, final_hit, grazes_a_corner, num,
    record, record_query, traversal_question,
};
use crate::question::{Ask, Choice, Expected, Figure, Highlight, TreeFigure, node_label};

/// "Why first do near side?" The first is right; the others are of about its length, so the
/// longest option is not the answer.
const WHY_NEAR: [&str; 4] = [
    "its hits come first along the ray, so one found there lets the far side be skipped",
    "the near child always holds fewer of the shapes, so searching it first is cheaper",
    "the near child comes first in memory, so reading it first keeps the caches warm",
    "the near child's cell is always the smaller one, so its shapes are quicker to test first",
];

/// "What happens if we just traverse in file order?", for the slide's pseudo-code. The first
/// is right; the second is right for the variant that culls by the closest hit instead.
const FILE_ORDER: [&str; 4] = [
    "it can return a hit that is not the closest: a far cell's hit ends the search",
    "the same closest hit, found with more work: far cells are searched before it",
    "nothing changes: the same cells are entered, only in another order than before",
    "fewer cells are entered, because the nodes are read in the order memory holds them",
];

/// What the variant that culls by the closest hit does in file order. The first is right.
const CULLED: [&str; 4] = [
    "the closest hit: a side is skipped only if it starts beyond a hit already found",
    "the same hit as the rule above: the first hit found still ends the whole search",
    "no hit at all: every side still waiting starts beyond the hit found, and is culled",
    "the closest hit, and it enters fewer cells than near first does on this ray",
];

/// The smallest gap, in t, between the hit file order stops at and the closest one: enough to
/// see in the figure.
const CLEAR_GAP: f64 = 0.3;

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
    let structure = if generator.index(2) == 0 {
        Structure::KdMiddle
    } else {
        Structure::KdSah
    };
    let leaf_size = if generator.level == Level::Easy { 1 } else { 2 };
    let built = build(structure, &shapes, leaf_size);
    if grazes_a_corner(&built, &ray) {
        return None;
    }
    // A ray starting in a split plane visits both sides there: a case for another question.
    let origin = ray.origin.to_array();
    if (0..built.facts.node_count() as u32)
        .filter_map(|node| built.plane(node))
        .any(|(axis, split)| origin[axis] == split)
    {
        return None;
    }
    let slide = |order| record_query(&built, &shapes, &ray, order, Query::FirstInCell);
    let (near_steps, file_steps) = (slide(Order::NearFirst), slide(Order::FileOrder));
    let culled_steps = record(&built, &shapes, &ray, Order::FileOrder);
    if ![&near_steps, &file_steps, &culled_steps]
        .iter()
        .all(|steps| clear_steps(steps))
        || !clear_cell_hits(&near_steps)
        || !clear_cell_hits(&file_steps)
    {
        return None;
    }
    let (closest, t_closest) = final_hit(&near_steps)?;
    let (stopped_at, t_stopped) = final_hit(&file_steps)?;
    // The scene must make the slide's point: file order stops at a farther hit, clearly, and
    // where the ray first meets that shape (not inside it, where its cell begins).
    let first_contact = shapes.shapes[stopped_at as usize].intersect(&ray, 0.0, f64::INFINITY);
    if stopped_at == closest
        || t_stopped - t_closest < CLEAR_GAP
        || first_contact != Some(t_stopped)
    {
        return None;
    }
    let (near, file, culled) = (
        entered(&near_steps),
        entered(&file_steps),
        entered(&culled_steps),
    );
    let facts = &built.facts;
    let list = |nodes: &[u32]| {
        nodes
            .iter()
            .map(|node| node_label(facts, *node))
            .collect::<Vec<_>>()
            .join(", ")
    };
    // The cell file order stops in, with its part of the ray.
    let (stop_cell, stop_near, stop_far) =
        file_steps.iter().rev().find_map(|step| match *step {
            Step::CellEntered {
                node,
                t_near,
                t_far,
            } => Some((node, t_near, t_far)),
            _ => None,
        })?;
    // Where file order tested the closest shape but the ray meets it outside that cell's part
    // (the clipped ray holds no intersection there): said, so that "never reached" is not
    // read as "never tested".
    let mut cell = None;
    let tested_outside = file_steps.iter().find_map(|step| match *step {
        Step::CellEntered {
            node,
            t_near,
            t_far,
        } => {
            cell = Some((node, t_near, t_far));
            None
        }
        Step::PrimitiveTested {
            primitive,
            t_hit: Some(_),
        } if primitive == closest => cell,
        _ => None,
    });
    let tested_outside = tested_outside.map_or_else(String::new, |(node, t_near, t_far)| {
        format!(
            " (cell {} lists it too, but the hit lies outside that cell's part of the ray, t in [{}, {}])",
            node_label(&built.facts, node),
            num(t_near),
            num(t_far)
        )
    });
    let options = shape_options(&shapes);
    let asks = vec![
        Ask {
            prompt: "Why first do the near side?".into(),
            expected: choice(generator, &WHY_NEAR),
            explanation: "Along the ray, the near child's part comes before the far child's. A hit found there lies before anything on the far side, so the pseudo-code's `If(no intersection)` can skip the far side: near first finds the closest hit and does the least work.".into(),
            highlight: Highlight::default(),
            frame: 0,
            needs: Vec::new(),
        },
        Ask {
            prompt: "What happens if we just traverse in file order (the order nodes happen to be in memory), keeping the pseudo-code's `If(no intersection)`?".into(),
            expected: choice(generator, &FILE_ORDER),
            explanation: "The far child is searched only if the near one gave no intersection. In file order the child searched first may be the far one along the ray: a hit there ends the search, though a nearer hit waits in the other child.".into(),
            highlight: Highlight::default(),
            frame: 0,
            needs: Vec::new(),
        },
        Ask {
            prompt: "Here is that traversal on this kD-tree, children in file order (the one below the plane first). Which shape does it return?".into(),
            expected: Expected::Choice {
                options,
                correct: stopped_at as usize,
            },
            explanation: format!(
                "File order enters {} and stops in cell {}: the ray's part there, t in [{}, {}], meets {} at t = {}, and the search ends. The closest hit is {} at t = {}, in a cell it never reached{tested_outside}; near first enters {} and returns it.",
                list(&file),
                node_label(facts, stop_cell),
                num(stop_near),
                num(stop_far),
                shape_name(&shapes, stopped_at),
                num(t_stopped),
                shape_name(&shapes, closest),
                num(t_closest),
                list(&near)
            ),
            highlight: Highlight {
                nodes: file.clone(),
                shapes: vec![stopped_at],
                t: Some(t_stopped),
                t_label: format!("file order stops, t = {}", num(t_stopped)),
                frame: Some(file_steps.len()),
                ..Highlight::default()
            },
            frame: 0,
            needs: Vec::new(),
        },
        Ask {
            prompt: "A variant keeps file order but, instead of the `If(no intersection)` rule, searches every side and skips a waiting one only when it starts beyond the closest hit found so far. What does it return here?".into(),
            expected: choice(generator, &CULLED),
            explanation: format!(
                "It returns {} at t = {}: the hit at t = {} ends nothing, and the side still waiting starts before it, so it is searched. It enters {} cells ({}) where near first enters {}: the same hit as near first, found with more work.",
                shape_name(&shapes, closest),
                num(t_closest),
                num(t_stopped),
                culled.len(),
                list(&culled),
                near.len()
            ),
            highlight: Highlight {
                shapes: vec![closest],
                t: Some(t_closest),
                t_label: format!("closest, t = {}", num(t_closest)),
                frame: Some(file_steps.len()),
                ..Highlight::default()
            },
            frame: file_steps.len(),
            needs: Vec::new(),
        },
    ];
    let (fields, scene) = traversal_question(
        shapes,
        ray,
        TreeFigure {
            built,
            order: Order::FileOrder,
            query: Query::FirstInCell,
            steps: file_steps,
            reveal_as_reached: false,
        },
    );
    Some(Draft {
        prompt: "The lecture's quiz, on the kD-tree traversal it follows: why first do the near side, and what happens in file order? Then see it on a scene.".into(),
        figure: Figure::Scene(Box::new(scene)),
        asks,
        fields,
        answer: json!({
            "why_near_first": WHY_NEAR[0],
            "file_order": FILE_ORDER[0],
            "rule": "the far child only if the near child gave no intersection",
            "shape": closest,
            "file_order_returns": stopped_at,
            "near_first_visited": near,
            "file_order_visited": file,
            "culled_file_order": CULLED[0],
            "culled_file_order_visited": culled,
            "file_order_stops": {"cell": stop_cell, "part": [stop_near, stop_far], "t": t_stopped},
        }),
    })
}
