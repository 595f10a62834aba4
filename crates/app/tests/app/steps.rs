//! What each animated lesson shows at step k is the core's state at step k: the lesson's
//! recording is the core's (an independent build and traversal gives the same steps), its
//! counters and closest hit at every frame are the core's replay of that prefix, the words on
//! screen say the same, and in the kD lesson the canvas, the code line and the status line
//! describe the same step.

use crate::common;

use common::{lesson_harness, lesson_text};

use accelviz_app::lesson::Lesson;
use accelviz_app::lessons::build_steps::{BuildStepsLesson, Way};
use accelviz_app::lessons::bvh::BvhLesson;
use accelviz_app::lessons::kd::{KdLesson, Part};
use accelviz_app::lessons::near_first::{FAMILIES, NearFirstLesson, ORDERS};
use accelviz_app::lessons::trivial::TrivialLoop;
use accelviz_app::stage::{build_params, with_settings};
use accelviz_core::{
    BuildRecorder, Built, NoBuildObserver, Query, Recorder, SplitRule, Step, Structure,
    TraceOptions, TraversalStacks, brute_force, counters_of,
};
use accelviz_scene::document::{GeneratorEntry, LayoutEntry};
use egui_kittest::kittest::Queryable;

/// The core's recording of `structure` traced over the lesson's scene and ray.
fn core_steps(lesson: &dyn Lesson, structure: Structure, options: &TraceOptions) -> Vec<Step<f64>> {
    let scene = &common::flat(lesson).scene;
    let structure = with_settings(structure, &scene.settings);
    let built = Built::new(
        structure,
        &scene.shapes,
        &build_params(&scene.settings),
        &mut NoBuildObserver,
    );
    let ray = common::flat(lesson).ray().expect("the lesson's ray");
    let mut recorder = Recorder::default();
    built.tree.trace(
        &scene.shapes,
        &ray,
        options,
        &mut TraversalStacks::default(),
        &mut recorder,
    );
    recorder.steps
}

#[test]
fn the_trivial_loop_shows_the_cores_state_at_every_step() {
    let mut harness = lesson_harness(TrivialLoop::new(lesson_text("01-trivial.ron")));
    harness.run();
    let lesson = harness.state();
    let scene = common::flat(lesson).scene.clone();
    let ray = common::flat(lesson).ray().expect("ray");
    let mut recorder = Recorder::default();
    brute_force(&scene.shapes, &ray, &TraceOptions::default(), &mut recorder);
    let total = scene.shapes.shapes.len();
    assert_eq!(
        harness.state().stage().timeline.len,
        total,
        "one step per test"
    );
    for frame in 0..=total {
        harness.state_mut().stage_mut().timeline.shown = frame;
        harness.run();
        let state = harness.state().shown_state().expect("a trace");
        assert_eq!(
            state.counters.primitive_tests as usize, frame,
            "step {frame}: tests"
        );
        // The core's steps up to that test: the same counters and closest hit.
        let tests_seen = recorder
            .steps
            .iter()
            .position({
                let mut tests = 0;
                move |step| {
                    if matches!(step, Step::PrimitiveTested { .. }) {
                        tests += 1;
                    }
                    tests > frame
                }
            })
            .unwrap_or(recorder.steps.len());
        let prefix = &recorder.steps[..tests_seen];
        assert_eq!(state.counters, counters_of(prefix), "step {frame}");
        assert_eq!(
            state.closest,
            accelviz_app::trace::closest_so_far(prefix),
            "step {frame}"
        );
        let text = format!("primitives tested: {frame} of {total}");
        assert!(
            harness.query_by_label(&text).is_some(),
            "step {frame}: the inspector says {text}"
        );
        if frame == total {
            assert!(
                harness.query_by_label_contains("Done:").is_some(),
                "the last step sums up"
            );
        }
    }
}

#[test]
fn the_bvh_lesson_shows_the_cores_traversal_at_every_step() {
    let mut harness = lesson_harness(BvhLesson::new(lesson_text("04-bvh.ron")));
    harness.run();
    let core = core_steps(
        harness.state(),
        Structure::lecture(accelviz_core::Family::Bvh, SplitRule::Sah),
        &TraceOptions::default(),
    );
    let trace = harness.state().trace().expect("a trace").clone();
    assert_eq!(trace.steps, core, "the lesson records the core's traversal");
    let frames = harness.state().stage().timeline.len;
    assert!(frames > 4, "the slide's ray takes a few steps: {frames}");
    for frame in 0..=frames {
        harness.state_mut().stage_mut().timeline.shown = frame;
        harness.run();
        let state = harness.state().shown_state().expect("a trace");
        let prefix = trace.shown(frame);
        assert_eq!(
            &core[..prefix.len()],
            prefix,
            "frame {frame}: a prefix of the core's steps"
        );
        assert_eq!(state.counters, counters_of(prefix), "frame {frame}");
        assert_eq!(
            state.closest,
            accelviz_app::trace::closest_so_far(prefix),
            "frame {frame}"
        );
    }
    assert_eq!(
        trace.shown(frames).len(),
        core.len(),
        "the last frame shows every step"
    );
}

#[test]
fn the_kd_lesson_describes_one_step_in_every_panel() {
    let mut harness = lesson_harness(KdLesson::new(lesson_text("05-kd-tree.ron")));
    harness.run();
    // The slide's pseudo-code: each leaf tests against the ray clipped to its cell.
    let core = core_steps(
        harness.state(),
        Structure::KdMiddle,
        &TraceOptions {
            order: accelviz_core::Order::NearFirst,
            query: Query::FirstInCell,
            ..TraceOptions::default()
        },
    );
    let trace = harness.state().trace().expect("a trace").clone();
    assert_eq!(trace.steps, core, "the lesson records the core's traversal");
    let tree = harness.state().tree().expect("a tree").clone();
    let facts = &tree.built.facts;
    let frames = harness.state().stage().timeline.len;
    let (mut found, mut empty, mut near, mut far) = (false, false, false, false);
    for frame in 1..=frames {
        harness.state_mut().stage_mut().timeline.shown = frame;
        harness.run();
        let view = harness.state().view().expect("a view");
        let step = trace.frame(frame)[0];
        // The status line is the view's text.
        let caption = harness.state().caption().expect("a caption");
        assert!(caption.starts_with(&view.text), "frame {frame}: {caption}");
        match step {
            Step::CellEntered {
                node,
                t_near,
                t_far,
            } => {
                assert_eq!(
                    view.cell,
                    Some(node),
                    "frame {frame}: the canvas shows the entered cell"
                );
                assert_eq!(
                    view.plane_of, facts.parent[node as usize],
                    "frame {frame}: its parent's plane"
                );
                let (from, to, part) = view.segment.expect("the part of the ray");
                assert_eq!(
                    (from, to),
                    (t_near, t_far),
                    "frame {frame}: the reported segment"
                );
                match part {
                    Part::Near => {
                        near = true;
                        assert_eq!(view.lines, [4, 5], "frame {frame}: rayNear's lines");
                    }
                    Part::Far => {
                        far = true;
                        assert_eq!(view.lines, [6, 7, 8], "frame {frame}: rayFar's lines");
                    }
                    Part::Root => assert!(view.lines.contains(&0)),
                }
            }
            Step::CellMissed { node } => {
                empty = true;
                assert_eq!(view.cell, Some(node));
                assert!(
                    view.lines.contains(&1),
                    "frame {frame}: 'If empty(ray) return' is lit"
                );
            }
            Step::NodeCulled { .. } => {
                panic!("frame {frame}: the pseudo-code never culls a node by a hit beyond it")
            }
            Step::PrimitiveTested { .. } => assert_eq!(view.lines, [2]),
            _ => {}
        }
        // A test that finds the closest hit in its cell shows it in the same frame, and says
        // the search ends with the leaf.
        let finds = trace
            .frame(frame)
            .iter()
            .any(|step| matches!(step, Step::ClosestHitUpdated { .. }));
        assert_eq!(
            view.text.contains("the search ends"),
            finds,
            "frame {frame}: {}",
            view.text
        );
        found |= finds;
    }
    assert!(
        found && empty && near && far,
        "the default scene shows a hit in its cell ({found}), an empty part ({empty}), rayNear ({near}) and rayFar ({far})"
    );
}

/// A primitive tested twice (it straddles a plane) is said to be; with the mailbox on, the
/// second test is skipped and said to be.
#[test]
fn the_kd_lesson_names_a_straddler_tested_twice_and_the_mailbox() {
    let mut harness = lesson_harness(KdLesson::new(lesson_text("05-kd-tree.ron")));
    harness.run();
    let frames = harness.state().stage().timeline.len;
    let mut said = Vec::new();
    for frame in 1..=frames {
        harness.state_mut().stage_mut().timeline.shown = frame;
        harness.run();
        said.push(harness.state().view().expect("a view").text);
    }
    assert!(
        said.iter()
            .any(|text| text.contains("Tested again") && text.contains("mailbox")),
        "some straddler is tested twice on the lesson's ray: {said:#?}"
    );
    harness
        .get_by_label("mailboxing: test a straddling primitive once per ray")
        .click();
    harness.run();
    let frames = harness.state().stage().timeline.len;
    let mut skipped = false;
    for frame in 1..=frames {
        harness.state_mut().stage_mut().timeline.shown = frame;
        harness.run();
        skipped |= harness
            .state()
            .view()
            .expect("a view")
            .text
            .contains("not tested again");
    }
    assert!(skipped, "the mailbox skips the second test");
}

#[test]
fn near_first_panes_show_the_cores_counters_and_no_answer_ahead_of_time() {
    let mut harness = lesson_harness(NearFirstLesson::new(lesson_text("06-near-first.ron")));
    harness.run();
    // At the start nothing is known yet: no closest hit, answers hidden.
    assert_eq!(harness.query_all_by_label("not yet").count(), 4);
    assert!(!harness.state().revealed(0) && !harness.state().revealed(1));
    let frames = harness.state().stage().timeline.len;
    for frame in [1, frames / 3, frames / 2, frames] {
        harness.state_mut().stage_mut().timeline.shown = frame;
        harness.run();
        for (structure, family) in FAMILIES.iter().enumerate() {
            for (order, (order_kind, name)) in ORDERS.iter().enumerate() {
                let options = harness.state().options(*order_kind);
                assert_eq!(options.query, Query::FirstInCell, "the slide's rule first");
                let core = core_steps(
                    harness.state(),
                    Structure::lecture(*family, SplitRule::Sah),
                    &options,
                );
                let trace = harness
                    .state()
                    .trace(structure, order)
                    .expect("a pane")
                    .clone();
                assert_eq!(trace.steps, core, "{family:?} {name}: the core's traversal");
                let state = harness
                    .state()
                    .pane_state(structure, order)
                    .expect("a pane");
                let prefix = trace.shown(frame);
                assert_eq!(
                    state.counters,
                    counters_of(prefix),
                    "{family:?} {name}, frame {frame}"
                );
                assert_eq!(
                    state.closest,
                    accelviz_app::trace::closest_so_far(prefix),
                    "{family:?} {name}, frame {frame}"
                );
            }
        }
    }
    // At the end, under the slide's rule, the kD-tree near first returns the closest hit and
    // file order a farther one: the lecture's answer, on the lesson's own ray.
    let closest = |lesson: &NearFirstLesson, structure: usize, order: usize| {
        let trace = lesson.trace(structure, order).expect("a pane");
        accelviz_app::trace::closest_so_far(&trace.steps).expect("a hit")
    };
    let (near, file) = (
        closest(harness.state(), 0, 0),
        closest(harness.state(), 0, 1),
    );
    assert!(
        near.1 < file.1,
        "kD near first {near:?}, file order {file:?}"
    );
    harness.get_by_label("cull by the closest hit").click();
    harness.run();
    assert_eq!(harness.state().rule(), Query::Closest);
    harness.state_mut().stage_mut().timeline.shown = harness.state().stage().timeline.len;
    harness.run();
    // Culling, both orders find the same hit, and near first did less on both structures.
    let counters = harness.state().pane_counters().expect("counters");
    for (structure, family) in FAMILIES.iter().enumerate() {
        assert_eq!(
            closest(harness.state(), structure, 0),
            closest(harness.state(), structure, 1),
            "{family:?}"
        );
        assert!(
            counters[structure][0].nodes_visited < counters[structure][1].nodes_visited,
            "{family:?}: near first visits fewer nodes on the lesson's ray: {counters:?}"
        );
    }
    harness
        .get_all_by_label("show the answer")
        .next()
        .expect("the first question's button")
        .click();
    harness.run();
    assert!(harness.state().revealed(0), "asking shows the answer");
}

/// A generated scene's ray makes the lesson's point: near first does less than file order.
#[test]
fn near_first_generated_scenes_make_the_point() {
    let mut harness = lesson_harness(NearFirstLesson::new(lesson_text("06-near-first.ron")));
    for seed in 1..=4 {
        let lesson = harness.state_mut();
        let scene = &mut lesson.stage_mut().scene.as_flat().expect("a 2D scene");
        scene.generator = GeneratorEntry {
            layout: LayoutEntry::Uniform,
            count: 500,
            seed,
        };
        scene.generate();
        assert!(
            lesson
                .stage_mut()
                .scene
                .as_flat()
                .expect("a 2D scene")
                .take_generated()
        );
        let (origin, toward) = lesson
            .place_generated_ray(&common::flat(lesson).scene)
            .expect("the lesson places the ray");
        let scene = &mut lesson.stage_mut().scene.as_flat().expect("a 2D scene");
        scene.scene.ray_origin = origin;
        scene.scene.ray_toward = toward;
        scene.touch_ray();
        harness.run();
        let timeline = &mut harness.state_mut().stage_mut().timeline;
        timeline.shown = timeline.len;
        harness.run();
        // Under the slide's rule file order either works more or returns a farther hit.
        let counters = harness.state().pane_counters().expect("counters");
        for (structure, family) in FAMILIES.iter().enumerate() {
            let [near, file] = counters[structure];
            let hit = |order: usize| {
                let trace = harness.state().trace(structure, order).expect("a pane");
                accelviz_app::trace::closest_so_far(&trace.steps).map_or(f64::INFINITY, |hit| hit.1)
            };
            assert!(
                near.nodes_visited + near.primitive_tests
                    < file.nodes_visited + file.primitive_tests
                    || hit(0) < hit(1),
                "seed {seed}, {family:?}: near first {near:?} against file order {file:?}"
            );
        }
    }
}

/// Lesson 9's steps are the builder's own: a fresh build of the same structure with a
/// recorder gives the same steps, both ways, and the two ways build the same tree.
#[test]
fn build_steps_are_the_builders_own() {
    let mut harness = lesson_harness(BuildStepsLesson::new(lesson_text(
        "09-building-is-optimisation.ron",
    )));
    harness.run();
    let mut trees = Vec::new();
    for (way, label) in [
        (Way::SortAtEachNode, "sort at each node"),
        (Way::SortOnce, "sort once"),
    ] {
        harness.get_by_label(label).click();
        harness.run();
        let scene = common::flat(harness.state()).scene.clone();
        let mut recorder = BuildRecorder::default();
        let built = Built::new(
            way.structure(),
            &scene.shapes,
            &build_params(&scene.settings),
            &mut recorder,
        );
        assert_eq!(
            harness.state().steps(),
            recorder.steps.as_slice(),
            "{label}"
        );
        assert_eq!(harness.state().stage().timeline.len, recorder.steps.len());
        let sorts = recorder
            .steps
            .iter()
            .filter(|step| matches!(step, accelviz_core::BuildStep::Sorted { .. }))
            .count();
        match way {
            Way::SortOnce => assert_eq!(sorts, 2, "sorted once per axis, at the root"),
            Way::SortAtEachNode => assert!(sorts > 2, "sorted at every node split: {sorts}"),
        }
        trees.push(built.tree);
    }
    assert_eq!(trees[0], trees[1], "both ways build the same tree");
}
