//! Does the ray slip through? Two triangles share an edge, as in any closed mesh; a ray is
//! aimed at a point of that edge, and one of the two ray/triangle tests, in f32 or f64,
//! answers for each triangle. The core's own test decides, and the figure lists what it
//! computed: Möller–Trumbore's barycentric coordinates, which rounding can push just outside
//! both triangles (a crack: the ray slips through), or the watertight test's edge functions
//! (Woop, Benthin & Wald 2013), which two triangles sharing an edge compute alike, so one of
//! them always has the point.

use accelviz_core::crack::SharedEdge;
use accelviz_core::{HitTest, Vector3};
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

/// The core's case of a ray aimed at a shared edge ([`SharedEdge`]), tested in `V`'s
/// precision.
fn draw<V: Vector3>(generator: &mut Gen, test: HitTest) -> Option<Case> {
    let tested = SharedEdge::draw(|| generator.uniform()).test::<V>(test)?;
    let computed = tested.values.map(|values| match test {
        // u, v and 1 − (u + v): the last from the sum the test compared with 1.
        HitTest::Fast => [
            values.coordinates[0],
            values.coordinates[1],
            values.coordinates[2].map(|sum| 1.0 - sum),
        ],
        HitTest::Watertight => values.coordinates,
    });
    Some(Case {
        corners: tested
            .corners
            .map(|triangle| triangle.map(|corner| corner.to_array())),
        origin: tested.origin.to_array(),
        direction: tested.direction.to_array(),
        hit: tested.hit.map(|hit| hit.primitive),
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
    fields.insert("test".into(), json!(test.name()));
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
