//! Does a primitive reach into a box? What a grid's builder asks of every cell a primitive's
//! box touches, so that a primitive is listed only in the cells it really reaches.
//!
//! Both tests are exact up to rounding, and rounding is resolved towards "yes": a primitive
//! that touches a cell's side, edge or corner is in the cell (cells are closed), and one that
//! misses it by less than the arithmetic can tell is too. Listing a primitive in a cell it
//! does not reach costs a test; leaving it out of one it reaches would lose hits.

use crate::aabb::Aabb;
use crate::math::{Vector, Vector3};

/// The relative size of what f64 arithmetic cannot tell from zero here, with room to spare:
/// the inputs are at most f64, and a test takes a few products and sums of them.
const TOLERANCE: f64 = 1e-12;

/// Whether the triangle `corners` reaches into the closed box `cell`: the separating axis
/// test of Akenine-Möller 2001, "Fast 3D Triangle-Box Overlap Testing" (the box's three
/// axes, the triangle's normal, and the nine cross products of their edges), in f64 and
/// conservative (see the module's docs). A degenerate triangle (a segment or a point) is
/// tested as what it is.
pub(crate) fn triangle_overlaps_box<V: Vector3>(corners: &[V; 3], cell: &Aabb<V>) -> bool {
    let (low, high) = (cell.min.to_f64_array(), cell.max.to_f64_array());
    let center: [f64; 3] = std::array::from_fn(|axis| 0.5 * (low[axis] + high[axis]));
    let half: [f64; 3] = std::array::from_fn(|axis| 0.5 * (high[axis] - low[axis]));
    // The triangle relative to the box's centre.
    let points: [[f64; 3]; 3] = corners.map(|corner| {
        let corner = corner.to_f64_array();
        std::array::from_fn(|axis| corner[axis] - center[axis])
    });
    // Separated along `axis` when the triangle's projection lies beyond the box's radius,
    // by more than rounding can explain.
    let separated = |axis: [f64; 3]| {
        let project =
            |point: &[f64; 3]| point[0] * axis[0] + point[1] * axis[1] + point[2] * axis[2];
        let [a, b, c] = [
            project(&points[0]),
            project(&points[1]),
            project(&points[2]),
        ];
        let (least, greatest) = (a.min(b).min(c), a.max(b).max(c));
        let radius = half[0] * axis[0].abs() + half[1] * axis[1].abs() + half[2] * axis[2].abs();
        let scale = least.abs().max(greatest.abs()).max(radius) + f64::MIN_POSITIVE;
        let slack = TOLERANCE * scale;
        least > radius + slack || greatest < -radius - slack
    };
    // The box's own axes: the triangle's box against the cell.
    for axis in 0..3 {
        let mut unit = [0.0; 3];
        unit[axis] = 1.0;
        if separated(unit) {
            return false;
        }
    }
    let edges: [[f64; 3]; 3] = std::array::from_fn(|edge| {
        let (from, to) = (points[edge], points[(edge + 1) % 3]);
        std::array::from_fn(|axis| to[axis] - from[axis])
    });
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    // The nine edge × box-axis directions (a zero one, from an edge along a box axis,
    // separates nothing: every projection is zero).
    for edge in edges {
        for axis in 0..3 {
            let mut unit = [0.0; 3];
            unit[axis] = 1.0;
            if separated(cross(edge, unit)) {
                return false;
            }
        }
    }
    // The triangle's plane (zero for a degenerate triangle: no separation there).
    !separated(cross(edges[0], edges[1]))
}

/// Whether the closed ball (disc in 2D) at `center` of `radius` reaches into the closed box
/// `cell`: its centre's distance to the box, at most the radius (Arvo 1990, "A simple method
/// for box-sphere intersection testing"), conservative as above.
pub(crate) fn sphere_overlaps_box<V: Vector>(center: V, radius: V::Scalar, cell: &Aabb<V>) -> bool {
    use crate::math::Real;
    let (center, low, high) = (
        center.to_f64_array(),
        cell.min.to_f64_array(),
        cell.max.to_f64_array(),
    );
    let mut distance_squared = 0.0;
    let mut scale = 0.0f64;
    for axis in 0..V::DIM {
        let outside = if center[axis] < low[axis] {
            low[axis] - center[axis]
        } else if center[axis] > high[axis] {
            center[axis] - high[axis]
        } else {
            0.0
        };
        distance_squared += outside * outside;
        scale = scale
            .max(center[axis].abs())
            .max(low[axis].abs())
            .max(high[axis].abs());
    }
    let radius = radius.to_f64();
    let reach = radius + TOLERANCE * (scale + radius) + f64::MIN_POSITIVE;
    distance_squared <= reach * reach
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, Vec3};

    use super::*;

    fn unit_box() -> Aabb<Vec3> {
        Aabb::new(Vec3::ZERO, Vec3::ONE)
    }

    #[test]
    fn triangles_in_touching_and_apart() {
        let cell = unit_box();
        let inside = [
            Vec3::splat(0.2),
            Vec3::new(0.8, 0.2, 0.5),
            Vec3::new(0.2, 0.8, 0.5),
        ];
        assert!(triangle_overlaps_box(&inside, &cell));
        // Crossing the box with every corner outside it.
        let across = [
            Vec3::new(-5.0, -5.0, 0.5),
            Vec3::new(5.0, -5.0, 0.5),
            Vec3::new(0.0, 10.0, 0.5),
        ];
        assert!(triangle_overlaps_box(&across, &cell));
        // Touching the box's top face from above, and one corner touching its corner.
        let on_face = [
            Vec3::new(0.5, 0.5, 1.0),
            Vec3::new(2.0, 0.5, 1.0),
            Vec3::new(0.5, 2.0, 1.0),
        ];
        assert!(triangle_overlaps_box(&on_face, &cell));
        let at_corner = [
            Vec3::ONE,
            Vec3::new(2.0, 1.0, 3.0),
            Vec3::new(3.0, 2.0, 1.0),
        ];
        assert!(triangle_overlaps_box(&at_corner, &cell));
        // The triangle's box overlaps the cell, but the triangle passes beside the corner:
        // only its own edge axis separates them.
        let beside = [
            Vec3::new(1.5, -0.5, 0.5),
            Vec3::new(-0.5, 1.5, 0.5),
            Vec3::new(1.6, 1.6, 0.5),
        ];
        assert!(
            triangle_overlaps_box(&beside, &cell),
            "crosses the box's middle"
        );
        let past_corner = [
            Vec3::new(2.1, 0.0, 0.5),
            Vec3::new(0.0, 2.1, 0.5),
            Vec3::new(2.1, 2.1, 0.5),
        ];
        assert!(!triangle_overlaps_box(&past_corner, &cell));
        // Its plane passes beside the box: only the normal separates them.
        let tilted = [
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 0.0, 2.0),
        ]
        .map(|point| point + Vec3::splat(1.0));
        assert!(!triangle_overlaps_box(&tilted, &cell));
        let through = [
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 0.0, 2.0),
        ];
        assert!(triangle_overlaps_box(&through, &cell));
        // A degenerate triangle (a segment) beside the box.
        let segment = [
            Vec3::new(2.0, 0.0, 0.5),
            Vec3::new(0.0, 2.0, 0.5).lerp(Vec3::new(2.0, 0.0, 0.5), 0.5),
            Vec3::new(3.0, -1.0, 0.5),
        ];
        assert!(!triangle_overlaps_box(
            &segment,
            &Aabb::new(Vec3::ZERO, Vec3::splat(0.9))
        ));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 4000,
            failure_persistence: None,
            ..proptest::prelude::ProptestConfig::default()
        })]

        /// The separating axis test says a triangle reaches a box exactly where clipping the
        /// triangle to the box leaves something (an independent test), but where the
        /// triangle passes within rounding of the box, which it counts as touching.
        #[test]
        fn the_axis_test_agrees_with_clipping(
            corners in proptest::array::uniform3(proptest::array::uniform3(-3i32..4)),
            offset in proptest::array::uniform3(proptest::prelude::prop_oneof![
                3 => proptest::prelude::Just(0.0f32),
                1 => -1.0f32..1.0,
            ]),
            size in proptest::array::uniform3(proptest::prelude::prop_oneof![
                3 => proptest::prelude::Just(1.0f32),
                1 => 0.0f32..2.0,
            ]),
        ) {
            // Whole-number corners make touching common; the offsets, nearly touching.
            let triangle = corners.map(|corner| {
                Vec3::new(corner[0] as f32, corner[1] as f32, corner[2] as f32) * 0.5
                    + Vec3::from_array(offset) * 0.25
            });
            let cell = Aabb::new(Vec3::ZERO, Vec3::from_array(size));
            let clipped = crate::primitive::clip::clipped_bounds(&triangle, &cell).is_some();
            let axes = triangle_overlaps_box(&triangle, &cell);
            if clipped {
                proptest::prop_assert!(axes, "{triangle:?} {cell:?}");
            } else if axes {
                // Only a graze: the box grown by a hair reaches the clipped triangle.
                let hair = Vec3::splat(1e-5);
                let grown = Aabb::new(cell.min - hair, cell.max + hair);
                proptest::prop_assert!(
                    crate::primitive::clip::clipped_bounds(&triangle, &grown).is_some(),
                    "{triangle:?} {cell:?}"
                );
            }
        }
    }

    #[test]
    fn discs_reach_boxes_by_their_distance() {
        let cell = Aabb::new(DVec2::ZERO, DVec2::ONE);
        assert!(sphere_overlaps_box(DVec2::new(0.5, 0.5), 0.1, &cell));
        assert!(
            sphere_overlaps_box(DVec2::new(2.0, 0.5), 1.0, &cell),
            "touches a side"
        );
        assert!(!sphere_overlaps_box(DVec2::new(2.0, 0.5), 0.99, &cell));
        // Near a corner the box's corner is what it must reach.
        let corner_distance = (2.0f64).sqrt() * 0.5;
        assert!(!sphere_overlaps_box(
            DVec2::new(1.5, 1.5),
            corner_distance * 0.99,
            &cell
        ));
        assert!(sphere_overlaps_box(
            DVec2::new(1.5, 1.5),
            corner_distance * 1.01,
            &cell
        ));
    }
}
