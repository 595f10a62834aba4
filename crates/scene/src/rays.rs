//! Ray files and seeded ray generators.
//!
//! A ray file has one ray a line, `ox oy oz dx dy dz [tmin tmax]`; a line starting with `#`
//! is a comment, a blank line is skipped. The interval defaults to `[0, +inf)`; `tmax` may be
//! `inf`.

use accelviz_core::camera::bounding_sphere_of_box;
use accelviz_core::{Aabb, Ray, RayError, Vector};
use glam::{DVec3, Vec3};

use crate::error::{LoadError, read_text};
use crate::rng::SplitMix64;

/// One ray as read or generated, in f64, with the line it came from (0 when generated).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RaySpec {
    /// The 1-based line in its file, or 0.
    pub line: usize,
    /// Origin.
    pub origin: [f64; 3],
    /// Direction (nonzero).
    pub direction: [f64; 3],
    /// Start of the interval.
    pub t_min: f64,
    /// End of the interval (may be +∞).
    pub t_max: f64,
}

impl RaySpec {
    /// A generated ray (no file line) over `[0, +inf)`.
    pub fn generated(origin: DVec3, direction: DVec3) -> Self {
        Self {
            line: 0,
            origin: origin.to_array(),
            direction: direction.to_array(),
            t_min: 0.0,
            t_max: f64::INFINITY,
        }
    }

    /// The ray in the precision of `V` (checked again after rounding).
    pub fn to_ray<V: Vector>(&self) -> Result<Ray<V>, RayError> {
        Ray::<DVec3> {
            origin: DVec3::from_array(self.origin),
            direction: DVec3::from_array(self.direction),
            t_min: self.t_min,
            t_max: self.t_max,
        }
        .cast::<V>()
        .revalidated()
    }
}

trait Revalidate: Sized {
    fn revalidated(self) -> Result<Self, RayError>;
}

impl<V: Vector> Revalidate for Ray<V> {
    fn revalidated(self) -> Result<Self, RayError> {
        Ray::try_with_interval(self.origin, self.direction, self.t_min, self.t_max)
    }
}

/// Reads a ray file whole (up to [`MAX_FILE_BYTES`](crate::error::MAX_FILE_BYTES); a
/// larger one is read a line at a time with [`RayReader`]).
pub fn load_rays(path: &str) -> Result<Vec<RaySpec>, LoadError> {
    parse_rays(&read_text(path)?, path)
}

/// Parses ray-file text; `path` names it in errors.
pub fn parse_rays(text: &str, path: &str) -> Result<Vec<RaySpec>, LoadError> {
    let mut rays = Vec::new();
    for (line_index, line) in text.lines().enumerate() {
        if let Some(ray) = parse_ray_line(line, line_index + 1, path)? {
            rays.push(ray);
        }
    }
    Ok(rays)
}

/// `ray` as a ray-file line (`ox oy oz dx dy dz`, and `tmin tmax` when the interval is not
/// `[0, inf)`), each number in the fewest digits that read back as the same f64, so the line
/// names exactly this ray ([`parse_ray_line`] reads it back bit for bit).
pub fn ray_line(ray: &RaySpec) -> String {
    let numbers = ray.origin.iter().chain(&ray.direction);
    let mut line = numbers
        .map(|value| format!("{value:?}"))
        .collect::<Vec<_>>()
        .join(" ");
    if ray.t_min != 0.0 || ray.t_max != f64::INFINITY {
        line.push_str(&format!(" {:?} {:?}", ray.t_min, ray.t_max));
    }
    line
}

/// The longest line a ray file may have: a ray is eight numbers.
pub const MAX_RAY_LINE_BYTES: usize = 4096;

/// One line of a ray file: a ray, or `None` for a blank line or a `#` comment.
pub fn parse_ray_line(
    line: &str,
    line_number: usize,
    path: &str,
) -> Result<Option<RaySpec>, LoadError> {
    let trimmed = line.trim();
    if trimmed.is_empty() || trimmed.starts_with('#') {
        return Ok(None);
    }
    let fail = |problem: String| LoadError::at_line(path, line_number, problem);
    let mut words = [""; 8];
    let mut word_count = 0;
    for word in trimmed.split_ascii_whitespace() {
        if word_count < words.len() {
            words[word_count] = word;
        }
        word_count += 1;
    }
    if word_count != 6 && word_count != 8 {
        return Err(fail(format!(
            "a ray is 'ox oy oz dx dy dz [tmin tmax]', found {}",
            accelviz_core::format::counted(word_count, "value", "values")
        )));
    }
    let mut numbers = [0.0f64; 8];
    for (slot, word) in words[..word_count].iter().enumerate() {
        numbers[slot] = word
            .parse()
            .map_err(|_| fail(format!("'{word}' is not a number")))?;
    }
    let (t_min, t_max) = if word_count == 8 {
        (numbers[6], numbers[7])
    } else {
        (0.0, f64::INFINITY)
    };
    if !t_min.is_finite() || t_max.is_nan() || t_max == f64::NEG_INFINITY {
        return Err(fail(format!(
            "the interval [{t_min}, {t_max}] must have a finite tmin and a tmax that is a number or inf"
        )));
    }
    let ray = RaySpec {
        line: line_number,
        origin: [numbers[0], numbers[1], numbers[2]],
        direction: [numbers[3], numbers[4], numbers[5]],
        t_min,
        t_max,
    };
    // Check in both precisions: a direction can be nonzero in f64 and zero in f32.
    for (precision, result) in [
        ("", ray.to_ray::<DVec3>().err()),
        (" in f32 precision", ray.to_ray::<Vec3>().err()),
    ] {
        if let Some(error) = result {
            return Err(fail(format!("bad ray{precision}: {error}")));
        }
    }
    Ok(Some(ray))
}

/// A ray file read a line at a time, so a file of any size takes a few kilobytes: each item is
/// a ray, or the first error (which names the file and line; the reader then stops).
pub struct RayReader {
    path: String,
    reader: std::io::BufReader<std::fs::File>,
    line_number: usize,
    line: Vec<u8>,
    failed: bool,
}

impl RayReader {
    /// Opens `path`.
    pub fn open(path: &str) -> Result<Self, LoadError> {
        let file = std::fs::File::open(path).map_err(|cause| LoadError::Io {
            path: path.to_owned(),
            cause,
        })?;
        Ok(Self {
            path: path.to_owned(),
            reader: std::io::BufReader::with_capacity(1 << 16, file),
            line_number: 0,
            line: Vec::with_capacity(128),
            failed: false,
        })
    }
}

impl RayReader {
    /// The next lines of the file, whole, about `bytes` long in all, with the number of the
    /// first: what a caller parses with [`parse_ray_line`] (on several threads, say). `None`
    /// at the end.
    pub fn next_block(&mut self, bytes: usize) -> Option<Result<(usize, String), LoadError>> {
        use std::io::{BufRead, Read};
        if self.failed {
            return None;
        }
        let first_line = self.line_number + 1;
        let mut block = Vec::with_capacity(bytes + MAX_RAY_LINE_BYTES);
        while block.len() < bytes {
            let start = block.len();
            let limit = MAX_RAY_LINE_BYTES as u64 + 1;
            match (&mut self.reader).take(limit).read_until(b'\n', &mut block) {
                Ok(0) => break,
                Ok(_) => self.line_number += 1,
                Err(cause) => {
                    self.failed = true;
                    return Some(Err(LoadError::Io {
                        path: self.path.clone(),
                        cause,
                    }));
                }
            }
            if block.len() - start > MAX_RAY_LINE_BYTES && block.last() != Some(&b'\n') {
                self.failed = true;
                return Some(Err(LoadError::at_line(
                    &self.path,
                    self.line_number,
                    format!("the line is longer than {MAX_RAY_LINE_BYTES} bytes"),
                )));
            }
        }
        if block.is_empty() {
            return None;
        }
        Some(String::from_utf8(block).map_err(|error| {
            self.failed = true;
            let offset = error.utf8_error().valid_up_to();
            let line = error.as_bytes()[..offset]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            LoadError::at_line(&self.path, first_line + line, "the line is not UTF-8 text")
        }))
        .map(|text| text.map(|text| (first_line, text)))
    }
}

impl Iterator for RayReader {
    type Item = Result<RaySpec, LoadError>;

    fn next(&mut self) -> Option<Self::Item> {
        use std::io::{BufRead, Read};
        while !self.failed {
            self.line.clear();
            self.line_number += 1;
            let limit = MAX_RAY_LINE_BYTES as u64 + 1;
            let parsed = match (&mut self.reader)
                .take(limit)
                .read_until(b'\n', &mut self.line)
            {
                Ok(0) => return None,
                Err(cause) => Err(LoadError::Io {
                    path: self.path.clone(),
                    cause,
                }),
                Ok(_)
                    if self.line.len() > MAX_RAY_LINE_BYTES && self.line.last() != Some(&b'\n') =>
                {
                    Err(LoadError::at_line(
                        &self.path,
                        self.line_number,
                        format!("the line is longer than {MAX_RAY_LINE_BYTES} bytes"),
                    ))
                }
                Ok(_) => match std::str::from_utf8(&self.line) {
                    Ok(text) => parse_ray_line(text, self.line_number, &self.path),
                    Err(_) => Err(LoadError::at_line(
                        &self.path,
                        self.line_number,
                        "the line is not UTF-8 text",
                    )),
                },
            };
            match parsed {
                Ok(None) => continue,
                Ok(Some(ray)) => return Some(Ok(ray)),
                Err(error) => {
                    self.failed = true;
                    return Some(Err(error));
                }
            }
        }
        None
    }
}

/// `count` random rays around `bounds`, the same for the same seed on every machine.
///
/// Each ray starts on the sphere of radius `2r` around the box's centre (`r` half the box's
/// diagonal, so every origin is outside the box) at a uniformly random point, and is aimed at
/// a uniformly random point inside the box. Its direction is that difference (not normalised,
/// so `t = 1` is the aim point); its interval is `[0, +inf)`.
pub fn random_rays(bounds: &Aabb<DVec3>, count: usize, seed: u64) -> Vec<RaySpec> {
    let mut rng = SplitMix64::new(seed);
    let (center, radius) = bounding_sphere_of_box(bounds);
    let radius = 2.0 * radius;
    let mut rays = Vec::with_capacity(count);
    while rays.len() < count {
        let origin = center + DVec3::from_array(rng.unit_vector()) * radius;
        let target = DVec3::new(
            rng.range(bounds.min.x, bounds.max.x),
            rng.range(bounds.min.y, bounds.max.y),
            rng.range(bounds.min.z, bounds.max.z),
        );
        let direction = target - origin;
        if direction == DVec3::ZERO {
            continue;
        }
        rays.push(RaySpec::generated(origin, direction));
    }
    rays
}

/// Where a benchmark's rays come from: the same choices for `accelviz-cli bench` and for the
/// peer benchmark, so both trace exactly the same rays.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RaySource {
    /// [`random_rays`] with this count and seed.
    Random {
        /// How many rays.
        count: usize,
        /// The generator's seed.
        seed: u64,
    },
    /// [`camera_rays`] at this resolution.
    Camera {
        /// Pixels across.
        width: usize,
        /// Pixels down.
        height: usize,
    },
    /// About this many rays of a kind ([`RayKind::rays`]: aimed rays, a random sample; shadow,
    /// ambient occlusion or bounce rays) from this seed.
    Kind {
        /// Which.
        kind: RayKind,
        /// How many rays.
        count: usize,
        /// The generator's seed.
        seed: u64,
    },
    /// Shadow, ambient occlusion or bounce rays from every pixel of the benchmark camera's
    /// image ([`rays_from_pixels`]), in tiles of pixels: coherent packets.
    FromPixels {
        /// Which.
        kind: RayKind,
        /// Pixels across.
        width: usize,
        /// Pixels down.
        height: usize,
    },
    /// A ray file.
    File(String),
}

impl RaySource {
    /// Chooses from command-line options without a ray kind: a file, else a camera
    /// (`WIDTHxHEIGHT`), else random rays.
    pub fn from_options(
        file: Option<&str>,
        camera: Option<&str>,
        count: usize,
        seed: u64,
    ) -> Result<Self, String> {
        let kind = if camera.is_some() {
            RayKind::Camera
        } else {
            RayKind::Random
        };
        Self::of_kind(file, camera, kind, count, seed)
    }

    /// The kind of rays it makes (`None` for a file).
    pub fn kind(&self) -> Option<RayKind> {
        match self {
            Self::Random { .. } => Some(RayKind::Random),
            Self::Camera { .. } => Some(RayKind::Camera),
            Self::Kind { kind, .. } | Self::FromPixels { kind, .. } => Some(*kind),
            Self::File(_) => None,
        }
    }

    /// Chooses from command-line options with a ray kind: a file, else `kind` (a camera's
    /// image `camera`, `WIDTHxHEIGHT`, or about `count` pixels; shadow, ambient occlusion and
    /// bounce rays from every pixel of the image `camera` if given, else about `count` from
    /// random pixels).
    pub fn of_kind(
        file: Option<&str>,
        camera: Option<&str>,
        kind: RayKind,
        count: usize,
        seed: u64,
    ) -> Result<Self, String> {
        if let Some(path) = file {
            return Ok(Self::File(path.to_owned()));
        }
        let image = camera
            .map(|camera| parse_resolution(camera).map_err(|error| format!("--camera: {error}")))
            .transpose()?;
        Ok(match (kind, image) {
            (RayKind::Random, _) => Self::Random { count, seed },
            (RayKind::Camera, image) => {
                let (width, height) = image.unwrap_or_else(|| square_image(count));
                Self::Camera { width, height }
            }
            (RayKind::Shadow | RayKind::Ao | RayKind::Bounce, Some((width, height))) => {
                Self::FromPixels {
                    kind,
                    width,
                    height,
                }
            }
            (RayKind::Aimed | RayKind::Shadow | RayKind::Ao | RayKind::Bounce, _) => {
                Self::Kind { kind, count, seed }
            }
        })
    }

    /// The rays, for `mesh`.
    pub fn rays(&self, mesh: &crate::Mesh) -> Result<Vec<RaySpec>, LoadError> {
        Ok(match self {
            Self::Kind { kind, count, seed } => kind
                .rays(mesh, *count, *seed, None)
                .map_err(|problem| LoadError::in_file(&mesh.name, problem))?,
            Self::Random { count, seed } => random_rays(&mesh.bounds(), *count, *seed),
            Self::Camera { width, height } => camera_rays(&mesh.bounds(), *width, *height),
            Self::FromPixels {
                kind,
                width,
                height,
            } => rays_from_pixels(*kind, mesh, *width, *height)
                .map_err(|problem| LoadError::in_file(&mesh.name, problem))?,
            Self::File(path) => load_rays(path)?,
        })
    }

    /// A short label for reports: `random:100000:seed1`, `camera:512x512`,
    /// `aimed:100000:seed1`, `shadow:100000:seed1`, or the file's path.
    pub fn label(&self) -> String {
        match self {
            Self::Random { count, seed } => format!("random:{count}:seed{seed}"),
            Self::Camera { width, height } => format!("camera:{width}x{height}"),
            Self::Kind { kind, count, seed } => format!("{}:{count}:seed{seed}", kind.name()),
            Self::FromPixels {
                kind,
                width,
                height,
            } => format!("{}:camera:{width}x{height}", kind.name()),
            Self::File(path) => path.clone(),
        }
    }
}

/// Parses a camera resolution `WIDTHxHEIGHT` (e.g. `512x512`) of at most [`MAX_PIXELS`].
pub fn parse_resolution(text: &str) -> Result<(usize, usize), String> {
    let parsed = text
        .split_once('x')
        .and_then(|(width, height)| Some((width.parse().ok()?, height.parse().ok()?)));
    match parsed {
        Some((width, height)) if width > 0 && height > 0 => {
            let pixels = (width as u64).saturating_mul(height as u64);
            if pixels > MAX_PIXELS {
                return Err(format!(
                    "{text} is {pixels} pixels; an image has at most {MAX_PIXELS} (4096x4096): its rays and counts are held in memory"
                ));
            }
            Ok((width, height))
        }
        _ => Err(format!("'{text}' is not WIDTHxHEIGHT, e.g. 512x512")),
    }
}

/// The most pixels an image of camera rays has (4096 × 4096): each pixel's ray and counts are
/// held in memory, a few tens of bytes each.
pub const MAX_PIXELS: u64 = 1 << 24;

/// Primary rays of the benchmark's camera ([`accelviz_core::camera::Camera::framing`]: a 45°
/// pinhole looking at the box's centre from the +z side, slightly raised, from far enough
/// that the box fills the frame), one through the centre of each of `width × height` pixels
/// (row by row from the top left): coherent rays, as a renderer traces them. The heat maps
/// trace the same rays.
pub fn camera_rays(bounds: &Aabb<DVec3>, width: usize, height: usize) -> Vec<RaySpec> {
    let camera = accelviz_core::camera::Camera::framing(bounds);
    let mut rays = Vec::with_capacity(width * height);
    for row in 0..height {
        for column in 0..width {
            let (origin, direction) =
                camera.ray_through(column as f64 + 0.5, row as f64 + 0.5, width, height);
            rays.push(RaySpec::generated(origin, direction));
        }
    }
    rays
}

/// The pixels of a `width × height` image (numbered row by row, as [`camera_rays`] makes
/// them) in tiles of `tile_width × tile_height`, tiles row by row: the groups a packet tracer
/// traces together (neighbouring pixels, so rays of nearly one direction). Edge tiles are
/// cut to the image.
pub fn pixel_tiles(
    width: usize,
    height: usize,
    tile_width: usize,
    tile_height: usize,
) -> Vec<Vec<u32>> {
    let (tile_width, tile_height) = (tile_width.max(1), tile_height.max(1));
    let mut tiles = Vec::with_capacity(width.div_ceil(tile_width) * height.div_ceil(tile_height));
    for top in (0..height).step_by(tile_height) {
        for left in (0..width).step_by(tile_width) {
            let rows = top..(top + tile_height).min(height);
            tiles.push(
                rows.flat_map(|row| {
                    (left..(left + tile_width).min(width))
                        .map(move |column| (row * width + column) as u32)
                })
                .collect(),
            );
        }
    }
    tiles
}

/// How many rays [`surface_aim_rays`] aims at each triangle: at each of its three corners, at
/// the midpoint of the edge from it and at a random point on that edge, an oblique ray and
/// one along an axis.
pub const AIMED_PER_TRIANGLE: usize = 18;

/// Rays from outside a mesh aimed exactly at each triangle corner, at the midpoint of each edge
/// and at a random point on each edge: where a ray test that is not watertight lets rays slip
/// between neighbours. [`AIMED_PER_TRIANGLE`] a triangle, in the order of [`SurfaceAim::ray`].
///
/// Meant for closed meshes that are star-shaped around their box's centre (spheres, cubes):
/// each ray comes from a distance `2r` off the surface, from a seeded random direction within
/// about 30° of the radial direction through its target, so that it crosses the surface there.
/// (A ray grazing a silhouette edge may truly miss: after rounding it passes a hair outside.)
/// The oblique rays' direction is `target − origin`, so the aim point is at `t = 1`; each
/// target also gets a ray along the coordinate axis nearest its radial direction.
pub fn surface_aim_rays(triangles: &[[[f64; 3]; 3]], seed: u64) -> Vec<RaySpec> {
    let aim = SurfaceAim::new(triangles, seed);
    (0..aim.len()).map(|index| aim.ray(index)).collect()
}

/// `count` of [`surface_aim_rays`]'s rays (all of them if there are no more), each as likely
/// as any other: a seeded uniform sample without replacement, in their order (Knuth's
/// selection sampling, TAOCP vol. 2, 3.4.2, Algorithm S). A share of them, taken every k-th,
/// would follow their pattern of 18 a triangle (an even step takes only the oblique rays),
/// and a leak rate would move with the count; a random sample's rate is the whole set's,
/// within its sampling error. Only the rays drawn are made.
pub fn surface_aim_sample(triangles: &[[[f64; 3]; 3]], count: usize, seed: u64) -> Vec<RaySpec> {
    let aim = SurfaceAim::new(triangles, seed);
    let total = aim.len();
    if count >= total {
        return (0..total).map(|index| aim.ray(index)).collect();
    }
    // Each ray in turn is taken with probability (still wanted) / (still left): exactly
    // `count` taken, every subset equally likely.
    let mut rng = SplitMix64::new(seed ^ 0x5a4d_706c_6520_6169);
    let mut rays = Vec::with_capacity(count);
    for index in 0..total {
        let (wanted, left) = (count - rays.len(), total - index);
        if wanted == 0 {
            break;
        }
        if (rng.next_f64() * left as f64) < wanted as f64 {
            rays.push(aim.ray(index));
        }
    }
    rays
}

/// Where [`surface_aim_rays`] aims, ray by ray: each made alone from its number.
pub struct SurfaceAim<'a> {
    triangles: &'a [[[f64; 3]; 3]],
    center: DVec3,
    /// How far off the surface the rays start.
    distance: f64,
    seed: u64,
}

impl<'a> SurfaceAim<'a> {
    /// The aims at `triangles`, from `seed`.
    pub fn new(triangles: &'a [[[f64; 3]; 3]], seed: u64) -> Self {
        let bounds = Aabb::from_points(triangles.iter().flatten().map(|&c| DVec3::from_array(c)));
        let (center, radius) = bounding_sphere_of_box(&bounds);
        Self {
            triangles,
            center,
            distance: 2.0 * radius,
            seed,
        }
    }

    /// How many rays: [`AIMED_PER_TRIANGLE`] a triangle.
    pub fn len(&self) -> usize {
        self.triangles.len() * AIMED_PER_TRIANGLE
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Ray `index`: triangle `index / 18`; then its corner, the target on the edge from
    /// that corner (the corner, the edge's midpoint, a random point on it), and the ray
    /// (oblique, along an axis). A corner's random draws are its own, from the seed.
    pub fn ray(&self, index: usize) -> RaySpec {
        let (triangle, within) = (index / AIMED_PER_TRIANGLE, index % AIMED_PER_TRIANGLE);
        let (corner, target_kind, along_an_axis) = (within / 6, (within / 2) % 3, within % 2 == 1);
        let triangle_corners = &self.triangles[triangle];
        let a = DVec3::from_array(triangle_corners[corner]);
        let b = DVec3::from_array(triangle_corners[(corner + 1) % 3]);
        // The corner's draws, in a fixed order: where the random target lies along the edge,
        // then each target's approach.
        let mut rng = SplitMix64::for_item(self.seed, (triangle * 3 + corner) as u64);
        let along = rng.next_f64();
        let mut approach_noise = [[0.0; 3]; 3];
        for noise in &mut approach_noise {
            *noise = rng.unit_vector();
        }
        let target = [a, (a + b) * 0.5, a + (b - a) * along][target_kind];
        let radial = (target - self.center).normalize_or(DVec3::Z);
        if along_an_axis {
            // Along the axis nearest the radial direction: it keeps the target's other two
            // coordinates exactly, so at a corner the edge functions are exactly zero, the
            // case a watertight test must get right.
            let axis = radial.abs().max_position();
            let mut along_axis = DVec3::ZERO;
            along_axis[axis] = radial[axis].signum();
            RaySpec::generated(target + along_axis * self.distance, -along_axis)
        } else {
            let noise = DVec3::from_array(approach_noise[target_kind]);
            let approach = (radial + noise * 0.5).normalize();
            let origin = target + approach * self.distance;
            RaySpec::generated(origin, target - origin)
        }
    }
}

/// A name that is not a [`RayKind`]'s; the message lists theirs.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("'{0}' is not a ray kind; ray kinds are {names}", names = RayKind::ALL.map(RayKind::name).join(", "))]
pub struct RayKindError(pub String);

/// The kinds of rays accelviz makes, from a seed, the same on every machine: what a renderer
/// traces, from the coherent to the incoherent (`--ray-kind` wherever rays are made).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RayKind {
    /// From a sphere around the scene towards random points in its box ([`random_rays`]).
    #[default]
    Random,
    /// The benchmark camera's primary rays ([`camera_rays`]): coherent.
    Camera,
    /// Aimed exactly at triangle corners and edge points ([`surface_aim_rays`]): where
    /// rounding decides.
    Aimed,
    /// From camera rays' hits, just off the surface, to a point light; `t_max` at the light.
    Shadow,
    /// A few short cosine-distributed rays from each camera ray's hit (ambient occlusion);
    /// `t_max` a small share of the scene's size.
    Ao,
    /// One diffuse bounce from each camera ray's hit: incoherent secondary rays.
    Bounce,
}

/// Ambient occlusion rays made at each hit.
pub const AO_RAYS_PER_HIT: usize = 4;

/// The reach of an ambient occlusion ray, as a share of the scene's bounding radius.
pub const AO_REACH: f64 = 0.1;

impl RayKind {
    /// Every kind.
    pub const ALL: [RayKind; 6] = [
        RayKind::Random,
        RayKind::Camera,
        RayKind::Aimed,
        RayKind::Shadow,
        RayKind::Ao,
        RayKind::Bounce,
    ];

    /// Its name on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Random => "random",
            RayKind::Camera => "camera",
            RayKind::Aimed => "aimed",
            RayKind::Shadow => "shadow",
            RayKind::Ao => "ao",
            RayKind::Bounce => "bounce",
        }
    }

    /// The kind of that [`RayKind::name`].
    pub fn from_name(name: &str) -> Option<RayKind> {
        RayKind::ALL.into_iter().find(|kind| kind.name() == name)
    }

    /// The kind `name` names, or an error that lists them (`--ray-kind`).
    pub fn parse(name: &str) -> Result<RayKind, RayKindError> {
        RayKind::from_name(name).ok_or_else(|| RayKindError(name.to_owned()))
    }

    /// One line on what the rays are.
    pub fn about(self) -> &'static str {
        match self {
            RayKind::Random => "from around the scene to random points in its box",
            RayKind::Camera => "the benchmark camera's primary rays (coherent)",
            RayKind::Aimed => "aimed exactly at triangle corners and edge points",
            RayKind::Shadow => "from camera hits to a point light, any hit",
            RayKind::Ao => "short cosine-distributed rays from camera hits, any hit",
            RayKind::Bounce => "one diffuse bounce from each camera hit (incoherent)",
        }
    }

    /// The query a renderer asks of these rays: any hit for shadow and occlusion rays (is
    /// anything in the way?), the closest hit otherwise.
    pub fn default_query(self) -> accelviz_core::Query {
        match self {
            RayKind::Shadow | RayKind::Ao => accelviz_core::Query::Any,
            _ => accelviz_core::Query::Closest,
        }
    }

    /// `count` rays of this kind for `mesh` from `seed` (a camera's are its `camera` image
    /// if given, else about `count` pixels; aimed rays are a random sample of `count` of the
    /// mesh's [`AIMED_PER_TRIANGLE`] a triangle, or all of them if there are fewer). Fails
    /// only when the camera sees too little of the mesh to start secondary rays from.
    pub fn rays(
        self,
        mesh: &crate::Mesh,
        count: usize,
        seed: u64,
        camera: Option<(usize, usize)>,
    ) -> Result<Vec<RaySpec>, String> {
        Ok(match self {
            RayKind::Random => random_rays(&mesh.bounds(), count, seed),
            RayKind::Camera => {
                let (width, height) = camera.unwrap_or_else(|| square_image(count));
                camera_rays(&mesh.bounds(), width, height)
            }
            RayKind::Aimed => surface_aim_sample(&mesh.triangles, count, seed),
            RayKind::Shadow | RayKind::Ao | RayKind::Bounce => {
                secondary_rays(self, mesh, count, seed)?
            }
        })
    }
}

/// An image of about `pixels` pixels, as square as can be.
pub fn square_image(pixels: usize) -> (usize, usize) {
    let width = (pixels.max(1) as f64).sqrt().ceil() as usize;
    (width, pixels.max(1).div_ceil(width))
}

/// Where the shadow rays' point light is: above, right of and in front of the scene, as the
/// benchmark camera sees it, three bounding radii from its centre.
pub fn light_position(bounds: &Aabb<DVec3>) -> DVec3 {
    let (center, radius) = bounding_sphere_of_box(bounds);
    center + DVec3::new(0.6, 1.2, 0.9).normalize() * (3.0 * radius)
}

/// How far secondary rays start off the surface, along its normal, towards the side the
/// camera ray came from: a share of the scene's size, and never less than a few units in the
/// last place of the hit point (so that rounding cannot put the origin back on the surface).
pub fn surface_offset(bounds: &Aabb<DVec3>, point: DVec3) -> f64 {
    let (_, radius) = bounding_sphere_of_box(bounds);
    (1e-5 * radius).max(point.abs().max_element() * 64.0 * f32::EPSILON as f64)
}

/// A mesh's closest hits in f64 with the watertight test: where secondary rays start from.
struct ReferenceHits {
    triangles: accelviz_core::TriangleSet<DVec3>,
    bvh: accelviz_core::bvh::Bvh<DVec3>,
    stack: accelviz_core::bvh::TraversalStack<f64>,
}

impl ReferenceHits {
    fn new(mesh: &crate::Mesh) -> Self {
        use accelviz_core::PrimitiveSet;
        use accelviz_core::bvh::{BinnedSah, Builder};
        let triangles = accelviz_core::TriangleSet::<DVec3>::from_f64(&mesh.triangles);
        let bvh = BinnedSah::default().build(
            &triangles.all_bounds(),
            &accelviz_core::params::BuildParams::default(),
        );
        Self {
            triangles,
            bvh,
            stack: accelviz_core::bvh::TraversalStack::new(),
        }
    }

    fn closest(&mut self, ray: &Ray<DVec3>) -> Option<accelviz_core::Hit<f64>> {
        accelviz_core::bvh::traverse(
            &self.bvh,
            &self.triangles,
            ray,
            &accelviz_core::TraceOptions::default().with_robust(true),
            &mut self.stack,
            &mut accelviz_core::NoObserver,
        )
    }
}

/// Shadow, ambient occlusion or bounce rays: camera rays through seeded random points of
/// the benchmark camera's image are traced (in f64, watertight) until `count` rays are made
/// from their hits.
fn secondary_rays(
    kind: RayKind,
    mesh: &crate::Mesh,
    count: usize,
    seed: u64,
) -> Result<Vec<RaySpec>, String> {
    let bounds = mesh.bounds();
    let mut hits = ReferenceHits::new(mesh);
    let camera = accelviz_core::camera::Camera::framing(&bounds);
    let mut rng = SplitMix64::new(seed);
    let mut rays = Vec::with_capacity(count);
    // A camera that sees the mesh hits it often; one that sees a sliver may never make
    // `count` rays: give up after many tries.
    let attempts = 64 * count.max(16);
    const IMAGE: usize = 1 << 16;
    for _ in 0..attempts {
        if rays.len() >= count {
            break;
        }
        let (x, y) = (rng.next_f64() * IMAGE as f64, rng.next_f64() * IMAGE as f64);
        let (origin, direction) = camera.ray_through(x, y, IMAGE, IMAGE);
        let Ok(primary) = Ray::try_new(origin, direction) else {
            continue;
        };
        let Some(hit) = hits.closest(&primary) else {
            continue;
        };
        let from_hit = rays_from_hit(
            kind,
            &bounds,
            hits.triangles.triangles()[hit.primitive as usize],
            primary.at(hit.t),
            direction,
            &mut rng,
        );
        rays.extend(from_hit.into_iter().take(count - rays.len()));
    }
    if rays.len() < count {
        return Err(format!(
            "the benchmark camera sees too little of the mesh to start {count} {} rays from its hits",
            kind.name()
        ));
    }
    Ok(rays)
}

/// The secondary rays of `kind` (shadow, ambient occlusion or bounce; none for the other
/// kinds) from a camera ray's hit at `point` on `triangle`, the camera ray going `incoming`:
/// from just off the surface on the side it came from ([`surface_offset`]); a shadow ray to
/// the [`light_position`] with `t_max` there (none when the light is behind the surface),
/// [`AO_RAYS_PER_HIT`] cosine-distributed rays reaching [`AO_REACH`] of the scene's radius,
/// or one cosine-distributed bounce. `rng` draws the directions.
pub fn rays_from_hit(
    kind: RayKind,
    bounds: &Aabb<DVec3>,
    triangle: [DVec3; 3],
    point: DVec3,
    incoming: DVec3,
    rng: &mut SplitMix64,
) -> Vec<RaySpec> {
    let [a, b, c] = triangle;
    let mut normal = (b - a).cross(c - a).normalize_or_zero();
    if normal == DVec3::ZERO {
        return Vec::new();
    }
    // The side the camera sees.
    if normal.dot(incoming) > 0.0 {
        normal = -normal;
    }
    let start = point + normal * surface_offset(bounds, point);
    match kind {
        RayKind::Shadow => {
            let to_light = light_position(bounds) - start;
            // A light behind the surface casts no shadow ray (a renderer would not trace one).
            if to_light.dot(normal) <= 0.0 {
                return Vec::new();
            }
            vec![RaySpec {
                t_max: 1.0,
                ..RaySpec::generated(start, to_light)
            }]
        }
        RayKind::Ao => {
            let (_, radius) = bounding_sphere_of_box(bounds);
            (0..AO_RAYS_PER_HIT)
                .map(|_| RaySpec {
                    t_max: AO_REACH * radius,
                    ..RaySpec::generated(start, cosine_direction(rng, normal))
                })
                .collect()
        }
        RayKind::Bounce => vec![RaySpec::generated(start, cosine_direction(rng, normal))],
        RayKind::Random | RayKind::Camera | RayKind::Aimed => Vec::new(),
    }
}

/// The secondary rays of `kind` that a heat map's pixel traces, the same in the CLI's
/// `heatmap` and in lesson 14: the pixel's camera ray `ray` found `hit` on `mesh`, and
/// [`rays_from_hit`] makes the rays from there, in `V`'s precision (a ray that precision
/// cannot hold is left out). Their directions are drawn from a generator seeded by the camera
/// ray's numbers, so a map is the same every time and on every machine.
pub fn pixel_secondary_rays<V: accelviz_core::Vector3>(
    kind: RayKind,
    mesh: &crate::Mesh,
    bounds: &Aabb<DVec3>,
    ray: &Ray<V>,
    hit: accelviz_core::Hit<V::Scalar>,
) -> Vec<Ray<V>> {
    pixel_secondary_specs(
        kind,
        mesh,
        bounds,
        &ray.cast::<DVec3>(),
        accelviz_core::Real::to_f64(hit.t),
        hit.primitive,
    )
    .iter()
    .filter_map(|spec| spec.to_ray::<V>().ok())
    .collect()
}

/// [`pixel_secondary_rays`] in f64, as specifications: from the camera ray `ray`'s hit at
/// `t` on triangle `primitive`.
fn pixel_secondary_specs(
    kind: RayKind,
    mesh: &crate::Mesh,
    bounds: &Aabb<DVec3>,
    ray: &Ray<DVec3>,
    t: f64,
    primitive: u32,
) -> Vec<RaySpec> {
    let Some(triangle) = mesh.triangles.get(primitive as usize) else {
        return Vec::new();
    };
    let seed = ray
        .origin
        .to_array()
        .iter()
        .chain(&ray.direction.to_array())
        .fold(0u64, |seed, value| seed.rotate_left(13) ^ value.to_bits());
    rays_from_hit(
        kind,
        bounds,
        triangle.map(DVec3::from_array),
        ray.at(t),
        ray.direction,
        &mut SplitMix64::new(seed),
    )
}

/// The side of the square tiles [`rays_from_pixels`] takes pixels in: 64 pixels, a packet's
/// worth of camera rays.
pub const PIXEL_TILE: usize = 8;

/// Shadow, ambient occlusion or bounce rays from every pixel of the benchmark camera's
/// `width × height` image whose ray hits `mesh` (traced in f64, watertight), the rays each
/// pixel's heat map counts ([`pixel_secondary_rays`]); the pixels in tiles of
/// [`PIXEL_TILE`]² ([`pixel_tiles`]), so neighbouring pixels' rays are neighbours and a
/// packet of them is coherent, as a renderer's that traces a tile's shadow rays together.
/// Fails when the camera sees none of the mesh.
pub fn rays_from_pixels(
    kind: RayKind,
    mesh: &crate::Mesh,
    width: usize,
    height: usize,
) -> Result<Vec<RaySpec>, String> {
    let bounds = mesh.bounds();
    let mut hits = ReferenceHits::new(mesh);
    let primaries = camera_rays(&bounds, width, height);
    let mut rays = Vec::new();
    for pixel in pixel_tiles(width, height, PIXEL_TILE, PIXEL_TILE)
        .into_iter()
        .flatten()
    {
        let Ok(primary) = primaries[pixel as usize].to_ray::<DVec3>() else {
            continue;
        };
        if let Some(hit) = hits.closest(&primary) {
            rays.extend(pixel_secondary_specs(
                kind,
                mesh,
                &bounds,
                &primary,
                hit.t,
                hit.primitive,
            ));
        }
    }
    if rays.is_empty() {
        return Err(format!(
            "the benchmark camera's {width}x{height} pixels start no {} rays on the mesh",
            kind.name()
        ));
    }
    Ok(rays)
}

/// A unit direction about `normal`, with density proportional to the cosine of its angle
/// to it (Malley's method: a uniform point of the unit disc lifted onto the hemisphere).
fn cosine_direction(rng: &mut SplitMix64, normal: DVec3) -> DVec3 {
    let radius = rng.next_f64().sqrt();
    let angle = rng.next_f64() * std::f64::consts::TAU;
    let (x, y) = (radius * angle.cos(), radius * angle.sin());
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    let (tangent, bitangent) = normal.any_orthonormal_pair();
    (tangent * x + bitangent * y + normal * z).normalize()
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_ray_line_reads_back_as_the_same_ray_bit_for_bit() {
        let mut rng = crate::rng::SplitMix64::new(7);
        let value = |rng: &mut crate::rng::SplitMix64| {
            // Scales f32 holds too (the line is checked in both precisions), both signs,
            // values that print oddly (-0, 0.1).
            let scale = 10f64.powi((rng.next_f64() * 60.0 - 30.0) as i32);
            match rng.next_u64() % 8 {
                0 => -0.0,
                1 => 0.1,
                _ => (rng.next_f64() - 0.5) * scale,
            }
        };
        for case in 0..2000 {
            let mut ray = super::RaySpec::generated(
                glam::DVec3::new(value(&mut rng), value(&mut rng), value(&mut rng)),
                glam::DVec3::new(
                    value(&mut rng),
                    value(&mut rng),
                    1.0 + value(&mut rng).abs(),
                ),
            );
            if case % 3 == 0 {
                ray.t_min = 0.25;
                ray.t_max = 1e9;
            }
            let line = super::ray_line(&ray);
            let read = super::parse_ray_line(&line, 5, "clicked.rays")
                .expect("reads")
                .expect("a ray");
            let bits = |ray: &super::RaySpec| {
                (ray.origin.iter().chain(&ray.direction))
                    .chain([&ray.t_min, &ray.t_max])
                    .map(|v| v.to_bits())
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&read), bits(&ray), "{line}");
        }
    }

    use super::*;

    #[test]
    fn a_ray_kind_is_parsed_by_name_and_an_unknown_one_lists_them() {
        for kind in RayKind::ALL {
            assert_eq!(RayKind::parse(kind.name()), Ok(kind));
        }
        let error = RayKind::parse("sideways").unwrap_err().to_string();
        assert!(
            error.starts_with("'sideways' is not a ray kind; ray kinds are random, ")
                && error.contains("camera"),
            "{error}"
        );
    }

    #[test]
    fn parses_rays_and_names_bad_lines() {
        let rays = parse_rays(
            "# a comment\n0 0 0 1 0 0\n\n1 2 3 0 0 -1 0.5 inf\n",
            "r.txt",
        )
        .unwrap();
        assert_eq!(rays.len(), 2);
        assert_eq!(rays[1].line, 4);
        assert_eq!((rays[1].t_min, rays[1].t_max), (0.5, f64::INFINITY));
        let cases = [
            ("0 0 0 0 0 0\n", "r.txt:1: bad ray: the direction is zero"),
            ("0 0 0 -0 0 0\n", "r.txt:1: bad ray: the direction is zero"),
            (
                "0 0 0 1e-50 0 0\n",
                "r.txt:1: bad ray in f32 precision: the direction is zero",
            ),
            (
                "\n0 nan 0 1 0 0\n",
                "r.txt:2: bad ray: the origin is not finite",
            ),
            (
                "0 0 0 inf 0 0\n",
                "r.txt:1: bad ray: the direction is not finite",
            ),
            (
                "0 0 0 1 0\n",
                "r.txt:1: a ray is 'ox oy oz dx dy dz [tmin tmax]', found 5 values",
            ),
            ("0 0 0 1 0 x\n", "r.txt:1: 'x' is not a number"),
            ("0 0 0 1 0 0 2 1\n", "r.txt:1: bad ray: the interval"),
            ("0 0 0 1 0 0 nan 1\n", "r.txt:1: the interval"),
        ];
        for (text, expected) in cases {
            let message = parse_rays(text, "r.txt").unwrap_err().to_string();
            assert!(
                message.starts_with(expected),
                "{message:?} should start with {expected:?}"
            );
        }
    }

    #[test]
    fn random_rays_start_outside_and_aim_inside() {
        let bounds = Aabb::new(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0));
        let rays = random_rays(&bounds, 100, 7);
        assert_eq!(rays, random_rays(&bounds, 100, 7));
        for ray in &rays {
            let origin = DVec3::from_array(ray.origin);
            let aim = origin + DVec3::from_array(ray.direction);
            assert!(!bounds.contains_point(origin));
            assert!(bounds.contains_point(aim));
        }
    }

    /// Rays from pixels are each hit pixel's heat-map rays, the pixels in tiles: the first
    /// rays come from the first tile's pixels; a camera with a ray kind asks for them.
    #[test]
    fn rays_from_pixels_are_the_pixels_rays_tile_by_tile() {
        let mesh = crate::builtin::teapot();
        let (width, height) = (21, 13);
        let source =
            RaySource::of_kind(None, Some("21x13"), RayKind::Shadow, 5, 1).expect("a source");
        assert_eq!(source.label(), "shadow:camera:21x13");
        assert_eq!(source.kind(), Some(RayKind::Shadow));
        assert!(matches!(
            RaySource::of_kind(None, None, RayKind::Shadow, 5, 1),
            Ok(RaySource::Kind { .. })
        ));

        let bounds = mesh.bounds();
        let mut hits = ReferenceHits::new(&mesh);
        let primaries = camera_rays(&bounds, width, height);
        for kind in [RayKind::Shadow, RayKind::Ao, RayKind::Bounce] {
            let made = rays_from_pixels(kind, &mesh, width, height).expect("rays");
            let mut expected = Vec::new();
            for tile in pixel_tiles(width, height, PIXEL_TILE, PIXEL_TILE) {
                for pixel in tile {
                    let ray = primaries[pixel as usize].to_ray::<DVec3>().expect("a ray");
                    if let Some(hit) = hits.closest(&ray) {
                        expected.extend(pixel_secondary_rays::<DVec3>(
                            kind, &mesh, &bounds, &ray, hit,
                        ));
                    }
                }
            }
            let made: Vec<_> = made
                .iter()
                .map(|spec| spec.to_ray::<DVec3>().expect("a ray"))
                .collect();
            assert!(made.len() > 10, "{}: {}", kind.name(), made.len());
            assert_eq!(made, expected, "{}", kind.name());
            let via_source = RaySource::of_kind(None, Some("21x13"), kind, 5, 1)
                .expect("a source")
                .rays(&mesh)
                .expect("rays");
            assert_eq!(via_source.len(), made.len());
        }
        // Pixels that start nothing (a triangle flat as a line) say so.
        let line = crate::Mesh {
            name: "line.obj".into(),
            triangles: vec![[[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 2.0, 0.0]]],
        };
        let problem = rays_from_pixels(RayKind::Shadow, &line, 4, 4).unwrap_err();
        assert!(problem.contains("start no shadow rays"), "{problem}");
    }
}
