//! The first hit: the lecture's trivial loop answers it (test every shape, keep the
//! closest), here the core's `brute_force`.

use accelviz_core::{NoObserver, Ray, Shape, ShapeSet, TraceOptions, brute_force};
use glam::DVec2;
use serde_json::{Map, json};

use super::{Draft, tolerance};
use crate::generate::{Gen, num, ray_json, ray_numbers, shape_numbers, shapes_json};
use crate::question::{Ask, Choice, Expected, Figure, Highlight, SceneFigure};

/// Where `ray` first meets each shape, by shape number (`None`: it misses).
pub(super) fn hits(shapes: &ShapeSet<DVec2>, ray: &Ray<DVec2>) -> Vec<Option<f64>> {
    shapes
        .shapes
        .iter()
        .map(|shape| shape.intersect(ray, 0.0, f64::INFINITY))
        .collect()
}

/// True when no two shapes are hit at nearly the same `t` and no hit grazes a shape, so a
/// pencil and a ruler can tell the answer.
pub(super) fn clear_hits(shapes: &ShapeSet<DVec2>, ray: &Ray<DVec2>) -> bool {
    let mut ts: Vec<f64> = hits(shapes, ray).into_iter().flatten().collect();
    ts.sort_by(f64::total_cmp);
    let apart = ts.windows(2).all(|pair| pair[1] - pair[0] > 0.05);
    // A ray that only grazes a disc or a box corner is too close to call.
    let grazing = shapes.shapes.iter().any(|shape| {
        let nudged = |offset: DVec2| {
            Ray::try_new(ray.origin + offset, ray.direction)
                .map(|moved| shape.intersect(&moved, 0.0, f64::INFINITY).is_some())
                .unwrap_or(false)
        };
        let side = ray.direction.perp().normalize() * 0.08;
        let here = shape.intersect(ray, 0.0, f64::INFINITY).is_some();
        here != nudged(side) || here != nudged(-side)
    });
    apart && !grazing
}

/// A scene of the level's size and a ray into it whose hits are clear (see [`clear_hits`]),
/// or `None` for a draw to throw away.
pub(super) fn scene_and_ray(generator: &mut Gen) -> Option<(ShapeSet<DVec2>, Ray<DVec2>)> {
    let shapes = generator.shapes(generator.level.shape_count());
    let ray = generator.ray_into(&shapes);
    clear_hits(&shapes, &ray).then_some((shapes, ray))
}

/// A shape's name in a choice: its number and kind.
pub(super) fn shape_name(shapes: &ShapeSet<DVec2>, index: u32) -> String {
    let kind = match shapes.shapes[index as usize] {
        Shape::Sphere(_) => "disc",
        Shape::Box(_) => "box",
        Shape::Segment(_) => "segment",
    };
    format!("shape {index} ({kind})")
}

/// The options "shape 0 (disc)" … and "none".
pub(super) fn shape_options(shapes: &ShapeSet<DVec2>) -> Vec<Choice> {
    let mut options: Vec<Choice> = (0..shapes.shapes.len() as u32)
        .map(|index| Choice {
            label: shape_name(shapes, index),
            node: None,
            shape: Some(index),
        })
        .collect();
    options.push(Choice::text("none: the ray misses every shape"));
    options
}

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let (shapes, ray) = scene_and_ray(generator)?;
    let hit = brute_force(&shapes, &ray, &TraceOptions::default(), &mut NoObserver);
    let options = shape_options(&shapes);
    let none = options.len() - 1;
    let all_hits = hits(&shapes, &ray);
    // The shapes in the order the ray meets them (their t comes with the next step).
    let mut met: Vec<(usize, f64)> = all_hits
        .iter()
        .enumerate()
        .filter_map(|(index, t)| t.map(|t| (index, t)))
        .collect();
    met.sort_by(|a, b| a.1.total_cmp(&b.1));
    let hit_list: Vec<String> = met
        .iter()
        .map(|(index, _)| format!("shape {index}"))
        .collect();
    let listed = if hit_list.is_empty() {
        "The ray meets no shape.".to_owned()
    } else {
        match hit_list.as_slice() {
            [only] => format!("Along the ray it meets {only} only."),
            _ => format!(
                "Along the ray it meets {}, in that order.",
                hit_list.join(", then ")
            ),
        }
    };
    let mut asks = vec![Ask {
        prompt: "Which shape does the ray hit first?".into(),
        expected: Expected::Choice {
            options,
            correct: hit.map_or(none, |hit| hit.primitive as usize),
        },
        explanation: match hit {
            Some(hit) => format!(
                "{listed} The closest, shape {}, is the first hit: testing every shape and keeping the smallest t finds it.",
                hit.primitive
            ),
            None => listed,
        },
        highlight: Highlight {
            shapes: hit.map(|hit| vec![hit.primitive]).unwrap_or_default(),
            t: hit.map(|hit| hit.t),
            // Where, not how far: the next step asks for its t.
            t_label: hit.map_or_else(String::new, |_| "closest".to_owned()),
            ..Highlight::default()
        },
        frame: 0,
        needs: Vec::new(),
    }];
    if let Some(hit) = hit {
        asks.push(Ask {
            prompt: format!("At what t does the ray hit shape {}?", hit.primitive),
            expected: Expected::Number {
                value: hit.t,
                tolerance: tolerance(hit.t),
            },
            explanation: format!(
                "The ray o + t·d enters shape {} at t = {}, the point ({}, {}).",
                hit.primitive,
                num(hit.t),
                num(ray.at(hit.t).x),
                num(ray.at(hit.t).y)
            ),
            highlight: Highlight {
                shapes: vec![hit.primitive],
                t: Some(hit.t),
                t_label: format!("shape {}, t = {}", hit.primitive, num(hit.t)),
                ..Highlight::default()
            },
            frame: 0,
            needs: [
                ray_numbers(&ray),
                shape_numbers(&shapes.shapes[hit.primitive as usize]),
            ]
            .concat(),
        });
    }
    let mut fields = Map::new();
    fields.insert("shapes".into(), shapes_json(&shapes));
    fields.insert(
        "ray".into(),
        ray_json(&ray.origin.to_array(), &ray.direction.to_array()),
    );
    let mut figure = SceneFigure::of(shapes);
    figure.ray = Some(ray);
    Some(Draft {
        prompt: "A ray crosses a scene of shapes. Which does it hit first?".into(),
        figure: Figure::Scene(Box::new(figure)),
        asks,
        fields,
        answer: json!({
            "shape": hit.map(|hit| hit.primitive),
            "t": hit.map(|hit| hit.t),
        }),
    })
}
