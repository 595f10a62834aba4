//! What the kD builders share: the top-down driver that cuts cells and sorts primitives into
//! the children they overlap.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReason, NoBuildObserver};
use crate::facts::Children;
use crate::kd::tree::{KdBudgetExceeded, KdLimits, KdNode, KdTree};
use crate::math::{Real, Vector};
use crate::params::BuildParams;

/// A kD-tree construction algorithm.
pub trait KdBuilder {
    /// A short name, e.g. `middle`.
    fn name(&self) -> String;

    /// Builds a kD-tree over primitives with these boxes, telling `observer` about each node:
    /// what it sorted and swept, where it cut, and why each leaf is a leaf.
    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> KdTree<V>;

    /// Builds a kD-tree over primitives with these boxes.
    fn build<V: Vector>(&self, primitive_bounds: &[Aabb<V>], params: &BuildParams) -> KdTree<V> {
        self.build_observed(primitive_bounds, params, &mut NoBuildObserver)
    }
}

/// The depth past which no cell is cut: `8 + 1.3 log₂ n` (pbrt-v3 §4.4.2), so that a scene
/// whose primitives all overlap cannot make the tree grow without end.
pub(crate) fn max_depth(primitive_count: usize) -> usize {
    (8.0 + 1.3 * (primitive_count.max(1) as f64).log2()).round() as usize
}

/// A cut of a cell: the plane, and the side given to primitives lying flat in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cut<S> {
    /// The axis the plane is perpendicular to.
    pub(crate) axis: usize,
    /// Where the plane crosses that axis.
    pub(crate) position: S,
    /// Where a primitive lying in the plane goes: below (true) or above.
    pub(crate) planar_below: bool,
}

impl<S: Real> Cut<S> {
    /// A cut that puts primitives lying in the plane below it.
    pub(crate) fn new(axis: usize, position: S) -> Self {
        Self {
            axis,
            position,
            planar_below: true,
        }
    }

    /// Which children a primitive box goes to: `(below, above)`. A box reaching across the
    /// plane goes to both. A box that only touches the plane goes to the side holding the rest
    /// of it: a ray meets it at the plane from either side, and the traversal visits both cells
    /// whenever the ray reaches the plane. A box lying in the plane goes to one side, chosen
    /// by the builder (Wald & Havran 2006, §4.2), so no primitive is listed twice for merely
    /// touching a plane. Triangle meshes share vertices, so that matters: every plane through
    /// a vertex touches several triangles.
    #[inline]
    pub(crate) fn sides<V: Vector<Scalar = S>>(&self, bounds: &Aabb<V>) -> (bool, bool) {
        let (low, high) = (bounds.min[self.axis], bounds.max[self.axis]);
        if low == self.position && high == self.position {
            (self.planar_below, !self.planar_below)
        } else {
            (low < self.position, high > self.position)
        }
    }
}

/// How a kD builder decides cuts. Beyond each node's primitive list, a splitter may keep its
/// own per-node data (`NodeData`: presorted events, say), handed down from parent to children.
pub(crate) trait CellSplitter<V: Vector> {
    /// What the splitter keeps for each node.
    type NodeData;

    /// The root's data (what the splitter sorts once, it tells `observer`).
    fn root_data<O: BuildObserver>(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        observer: &mut O,
    ) -> Self::NodeData;

    /// Where to cut `cell` (with the cut's SAH cost, where weighed), or why it stays a leaf.
    /// What the splitter sorts and sweeps on the way it tells `observer`.
    fn choose<O: BuildObserver>(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        data: &Self::NodeData,
        observer: &mut O,
    ) -> Result<(Cut<V::Scalar>, Option<f64>), LeafReason>;

    /// The children's data once `cut` is made (`below` and `above` are the child cells).
    fn divide<O: BuildObserver>(
        &mut self,
        data: Self::NodeData,
        cut: &Cut<V::Scalar>,
        below: &Aabb<V>,
        above: &Aabb<V>,
        observer: &mut O,
    ) -> (Self::NodeData, Self::NodeData);

    /// Decides which children each primitive goes to, before [`sides_of`](Self::sides_of) is
    /// asked (`below` and `above` are the child cells).
    fn classify(
        &mut self,
        _data: &Self::NodeData,
        _cut: &Cut<V::Scalar>,
        _below: &Aabb<V>,
        _above: &Aabb<V>,
    ) {
    }

    /// Which children `primitive` (with box `bounds`) goes to: by default, by its box.
    fn sides_of(&self, _primitive: u32, cut: &Cut<V::Scalar>, bounds: &Aabb<V>) -> (bool, bool) {
        cut.sides(bounds)
    }

    /// Called with the data of a node that becomes a leaf, so the splitter can reuse it.
    fn discard(&mut self, _data: Self::NodeData) {}
}

/// A splitter with no per-node data: a fixed rule.
struct Rule<F>(F);

impl<V: Vector, F: FnMut(&Aabb<V>, &[u32]) -> Cut<V::Scalar>> CellSplitter<V> for Rule<F> {
    type NodeData = ();

    fn root_data<O: BuildObserver>(&mut self, _cell: &Aabb<V>, _primitives: &[u32], _: &mut O) {}

    fn choose<O: BuildObserver>(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        _data: &(),
        _observer: &mut O,
    ) -> Result<(Cut<V::Scalar>, Option<f64>), LeafReason> {
        Ok(((self.0)(cell, primitives), None))
    }

    fn divide<O: BuildObserver>(
        &mut self,
        _: (),
        _: &Cut<V::Scalar>,
        _: &Aabb<V>,
        _: &Aabb<V>,
        _: &mut O,
    ) -> ((), ()) {
        ((), ())
    }
}

/// Builds top down with a fixed rule: a cell with more than `max_leaf_size` primitives (and
/// above the depth limit) is cut where `rule` says, strictly inside the cell, if the cut
/// separates anything; otherwise it becomes a leaf.
pub(crate) fn build_by_rule<V: Vector>(
    primitive_bounds: &[Aabb<V>],
    params: &BuildParams,
    observer: &mut impl BuildObserver,
    rule: impl Fn(&Aabb<V>, &[u32], &[Aabb<V>]) -> Cut<V::Scalar>,
) -> KdTree<V> {
    build_top_down(
        primitive_bounds,
        params,
        params.max_leaf_size,
        observer,
        || Rule(|cell: &Aabb<V>, primitives: &[u32]| rule(cell, primitives, primitive_bounds)),
    )
}

/// The kD driver: cuts cells where the splitter says, sorts primitives into the children whose
/// cells they reach, and lays the nodes out flat with siblings side by side.
///
/// The tree grows to the depth limit `8 + 1.3 log₂ n` unless it would pass the node or
/// reference budget of `params.kd_budget`; then it is built again with the deepest limit that
/// fits (found by halving: the tree at a lower limit is a part of the tree at a higher one),
/// and [`KdTree::limits`] says so. `make_splitter` makes a fresh splitter for each attempt.
#[inline(never)] // One call a build; kept apart so profiles can single it out.
pub(crate) fn build_top_down<V: Vector, S: CellSplitter<V>, O: BuildObserver>(
    primitive_bounds: &[Aabb<V>],
    params: &BuildParams,
    max_leaf_size: usize,
    observer: &mut O,
    mut make_splitter: impl FnMut() -> S,
) -> KdTree<V> {
    let count = primitive_bounds.len();
    let budget = Budget {
        nodes: params.kd_budget.nodes_for(count),
        references: params.kd_budget.references_for(count),
    };
    let usual_limit = max_depth(count);
    let first_try = build_within(
        primitive_bounds,
        max_leaf_size,
        usual_limit,
        &budget,
        make_splitter(),
        observer,
    );
    let exceeded = match first_try {
        Ok(tree) => return tree,
        Err(exceeded) => exceeded,
    };
    // Over budget: the deepest limit that fits. Depth 0 (one leaf) always does.
    let (mut fits, mut too_deep) = (0, usual_limit);
    while too_deep - fits > 1 {
        let middle = (fits + too_deep) / 2;
        let attempt = build_within(
            primitive_bounds,
            max_leaf_size,
            middle,
            &budget,
            make_splitter(),
            &mut NoBuildObserver,
        );
        match attempt {
            Ok(_) => fits = middle,
            Err(_) => too_deep = middle,
        }
    }
    observer.restarted();
    let last_try = build_within(
        primitive_bounds,
        max_leaf_size,
        fits,
        &budget,
        make_splitter(),
        observer,
    );
    let mut tree = last_try.unwrap_or_else(|_| unreachable!("depth {fits} fitted before"));
    tree.limits.lowered_from = Some((usual_limit, exceeded));
    tree
}

/// The node and reference budgets of one build.
struct Budget {
    nodes: usize,
    references: usize,
}

/// Builds with `depth_limit`, or stops as soon as the tree passes a budget and says which.
fn build_within<V: Vector, S: CellSplitter<V>, O: BuildObserver>(
    primitive_bounds: &[Aabb<V>],
    max_leaf_size: usize,
    depth_limit: usize,
    budget: &Budget,
    mut splitter: S,
    observer: &mut O,
) -> Result<KdTree<V>, KdBudgetExceeded> {
    let root_cell = primitive_bounds
        .iter()
        .fold(Aabb::empty(), |acc, bounds| acc.union(*bounds));
    let max_leaf_size = max_leaf_size.max(1);
    let mut nodes = vec![KdNode {
        split: V::Scalar::ZERO,
        axis: KdNode::<V::Scalar>::LEAF,
        first: 0,
        count: 0,
    }];
    let mut primitive_indices = Vec::new();
    let all: Vec<u32> = (0..primitive_bounds.len() as u32).collect();
    // Primitive references in leaves and on the work list: what the leaves will hold.
    let mut references = all.len();
    let mut limits = KdLimits {
        depth_limit,
        leaves_at_depth_limit: 0,
        lowered_from: None,
    };
    observer.node_started(0, 0, all.len());
    let root_data = splitter.root_data(&root_cell, &all, observer);
    let mut work = vec![(0usize, root_cell, all, root_data, 0usize)];
    while let Some((node_index, cell, primitives, data, depth)) = work.pop() {
        if node_index != 0 {
            observer.node_started(node_index as u32, depth, primitives.len());
        }
        let decision = if primitives.len() <= max_leaf_size {
            Err(LeafReason::SmallEnough {
                count: primitives.len(),
                max_leaf_size,
            })
        } else if depth >= depth_limit {
            limits.leaves_at_depth_limit += 1;
            Err(LeafReason::DepthLimit { limit: depth_limit })
        } else {
            splitter.choose(&cell, &primitives, &data, observer)
        };
        let children = decision.and_then(|(cut, cost)| {
            if !(cell.min[cut.axis] < cut.position && cut.position < cell.max[cut.axis]) {
                return Err(LeafReason::Inseparable {
                    count: primitives.len(),
                });
            }
            let mut below_cell = cell;
            let mut above_cell = cell;
            below_cell.max[cut.axis] = cut.position;
            above_cell.min[cut.axis] = cut.position;
            splitter.classify(&data, &cut, &below_cell, &above_cell);
            // Sort each primitive into the children whose cells it reaches.
            let mut below = Vec::with_capacity(primitives.len());
            let mut above = Vec::with_capacity(primitives.len());
            for &primitive in &primitives {
                let bounds = &primitive_bounds[primitive as usize];
                let (is_below, is_above) = splitter.sides_of(primitive, &cut, bounds);
                if is_below {
                    below.push(primitive);
                }
                if is_above {
                    above.push(primitive);
                }
            }
            // A cut that leaves every primitive on both sides gains nothing.
            let separates = below.len() < primitives.len() || above.len() < primitives.len();
            if separates {
                Ok((cut, cost, below, above, below_cell, above_cell))
            } else {
                Err(LeafReason::Inseparable {
                    count: primitives.len(),
                })
            }
        });
        let (cut, cost, below, above, below_cell, above_cell) = match children {
            Ok(children) => children,
            Err(reason) => {
                splitter.discard(data);
                nodes[node_index] = KdNode {
                    split: V::Scalar::ZERO,
                    axis: KdNode::<V::Scalar>::LEAF,
                    first: primitive_indices.len() as u32,
                    count: primitives.len() as u32,
                };
                primitive_indices.extend_from_slice(&primitives);
                observer.leaf(node_index as u32, reason);
                continue;
            }
        };
        references = references + below.len() + above.len() - primitives.len();
        if nodes.len() + 2 > budget.nodes {
            return Err(KdBudgetExceeded::Nodes(budget.nodes));
        }
        if references > budget.references {
            return Err(KdBudgetExceeded::References(budget.references));
        }
        let left = nodes.len();
        nodes[node_index] = KdNode {
            split: cut.position,
            axis: cut.axis as u32,
            first: left as u32,
            count: 0,
        };
        let leaf = nodes[node_index];
        nodes.push(leaf);
        nodes.push(leaf);
        observer.split(node_index as u32, Children::pair(left as u32), cost);
        let (below_data, above_data) =
            splitter.divide(data, &cut, &below_cell, &above_cell, observer);
        // Above first on the work list, so the subtree below the plane is laid out first.
        work.push((left + 1, above_cell, above, above_data, depth + 1));
        work.push((left, below_cell, below, below_data, depth + 1));
    }
    Ok(KdTree {
        bounds: root_cell,
        nodes,
        primitive_indices,
        limits,
    })
}
