//! A traversal recorded by the core's [`Recorder`] and stepped by the timeline.
//!
//! The timeline moves in frames: one step of the core each, except that a primitive test and
//! the "closest hit so far" it made are one frame (one action: test, and keep the hit), and
//! that a wide node's child boxes, tested together, are one frame with the order chosen for
//! them (one SIMD test). So a brute-force loop over 16 shapes has 16 frames and "tested k of
//! 16" matches "step k of 16".
//! Whatever a lesson shows part-way through is [`Trace::state`] at that frame: the core's
//! counters replayed, the closest hit so far, the step being taken.

use accelviz_core::format::{counted, number};
use accelviz_core::{
    Counters, Hit, LeafPrimitives, Order, Ray, Real, Recorder, ShapeSet, Step, TraceOptions,
    TraversalStacks, Tree, Vector, brute_force, counters_of,
};
use glam::DVec2;

use crate::stage::SceneTree;

/// One recorded traversal.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// Every step, in order.
    pub steps: Vec<Step<f64>>,
    /// The answer.
    pub hit: Option<Hit<f64>>,
    /// Where each frame ends in `steps`.
    frame_ends: Vec<usize>,
}

/// What a trace shows after some frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceState {
    /// The core's counters of the steps shown.
    pub counters: Counters,
    /// The closest hit so far: primitive and t.
    pub closest: Option<(u32, f64)>,
    /// The step the current frame took (its first).
    pub current: Option<Step<f64>>,
    /// Whether every frame is shown.
    pub done: bool,
}

impl Trace {
    /// Runs `trace` with a recorder and keeps its steps and answer.
    fn record(trace: impl FnOnce(&mut Recorder<f64>) -> Option<Hit<f64>>) -> Self {
        let mut recorder = Recorder::default();
        let hit = trace(&mut recorder);
        let steps = recorder.steps;
        let mut frame_ends = Vec::with_capacity(steps.len());
        for (index, step) in steps.iter().enumerate() {
            let joins_previous = matches!(step, Step::ClosestHitUpdated { .. })
                && matches!(
                    index.checked_sub(1).map(|previous| steps[previous]),
                    Some(Step::PrimitiveTested { .. })
                );
            if let Step::ChildrenOrdered { tested, .. } = *step {
                // The box tests just before were one test of all the children.
                let kept = frame_ends.len().saturating_sub(tested as usize);
                frame_ends.truncate(kept);
                frame_ends.push(index + 1);
                continue;
            }
            match frame_ends.last_mut() {
                Some(end) if joins_previous => *end = index + 1,
                _ => frame_ends.push(index + 1),
            }
        }
        Self {
            steps,
            hit,
            frame_ends,
        }
    }

    /// Records the one traversal of `tree`'s kind on `ray`.
    pub fn of_tree(tree: &SceneTree, ray: &Ray<DVec2>, options: &TraceOptions) -> Self {
        Self::of(&tree.built.tree, tree.shapes.as_ref(), ray, options)
    }

    /// Records the one traversal of `tree`'s kind over `primitives` on `ray`, in 2D or 3D.
    pub fn of<V: Vector<Scalar = f64>>(
        tree: &Tree<V>,
        primitives: &impl LeafPrimitives<V>,
        ray: &Ray<V>,
        options: &TraceOptions,
    ) -> Self {
        Self::record(|recorder| {
            tree.trace(
                primitives,
                ray,
                options,
                &mut TraversalStacks::default(),
                recorder,
            )
        })
    }

    /// [`Trace::of`] a traversal in any precision (a trade row's f32), heard in f64 through
    /// [`Widened`](accelviz_core::observer::Widened): every step, its numbers exactly.
    pub fn of_any_precision<V: Vector>(
        tree: &Tree<V>,
        primitives: &impl LeafPrimitives<V>,
        ray: &Ray<V>,
        options: &TraceOptions,
    ) -> Self {
        Self::record(|recorder| {
            tree.trace(
                primitives,
                ray,
                options,
                &mut TraversalStacks::default(),
                &mut accelviz_core::observer::Widened(recorder),
            )
            .map(|hit| Hit {
                primitive: hit.primitive,
                t: hit.t.to_f64(),
            })
        })
    }

    /// Records the trivial loop: every primitive, in file order.
    pub fn of_brute_force(shapes: &ShapeSet<DVec2>, ray: &Ray<DVec2>) -> Self {
        Self::record(|recorder| brute_force(shapes, ray, &TraceOptions::default(), recorder))
    }

    /// How many frames.
    pub fn frames(&self) -> usize {
        self.frame_ends.len()
    }

    /// The steps of the first `frames` frames.
    pub fn shown(&self, frames: usize) -> &[Step<f64>] {
        let end = match frames.min(self.frames()) {
            0 => 0,
            shown => self.frame_ends[shown - 1],
        };
        &self.steps[..end]
    }

    /// The steps of frame `frame` (1-based; 0 is before the first).
    pub fn frame(&self, frame: usize) -> &[Step<f64>] {
        let shown = self.shown(frame);
        let start = self.shown(frame.saturating_sub(1)).len();
        &shown[start.min(shown.len())..]
    }

    /// What is shown after `frames` frames.
    pub fn state(&self, frames: usize) -> TraceState {
        let shown = self.shown(frames);
        TraceState {
            counters: counters_of(shown),
            closest: closest_so_far(shown),
            current: self.frame(frames).first().copied(),
            done: frames >= self.frames() && frames > 0,
        }
    }

    /// How the trace ended, for the caption of its last frame.
    pub fn summary(&self) -> String {
        let counters = counters_of(&self.steps);
        let work = if counters.box_tests > 0 || counters.nodes_visited > 0 {
            format!(
                "{} visited, {}, {}",
                counted(counters.nodes_visited as usize, "node", "nodes"),
                counted(counters.box_tests as usize, "box test", "box tests"),
                counted(
                    counters.primitive_tests as usize,
                    "primitive test",
                    "primitive tests"
                )
            )
        } else {
            counted(
                counters.primitive_tests as usize,
                "primitive test",
                "primitive tests",
            )
        };
        match self.hit {
            Some(hit) => format!(
                "Done: the closest hit is primitive {} at t = {}; {work}.",
                hit.primitive,
                number(hit.t)
            ),
            None => format!("Done: the ray hits nothing; {work}."),
        }
    }

    /// The caption of frame `frame`: `intro` before the first, the step in words, and the
    /// summary with the last.
    pub fn caption(
        &self,
        frame: usize,
        intro: &str,
        describe: impl Fn(&Step<f64>) -> String,
    ) -> String {
        // A frame of boxes tested together is told by its last step, which says what came of it.
        let steps = self.frame(frame);
        let told = match steps.last() {
            Some(last @ Step::ChildrenOrdered { .. }) => Some(last),
            _ => steps.first(),
        };
        let Some(step) = told else {
            return if self.frames() == 0 {
                "No ray to trace.".to_owned()
            } else {
                intro.to_owned()
            };
        };
        let said = describe(step);
        if frame >= self.frames() {
            format!("{said}. {}", self.summary())
        } else {
            said
        }
    }
}

/// The closest hit after some steps: primitive and t.
pub fn closest_so_far(steps: &[Step<f64>]) -> Option<(u32, f64)> {
    steps.iter().rev().find_map(|step| match *step {
        Step::ClosestHitUpdated { primitive, t } => Some((primitive, t)),
        _ => None,
    })
}

/// The options of a recorded trace: the core's defaults in the given order.
pub fn options_in(order: Order) -> TraceOptions {
    TraceOptions {
        order,
        ..TraceOptions::default()
    }
}

/// What a step did, in words; `node_name` names a node.
pub fn describe_step(step: &Step<f64>, node_name: impl Fn(u32) -> String) -> String {
    match *step {
        Step::BoxTested {
            node,
            t_enter,
            t_exit,
            hit,
        } => {
            if hit {
                format!(
                    "box of {} tested: hit, the ray is inside for t in [{}, {}]",
                    node_name(node),
                    number(t_enter),
                    number(t_exit)
                )
            } else {
                format!(
                    "box of {} tested: missed, skip everything inside it",
                    node_name(node)
                )
            }
        }
        Step::NodeEntered { node } => format!("enter {}", node_name(node)),
        Step::CellEntered {
            node,
            t_near,
            t_far,
        } => format!(
            "enter {} with the ray clipped to it: t in [{}, {}]",
            node_name(node),
            number(t_near),
            number(t_far)
        ),
        Step::CellMissed { node } => format!(
            "the ray does not reach {}: its part there is empty",
            node_name(node)
        ),
        Step::CellSkipped {
            node,
            t_near,
            t_far,
        } => format!(
            "pass {} (t in [{}, {}]): nothing is listed there",
            node_name(node),
            number(t_near),
            number(t_far)
        ),
        Step::GridStepped { axis, t_next } => {
            let axis = usize::from(axis).min(2);
            format!(
                "the next {} line is nearest (t = {}): step across it",
                ["vertical", "horizontal", "depth"][axis],
                number(t_next[axis])
            )
        }
        Step::CellLookedUp { node, probes } => format!(
            "look {} up in the hash table: {probes} {}",
            node_name(node),
            if probes == 1 {
                "place read"
            } else {
                "places read"
            }
        ),
        Step::NodeCulled {
            node,
            t_enter,
            t_closest,
        } => format!(
            "skip {}: it starts at t = {} beyond the closest hit so far (t = {})",
            node_name(node),
            number(t_enter),
            number(t_closest)
        ),
        Step::PrimitiveTested { primitive, t_hit } => match t_hit {
            Some(t) => format!("primitive {primitive} tested: hit at t = {}", number(t)),
            None => format!("primitive {primitive} tested: miss"),
        },
        Step::ClosestHitUpdated { primitive, t } => {
            format!(
                "closest hit so far: primitive {primitive} at t = {}",
                number(t)
            )
        }
        Step::PrimitiveSkipped { primitive } => {
            format!("primitive {primitive} skipped: already tested for this ray (mailbox)")
        }
        Step::ChildrenOrdered {
            node,
            tested,
            order,
            count,
        } => {
            let names: Vec<String> = order[..count as usize]
                .iter()
                .map(|&child| node_name(child))
                .collect();
            let next = match names.as_slice() {
                [] => "none is hit: back to the stack".to_owned(),
                [only] => format!("visit {only}"),
                [first, rest @ ..] => {
                    format!(
                        "visit {first} first, then {} (on the stack)",
                        rest.join(", then ")
                    )
                }
            };
            if tested == 0 {
                // An octree: the ray's crossings of the middle planes order the children.
                format!(
                    "{} is cut at its middle: the ray passes {} of its children, front to back: {next}",
                    node_name(node),
                    count
                )
            } else {
                format!(
                    "the {tested} child boxes of {} tested at once: {next}",
                    node_name(node)
                )
            }
        }
    }
}

/// The node a step is at, if it is at one.
pub fn step_node(step: &Step<f64>) -> Option<u32> {
    match *step {
        Step::BoxTested { node, .. }
        | Step::NodeEntered { node }
        | Step::CellEntered { node, .. }
        | Step::CellMissed { node }
        | Step::CellSkipped { node, .. }
        | Step::CellLookedUp { node, .. }
        | Step::NodeCulled { node, .. }
        | Step::ChildrenOrdered { node, .. } => Some(node),
        Step::PrimitiveTested { .. }
        | Step::ClosestHitUpdated { .. }
        | Step::PrimitiveSkipped { .. }
        | Step::GridStepped { .. } => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use accelviz_core::{Shape, Sphere};

    /// A hit and its "closest so far" are one frame; the last frame's caption sums up.
    #[test]
    fn a_test_and_the_hit_it_keeps_are_one_frame() {
        let disc = |x: f64| {
            Shape::Sphere(Sphere {
                center: DVec2::new(x, 0.0),
                radius: 1.0,
            })
        };
        let shapes = ShapeSet {
            shapes: vec![disc(5.0), disc(9.0), disc(20.0)],
        };
        let ray = Ray::try_new(DVec2::ZERO, DVec2::X).unwrap_or_else(|_| unreachable!());
        let trace = Trace::of_brute_force(&shapes, &ray);
        assert_eq!(
            trace.steps.len(),
            4,
            "three tests, one closest-hit update (the farther discs do not beat the first)"
        );
        assert_eq!(trace.frames(), 3, "one frame per test");
        assert_eq!(trace.state(1).counters.primitive_tests, 1);
        assert_eq!(trace.state(1).closest, Some((0, 4.0)));
        assert_eq!(trace.state(0).current, None);
        assert!(trace.state(3).done && !trace.state(2).done);
        let last = trace.caption(3, "start", |step| {
            describe_step(step, |node| node.to_string())
        });
        assert!(
            last.ends_with("Done: the closest hit is primitive 0 at t = 4.000; 3 primitive tests."),
            "{last}"
        );
    }

    /// A quadtree tests no boxes: the order of a cell's children (from its middle lines) is a
    /// frame of its own, after the frame that entered the cell, and says so.
    #[test]
    fn a_quadtrees_order_is_a_frame_of_its_own() {
        use accelviz_core::params::BuildParams;
        use accelviz_core::{Built, NoBuildObserver, Structure};
        let disc = |x: f64, y: f64| {
            Shape::Sphere(Sphere {
                center: DVec2::new(x, y),
                radius: 1.0,
            })
        };
        let shapes = ShapeSet {
            shapes: vec![
                disc(0.0, 0.0),
                disc(20.0, 0.0),
                disc(0.0, 20.0),
                disc(20.0, 20.0),
            ],
        };
        let built = Built::new(
            Structure::Octree { leaf: 1 },
            &shapes,
            &BuildParams::default(),
            &mut NoBuildObserver,
        );
        let ray = Ray::try_new(DVec2::new(-5.0, 1.0), DVec2::X).unwrap_or_else(|_| unreachable!());
        let trace = Trace::of(&built.tree, &shapes, &ray, &options_in(Order::NearFirst));
        let ordered = (1..=trace.frames())
            .find(|&frame| {
                matches!(
                    trace.frame(frame).last(),
                    Some(Step::ChildrenOrdered { .. })
                )
            })
            .expect("the root's children ordered");
        assert_eq!(trace.frame(ordered).len(), 1, "{:?}", trace.frame(ordered));
        assert!(matches!(
            trace.frame(ordered - 1),
            [Step::CellEntered { node: 0, .. }]
        ));
        let said = trace.caption(ordered, "start", |step| {
            describe_step(step, |node| node.to_string())
        });
        assert!(
            said.starts_with(
                "0 is cut at its middle: the ray passes 2 of its children, front to back: visit "
            ),
            "{said}"
        );
    }

    /// A wide node's box tests are one frame with the order chosen, told by that order.
    #[test]
    fn a_wide_nodes_children_are_tested_in_one_frame() {
        use accelviz_core::params::BuildParams;
        use accelviz_core::{Built, NoBuildObserver, Structure, Width};
        let disc = |x: f64, y: f64| {
            Shape::Sphere(Sphere {
                center: DVec2::new(x, y),
                radius: 1.0,
            })
        };
        let shapes = ShapeSet {
            shapes: [0.0, 10.0, 20.0, 30.0]
                .iter()
                .flat_map(|&x| [disc(x, 0.0), disc(x + 3.0, 6.0)])
                .collect(),
        };
        let params = BuildParams {
            max_leaf_size: 1,
            ..BuildParams::default()
        };
        let structure = Structure::BvhMedian { width: Width::Four };
        let built = Built::new(structure, &shapes, &params, &mut NoBuildObserver);
        let ray = Ray::try_new(DVec2::new(-5.0, 0.0), DVec2::X).unwrap_or_else(|_| unreachable!());
        let trace = Trace::of(&built.tree, &shapes, &ray, &options_in(Order::NearFirst));
        // Frame 1 enters the root; frame 2 is every child box of the root and the order.
        assert!(matches!(trace.frame(1), [Step::NodeEntered { node: 0 }]));
        let tested = trace.frame(2);
        let Some(&Step::ChildrenOrdered { tested: count, .. }) = tested.last() else {
            panic!("{tested:?}");
        };
        assert!(count >= 2);
        assert_eq!(tested.len(), count as usize + 1);
        assert!(
            tested[..count as usize]
                .iter()
                .all(|step| matches!(step, Step::BoxTested { .. }))
        );
        let said = trace.caption(2, "start", |step| {
            describe_step(step, |node| node.to_string())
        });
        assert!(
            said.starts_with(&format!(
                "the {count} child boxes of 0 tested at once: visit "
            )),
            "{said}"
        );
        // Every step is in some frame, and the counters are the core's.
        assert_eq!(trace.shown(trace.frames()).len(), trace.steps.len());
        assert_eq!(trace.state(2).counters.box_tests, u64::from(count));
    }
}
