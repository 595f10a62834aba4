//! A structure built with what views show about it ([`Built`]): the tree, its facts and why
//! each leaf is a leaf, and what a view asks of it (its root's box, a node's cuts and
//! planes, a grid's cells and lines, the primitives below a node, a subtree's stats). Its
//! bytes are in `built_bytes.rs`.

use crate::aabb::Aabb;
use crate::build_observer::{BuildObserver, LeafReasons};
use crate::facts::TreeFacts;
use crate::math::{Real, Vector};
use crate::octree;
use crate::params::BuildParams;
use crate::primitive::PrimitiveSet;
use crate::stats::TreeStats;
use crate::structure::{Structure, Tree};

/// A structure built with what views show about it: the tree and its facts (with why each
/// leaf is a leaf, from the builder).
#[derive(Clone, Debug, PartialEq)]
pub struct Built<V: Vector> {
    /// What was built.
    pub structure: Structure,
    /// The tree.
    pub tree: Tree<V>,
    /// Its facts.
    pub facts: TreeFacts<V>,
}

impl<V: Vector> Built<V> {
    /// The same tree in another precision `W`, node for node, with the same leaf reasons
    /// (exact from f32 to f64; see [`Vector::converted`]): a tree built in f32, as a trade
    /// row built it, drawn by a view that works in f64.
    pub fn converted<W: Vector>(&self) -> Built<W> {
        let tree = self.tree.converted();
        let facts = TreeFacts::with_leaf_reasons(&tree, self.facts.leaf_reasons.clone());
        Built {
            structure: self.structure,
            tree,
            facts,
        }
    }

    /// Builds `structure` over `primitives` and gathers its facts; `observer` is told about
    /// the build too (pass [`NoBuildObserver`](crate::build_observer::NoBuildObserver) unless you record it).
    pub fn new<P: PrimitiveSet<V>, O: BuildObserver>(
        structure: Structure,
        primitives: &P,
        params: &BuildParams,
        observer: &mut O,
    ) -> Self {
        let mut observers = (LeafReasons::default(), observer);
        let tree = structure.build_observed(primitives, params, &mut observers);
        let facts = TreeFacts::with_leaf_reasons(&tree, observers.0.reasons);
        Self {
            structure,
            tree,
            facts,
        }
    }

    /// The root's box or cell (empty for a tree with no nodes).
    pub fn root_bounds(&self) -> Aabb<V> {
        self.facts
            .bounds
            .first()
            .copied()
            .unwrap_or_else(Aabb::empty)
    }

    /// Where an interior node cuts its cell, axis by axis: a kD node's one plane, an octree
    /// node's middle on every axis; nothing for a leaf, a BVH node or a grid.
    pub fn cuts(&self, node: u32) -> Vec<(usize, f64)> {
        match &self.tree {
            Tree::Octree(tree) => match tree.nodes.get(node as usize) {
                Some(entry) if !entry.is_leaf() => {
                    let middle = octree::middle(&self.facts.bounds[node as usize]);
                    (0..V::DIM)
                        .map(|axis| (axis, middle[axis].to_f64()))
                        .collect()
                }
                _ => Vec::new(),
            },
            _ => self.plane(node).into_iter().collect(),
        }
    }

    /// A kD node's plane: its axis and where it cuts it (`None` for a leaf or a BVH node).
    pub fn plane(&self, node: u32) -> Option<(usize, f64)> {
        match &self.tree {
            Tree::Kd(tree) => {
                let entry = tree.nodes.get(node as usize)?;
                (!entry.is_leaf()).then(|| (entry.axis as usize, entry.split.to_f64()))
            }
            _ => None,
        }
    }

    /// A grid's cells (dense or hashed); `None` for trees.
    pub fn grid_cells(&self) -> Option<&crate::grid::GridCells<V>> {
        match &self.tree {
            Tree::Grid(grid) => Some(&grid.cells),
            Tree::HashedGrid(grid) => Some(&grid.cells),
            _ => None,
        }
    }

    /// A hashed grid's table; `None` for any other structure.
    pub fn hashed_cells(&self) -> Option<&crate::grid::HashedCells> {
        match &self.tree {
            Tree::HashedGrid(grid) => Some(&grid.store),
            _ => None,
        }
    }

    /// A grid cell's coordinates from its node (`node − 1` is the cell's number); `None` for
    /// the grid's box, a node past the cells, or a tree.
    pub fn grid_coordinates(&self, node: u32) -> Option<[u32; 3]> {
        let cells = self.grid_cells()?;
        let cell = node.checked_sub(1)?;
        ((cell as usize) < cells.cell_count()).then(|| cells.coordinates(cell))
    }

    /// A grid's planes between its cells, per axis (the box's own sides left out): what a
    /// view draws as the grid's lines. Empty for trees.
    pub fn grid_planes(&self) -> Vec<(usize, Vec<f64>)> {
        let Some(cells) = self.grid_cells() else {
            return Vec::new();
        };
        (0..V::DIM)
            .map(|axis| {
                let planes = &cells.planes[axis];
                let inner = &planes[1..planes.len() - 1];
                (axis, inner.iter().map(|plane| plane.to_f64()).collect())
            })
            .collect()
    }

    /// The primitives below `node`, each once.
    pub fn primitives_below(&self, node: u32) -> Vec<u32> {
        self.facts.primitives_below(&self.tree, node)
    }

    /// The statistics of the subtree of `node` (the whole tree at node 0; a wide BVH's
    /// count its wide nodes, below the root its binary tree's; a grid's are its walk's).
    pub fn stats(&self, node: u32, cost: &crate::sah::SahCost) -> TreeStats {
        if self.facts.node_count() == 0 {
            return TreeStats::default();
        }
        match &self.tree {
            Tree::Bvh4(_) | Tree::Bvh8(_) | Tree::Grid(_) | Tree::HashedGrid(_) if node == 0 => {
                self.tree.stats(cost)
            }
            _ => TreeStats::of_subtree(&self.facts, node, cost),
        }
    }
}
