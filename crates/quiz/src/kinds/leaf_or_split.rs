//! Leaf or split? The SAH builder keeps a node a leaf when no split costs less than testing
//! its shapes (`N · C_isect`). The answer is what the core's sweep builder does with this
//! node; the costs are its cost curve.

use accelviz_core::curve::bvh_curve;
use accelviz_core::params::BuildParams;
use accelviz_core::{Built, NoBuildObserver, SahCost, Structure, Width};
use serde_json::{Map, json};

use super::{Draft, tolerance, yes_no};
use crate::generate::{AXES, Gen, Level, box_json, num, shape_numbers, shapes_json};
use crate::question::{Ask, Expected, Figure, Highlight, SceneFigure};

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let count = match generator.level {
        Level::Easy => 2 + generator.index(2),
        Level::Medium => 3 + generator.index(3),
        Level::Hard => 4 + generator.index(5),
    };
    let shapes = generator.shapes(count);
    // A shape's test costs other than 1, so the leaf's cost is worked out, not read off the
    // shape count.
    let cost = SahCost {
        traversal_cost: [0.5, 1.0, 2.0, 3.0][generator.index(4)],
        intersection_cost: [0.5, 1.5, 2.0][generator.index(3)],
        ..SahCost::default()
    };
    let boxes: Vec<_> = shapes.shapes.iter().map(|shape| shape.bounds()).collect();
    let node_shapes: Vec<u32> = (0..shapes.shapes.len() as u32).collect();
    let curve = bvh_curve(&boxes, &node_shapes, &cost, None);
    let best = curve.best?;
    // A near tie between leaf and split is for the builder's rounding, not for a student.
    if (best.cost - curve.leaf_cost).abs() < 0.05 {
        return None;
    }
    let params = BuildParams {
        max_leaf_size: count,
        cost,
        ..BuildParams::default()
    };
    let built = Built::new(
        Structure::BvhSahSweep {
            width: Width::Binary,
        },
        &shapes,
        &params,
        &mut NoBuildObserver,
    );
    let leaf = built.facts.is_leaf(0);
    let node_box = built.root_bounds();
    let verdict = if leaf {
        format!(
            "The leaf costs {} and the best split {}: splitting would cost more, so the builder keeps a leaf.",
            num(curve.leaf_cost),
            num(best.cost)
        )
    } else {
        format!(
            "The best split costs {}, less than the leaf's {}: the builder splits at {} = {}.",
            num(best.cost),
            num(curve.leaf_cost),
            AXES[best.axis],
            num(best.position)
        )
    };
    let asks = vec![
        Ask {
            prompt: format!(
                "What does keeping this node a leaf cost? (C_isect = {})",
                num(cost.intersection_cost)
            ),
            expected: Expected::Number {
                value: curve.leaf_cost,
                tolerance: tolerance(curve.leaf_cost),
            },
            explanation: format!(
                "A leaf tests every shape: N · C_isect = {} · {} = {}.",
                count,
                num(cost.intersection_cost),
                num(curve.leaf_cost)
            ),
            highlight: Highlight::default(),
            frame: 0,
            needs: vec![count as f64, cost.intersection_cost],
        },
        Ask {
            prompt: format!(
                "What does the cheapest split cost? (C_trav = {}; try every axis)",
                num(cost.traversal_cost)
            ),
            expected: Expected::Number {
                value: best.cost,
                tolerance: tolerance(best.cost),
            },
            explanation: format!(
                "The cheapest of every split on every axis is at {} = {}: C_trav + (P_L · N_L + P_R · N_R) · C_isect = {}.",
                AXES[best.axis],
                num(best.position),
                num(best.cost)
            ),
            highlight: Highlight {
                candidate: Some(0),
                ..Highlight::default()
            },
            frame: 0,
            needs: [cost.traversal_cost, cost.intersection_cost]
                .into_iter()
                .chain(shapes.shapes.iter().flat_map(shape_numbers))
                .collect(),
        },
        Ask {
            prompt: "Does the SAH builder keep this node a leaf?".into(),
            expected: Expected::Choice {
                options: yes_no(),
                correct: if leaf { 0 } else { 1 },
            },
            explanation: verdict,
            highlight: Highlight {
                candidate: Some(0),
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
    fields.insert(
        "cost".into(),
        json!({"c_trav": cost.traversal_cost, "c_isect": cost.intersection_cost}),
    );
    let mut scene = SceneFigure::of(shapes);
    scene.node = Some((node_box, node_shapes));
    let mut scene = scene.with_candidates(vec![(best.axis, best.position)]);
    scene.candidates_before_answer = false;
    Some(Draft {
        prompt: format!(
            "A BVH node holds {count} shapes. Will the SAH builder split it, or keep it a leaf?"
        ),
        figure: Figure::Scene(Box::new(scene)),
        asks,
        fields,
        answer: json!({
            "leaf": leaf,
            "leaf_cost": curve.leaf_cost,
            "best_split_cost": best.cost,
            "best_split": {"axis": best.axis, "position": best.position},
        }),
    })
}
