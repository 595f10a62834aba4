//! A camera: which ray goes through which pixel, and the matching projection for drawing.
//!
//! One camera serves the benchmark's coherent rays (`accelviz-cli bench --camera`), the heat
//! maps ([`crate::heatmap`]) and the app's 3D view: the ray a click picks is the ray through
//! that pixel, and the image the GPU draws uses [`Camera::view_projection`], built from the
//! same eye, basis and field of view. Pixels are numbered row by row from the top left;
//! pixel `(column, row)` covers `[column, column + 1) × [row, row + 1)` and its ray goes
//! through its centre.

use glam::{DMat4, DVec3, DVec4};

use crate::aabb::Aabb;
use crate::math::Vector3;
use crate::ray::{Ray, RayError};

/// How the camera maps the image plane to rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// A pinhole: every ray starts at the eye; `fov` (radians) is the angle across the
    /// image's shorter side: top to bottom of a landscape image, left to right of a portrait
    /// one. So what fills a square image fills any other, not only one as wide as high (a
    /// tall, narrow view with a fixed vertical angle cut a framed scene at its sides).
    Perspective {
        /// The field of view across the image's shorter side in radians, in (0, π).
        fov: f64,
    },
    /// Parallel rays along the view direction, from a plane through the eye; the image's
    /// shorter side is `2 · half_size` world units long.
    Orthographic {
        /// Half the image's shorter side in world units.
        half_size: f64,
    },
}

/// Where the camera is, where it looks, and how it projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye (the pinhole, or the centre of the orthographic image plane).
    pub eye: DVec3,
    /// The point the camera looks at: the centre of the image.
    pub target: DVec3,
    /// Which way is up; need not be perpendicular to the view direction, only not parallel.
    pub up: DVec3,
    /// Perspective or orthographic.
    pub projection: Projection,
}

/// The camera's orthonormal basis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basis {
    /// Towards the image's right edge.
    pub right: DVec3,
    /// Towards the image's top edge.
    pub up: DVec3,
    /// From the eye to the target.
    pub forward: DVec3,
}

impl Camera {
    /// The field of view of [`Camera::framing`] (across the image's shorter side): 45°.
    pub const FRAMING_FOV_DEGREES: f64 = 45.0;

    /// The benchmark's camera (`bench --camera WxH`, `heatmap`): a 45° pinhole looking at the
    /// box's centre from the +z side, slightly raised (direction (0.25, 0.35, 1)), from just
    /// far enough that the box's bounding sphere fills the frame's shorter side.
    pub fn framing(bounds: &Aabb<DVec3>) -> Self {
        let (center, radius) = bounding_sphere_of_box(bounds);
        let fov = Self::FRAMING_FOV_DEGREES.to_radians();
        let distance = radius / (fov / 2.0).sin();
        Self {
            eye: center + DVec3::new(0.25, 0.35, 1.0).normalize() * distance,
            target: center,
            up: DVec3::Y,
            projection: Projection::Perspective { fov },
        }
    }

    /// The basis: forward from the eye to the target, right = forward × up, and up again
    /// made perpendicular.
    pub fn basis(&self) -> Basis {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        Basis { right, up, forward }
    }

    /// Half the image's size at unit distance in front of a pinhole (perspective), or in
    /// world units (orthographic), for an image of `aspect = width / height`:
    /// `(half_width, half_height)`, the shorter side's half the projection's.
    fn half_extent(&self, aspect: f64) -> (f64, f64) {
        let half_shorter = match self.projection {
            Projection::Perspective { fov } => (fov / 2.0).tan(),
            Projection::Orthographic { half_size } => half_size,
        };
        if aspect >= 1.0 {
            (half_shorter * aspect, half_shorter)
        } else {
            (half_shorter, half_shorter / aspect)
        }
    }

    /// The ray through the image point `(x, y)` in pixels (`(column + 0.5, row + 0.5)` is a
    /// pixel's centre) of a `width × height` image: its origin and its direction (not
    /// normalised: a perspective ray's direction is `forward` plus the offset on the image
    /// plane at unit distance).
    pub fn ray_through(&self, x: f64, y: f64, width: usize, height: usize) -> (DVec3, DVec3) {
        let Basis { right, up, forward } = self.basis();
        let (half_width, half_height) =
            self.half_extent(width.max(1) as f64 / height.max(1) as f64);
        let horizontal = (x / width.max(1) as f64 * 2.0 - 1.0) * half_width;
        let vertical = (1.0 - y / height.max(1) as f64 * 2.0) * half_height;
        match self.projection {
            Projection::Perspective { .. } => {
                (self.eye, forward + right * horizontal + up * vertical)
            }
            Projection::Orthographic { .. } => {
                (self.eye + right * horizontal + up * vertical, forward)
            }
        }
    }

    /// The ray through the centre of pixel `(column, row)`, over `[0, +∞)`, in the precision
    /// of `V` (checked again after rounding, as a ray read from a file is).
    pub fn pixel_ray<V: Vector3>(
        &self,
        column: usize,
        row: usize,
        width: usize,
        height: usize,
    ) -> Result<Ray<V>, RayError> {
        let (origin, direction) =
            self.ray_through(column as f64 + 0.5, row as f64 + 0.5, width, height);
        let ray = Ray::<DVec3>::try_new(origin, direction)?.cast::<V>();
        Ray::try_with_interval(ray.origin, ray.direction, ray.t_min, ray.t_max)
    }

    /// The matrix from world to clip space (wgpu's: depth in [0, 1]) for an image of
    /// `aspect = width / height`, drawing depths from `near` to `far` in front of the eye.
    /// A point drawn at pixel `(x, y)` lies on [`Camera::ray_through`]`(x, y)`.
    pub fn view_projection(&self, aspect: f64, near: f64, far: f64) -> DMat4 {
        let Basis { right, up, forward } = self.basis();
        // The view matrix from the same basis the rays use (right, up, −forward).
        let view = DMat4::from_cols(
            right.extend(0.0),
            up.extend(0.0),
            (-forward).extend(0.0),
            self.eye.extend(1.0),
        )
        .inverse();
        // Right-handed view space (looking down −z) to clip space with depth 0 at `near` and
        // 1 at `far`, as wgpu expects.
        let depth_scale = 1.0 / (near - far);
        let (half_width, half_height) = self.half_extent(aspect);
        let projection = match self.projection {
            Projection::Perspective { .. } => DMat4::from_cols(
                DVec4::new(1.0 / half_width, 0.0, 0.0, 0.0),
                DVec4::new(0.0, 1.0 / half_height, 0.0, 0.0),
                DVec4::new(0.0, 0.0, far * depth_scale, -1.0),
                DVec4::new(0.0, 0.0, near * far * depth_scale, 0.0),
            ),
            Projection::Orthographic { .. } => DMat4::from_cols(
                DVec4::new(1.0 / half_width, 0.0, 0.0, 0.0),
                DVec4::new(0.0, 1.0 / half_height, 0.0, 0.0),
                DVec4::new(0.0, 0.0, depth_scale, 0.0),
                DVec4::new(0.0, 0.0, near * depth_scale, 1.0),
            ),
        };
        projection * view
    }

    /// Near and far drawing depths that hold everything within `radius` of `center`, for
    /// [`Camera::view_projection`]: as tight as the scene allows, for depth precision.
    pub fn depth_range(&self, center: DVec3, radius: f64) -> (f64, f64) {
        let distance = (center - self.eye).dot(self.basis().forward);
        let far = (distance + radius).max(1e-6);
        let near = match self.projection {
            // A perspective near plane must stay in front of the eye.
            Projection::Perspective { .. } => (distance - radius).max(far * 1e-4),
            // Orthographic rays start on the eye's plane and may look at things behind it.
            Projection::Orthographic { .. } => distance - radius,
        };
        (near, far)
    }
}

/// The centre of `bounds` and half its diagonal (never zero): the sphere around the box.
pub fn bounding_sphere_of_box(bounds: &Aabb<DVec3>) -> (DVec3, f64) {
    (
        bounds.center(),
        (bounds.extent().length() * 0.5).max(f64::MIN_POSITIVE),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Aabb<DVec3> {
        Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0))
    }

    #[test]
    fn the_centre_pixel_looks_at_the_target() {
        for camera in [
            Camera::framing(&unit_box()),
            Camera {
                projection: Projection::Orthographic { half_size: 2.0 },
                ..Camera::framing(&unit_box())
            },
        ] {
            let (origin, direction) = camera.ray_through(50.0, 30.0, 100, 60);
            let to_target = camera.target - origin;
            assert!(
                direction.normalize().dot(to_target.normalize()) > 1.0 - 1e-12,
                "{camera:?}"
            );
        }
    }

    #[test]
    fn drawn_points_lie_on_their_pixels_rays() {
        // Project points along rays through several pixels: each lands on its pixel.
        for ((width, height), projection) in
            [(64usize, 48usize), (48, 64)].into_iter().flat_map(|size| {
                [
                    Projection::Perspective { fov: 0.9 },
                    Projection::Orthographic { half_size: 1.7 },
                ]
                .map(|projection| (size, projection))
            })
        {
            let camera = Camera {
                eye: DVec3::new(3.0, 2.0, 5.0),
                target: DVec3::new(0.1, -0.2, 0.3),
                up: DVec3::Y,
                projection,
            };
            let matrix = camera.view_projection(width as f64 / height as f64, 0.5, 20.0);
            for (x, y) in [(0.5, 0.5), (10.25, 40.0), (63.5, 1.5), (32.0, 24.0)] {
                let (origin, direction) = camera.ray_through(x, y, width, height);
                let point = origin + direction.normalize() * 4.0;
                let clip = matrix * point.extend(1.0);
                let ndc = clip.truncate() / clip.w;
                let pixel_x = (ndc.x + 1.0) / 2.0 * width as f64;
                let pixel_y = (1.0 - ndc.y) / 2.0 * height as f64;
                assert!(
                    (pixel_x - x).abs() < 1e-9 && (pixel_y - y).abs() < 1e-9,
                    "{projection:?} ({x}, {y}) drawn at ({pixel_x}, {pixel_y})"
                );
                assert!((0.0..=1.0).contains(&ndc.z), "depth {}", ndc.z);
            }
        }
    }

    #[test]
    fn the_framed_sphere_fits_landscape_and_portrait_images() {
        let camera = Camera::framing(&unit_box());
        let (center, radius) = bounding_sphere_of_box(&unit_box());
        let seen_at = (radius / (camera.eye - center).length()).asin();
        let forward = camera.basis().forward;
        for (width, height) in [(64usize, 48usize), (48, 64), (20, 100), (100, 100)] {
            // The middles of the left and top edges: the sphere fits between the edges, and
            // touches those of the shorter side.
            let left = camera
                .ray_through(0.0, height as f64 / 2.0, width, height)
                .1;
            let top = camera.ray_through(width as f64 / 2.0, 0.0, width, height).1;
            let [across, down] = [left, top].map(|edge| edge.normalize().dot(forward).acos());
            assert!(
                across >= seen_at - 1e-12 && down >= seen_at - 1e-12,
                "{width}x{height}: {across} and {down} against {seen_at}"
            );
            let shorter = if width >= height { down } else { across };
            assert!((shorter - seen_at).abs() < 1e-12, "{width}x{height}");
        }
    }

    #[test]
    fn depth_range_holds_the_sphere() {
        let camera = Camera::framing(&unit_box());
        let (near, far) = camera.depth_range(DVec3::ZERO, 3f64.sqrt());
        let distance = (camera.eye).length();
        assert!(near > 0.0 && near <= distance - 3f64.sqrt() + 1e-12);
        assert!((far - (distance + 3f64.sqrt())).abs() < 1e-9);
    }
}
