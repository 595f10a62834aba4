//! Intel's Embree, the reference tracer accelviz measures itself against: Embree 3 (Debian's
//! `libembree3`, 3.13) and Embree 4 (4.4, the shared library inside the PyPI wheel `embreex`),
//! loaded at run time so that the workspace builds, and CI compiles this crate, on machines
//! without either. Benchmark only: nothing of accelviz depends on it but `accelviz-peers`.
//!
//! The few entry points used are declared here by hand after the libraries' headers
//! (`embree3/rtcore*.h` 3.13.5, `embree4/rtcore*.h` 4.4.0): one instance level; Embree 4's
//! hit carries an instance primitive number too (`RTC_GEOMETRY_INSTANCE_ARRAY`), and its
//! calls take an arguments record after the ray where Embree 3's took a context before it.
//! Records are given spare room at their ends, so that a library built with more instance
//! levels writes into padding rather than past them.
//!
//! A scene is built as an application builds it by default (`rtcCommitScene`, medium
//! quality) on the threads asked for (one, as accelviz's benchmark builds), optionally
//! limited to one instruction set (`isa=avx2` in the device's configuration). Rays are traced
//! one at a time (`rtcIntersect1`, `rtcOccluded1`, the incoherent flag) or 16 at a time as
//! coherent packets (`rtcIntersect16`, `rtcOccluded16`, the coherent flag), as Embree's
//! documentation advises for primary and shadow rays of neighbouring pixels.

// A foreign library is reached only through raw pointers; every call below is to a function
// looked up by its documented name and signature, with arguments laid out as its headers say.
#![allow(unsafe_code)]

use std::ffi::{CString, c_char, c_int, c_uint, c_void};
use std::sync::OnceLock;

use anyhow::{Context as _, Result, bail};

/// Which Embree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    /// Embree 3 (3.13): Debian's `libembree3.so.3`.
    Three,
    /// Embree 4 (4.4): the library named by the environment variable
    /// [`EMBREE4_LIBRARY_VARIABLE`], else `libembree4.so.4` on the library path.
    Four,
}

/// The environment variable naming Embree 4's shared library (`scripts/bench` sets it to the
/// `embreex` wheel's `libembree4-*.so.4`).
pub const EMBREE4_LIBRARY_VARIABLE: &str = "ACCELVIZ_EMBREE4";

impl Version {
    /// `embree3` or `embree4`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Three => "embree3",
            Self::Four => "embree4",
        }
    }

    fn library(self) -> String {
        match self {
            Self::Three => "libembree3.so.3".to_owned(),
            Self::Four => std::env::var(EMBREE4_LIBRARY_VARIABLE)
                .unwrap_or_else(|_| "libembree4.so.4".to_owned()),
        }
    }

    fn how_to_install(self) -> &'static str {
        match self {
            Self::Three => "Debian: apt-get install libembree-dev (scripts/bench does)",
            Self::Four => {
                "pip install embreex==4.4.0.post1 and set ACCELVIZ_EMBREE4 to its \
                 embreex.libs/libembree4-*.so.4 (scripts/bench does)"
            }
        }
    }
}

/// A ray: origin, direction (not necessarily of unit length) and where it ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where it starts.
    pub origin: [f32; 3],
    /// Where it goes; `t` counts lengths of this vector.
    pub direction: [f32; 3],
    /// Hits beyond this `t` are not reported.
    pub t_max: f32,
}

/// A closest hit: the triangle's number in the order given to [`Embree::build`], and `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The triangle.
    pub primitive: u32,
    /// Its distance along the ray, in lengths of the ray's direction.
    pub t: f32,
}

/// Rays in a packet.
pub const PACKET: usize = 16;

type Device = *mut c_void;
type Scene = *mut c_void;
type Geometry = *mut c_void;

const GEOMETRY_TYPE_TRIANGLE: c_uint = 0;
const BUFFER_TYPE_INDEX: c_uint = 0;
const BUFFER_TYPE_VERTEX: c_uint = 1;
const FORMAT_UINT3: c_uint = 0x5003;
const FORMAT_FLOAT3: c_uint = 0x9003;
const INVALID_ID: c_uint = u32::MAX;

/// Embree 3's `RTCIntersectContext` (one instance level): before the ray in every call.
#[repr(C)]
struct Context3 {
    flags: c_uint,
    filter: *const c_void,
    instance_id: [c_uint; 1],
}

/// Embree 4's `RTCIntersectArguments` and `RTCOccludedArguments` (the same layout), after the
/// ray in every call; the last field is there only in builds with `RTC_MIN_WIDTH`.
#[repr(C)]
struct Arguments4 {
    flags: c_uint,
    feature_mask: c_uint,
    context: *mut c_void,
    filter: *const c_void,
    callback: *const c_void,
    min_width_distance_factor: f32,
}

/// `struct RTCRayHit`: `RTCRay` (all `rtcOccluded1` reads and writes) then `RTCHit`.
#[repr(C, align(16))]
struct RayHit {
    origin: [f32; 3],
    t_near: f32,
    direction: [f32; 3],
    time: f32,
    t_far: f32,
    mask: c_uint,
    id: c_uint,
    flags: c_uint,
    normal: [f32; 3],
    u: f32,
    v: f32,
    primitive: c_uint,
    geometry: c_uint,
    instance: [c_uint; 1],
    /// Embree 4's `instPrimID`, and room.
    _spare: [c_uint; 4],
}

impl RayHit {
    fn new(ray: &Ray) -> Self {
        Self {
            origin: ray.origin,
            t_near: 0.0,
            direction: ray.direction,
            time: 0.0,
            t_far: ray.t_max,
            mask: u32::MAX,
            id: 0,
            flags: 0,
            normal: [0.0; 3],
            u: 0.0,
            v: 0.0,
            primitive: INVALID_ID,
            geometry: INVALID_ID,
            instance: [INVALID_ID],
            _spare: [INVALID_ID; 4],
        }
    }
}

/// `struct RTCRayHit16`: each field of [`RayHit`] as 16 lanes.
#[repr(C, align(64))]
struct RayHitPacket {
    origin: [[f32; PACKET]; 3],
    t_near: [f32; PACKET],
    direction: [[f32; PACKET]; 3],
    time: [f32; PACKET],
    t_far: [f32; PACKET],
    mask: [c_uint; PACKET],
    id: [c_uint; PACKET],
    flags: [c_uint; PACKET],
    normal: [[f32; PACKET]; 3],
    u: [f32; PACKET],
    v: [f32; PACKET],
    primitive: [c_uint; PACKET],
    geometry: [c_uint; PACKET],
    instance: [[c_uint; PACKET]; 1],
    /// Embree 4's `instPrimID`, and room.
    _spare: [[c_uint; PACKET]; 4],
}

impl RayHitPacket {
    /// The packet of `rays` (at most 16) and the valid mask of its lanes.
    fn new(rays: &[Ray]) -> (Box<Self>, ValidMask) {
        let mut packet = Box::new(Self {
            origin: [[0.0; PACKET]; 3],
            t_near: [0.0; PACKET],
            direction: [[0.0; PACKET]; 3],
            time: [0.0; PACKET],
            t_far: [0.0; PACKET],
            mask: [u32::MAX; PACKET],
            id: [0; PACKET],
            flags: [0; PACKET],
            normal: [[0.0; PACKET]; 3],
            u: [0.0; PACKET],
            v: [0.0; PACKET],
            primitive: [INVALID_ID; PACKET],
            geometry: [INVALID_ID; PACKET],
            instance: [[INVALID_ID; PACKET]; 1],
            _spare: [[INVALID_ID; PACKET]; 4],
        });
        let mut valid = ValidMask([0; PACKET]);
        packet.refill(rays, &mut valid);
        (packet, valid)
    }

    /// Writes the new rays into the packet's lanes and clears their hits.
    fn refill(&mut self, rays: &[Ray], valid: &mut ValidMask) {
        let valid = &mut valid.0;
        *valid = [0; PACKET];
        for (lane, ray) in rays.iter().enumerate().take(PACKET) {
            for axis in 0..3 {
                self.origin[axis][lane] = ray.origin[axis];
                self.direction[axis][lane] = ray.direction[axis];
            }
            self.t_far[lane] = ray.t_max;
            self.geometry[lane] = INVALID_ID;
            valid[lane] = -1;
        }
    }
}

/// A packet's valid mask (-1 for a ray, 0 for an empty lane), 64-byte aligned as Embree
/// requires: its release builds load it with an aligned vector load and crash otherwise.
#[repr(C, align(64))]
#[derive(Clone, Copy)]
struct ValidMask([c_int; PACKET]);

/// One ray's call: Embree 3's `(scene, context, ray)`, Embree 4's `(scene, ray, arguments)`.
type Call1 = unsafe extern "C" fn(Scene, *mut c_void, *mut c_void);
/// A packet's call: Embree 3's `(valid, scene, context, rays)`, Embree 4's
/// `(valid, scene, rays, arguments)`.
type Call16 = unsafe extern "C" fn(*const c_int, Scene, *mut c_void, *mut c_void);

/// The entry points used, looked up once.
struct Api {
    version: Version,
    _library: libloading::Library,
    new_device: unsafe extern "C" fn(*const c_char) -> Device,
    release_device: unsafe extern "C" fn(Device),
    new_scene: unsafe extern "C" fn(Device) -> Scene,
    release_scene: unsafe extern "C" fn(Scene),
    new_geometry: unsafe extern "C" fn(Device, c_uint) -> Geometry,
    set_new_buffer:
        unsafe extern "C" fn(Geometry, c_uint, c_uint, c_uint, usize, usize) -> *mut c_void,
    commit_geometry: unsafe extern "C" fn(Geometry),
    attach_geometry: unsafe extern "C" fn(Scene, Geometry) -> c_uint,
    release_geometry: unsafe extern "C" fn(Geometry),
    commit_scene: unsafe extern "C" fn(Scene),
    device_error: unsafe extern "C" fn(Device) -> c_uint,
    intersect1: Call1,
    occluded1: Call1,
    intersect16: Call16,
    occluded16: Call16,
}

/// Each version loaded once and never unloaded: Embree's worker threads outlive any one
/// scene, and unloading the library under them crashes the process.
static EMBREE3: OnceLock<Result<Api, String>> = OnceLock::new();
static EMBREE4: OnceLock<Result<Api, String>> = OnceLock::new();

impl Api {
    fn get(version: Version) -> Result<&'static Api> {
        let cell = match version {
            Version::Three => &EMBREE3,
            Version::Four => &EMBREE4,
        };
        cell.get_or_init(|| Api::load(version).map_err(|error| format!("{error:#}")))
            .as_ref()
            .map_err(|error| anyhow::anyhow!("{error}"))
    }

    fn load(version: Version) -> Result<Self> {
        let path = version.library();
        // SAFETY: loading Embree runs its initialisers, which have no preconditions.
        let library = unsafe { libloading::Library::new(&path) }.with_context(|| {
            format!(
                "{} is not installed, or not at {path} ({})",
                version.name(),
                version.how_to_install()
            )
        })?;
        macro_rules! symbol {
            ($name:literal) => {
                // SAFETY: the symbol is Embree's function of that name, whose C signature is
                // the field's type (for the calls, as `Call1` and `Call16` say per version).
                *unsafe { library.get(concat!($name, "\0").as_bytes()) }
                    .with_context(|| format!("{path} lacks {}", $name))?
            };
        }
        Ok(Self {
            version,
            new_device: symbol!("rtcNewDevice"),
            release_device: symbol!("rtcReleaseDevice"),
            new_scene: symbol!("rtcNewScene"),
            release_scene: symbol!("rtcReleaseScene"),
            new_geometry: symbol!("rtcNewGeometry"),
            set_new_buffer: symbol!("rtcSetNewGeometryBuffer"),
            commit_geometry: symbol!("rtcCommitGeometry"),
            attach_geometry: symbol!("rtcAttachGeometry"),
            release_geometry: symbol!("rtcReleaseGeometry"),
            commit_scene: symbol!("rtcCommitScene"),
            device_error: symbol!("rtcGetDeviceError"),
            intersect1: symbol!("rtcIntersect1"),
            occluded1: symbol!("rtcOccluded1"),
            intersect16: symbol!("rtcIntersect16"),
            occluded16: symbol!("rtcOccluded16"),
            _library: library,
        })
    }
}

/// How rays are traced: one at a time from anywhere, or packets of neighbouring rays.
#[derive(Clone, Copy)]
enum Coherence {
    Incoherent,
    Coherent,
}

/// The query's context (Embree 3) or arguments (Embree 4), and where each goes in a call.
enum QueryRecord {
    Three(Context3),
    Four(Arguments4),
}

impl QueryRecord {
    fn new(version: Version, coherence: Coherence) -> Self {
        match version {
            Version::Three => Self::Three(Context3 {
                // RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT = 0, _COHERENT = 1.
                flags: matches!(coherence, Coherence::Coherent) as c_uint,
                filter: std::ptr::null(),
                instance_id: [INVALID_ID],
            }),
            Version::Four => Self::Four(Arguments4 {
                // RTC_RAY_QUERY_FLAG_INCOHERENT = 0 << 16, _COHERENT = 1 << 16.
                flags: (matches!(coherence, Coherence::Coherent) as c_uint) << 16,
                // RTC_FEATURE_FLAG_ALL, as `rtcInitIntersectArguments` sets it.
                feature_mask: u32::MAX,
                context: std::ptr::null_mut(),
                filter: std::ptr::null(),
                callback: std::ptr::null(),
                min_width_distance_factor: 0.0,
            }),
        }
    }

    /// The two pointer arguments after the scene, in the version's order, around `rays`.
    fn around(&mut self, rays: *mut c_void) -> (*mut c_void, *mut c_void) {
        match self {
            Self::Three(context) => ((context as *mut Context3).cast(), rays),
            Self::Four(arguments) => (rays, (arguments as *mut Arguments4).cast()),
        }
    }
}

/// An Embree device with one committed triangle scene.
pub struct Embree {
    api: &'static Api,
    device: Device,
    scene: Scene,
}

impl Drop for Embree {
    fn drop(&mut self) {
        // SAFETY: both handles came from this API and are released once.
        unsafe {
            (self.api.release_scene)(self.scene);
            (self.api.release_device)(self.device);
        }
    }
}

// SAFETY: a committed Embree scene may be traced from any thread (Embree's documentation:
// the query functions are thread-safe); the handles are only released on drop.
unsafe impl Sync for Embree {}
// SAFETY: as above; no thread-local state is tied to the handles.
unsafe impl Send for Embree {}

impl Embree {
    /// Builds a scene of `triangles` (each its three corners) with Embree `version` on
    /// `threads` threads, limited to the instruction set `isa` if given (Embree's names:
    /// `sse2`, `sse4.2`, `avx`, `avx2`, `avx512`).
    pub fn build(
        version: Version,
        triangles: &[[[f32; 3]; 3]],
        threads: usize,
        isa: Option<&str>,
    ) -> Result<Self> {
        let api = Api::get(version)?;
        let mut config = format!("threads={}", threads.max(1));
        if let Some(isa) = isa {
            config.push_str(&format!(",isa={isa}"));
        }
        let config = CString::new(config).context("a configuration without NUL bytes")?;
        // SAFETY: a NUL-terminated configuration string.
        let device = unsafe { (api.new_device)(config.as_ptr()) };
        if device.is_null() {
            bail!("{} refused to create a device", version.name());
        }
        // SAFETY: calls on the device just made; the buffers Embree returns hold exactly the
        // items asked for, each of the stride given, and are filled before the commit.
        unsafe {
            let scene = (api.new_scene)(device);
            let embree = Self { api, device, scene };
            let geometry = (api.new_geometry)(device, GEOMETRY_TYPE_TRIANGLE);
            let count = triangles.len();
            let vertices = (api.set_new_buffer)(
                geometry,
                BUFFER_TYPE_VERTEX,
                0,
                FORMAT_FLOAT3,
                12,
                3 * count,
            )
            .cast::<[f32; 3]>();
            let indices =
                (api.set_new_buffer)(geometry, BUFFER_TYPE_INDEX, 0, FORMAT_UINT3, 12, count)
                    .cast::<[u32; 3]>();
            if vertices.is_null() || indices.is_null() {
                (api.release_geometry)(geometry);
                bail!("{} could not allocate the mesh's buffers", version.name());
            }
            for (index, corners) in triangles.iter().enumerate() {
                for (corner, &point) in corners.iter().enumerate() {
                    vertices.add(3 * index + corner).write(point);
                }
                let first = 3 * index as u32;
                indices.add(index).write([first, first + 1, first + 2]);
            }
            (api.commit_geometry)(geometry);
            (api.attach_geometry)(scene, geometry);
            (api.release_geometry)(geometry);
            (api.commit_scene)(scene);
            let error = (api.device_error)(device);
            if error != 0 {
                bail!("{} reported error {error} while building", version.name());
            }
            Ok(embree)
        }
    }

    /// Which Embree built it.
    pub fn version(&self) -> Version {
        self.api.version
    }

    /// The closest hit of one ray (`rtcIntersect1`).
    pub fn closest(&self, ray: &Ray) -> Option<Hit> {
        let mut ray_hit = RayHit::new(ray);
        let mut record = QueryRecord::new(self.api.version, Coherence::Incoherent);
        let (first, second) = record.around((&mut ray_hit as *mut RayHit).cast());
        // SAFETY: a committed scene; the record and the ray laid out as the version's headers
        // say, in its order.
        unsafe { (self.api.intersect1)(self.scene, first, second) };
        (ray_hit.geometry != INVALID_ID).then_some(Hit {
            primitive: ray_hit.primitive,
            t: ray_hit.t_far,
        })
    }

    /// Whether anything lies on the ray before its end (`rtcOccluded1`, which marks an
    /// occluded ray by setting its `t_far` to minus infinity).
    pub fn occluded(&self, ray: &Ray) -> bool {
        let mut ray_hit = RayHit::new(ray);
        let mut record = QueryRecord::new(self.api.version, Coherence::Incoherent);
        let (first, second) = record.around((&mut ray_hit as *mut RayHit).cast());
        // SAFETY: as in `closest`; `RTCRay` is the start of `RayHit`.
        unsafe { (self.api.occluded1)(self.scene, first, second) };
        ray_hit.t_far == f32::NEG_INFINITY
    }

    /// A packet tracer: `rays` traced 16 at a time as coherent packets.
    pub fn packets(&self) -> Packets<'_> {
        let (packet, valid) = RayHitPacket::new(&[]);
        Packets {
            embree: self,
            packet,
            valid,
        }
    }
}

/// Coherent 16-wide packets on one scene, reusing one packet record.
pub struct Packets<'a> {
    embree: &'a Embree,
    packet: Box<RayHitPacket>,
    valid: ValidMask,
}

impl Packets<'_> {
    /// The closest hits of up to 16 rays (`rtcIntersect16`), into `hits`.
    pub fn closest(&mut self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        self.trace(rays, self.embree.api.intersect16);
        for (lane, hit) in hits.iter_mut().enumerate().take(rays.len().min(PACKET)) {
            *hit = (self.packet.geometry[lane] != INVALID_ID).then_some(Hit {
                primitive: self.packet.primitive[lane],
                t: self.packet.t_far[lane],
            });
        }
    }

    /// Whether anything lies on each of up to 16 rays (`rtcOccluded16`), into `occluded`.
    pub fn occluded(&mut self, rays: &[Ray], occluded: &mut [bool]) {
        self.trace(rays, self.embree.api.occluded16);
        for (lane, answer) in occluded.iter_mut().enumerate().take(rays.len().min(PACKET)) {
            *answer = self.packet.t_far[lane] == f32::NEG_INFINITY;
        }
    }

    fn trace(&mut self, rays: &[Ray], call: Call16) {
        self.packet.refill(rays, &mut self.valid);
        let mut record = QueryRecord::new(self.embree.api.version, Coherence::Coherent);
        let (first, second) = record.around((&mut *self.packet as *mut RayHitPacket).cast());
        // SAFETY: a committed scene; a packet laid out as `RTCRayHit16` (whose start is
        // `RTCRay16`) and a valid mask of 16 lanes, both 64-byte aligned; the record in the
        // version's order.
        unsafe { call(self.valid.0.as_ptr(), self.embree.scene, first, second) };
    }
}
