//! Clipping a convex polygon (a triangle, a segment) to a box: the bounds of the part inside,
//! for kD "perfect splits" (Havran 2000, "Heuristic Ray Shooting Algorithms", §4.5; Wald &
//! Havran 2006, §4.3), where a primitive cut by a plane gets the box of its part in each
//! child cell instead of its whole box clipped.

use crate::aabb::Aabb;
use crate::math::{Real, Vector};

/// The box around the part of the convex polygon `corners` inside the closed box `cell`, or
/// `None` if no part of it is. Sutherland & Hodgman 1974, one slab side at a time, in f64.
/// Corners and coordinates on a cell side are exact; a crossing's other coordinates are
/// rounded, so those are widened by a few units of roundoff of the scene's precision (then
/// clamped to the cell): the box is never smaller than the exact one, and no larger than it
/// needs to be where nothing was rounded.
pub(crate) fn clipped_bounds<V: Vector>(corners: &[V], cell: &Aabb<V>) -> Option<Aabb<V>> {
    let dimensions = V::DIM;
    let (low, high) = (cell.min.to_f64_array(), cell.max.to_f64_array());
    let polygon = clip_polygon(corners, cell)?;
    // Rounded coordinates are widened by their roundoff (relative, in the scene's precision,
    // so that converting back cannot make the box smaller); then the box is kept in the cell.
    let widen = 4.0 * V::Scalar::UNIT_ROUNDOFF.to_f64();
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    for (point, rounded) in &polygon {
        for axis in 0..dimensions {
            let margin = if rounded & (1 << axis) != 0 {
                widen * point[axis].abs() + f64::MIN_POSITIVE
            } else {
                0.0
            };
            min[axis] = min[axis].min(point[axis] - margin);
            max[axis] = max[axis].max(point[axis] + margin);
        }
    }
    for axis in 0..dimensions {
        min[axis] = min[axis].max(low[axis]);
        max[axis] = max[axis].min(high[axis]);
    }
    Some(Aabb::new(
        V::from_f64_slice(&min[..dimensions]),
        V::from_f64_slice(&max[..dimensions]),
    ))
}

/// The convex polygon `corners` clipped to the closed box `cell` (Sutherland & Hodgman 1974,
/// one slab side at a time, in f64), each point with a mask of its coordinates that were
/// rounded (crossings' coordinates other than the side's); `None` if no part is inside.
fn clip_polygon<V: Vector>(corners: &[V], cell: &Aabb<V>) -> Option<Vec<([f64; 3], u8)>> {
    let dimensions = V::DIM;
    let mut polygon: Vec<([f64; 3], u8)> = corners
        .iter()
        .map(|corner| (corner.to_f64_array(), 0))
        .collect();
    let mut clipped = Vec::with_capacity(polygon.len() + 6);
    let (low, high) = (cell.min.to_f64_array(), cell.max.to_f64_array());
    for axis in 0..dimensions {
        for (bound, keep_above) in [(low[axis], true), (high[axis], false)] {
            // Signed distance inside the side (>= 0 is kept).
            let inside = |(point, _): &([f64; 3], u8)| {
                if keep_above {
                    point[axis] - bound
                } else {
                    bound - point[axis]
                }
            };
            clipped.clear();
            for (index, start) in polygon.iter().enumerate() {
                let end = &polygon[(index + 1) % polygon.len()];
                let (start_inside, end_inside) = (inside(start), inside(end));
                if start_inside >= 0.0 {
                    clipped.push(*start);
                }
                if (start_inside >= 0.0) != (end_inside >= 0.0) {
                    let t = start_inside / (start_inside - end_inside);
                    let ((a, a_rounded), (b, b_rounded)) = (start, end);
                    let mut crossing = [0.0; 3];
                    let mut rounded = a_rounded | b_rounded;
                    for other in 0..dimensions {
                        crossing[other] = a[other] + t * (b[other] - a[other]);
                        if a[other] != b[other] {
                            rounded |= 1 << other;
                        }
                    }
                    // Exactly on the side, whatever the rounding above.
                    crossing[axis] = bound;
                    rounded &= !(1 << axis);
                    clipped.push((crossing, rounded));
                }
            }
            if clipped.is_empty() {
                return None;
            }
            std::mem::swap(&mut polygon, &mut clipped);
        }
    }
    Some(polygon)
}

/// The part of the convex polygon `corners` inside the closed box `cell`, as its corners (none
/// when no part is inside): also what a view zoomed far in draws of a triangle.
pub fn clipped_polygon<V: Vector>(corners: &[V], cell: &Aabb<V>) -> Vec<V> {
    clip_polygon(corners, cell).map_or_else(Vec::new, |polygon| {
        polygon
            .iter()
            .map(|(point, _)| V::from_f64_slice(&point[..V::DIM]))
            .collect()
    })
}

/// The area of the part of triangle `corners` inside the closed box `cell` (0 when none is).
pub(crate) fn clipped_area<V: Vector>(corners: &[V; 3], cell: &Aabb<V>) -> f64 {
    let Some(polygon) = clip_polygon(corners, cell) else {
        return 0.0;
    };
    // Half the length of the sum of the edges' cross products (the polygon is planar).
    let mut sum = glam::DVec3::ZERO;
    for (index, (start, _)) in polygon.iter().enumerate() {
        let end = glam::DVec3::from_array(polygon[(index + 1) % polygon.len()].0);
        sum += glam::DVec3::from_array(*start).cross(end);
    }
    0.5 * sum.length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec2};

    #[test]
    fn a_triangle_clipped_to_half_of_its_box() {
        // The right triangle (0,0,0) (4,0,0) (0,4,0): in the cell x >= 2 its part is the
        // triangle (2,0) (4,0) (2,2), so y reaches only 2.
        let triangle = [
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(0.0, 4.0, 0.0),
        ];
        let cell = Aabb::new(DVec3::new(2.0, 0.0, 0.0), DVec3::new(4.0, 4.0, 0.0));
        let clipped = clipped_bounds(&triangle, &cell).unwrap();
        assert_eq!(clipped.min, DVec3::new(2.0, 0.0, 0.0));
        assert!(
            (clipped.max - DVec3::new(4.0, 2.0, 0.0))
                .abs()
                .max_element()
                < 1e-12
        );
        // The cell x >= 2, y >= 3 holds no part of it.
        let corner = Aabb::new(DVec3::new(2.0, 3.0, 0.0), DVec3::new(4.0, 4.0, 0.0));
        assert_eq!(clipped_bounds(&triangle, &corner), None);
    }

    #[test]
    fn a_segment_in_2d_and_a_touching_point() {
        let segment = [Vec2::new(-1.0, -1.0), Vec2::new(3.0, 3.0)];
        let cell = Aabb::new(Vec2::ZERO, Vec2::new(1.0, 2.0));
        let clipped = clipped_bounds(&segment, &cell).unwrap();
        assert!(clipped.min.abs().max_element() < 1e-6);
        assert!((clipped.max - Vec2::new(1.0, 1.0)).abs().max_element() < 1e-6);
        // A segment touching the cell at a corner keeps that point.
        let touching = [Vec2::new(1.0, 2.0), Vec2::new(3.0, 5.0)];
        let point = clipped_bounds(&touching, &cell).unwrap();
        assert!(point.max.x >= 1.0 && point.max.y >= 2.0);
    }
}
