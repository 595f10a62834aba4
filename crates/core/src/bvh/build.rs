//! What every BVH builder shares: the [`Builder`] trait, and the top-down driver that turns a
//! splitter's decisions into flat nodes.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReason, NoBuildObserver};
use crate::bvh::tree::{Bvh, BvhNode};
use crate::facts::Children;
use crate::math::Vector;
use crate::params::BuildParams;

/// A BVH construction algorithm.
pub trait Builder {
    /// A short name, e.g. `sah-binned:16`.
    fn name(&self) -> String;

    /// Builds a BVH over primitives with these boxes (primitive `i` has `primitive_bounds[i]`),
    /// telling `observer` about each node: where it splits, and why each leaf is a leaf.
    fn build_observed<V: Vector, O: BuildObserver>(
        &self,
        primitive_bounds: &[Aabb<V>],
        params: &BuildParams,
        observer: &mut O,
    ) -> Bvh<V>;

    /// Builds a BVH over primitives with these boxes (primitive `i` has `primitive_bounds[i]`).
    fn build<V: Vector>(&self, primitive_bounds: &[Aabb<V>], params: &BuildParams) -> Bvh<V> {
        self.build_observed(primitive_bounds, params, &mut NoBuildObserver)
    }
}

/// A split of the range `begin..end` into `begin..mid` and `mid..end`, with what the
/// splitter already knows of each child (its box, and its own per-node notes).
pub(crate) struct Split<V: Vector, Info> {
    pub(crate) mid: usize,
    /// The split's SAH cost, where the splitter weighed it.
    pub(crate) cost: Option<f64>,
    pub(crate) left: (Aabb<V>, Info),
    pub(crate) right: (Aabb<V>, Info),
}

/// How a builder chooses splits. It owns the order of the primitives; a node is a range
/// `begin..end` of that order.
pub(crate) trait RangeSplitter<V: Vector> {
    /// What a splitter learns about a child while splitting its parent and wants back when it
    /// splits the child (e.g. the box around the child's centroids).
    type NodeInfo;

    /// The root: the box around every primitive, and its notes.
    fn root(&self) -> (Aabb<V>, Self::NodeInfo);

    /// Reorders `begin..end` so that the left child is `begin..mid` (`begin < mid < end`), or
    /// says why the node stays a leaf. Called only for nodes of two or more primitives.
    fn split(
        &mut self,
        begin: usize,
        end: usize,
        node_bounds: &Aabb<V>,
        info: &Self::NodeInfo,
    ) -> Result<Split<V, Self::NodeInfo>, LeafReason>;

    /// The final order of the primitives: the BVH's `primitive_indices`.
    fn into_order(self) -> Vec<u32>;
}

/// Builds the tree top down with an explicit work list (no recursion, so degenerate inputs
/// cannot overflow the call stack). Siblings are allocated together.
pub(crate) fn build_top_down<V: Vector, S: RangeSplitter<V>, O: BuildObserver>(
    mut splitter: S,
    primitive_count: usize,
    max_leaf_size: usize,
    observer: &mut O,
) -> Bvh<V> {
    if primitive_count == 0 {
        return Bvh::default();
    }
    let (root_bounds, root_info) = splitter.root();
    let nodes = grow_subtree(
        &mut splitter,
        root_bounds,
        (0, primitive_count),
        root_info,
        0,
        max_leaf_size,
        observer,
    );
    Bvh {
        nodes,
        primitive_indices: splitter.into_order(),
    }
}

/// The subtree of the node over `begin..end` (with its box and the splitter's notes, at
/// `depth`), laid out as the whole tree is: the node first (index 0), then its children side
/// by side, then the left child's subtree, then the right's. Interior nodes' `first` counts
/// from the returned list's start; leaves' `first` is a position in the splitter's order.
fn grow_subtree<V: Vector, S: RangeSplitter<V>, O: BuildObserver>(
    splitter: &mut S,
    bounds: Aabb<V>,
    (begin, end): (usize, usize),
    info: S::NodeInfo,
    depth: usize,
    max_leaf_size: usize,
    observer: &mut O,
) -> Vec<BvhNode<V>> {
    // At most two nodes a primitive (a leaf holds at least one).
    let mut nodes = Vec::with_capacity(2 * (end - begin));
    nodes.push(BvhNode {
        bounds,
        first: begin as u32,
        count: (end - begin) as u32,
    });
    let mut work = vec![(0usize, begin, end, info, depth)];
    while let Some((node_index, begin, end, info, depth)) = work.pop() {
        observer.node_started(node_index as u32, depth, end - begin);
        let node_bounds = nodes[node_index].bounds;
        let split = if end - begin > 1 {
            splitter.split(begin, end, &node_bounds, &info)
        } else {
            Err(LeafReason::SmallEnough {
                count: end - begin,
                max_leaf_size,
            })
        };
        let Split {
            mid,
            cost,
            left,
            right,
        } = match split {
            Ok(split) => split,
            Err(reason) => {
                nodes[node_index].first = begin as u32;
                nodes[node_index].count = (end - begin) as u32;
                observer.leaf(node_index as u32, reason);
                continue;
            }
        };
        debug_assert!(
            begin < mid && mid < end,
            "a splitter returned an empty side"
        );
        let left_index = nodes.len();
        nodes[node_index].first = left_index as u32;
        nodes[node_index].count = 0;
        for (bounds, child_begin, child_end) in [(left.0, begin, mid), (right.0, mid, end)] {
            nodes.push(BvhNode {
                bounds,
                first: child_begin as u32,
                count: (child_end - child_begin) as u32,
            });
        }
        observer.split(node_index as u32, Children::pair(left_index as u32), cost);
        // Right first on the work list, so the left subtree is built (and laid out) first.
        work.push((left_index + 1, mid, end, right.1, depth + 1));
        work.push((left_index, begin, mid, left.1, depth + 1));
    }
    nodes
}

/// A splitter whose two sides of a split can be built at once: it hands each side its own
/// part of the primitives' order (disjoint, so the threads share nothing).
pub(crate) trait ForkingSplitter<V: Vector>: RangeSplitter<V> + Send + Sized
where
    Self::NodeInfo: Send,
{
    /// The splitters of `begin..mid` and `mid..end`, for a splitter holding exactly the
    /// range `begin..end` of a node just split at `mid`.
    fn fork(self, mid: usize) -> (Self, Self);
}

/// A node needs at least this many primitives for its two sides to be built in parallel:
/// below it, handing a side to another thread costs more than it saves.
const PARALLEL_GRAIN: usize = 4096;

/// Forks nest at most this deep (a lopsided tree would otherwise deepen the call stack by
/// one frame a level); deeper subtrees are built by the sequential driver.
const MAX_FORK_DEPTH: usize = 16;

/// A subtree built in parallel: the pieces before they are laid out as one list.
enum Part<V: Vector> {
    /// A subtree from the sequential driver ([`grow_subtree`]'s layout).
    Grown(Vec<BvhNode<V>>),
    /// A node whose two sides were built at once: its box, then the left and right parts.
    Forked(Aabb<V>, Box<[Part<V>; 2]>),
}

/// [`build_top_down`] on every thread of the current rayon pool: a node of at least twice
/// [`PARALLEL_GRAIN`] primitives, once split, has its two sides built at once (`rayon::join`;
/// work stealing balances lopsided splits). The splits are the splitter's, made on the same
/// ranges in the same state, and the pieces are laid out as the sequential driver lays them
/// out, so the tree is identical on any number of threads (tested), one included, and to the
/// observed sequential build's. Returns the nodes; the order of the primitives is left in the
/// splitter's storage.
pub(crate) fn build_top_down_parallel<V: Vector, S: ForkingSplitter<V>>(
    splitter: S,
    primitive_count: usize,
    max_leaf_size: usize,
) -> Vec<BvhNode<V>>
where
    S::NodeInfo: Send,
{
    if primitive_count == 0 {
        return Vec::new();
    }
    let (bounds, info) = splitter.root();
    let root = grow_parallel(
        splitter,
        bounds,
        (0, primitive_count),
        info,
        (0, 0),
        max_leaf_size,
    );
    let mut nodes = Vec::with_capacity(2 * primitive_count.div_ceil(max_leaf_size.max(1)));
    nodes.push(BvhNode {
        bounds,
        first: 0,
        count: 0,
    });
    lay_out(root, 0, &mut nodes);
    nodes
}

/// Builds the subtree of `begin..end` (`depth` deep in the tree, `forks` deep in forks), its
/// sides at once where the node is big enough.
fn grow_parallel<V: Vector, S: ForkingSplitter<V>>(
    mut splitter: S,
    bounds: Aabb<V>,
    (begin, end): (usize, usize),
    info: S::NodeInfo,
    (depth, forks): (usize, usize),
    max_leaf_size: usize,
) -> Part<V>
where
    S::NodeInfo: Send,
{
    let sequential = |mut splitter: S, info| {
        Part::Grown(grow_subtree(
            &mut splitter,
            bounds,
            (begin, end),
            info,
            depth,
            max_leaf_size,
            &mut NoBuildObserver,
        ))
    };
    if end - begin < 2 * PARALLEL_GRAIN || forks >= MAX_FORK_DEPTH {
        return sequential(splitter, info);
    }
    let Ok(split) = splitter.split(begin, end, &bounds, &info) else {
        // A leaf (the splitter keeps its reasons for the observed build).
        return Part::Grown(vec![BvhNode {
            bounds,
            first: begin as u32,
            count: (end - begin) as u32,
        }]);
    };
    let (left, right) = splitter.fork(split.mid);
    let next = (depth + 1, forks + 1);
    let (left, right) = rayon::join(
        || {
            grow_parallel(
                left,
                split.left.0,
                (begin, split.mid),
                split.left.1,
                next,
                max_leaf_size,
            )
        },
        || {
            grow_parallel(
                right,
                split.right.0,
                (split.mid, end),
                split.right.1,
                next,
                max_leaf_size,
            )
        },
    );
    Part::Forked(bounds, Box::new([left, right]))
}

/// Writes `part`, whose root is already at `nodes[at]`, into `nodes`: its descendants
/// appended in the sequential driver's order, interior nodes' `first` made absolute.
fn lay_out<V: Vector>(part: Part<V>, at: usize, nodes: &mut Vec<BvhNode<V>>) {
    match part {
        Part::Grown(grown) => {
            // The part's index k > 0 lands at base + k - 1.
            let base = nodes.len();
            let place = |node: BvhNode<V>| {
                if node.is_leaf() {
                    node
                } else {
                    BvhNode {
                        first: (base + node.first as usize - 1) as u32,
                        ..node
                    }
                }
            };
            let mut grown = grown.into_iter();
            if let Some(root) = grown.next() {
                nodes[at] = place(root);
            }
            nodes.extend(grown.map(place));
        }
        Part::Forked(bounds, sides) => {
            let first = nodes.len();
            nodes[at] = BvhNode {
                bounds,
                first: first as u32,
                count: 0,
            };
            let [left, right] = *sides;
            let placeholder = |part: &Part<V>| BvhNode {
                bounds: match part {
                    Part::Grown(grown) => grown[0].bounds,
                    Part::Forked(bounds, _) => *bounds,
                },
                first: 0,
                count: 0,
            };
            nodes.push(placeholder(&left));
            nodes.push(placeholder(&right));
            lay_out(left, first, nodes);
            lay_out(right, first + 1, nodes);
        }
    }
}

/// Builds with a fixed rule (middle, median): every node with more than `max_leaf_size`
/// primitives is split; `rule` reorders the node's range `begin..end` of `boxes.order` and
/// returns where the left child ends (strictly inside the range).
pub(crate) fn build_by_rule<V: Vector>(
    primitive_bounds: &[Aabb<V>],
    max_leaf_size: usize,
    observer: &mut impl BuildObserver,
    rule: impl FnMut(&mut IndexedBoxes<'_, V>, usize, usize) -> usize,
) -> Bvh<V> {
    struct RuleSplitter<'a, V: Vector, R> {
        boxes: IndexedBoxes<'a, V>,
        max_leaf_size: usize,
        rule: R,
    }

    impl<V: Vector, R: FnMut(&mut IndexedBoxes<'_, V>, usize, usize) -> usize> RangeSplitter<V>
        for RuleSplitter<'_, V, R>
    {
        type NodeInfo = ();

        fn root(&self) -> (Aabb<V>, ()) {
            (self.boxes.range_bounds(0, self.boxes.order.len()), ())
        }

        fn split(
            &mut self,
            begin: usize,
            end: usize,
            _node_bounds: &Aabb<V>,
            _info: &(),
        ) -> Result<Split<V, ()>, LeafReason> {
            let count = end - begin;
            if count <= self.max_leaf_size {
                return Err(LeafReason::SmallEnough {
                    count,
                    max_leaf_size: self.max_leaf_size,
                });
            }
            let mid = (self.rule)(&mut self.boxes, begin, end);
            Ok(self.boxes.split_at(begin, mid, end))
        }

        fn into_order(self) -> Vec<u32> {
            self.boxes.order
        }
    }

    let max_leaf_size = max_leaf_size.max(1);
    let splitter = RuleSplitter {
        boxes: IndexedBoxes::new(primitive_bounds),
        max_leaf_size,
        rule,
    };
    build_top_down(splitter, primitive_bounds.len(), max_leaf_size, observer)
}

/// Primitive boxes, their centroids and a working order: the state of the splitters that
/// reorder one index list (middle, median, binned).
pub(crate) struct IndexedBoxes<'a, V: Vector> {
    pub(crate) bounds: &'a [Aabb<V>],
    pub(crate) centroids: Vec<V>,
    pub(crate) order: Vec<u32>,
}

impl<'a, V: Vector> IndexedBoxes<'a, V> {
    pub(crate) fn new(bounds: &'a [Aabb<V>]) -> Self {
        Self {
            bounds,
            centroids: bounds.iter().map(Aabb::center).collect(),
            order: (0..bounds.len() as u32).collect(),
        }
    }

    pub(crate) fn range_bounds(&self, begin: usize, end: usize) -> Aabb<V> {
        self.order[begin..end]
            .iter()
            .fold(Aabb::empty(), |acc, &index| {
                acc.union(self.bounds[index as usize])
            })
    }

    /// The box around the centroids in `begin..end`: where splits can separate primitives.
    pub(crate) fn centroid_bounds(&self, begin: usize, end: usize) -> Aabb<V> {
        self.order[begin..end]
            .iter()
            .fold(Aabb::empty(), |acc, &index| {
                acc.grown(self.centroids[index as usize])
            })
    }

    /// A split at `mid` with both children's boxes computed from their primitives.
    pub(crate) fn split_at(&self, begin: usize, mid: usize, end: usize) -> Split<V, ()> {
        Split {
            mid,
            cost: None,
            left: (self.range_bounds(begin, mid), ()),
            right: (self.range_bounds(mid, end), ()),
        }
    }

    /// Puts the primitives whose centroid satisfies `goes_left` first; returns where they end.
    pub(crate) fn partition(
        &mut self,
        begin: usize,
        end: usize,
        mut goes_left: impl FnMut(V) -> bool,
    ) -> usize {
        let centroids = &self.centroids;
        let range = &mut self.order[begin..end];
        let mut left_end = 0;
        for slot in 0..range.len() {
            if goes_left(centroids[range[slot] as usize]) {
                range.swap(left_end, slot);
                left_end += 1;
            }
        }
        begin + left_end
    }

    /// Splits `begin..end` at its middle element along `axis` (object median), in O(n).
    pub(crate) fn median_split(&mut self, begin: usize, end: usize, axis: usize) -> usize {
        let centroids = &self.centroids;
        let range = &mut self.order[begin..end];
        let half = range.len() / 2;
        range.select_nth_unstable_by(half, |&a, &b| {
            let (ca, cb) = (centroids[a as usize][axis], centroids[b as usize][axis]);
            ca.partial_cmp(&cb)
                .unwrap_or(std::cmp::Ordering::Equal)
                .then(a.cmp(&b))
        });
        begin + half
    }
}
