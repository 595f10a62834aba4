//! The grid walk: Amanatides & Woo 1987, "A fast voxel traversal algorithm for ray tracing".
//!
//! The ray is clipped to the grid's box and starts in the cell where it enters. Along each axis
//! it keeps the `t` at which it reaches its next plane (`t_next`, their `tMax`); the least of
//! them is where it leaves the cell, and across that plane is the next cell. Each cell's
//! primitives are tested against the ray (once each with a mailbox), and the walk stops at the
//! first cell whose part of the ray holds the closest hit so far: cells come in the order the
//! ray meets them, so nothing beyond can be nearer. A hit found beyond its cell (a primitive
//! reaching further) is kept, and ends the walk in the cell where it lies.
//!
//! One walk serves the dense grid and the hashed grid: they differ only in how a cell's list is
//! looked up ([`CellStore`]).
//!
//! # Robust mode
//! Where the ray passes exactly (within rounding) through an edge or corner between cells, it
//! touches every cell there, and a primitive touching that point may be listed only in a cell
//! the plain walk steps over diagonally; robust mode visits each of them (as an empty part of
//! the ray, `[t, t]`). A ray lying in a plane between cells runs along both sides of it, and
//! robust mode walks both. And it stops only once the closest hit lies inside the cell by more
//! than rounding: a hit at the cell's far plane may have a nearer twin just across it.

use crate::grid::tree::{CellStore, Grid};
use crate::math::{Real, Vector};
use crate::observer::Observer;
use crate::primitive::{LeafPrimitives, PrimitiveSet};
use crate::query::{Hit, Query, TraceOptions};
use crate::ray::Ray;
use crate::search::{CellSearch, HitSearch, Mailbox};

/// Traces `ray` through `grid` over `primitives` (in their own numbering, or the grid's
/// [`leaf_ordered`](Grid::leaf_ordered) copy). Cells have no order to choose: the walk meets
/// them along the ray whatever [`TraceOptions::order`] says. [`Query::FirstInCell`](crate::query::Query::FirstInCell) is the
/// walk's own rule.
pub fn traverse<V, C, P, O>(
    grid: &Grid<V, C>,
    primitives: &P,
    ray: &Ray<V>,
    options: &TraceOptions,
    observer: &mut O,
) -> Option<Hit<V::Scalar>>
where
    V: Vector,
    C: CellStore,
    P: LeafPrimitives<V>,
    O: Observer<V::Scalar>,
{
    let cells = &grid.cells;
    let robust = options.robust_traversal;
    // Clip the ray to the grid's box.
    let CellSearch {
        slab_ray,
        t_enter,
        t_exit,
        primitive_ray,
        mut search,
    } = CellSearch::enter(&cells.bounds, primitives, ray, options, observer)?;
    // The walk meets cells in the ray's order and ends at the first whose part holds the
    // closest hit so far: the pseudo-code's rule is its own, and its cells search for the
    // closest hit (one found beyond its cell is kept, and ends the walk where it lies).
    if search.query == Query::FirstInCell {
        search.query = Query::Closest;
    }
    let mut walk = Walk {
        grid,
        primitives,
        primitive_ray,
        t_min: ray.t_min,
        search,
        mailbox: Mailbox::new(options.mailboxing),
        twins: 0,
    };
    let origin = ray.origin.to_array3();
    let direction = ray.direction.to_array3();
    let inverse = slab_ray.inv_direction.to_array3();
    let plane_t = |axis: usize, plane: V::Scalar| (plane - origin[axis]) * inverse[axis];
    // Roundoff allowed where robust mode asks whether two `t` or two coordinates are one.
    let slack = slab_ray.far_scale - V::Scalar::ONE;
    let close = |a: V::Scalar, b: V::Scalar| (a - b).abs() <= slack * a.abs().max(b.abs());
    // The cell the ray enters and, along each axis, where it reaches its next plane.
    let mut cell = [0u32; 3];
    let mut step = [0i32; 3];
    let mut t_next = [V::Scalar::INFINITY; 3];
    for axis in 0..V::DIM {
        let planes = &cells.planes[axis];
        let last = cells.resolution[axis] - 1;
        if !inverse[axis].is_finite() {
            // The ray does not move along this axis: it stays in the cell of its origin's
            // coordinate, and in robust mode also in the one below a plane it lies in.
            cell[axis] = cells.cell_along(axis, origin[axis]);
            let below = planes[cell[axis] as usize];
            if robust && cell[axis] > 0 && close(origin[axis], below) {
                walk.twins |= 1 << axis;
            }
            if robust && cell[axis] < last && close(origin[axis], planes[cell[axis] as usize + 1]) {
                cell[axis] += 1;
                walk.twins |= 1 << axis;
            }
            continue;
        }
        // A first guess from where the ray enters, settled on the `t` of the stored planes:
        // the cell whose part of the axis holds `t_enter` as the walk measures it. Where
        // planes cannot be told apart in `t` (a ray from very far away), the guess stands,
        // and the cells between are passed with empty parts.
        let entry = origin[axis] + t_enter * direction[axis];
        let mut at = cells.cell_along(axis, entry);
        if slab_ray.negative[axis] {
            step[axis] = -1;
            while at > 0 && plane_t(axis, planes[at as usize]) < t_enter {
                at -= 1;
            }
            while at < last && plane_t(axis, planes[at as usize + 1]) > t_enter {
                at += 1;
            }
            t_next[axis] = plane_t(axis, planes[at as usize]);
        } else {
            step[axis] = 1;
            while at < last && plane_t(axis, planes[at as usize + 1]) < t_enter {
                at += 1;
            }
            while at > 0 && plane_t(axis, planes[at as usize]) > t_enter {
                at -= 1;
            }
            t_next[axis] = plane_t(axis, planes[at as usize + 1]);
        }
        cell[axis] = at;
    }
    // The walk keeps the cell's number too, moving it by an axis's stride at each step; and
    // per axis the coordinate one past the last cell it can step to, where the walk ends.
    let [nx, ny, _] = cells.resolution;
    let stride = [1isize, nx as isize, (nx * ny) as isize];
    let mut index = cells.index(cell) as usize;
    let mut end = [u32::MAX; 3];
    let mut next_side = [0usize; 3];
    for axis in 0..V::DIM {
        if step[axis] > 0 {
            end[axis] = cells.resolution[axis];
            next_side[axis] = 1;
        }
    }
    let mut t_cell_enter = t_enter;
    loop {
        // The plane met first (the lowest axis where two are met at once).
        let mut axis = 0;
        for other in 1..V::DIM {
            if t_next[other] < t_next[axis] {
                axis = other;
            }
        }
        let t_leave = t_next[axis];
        let t_cell_exit = if t_leave < t_exit { t_leave } else { t_exit };
        if walk.visit(index, cell, t_cell_enter, t_cell_exit, observer) {
            return walk.search.closest;
        }
        // The closest hit lies in this cell's part of the ray (in robust mode, by more than
        // rounding): nothing further on is nearer.
        if walk.search.closest.is_some() {
            let t_closest = walk.search.t_closest;
            let inside = if robust {
                t_closest * slab_ray.far_scale < t_cell_exit
            } else {
                t_closest <= t_cell_exit
            };
            if inside {
                return walk.search.closest;
            }
        }
        // The ray ends inside this cell.
        if t_leave > t_exit || t_leave.is_nan() {
            return walk.search.closest;
        }
        observer.grid_stepped(axis, t_next);
        // The axes crossed here: the first, and in robust mode every other one reached at
        // the same `t`, whose cells the ray touches at that one point.
        let mut crossed = 1u32 << axis;
        if robust {
            for (other, &t_other) in t_next.iter().enumerate().take(V::DIM) {
                if other != axis && t_other.is_finite() && close(t_other, t_leave) {
                    crossed |= 1 << other;
                }
            }
            // Every cell at the edge or corner but the one the walk moves into: each nonempty
            // part of the axes crossed, smallest first.
            let mut corner = crossed & crossed.wrapping_neg();
            while corner != crossed {
                let mut touched = index as isize;
                let mut coordinates = cell;
                let mut inside = true;
                for axis in 0..V::DIM {
                    if corner & (1 << axis) != 0 {
                        coordinates[axis] = cell[axis].wrapping_add(step[axis] as u32);
                        inside &= coordinates[axis] != end[axis];
                        touched += stride[axis] * step[axis] as isize;
                    }
                }
                if inside && walk.visit(touched as usize, coordinates, t_leave, t_leave, observer) {
                    return walk.search.closest;
                }
                corner = corner.wrapping_sub(crossed) & crossed;
            }
        }
        while crossed != 0 {
            let axis = crossed.trailing_zeros() as usize;
            crossed &= crossed - 1;
            cell[axis] = cell[axis].wrapping_add(step[axis] as u32);
            if cell[axis] == end[axis] {
                // It leaves the grid.
                return walk.search.closest;
            }
            index = index.wrapping_add_signed(stride[axis] * step[axis] as isize);
            let next_plane = cells.planes[axis][cell[axis] as usize + next_side[axis]];
            t_next[axis] = plane_t(axis, next_plane);
        }
        t_cell_enter = t_leave;
    }
}

/// One ray's walk under way: what it tests with, and what it has found.
struct Walk<'a, V: Vector, C: CellStore, P: LeafPrimitives<V>> {
    grid: &'a Grid<V, C>,
    primitives: &'a P,
    primitive_ray: <P::Set as PrimitiveSet<V>>::RayData,
    t_min: V::Scalar,
    search: HitSearch<V::Scalar>,
    mailbox: Mailbox<V::Scalar>,
    /// Axes along which the ray lies in a plane between cells (robust mode): every cell
    /// visited is visited with its twin below that plane too.
    twins: u32,
}

impl<V: Vector, C: CellStore, P: LeafPrimitives<V>> Walk<'_, V, C, P> {
    /// Looks up and tests cell `cell` at `coordinates` (and its twins across the planes the
    /// ray lies in) over `[t_near, t_far]`; true when an any-hit query has its answer.
    #[inline(always)]
    fn visit<O: Observer<V::Scalar>>(
        &mut self,
        cell: usize,
        coordinates: [u32; 3],
        t_near: V::Scalar,
        t_far: V::Scalar,
        observer: &mut O,
    ) -> bool {
        if self.twins == 0 {
            return self.test_cell(cell as u32, coordinates, t_near, t_far, observer);
        }
        // The cell, then each combination of its twins below the planes.
        let [nx, ny, _] = self.grid.cells.resolution;
        let stride = [1, nx as usize, (nx * ny) as usize];
        let mut below = 0u32;
        loop {
            let mut twin = (cell, coordinates);
            for axis in (0..3).filter(|&axis| below & (1 << axis) != 0) {
                twin.0 -= stride[axis];
                twin.1[axis] -= 1;
            }
            if self.test_cell(twin.0 as u32, twin.1, t_near, t_far, observer) {
                return true;
            }
            below = below.wrapping_sub(self.twins) & self.twins;
            if below == 0 {
                return false;
            }
        }
    }

    #[inline(always)]
    fn test_cell<O: Observer<V::Scalar>>(
        &mut self,
        cell: u32,
        coordinates: [u32; 3],
        t_near: V::Scalar,
        t_far: V::Scalar,
        observer: &mut O,
    ) -> bool {
        let node = Grid::<V, C>::node_of_cell(cell);
        let lookup = self.grid.store.lookup_at(cell, coordinates);
        if C::HASHED {
            observer.cell_looked_up(node, lookup.probes);
        }
        if lookup.primitives.is_empty() {
            observer.cell_skipped(node, t_near, t_far);
            return false;
        }
        observer.cell_entered(node, t_near, t_far);
        self.search.test_leaf(
            self.primitives,
            &self.primitive_ray,
            self.t_min,
            lookup.first as usize,
            lookup.primitives,
            &mut self.mailbox,
            observer,
        )
    }
}
