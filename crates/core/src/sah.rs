//! The surface area heuristic's cost model: one object shared by every builder and by the
//! cost-curve view, so that what a view plots is what a builder minimised.
//!
//! `cost(node) = C_trav + P(L)·N_L·C_isect + P(R)·N_R·C_isect` with `P(child) = area(child) /
//! area(node)`: the chance that a ray through the node also passes through the child, for
//! uniformly distributed rays (Goldsmith & Salmon 1987; MacDonald & Booth 1990). "Area" is the
//! surface area in 3D and the perimeter in 2D.

/// A count as f64. Through i64: converting a signed integer is one instruction on x86-64,
/// an unsigned 64-bit one several, and the sweeps convert millions of counts.
#[inline(always)]
fn real(count: usize) -> f64 {
    count as i64 as f64
}

/// The constants of the SAH cost model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SahCost {
    /// `C_trav`: the cost of visiting an interior node (its two box tests).
    pub traversal_cost: f64,
    /// `C_isect`: the cost of one ray/primitive test.
    pub intersection_cost: f64,
    /// kD-trees only: the share by which a cut that leaves one side empty is made cheaper, so
    /// the builder prefers cutting off empty space (Wald & Havran 2006 use 0.2). BVH builders
    /// ignore it: a BVH child is never empty.
    pub empty_bonus: f64,
}

/// `C_trav = 3`, `C_isect = 1`: measured on this project's traversal, visiting an interior node
/// (two slab tests, the stack) costs about as much as three ray/triangle tests, and with these
/// constants the SAH trees of the shared meshes trace fastest (README, performance). The
/// lecture's "triangle count" model is `C_trav = C_isect = 1`; lessons may set it.
impl Default for SahCost {
    fn default() -> Self {
        Self {
            traversal_cost: 3.0,
            intersection_cost: 1.0,
            empty_bonus: 0.2,
        }
    }
}

impl SahCost {
    /// What traversal measured costs a ray in these units: `C_trav · nodes + C_isect · tests`
    /// (nodes or cells entered, primitives tested, per ray).
    pub fn per_ray(&self, nodes: f64, tests: f64) -> f64 {
        self.traversal_cost * nodes + self.intersection_cost * tests
    }

    /// The cost of making a leaf of `count` primitives: `N · C_isect`.
    #[inline]
    pub fn leaf_cost(&self, count: usize) -> f64 {
        real(count) * self.intersection_cost
    }

    /// True when a node of `count` primitives is cheaper as a leaf than any split can be: a
    /// split costs at least `C_trav`, so with `N·C_isect <= C_trav` the search can be skipped
    /// without changing the tree.
    #[inline]
    pub fn leaf_beats_any_split(&self, count: usize) -> bool {
        self.leaf_cost(count) <= self.traversal_cost
    }

    /// The kD form of [`leaf_beats_any_split`](Self::leaf_beats_any_split): a kD cut costs at
    /// least `C_trav·(1 − empty_bonus)`.
    #[inline]
    pub fn kd_leaf_beats_any_split(&self, count: usize) -> bool {
        self.leaf_cost(count) <= self.traversal_cost * (1.0 - self.empty_bonus)
    }

    /// The cost of splitting a node of area `parent_area` into children with these areas and
    /// primitive counts.
    #[inline]
    pub fn split_cost(
        &self,
        parent_area: f64,
        left_area: f64,
        left_count: usize,
        right_area: f64,
        right_count: usize,
    ) -> f64 {
        self.split_cost_weighted(
            parent_area,
            left_area * real(left_count) + right_area * real(right_count),
            left_count + right_count,
        )
    }

    /// The cost of cutting a kD cell of area `parent_area` into cells with these areas and
    /// primitive counts (a primitive reaching both cells counts in both): the split cost,
    /// discounted by `empty_bonus` when one side holds nothing.
    pub fn kd_split_cost(
        &self,
        parent_area: f64,
        left_area: f64,
        left_count: usize,
        right_area: f64,
        right_count: usize,
    ) -> f64 {
        let scaled =
            self.kd_split_cost_scaled(parent_area, left_area, left_count, right_area, right_count);
        Self::unscale(scaled, parent_area)
    }

    /// [`kd_split_cost`](Self::kd_split_cost) times `parent_area` (for a cell of no area, the
    /// cost itself): within one cell it orders the cuts as the cost does, without a division,
    /// which is what the sweep over every candidate compares.
    #[inline(always)]
    pub fn kd_split_cost_scaled(
        &self,
        parent_area: f64,
        left_area: f64,
        left_count: usize,
        right_area: f64,
        right_count: usize,
    ) -> f64 {
        let discount = if left_count == 0 || right_count == 0 {
            1.0 - self.empty_bonus
        } else {
            1.0
        };
        if parent_area <= 0.0 {
            // A cell of no area: every ray that reaches it reaches both children.
            let count = real(left_count + right_count);
            return discount * (self.traversal_cost + count * self.intersection_cost);
        }
        let weighted = left_area * real(left_count) + right_area * real(right_count);
        discount * (self.traversal_cost * parent_area + self.intersection_cost * weighted)
    }

    /// The cost from [`kd_split_cost_scaled`](Self::kd_split_cost_scaled).
    #[inline(always)]
    pub fn unscale(scaled: f64, parent_area: f64) -> f64 {
        if parent_area <= 0.0 {
            scaled
        } else {
            scaled / parent_area
        }
    }

    /// The same cost from `A_L·N_L + A_R·N_R` (`area_weighted_count`): within one node only
    /// this sum varies between candidates, so builders minimise it and cost the winner.
    #[inline]
    pub fn split_cost_weighted(
        &self,
        parent_area: f64,
        area_weighted_count: f64,
        count: usize,
    ) -> f64 {
        if parent_area <= 0.0 {
            // A point-sized node: every ray that reaches it reaches both children.
            return self.traversal_cost + real(count) * self.intersection_cost;
        }
        self.traversal_cost + area_weighted_count / parent_area * self.intersection_cost
    }
}
