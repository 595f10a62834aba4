//! A uniform grid's cells: the box around the primitives cut into equal cells, `n_x` across
//! by `n_y` (by `n_z` in 3D), numbered along x first from the box's minimum corner.

use crate::aabb::Aabb;
use crate::math::{Real, Vector};

/// The cells of a uniform grid.
///
/// The planes between cells are stored, not recomputed: the builder lists primitives by the
/// cells these planes bound, and the walk crosses the same planes, so the two never disagree
/// about where a cell ends (a plane computed twice in different ways can differ in its last
/// bit).
#[derive(Clone, Debug, PartialEq)]
pub struct GridCells<V: Vector> {
    /// The grid's box.
    pub bounds: Aabb<V>,
    /// Cells per axis; 1 along the axes a 2D grid does not have, and along an axis the box
    /// has no extent on.
    pub resolution: [u32; 3],
    /// Per axis, the `resolution + 1` planes bounding its cells, from `bounds.min` to
    /// `bounds.max` (both exactly), never decreasing.
    pub planes: [Vec<V::Scalar>; 3],
    /// Per axis, cells per unit length (0 along an axis without extent): where a point's
    /// cell is first guessed.
    inverse_cell_size: [f64; 3],
}

/// The most cells a grid has, whatever the density asks for (16.8 million: 64 MiB of cell
/// starts in the dense grid).
pub const MAX_CELLS: u64 = 1 << 24;

impl<V: Vector> GridCells<V> {
    /// The same cells in another precision `W` (exact from f32 to f64; see
    /// [`Vector::converted`]).
    pub fn converted<W: Vector>(&self) -> GridCells<W> {
        GridCells {
            bounds: self.bounds.converted(),
            resolution: self.resolution,
            planes: self.planes.clone().map(|planes| {
                planes
                    .into_iter()
                    .map(|plane| W::Scalar::from_f64(plane.to_f64()))
                    .collect()
            }),
            inverse_cell_size: self.inverse_cell_size,
        }
    }

    /// The cells Cleary & Wyvill 1988 and Ize, Shirley & Parker 2007 ("Grid creation
    /// strategies for efficient ray tracing") choose for `primitive_count` primitives in
    /// `bounds`: cells near cubes (squares in 2D), about `density` of them per primitive,
    /// `n_a = d_a · (K·N / V)^(1/D)` along each axis `a` of extent `d_a`, `V` the box's volume
    /// (area in 2D) and `D` the dimension. An axis without extent gets one cell and is left
    /// out of `V` and `D`; at most [`MAX_CELLS`] in all.
    pub fn for_primitives(bounds: Aabb<V>, primitive_count: usize, density: f64) -> Self {
        Self::near_square(bounds, |extent: &[f64], spread: &[usize]| {
            if primitive_count == 0 {
                return 0.0;
            }
            let measure: f64 = spread.iter().map(|&axis| extent[axis]).product();
            let cells_wanted = density.max(0.0) * primitive_count as f64;
            (cells_wanted / measure).powf(1.0 / spread.len() as f64)
        })
    }

    /// `count` cells along the box's longest side (at least 1), the other sides cut into
    /// cells as near square (cube) as whole numbers allow: what a lesson's cell-size slider
    /// asks for. At most [`MAX_CELLS`] in all.
    pub fn along_longest(bounds: Aabb<V>, count: u32) -> Self {
        Self::near_square(bounds, |extent: &[f64], spread: &[usize]| {
            let longest = spread.iter().map(|&axis| extent[axis]).fold(0.0, f64::max);
            f64::from(count.max(1)) / longest
        })
    }

    /// Cells of one size along every axis the box spreads along: `per_length(extent,
    /// spread)` cells per unit length, each axis's count rounded (at least 1); one cell along
    /// a flat axis (tiny next to the largest one, or empty); scaled down alike past
    /// [`MAX_CELLS`].
    fn near_square(bounds: Aabb<V>, per_length: impl Fn(&[f64], &[usize]) -> f64) -> Self {
        let extent = bounds.extent().to_f64_array();
        let largest = (0..V::DIM).map(|axis| extent[axis]).fold(0.0f64, f64::max);
        let spread: Vec<usize> = (0..V::DIM)
            .filter(|&axis| extent[axis] > largest * 1e-9 && extent[axis] > 0.0)
            .collect();
        let mut resolution = [1u32; 3];
        if !spread.is_empty() {
            let per_length = per_length(&extent, &spread);
            for &axis in &spread {
                let count = extent[axis] * per_length;
                resolution[axis] = if count.is_finite() {
                    count.round().clamp(1.0, MAX_CELLS as f64) as u32
                } else {
                    1
                };
            }
            let total = |resolution: &[u32; 3]| {
                resolution
                    .iter()
                    .fold(1u64, |total, &n| total.saturating_mul(u64::from(n)))
            };
            while total(&resolution) > MAX_CELLS {
                for &axis in &spread {
                    resolution[axis] = (resolution[axis] - resolution[axis] / 8).max(1);
                }
            }
        }
        Self::with_resolution(bounds, resolution)
    }

    /// The box cut into `resolution[a]` cells along each axis `a` (values below 1 count as
    /// 1; axes beyond the dimension get 1).
    pub fn with_resolution(bounds: Aabb<V>, resolution: [u32; 3]) -> Self {
        let mut cells = [1u32; 3];
        let mut planes: [Vec<V::Scalar>; 3] = Default::default();
        let mut inverse_cell_size = [0.0; 3];
        let (low, high) = (bounds.min.to_f64_array(), bounds.max.to_f64_array());
        for axis in 0..3 {
            if axis >= V::DIM {
                planes[axis] = vec![V::Scalar::ZERO; 2];
                continue;
            }
            let count = resolution[axis].max(1);
            cells[axis] = count;
            let extent = high[axis] - low[axis];
            // Each plane from the box's corners in f64, rounded once: never decreasing, and
            // the end planes are the box's own.
            planes[axis] = (0..=count)
                .map(|plane| match plane {
                    0 => bounds.min[axis],
                    _ if plane == count => bounds.max[axis],
                    _ => V::Scalar::from_f64(
                        low[axis] + extent * (f64::from(plane) / f64::from(count)),
                    ),
                })
                .collect();
            if extent > 0.0 {
                inverse_cell_size[axis] = f64::from(count) / extent;
            }
        }
        Self {
            bounds,
            resolution: cells,
            planes,
            inverse_cell_size,
        }
    }

    /// The most cells along any axis: along the longest side for cells near square (what
    /// [`GridCells::along_longest`] was asked for).
    pub fn cells_along_longest(&self) -> u32 {
        self.resolution.into_iter().max().unwrap_or(1)
    }

    /// How many cells.
    pub fn cell_count(&self) -> usize {
        self.resolution.iter().map(|&n| n as usize).product()
    }

    /// The number of the cell at `coordinates` (x first, then y, then z).
    #[inline(always)]
    pub fn index(&self, coordinates: [u32; 3]) -> u32 {
        let [nx, ny, _] = self.resolution;
        coordinates[0] + nx * (coordinates[1] + ny * coordinates[2])
    }

    /// The coordinates of cell `index`.
    pub fn coordinates(&self, index: u32) -> [u32; 3] {
        let [nx, ny, _] = self.resolution;
        [index % nx, (index / nx) % ny, index / (nx * ny)]
    }

    /// The closed box of the cell at `coordinates`.
    pub fn cell_bounds(&self, coordinates: [u32; 3]) -> Aabb<V> {
        let mut bounds = self.bounds;
        for (axis, &at) in coordinates.iter().enumerate().take(V::DIM) {
            bounds.min[axis] = self.planes[axis][at as usize];
            bounds.max[axis] = self.planes[axis][at as usize + 1];
        }
        bounds
    }

    /// The cell along `axis` holding the coordinate `value` (cells are half-open,
    /// `[plane_i, plane_i+1)`, but for the last, which holds its far plane), clamped to the
    /// grid.
    pub fn cell_along(&self, axis: usize, value: V::Scalar) -> u32 {
        let planes = &self.planes[axis];
        let last = self.resolution[axis] - 1;
        let guess = (value.to_f64() - planes[0].to_f64()) * self.inverse_cell_size[axis];
        let mut cell = if guess.is_nan() {
            0
        } else {
            guess.floor().clamp(0.0, f64::from(last)) as u32
        };
        // The guess is rounded: settle it against the stored planes.
        while cell > 0 && value < planes[cell as usize] {
            cell -= 1;
        }
        while cell < last && value >= planes[cell as usize + 1] {
            cell += 1;
        }
        cell
    }

    /// The first and last cell, per axis, whose closed box meets the closed box `bounds`
    /// (clamped to the grid).
    pub fn cells_touching(&self, bounds: &Aabb<V>) -> ([u32; 3], [u32; 3]) {
        let mut first = [0u32; 3];
        let mut last = [0u32; 3];
        for axis in 0..V::DIM {
            let planes = &self.planes[axis];
            let count = self.resolution[axis] as usize;
            // Cell i meets [low, high] when plane_i <= high and plane_i+1 >= low.
            let (low, high) = (bounds.min[axis], bounds.max[axis]);
            let below = planes[1..].partition_point(|&plane| plane < low);
            let reached = planes[..count].partition_point(|&plane| plane <= high);
            first[axis] = below.min(count - 1) as u32;
            last[axis] = reached.saturating_sub(1).max(below.min(count - 1)) as u32;
        }
        (first, last)
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, Vec3};

    use super::*;

    #[test]
    fn the_density_rule_makes_cubes_and_flat_axes_get_one_cell() {
        // A 4 × 2 × 1 box, 100 primitives, 1 cell each: (100 / 8)^(1/3) = 2.32 cells a unit.
        let bounds = Aabb::new(Vec3::ZERO, Vec3::new(4.0, 2.0, 1.0));
        let cells = GridCells::for_primitives(bounds, 100, 1.0);
        assert_eq!(cells.resolution, [9, 5, 2]);
        // A flat box: 2D in a 3D scene.
        let flat = Aabb::new(Vec3::ZERO, Vec3::new(10.0, 10.0, 0.0));
        assert_eq!(
            GridCells::for_primitives(flat, 100, 1.0).resolution,
            [10, 10, 1]
        );
        // A 2D scene: the area, square roots.
        let square = Aabb::new(DVec2::ZERO, DVec2::splat(3.0));
        assert_eq!(
            GridCells::for_primitives(square, 36, 4.0).resolution,
            [12, 12, 1]
        );
        // One point: one cell.
        let point = Aabb::from_point(Vec3::ONE);
        assert_eq!(
            GridCells::for_primitives(point, 5, 3.0).resolution,
            [1, 1, 1]
        );
        // Capped.
        let huge = GridCells::for_primitives(bounds, 100_000_000, 8.0);
        assert!(
            huge.cell_count() as u64 <= MAX_CELLS,
            "{:?}",
            huge.resolution
        );
    }

    #[test]
    fn cells_along_the_longest_side_make_squares_and_at_least_one() {
        // 100 × 30: 10 cells along x, 3 along y (cells 10 × 10).
        let wide = Aabb::new(DVec2::ZERO, DVec2::new(100.0, 30.0));
        assert_eq!(GridCells::along_longest(wide, 10).resolution, [10, 3, 1]);
        assert_eq!(GridCells::along_longest(wide, 10).cells_along_longest(), 10);
        // Along the longer side whichever it is; the short side keeps one cell.
        let tall = Aabb::new(DVec2::ZERO, DVec2::new(2.0, 100.0));
        assert_eq!(GridCells::along_longest(tall, 7).resolution, [1, 7, 1]);
        // 0 asks for one cell; a point has one.
        assert_eq!(GridCells::along_longest(wide, 0).resolution, [1, 1, 1]);
        assert_eq!(
            GridCells::along_longest(Aabb::from_point(Vec3::ONE), 9).resolution,
            [1, 1, 1]
        );
        // 3D: 4 × 2 × 1 at 8 along x.
        let bounds = Aabb::new(Vec3::ZERO, Vec3::new(4.0, 2.0, 1.0));
        assert_eq!(GridCells::along_longest(bounds, 8).resolution, [8, 4, 2]);
        assert!(GridCells::along_longest(bounds, u32::MAX).cell_count() as u64 <= MAX_CELLS);
    }

    #[test]
    fn points_and_boxes_find_their_cells_on_the_stored_planes() {
        let cells = GridCells::with_resolution(
            Aabb::new(DVec2::new(-1.0, 0.0), DVec2::new(2.0, 1.0)),
            [3, 2, 7],
        );
        assert_eq!(cells.resolution, [3, 2, 1]);
        assert_eq!(cells.planes[0], vec![-1.0, 0.0, 1.0, 2.0]);
        assert_eq!(cells.cell_along(0, -1.0), 0);
        assert_eq!(
            cells.cell_along(0, 0.0),
            1,
            "a plane belongs to the cell above it"
        );
        assert_eq!(
            cells.cell_along(0, 2.0),
            2,
            "but the far side to the last cell"
        );
        assert_eq!(cells.cell_along(0, -7.0), 0);
        assert_eq!(cells.cell_along(1, 0.75), 1);
        // A box touching the plane x = 0 from below meets the cell above it too.
        let touching = Aabb::new(DVec2::new(-0.5, 0.2), DVec2::new(0.0, 0.3));
        assert_eq!(cells.cells_touching(&touching), ([0, 0, 0], [1, 0, 0]));
        let inside = Aabb::new(DVec2::new(0.2, 0.6), DVec2::new(0.7, 0.9));
        assert_eq!(cells.cells_touching(&inside), ([1, 1, 0], [1, 1, 0]));
        let everything = cells.bounds;
        assert_eq!(cells.cells_touching(&everything), ([0, 0, 0], [2, 1, 0]));
        assert_eq!(cells.index([2, 1, 0]), 5);
        assert_eq!(cells.coordinates(5), [2, 1, 0]);
        assert_eq!(
            cells.cell_bounds([2, 1, 0]),
            Aabb::new(DVec2::new(1.0, 0.5), DVec2::new(2.0, 1.0))
        );
    }
}
