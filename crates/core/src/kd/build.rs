//! What the kD builders share: the top-down driver that cuts cells and sorts primitives into
//! the children they overlap.

use crate::aabb::Aabb;
use crate::bvh::BuildParams;
use crate::kd::tree::{KdNode, KdTree};
use crate::math::{Real, Vector};

/// A kD-tree construction algorithm.
pub trait KdBuilder {
    /// A short name, e.g. `middle`.
    fn name(&self) -> String;

    /// Builds a kD-tree over primitives with these boxes.
    fn build<V: Vector>(&self, primitive_bounds: &[Aabb<V>], params: &BuildParams) -> KdTree<V>;
}

/// The depth past which no cell is cut: `8 + 1.3 log₂ n` (pbrt-v3 §4.4.2), so that a scene
/// whose primitives all overlap cannot make the tree grow without end.
pub(crate) fn max_depth(primitive_count: usize) -> usize {
    (8.0 + 1.3 * (primitive_count.max(1) as f64).log2()).round() as usize
}

/// Whether a primitive box reaches the closed cell below (`[.., split]`) and above
/// (`[split, ..]`) a plane on `axis`. A box touching the plane, or lying in it, is on both
/// sides: a ray through the plane may meet it from either cell.
#[inline]
pub(crate) fn sides<V: Vector>(bounds: &Aabb<V>, axis: usize, split: V::Scalar) -> (bool, bool) {
    (bounds.min[axis] <= split, bounds.max[axis] >= split)
}

/// How a kD builder decides cuts. Beyond each node's primitive list, a splitter may keep its
/// own per-node data (`NodeData`: presorted events, say), handed down from parent to children.
pub(crate) trait CellSplitter<V: Vector> {
    /// What the splitter keeps for each node.
    type NodeData;

    /// The root's data.
    fn root_data(&mut self, cell: &Aabb<V>, primitives: &[u32]) -> Self::NodeData;

    /// Where to cut `cell`, or `None` for a leaf.
    fn choose(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        data: &Self::NodeData,
    ) -> Option<(usize, V::Scalar)>;

    /// The children's data once the cut is made (`below` and `above` are the child cells).
    fn divide(
        &mut self,
        data: Self::NodeData,
        axis: usize,
        split: V::Scalar,
        below: &Aabb<V>,
        above: &Aabb<V>,
    ) -> (Self::NodeData, Self::NodeData);
}

/// A splitter with no per-node data: a fixed rule.
struct Rule<F>(F);

impl<V: Vector, F: FnMut(&Aabb<V>, &[u32]) -> Option<(usize, V::Scalar)>> CellSplitter<V>
    for Rule<F>
{
    type NodeData = ();

    fn root_data(&mut self, _cell: &Aabb<V>, _primitives: &[u32]) {}

    fn choose(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        _data: &(),
    ) -> Option<(usize, V::Scalar)> {
        (self.0)(cell, primitives)
    }

    fn divide(&mut self, _: (), _: usize, _: V::Scalar, _: &Aabb<V>, _: &Aabb<V>) -> ((), ()) {
        ((), ())
    }
}

/// Builds top down with a fixed rule: a cell with more than `max_leaf_size` primitives (and
/// above the depth limit) is cut where `rule` says, strictly inside the cell, if the cut
/// separates anything; otherwise it becomes a leaf.
pub(crate) fn build_by_rule<V: Vector>(
    primitive_bounds: &[Aabb<V>],
    params: &BuildParams,
    mut rule: impl FnMut(&Aabb<V>, &[u32], &[Aabb<V>]) -> Option<(usize, V::Scalar)>,
) -> KdTree<V> {
    build_top_down(
        primitive_bounds,
        params.max_leaf_size,
        Rule(|cell: &Aabb<V>, primitives: &[u32]| rule(cell, primitives, primitive_bounds)),
    )
}

/// The kD driver: cuts cells where the splitter says, sorts primitives into the children whose
/// cells they reach, and lays the nodes out flat with siblings side by side.
pub(crate) fn build_top_down<V: Vector, S: CellSplitter<V>>(
    primitive_bounds: &[Aabb<V>],
    max_leaf_size: usize,
    mut splitter: S,
) -> KdTree<V> {
    let root_cell = primitive_bounds
        .iter()
        .fold(Aabb::empty(), |acc, bounds| acc.union(*bounds));
    let depth_limit = max_depth(primitive_bounds.len());
    let max_leaf_size = max_leaf_size.max(1);
    let mut nodes = vec![KdNode {
        split: V::Scalar::ZERO,
        axis: KdNode::<V::Scalar>::LEAF,
        first: 0,
        count: 0,
    }];
    let mut primitive_indices = Vec::new();
    let all: Vec<u32> = (0..primitive_bounds.len() as u32).collect();
    let root_data = splitter.root_data(&root_cell, &all);
    let mut work = vec![(0usize, root_cell, all, root_data, 0usize)];
    while let Some((node_index, cell, primitives, data, depth)) = work.pop() {
        let cut = (primitives.len() > max_leaf_size && depth < depth_limit)
            .then(|| splitter.choose(&cell, &primitives, &data))
            .flatten()
            .filter(|&(axis, split)| cell.min[axis] < split && split < cell.max[axis]);
        let children = cut.and_then(|(axis, split)| {
            // Sort each primitive into the children whose cells it reaches.
            let (mut below, mut above) = (Vec::new(), Vec::new());
            for &primitive in &primitives {
                let (is_below, is_above) =
                    sides(&primitive_bounds[primitive as usize], axis, split);
                if is_below {
                    below.push(primitive);
                }
                if is_above {
                    above.push(primitive);
                }
            }
            // A cut that leaves every primitive on both sides gains nothing.
            let separates = below.len() < primitives.len() || above.len() < primitives.len();
            separates.then_some((axis, split, below, above))
        });
        let Some((axis, split, below, above)) = children else {
            nodes[node_index] = KdNode {
                split: V::Scalar::ZERO,
                axis: KdNode::<V::Scalar>::LEAF,
                first: primitive_indices.len() as u32,
                count: primitives.len() as u32,
            };
            primitive_indices.extend_from_slice(&primitives);
            continue;
        };
        let left = nodes.len();
        nodes[node_index] = KdNode {
            split,
            axis: axis as u32,
            first: left as u32,
            count: 0,
        };
        let leaf = nodes[node_index];
        nodes.push(leaf);
        nodes.push(leaf);
        let [below_cell, above_cell] = KdTree::child_cells(&nodes[node_index], &cell);
        let (below_data, above_data) = splitter.divide(data, axis, split, &below_cell, &above_cell);
        // Above first on the work list, so the subtree below the plane is laid out first.
        work.push((left + 1, above_cell, above, above_data, depth + 1));
        work.push((left, below_cell, below, below_data, depth + 1));
    }
    KdTree {
        bounds: root_cell,
        nodes,
        primitive_indices,
    }
}
