//! Large meshes read and built aside in the browser. The page has one thread, and a million
//! triangles take seconds to read and to build over: done there, the page would freeze. So a
//! Web Worker (`web/worker.js`) runs this same WASM module and does it, while the page keeps
//! drawing and can cancel (the worker is stopped). On the desktop worker threads do the same
//! ([`crate::background`], [`super::scene`]).
//!
//! A worker has its own memory: what it makes comes back as bytes. A mesh is its corners,
//! nine numbers a triangle ([`flat_triangles`]); a built structure is [`pack`]ed with what
//! the builder's thread measured of it, and [`unpack`]ed into the same `Built` (tested: equal
//! field for field), its facts made again from the tree.

use accelviz_core::bytes::{ByteReader, ByteWriter, BytesError};
use accelviz_core::{Built, TreeStats};

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use accelviz_scene::Mesh;

use super::tree::MeshBuild;
use crate::view3d::DrawTriangle;

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

/// `built` as bytes: the core's bytes of the structure ([`Built::write_bytes`]), then what the
/// builder's thread measured of it and the triangles as the 3D view draws them.
pub fn pack(built: &MeshBuild) -> Vec<u8> {
    let mut out = ByteWriter::new();
    built.built.write_bytes(&mut out);
    built.stats.write_bytes(&mut out);
    out.f64(built.build_millis);
    out.usize(built.root_triangles);
    let (center, radius) = built.sphere;
    out.vector(center);
    out.f64(radius);
    out.usize(built.drawn.len());
    out.reserve(built.drawn.len() * DRAWN_TRIANGLE_BYTES);
    for triangle in &built.drawn {
        for &value in triangle.corners.iter().flatten() {
            out.f32(value);
        }
        out.raw(&triangle.color);
    }
    out.into_bytes()
}

/// A drawn triangle's bytes: nine `f32` corners and four colour bytes.
const DRAWN_TRIANGLE_BYTES: usize = 9 * 4 + 4;

/// What [`pack`] made, back; or why the bytes are not that.
pub fn unpack(bytes: &[u8]) -> Result<MeshBuild, String> {
    let read = || -> Result<MeshBuild, BytesError> {
        let mut input = ByteReader::new(bytes);
        let built = Built::read_bytes(&mut input)?;
        let stats = TreeStats::read_bytes(&mut input)?;
        let build_millis = input.f64()?;
        let root_triangles = input.usize()?;
        let sphere = (input.vector()?, input.f64()?);
        let drawn = input.items(DRAWN_TRIANGLE_BYTES, |input| {
            let mut corner = || -> Result<[f32; 3], BytesError> {
                Ok([input.f32()?, input.f32()?, input.f32()?])
            };
            let corners = [corner()?, corner()?, corner()?];
            Ok(DrawTriangle {
                corners,
                color: input.array()?,
            })
        })?;
        input.finish()?;
        Ok(MeshBuild {
            built,
            stats,
            root_triangles,
            build_millis,
            sphere,
            drawn,
        })
    };
    read().map_err(|error| format!("the structure sent back: {error}"))
}

/// A mesh's triangles as nine numbers each (the corners in order), to send to a worker.
pub fn flat_triangles(triangles: &[[[f64; 3]; 3]]) -> &[f64] {
    triangles.as_flattened().as_flattened()
}

/// Triangles from [`flat_triangles`]' numbers (a partial triangle at the end is dropped).
pub fn triangles_of(numbers: &[f64]) -> Vec<[[f64; 3]; 3]> {
    numbers
        .chunks_exact(9)
        .map(|n| [[n[0], n[1], n[2]], [n[3], n[4], n[5]], [n[6], n[7], n[8]]])
        .collect()
}

/// The work a worker does, called by `web/worker.js` through the exports in `main.rs`.
pub mod work {
    use super::{flat_triangles, pack, triangles_of};
    use crate::mesh::MeshTree;
    use accelviz_core::{Structure, TriangleSet};
    use accelviz_scene::Mesh;

    /// Reads OBJ `bytes` named `name`, telling `progress` how far it got (per mille, only
    /// when that changes); the triangles' corners, nine numbers a triangle.
    pub fn read_obj(name: &str, bytes: &[u8], progress: &dyn Fn(u32)) -> Result<Vec<f64>, String> {
        let text = std::str::from_utf8(bytes)
            .map_err(|_| format!("{name}: not a text file (it is not UTF-8)"))?;
        let last = std::cell::Cell::new(u32::MAX);
        let mesh = accelviz_scene::obj::parse_obj_with_progress(text, name, &|permille| {
            if last.replace(permille) != permille {
                progress(permille);
            }
        })
        .map_err(|error| error.to_string())?;
        Ok(flat_triangles(&mesh.triangles).to_vec())
    }

    /// Builds the structure named `structure` over `triangles` (nine numbers each), packed.
    pub fn build(triangles: &[f64], structure: &str) -> Result<Vec<u8>, String> {
        let structure = Structure::parse(structure).map_err(|error| error.to_string())?;
        let mesh = Mesh {
            name: String::new(),
            triangles: triangles_of(triangles),
        };
        let triangles = TriangleSet::from_f64(&mesh.triangles);
        Ok(pack(&MeshTree::build_structure(
            &mesh, &triangles, structure,
        )))
    }
}

/// Jobs sent to a Web Worker from the page.
#[cfg(target_arch = "wasm32")]
pub mod worker {
    use std::cell::RefCell;
    use std::rc::Rc;

    use wasm_bindgen::JsCast;
    use wasm_bindgen::prelude::{Closure, JsValue};

    /// A Web Worker running `web/worker.js`, with the handlers that hear it; dropped, it
    /// stops.
    pub struct Spawned {
        worker: web_sys::Worker,
        _on_message: Closure<dyn FnMut(web_sys::MessageEvent)>,
        _on_error: Closure<dyn FnMut(web_sys::Event)>,
    }

    impl Drop for Spawned {
        fn drop(&mut self) {
            self.worker.terminate();
        }
    }

    impl Spawned {
        /// Starts `web/worker.js`; `on_message` hears every message it sends (its data),
        /// `on_error` why it failed, if it does.
        pub fn new(
            mut on_message: impl FnMut(JsValue) + 'static,
            mut on_error: impl FnMut(String) + 'static,
        ) -> Result<Self, String> {
            let options = web_sys::WorkerOptions::new();
            options.set_type(web_sys::WorkerType::Module);
            let worker =
                web_sys::Worker::new_with_options("./worker.js", &options).map_err(describe)?;
            let on_message = Closure::<dyn FnMut(web_sys::MessageEvent)>::new(
                move |event: web_sys::MessageEvent| on_message(event.data()),
            );
            let on_error =
                Closure::<dyn FnMut(web_sys::Event)>::new(move |event: web_sys::Event| {
                    let message = event
                        .dyn_ref::<web_sys::ErrorEvent>()
                        .map(|error| error.message())
                        .unwrap_or_else(|| "worker.js could not be loaded".to_owned());
                    on_error(format!("the background worker failed: {message}"));
                });
            worker.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
            worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
            Ok(Self {
                worker,
                _on_message: on_message,
                _on_error: on_error,
            })
        }

        /// Sends `job` (an object of named fields, see `web/worker.js`), handing over the
        /// buffers in `transfer`, with the page's compiled module (so the worker need not
        /// compile it again).
        pub fn post(&self, job: &[(&str, JsValue)], transfer: &[JsValue]) -> Result<(), String> {
            let message = js_sys::Object::new();
            let module = ("module", wasm_bindgen::module());
            for (name, value) in job.iter().chain([&module]) {
                js_sys::Reflect::set(&message, &JsValue::from_str(name), value)
                    .map_err(describe)?;
            }
            let transfer: js_sys::Array = transfer.iter().collect();
            self.worker
                .post_message_with_transfer(&message, &transfer)
                .map_err(describe)
        }
    }

    fn describe(error: JsValue) -> String {
        format!("{error:?}")
    }

    /// A field of a worker's message, if it has it.
    pub fn field(data: &JsValue, name: &str) -> Option<JsValue> {
        js_sys::Reflect::get(data, &JsValue::from_str(name))
            .ok()
            .filter(|value| !value.is_undefined())
    }

    /// A job running in a Web Worker of its own; dropping it stops the worker.
    pub type WorkerJob = Spawned;

    /// What a worker sends back: its result's bytes (a typed array), or why there is none.
    pub type Outcome = Result<JsValue, String>;

    /// What a worker says before it is done.
    pub enum Report {
        /// How far it got, per mille.
        Progress(u32),
    }

    /// What hears a job's outcome, shared by the handlers that may hear it.
    type OnDone = Rc<RefCell<Option<Box<dyn FnOnce(Outcome)>>>>;

    /// Starts a worker of its own on `job` (see [`Spawned::post`]), handing it the buffers in
    /// `transfer`; `on_report` hears what it reports on the way, `on_done` its outcome, once.
    pub fn start(
        job: &[(&str, JsValue)],
        transfer: &[JsValue],
        on_report: impl Fn(Report) + 'static,
        on_done: impl FnOnce(Outcome) + 'static,
    ) -> Result<WorkerJob, String> {
        // Called once, by whichever of the message and error handlers hears the end first.
        let on_done: OnDone = Rc::new(RefCell::new(Some(Box::new(on_done))));
        let finish = move |outcome: Outcome| {
            if let Some(on_done) = on_done.borrow_mut().take() {
                on_done(outcome);
            }
        };
        let finish_on_error = finish.clone();
        let spawned = Spawned::new(
            move |data| {
                if let Some(progress) = field(&data, "progress").and_then(|value| value.as_f64()) {
                    on_report(Report::Progress(progress as u32));
                } else if let Some(done) = field(&data, "done") {
                    finish(Ok(done));
                } else {
                    let problem = field(&data, "problem").and_then(|value| value.as_string());
                    finish(Err(
                        problem.unwrap_or_else(|| "the worker sent nothing".to_owned())
                    ));
                }
            },
            move |problem| finish_on_error(Err(problem)),
        )?;
        spawned.post(job, transfer)?;
        Ok(spawned)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::MeshTree;
    use accelviz_core::Structure;
    use std::sync::Arc;

    #[test]
    fn every_structure_comes_back_equal() {
        let mesh = Arc::new(accelviz_scene::builtin::teapot());
        let wide = [accelviz_core::Width::Four, accelviz_core::Width::Eight]
            .map(|width| accelviz_core::CATALOGUE[3].structure.with_width(width));
        let structures = accelviz_core::CATALOGUE.iter().map(|entry| entry.structure);
        for structure in structures.chain(wide) {
            let tree = MeshTree::build(mesh.clone(), structure);
            let bytes = pack(&tree.build);
            assert_eq!(
                unpack(&bytes).as_ref(),
                Ok(&tree.build),
                "{}",
                structure.name()
            );
            // Cut short or padded: an error, never a panic.
            for cut in [0, 7, 8, 40, bytes.len() / 2, bytes.len() - 1] {
                assert!(unpack(&bytes[..cut]).is_err(), "cut at {cut}");
            }
            let mut padded = bytes.clone();
            padded.push(0);
            assert!(unpack(&padded).is_err());
        }
        let flat = flat_triangles(&mesh.triangles);
        assert_eq!(triangles_of(flat), mesh.triangles);
    }

    #[test]
    fn the_workers_read_and_build_are_the_apps() {
        let mesh = accelviz_scene::builtin::teapot();
        let text = accelviz_scene::obj::obj_text(&mesh);
        let heard = std::cell::RefCell::new(Vec::new());
        let numbers = work::read_obj("teapot.obj", text.as_bytes(), &|permille| {
            heard.borrow_mut().push(permille)
        })
        .expect("reads");
        assert_eq!(triangles_of(&numbers), mesh.triangles);
        let heard = heard.into_inner();
        assert!(heard.windows(2).all(|pair| pair[0] < pair[1]), "{heard:?}");

        let structure = Structure::parse("kd:sah").expect("in the catalogue");
        let mut from_worker =
            unpack(&work::build(&numbers, &structure.name()).expect("builds")).expect("unpacks");
        let on_page = MeshTree::build(Arc::new(mesh), structure).build;
        from_worker.build_millis = on_page.build_millis;
        assert_eq!(from_worker, on_page);

        // Bad input: a message naming the file and line, or the structure.
        let problem = work::read_obj("bad.obj", b"v 0 0 0\nv 1 x 0\n", &|_| {}).unwrap_err();
        assert!(problem.contains("bad.obj:2"), "{problem}");
        let problem = work::read_obj("binary.obj", &[0xff, 0xfe, 0], &|_| {}).unwrap_err();
        assert!(problem.contains("binary.obj: not a text file"), "{problem}");
        assert!(work::build(&numbers, "bvh:nonsense").is_err());
    }
}
