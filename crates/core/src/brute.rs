//! The lecture's trivial loop: test every primitive. Correct, O(n) per ray, and the reference
//! every structure is checked against.

use crate::math::Vector;
use crate::observer::Observer;
use crate::primitive::PrimitiveSet;
use crate::query::{Hit, Query, TraceOptions};
use crate::ray::Ray;

/// Tests `ray` against every primitive in order, telling `observer` about each test.
pub fn brute_force<V: Vector, P: PrimitiveSet<V>, O: Observer<V::Scalar>>(
    primitives: &P,
    ray: &Ray<V>,
    options: &TraceOptions,
    observer: &mut O,
) -> Option<Hit<V::Scalar>> {
    let prepared = primitives.prepare(ray, options.hit_test);
    let mut closest: Option<Hit<V::Scalar>> = None;
    for index in 0..primitives.len() {
        let t_max = closest.map_or(ray.t_max, |hit| hit.t);
        let t_hit = primitives.intersect(&prepared, index, ray.t_min, t_max);
        observer.primitive_tested(index as u32, t_hit);
        if let Some(t) = t_hit {
            let primitive = index as u32;
            if closest.is_none_or(|hit| hit.is_beaten_by(primitive, t)) {
                closest = Some(Hit { primitive, t });
                observer.closest_hit_updated(primitive, t);
                if options.query == Query::Any {
                    break;
                }
            }
        }
    }
    closest
}
