//! "Build the tree yourself" (Naps et al. 2002's "constructing" level; TRAKLA2's
//! build-the-structure exercises): at each node the student picks a split, by axis and
//! position, or keeps a leaf. Each option's SAH cost is shown beside the builder's choice; the
//! student's tree is the student's own (a costlier pick is kept, not fixed), and the score is
//! the SAH cost of the core's sweep builder's tree over the student's, both measured by the
//! core's `TreeStats`.

use accelviz_core::bvh::{Bvh, BvhNode, validate};
use accelviz_core::curve::bvh_curve;
use accelviz_core::params::BuildParams;
use accelviz_core::{Aabb, Built, NoBuildObserver, SahCost, ShapeSet, Structure, TreeStats, Width};
use glam::DVec2;

use crate::generate::{AXES, num};
use crate::question::{Ask, Choice, Expected, Highlight};

/// One option at a node: keep a leaf, or split at a position on an axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pick {
    /// Keep the node a leaf.
    Leaf,
    /// Split: shapes whose box centre lies below `position` on `axis` go left.
    Split {
        /// The axis.
        axis: usize,
        /// Where.
        position: f64,
    },
}

/// A node to decide: its shapes, and its options with their SAH costs.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeChoice {
    /// The node's path from the root (`""` for the root, then `L`, `LR`, …).
    pub path: String,
    /// The node's shapes.
    pub shapes: Vec<u32>,
    /// The box around them.
    pub bounds: Aabb<DVec2>,
    /// The options: the leaf first, then every split on x, then on y.
    pub picks: Vec<Pick>,
    /// Each option's SAH cost (the leaf's is `N · C_isect`).
    pub costs: Vec<f64>,
    /// The option the SAH builder takes (the cheapest; the leaf when no split is cheaper).
    pub builder: usize,
}

/// A tree being built by a student.
#[derive(Clone, Debug, PartialEq)]
pub struct BuildExercise {
    shapes: ShapeSet<DVec2>,
    cost: SahCost,
    /// Nodes decided, in the order decided (depth first, left before right), with the pick.
    decided: Vec<(NodeChoice, usize)>,
    /// Nodes still to decide (their shapes and paths), the next on top.
    pending: Vec<(String, Vec<u32>)>,
    builder_cost: f64,
}

/// How a finished tree compares with the builder's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildScore {
    /// The SAH cost of the student's tree (leaves for any node not yet decided).
    pub student_cost: f64,
    /// The SAH cost of the SAH builder's tree.
    pub builder_cost: f64,
    /// `builder_cost / student_cost`: 1 matches the builder, above 1 beats it (the builder is
    /// greedy, so a far-sighted student can).
    pub ratio: f64,
}

impl BuildExercise {
    /// An exercise over `shapes` with cost constants `cost`.
    pub fn new(shapes: ShapeSet<DVec2>, cost: SahCost) -> Self {
        let params = BuildParams {
            max_leaf_size: 1,
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
        let builder_cost = built.stats(0, &cost).sah_cost;
        let all: Vec<u32> = (0..shapes.shapes.len() as u32).collect();
        Self {
            shapes,
            cost,
            decided: Vec::new(),
            pending: vec![(String::new(), all)],
            builder_cost,
        }
    }

    /// The shapes.
    pub fn shapes(&self) -> &ShapeSet<DVec2> {
        &self.shapes
    }

    /// The cost constants.
    pub fn cost(&self) -> SahCost {
        self.cost
    }

    /// The nodes decided so far, each with the option picked.
    pub fn decided(&self) -> &[(NodeChoice, usize)] {
        &self.decided
    }

    /// How many nodes wait to be decided, the next one included (each split adds its two
    /// children): how much of the exercise is left, as far as it is known.
    pub fn waiting(&self) -> usize {
        self.pending.len()
    }

    /// The node to decide next, with its options, or `None` when the tree is done.
    pub fn next_choice(&self) -> Option<NodeChoice> {
        let (path, members) = self.pending.last()?;
        Some(self.choice_at(path, members))
    }

    fn choice_at(&self, path: &str, members: &[u32]) -> NodeChoice {
        let boxes: Vec<Aabb<DVec2>> = self.shapes.shapes.iter().map(|s| s.bounds()).collect();
        let curve = bvh_curve(&boxes, members, &self.cost, None);
        let centres: Vec<DVec2> = boxes.iter().map(Aabb::center).collect();
        let mut picks = vec![Pick::Leaf];
        let mut costs = vec![curve.leaf_cost];
        let mut sides: Vec<Vec<u32>> = Vec::new();
        for candidates in &curve.axes {
            for candidate in candidates {
                // Offered only where "centre below the position goes left" is the split the
                // curve costed (two centres in one place cannot be told apart).
                let left: Vec<u32> = members
                    .iter()
                    .copied()
                    .filter(|m| centres[*m as usize][candidate.axis] < candidate.position)
                    .collect();
                // A split on y that divides the shapes as one on x does is the same tree:
                // offered once.
                if left.len() == candidate.count_left && !sides.contains(&left) {
                    sides.push(left);
                    picks.push(Pick::Split {
                        axis: candidate.axis,
                        position: candidate.position,
                    });
                    costs.push(candidate.cost);
                }
            }
        }
        // The builder's choice: the cheapest option, the leaf when no split is cheaper (the
        // sweep builder's rule; the exercise is drawn only where its tree is the builder's).
        let builder = (0..costs.len())
            .min_by(|a, b| costs[*a].total_cmp(&costs[*b]))
            .unwrap_or(0);
        let bounds = members
            .iter()
            .fold(Aabb::empty(), |acc, m| acc.union(boxes[*m as usize]));
        NodeChoice {
            path: path.to_owned(),
            shapes: members.to_vec(),
            bounds,
            picks,
            costs,
            builder,
        }
    }

    /// Takes option `index` at the next node. False (and nothing changes) when the tree is
    /// done or there is no such option.
    pub fn pick(&mut self, index: usize) -> bool {
        let Some(choice) = self.next_choice() else {
            return false;
        };
        let Some(pick) = choice.picks.get(index).copied() else {
            return false;
        };
        self.pending.pop();
        if let Pick::Split { axis, position } = pick {
            let (left, right): (Vec<u32>, Vec<u32>) = choice
                .shapes
                .iter()
                .partition(|m| self.shapes.shapes[**m as usize].bounds().center()[axis] < position);
            // Right below left on the stack: the left child is decided first.
            self.pending.push((format!("{}R", choice.path), right));
            self.pending.push((format!("{}L", choice.path), left));
        }
        self.decided.push((choice, index));
        // A node of one shape has nothing to decide: it is a leaf.
        while let Some((path, members)) = self.pending.last().cloned() {
            if members.len() > 1 {
                break;
            }
            self.pending.pop();
            let choice = self.choice_at(&path, &members);
            self.decided.push((choice, 0));
        }
        true
    }

    /// True when every node is decided.
    pub fn is_done(&self) -> bool {
        self.pending.is_empty()
    }

    /// The student's tree so far, in the core's layout (an undecided node is a leaf).
    pub fn tree(&self) -> Bvh<DVec2> {
        let mut bvh = Bvh::default();
        if self.shapes.shapes.is_empty() {
            return bvh;
        }
        let boxes: Vec<Aabb<DVec2>> = self.shapes.shapes.iter().map(|s| s.bounds()).collect();
        let split_of = |path: &str| {
            self.decided
                .iter()
                .find(|(choice, _)| choice.path == path)
                .and_then(|(choice, index)| match choice.picks[*index] {
                    Pick::Split { axis, position } => Some((axis, position)),
                    Pick::Leaf => None,
                })
        };
        // Breadth of the core's layout: children side by side, allocated when the parent is.
        let all: Vec<u32> = (0..boxes.len() as u32).collect();
        let bounds_of = |members: &[u32]| {
            members
                .iter()
                .fold(Aabb::empty(), |acc, m| acc.union(boxes[*m as usize]))
        };
        bvh.nodes.push(BvhNode {
            bounds: bounds_of(&all),
            first: 0,
            count: 0,
        });
        let mut work = vec![(0usize, String::new(), all)];
        while let Some((index, path, members)) = work.pop() {
            match split_of(&path) {
                Some((axis, position)) => {
                    let (left, right): (Vec<u32>, Vec<u32>) = members
                        .iter()
                        .partition(|m| boxes[**m as usize].center()[axis] < position);
                    let first = bvh.nodes.len();
                    for side in [&left, &right] {
                        bvh.nodes.push(BvhNode {
                            bounds: bounds_of(side),
                            first: 0,
                            count: 0,
                        });
                    }
                    bvh.nodes[index].first = first as u32;
                    bvh.nodes[index].count = 0;
                    work.push((first + 1, format!("{path}R"), right));
                    work.push((first, format!("{path}L"), left));
                }
                None => {
                    bvh.nodes[index].first = bvh.primitive_indices.len() as u32;
                    bvh.nodes[index].count = members.len() as u32;
                    bvh.primitive_indices.extend(&members);
                }
            }
        }
        bvh
    }

    /// The student's tree's SAH cost against the builder's.
    pub fn score(&self) -> BuildScore {
        let tree = self.tree();
        let student_cost = TreeStats::of(&tree, &self.cost).sah_cost;
        BuildScore {
            student_cost,
            builder_cost: self.builder_cost,
            ratio: if student_cost > 0.0 {
                self.builder_cost / student_cost
            } else {
                1.0
            },
        }
    }

    /// The student's tree checked by the core's validator.
    pub fn validate(&self) -> Result<(), String> {
        let boxes: Vec<Aabb<DVec2>> = self.shapes.shapes.iter().map(|s| s.bounds()).collect();
        validate(&self.tree(), &boxes).map_err(|error| error.to_string())
    }

    /// The next node as a step of the question.
    pub fn next_ask(&self) -> Option<Ask> {
        let choice = self.next_choice()?;
        let label = |pick: &Pick, count_left: Option<(usize, usize)>| match pick {
            Pick::Leaf => "keep a leaf".to_owned(),
            Pick::Split { axis, position } => {
                let (left, right) = count_left.unwrap_or_default();
                format!(
                    "split at {} = {} ({left} | {right})",
                    AXES[*axis],
                    num(*position)
                )
            }
        };
        let options: Vec<Choice> = choice
            .picks
            .iter()
            .map(|pick| {
                let counts = match pick {
                    Pick::Split { axis, position } => {
                        let left = choice
                            .shapes
                            .iter()
                            .filter(|m| {
                                self.shapes.shapes[**m as usize].bounds().center()[*axis]
                                    < *position
                            })
                            .count();
                        Some((left, choice.shapes.len() - left))
                    }
                    Pick::Leaf => None,
                };
                Choice::text(label(pick, counts))
            })
            .collect();
        let node = if choice.path.is_empty() {
            "the root".to_owned()
        } else {
            format!("node {}", choice.path)
        };
        let builder_label = options[choice.builder].label.clone();
        Some(Ask {
            prompt: format!(
                "Build the tree: how should {node} ({} shapes) be split?",
                choice.shapes.len()
            ),
            explanation: format!(
                "The SAH builder would {builder_label}, at cost {}; keeping a leaf costs {}.",
                num(choice.costs[choice.builder]),
                num(choice.costs[0])
            ),
            expected: Expected::Costed {
                options,
                costs: choice.costs.clone(),
            },
            highlight: Highlight {
                candidate: Some(choice.builder),
                ..Highlight::default()
            },
            frame: 0,
            needs: Vec::new(),
        })
    }
}
