//! The build observer: how a builder tells a lesson what it does, node by node, and why it
//! made each leaf.
//!
//! Like the traversal's [`Observer`](crate::observer::Observer), every method has an empty
//! default that is inlined away, so a build with [`NoBuildObserver`] costs what it cost
//! before. [`LeafReasons`] keeps why each leaf is a leaf (what a node inspector shows);
//! [`BuildRecorder`] keeps every step, for a lesson that steps through a build.

use crate::facts::Children;

/// Why a builder made a node a leaf.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LeafReason {
    /// It holds at most `max_leaf_size` primitives (or just one), where the builder stops.
    SmallEnough {
        /// Primitives in the node.
        count: usize,
        /// The builder's limit.
        max_leaf_size: usize,
    },
    /// The SAH keeps it: the leaf costs `leaf_cost` (`N·C_isect`) and no split is cheaper.
    /// `split_cost` is the cheapest split's cost, or `None` when the search was skipped
    /// because any split costs at least `C_trav` and the leaf costs no more than that.
    LeafCheaper {
        /// `N·C_isect`.
        leaf_cost: f64,
        /// The cheapest split's cost, if the builder searched.
        split_cost: Option<f64>,
    },
    /// Nothing separates its primitives: their centroids coincide (BVH), or every cut would
    /// leave each of them on both sides (kD).
    Inseparable {
        /// Primitives in the node.
        count: usize,
    },
    /// A kD cell at the depth limit, which would otherwise have been cut.
    DepthLimit {
        /// The limit.
        limit: usize,
    },
    /// A grid's cell: the grid is one level of equal cells, none of them cut further.
    GridCell,
}

impl std::fmt::Display for LeafReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            LeafReason::SmallEnough { count: 0, .. } => write!(f, "empty: nothing to split"),
            LeafReason::SmallEnough { count: 1, .. } => {
                write!(f, "one primitive: nothing to split")
            }
            LeafReason::SmallEnough {
                count,
                max_leaf_size,
            } => write!(
                f,
                "{count} primitives, at most the maximum leaf size {max_leaf_size}: the rule stops here"
            ),
            LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: Some(split_cost),
            } => write!(
                f,
                "the leaf costs {} (N·C_isect), the cheapest split {}: no split is cheaper",
                crate::format::number(leaf_cost),
                crate::format::number(split_cost)
            ),
            LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: None,
            } => write!(
                f,
                "the leaf costs {} (N·C_isect), no more than C_trav, which any split costs at least",
                crate::format::number(leaf_cost)
            ),
            LeafReason::Inseparable { count } => write!(
                f,
                "nothing separates its {count} primitives (they overlap every cut)"
            ),
            LeafReason::DepthLimit { limit } => {
                write!(f, "the depth limit {limit} stops the cutting here")
            }
            LeafReason::GridCell => write!(f, "a cell of the grid: every cell is a leaf"),
        }
    }
}

/// Told about every step of a build.
pub trait BuildObserver {
    /// False for an observer that hears nothing ([`NoBuildObserver`]): a builder may then
    /// build in parallel, in whatever order its threads finish (the tree is the same).
    const ACTIVE: bool = true;

    /// The builder starts on `node` at `depth`, which holds `primitive_count` primitives.
    #[inline(always)]
    fn node_started(&mut self, _node: u32, _depth: usize, _primitive_count: usize) {}
    /// The current node's primitives (kD: their events) were sorted along `axis`.
    #[inline(always)]
    fn sorted(&mut self, _axis: usize) {}
    /// Every candidate split of the current node on `axis` was costed in one sweep.
    #[inline(always)]
    fn swept(&mut self, _axis: usize) {}
    /// The current node was split into `children`; `cost` is the split's SAH cost where the
    /// builder weighed it.
    #[inline(always)]
    fn split(&mut self, _node: u32, _children: Children, _cost: Option<f64>) {}
    /// The current node's sorted lists were divided between its children keeping their order,
    /// so the children need no sort (Wald & Havran 2006).
    #[inline(always)]
    fn lists_divided(&mut self) {}
    /// `node` became a leaf, for `reason`.
    #[inline(always)]
    fn leaf(&mut self, _node: u32, _reason: LeafReason) {}
    /// The build starts over (a kD build that went over its node or reference budget, with a
    /// lower depth limit): what was reported before no longer holds.
    #[inline(always)]
    fn restarted(&mut self) {}
}

/// Observes nothing, at no cost.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoBuildObserver;

impl BuildObserver for NoBuildObserver {
    const ACTIVE: bool = false;
}

/// Keeps why each leaf is a leaf, by node.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LeafReasons {
    /// By node; `None` for interior nodes.
    pub reasons: Vec<Option<LeafReason>>,
}

impl BuildObserver for LeafReasons {
    fn leaf(&mut self, node: u32, reason: LeafReason) {
        let index = node as usize;
        if self.reasons.len() <= index {
            self.reasons.resize(index + 1, None);
        }
        self.reasons[index] = Some(reason);
    }

    fn restarted(&mut self) {
        self.reasons.clear();
    }
}

/// One step of a build, as a lesson shows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BuildStep {
    /// See [`BuildObserver::node_started`].
    NodeStarted {
        /// The node.
        node: u32,
        /// Its depth (the root is at 0).
        depth: usize,
        /// Its primitives.
        primitive_count: usize,
    },
    /// See [`BuildObserver::sorted`].
    Sorted {
        /// The node.
        node: u32,
        /// The axis.
        axis: usize,
    },
    /// See [`BuildObserver::swept`].
    Swept {
        /// The node.
        node: u32,
        /// The axis.
        axis: usize,
    },
    /// See [`BuildObserver::split`].
    Split {
        /// The node.
        node: u32,
        /// Its children.
        children: Children,
        /// The split's SAH cost, where weighed.
        cost: Option<f64>,
    },
    /// See [`BuildObserver::lists_divided`].
    ListsDivided {
        /// The node whose lists were divided.
        node: u32,
    },
    /// See [`BuildObserver::leaf`].
    Leaf {
        /// The node.
        node: u32,
        /// Why.
        reason: LeafReason,
    },
}

impl BuildStep {
    /// The node the step is about.
    pub fn node(&self) -> u32 {
        match *self {
            BuildStep::NodeStarted { node, .. }
            | BuildStep::Sorted { node, .. }
            | BuildStep::Swept { node, .. }
            | BuildStep::Split { node, .. }
            | BuildStep::ListsDivided { node }
            | BuildStep::Leaf { node, .. } => node,
        }
    }
}

/// Records every step of a build, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BuildRecorder {
    /// The steps.
    pub steps: Vec<BuildStep>,
    /// The node being built (the last one started).
    current: u32,
}

impl BuildObserver for BuildRecorder {
    fn node_started(&mut self, node: u32, depth: usize, primitive_count: usize) {
        self.current = node;
        self.steps.push(BuildStep::NodeStarted {
            node,
            depth,
            primitive_count,
        });
    }
    fn sorted(&mut self, axis: usize) {
        self.steps.push(BuildStep::Sorted {
            node: self.current,
            axis,
        });
    }
    fn swept(&mut self, axis: usize) {
        self.steps.push(BuildStep::Swept {
            node: self.current,
            axis,
        });
    }
    fn split(&mut self, node: u32, children: Children, cost: Option<f64>) {
        self.steps.push(BuildStep::Split {
            node,
            children,
            cost,
        });
    }
    fn lists_divided(&mut self) {
        self.steps
            .push(BuildStep::ListsDivided { node: self.current });
    }
    fn leaf(&mut self, node: u32, reason: LeafReason) {
        self.steps.push(BuildStep::Leaf { node, reason });
    }
    fn restarted(&mut self) {
        self.steps.clear();
        self.current = 0;
    }
}

/// Forwards every step to two observers (e.g. record the steps and keep the leaf reasons).
impl<A: BuildObserver, B: BuildObserver> BuildObserver for (A, B) {
    #[inline(always)]
    fn node_started(&mut self, node: u32, depth: usize, primitive_count: usize) {
        self.0.node_started(node, depth, primitive_count);
        self.1.node_started(node, depth, primitive_count);
    }
    #[inline(always)]
    fn sorted(&mut self, axis: usize) {
        self.0.sorted(axis);
        self.1.sorted(axis);
    }
    #[inline(always)]
    fn swept(&mut self, axis: usize) {
        self.0.swept(axis);
        self.1.swept(axis);
    }
    #[inline(always)]
    fn split(&mut self, node: u32, children: Children, cost: Option<f64>) {
        self.0.split(node, children, cost);
        self.1.split(node, children, cost);
    }
    #[inline(always)]
    fn lists_divided(&mut self) {
        self.0.lists_divided();
        self.1.lists_divided();
    }
    #[inline(always)]
    fn leaf(&mut self, node: u32, reason: LeafReason) {
        self.0.leaf(node, reason);
        self.1.leaf(node, reason);
    }
    #[inline(always)]
    fn restarted(&mut self) {
        self.0.restarted();
        self.1.restarted();
    }
}

/// An observer lent to a build (so a caller keeps what it observed).
impl<O: BuildObserver + ?Sized> BuildObserver for &mut O {
    #[inline(always)]
    fn node_started(&mut self, node: u32, depth: usize, primitive_count: usize) {
        (**self).node_started(node, depth, primitive_count);
    }
    #[inline(always)]
    fn sorted(&mut self, axis: usize) {
        (**self).sorted(axis);
    }
    #[inline(always)]
    fn swept(&mut self, axis: usize) {
        (**self).swept(axis);
    }
    #[inline(always)]
    fn split(&mut self, node: u32, children: Children, cost: Option<f64>) {
        (**self).split(node, children, cost);
    }
    #[inline(always)]
    fn lists_divided(&mut self) {
        (**self).lists_divided();
    }
    #[inline(always)]
    fn leaf(&mut self, node: u32, reason: LeafReason) {
        (**self).leaf(node, reason);
    }
    #[inline(always)]
    fn restarted(&mut self) {
        (**self).restarted();
    }
}
