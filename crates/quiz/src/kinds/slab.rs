//! The slab test (Kay & Kajiya 1986): does the ray hit the box, which axis's slab is entered
//! last (it gives t_enter), and where. Answers from the core's `slab_record`, the record the
//! slab-test lessons and `accelviz-cli slab` show.

use accelviz_core::{Aabb, Ray, Real, Vector, slab_record};
use glam::{DVec2, DVec3};
use serde_json::{Map, json};

use super::{Draft, tolerance, yes_no};
use crate::generate::{AXES, Gen, Level, num, ray_json};
use crate::question::{Ask, Choice, Expected, Figure, Highlight};

/// What the slab test finds, per axis and in all.
struct Slabs {
    t_near: Vec<f64>,
    t_far: Vec<f64>,
    t_enter: f64,
    t_exit: f64,
    hit: bool,
}

fn slabs<V: Vector>(min: &[f64], max: &[f64], origin: &[f64], direction: &[f64]) -> Option<Slabs> {
    let bounds = Aabb::new(V::from_f64_slice(min), V::from_f64_slice(max));
    let ray = Ray::try_new(V::from_f64_slice(origin), V::from_f64_slice(direction)).ok()?;
    let record = slab_record(&bounds, &ray, false);
    let dimensions = min.len();
    let per_axis = |vector: V| vector.to_f64_array()[..dimensions].to_vec();
    Some(Slabs {
        t_near: per_axis(record.t_near),
        t_far: per_axis(record.t_far),
        t_enter: record.t_enter.to_f64(),
        t_exit: record.t_exit.to_f64(),
        hit: record.hit,
    })
}

/// A number to subtract or divide by: in parentheses when negative, `(−2)`.
fn signed(value: f64) -> String {
    if value < 0.0 {
        format!("({})", num(value))
    } else {
        num(value)
    }
}

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let dimensions = if generator.level == Level::Hard { 3 } else { 2 };
    let mut min = Vec::new();
    let mut max = Vec::new();
    let mut origin = Vec::new();
    let mut direction = Vec::new();
    for _ in 0..dimensions {
        let low = generator.integer(-4, 3) as f64;
        let size = generator.coordinate(1.0, 5.0).max(1.0);
        min.push(low);
        max.push(generator.round(low + size));
        // A target in or near the box, so that some rays hit and some miss.
        let target = generator.coordinate(low - 1.5, low + size + 1.5);
        let start = generator.integer(-9, 9) as f64;
        origin.push(start);
        direction.push(generator.round((target - start) / 2.0));
    }
    if direction.contains(&0.0) {
        return None;
    }
    let inside = (0..dimensions).all(|axis| min[axis] <= origin[axis] && origin[axis] <= max[axis]);
    let slabs = if dimensions == 2 {
        slabs::<DVec2>(&min, &max, &origin, &direction)?
    } else {
        slabs::<DVec3>(&min, &max, &origin, &direction)?
    };
    // Teach with clear cases: no origin inside the box, no entry behind the origin, a clear
    // winner among the slabs, and no near miss that rounding could turn into a hit.
    let mut sorted = slabs.t_near.clone();
    sorted.sort_by(f64::total_cmp);
    let clear_winner = sorted[dimensions - 1] - sorted[dimensions - 2] > 0.1;
    // And t_exit is not one of the t_near values t_enter's explanation lists (it would read as
    // given away).
    let exit_listed = slabs.t_near.iter().any(|t| num(*t) == num(slabs.t_exit));
    if inside
        || slabs.t_enter < 0.0
        || !clear_winner
        || (slabs.t_exit - slabs.t_enter).abs() < 0.1
        || exit_listed
    {
        return None;
    }
    let enter_axis = (0..dimensions)
        .max_by(|a, b| slabs.t_near[*a].total_cmp(&slabs.t_near[*b]))
        .unwrap_or(0);
    let exit_axis = (0..dimensions)
        .min_by(|a, b| slabs.t_far[*a].total_cmp(&slabs.t_far[*b]))
        .unwrap_or(0);

    let intervals: Vec<String> = (0..dimensions)
        .map(|axis| {
            format!(
                "{name}: t = ({lo} − {o}) / {d} = {a} and ({hi} − {o}) / {d} = {b}, so [{near}, {far}]",
                name = AXES[axis],
                lo = num(min[axis]),
                hi = num(max[axis]),
                o = signed(origin[axis]),
                d = signed(direction[axis]),
                a = num((min[axis] - origin[axis]) / direction[axis]),
                b = num((max[axis] - origin[axis]) / direction[axis]),
                near = num(slabs.t_near[axis]),
                far = num(slabs.t_far[axis]),
            )
        })
        .collect();
    let intervals = intervals.join("; ");
    let near_steps: Vec<String> = (0..dimensions)
        .map(|axis| format!("{}: t_near = {}", AXES[axis], num(slabs.t_near[axis])))
        .collect();
    let near_steps = near_steps.join(", ");
    let verdict = if slabs.hit {
        format!(
            "t_enter = {} ≤ t_exit = {}: the ray is inside every slab at once between them, so it hits the box.",
            num(slabs.t_enter),
            num(slabs.t_exit)
        )
    } else {
        format!(
            "t_enter = {} > t_exit = {}: the ray leaves the {} slab before it has entered the {} slab, so it misses.",
            num(slabs.t_enter),
            num(slabs.t_exit),
            AXES[exit_axis],
            AXES[enter_axis]
        )
    };
    let axis_options: Vec<Choice> = AXES[..dimensions]
        .iter()
        .map(|name| Choice::text(*name))
        .collect();
    // What the intervals are worked out from: the box and the ray.
    let needs: Vec<f64> = [&min, &max, &origin, &direction]
        .into_iter()
        .flatten()
        .copied()
        .collect();
    // In this order each explanation gives away no later step's answer: the axis (in words),
    // then t_enter (with every t_near), t_exit (with every t_far), and the verdict.
    let asks = vec![
        Ask {
            prompt: "Which axis's slab does the ray enter last (the one whose t_near is t_enter)?"
                .into(),
            expected: Expected::Choice {
                options: axis_options,
                correct: enter_axis,
            },
            explanation: format!(
                "The ray is inside the box only once it is inside every slab: t_enter is the largest t_near, here the {} slab's (its planes are crossed last on the way in).",
                AXES[enter_axis]
            ),
            highlight: Highlight {
                axis: Some(enter_axis),
                ..Highlight::default()
            },
            frame: 0,
            needs: Vec::new(),
        },
        Ask {
            prompt: "What is t_enter?".into(),
            expected: Expected::Number {
                value: slabs.t_enter,
                tolerance: tolerance(slabs.t_enter),
            },
            explanation: format!(
                "Per axis t = (plane − origin) / direction: {near_steps}. t_enter = max of t_near = {}.",
                num(slabs.t_enter)
            ),
            highlight: Highlight {
                axis: Some(enter_axis),
                t: Some(slabs.t_enter),
                t_label: format!("t_enter = {}", num(slabs.t_enter)),
                marks: slabs.t_near.clone(),
                ..Highlight::default()
            },
            frame: 0,
            needs: needs.clone(),
        },
        Ask {
            prompt: "What is t_exit?".into(),
            expected: Expected::Number {
                value: slabs.t_exit,
                tolerance: tolerance(slabs.t_exit),
            },
            explanation: format!(
                "t_exit = min of t_far = min({}) = {}, on the {} axis.",
                slabs
                    .t_far
                    .iter()
                    .map(|t| num(*t))
                    .collect::<Vec<_>>()
                    .join(", "),
                num(slabs.t_exit),
                AXES[exit_axis]
            ),
            highlight: Highlight {
                axis: Some(exit_axis),
                t: Some(slabs.t_exit),
                t_label: format!("t_exit = {}", num(slabs.t_exit)),
                marks: slabs.t_near.iter().chain(&slabs.t_far).copied().collect(),
                ..Highlight::default()
            },
            frame: 0,
            needs: needs.clone(),
        },
        Ask {
            prompt: "Does the ray hit the box?".into(),
            expected: Expected::Choice {
                options: yes_no(),
                correct: if slabs.hit { 0 } else { 1 },
            },
            explanation: format!(
                "Per axis, the ray is between the two planes for t in [t_near, t_far]: {intervals}. {verdict}"
            ),
            highlight: Highlight {
                t: Some(slabs.t_enter),
                t_label: format!("t_enter = {}", num(slabs.t_enter)),
                marks: slabs.t_near.iter().chain(&slabs.t_far).copied().collect(),
                intervals: true,
                ..Highlight::default()
            },
            frame: 0,
            needs: Vec::new(),
        },
    ];
    let mut fields = Map::new();
    let corners: Vec<f64> = min.iter().chain(&max).copied().collect();
    fields.insert("box".into(), json!(corners));
    fields.insert("ray".into(), ray_json(&origin, &direction));
    Some(Draft {
        prompt: format!(
            "A ray and an axis-aligned box in {dimensions}D. Work through the slab test: per axis, where the ray crosses the box's two planes."
        ),
        figure: Figure::Slab {
            min,
            max,
            origin,
            direction,
        },
        asks,
        fields,
        answer: json!({
            "hit": slabs.hit,
            "t_enter": slabs.t_enter,
            "t_exit": slabs.t_exit,
            "enter_axis": enter_axis,
        }),
    })
}
