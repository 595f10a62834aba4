//! Choosing a BVH split (the lecture's "Splitting with cost in mind"): among candidate
//! positions on one axis, which does the surface area heuristic (Goldsmith & Salmon 1987;
//! MacDonald & Booth 1990) choose, which do the middle and median rules choose, and what does
//! one cost? The candidates and their costs are the core's cost curve, made by the sweep
//! builder's own code.

use accelviz_core::SahCost;
use accelviz_core::curve::{Candidate, bvh_curve};
use serde_json::{Map, json};

use super::{Draft, tolerance};
use crate::generate::{AXES, Gen, box_json, num, shapes_json};
use crate::question::{Ask, Choice, Expected, Figure, Highlight, SceneFigure, option_letter};

/// The most candidates offered.
const MOST_CANDIDATES: usize = 5;

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let shapes = generator.shapes(generator.level.shape_count());
    let cost = SahCost {
        traversal_cost: [1.0, 2.0, 3.0][generator.index(3)],
        intersection_cost: 1.0,
        ..SahCost::default()
    };
    let boxes: Vec<_> = shapes.shapes.iter().map(|shape| shape.bounds()).collect();
    let node_shapes: Vec<u32> = (0..shapes.shapes.len() as u32).collect();
    let curve = bvh_curve(&boxes, &node_shapes, &cost, None);
    let (middle, median) = (curve.middle?, curve.median?);
    let axis = middle.axis;
    let centres: Vec<f64> = boxes.iter().map(|bounds| bounds.center()[axis]).collect();
    // A candidate is offered only where "a shape goes left when its box centre is below the
    // position" gives the split the curve costed (no two centres at the same place).
    let fits = |candidate: &Candidate| {
        centres
            .iter()
            .filter(|centre| **centre < candidate.position)
            .count()
            == candidate.count_left
    };
    let along: Vec<Candidate> = curve.axes[axis].iter().copied().filter(fits).collect();
    let cheapest = (0..along.len()).min_by(|a, b| along[*a].cost.total_cmp(&along[*b].cost))?;
    // The rules' cuts must be offered as the rule makes them; two centres in one place make
    // the median ambiguous under the "below the position" rule, so such a draw is left out.
    let median_at = along.iter().position(|c| c.position == median.position)?;
    let middle_left = centres.iter().filter(|c| **c < middle.position).count();
    let middle_at = along.iter().position(|c| c.count_left == middle_left)?;
    let mut chosen = vec![cheapest, middle_at, median_at];
    let mut others: Vec<usize> = (0..along.len()).filter(|i| !chosen.contains(i)).collect();
    generator.shuffle(&mut others);
    chosen.extend(others);
    chosen.dedup();
    let mut picked: Vec<usize> = Vec::new();
    for index in chosen {
        if !picked.contains(&index) && picked.len() < MOST_CANDIDATES {
            picked.push(index);
        }
    }
    picked.sort_unstable_by(|a, b| along[*a].position.total_cmp(&along[*b].position));
    let mut candidates: Vec<Candidate> = picked.iter().map(|index| along[*index]).collect();
    // The middle rule cuts at the middle of the centroids' extent, not between two centres.
    let middle_index = picked.iter().position(|index| *index == middle_at)?;
    candidates[middle_index].position = middle.position;
    let median_index = picked.iter().position(|index| *index == median_at)?;
    let best = picked.iter().position(|index| *index == cheapest)?;
    if candidates.len() < 3
        || candidates
            .iter()
            .enumerate()
            .any(|(index, c)| index != best && c.cost - candidates[best].cost < 0.05)
        || !candidates.iter().all(fits)
    {
        return None;
    }
    let costs: Vec<f64> = candidates.iter().map(|c| c.cost).collect();
    let options: Vec<Choice> = candidates
        .iter()
        .map(|c| {
            Choice::text(format!(
                "{} = {} ({} left, {} right)",
                AXES[axis],
                num(c.position),
                c.count_left,
                c.count_right
            ))
        })
        .collect();
    let asked = (best + 1 + generator.index(candidates.len() - 1)) % candidates.len();
    let parts = |c: &Candidate| {
        format!(
            "{} + ({}/{} · {} + {}/{} · {}) · {} = {}",
            num(cost.traversal_cost),
            num(c.area_left),
            num(curve.area),
            c.count_left,
            num(c.area_right),
            num(curve.area),
            c.count_right,
            num(cost.intersection_cost),
            num(c.cost)
        )
    };
    let table: Vec<String> = candidates
        .iter()
        .enumerate()
        .map(|(index, c)| format!("({}) {}", option_letter(index), num(c.cost)))
        .collect();
    let node_box = accelviz_core::Aabb::new(
        glam::DVec2::new(curve.bounds[0][0], curve.bounds[1][0]),
        glam::DVec2::new(curve.bounds[0][1], curve.bounds[1][1]),
    );
    // The cost first: the choice's explanation lists every candidate's.
    let asks = vec![
        Ask {
            prompt: format!(
                "What is the SAH cost of split ({})? (C_trav = {}, C_isect = {}; a side's probability is its box's perimeter over the node's.)",
                option_letter(asked),
                num(cost.traversal_cost),
                num(cost.intersection_cost)
            ),
            expected: Expected::Number {
                value: candidates[asked].cost,
                tolerance: tolerance(candidates[asked].cost),
            },
            explanation: format!(
                "cost = C_trav + (P_L · N_L + P_R · N_R) · C_isect = {}.",
                parts(&candidates[asked])
            ),
            highlight: Highlight {
                candidate: Some(asked),
                ..Highlight::default()
            },
            frame: 0,
            needs: vec![
                cost.traversal_cost,
                cost.intersection_cost,
                candidates[asked].area_left,
                candidates[asked].area_right,
                curve.area,
                candidates[asked].count_left as f64,
                candidates[asked].count_right as f64,
            ],
        },
        Ask {
            prompt: "Which candidate split does the SAH builder choose?".into(),
            expected: Expected::Choice {
                options: options.clone(),
                correct: best,
            },
            explanation: format!(
                "SAH takes the cheapest. The costs are {}. The cheapest, ({}), costs {}.",
                table.join(", "),
                option_letter(best),
                parts(&candidates[best])
            ),
            highlight: Highlight {
                candidate: Some(best),
                ..Highlight::default()
            },
            frame: 0,
            needs: Vec::new(),
        },
        Ask {
            prompt: "Which split does the middle rule choose?".into(),
            expected: Expected::Choice {
                options: options.clone(),
                correct: middle_index,
            },
            explanation: format!(
                "The middle rule cuts the longest axis of the shapes' centres in half: {} = {}, wherever the shapes are.",
                AXES[axis],
                num(middle.position)
            ),
            highlight: Highlight {
                candidate: Some(middle_index),
                ..Highlight::default()
            },
            frame: 0,
            needs: Vec::new(),
        },
        Ask {
            // With an odd count two splits are "half and half": say which one the rule takes.
            prompt: if curve.count % 2 == 1 {
                format!(
                    "Which split does the median rule choose? ({} shapes: the left side takes {}, the extra one goes right.)",
                    curve.count,
                    curve.count / 2
                )
            } else {
                "Which split does the median rule choose?".into()
            },
            expected: Expected::Choice {
                options,
                correct: median_index,
            },
            explanation: format!(
                "The median rule puts half the shapes on each side ({} of {} on the left), whatever the sizes of the two boxes.",
                candidates[median_index].count_left, curve.count
            ),
            highlight: Highlight {
                candidate: Some(median_index),
                ..Highlight::default()
            },
            frame: 0,
            needs: Vec::new(),
        },
    ];
    let mut fields = Map::new();
    fields.insert("shapes".into(), shapes_json(&shapes));
    fields.insert("node_box".into(), box_json(&node_box));
    fields.insert("node_shapes".into(), json!(node_shapes));
    fields.insert("axis".into(), json!(axis));
    fields.insert(
        "cost".into(),
        json!({"c_trav": cost.traversal_cost, "c_isect": cost.intersection_cost}),
    );
    fields.insert(
        "candidates".into(),
        json!(candidates.iter().map(|c| c.position).collect::<Vec<_>>()),
    );
    let mut scene = SceneFigure::of(shapes);
    scene.node = Some((node_box, node_shapes));
    let scene = scene.with_candidates(candidates.iter().map(|c| (axis, c.position)).collect());
    Some(Draft {
        prompt: format!(
            "Split this BVH node along {}: a shape goes left when its box's centre is below the split. Each side's box bounds its shapes.",
            AXES[axis]
        ),
        figure: Figure::Scene(Box::new(scene)),
        asks,
        fields,
        answer: json!({
            "best": best,
            "costs": costs,
            "middle": middle_index,
            "median": median_index,
        }),
    })
}
