//! The kernels' operations written once over any instruction set's registers: a node's
//! child boxes ([`children_in_lanes`]), Möller–Trumbore ([`moller_trumbore4`]) and the
//! watertight test ([`watertight4`]) on a block of four triangles, and one box against a group
//! of a packet's rays ([`box_in_lanes`]). Each instruction set implements [`Register`] for its
//! registers (`x86.rs`, `wasm.rs`); its kernels instantiate these functions with them.

use crate::math::{Real, Vector};
use crate::primitive::{TriangleBlock, TriangleRay};
use crate::simd::kernel::{
    BoxAgainstRays, ChildTests, LANES, MAX_PACKET, NodeLanes, PacketLanes, Planes,
};

/// A register of f32 or f64 lanes and the operations the kernels need. Masks are lanes of all
/// ones or all zeros. An implementation executes its instruction set's instructions: its
/// methods run only inside that set's kernels, which run only after
/// [`Isa::active`](crate::simd::Isa::active) named the set.
pub(crate) trait Register: Copy {
    /// What a lane holds.
    type Scalar: Real;
    /// How many lanes.
    const COUNT: usize;
    fn splat(value: Self::Scalar) -> Self;
    /// The first `COUNT` values of `values`.
    fn from_slice(values: &[Self::Scalar]) -> Self;
    /// Writes the lanes to the first `COUNT` places of `out`.
    fn write_to(self, out: &mut [Self::Scalar]);
    fn add(self, other: Self) -> Self;
    fn sub(self, other: Self) -> Self;
    fn mul(self, other: Self) -> Self;
    fn div(self, other: Self) -> Self;
    fn lt(self, other: Self) -> Self;
    fn gt(self, other: Self) -> Self;
    fn le(self, other: Self) -> Self;
    fn ge(self, other: Self) -> Self;
    fn ne(self, other: Self) -> Self;
    fn or(self, other: Self) -> Self;
    fn and(self, other: Self) -> Self;
    /// `self & !other`.
    fn and_not(self, other: Self) -> Self;
    /// `mask ? self : other`, lane by lane.
    fn select(self, other: Self, mask: Self) -> Self;
    /// `self > other ? self : other`: a NaN `self` gives `other` (the slab module's rule).
    fn later(self, other: Self) -> Self;
    /// `self < other ? self : other`: a NaN `self` gives `other`.
    fn earlier(self, other: Self) -> Self;
    /// A mask's lanes as bits, lane 0 lowest.
    fn bits(self) -> u32;
    /// The mask whose lane `i` is set where bit `i` of `bits` is (the inverse of `bits`).
    fn from_bits(bits: u32) -> Self;
}

/// The slab test of every child of a node (3D), `L::COUNT` children at a time: the arithmetic
/// of `Portable::test_children` (the same planes, products and
/// NaN-ignoring reductions), so the same intervals bit for bit.
#[inline(always)]
pub(crate) fn children_in_lanes<L: Register, const W: usize>(
    planes: &Planes<L::Scalar, W>,
    ray: &NodeLanes<L::Scalar, W>,
    t_max: L::Scalar,
) -> ChildTests<L::Scalar, W> {
    let mut tests = ChildTests {
        t_enter: [L::Scalar::ZERO; W],
        t_exit: [L::Scalar::ZERO; W],
        hit_mask: 0,
    };
    for first in (0..W).step_by(L::COUNT) {
        let mut t_enter = L::from_slice(&ray.t_min);
        let mut t_exit = L::splat(L::Scalar::INFINITY);
        for axis in 0..3 {
            // The near and far planes for this ray, chosen by the sign of its direction
            // (Williams et al. 2005), at offsets found once per ray.
            let (near, far) = ray.planes(planes, axis);
            let origin = L::from_slice(&ray.origin[axis]);
            let inverse = L::from_slice(&ray.inverse[axis]);
            let t_near = L::from_slice(&near[first..]).sub(origin).mul(inverse);
            let t_far = L::from_slice(&far[first..]).sub(origin).mul(inverse);
            t_enter = t_near.later(t_enter);
            t_exit = t_far.earlier(t_exit);
        }
        // The fast mode's scale is 1, and multiplying by 1 changes nothing: it is skipped,
        // to keep a multiplication off the path from a node's planes to its next node.
        let far_scale = ray.far_scale;
        let t_exit = if far_scale == L::Scalar::ONE {
            t_exit
        } else {
            t_exit.mul(L::splat(far_scale))
        };
        let t_exit = t_exit.earlier(L::splat(t_max));
        tests.hit_mask |= t_enter.le(t_exit).bits() << first;
        t_enter.write_to(&mut tests.t_enter[first..]);
        t_exit.write_to(&mut tests.t_exit[first..]);
    }
    tests
}

/// Möller–Trumbore (Möller & Trumbore 1997) lane by lane: each lane's triangle (corner `v0`,
/// edges `e1` and `e2`) against its ray, within `t_min`..`t_max`. The portable code's products
/// and sums in its order (glam's cross and dot), so the same `t`, and its rejections written as
/// it writes them (a NaN `u` or `v` is rejected only through `t`). Returns `t` and the mask of
/// the lanes hit.
#[inline(always)]
fn moller_trumbore_in_lanes<L: Register>(
    v0: [L; 3],
    e1: [L; 3],
    e2: [L; 3],
    origin: [L; 3],
    direction: [L; 3],
    t_min: L,
    t_max: L,
) -> (L, L) {
    let ([e1x, e1y, e1z], [e2x, e2y, e2z]) = (e1, e2);
    let [dx, dy, dz] = direction;
    // p = d × e2
    let px = dy.mul(e2z).sub(e2y.mul(dz));
    let py = dz.mul(e2x).sub(e2z.mul(dx));
    let pz = dx.mul(e2y).sub(e2x.mul(dy));
    let det = e1x.mul(px).add(e1y.mul(py)).add(e1z.mul(pz));
    let (zero, one) = (L::splat(L::Scalar::ZERO), L::splat(L::Scalar::ONE));
    let inv_det = one.div(det);
    let sx = origin[0].sub(v0[0]);
    let sy = origin[1].sub(v0[1]);
    let sz = origin[2].sub(v0[2]);
    let u = sx.mul(px).add(sy.mul(py)).add(sz.mul(pz)).mul(inv_det);
    // q = s × e1
    let qx = sy.mul(e1z).sub(e1y.mul(sz));
    let qy = sz.mul(e1x).sub(e1z.mul(sx));
    let qz = sx.mul(e1y).sub(e1x.mul(sy));
    let v = dx.mul(qx).add(dy.mul(qy)).add(dz.mul(qz)).mul(inv_det);
    let t = e2x.mul(qx).add(e2y.mul(qy)).add(e2z.mul(qz)).mul(inv_det);
    let rejected = u.lt(zero).or(u.gt(one)).or(v.lt(zero).or(u.add(v).gt(one)));
    let accepted = det.ne(zero).and(t.ge(t_min).and(t.le(t_max)));
    (t, accepted.and_not(rejected))
}

/// [`moller_trumbore_in_lanes`] on the four triangles of `block`, a triangle in each lane,
/// against one ray (the edges taken from the corners as the portable code takes them). `NaN`
/// where no hit. `L` has four lanes.
#[inline(always)]
pub(crate) fn moller_trumbore4<L: Register>(
    block: &TriangleBlock<L::Scalar>,
    origin: <L::Scalar as Real>::Vec3,
    direction: <L::Scalar as Real>::Vec3,
    t_min: L::Scalar,
    t_max: L::Scalar,
) -> [L::Scalar; 4] {
    // (Plain loads: `array::map` here is not always inlined.)
    let [v0, v1, v2] = &block.corners;
    let v0 = [
        L::from_slice(&v0[0]),
        L::from_slice(&v0[1]),
        L::from_slice(&v0[2]),
    ];
    let edge = |to: &[[L::Scalar; 4]; 3], axis: usize| L::from_slice(&to[axis]).sub(v0[axis]);
    let (t, hit) = moller_trumbore_in_lanes(
        v0,
        [edge(v1, 0), edge(v1, 1), edge(v1, 2)],
        [edge(v2, 0), edge(v2, 1), edge(v2, 2)],
        [
            L::splat(origin[0]),
            L::splat(origin[1]),
            L::splat(origin[2]),
        ],
        [
            L::splat(direction[0]),
            L::splat(direction[1]),
            L::splat(direction[2]),
        ],
        L::splat(t_min),
        L::splat(t_max),
    );
    let mut out = [L::Scalar::NAN; 4];
    t.select(L::splat(L::Scalar::NAN), hit).write_to(&mut out);
    out
}

/// [`moller_trumbore_in_lanes`] on triangle `lane` of `block`, in every lane, against the rays
/// `first..first + LANES` of a packet, `L::COUNT` rays at a time, each in its own interval
/// (`t_min` to `t_closest`): the block kernel's test with the lanes' roles swapped, so the same
/// `t` bit for bit. `NaN` where no hit; the rays hit as bits.
#[inline(always)]
pub(crate) fn moller_trumbore_rays<L: Register>(
    block: &TriangleBlock<L::Scalar>,
    lane: usize,
    lanes: &PacketLanes<L::Scalar>,
    first: usize,
) -> ([L::Scalar; LANES], u32) {
    let [v0, v1, v2] = &block.corners;
    let corner = |rows: &[[L::Scalar; 4]; 3], axis: usize| L::splat(rows[axis][lane]);
    let v0 = [corner(v0, 0), corner(v0, 1), corner(v0, 2)];
    let edge = |to: &[[L::Scalar; 4]; 3], axis: usize| corner(to, axis).sub(v0[axis]);
    let e1 = [edge(v1, 0), edge(v1, 1), edge(v1, 2)];
    let e2 = [edge(v2, 0), edge(v2, 1), edge(v2, 2)];
    let mut out = [L::Scalar::NAN; LANES];
    let mut hits = 0;
    for start in (0..LANES).step_by(L::COUNT) {
        let rays = first + start..first + LANES;
        let row = |rows: &[[L::Scalar; MAX_PACKET]; 3], axis: usize| {
            L::from_slice(&rows[axis][rays.clone()])
        };
        let (t, hit) = moller_trumbore_in_lanes(
            v0,
            e1,
            e2,
            [
                row(&lanes.origin, 0),
                row(&lanes.origin, 1),
                row(&lanes.origin, 2),
            ],
            [
                row(&lanes.direction, 0),
                row(&lanes.direction, 1),
                row(&lanes.direction, 2),
            ],
            L::from_slice(&lanes.t_min[rays.clone()]),
            L::from_slice(&lanes.t_closest[rays.clone()]),
        );
        t.select(L::splat(L::Scalar::NAN), hit)
            .write_to(&mut out[start..]);
        hits |= hit.bits() << start;
    }
    (out, hits)
}

/// Woop, Benthin & Wald's watertight test (see the one-triangle `watertight` in
/// `primitive::triangle`) on the four triangles of `block` in lanes, with the portable code's
/// operations in its order, so the same `t`. Where an edge function is exactly zero in some
/// lane the portable code redoes it in f64; that is rare (a ray through an edge or a corner),
/// so the whole block then goes to the portable code. `NaN` where no hit. `L` has four lanes.
#[inline(always)]
pub(crate) fn watertight4<L: Register>(
    block: &TriangleBlock<L::Scalar>,
    ray: &TriangleRay<<L::Scalar as Real>::Vec3>,
    t_min: L::Scalar,
    t_max: L::Scalar,
) -> [L::Scalar; 4] {
    let (kx, ky, kz) = (ray.axis_x, ray.axis_y, ray.axis_z);
    let [sx, sy, sz] = ray.shear;
    let (sx, sy, sz) = (L::splat(sx), L::splat(sy), L::splat(sz));
    // (An array: a glam vector indexed by a run-time axis is a `match`, with branches.)
    let origin = ray.ray.origin.to_array3();
    let origin = [
        L::splat(origin[kx]),
        L::splat(origin[ky]),
        L::splat(origin[kz]),
    ];
    let axes = [kx, ky, kz];
    let (a, b, c) = (
        relative(&block.corners[0], axes, origin),
        relative(&block.corners[1], axes, origin),
        relative(&block.corners[2], axes, origin),
    );
    // Shear and scale the corners into ray space.
    let (ax, ay) = (a.0.sub(sx.mul(a.2)), a.1.sub(sy.mul(a.2)));
    let (bx, by) = (b.0.sub(sx.mul(b.2)), b.1.sub(sy.mul(b.2)));
    let (cx, cy) = (c.0.sub(sx.mul(c.2)), c.1.sub(sy.mul(c.2)));
    let u = cx.mul(by).sub(cy.mul(bx));
    let v = ax.mul(cy).sub(ay.mul(cx));
    let w = bx.mul(ay).sub(by.mul(ax));
    let zero = L::splat(L::Scalar::ZERO);
    if u.ne(zero).and(v.ne(zero)).and(w.ne(zero)).bits() != (1 << L::COUNT) - 1 {
        return on_an_edge(block, ray, t_min, t_max);
    }
    let mixed = u
        .lt(zero)
        .or(v.lt(zero))
        .or(w.lt(zero))
        .and(u.gt(zero).or(v.gt(zero)).or(w.gt(zero)));
    let det = u.add(v).add(w);
    let (az, bz, cz) = (sz.mul(a.2), sz.mul(b.2), sz.mul(c.2));
    let t_scaled = u.mul(az).add(v.mul(bz)).add(w.mul(cz));
    // Compare t against the interval before dividing, with the sign of det folded in.
    let (low, high) = (L::splat(t_min).mul(det), L::splat(t_max).mul(det));
    let outside_if_negative = t_scaled.gt(low).or(t_scaled.lt(high));
    let outside_if_positive = t_scaled.lt(low).or(t_scaled.gt(high));
    let outside = outside_if_negative.select(outside_if_positive, det.lt(zero));
    let accepted = det.ne(zero).and_not(mixed.or(outside));
    let mut out = [L::Scalar::NAN; 4];
    t_scaled
        .div(det)
        .select(L::splat(L::Scalar::NAN), accepted)
        .write_to(&mut out);
    out
}

/// [`watertight4`]'s rare case, out of line so that the kernel stays small enough to inline.
#[cold]
#[inline(never)]
fn on_an_edge<S: Real>(
    block: &TriangleBlock<S>,
    ray: &TriangleRay<S::Vec3>,
    t_min: S,
    t_max: S,
) -> [S; 4] {
    block.intersect(ray, t_min, t_max)
}

/// One box against a group of [`LANES`] rays of a packet, `L::COUNT` rays at a time: the
/// arithmetic of `Portable::box_against_rays` (each ray's near plane chosen by the sign of
/// its reciprocal direction, which is its sign bit: a reciprocal is never zero or NaN), so the
/// same intervals bit for bit.
#[inline(always)]
pub(crate) fn box_in_lanes<L: Register>(
    lanes: &PacketLanes<L::Scalar>,
    lower: [L::Scalar; 3],
    upper: [L::Scalar; 3],
    first: usize,
    dims: usize,
    active: u32,
) -> BoxAgainstRays<L::Scalar> {
    let mut tests = BoxAgainstRays {
        t_enter: [L::Scalar::ZERO; LANES],
        t_exit: [L::Scalar::ZERO; LANES],
        hits: 0,
        entries: [L::Scalar::ZERO; LANES],
    };
    let infinity = L::splat(L::Scalar::INFINITY);
    let zero = L::splat(L::Scalar::ZERO);
    for start in (0..LANES).step_by(L::COUNT) {
        let at = first + start;
        let mut t_enter = L::from_slice(&lanes.t_min[at..]);
        let mut t_exit = L::splat(L::Scalar::INFINITY);
        for axis in 0..dims {
            let origin = L::from_slice(&lanes.origin[axis][at..]);
            let inverse = L::from_slice(&lanes.inv_direction[axis][at..]);
            let t_lower = L::splat(lower[axis]).sub(origin).mul(inverse);
            let t_upper = L::splat(upper[axis]).sub(origin).mul(inverse);
            let negative = inverse.lt(zero);
            t_enter = t_upper.select(t_lower, negative).later(t_enter);
            t_exit = t_lower.select(t_upper, negative).earlier(t_exit);
        }
        let t_exit = t_exit
            .mul(L::splat(lanes.far_scale))
            .earlier(L::from_slice(&lanes.t_closest[at..]));
        let hit = t_enter.le(t_exit).and(L::from_bits(active >> start));
        tests.hits |= hit.bits() << start;
        t_enter.write_to(&mut tests.t_enter[start..]);
        t_exit.write_to(&mut tests.t_exit[start..]);
        t_enter
            .select(infinity, hit)
            .write_to(&mut tests.entries[start..]);
    }
    tests
}

/// A block's corner relative to the ray's origin, its axes permuted to the ray's (a function,
/// not a closure: the compiler does not always inline closures here).
#[inline(always)]
fn relative<L: Register>(
    corner: &[[L::Scalar; 4]; 3],
    [kx, ky, kz]: [usize; 3],
    [ox, oy, oz]: [L; 3],
) -> (L, L, L) {
    (
        L::from_slice(&corner[kx]).sub(ox),
        L::from_slice(&corner[ky]).sub(oy),
        L::from_slice(&corner[kz]).sub(oz),
    )
}
