//! What views show about a built tree, computed once, the same way for a BVH and a kD-tree, in
//! 2D and 3D: each node's parent, children and depth, its box (BVH) or cell (kD), the path to
//! it from the root (`LRL`), the primitives below it, and why a leaf is a leaf.
//!
//! A 2D lesson's tree diagram and node inspector and a 3D view read these; none of them walks
//! a tree itself.

use crate::aabb::Aabb;
use crate::build_observer::LeafReason;
use crate::math::Vector;

/// What the facts need of a tree: its nodes' children and leaves, and each node's box or cell.
/// Node 0 is the root and every child comes after its parent. Each family implements it beside
/// its tree (`bvh/tree.rs`, `kd/tree.rs`).
pub trait Hierarchy<V: Vector> {
    /// How many nodes.
    fn node_count(&self) -> usize;
    /// A node's two children, or `None` for a leaf.
    fn children(&self, node: u32) -> Option<[u32; 2]>;
    /// The primitives a leaf lists (empty for an interior node).
    fn leaf_primitives(&self, node: u32) -> &[u32];
    /// Every node's box (BVH) or cell (kD), by node.
    fn node_bounds(&self) -> Vec<Aabb<V>>;
}

/// What can be wrong with a node path such as `LRL`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NodePathError {
    /// A step is neither `L` nor `R`.
    #[error("node path: step {position} is {step:?}; use L and R")]
    BadStep {
        /// Where in the path (1-based).
        position: usize,
        /// What was there.
        step: char,
    },
    /// The path goes on below a leaf.
    #[error("node path: the node after {depth} steps is a leaf; the path is too long")]
    PastLeaf {
        /// The leaf's depth.
        depth: usize,
    },
}

/// Each node's place in the tree and its box or cell, with why each leaf is a leaf when the
/// build was observed.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeFacts<V: Vector> {
    /// Each node's children (`None` for a leaf).
    pub children: Vec<Option<[u32; 2]>>,
    /// Each node's parent (`None` for the root).
    pub parent: Vec<Option<u32>>,
    /// Each node's depth (the root's is 0).
    pub depth: Vec<u32>,
    /// Each node's box (BVH) or cell (kD).
    pub bounds: Vec<Aabb<V>>,
    /// How many primitives each leaf lists (0 for interior nodes).
    pub leaf_sizes: Vec<u32>,
    /// Why each leaf is a leaf, from the builder (empty when the build was not observed).
    pub leaf_reasons: Vec<Option<LeafReason>>,
    /// How many nodes lie at each depth.
    pub nodes_per_depth: Vec<usize>,
    /// Every node, shallowest first (each depth's nodes in node order): the order to draw in
    /// when a view cannot draw them all, so what is left out is the deepest levels.
    pub by_depth: Vec<u32>,
}

impl<V: Vector> TreeFacts<V> {
    /// The facts of `tree`.
    pub fn of(tree: &impl Hierarchy<V>) -> Self {
        let count = tree.node_count();
        let children: Vec<Option<[u32; 2]>> =
            (0..count as u32).map(|node| tree.children(node)).collect();
        let mut parent = vec![None; count];
        let mut depth = vec![0u32; count];
        // Children come after their parents: one forward pass.
        for node in 0..count {
            if let Some(pair) = children[node] {
                for child in pair {
                    parent[child as usize] = Some(node as u32);
                    depth[child as usize] = depth[node] + 1;
                }
            }
        }
        let mut nodes_per_depth = Vec::new();
        for &node_depth in &depth {
            let node_depth = node_depth as usize;
            if nodes_per_depth.len() <= node_depth {
                nodes_per_depth.resize(node_depth + 1, 0);
            }
            nodes_per_depth[node_depth] += 1;
        }
        // A counting sort by depth.
        let mut next_slot: Vec<usize> = nodes_per_depth
            .iter()
            .scan(0, |start, &count| {
                let slot = *start;
                *start += count;
                Some(slot)
            })
            .collect();
        let mut by_depth = vec![0u32; count];
        for (node, &node_depth) in depth.iter().enumerate() {
            let slot = &mut next_slot[node_depth as usize];
            by_depth[*slot] = node as u32;
            *slot += 1;
        }
        Self {
            by_depth,
            leaf_sizes: (0..count as u32)
                .map(|node| tree.leaf_primitives(node).len() as u32)
                .collect(),
            children,
            parent,
            depth,
            bounds: tree.node_bounds(),
            leaf_reasons: Vec::new(),
            nodes_per_depth,
        }
    }

    /// The facts of `tree` with why each leaf is a leaf (from a [`LeafReasons`] observer of
    /// its build).
    ///
    /// [`LeafReasons`]: crate::build_observer::LeafReasons
    pub fn with_leaf_reasons(
        tree: &impl Hierarchy<V>,
        mut reasons: Vec<Option<LeafReason>>,
    ) -> Self {
        let mut facts = Self::of(tree);
        reasons.resize(facts.children.len(), None);
        facts.leaf_reasons = reasons;
        facts
    }

    /// How many nodes.
    pub fn node_count(&self) -> usize {
        self.children.len()
    }

    /// Whether `node` is a leaf.
    pub fn is_leaf(&self, node: u32) -> bool {
        self.children[node as usize].is_none()
    }

    /// The deepest node's depth.
    pub fn max_depth(&self) -> usize {
        self.nodes_per_depth.len().saturating_sub(1)
    }

    /// Why leaf `node` is a leaf, if the build was observed.
    pub fn leaf_reason(&self, node: u32) -> Option<LeafReason> {
        self.leaf_reasons.get(node as usize).copied().flatten()
    }

    /// The path from the root to `node`: `L` (left, below the plane) or `R` per step.
    pub fn path_to(&self, node: u32) -> String {
        let mut steps = Vec::new();
        let mut current = node;
        while let Some(parent) = self.parent[current as usize] {
            let right = self.children[parent as usize].is_some_and(|[_, right]| right == current);
            steps.push(if right { 'R' } else { 'L' });
            current = parent;
        }
        steps.iter().rev().collect()
    }

    /// The node at the end of a path of `L` and `R` steps from the root.
    pub fn node_at(&self, path: &str) -> Result<u32, NodePathError> {
        // Check the whole path before walking, so a typo is named as such wherever it is.
        let mut sides = Vec::with_capacity(path.len());
        for (index, step) in path.chars().enumerate() {
            sides.push(match step.to_ascii_uppercase() {
                'L' => 0,
                'R' => 1,
                step => {
                    return Err(NodePathError::BadStep {
                        position: index + 1,
                        step,
                    });
                }
            });
        }
        let mut node = 0u32;
        for (depth, side) in sides.into_iter().enumerate() {
            let children = self.children[node as usize].ok_or(NodePathError::PastLeaf { depth })?;
            node = children[side];
        }
        Ok(node)
    }

    /// Whether `node` lies in the subtree of `ancestor` (itself included).
    pub fn is_within(&self, node: u32, ancestor: u32) -> bool {
        let mut current = Some(node);
        while let Some(at) = current {
            if at == ancestor {
                return true;
            }
            current = self.parent[at as usize];
        }
        false
    }

    /// The nodes of the subtree of `node`, depth first, the left subtree first.
    pub fn subtree(&self, node: u32) -> Vec<u32> {
        let mut nodes = Vec::new();
        let mut pending = vec![node];
        while let Some(at) = pending.pop() {
            nodes.push(at);
            if let Some([left, right]) = self.children[at as usize] {
                pending.push(right);
                pending.push(left);
            }
        }
        nodes
    }

    /// The primitives in the leaves below `node`, sorted, each once (a kD primitive reaching
    /// several leaves below the node is one of its primitives once).
    pub fn primitives_below(&self, tree: &impl Hierarchy<V>, node: u32) -> Vec<u32> {
        let mut primitives = Vec::new();
        for at in self.subtree(node) {
            primitives.extend_from_slice(tree.leaf_primitives(at));
        }
        primitives.sort_unstable();
        primitives.dedup();
        primitives
    }
}
