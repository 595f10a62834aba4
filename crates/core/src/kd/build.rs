//! What the kD builders share: the top-down driver that cuts cells and sorts primitives into
//! the children they overlap.

use std::sync::atomic::{AtomicUsize, Ordering};

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
///
/// A splitter's own fields are settings and scratch space: its cuts depend only on the node it
/// is asked about, so a subtree can be built by a [`fork`](Self::fork) of it on another thread.
pub(crate) trait CellSplitter<V: Vector>: Send + Sized {
    /// What the splitter keeps for each node.
    type NodeData: Send;

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

    /// A splitter for a subtree built on another thread: the same settings, scratch of its
    /// own.
    fn fork(&self) -> Self;
}

/// A splitter with no per-node data: a fixed rule, and scratch space the rule may use.
struct Rule<'a, V: Vector, F> {
    rule: &'a F,
    bounds: &'a [Aabb<V>],
    scratch: Vec<V::Scalar>,
}

impl<V: Vector, F> CellSplitter<V> for Rule<'_, V, F>
where
    F: Fn(&Aabb<V>, &[u32], &[Aabb<V>], &mut Vec<V::Scalar>) -> Cut<V::Scalar> + Sync,
{
    type NodeData = ();

    fn root_data<O: BuildObserver>(&mut self, _cell: &Aabb<V>, _primitives: &[u32], _: &mut O) {}

    fn choose<O: BuildObserver>(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        _data: &(),
        _observer: &mut O,
    ) -> Result<(Cut<V::Scalar>, Option<f64>), LeafReason> {
        Ok((
            (self.rule)(cell, primitives, self.bounds, &mut self.scratch),
            None,
        ))
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

    fn fork(&self) -> Self {
        Rule {
            rule: self.rule,
            bounds: self.bounds,
            scratch: Vec::new(),
        }
    }
}

/// Builds top down with a fixed rule: a cell with more than `max_leaf_size` primitives (and
/// above the depth limit) is cut where `rule` says, strictly inside the cell, if the cut
/// separates anything; otherwise it becomes a leaf. The rule is handed the primitives' boxes
/// and scratch space of its own.
pub(crate) fn build_by_rule<V: Vector>(
    primitive_bounds: &[Aabb<V>],
    params: &BuildParams,
    observer: &mut impl BuildObserver,
    rule: impl Fn(&Aabb<V>, &[u32], &[Aabb<V>], &mut Vec<V::Scalar>) -> Cut<V::Scalar> + Sync,
) -> KdTree<V> {
    build_top_down(
        primitive_bounds,
        params,
        params.max_leaf_size,
        observer,
        || Rule {
            rule: &rule,
            bounds: primitive_bounds,
            scratch: Vec::new(),
        },
    )
}

/// The kD driver: cuts cells where the splitter says, sorts primitives into the children whose
/// cells they reach, and lays the nodes out flat with siblings side by side.
///
/// The tree grows to the depth limit `8 + 1.3 log₂ n` unless it would pass the node or
/// reference budget of `params.kd_budget`; then it is built again with the deepest limit that
/// fits (found by halving: the tree at a lower limit is a part of the tree at a higher one),
/// and [`KdTree::limits`] says so. `make_splitter` makes a fresh splitter for each attempt.
///
/// Unobserved, on a rayon pool of more than one thread, the upper levels' subtrees are built
/// at once ([`build_parallel`]); the tree is the same (tested).
#[inline(never)] // One call a build; kept apart so profiles can single it out.
pub(crate) fn build_top_down<V: Vector, S: CellSplitter<V>, O: BuildObserver>(
    primitive_bounds: &[Aabb<V>],
    params: &BuildParams,
    max_leaf_size: usize,
    observer: &mut O,
    mut make_splitter: impl FnMut() -> S,
) -> KdTree<V> {
    let count = primitive_bounds.len();
    let context = Context {
        primitive_bounds,
        max_leaf_size: max_leaf_size.max(1),
        depth_limit: max_depth(count),
        budget: Budget {
            nodes: params.kd_budget.nodes_for(count),
            references: params.kd_budget.references_for(count),
        },
    };
    let usual_limit = context.depth_limit;
    let first_try = build_within(&context, &mut make_splitter, observer);
    let exceeded = match first_try {
        Ok(tree) => return tree,
        Err(exceeded) => exceeded,
    };
    // Over budget: the deepest limit that fits. Depth 0 (one leaf) always does.
    let (mut fits, mut too_deep) = (0, usual_limit);
    while too_deep - fits > 1 {
        let middle = (fits + too_deep) / 2;
        let attempt = build_within(
            &Context {
                depth_limit: middle,
                ..context
            },
            &mut make_splitter,
            &mut NoBuildObserver,
        );
        match attempt {
            Ok(_) => fits = middle,
            Err(_) => too_deep = middle,
        }
    }
    observer.restarted();
    let last_try = build_within(
        &Context {
            depth_limit: fits,
            ..context
        },
        &mut make_splitter,
        observer,
    );
    let mut tree = last_try.unwrap_or_else(|_| unreachable!("depth {fits} fitted before"));
    tree.limits.lowered_from = Some((usual_limit, exceeded));
    tree
}

/// The node and reference budgets of one build.
#[derive(Clone, Copy)]
struct Budget {
    nodes: usize,
    references: usize,
}

/// What one attempt at a build is given.
#[derive(Clone, Copy)]
struct Context<'a, V: Vector> {
    primitive_bounds: &'a [Aabb<V>],
    max_leaf_size: usize,
    depth_limit: usize,
    budget: Budget,
}

/// A node waiting to be built: its cell, its primitives, the splitter's data and its depth.
struct Pending<V: Vector, D> {
    cell: Aabb<V>,
    primitives: Vec<u32>,
    data: D,
    depth: usize,
}

/// A cut made: the plane and its cost, and the two children waiting (data to come).
struct Division<V: Vector> {
    cut: Cut<V::Scalar>,
    cost: Option<f64>,
    below: (Aabb<V>, Vec<u32>),
    above: (Aabb<V>, Vec<u32>),
}

/// Decides a node: a leaf (why), or the cut with each child's cell and primitives. The
/// splitter's data is handed back either way.
fn try_cut<V: Vector, S: CellSplitter<V>, O: BuildObserver>(
    context: &Context<V>,
    splitter: &mut S,
    node: &Pending<V, S::NodeData>,
    observer: &mut O,
) -> Result<Division<V>, LeafReason> {
    let Pending {
        cell,
        primitives,
        data,
        depth,
    } = node;
    let (cut, cost) = if primitives.len() <= context.max_leaf_size {
        return Err(LeafReason::SmallEnough {
            count: primitives.len(),
            max_leaf_size: context.max_leaf_size,
        });
    } else if *depth >= context.depth_limit {
        return Err(LeafReason::DepthLimit {
            limit: context.depth_limit,
        });
    } else {
        splitter.choose(cell, primitives, data, observer)?
    };
    if !(cell.min[cut.axis] < cut.position && cut.position < cell.max[cut.axis]) {
        return Err(LeafReason::Inseparable {
            count: primitives.len(),
        });
    }
    let mut below_cell = *cell;
    let mut above_cell = *cell;
    below_cell.max[cut.axis] = cut.position;
    above_cell.min[cut.axis] = cut.position;
    splitter.classify(data, &cut, &below_cell, &above_cell);
    // Sort each primitive into the children whose cells it reaches.
    let mut below = Vec::with_capacity(primitives.len());
    let mut above = Vec::with_capacity(primitives.len());
    for &primitive in primitives {
        let bounds = &context.primitive_bounds[primitive as usize];
        let (is_below, is_above) = splitter.sides_of(primitive, &cut, bounds);
        if is_below {
            below.push(primitive);
        }
        if is_above {
            above.push(primitive);
        }
    }
    // A cut that leaves every primitive on both sides gains nothing.
    if below.len() == primitives.len() && above.len() == primitives.len() {
        return Err(LeafReason::Inseparable {
            count: primitives.len(),
        });
    }
    Ok(Division {
        cut,
        cost,
        below: (below_cell, below),
        above: (above_cell, above),
    })
}

/// Why a build stopped before its tree was done.
enum Stop {
    /// It passed a budget.
    Exceeded(KdBudgetExceeded),
    /// A parallel build cannot tell whether the sequential one would pass a budget (a cut
    /// dropped a primitive from both sides): the sequential driver must decide.
    Unsure,
}

/// Counts what a build has made against its budgets.
trait Tally {
    /// Counts a cut whose children hold `added` references in place of their parent's
    /// `removed`, and two new nodes.
    fn count_cut(&mut self, added: usize, removed: usize) -> Result<(), Stop>;
}

/// The sequential driver's running counts: the budget is checked at each cut, in its order.
struct Running<'a> {
    budget: &'a Budget,
    nodes: usize,
    references: usize,
}

impl Tally for Running<'_> {
    fn count_cut(&mut self, added: usize, removed: usize) -> Result<(), Stop> {
        self.references = self.references + added - removed;
        self.nodes += 2;
        if self.nodes > self.budget.nodes {
            return Err(Stop::Exceeded(KdBudgetExceeded::Nodes(self.budget.nodes)));
        }
        if self.references > self.budget.references {
            return Err(Stop::Exceeded(KdBudgetExceeded::References(
                self.budget.references,
            )));
        }
        Ok(())
    }
}

/// A parallel build's counts, shared by its threads. While every cut keeps or adds
/// references, the counts only grow, so the sequential driver passes a budget exactly when
/// the totals do, whatever order the threads count in.
struct Shared<'a> {
    budget: &'a Budget,
    nodes: AtomicUsize,
    references: AtomicUsize,
}

impl Tally for &Shared<'_> {
    fn count_cut(&mut self, added: usize, removed: usize) -> Result<(), Stop> {
        if added < removed {
            return Err(Stop::Unsure);
        }
        let nodes = self.nodes.fetch_add(2, Ordering::Relaxed) + 2;
        let references = self
            .references
            .fetch_add(added - removed, Ordering::Relaxed);
        if nodes > self.budget.nodes || references + added - removed > self.budget.references {
            return Err(Stop::Unsure);
        }
        Ok(())
    }
}

/// A subtree as the sequential driver lays it out, its root at 0: nodes, the primitive
/// references of its leaves (leaves' `first` counted from 0), and its leaves at the depth
/// limit.
struct Subtree<V: Vector> {
    nodes: Vec<KdNode<V::Scalar>>,
    primitive_indices: Vec<u32>,
    leaves_at_depth_limit: usize,
}

/// Builds with `context.depth_limit`, or stops as soon as the tree passes a budget and says
/// which.
fn build_within<V: Vector, S: CellSplitter<V>, O: BuildObserver>(
    context: &Context<V>,
    make_splitter: &mut impl FnMut() -> S,
    observer: &mut O,
) -> Result<KdTree<V>, KdBudgetExceeded> {
    let root_cell = context
        .primitive_bounds
        .iter()
        .fold(Aabb::empty(), |acc, bounds| acc.union(*bounds));
    let count = context.primitive_bounds.len();
    // Over budget, or maybe, a parallel build stops: the sequential driver says which, in its
    // order.
    if !O::ACTIVE
        && count >= 2 * PARALLEL_GRAIN
        && crate::parallel::has_threads()
        && let Ok(tree) = build_parallel(context, root_cell, make_splitter())
    {
        return Ok(tree);
    }
    let mut splitter = make_splitter();
    let all: Vec<u32> = (0..count as u32).collect();
    observer.node_started(0, 0, count);
    let data = splitter.root_data(&root_cell, &all, observer);
    let root = Pending {
        cell: root_cell,
        primitives: all,
        data,
        depth: 0,
    };
    let mut tally = Running {
        budget: &context.budget,
        nodes: 1,
        references: count,
    };
    match grow_subtree(context, &mut splitter, root, &mut tally, observer) {
        Ok(subtree) => Ok(KdTree {
            bounds: root_cell,
            nodes: subtree.nodes,
            primitive_indices: subtree.primitive_indices,
            limits: KdLimits {
                depth_limit: context.depth_limit,
                leaves_at_depth_limit: subtree.leaves_at_depth_limit,
                lowered_from: None,
            },
        }),
        Err(Stop::Exceeded(exceeded)) => Err(exceeded),
        Err(Stop::Unsure) => unreachable!("the running count always knows"),
    }
}

/// Builds the subtree of `root` (whose `node_started` the caller has told `observer`), a node
/// at a time, the side below each plane first.
fn grow_subtree<V: Vector, S: CellSplitter<V>, O: BuildObserver>(
    context: &Context<V>,
    splitter: &mut S,
    root: Pending<V, S::NodeData>,
    tally: &mut impl Tally,
    observer: &mut O,
) -> Result<Subtree<V>, Stop> {
    let mut subtree = Subtree {
        nodes: vec![KdNode {
            split: V::Scalar::ZERO,
            axis: KdNode::<V::Scalar>::LEAF,
            first: 0,
            count: 0,
        }],
        primitive_indices: Vec::new(),
        leaves_at_depth_limit: 0,
    };
    let mut work = vec![(0usize, root)];
    while let Some((node_index, node)) = work.pop() {
        if node_index != 0 {
            observer.node_started(node_index as u32, node.depth, node.primitives.len());
        }
        let division = match try_cut(context, splitter, &node, observer) {
            Ok(division) => division,
            Err(reason) => {
                if let LeafReason::DepthLimit { .. } = reason {
                    subtree.leaves_at_depth_limit += 1;
                }
                splitter.discard(node.data);
                subtree.nodes[node_index] = leaf(&mut subtree.primitive_indices, &node.primitives);
                observer.leaf(node_index as u32, reason);
                continue;
            }
        };
        let Division {
            cut,
            cost,
            below,
            above,
        } = division;
        tally.count_cut(below.1.len() + above.1.len(), node.primitives.len())?;
        let left = subtree.nodes.len();
        subtree.nodes[node_index] = interior(&cut, left);
        let placeholder = subtree.nodes[node_index];
        subtree.nodes.extend([placeholder, placeholder]);
        observer.split(node_index as u32, Children::pair(left as u32), cost);
        let (below_data, above_data) =
            splitter.divide(node.data, &cut, &below.0, &above.0, observer);
        // Above first on the work list, so the subtree below the plane is laid out first.
        for (index, (cell, primitives), data) in
            [(left + 1, above, above_data), (left, below, below_data)]
        {
            let depth = node.depth + 1;
            work.push((
                index,
                Pending {
                    cell,
                    primitives,
                    data,
                    depth,
                },
            ));
        }
    }
    Ok(subtree)
}

/// A leaf of `primitives`, appended to `primitive_indices`.
fn leaf<S: Real>(primitive_indices: &mut Vec<u32>, primitives: &[u32]) -> KdNode<S> {
    let first = primitive_indices.len() as u32;
    primitive_indices.extend_from_slice(primitives);
    KdNode {
        split: S::ZERO,
        axis: KdNode::<S>::LEAF,
        first,
        count: primitives.len() as u32,
    }
}

/// An interior node cut by `cut`, its children at `left` and `left + 1`.
fn interior<S: Real>(cut: &Cut<S>, left: usize) -> KdNode<S> {
    KdNode {
        split: cut.position,
        axis: cut.axis as u32,
        first: left as u32,
        count: 0,
    }
}

/// A node needs at least this many primitives for its two sides to be built at once: below
/// it, handing a side to another thread costs more than it saves.
const PARALLEL_GRAIN: usize = 2048;

/// Forks nest at most this deep; deeper subtrees are built by the sequential driver.
const MAX_FORK_DEPTH: usize = 12;

/// A subtree built in parallel: the pieces before they are laid out as one tree.
enum Part<V: Vector> {
    /// A subtree from the sequential driver.
    Grown(Subtree<V>),
    /// A node whose two sides were built at once: the node, then the parts below and above.
    Forked(KdNode<V::Scalar>, Box<[Part<V>; 2]>),
}

/// [`build_within`] on every thread of the current rayon pool: a node of at least twice
/// [`PARALLEL_GRAIN`] primitives, once cut, has its two sides built at once by forks of the
/// splitter (`rayon::join`; work stealing balances lopsided cuts). The cuts are the
/// splitter's on the same nodes, and the pieces are laid out as the sequential driver lays
/// them out, so the tree is the same. A build that passes a budget, or may, stops: the
/// sequential driver then decides it.
fn build_parallel<V: Vector, S: CellSplitter<V>>(
    context: &Context<V>,
    root_cell: Aabb<V>,
    mut splitter: S,
) -> Result<KdTree<V>, Stop> {
    let count = context.primitive_bounds.len();
    let all: Vec<u32> = (0..count as u32).collect();
    let data = splitter.root_data(&root_cell, &all, &mut NoBuildObserver);
    let root = Pending {
        cell: root_cell,
        primitives: all,
        data,
        depth: 0,
    };
    let shared = Shared {
        budget: &context.budget,
        nodes: AtomicUsize::new(1),
        references: AtomicUsize::new(count),
    };
    let part = grow_parallel(context, splitter, root, 0, &shared)?;
    let mut tree = KdTree {
        bounds: root_cell,
        nodes: Vec::with_capacity(shared.nodes.load(Ordering::Relaxed)),
        primitive_indices: Vec::with_capacity(shared.references.load(Ordering::Relaxed)),
        limits: KdLimits {
            depth_limit: context.depth_limit,
            leaves_at_depth_limit: 0,
            lowered_from: None,
        },
    };
    tree.nodes.push(KdNode {
        split: V::Scalar::ZERO,
        axis: KdNode::<V::Scalar>::LEAF,
        first: 0,
        count: 0,
    });
    lay_out(part, 0, &mut tree);
    Ok(tree)
}

/// Builds the subtree of `node` (`forks` deep in forks), its sides at once where it is big
/// enough.
fn grow_parallel<V: Vector, S: CellSplitter<V>>(
    context: &Context<V>,
    mut splitter: S,
    node: Pending<V, S::NodeData>,
    forks: usize,
    shared: &Shared,
) -> Result<Part<V>, Stop> {
    if node.primitives.len() < 2 * PARALLEL_GRAIN || forks >= MAX_FORK_DEPTH {
        let mut tally = shared;
        let subtree = grow_subtree(
            context,
            &mut splitter,
            node,
            &mut tally,
            &mut NoBuildObserver,
        )?;
        return Ok(Part::Grown(subtree));
    }
    let Division {
        cut,
        cost: _,
        below,
        above,
    } = match try_cut(context, &mut splitter, &node, &mut NoBuildObserver) {
        Ok(division) => division,
        Err(reason) => {
            let mut primitive_indices = Vec::new();
            let leaf = leaf(&mut primitive_indices, &node.primitives);
            return Ok(Part::Grown(Subtree {
                nodes: vec![leaf],
                primitive_indices,
                leaves_at_depth_limit: matches!(reason, LeafReason::DepthLimit { .. }) as usize,
            }));
        }
    };
    let mut tally = shared;
    tally.count_cut(below.1.len() + above.1.len(), node.primitives.len())?;
    let (below_data, above_data) =
        splitter.divide(node.data, &cut, &below.0, &above.0, &mut NoBuildObserver);
    let other = splitter.fork();
    let depth = node.depth + 1;
    let pending = |(cell, primitives), data| Pending {
        cell,
        primitives,
        data,
        depth,
    };
    let (below_part, above_part) = rayon::join(
        || {
            grow_parallel(
                context,
                splitter,
                pending(below, below_data),
                forks + 1,
                shared,
            )
        },
        || {
            grow_parallel(
                context,
                other,
                pending(above, above_data),
                forks + 1,
                shared,
            )
        },
    );
    // The placeholder's `first` is set when the part is laid out.
    Ok(Part::Forked(
        interior(&cut, 0),
        Box::new([below_part?, above_part?]),
    ))
}

/// Writes `part`, whose root's place is `tree.nodes[at]`, into `tree`: its descendants and its
/// leaves' primitive references appended in the sequential driver's order, every `first`
/// made absolute.
fn lay_out<V: Vector>(part: Part<V>, at: usize, tree: &mut KdTree<V>) {
    match part {
        Part::Grown(subtree) => {
            // The subtree's node k > 0 lands at base + k - 1.
            let base = tree.nodes.len();
            let references = tree.primitive_indices.len();
            let place = |node: KdNode<V::Scalar>| KdNode {
                first: if node.is_leaf() {
                    (references + node.first as usize) as u32
                } else {
                    (base + node.first as usize - 1) as u32
                },
                ..node
            };
            let mut nodes = subtree.nodes.into_iter();
            if let Some(root) = nodes.next() {
                tree.nodes[at] = place(root);
            }
            tree.nodes.extend(nodes.map(place));
            tree.primitive_indices
                .extend_from_slice(&subtree.primitive_indices);
            tree.limits.leaves_at_depth_limit += subtree.leaves_at_depth_limit;
        }
        Part::Forked(node, sides) => {
            let left = tree.nodes.len();
            tree.nodes[at] = KdNode {
                first: left as u32,
                ..node
            };
            tree.nodes.extend([node, node]);
            let [below, above] = *sides;
            lay_out(below, left, tree);
            lay_out(above, left + 1, tree);
        }
    }
}
