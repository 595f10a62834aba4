//! Embree 3 (Intel's ray tracing kernels; Debian's `libembree3`), loaded at run time, so the
//! workspace builds and CI compiles this crate on machines without it; `scripts/bench`
//! installs `libembree-dev` when it is missing. The declarations follow Debian's headers
//! (`/usr/include/embree3`, version 3.13.5: one instance level, no minimum width).
//!
//! Built as an application builds it by default (`rtcCommitScene`, medium quality; on AVX
//! machines a BVH8 of four-triangle leaves) on one thread (`threads=1`, as accelviz builds);
//! traced one ray at a time (`rtcIntersect1`) or, for camera rays, in packets of 8 or 16 with
//! the coherent flag (`rtcIntersect8`/`rtcIntersect16`), as Embree's documentation advises.

// A foreign library is reached only through raw pointers; every call below is to a function
// looked up by its documented name and signature, with arguments laid out as its headers say.
#![allow(unsafe_code)]

use std::ffi::{CString, c_char, c_int, c_uint, c_void};

use anyhow::{Context, Result, bail};

type Device = *mut c_void;
type Scene = *mut c_void;
type Geometry = *mut c_void;

const GEOMETRY_TYPE_TRIANGLE: c_uint = 0;
const BUFFER_TYPE_INDEX: c_uint = 0;
const BUFFER_TYPE_VERTEX: c_uint = 1;
const FORMAT_UINT3: c_uint = 0x5003;
const FORMAT_FLOAT3: c_uint = 0x9003;
const CONTEXT_FLAG_INCOHERENT: c_uint = 0;
const CONTEXT_FLAG_COHERENT: c_uint = 1;
const INVALID_GEOMETRY_ID: c_uint = u32::MAX;

/// `struct RTCIntersectContext` with `RTC_MAX_INSTANCE_LEVEL_COUNT == 1`.
#[repr(C)]
struct IntersectContext {
    flags: c_uint,
    filter: *const c_void,
    instance_id: [c_uint; 1],
}

impl IntersectContext {
    /// What `rtcInitIntersectContext` (an inline function in the header) sets.
    fn new(flags: c_uint) -> Self {
        Self {
            flags,
            filter: std::ptr::null(),
            instance_id: [INVALID_GEOMETRY_ID],
        }
    }
}

/// `struct RTCRayHit`: `RTCRay` then `RTCHit`, each 16-byte aligned.
#[repr(C, align(16))]
#[derive(Clone, Copy)]
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
}

/// `struct RTCRayHitN` for N = 8 or 16: each field an array of N lanes.
#[repr(C, align(64))]
#[derive(Clone, Copy)]
struct RayHitPacket<const N: usize> {
    origin: [[f32; N]; 3],
    t_near: [f32; N],
    direction: [[f32; N]; 3],
    time: [f32; N],
    t_far: [f32; N],
    mask: [c_uint; N],
    id: [c_uint; N],
    flags: [c_uint; N],
    normal: [[f32; N]; 3],
    u: [f32; N],
    v: [f32; N],
    primitive: [c_uint; N],
    geometry: [c_uint; N],
    instance: [[c_uint; N]; 1],
}

/// The entry points used, looked up once.
struct Api {
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
    intersect1: unsafe extern "C" fn(Scene, *mut IntersectContext, *mut RayHit),
    intersect8:
        unsafe extern "C" fn(*const c_int, Scene, *mut IntersectContext, *mut RayHitPacket<8>),
    intersect16:
        unsafe extern "C" fn(*const c_int, Scene, *mut IntersectContext, *mut RayHitPacket<16>),
}

/// Loaded once and never unloaded: Embree's worker threads outlive any one scene, and
/// unloading the library under them crashes the process.
static API: std::sync::OnceLock<Result<Api, String>> = std::sync::OnceLock::new();

impl Api {
    fn get() -> Result<&'static Api> {
        API.get_or_init(|| Api::load().map_err(|error| format!("{error:#}")))
            .as_ref()
            .map_err(|error| anyhow::anyhow!("{error}"))
    }

    fn load() -> Result<Self> {
        // SAFETY: loading Embree runs its initialisers, which have no preconditions.
        let library = unsafe { libloading::Library::new("libembree3.so.3") }.context(
            "Embree 3 is not installed (Debian: apt-get install libembree-dev; scripts/bench does it)",
        )?;
        macro_rules! symbol {
            ($name:literal) => {
                // SAFETY: the symbol is Embree 3's function of that name, whose C signature
                // is the field's type.
                *unsafe { library.get(concat!($name, "\0").as_bytes()) }
                    .with_context(|| format!("Embree lacks {}", $name))?
            };
        }
        Ok(Self {
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
            intersect8: symbol!("rtcIntersect8"),
            intersect16: symbol!("rtcIntersect16"),
            _library: library,
        })
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

impl Embree {
    /// Builds a scene of `triangles` (each its three corners) on one thread.
    pub fn build(triangles: &[[[f32; 3]; 3]]) -> Result<Self> {
        let api = Api::get()?;
        let config = CString::new("threads=1").unwrap_or_default();
        // SAFETY: a NUL-terminated configuration string.
        let device = unsafe { (api.new_device)(config.as_ptr()) };
        if device.is_null() {
            bail!("Embree refused to create a device");
        }
        // SAFETY: calls on the device just made; the buffers Embree returns hold exactly the
        // items asked for, each of the stride given, and are filled before the commit.
        unsafe {
            let scene = (api.new_scene)(device);
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
                bail!("Embree could not allocate the mesh's buffers");
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
                bail!("Embree reported error {error} while building");
            }
            Ok(Self { api, device, scene })
        }
    }

    /// The closest hit of one ray: its triangle, or `None`.
    pub fn intersect1(&self, origin: [f32; 3], direction: [f32; 3], t_max: f32) -> Option<u32> {
        let mut ray_hit = RayHit {
            origin,
            t_near: 0.0,
            direction,
            time: 0.0,
            t_far: t_max,
            mask: u32::MAX,
            id: 0,
            flags: 0,
            normal: [0.0; 3],
            u: 0.0,
            v: 0.0,
            primitive: INVALID_GEOMETRY_ID,
            geometry: INVALID_GEOMETRY_ID,
            instance: [INVALID_GEOMETRY_ID],
        };
        let mut context = IntersectContext::new(CONTEXT_FLAG_INCOHERENT);
        // SAFETY: a committed scene, an initialised context and ray.
        unsafe { (self.api.intersect1)(self.scene, &mut context, &mut ray_hit) };
        (ray_hit.geometry != INVALID_GEOMETRY_ID).then_some(ray_hit.primitive)
    }

    /// The closest hits of up to `N` rays (8 or 16) traced together as one coherent packet.
    pub fn intersect_packet<const N: usize>(
        &self,
        rays: &[([f32; 3], [f32; 3], f32)],
        hits: &mut [Option<u32>],
    ) {
        assert!(N == 8 || N == 16, "Embree's packets hold 8 or 16 rays");
        let mut packet = RayHitPacket::<N> {
            origin: [[0.0; N]; 3],
            t_near: [0.0; N],
            direction: [[0.0; N]; 3],
            time: [0.0; N],
            t_far: [0.0; N],
            mask: [u32::MAX; N],
            id: [0; N],
            flags: [0; N],
            normal: [[0.0; N]; 3],
            u: [0.0; N],
            v: [0.0; N],
            primitive: [INVALID_GEOMETRY_ID; N],
            geometry: [INVALID_GEOMETRY_ID; N],
            instance: [[INVALID_GEOMETRY_ID; N]; 1],
        };
        let mut valid = [0 as c_int; N];
        for (lane, &(origin, direction, t_max)) in rays.iter().enumerate().take(N) {
            for axis in 0..3 {
                packet.origin[axis][lane] = origin[axis];
                packet.direction[axis][lane] = direction[axis];
            }
            packet.t_far[lane] = t_max;
            valid[lane] = -1;
        }
        let mut context = IntersectContext::new(CONTEXT_FLAG_COHERENT);
        let packet_pointer = (&mut packet as *mut RayHitPacket<N>).cast::<c_void>();
        // SAFETY: a committed scene, a packet laid out as `RTCRayHitN` for this N, and a
        // valid mask of N lanes.
        unsafe {
            if N == 8 {
                (self.api.intersect8)(
                    valid.as_ptr(),
                    self.scene,
                    &mut context,
                    packet_pointer.cast(),
                );
            } else {
                (self.api.intersect16)(
                    valid.as_ptr(),
                    self.scene,
                    &mut context,
                    packet_pointer.cast(),
                );
            }
        }
        for (lane, hit) in hits.iter_mut().enumerate().take(rays.len().min(N)) {
            *hit = (packet.geometry[lane] != INVALID_GEOMETRY_ID).then_some(packet.primitive[lane]);
        }
    }
}
