//! A tree in another precision: built in f32 (as a trade row builds it), widened to f64 node
//! for node for a view that works in f64, and narrowed back exactly; and a traversal in f32
//! told to an f64 observer, step for step.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_core::params::BuildParams;
use accelviz_core::{
    Built, CATALOGUE, NoBuildObserver, Ray, Recorder, Step, TraceOptions, TraversalStacks,
    TriangleSet, Width, observer::Widened,
};
use glam::{DVec3, Vec3};

/// A lumpy closed surface: a grid of bumps on a sphere.
fn triangles() -> Vec<[[f64; 3]; 3]> {
    let point = |u: usize, v: usize| {
        let (theta, phi) = (
            u as f64 / 12.0 * std::f64::consts::TAU,
            v as f64 / 8.0 * std::f64::consts::PI,
        );
        let radius = 1.0 + 0.1 * ((3.0 * theta).sin() * (2.0 * phi).cos());
        [
            radius * phi.sin() * theta.cos() + 0.3,
            radius * phi.sin() * theta.sin(),
            radius * phi.cos() - 0.7,
        ]
    };
    let mut out = Vec::new();
    for u in 0..12 {
        for v in 0..8 {
            out.push([point(u, v), point(u + 1, v), point(u, v + 1)]);
            out.push([point(u + 1, v), point(u + 1, v + 1), point(u, v + 1)]);
        }
    }
    out
}

#[test]
fn a_tree_built_in_f32_widens_to_f64_and_narrows_back_exactly() {
    let mesh = triangles();
    let in_f32 = TriangleSet::<Vec3>::from_f64(&mesh);
    let wide = [Width::Four, Width::Eight].map(|width| CATALOGUE[3].structure.with_width(width));
    let structures = CATALOGUE.iter().map(|entry| entry.structure).chain(wide);
    let rays: Vec<Ray<Vec3>> = (0..40)
        .map(|index| {
            let angle = index as f32 * 0.37;
            let origin = Vec3::new(
                4.0 * angle.cos(),
                3.0 * angle.sin(),
                2.5 - 0.1 * index as f32,
            );
            Ray::try_new(origin, Vec3::new(0.3, 0.0, -0.7) - origin).unwrap()
        })
        .collect();
    for structure in structures {
        let built = Built::new(
            structure,
            &in_f32,
            &BuildParams::default(),
            &mut NoBuildObserver,
        );
        let widened: Built<DVec3> = built.converted();
        let name = structure.name();
        // Node for node: the same facts, and the same tree once narrowed back.
        assert_eq!(widened.facts.children, built.facts.children, "{name}");
        assert_eq!(
            widened.facts.leaf_reasons, built.facts.leaf_reasons,
            "{name}"
        );
        assert_eq!(widened.tree.converted::<Vec3>(), built.tree, "{name}");
        // Valid where it was built (in f32 a perfect split's clipping decides at a cell's
        // edge, which an f64 check would decide again otherwise).
        structure
            .validate(&built.tree, &in_f32)
            .unwrap_or_else(|error| {
                panic!("{name}: {error}");
            });
        // The f32 traversal heard in f64: every step, its numbers widened exactly.
        let options = TraceOptions::default();
        let mut stacks = TraversalStacks::default();
        for ray in &rays {
            let mut in_its_own = Recorder::<f32>::default();
            let hit = built
                .tree
                .trace(&in_f32, ray, &options, &mut stacks, &mut in_its_own);
            let mut heard = Recorder::<f64>::default();
            let again = built.tree.trace(
                &in_f32,
                ray,
                &options,
                &mut stacks,
                &mut Widened(&mut heard),
            );
            assert_eq!(hit, again, "{name}");
            assert_eq!(heard.steps.len(), in_its_own.steps.len(), "{name}");
            for (wide, own) in heard.steps.iter().zip(&in_its_own.steps) {
                if let (
                    Step::ClosestHitUpdated { primitive, t },
                    Step::ClosestHitUpdated {
                        primitive: own_primitive,
                        t: own_t,
                    },
                ) = (wide, own)
                {
                    assert_eq!((*primitive, *t), (*own_primitive, f64::from(*own_t)));
                }
                let kind = |step: String| step.split([' ', '{']).next().unwrap().to_owned();
                assert_eq!(
                    kind(format!("{wide:?}")),
                    kind(format!("{own:?}")),
                    "{name}"
                );
            }
        }
    }
}
