//! Does the ray slip through? Two triangles share an edge, as in any closed mesh; a ray is
//! aimed at a point of that edge, and one of the two ray/triangle tests, in f32 or f64,
//! answers for each triangle. The core's own test decides, and the figure lists what it
//! computed: Möller–Trumbore's barycentric coordinates, which rounding can push just outside
//! both triangles (a crack: the ray slips through), or the watertight test's edge functions
//! (Woop, Benthin & Wald 2013), which two triangles sharing an edge compute alike, so one of
//! them always has the point.

use accelviz_core::{
    HitTest, NoObserver, PrimitiveSet, Ray, TraceOptions, TriangleSet, Vector3, brute_force,
};
use glam::{DVec2, DVec3, Vec3};
use serde_json::{Map, json};

use super::{Draft, yes_no};
use crate::generate::{Gen, Level, num};
use crate::question::{Ask, CrackFigure, Expected, Figure, Highlight};

/// What one draw made: the triangles and the ray in the tested precision, widened to f64.
struct Case {
    corners: [[[f64; 3]; 3]; 2],
    origin: [f64; 3],
    direction: [f64; 3],
    hit: Option<u32>,
    computed: [[Option<f64>; 3]; 2],
}

/// A square of jittered corners split along its diagonal a–c into A = (a, b, c) and
/// B = (a, c, d), both facing up; a ray from above aimed at a random point of the diagonal.
/// Everything is rounded to `V`'s precision before the test sees it.
fn draw<V: Vector3>(generator: &mut Gen, test: HitTest) -> Option<Case> {
    let mut jittered = |x: f64, y: f64| {
        [
            x + 0.4 * generator.uniform() - 0.2,
            y + 0.4 * generator.uniform() - 0.2,
            0.2 * generator.uniform(),
        ]
    };
    let [a, b, c, d] = [
        jittered(-1.0, -1.0),
        jittered(1.0, -1.0),
        jittered(1.0, 1.0),
        jittered(-1.0, 1.0),
    ];
    let triangles = TriangleSet::<V>::from_f64(&[[a, b, c], [a, c, d]]);
    let along = 0.15 + 0.7 * generator.uniform();
    let target = DVec3::from_array(a).lerp(DVec3::from_array(c), along);
    let origin = DVec3::new(
        generator.uniform() - 0.5,
        generator.uniform() - 0.5,
        3.0 + generator.uniform(),
    );
    let ray = Ray::try_new(
        V::from_f64_slice(&origin.to_array()),
        V::from_f64_slice(&(target - origin).to_array()),
    )
    .ok()?;
    let options = TraceOptions {
        hit_test: test,
        ..TraceOptions::default()
    };
    let hit = brute_force(&triangles, &ray, &options, &mut NoObserver).map(|hit| hit.primitive);
    let prepared = triangles.prepare(&ray, test);
    let computed = [0, 1].map(|index| {
        let values = triangles.explain(
            &prepared,
            index,
            ray.t_min,
            accelviz_core::Real::from_f64(f64::INFINITY),
        );
        let wide = values
            .coordinates
            .map(|value| value.map(accelviz_core::Real::to_f64));
        match test {
            // u, v and 1 − (u + v): the last from the sum the test compared with 1.
            HitTest::Fast => [wide[0], wide[1], wide[2].map(|sum| 1.0 - sum)],
            HitTest::Watertight => wide,
        }
    });
    let widen = |corner: &V| corner.to_f64_array();
    let stored = triangles.triangles();
    Some(Case {
        corners: [
            stored[0].each_ref().map(widen),
            stored[1].each_ref().map(widen),
        ],
        origin: ray.origin.to_f64_array(),
        direction: ray.direction.to_f64_array(),
        hit,
        computed,
    })
}

/// The triangles seen along the ray: each corner's place in a plane across it, the ray (a
/// point, seen along itself) at the middle of the figure's world ([0, 20]²), scaled to fill
/// it.
fn seen(case: &Case) -> ([[DVec2; 3]; 2], DVec2) {
    let direction = DVec3::from_array(case.direction).normalize();
    let (across, up) = direction.any_orthonormal_pair();
    let origin = DVec3::from_array(case.origin);
    let project = |point: [f64; 3]| {
        let relative = DVec3::from_array(point) - origin;
        DVec2::new(relative.dot(across), relative.dot(up))
    };
    let flat = case.corners.map(|triangle| triangle.map(project));
    let extent = flat.iter().flatten().fold(0.0f64, |widest, point| {
        widest.max(point.abs().max_element())
    });
    let scale = 9.0 / extent.max(f64::MIN_POSITIVE);
    let centre = DVec2::splat(10.0);
    (
        flat.map(|triangle| triangle.map(|point| centre + point * scale)),
        centre,
    )
}

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let test = if generator.index(2) == 0 {
        HitTest::Fast
    } else {
        HitTest::Watertight
    };
    // Harder levels ask in f64 too, where the fast test leaks as well.
    let in_f64 = generator.level == Level::Hard && generator.index(2) == 0;
    // The fast test slips through some rays only: ask about as often when it does as when it
    // does not.
    let want_leak = test == HitTest::Fast && generator.index(2) == 0;
    let case = if in_f64 {
        draw::<DVec3>(generator, test)?
    } else {
        draw::<Vec3>(generator, test)?
    };
    if test == HitTest::Fast && case.hit.is_none() != want_leak {
        return None;
    }
    let precision = if in_f64 { "f64" } else { "f32" };
    let (seen, ray_at) = seen(&case);
    let figure = CrackFigure {
        seen,
        ray_at,
        corners: case.corners,
        origin: case.origin,
        direction: case.direction,
        precision,
        test,
        computed: case.computed,
    };
    let names = figure.value_names();
    let hit = case.hit.is_some();
    let said = |index: usize| {
        let written: Vec<String> = names
            .iter()
            .zip(&case.computed[index])
            .filter_map(|(name, value)| value.map(|value| format!("{name} = {}", num(value))))
            .collect();
        written.join(", ")
    };
    let why = match (test, case.hit) {
        (HitTest::Fast, None) => format!(
            "No: the ray slips through. A hit needs u, v and w all ≥ 0, and rounding put the point just outside both triangles: A has {}, B has {}. The exact point lies on the edge they share, so a closed mesh leaks here: a crack.",
            said(0),
            said(1)
        ),
        (HitTest::Fast, Some(triangle)) => format!(
            "Yes: {} has u, v and w all ≥ 0 ({}). Rounding could have put the point outside both triangles, but here it did not.",
            ["A", "B"][triangle as usize],
            said(triangle as usize)
        ),
        (HitTest::Watertight, Some(triangle)) => format!(
            "Yes: {}'s edge functions have no opposite signs ({}). The two triangles compute the function of their shared edge alike (one with the other's sign), so a point on that edge is inside one of them: the watertight test never slips through.",
            ["A", "B"][triangle as usize],
            said(triangle as usize)
        ),
        (HitTest::Watertight, None) => {
            // The watertight test does not leak through a shared edge: this draw teaches the
            // wrong thing (it should not happen).
            return None;
        }
    };
    let test_name = match test {
        HitTest::Fast => "the fast test (Möller–Trumbore)",
        HitTest::Watertight => "the watertight test",
    };
    let asks = vec![Ask {
        prompt: format!(
            "The ray is aimed at a point of the edge A and B share. Does {test_name} in {precision} report a hit on A or B?"
        ),
        expected: Expected::Choice {
            options: yes_no(),
            correct: usize::from(!hit),
        },
        explanation: why,
        highlight: Highlight {
            shapes: case.hit.map(|triangle| vec![triangle]).unwrap_or_default(),
            ..Highlight::default()
        },
        frame: 0,
        needs: case.computed.iter().flatten().flatten().copied().collect(),
    }];
    let mut fields = Map::new();
    fields.insert("triangles".into(), json!(case.corners));
    fields.insert(
        "ray".into(),
        json!({"origin": case.origin, "direction": case.direction}),
    );
    fields.insert("precision".into(), json!(precision));
    fields.insert(
        "test".into(),
        json!(match test {
            HitTest::Fast => "fast",
            HitTest::Watertight => "watertight",
        }),
    );
    Some(Draft {
        prompt: format!(
            "Two triangles, A and B, share an edge, as every two neighbours of a closed mesh do. A ray comes from above, aimed exactly at a point of that edge, and is tested against both in {precision} by {test_name}; below, what the test computed for each."
        ),
        figure: Figure::Crack(Box::new(figure)),
        asks,
        fields,
        answer: json!({ "hit": hit }),
    })
}
