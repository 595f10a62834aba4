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

    /// The root's data.
    fn root_data(&mut self, cell: &Aabb<V>, primitives: &[u32]) -> Self::NodeData;

    /// Where to cut `cell`, or `None` for a leaf.
    fn choose(
        &mut self,
        cell: &Aabb<V>,
        primitives: &[u32],
        data: &Self::NodeData,
    ) -> Option<Cut<V::Scalar>>;

    /// The children's data once `cut` is made (`below` and `above` are the child cells).
    fn divide(
        &mut self,
        data: Self::NodeData,
        cut: &Cut<V::Scalar>,
        below: &Aabb<V>,
        above: &Aabb<V>,
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

impl<V: Vector, F: FnMut(&Aabb<V>, &[u32]) -> Option<Cut<V::Scalar>>> CellSplitter<V> for Rule<F> {
    type NodeData = ();

    fn root_data(&mut self, _cell: &Aabb<V>, _primitives: &[u32]) {}

    fn choose(&mut self, cell: &Aabb<V>, primitives: &[u32], _data: &()) -> Option<Cut<V::Scalar>> {
        (self.0)(cell, primitives)
    }

    fn divide(&mut self, _: (), _: &Cut<V::Scalar>, _: &Aabb<V>, _: &Aabb<V>) -> ((), ()) {
        ((), ())
    }
}

/// Builds top down with a fixed rule: a cell with more than `max_leaf_size` primitives (and
/// above the depth limit) is cut where `rule` says, strictly inside the cell, if the cut
/// separates anything; otherwise it becomes a leaf.
pub(crate) fn build_by_rule<V: Vector>(
    primitive_bounds: &[Aabb<V>],
    params: &BuildParams,
    mut rule: impl FnMut(&Aabb<V>, &[u32], &[Aabb<V>]) -> Option<Cut<V::Scalar>>,
) -> KdTree<V> {
    build_top_down(
        primitive_bounds,
        params.max_leaf_size,
        Rule(|cell: &Aabb<V>, primitives: &[u32]| rule(cell, primitives, primitive_bounds)),
    )
}

/// The kD driver: cuts cells where the splitter says, sorts primitives into the children whose
/// cells they reach, and lays the nodes out flat with siblings side by side.
#[inline(never)] // One call a build; kept apart so profiles can single it out.
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
            .filter(|cut| cell.min[cut.axis] < cut.position && cut.position < cell.max[cut.axis]);
        let children = cut.and_then(|cut| {
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
            separates.then_some((cut, below, above, below_cell, above_cell))
        });
        let Some((cut, below, above, below_cell, above_cell)) = children else {
            splitter.discard(data);
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
            split: cut.position,
            axis: cut.axis as u32,
            first: left as u32,
            count: 0,
        };
        let leaf = nodes[node_index];
        nodes.push(leaf);
        nodes.push(leaf);
        let (below_data, above_data) = splitter.divide(data, &cut, &below_cell, &above_cell);
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
