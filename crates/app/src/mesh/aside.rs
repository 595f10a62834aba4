//! Large meshes read and built aside in the browser. The page has one thread, and a million
//! triangles take seconds to read and to build over: done there, the page would freeze. So a
//! Web Worker (`web/worker.js`) runs this same WASM module and does it, while the page keeps
//! drawing and can cancel (the worker is stopped). On the desktop worker threads do the same
//! ([`crate::background`], [`super::scene`]).
//!
//! A worker has its own memory: what crosses to it and back is bytes ([`super::packed`]);
//! what it runs is [`super::work`], started through [`super::worker`].

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use accelviz_scene::Mesh;

#[cfg(target_arch = "wasm32")]
use super::packed::{flat_triangles, unpack};
#[cfg(target_arch = "wasm32")]
use super::worker;

/// An OBJ file read on a worker thread (a Web Worker in the browser): its name, how far it
/// got, and its result.
pub struct MeshLoad {
    /// The file's name.
    pub name: String,
    /// Read so far, per mille.
    progress: Arc<AtomicU32>,
    result: MeshSlot,
    /// Keeps a Web Worker going; dropped (cancelled, or read), it stops the worker.
    _work: Box<dyn std::any::Any>,
}

/// Where a mesh read aside is left.
type MeshSlot = Arc<Mutex<Option<Result<Mesh, String>>>>;

/// Reads `text` on a worker thread, reporting to `progress` and leaving the mesh in `result`;
/// `None` where there are no worker threads (the tests).
#[cfg(not(target_arch = "wasm32"))]
fn read_aside(
    name: &str,
    text: &str,
    progress: Arc<AtomicU32>,
    result: MeshSlot,
) -> Option<Box<dyn std::any::Any>> {
    if crate::background::worker_threads() == 0 {
        return None;
    }
    let (text, name) = (text.to_owned(), name.to_owned());
    std::thread::spawn(move || {
        let mesh = accelviz_scene::obj::parse_obj_with_progress(&text, &name, &|permille| {
            progress.store(permille, Ordering::Relaxed)
        })
        .map_err(|error| error.to_string());
        if let Ok(mut slot) = result.lock() {
            *slot = Some(mesh);
        }
    });
    // The thread needs nothing kept: it ends by itself, and a cancelled read is ignored.
    Some(Box::new(()))
}

/// Reads `text` in a Web Worker (see [`super::aside`]), reporting to `progress` and leaving
/// the mesh in `result`; `None` if no worker could start (the page then reads it itself).
#[cfg(target_arch = "wasm32")]
fn read_aside(
    name: &str,
    text: &str,
    progress: Arc<AtomicU32>,
    result: MeshSlot,
) -> Option<Box<dyn std::any::Any>> {
    let bytes = js_sys::Uint8Array::from(text.as_bytes());
    let buffer = bytes.buffer();
    let mesh_name = name.to_owned();
    let started = worker::start(
        &[
            ("job", "read".into()),
            ("name", name.into()),
            ("bytes", bytes.into()),
        ],
        &[buffer.into()],
        move |worker::Report::Progress(permille)| progress.store(permille, Ordering::Relaxed),
        move |outcome| {
            let mesh = outcome.map(|numbers| {
                // Copied once, straight into the triangles' memory.
                let numbers = js_sys::Float64Array::new(&numbers);
                let mut triangles = vec![[[0.0; 3]; 3]; numbers.length() as usize / 9];
                numbers
                    .subarray(0, triangles.len() as u32 * 9)
                    .copy_to(triangles.as_flattened_mut().as_flattened_mut());
                Mesh {
                    name: mesh_name,
                    triangles,
                }
            });
            if let Ok(mut slot) = result.lock() {
                *slot = Some(mesh);
            }
        },
    );
    match started {
        Ok(job) => Some(Box::new(job)),
        Err(problem) => {
            log::error!("accelviz: cannot read aside: {problem}");
            None
        }
    }
}

impl MeshLoad {
    /// Starts reading `text` (the file `name`) aside, if there is somewhere to do it.
    pub fn start(name: &str, text: &str) -> Option<Self> {
        let progress = Arc::new(AtomicU32::new(0));
        let result: MeshSlot = Arc::new(Mutex::new(None));
        let work = read_aside(name, text, progress.clone(), result.clone())?;
        Some(Self {
            name: name.to_owned(),
            progress,
            result,
            _work: work,
        })
    }

    /// How much of the file is read, from 0 to 1.
    pub fn progress(&self) -> f32 {
        self.progress.load(Ordering::Relaxed) as f32 / 1000.0
    }

    /// The mesh, or why it could not be read, once the read has ended (once).
    pub fn take_result(&self) -> Option<Result<Mesh, String>> {
        self.result.lock().ok().and_then(|mut result| result.take())
    }
}

/// In the browser, structures over this many triangles or more are built in a Web Worker (on
/// the page, the bunny's 70k took about 0.2 s: the page would stop for that long).
#[cfg(target_arch = "wasm32")]
pub const BUILD_ASIDE_FROM: usize = 50_000;

/// Builds `structure` over `mesh` in a Web Worker, sending the tree to `sender` when it is
/// back; if the worker fails, on the page instead (slow, but the lesson gets its tree).
#[cfg(target_arch = "wasm32")]
pub fn build_in_worker(
    mesh: Arc<Mesh>,
    structure: accelviz_core::Structure,
    sender: std::sync::mpsc::Sender<crate::mesh::MeshTree>,
) -> Result<worker::WorkerJob, String> {
    let triangles = js_sys::Float64Array::from(flat_triangles(&mesh.triangles));
    let buffer = triangles.buffer();
    worker::start(
        &[
            ("job", "build".into()),
            ("structure", structure.name().into()),
            ("triangles", triangles.into()),
        ],
        &[buffer.into()],
        |_| {},
        move |outcome| {
            let started = web_time::Instant::now();
            let unpacked =
                outcome.and_then(|bytes| unpack(&js_sys::Uint8Array::new(&bytes).to_vec()));
            let tree = match unpacked {
                Ok(aside) => {
                    let triangles =
                        accelviz_core::TriangleSet::<glam::DVec3>::from_f64(&mesh.triangles);
                    crate::mesh::MeshTree::with_built(mesh, triangles, aside)
                }
                Err(problem) => {
                    log::error!(
                        "accelviz: the build aside failed ({problem}); building on the page"
                    );
                    crate::mesh::MeshTree::build(mesh, structure)
                }
            };
            log::info!(
                "accelviz: {} built aside over {} triangles in {:.0} ms, taken in on the page in {:.0} ms",
                structure.name(),
                tree.mesh.triangles.len(),
                tree.build.build_millis,
                started.elapsed().as_secs_f64() * 1e3
            );
            let _ = sender.send(tree);
        },
    )
}
