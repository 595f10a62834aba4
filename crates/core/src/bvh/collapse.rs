//! Collapsing a binary BVH into a wide one, SAH-optimally (Ylitie, Karras & Laine 2017,
//! "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", §3.1).
//!
//! Every binary node `n` becomes, in the wide tree, a leaf, a wide node, or part of its
//! parent's wide node (its children then take slots of that node directly). A dynamic programme
//! over the binary tree, bottom up, finds the cheapest choice under the SAH: `cost(n, i)` is the
//! least cost of the subtree of `n` when it may fill at most `i` slots of a wide node,
//!
//! ```text
//! cost(n, 1)     = min(leaf(n), node(n))
//! cost(n, i > 1) = min(cost(n, i − 1), min over 0 < k < i of cost(left, k) + cost(right, i − k))
//! node(n)        = A(n)·C_trav + min over 0 < k < W of cost(left, k) + cost(right, W − k)
//! leaf(n)        = A(n)·N(n)·C_isect   (a binary leaf, or a subtree of at most LEAF_BLOCK)
//! ```
//!
//! with `A` the node's area and the shared [`SahCost`] constants, so the collapse minimises
//! the cost the binary builders minimise, counted for wide nodes. A subtree of up to
//! [`LEAF_BLOCK`] primitives may become one leaf, tested at once. The tree keeps the binary
//! order of the children (the wide tree's "file order" is the binary one).

use crate::bvh::tree::Bvh;
use crate::bvh::wide::{EMPTY_SLOT, LEAF_BLOCK, LOWER, UPPER, WideBvh, WideNode};
use crate::math::{Real, Vector};
use crate::sah::SahCost;

/// What the cheapest way to fill `i` slots with a subtree does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Choice {
    /// One slot: the subtree is a leaf.
    Leaf,
    /// One slot: the subtree is a wide node of its own.
    Node,
    /// The left child fills `k` slots and the right child the rest.
    Distribute(u8),
    /// Fewer slots do as well: see `i − 1`.
    Fewer,
}

/// The binary subtree of each node: its primitive range (contiguous in a top-down build).
fn subtree_ranges<V: Vector>(binary: &Bvh<V>) -> Vec<(u32, u32)> {
    let mut ranges = vec![(0u32, 0u32); binary.nodes.len()];
    // Children come after their parents, so a backward pass sees children first.
    for index in (0..binary.nodes.len()).rev() {
        let node = &binary.nodes[index];
        ranges[index] = if node.is_leaf() {
            (node.first, node.count)
        } else {
            let [left, right] = node.children().map(|child| ranges[child as usize]);
            debug_assert_eq!(
                left.0 + left.1,
                right.0,
                "a subtree's primitives are contiguous"
            );
            (left.0, left.1 + right.1)
        };
    }
    ranges
}

/// The dynamic programme's answers for one binary node: the cheapest way to fill at most
/// `i` slots (`costs[i - 1]`, `choices[i - 1]`), and how a wide node standing for it splits
/// its `W` slots between its children.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Row<const W: usize> {
    costs: [f64; W],
    choices: [Choice; W],
    node_split: u8,
}

impl<const W: usize> Row<W> {
    const UNSOLVED: Self = Self {
        costs: [f64::INFINITY; W],
        choices: [Choice::Fewer; W],
        node_split: 0,
    };

    /// The row of binary node `node` over `count` primitives, from its children's rows (a
    /// leaf has none).
    fn of<V: Vector>(
        node: &crate::bvh::BvhNode<V>,
        count: usize,
        children: Option<[&Row<W>; 2]>,
        cost: &SahCost,
    ) -> Self {
        let area = node.bounds.area().to_f64();
        let Some([left, right]) = children else {
            return Self {
                costs: [area * cost.leaf_cost(count); W],
                choices: [Choice::Leaf; W],
                node_split: 0,
            };
        };
        // The best split of i slots between the two children, for each i.
        let distribute = |slots: usize| -> (f64, u8) {
            (1..slots)
                .map(|k| (left.costs[k - 1] + right.costs[slots - k - 1], k as u8))
                .fold((f64::INFINITY, 0), |best, next| {
                    if next.0 < best.0 { next } else { best }
                })
        };
        let (children_cost, node_split) = distribute(W);
        let as_node = area * cost.traversal_cost + children_cost;
        let as_leaf = if count <= LEAF_BLOCK {
            area * cost.leaf_cost(count)
        } else {
            f64::INFINITY
        };
        let mut row = Self {
            node_split,
            ..Self::UNSOLVED
        };
        (row.costs[0], row.choices[0]) = if as_leaf <= as_node {
            (as_leaf, Choice::Leaf)
        } else {
            (as_node, Choice::Node)
        };
        for slots in 2..=W {
            let (split_cost, k) = distribute(slots);
            (row.costs[slots - 1], row.choices[slots - 1]) = if split_cost < row.costs[slots - 2] {
                (split_cost, Choice::Distribute(k))
            } else {
                (row.costs[slots - 2], Choice::Fewer)
            };
        }
        row
    }
}

/// A block of at least this many binary nodes has its two halves solved at once.
const PARALLEL_GRAIN: usize = 4096;

/// Blocks nest at most this deep in parallel (a lopsided tree's blocks would otherwise
/// deepen the call stack a frame a level); deeper, a block is solved in one loop.
const MAX_FORK_DEPTH: usize = 16;

/// Every node's [`Row`], children before parents. A tree laid out as the top-down builders
/// lay it out (a node's children side by side, then the left child's subtree, then the
/// right's) is cut into the blocks of its subtrees, and the two halves of a big block are
/// solved at once on the current rayon pool: each node's row depends on its children's
/// alone, so the rows are the same on any number of threads. Any other layout is solved in
/// one loop.
fn solve<V: Vector, const W: usize>(
    binary: &Bvh<V>,
    ranges: &[(u32, u32)],
    cost: &SahCost,
) -> Vec<Row<W>> {
    let nodes = &binary.nodes;
    let mut rows = vec![Row::<W>::UNSOLVED; nodes.len()];
    // How many nodes lie below each node (its descendants), and whether every subtree
    // occupies one block after its node's children.
    let mut below = vec![0usize; nodes.len()];
    let mut in_blocks = true;
    for index in (0..nodes.len()).rev() {
        let node = &nodes[index];
        if node.is_leaf() {
            continue;
        }
        let [left, right] = node.children().map(|child| child as usize);
        below[index] = 2 + below[left] + below[right];
        let left_first = left + 2;
        let right_first = left + 2 + below[left];
        in_blocks &= (nodes[left].is_leaf() || nodes[left].first as usize == left_first)
            && (nodes[right].is_leaf() || nodes[right].first as usize == right_first);
    }
    in_blocks &= nodes[0].is_leaf() || nodes[0].first == 1;
    let (root, rest) = rows.split_at_mut(1);
    if in_blocks && !nodes[0].is_leaf() && crate::parallel::has_threads() {
        let blocks = Blocks {
            binary,
            ranges,
            below: &below,
            cost,
        };
        blocks.solve(1, rest, 0);
    } else {
        solve_in_order(binary, ranges, cost, 1, rest);
    }
    let children = (!nodes[0].is_leaf()).then(|| [&rest[0], &rest[1]]);
    root[0] = Row::of(&nodes[0], ranges[0].1 as usize, children, cost);
    rows
}

/// Solves the nodes `first..first + rows.len()` (into `rows`), every one of whose children
/// lies among them, from the last to the first.
fn solve_in_order<V: Vector, const W: usize>(
    binary: &Bvh<V>,
    ranges: &[(u32, u32)],
    cost: &SahCost,
    first: usize,
    rows: &mut [Row<W>],
) {
    for index in (first..first + rows.len()).rev() {
        let node = &binary.nodes[index];
        let children =
            (!node.is_leaf()).then(|| node.children().map(|child| &rows[child as usize - first]));
        let row = Row::of(node, ranges[index].1 as usize, children, cost);
        rows[index - first] = row;
    }
}

/// The tree cut into the blocks of its subtrees, for [`solve`].
struct Blocks<'a, V: Vector> {
    binary: &'a Bvh<V>,
    ranges: &'a [(u32, u32)],
    below: &'a [usize],
    cost: &'a SahCost,
}

impl<V: Vector> Blocks<'_, V> {
    /// Solves the block of a node whose children are `first` and `first + 1`: the two
    /// children, then the left one's descendants, then the right one's (`rows`).
    fn solve<const W: usize>(&self, first: usize, rows: &mut [Row<W>], forks: usize) {
        if rows.len() < 2 * PARALLEL_GRAIN || forks >= MAX_FORK_DEPTH {
            solve_in_order(self.binary, self.ranges, self.cost, first, rows);
            return;
        }
        let (pair, below) = rows.split_at_mut(2);
        let (left_below, right_below) = below.split_at_mut(self.below[first]);
        let nodes = &self.binary.nodes;
        let descend = |child: usize, rows: &mut [Row<W>]| {
            if !nodes[child].is_leaf() {
                self.solve(nodes[child].first as usize, rows, forks + 1);
            }
        };
        rayon::join(
            || descend(first, left_below),
            || descend(first + 1, right_below),
        );
        for (slot, below) in [(0, &*left_below), (1, &*right_below)] {
            let node = &nodes[first + slot];
            let children = (!node.is_leaf()).then(|| [&below[0], &below[1]]);
            pair[slot] = Row::of(
                node,
                self.ranges[first + slot].1 as usize,
                children,
                self.cost,
            );
        }
    }
}

/// Collapses `binary` into a BVH of `W` children per node (`2 <= W <= 16`), with the
/// SAH-optimal choice of which binary nodes to keep (see the module docs). The wide tree keeps
/// the binary one.
pub fn collapse<V: Vector, const W: usize>(binary: Bvh<V>, cost: &SahCost) -> WideBvh<V, W> {
    assert!(
        (2..=16).contains(&W),
        "a wide BVH has 2 to 16 children per node"
    );
    if binary.nodes.is_empty() {
        return WideBvh {
            binary,
            ..WideBvh::default()
        };
    }
    let ranges = subtree_ranges(&binary);
    let rows = solve::<V, W>(&binary, &ranges, cost);

    let plan = Plan {
        binary: &binary,
        ranges: &ranges,
        rows: &rows,
    };
    // The root is a wide node even when the binary root would rather be a leaf.
    let layout = plan.part(0, 0);
    WideBvh {
        nodes: layout.nodes,
        primitive_indices: layout.primitive_indices,
        node_sources: layout.node_sources,
        leaf_sources: layout.leaf_sources,
        binary,
    }
}

/// A wide tree being laid out, or a part of one: a wide subtree laid out on its own, its node
/// 0 standing for its top and its primitive slots counted from 0.
struct Layout<S: Real, const W: usize> {
    nodes: Vec<WideNode<S, W>>,
    primitive_indices: Vec<u32>,
    node_sources: Vec<u32>,
    leaf_sources: Vec<u32>,
}

impl<S: Real, const W: usize> Layout<S, W> {
    /// A layout whose node 0, not yet filled, stands for binary node `source` over `count`
    /// primitives.
    fn rooted(source: u32, count: usize) -> Self {
        Self {
            nodes: vec![WideNode::default()],
            // Leaves padded to blocks of four take at most twice the slots.
            primitive_indices: Vec::with_capacity(2 * count),
            node_sources: vec![source],
            leaf_sources: Vec::new(),
        }
    }

    /// Puts `part` here, its node 0 at `at` (allocated, with its source, by its parent), the
    /// rest after everything laid out so far: where one layout, depth first, would have put
    /// it when it came to `at`.
    fn append(&mut self, at: usize, part: Self) {
        let node_base = self.nodes.len();
        let slot_base = self.primitive_indices.len() as u32;
        let place = |mut node: WideNode<S, W>| {
            for (child, &count) in node.child.iter_mut().zip(&node.count) {
                if *child == EMPTY_SLOT {
                    continue;
                }
                *child = if count > 0 {
                    *child + slot_base
                } else {
                    // A part's node k > 0 lands at node_base + k - 1.
                    (node_base + *child as usize - 1) as u32
                };
            }
            node
        };
        let mut nodes = part.nodes.into_iter();
        if let Some(top) = nodes.next() {
            self.nodes[at] = place(top);
        }
        self.nodes.extend(nodes.map(place));
        self.primitive_indices.extend(part.primitive_indices);
        self.node_sources.extend(&part.node_sources[1..]);
        self.leaf_sources.extend(part.leaf_sources);
    }
}

/// A subtree of at least this many primitives has its wide children's subtrees laid out at
/// once.
const PARALLEL_LAYOUT_GRAIN: usize = 8192;

/// What the layout reads: the binary tree, its subtrees' primitive ranges, the programme's
/// choices.
struct Plan<'a, V: Vector, const W: usize> {
    binary: &'a Bvh<V>,
    ranges: &'a [(u32, u32)],
    rows: &'a [Row<W>],
}

impl<V: Vector, const W: usize> Plan<'_, V, W> {
    /// The wide subtree standing for binary node `source`: laid out depth first, wide
    /// children side by side, each then filled; a big one's children's subtrees at once on
    /// the current rayon pool, as parts put in their places in order, so the tree is the one
    /// a single loop lays out, on any number of threads.
    fn part(&self, source: u32, forks: usize) -> Layout<V::Scalar, W> {
        let count = self.ranges[source as usize].1 as usize;
        let mut layout = Layout::rooted(source, count);
        if count < PARALLEL_LAYOUT_GRAIN
            || forks >= MAX_FORK_DEPTH
            || !crate::parallel::has_threads()
        {
            self.grow(&mut layout, source);
            return layout;
        }
        let children = self.emit(&mut layout, 0, source, &mut Vec::with_capacity(W));
        use rayon::prelude::*;
        let parts: Vec<Layout<V::Scalar, W>> = children
            .par_iter()
            .map(|&(_, child)| self.part(child, forks + 1))
            .collect();
        for (&(at, _), part) in children.iter().zip(parts) {
            layout.append(at, part);
        }
        layout
    }

    /// Lays out the whole wide subtree under `layout`'s node 0 (standing for `source`), one
    /// node after another.
    fn grow(&self, layout: &mut Layout<V::Scalar, W>, source: u32) {
        let mut pending = vec![(0usize, source)];
        let mut subtrees = Vec::with_capacity(W);
        while let Some((wide_index, source)) = pending.pop() {
            let children = self.emit(layout, wide_index, source, &mut subtrees);
            // Reversed, so the first child's subtree is laid out first.
            pending.extend(children.into_iter().rev());
        }
    }

    /// Fills wide node `wide_index`, standing for binary node `source`: each slot's box, its
    /// leaves' primitives (padded to blocks); allocates its wide children side by side and
    /// returns them (index, binary node) in slot order. `subtrees` is scratch.
    fn emit(
        &self,
        layout: &mut Layout<V::Scalar, W>,
        wide_index: usize,
        source: u32,
        subtrees: &mut Vec<u32>,
    ) -> Vec<(usize, u32)> {
        let (binary, rows, ranges) = (self.binary, self.rows, self.ranges);
        subtrees.clear();
        if binary.nodes[source as usize].is_leaf() {
            subtrees.push(source);
        } else {
            let [left, right] = binary.nodes[source as usize].children();
            let k = rows[source as usize].node_split as usize;
            slot_subtrees(binary, rows, left, k, subtrees);
            slot_subtrees(binary, rows, right, W - k, subtrees);
        }
        let mut node = WideNode::<V::Scalar, W>::default();
        let mut children = Vec::new();
        for (slot, &subtree) in subtrees.iter().enumerate() {
            let bounds = binary.nodes[subtree as usize].bounds;
            for axis in 0..V::DIM {
                node.planes[LOWER][axis][slot] = bounds.min[axis];
                node.planes[UPPER][axis][slot] = bounds.max[axis];
            }
            let is_leaf = binary.nodes[subtree as usize].is_leaf()
                || rows[subtree as usize].choices[0] == Choice::Leaf;
            if is_leaf {
                let (first, count) = ranges[subtree as usize];
                node.child[slot] = layout.primitive_indices.len() as u32;
                node.count[slot] = count;
                let primitives = &binary.primitive_indices[first as usize..][..count as usize];
                layout.primitive_indices.extend_from_slice(primitives);
                let blocks = (count as usize).div_ceil(LEAF_BLOCK);
                let last = primitives[primitives.len() - 1];
                layout
                    .primitive_indices
                    .resize(blocks * LEAF_BLOCK + node.child[slot] as usize, last);
                layout.leaf_sources.push(subtree);
                layout
                    .leaf_sources
                    .extend(std::iter::repeat_n(EMPTY_SLOT, blocks - 1));
            } else {
                let child_index = layout.nodes.len() + children.len();
                node.child[slot] = child_index as u32;
                children.push((child_index, subtree));
            }
        }
        layout.nodes[wide_index] = node;
        layout
            .nodes
            .resize(layout.nodes.len() + children.len(), WideNode::default());
        for &(child_index, subtree) in &children {
            layout.node_sources.push(subtree);
            debug_assert_eq!(layout.node_sources.len(), child_index + 1);
        }
        children
    }
}

/// The binary subtrees that fill at most `slots` slots of a wide node for the subtree of
/// `node`, by the choices made for it, in binary (left to right) order.
fn slot_subtrees<V: Vector, const W: usize>(
    binary: &Bvh<V>,
    rows: &[Row<W>],
    node: u32,
    slots: usize,
    out: &mut Vec<u32>,
) {
    match rows[node as usize].choices[slots - 1] {
        Choice::Leaf | Choice::Node => out.push(node),
        Choice::Fewer => slot_subtrees(binary, rows, node, slots - 1, out),
        Choice::Distribute(k) => {
            let [left, right] = binary.nodes[node as usize].children();
            slot_subtrees(binary, rows, left, k as usize, out);
            slot_subtrees(binary, rows, right, slots - k as usize, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aabb::Aabb;
    use crate::bvh::{BinnedSah, Builder, MiddleSplit, validate_wide};
    use crate::params::BuildParams;
    use glam::DVec3;

    /// Boxes from a small linear congruential generator, so the test needs no dependency.
    fn boxes(count: usize, seed: u64) -> Vec<Aabb<DVec3>> {
        let mut state = seed;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..count)
            .map(|_| {
                let corner = DVec3::new(next(), next(), next()) * 10.0;
                Aabb::new(corner, corner + DVec3::new(next(), next(), next()))
            })
            .collect()
    }

    /// Every way to fill at most `width` slots with subtrees of `node` (the node itself, or
    /// the ways of its children side by side).
    fn frontiers(binary: &Bvh<DVec3>, node: u32, width: usize) -> Vec<Vec<u32>> {
        let mut ways = vec![vec![node]];
        if !binary.nodes[node as usize].is_leaf() {
            ways.extend(children_frontiers(binary, node, width));
        }
        ways
    }

    fn children_frontiers(binary: &Bvh<DVec3>, node: u32, width: usize) -> Vec<Vec<u32>> {
        let [left, right] = binary.nodes[node as usize].children();
        let mut ways = Vec::new();
        for a in frontiers(binary, left, width) {
            for b in frontiers(binary, right, width) {
                if a.len() + b.len() <= width {
                    ways.push([a.clone(), b].concat());
                }
            }
        }
        ways
    }

    /// The least SAH cost of the subtree of `node` in one slot, by trying every collapse.
    fn exhaustive(binary: &Bvh<DVec3>, node: u32, width: usize, cost: &SahCost) -> f64 {
        let entry = &binary.nodes[node as usize];
        let area = entry.bounds.area();
        let count = subtree_ranges(binary)[node as usize].1 as usize;
        let leaf = if entry.is_leaf() || count <= LEAF_BLOCK {
            area * cost.leaf_cost(count)
        } else {
            f64::INFINITY
        };
        if entry.is_leaf() {
            return leaf;
        }
        leaf.min(as_node(binary, node, width, cost))
    }

    fn as_node(binary: &Bvh<DVec3>, node: u32, width: usize, cost: &SahCost) -> f64 {
        let area = binary.nodes[node as usize].bounds.area();
        let children = children_frontiers(binary, node, width)
            .into_iter()
            .map(|way| {
                way.iter()
                    .map(|&child| exhaustive(binary, child, width, cost))
                    .sum::<f64>()
            })
            .fold(f64::INFINITY, f64::min);
        area * cost.traversal_cost + children
    }

    #[test]
    fn the_collapse_costs_what_trying_every_collapse_finds() {
        for seed in 0..40 {
            let bounds = boxes(3 + seed as usize % 14, seed);
            for (max_leaf_size, cost) in [
                (1, SahCost::default()),
                (2, SahCost::default()),
                (
                    1,
                    SahCost {
                        traversal_cost: 1.0,
                        ..SahCost::default()
                    },
                ),
            ] {
                let params = BuildParams {
                    max_leaf_size,
                    cost,
                    ..BuildParams::default()
                };
                let binary = MiddleSplit.build(&bounds, &params);
                let root_area = binary.bounds().area();
                for (width, wide_cost) in [
                    (
                        4,
                        collapse::<DVec3, 4>(binary.clone(), &cost)
                            .stats(&cost)
                            .sah_cost,
                    ),
                    (
                        8,
                        collapse::<DVec3, 8>(binary.clone(), &cost)
                            .stats(&cost)
                            .sah_cost,
                    ),
                ] {
                    let best = if binary.nodes[0].is_leaf() {
                        // A root leaf sits in a wide root node.
                        root_area * cost.traversal_cost + exhaustive(&binary, 0, width, &cost)
                    } else {
                        as_node(&binary, 0, width, &cost)
                    };
                    let expected = best / root_area;
                    assert!(
                        (wide_cost - expected).abs() <= 1e-9 * expected,
                        "seed {seed}, width {width}: collapse {wide_cost}, best {expected}"
                    );
                }
            }
        }
    }

    /// The programme solved by blocks of subtrees, on two threads, gives every node the row
    /// one loop over the nodes gives.
    #[test]
    fn solving_by_blocks_gives_the_rows_of_one_loop() {
        let bounds = boxes(120_000, 11);
        let binary = BinnedSah { bins: 16 }.build(&bounds, &BuildParams::default());
        assert!(
            binary.nodes.len() > 4 * PARALLEL_GRAIN,
            "big enough to fork"
        );
        let ranges = subtree_ranges(&binary);
        let cost = SahCost::default();
        // Two threads where there are threads (WebAssembly has none: the blocks one by one).
        let by_blocks = match rayon::ThreadPoolBuilder::new().num_threads(2).build() {
            Ok(pool) => pool.install(|| solve::<DVec3, 8>(&binary, &ranges, &cost)),
            Err(_) => solve::<DVec3, 8>(&binary, &ranges, &cost),
        };
        let mut in_order = vec![Row::<8>::UNSOLVED; binary.nodes.len()];
        solve_in_order(&binary, &ranges, &cost, 0, &mut in_order);
        assert!(by_blocks == in_order);
    }

    /// The layout by parts, on two threads, puts every node, slot and source where one loop
    /// puts them.
    #[test]
    fn laying_out_by_parts_gives_the_layout_of_one_loop() {
        let bounds = boxes(120_000, 5);
        let binary = BinnedSah { bins: 16 }.build(&bounds, &BuildParams::default());
        let ranges = subtree_ranges(&binary);
        let rows = solve::<DVec3, 8>(&binary, &ranges, &SahCost::default());
        let plan = Plan {
            binary: &binary,
            ranges: &ranges,
            rows: &rows,
        };
        assert!(
            ranges[0].1 as usize > 4 * PARALLEL_LAYOUT_GRAIN,
            "big enough to fork"
        );
        let by_parts = match rayon::ThreadPoolBuilder::new().num_threads(2).build() {
            Ok(pool) => pool.install(|| plan.part(0, 0)),
            Err(_) => plan.part(0, 0),
        };
        let mut one_loop = Layout::rooted(0, binary.primitive_indices.len());
        plan.grow(&mut one_loop, 0);
        assert!(by_parts.nodes == one_loop.nodes);
        assert_eq!(by_parts.primitive_indices, one_loop.primitive_indices);
        assert_eq!(by_parts.node_sources, one_loop.node_sources);
        assert_eq!(by_parts.leaf_sources, one_loop.leaf_sources);
    }

    #[test]
    fn wide_trees_are_valid_and_fill_their_nodes() {
        let bounds = boxes(5000, 7);
        let binary = BinnedSah { bins: 16 }.build(&bounds, &BuildParams::default());
        let cost = SahCost::default();
        let four = collapse::<DVec3, 4>(binary.clone(), &cost);
        let eight = collapse::<DVec3, 8>(binary.clone(), &cost);
        validate_wide(&four, &bounds).unwrap();
        validate_wide(&eight, &bounds).unwrap();
        let binary_interior = binary.nodes.iter().filter(|node| !node.is_leaf()).count();
        for (width, nodes, slots) in [
            (
                4,
                four.node_count(),
                four.nodes.iter().map(WideNode::slots_used).sum::<usize>(),
            ),
            (
                8,
                eight.node_count(),
                eight.nodes.iter().map(WideNode::slots_used).sum::<usize>(),
            ),
        ] {
            // Each wide node replaces at least one binary interior node; most are full.
            assert!(nodes < binary_interior, "width {width}: {nodes} nodes");
            let fill = slots as f64 / (nodes * width) as f64;
            assert!(fill > 0.6, "width {width}: slots {fill:.2} full");
        }
        // Wider is shallower and never costs more under the same SAH.
        let (cost4, cost8) = (four.stats(&cost), eight.stats(&cost));
        assert!(cost8.sah_cost <= cost4.sah_cost);
        assert!(cost8.max_depth < cost4.max_depth);
        assert!(cost4.max_leaf_size <= BuildParams::default().max_leaf_size);
    }
}
