//! What views show about a built tree, computed once, the same way for a BVH and a kD-tree, in
//! 2D and 3D: each node's parent, children and depth, its box (BVH) or cell (kD), the path to
//! it from the root (`LRL`), the primitives below it, and why a leaf is a leaf.
//!
//! A 2D lesson's tree diagram and node inspector and a 3D view read these; none of them walks
//! a tree itself.

use crate::aabb::Aabb;
use crate::build_observer::LeafReason;
use crate::math::Vector;

/// A node's children: `count` consecutive nodes from `first` (every family makes a node's
/// children together): two in a binary tree, four or eight in a quadtree or octree, every
/// cell under a grid's box.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Children {
    /// The first child.
    pub first: u32,
    /// How many.
    pub count: u32,
}

impl Children {
    /// The two children of a binary node, `first` and `first + 1`.
    pub fn pair(first: u32) -> Self {
        Self { first, count: 2 }
    }

    /// The children of a binary node: below and above its plane (kD), left and right (BVH).
    /// `None` for a node of more than two.
    pub fn as_pair(self) -> Option<[u32; 2]> {
        (self.count == 2).then_some([self.first, self.first + 1])
    }

    /// The children, in order.
    pub fn iter(self) -> std::ops::Range<u32> {
        self.first..self.first + self.count
    }

    /// How many.
    pub fn len(self) -> usize {
        self.count as usize
    }

    /// Whether there are none (a leaf has no `Children` at all; this is for completeness).
    pub fn is_empty(self) -> bool {
        self.count == 0
    }

    /// The `index`-th child.
    pub fn get(self, index: usize) -> Option<u32> {
        (index < self.len()).then(|| self.first + index as u32)
    }

    /// Which child `node` is, if it is one.
    pub fn position(self, node: u32) -> Option<usize> {
        self.iter().position(|child| child == node)
    }
}

impl IntoIterator for Children {
    type Item = u32;
    type IntoIter = std::ops::Range<u32>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

/// What the facts need of a tree: its nodes' children and leaves, and each node's box or cell.
/// Node 0 is the root and every child comes after its parent. Each family implements it beside
/// its tree (`bvh/tree.rs`, `kd/tree.rs`).
pub trait Hierarchy<V: Vector> {
    /// How many nodes.
    fn node_count(&self) -> usize;
    /// A node's children, or `None` for a leaf.
    fn children(&self, node: u32) -> Option<Children>;
    /// The primitives a leaf lists (empty for an interior node).
    fn leaf_primitives(&self, node: u32) -> &[u32];
    /// Every node's box (BVH) or cell (kD), by node.
    fn node_bounds(&self) -> Vec<Aabb<V>>;
}

/// What can be wrong with a node path such as `LRL`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NodePathError {
    /// A step is neither `L` nor `R`.
    #[error("node path: step {position} is {step:?}; use L and R (or a child's digit)")]
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
    /// A step names a child the node does not have.
    #[error("node path: the node after {depth} steps has {count} children, not a child {child}")]
    NoSuchChild {
        /// The node's depth.
        depth: usize,
        /// The child asked for.
        child: usize,
        /// How many it has.
        count: usize,
    },
}

/// Each node's place in the tree and its box or cell, with why each leaf is a leaf when the
/// build was observed.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeFacts<V: Vector> {
    /// Each node's children (`None` for a leaf).
    pub children: Vec<Option<Children>>,
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
        let children: Vec<Option<Children>> =
            (0..count as u32).map(|node| tree.children(node)).collect();
        let mut parent = vec![None; count];
        let mut depth = vec![0u32; count];
        // Children come after their parents: one forward pass.
        for node in 0..count {
            if let Some(below) = children[node] {
                for child in below.iter() {
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

    /// The path from the root to `node`: per step, `L` (left, below the plane) or `R` in a
    /// binary tree, the child's number (`0`…`7`, an octant's bits x, y, z from the lowest) in
    /// a quadtree or an octree, and in brackets (`[17]`) among more (a grid's cells).
    pub fn path_to(&self, node: u32) -> String {
        let mut steps = Vec::new();
        let mut current = node;
        while let Some(parent) = self.parent[current as usize] {
            let siblings = self.children[parent as usize];
            let index = siblings
                .and_then(|children| children.position(current))
                .unwrap_or(0);
            steps.push(match siblings.map_or(2, Children::len) {
                2 => ['L', 'R'][index.min(1)].to_string(),
                3..=10 => index.to_string(),
                _ => format!("[{index}]"),
            });
            current = parent;
        }
        steps.iter().rev().map(String::as_str).collect()
    }

    /// The node at the end of a path of `L` and `R` steps from the root.
    pub fn node_at(&self, path: &str) -> Result<u32, NodePathError> {
        // Check the whole path before walking, so a typo is named as such wherever it is.
        let mut sides = Vec::with_capacity(path.len());
        let mut chars = path.chars().enumerate();
        while let Some((index, step)) = chars.next() {
            let bad = |step| NodePathError::BadStep {
                position: index + 1,
                step,
            };
            sides.push(match step.to_ascii_uppercase() {
                'L' => 0,
                'R' => 1,
                digit if digit.is_ascii_digit() => digit as usize - '0' as usize,
                '[' => {
                    let number: String = chars
                        .by_ref()
                        .map(|(_, step)| step)
                        .take_while(|&step| step != ']')
                        .collect();
                    number.parse().map_err(|_| bad('['))?
                }
                step => return Err(bad(step)),
            });
        }
        let mut node = 0u32;
        for (depth, side) in sides.into_iter().enumerate() {
            let children = self.children[node as usize].ok_or(NodePathError::PastLeaf { depth })?;
            node = children.get(side).ok_or(NodePathError::NoSuchChild {
                depth,
                child: side,
                count: children.len(),
            })?;
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

    /// The nodes of the subtree of `node`, depth first, the first child's subtree first.
    pub fn subtree(&self, node: u32) -> Vec<u32> {
        let mut nodes = Vec::new();
        let mut pending = vec![node];
        while let Some(at) = pending.pop() {
            nodes.push(at);
            if let Some(children) = self.children[at as usize] {
                pending.extend(children.iter().rev());
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
