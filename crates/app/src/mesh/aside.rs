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

use accelviz_core::Tree;
use accelviz_core::bvh::{Bvh, BvhNode, WideBvh};
use accelviz_core::grid::{DenseCells, Grid, GridCells, GridLimits, HashedCells};
use accelviz_core::kd::{KdBudgetExceeded, KdLimits, KdNode, KdTree};
use accelviz_core::octree::{Octree, OctreeLimits, OctreeNode};
use accelviz_core::{Built, Family, LeafReason, SahCost, Structure, TreeFacts, TreeStats};
use glam::DVec3;

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use accelviz_scene::Mesh;

use super::bytes::{Reader, Writer, aabb_at, f32_at, f64_at, u32_at};
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
    structure: Structure,
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
                    let triangles = accelviz_core::TriangleSet::<DVec3>::from_f64(&mesh.triangles);
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

/// Marks packed bytes, and their layout's version.
const MAGIC: &[u8; 8] = b"accelvz1";

/// `built` as bytes (little-endian).
pub fn pack(built: &MeshBuild) -> Vec<u8> {
    let mut out = Writer::default();
    out.bytes.extend_from_slice(MAGIC);
    let name = built.built.structure.name();
    out.u64(name.len() as u64);
    out.bytes.extend_from_slice(name.as_bytes());
    out.f64(built.build_millis);
    out.u64(built.root_triangles as u64);
    let stats = &built.stats;
    for count in [
        stats.node_count,
        stats.leaf_count,
        stats.max_depth,
        stats.min_leaf_size,
        stats.max_leaf_size,
        stats.primitive_references,
        stats.empty_leaf_count,
    ] {
        out.u64(count as u64);
    }
    for value in [stats.mean_leaf_size, stats.empty_leaf_share, stats.sah_cost] {
        out.f64(value);
    }
    // A wide BVH travels as its binary tree and is collapsed again (deterministic, and quick).
    match &built.built.tree {
        Tree::Bvh(bvh)
        | Tree::Bvh4(WideBvh { binary: bvh, .. })
        | Tree::Bvh8(WideBvh { binary: bvh, .. }) => {
            out.u64(0);
            out.u64(bvh.nodes.len() as u64);
            for node in &bvh.nodes {
                out.aabb(&node.bounds);
                out.u32(node.first);
                out.u32(node.count);
            }
            out.u32s(&bvh.primitive_indices);
        }
        Tree::Kd(kd) => {
            out.u64(1);
            out.aabb(&kd.bounds);
            out.u64(kd.nodes.len() as u64);
            for node in &kd.nodes {
                out.f64(node.split);
                out.u32(node.axis);
                out.u32(node.first);
                out.u32(node.count);
            }
            out.u32s(&kd.primitive_indices);
            out.u64(kd.limits.depth_limit as u64);
            out.u64(kd.limits.leaves_at_depth_limit as u64);
            let (tag, usual, budget) = match kd.limits.lowered_from {
                None => (0, 0, 0),
                Some((usual, KdBudgetExceeded::Nodes(budget))) => (1, usual, budget),
                Some((usual, KdBudgetExceeded::References(budget))) => (2, usual, budget),
            };
            for number in [tag, usual, budget] {
                out.u64(number as u64);
            }
        }
        // A grid travels as its dense table; the cells are made again from its box and
        // resolution, and a hashed grid's table again from the dense one (deterministic).
        Tree::Grid(Grid { cells, limits, .. }) | Tree::HashedGrid(Grid { cells, limits, .. }) => {
            let (dense, places) = match &built.built.tree {
                Tree::Grid(grid) => (grid.store.clone(), 0),
                Tree::HashedGrid(grid) => (
                    grid.store.to_dense(cells.cell_count()),
                    grid.store.buckets.len(),
                ),
                _ => unreachable!("a grid"),
            };
            out.u64(2);
            out.aabb(&cells.bounds);
            for count in cells.resolution {
                out.u32(count);
            }
            out.f64(limits.density_asked);
            out.f64(limits.density_used);
            out.u64(places as u64);
            out.u32s(&dense.cell_start);
            out.u32s(&dense.references);
        }
        Tree::Octree(tree) => {
            out.u64(3);
            out.aabb(&tree.bounds);
            out.u64(tree.nodes.len() as u64);
            for node in &tree.nodes {
                out.u32(node.first);
                out.u32(node.count);
            }
            out.u32s(&tree.primitive_indices);
            let limits = &tree.limits;
            out.u64(limits.depth_limit as u64);
            out.u64(limits.leaves_at_depth_limit as u64);
            out.u64(limits.lowered_from.map_or(0, |usual| usual as u64 + 1));
        }
    }
    let reasons = &built.built.facts.leaf_reasons;
    out.u64(reasons.len() as u64);
    for reason in reasons {
        // A tag and two numbers each.
        let (tag, a, b) = match *reason {
            None => (0, 0.0, 0.0),
            Some(LeafReason::SmallEnough {
                count,
                max_leaf_size,
            }) => (1, count as f64, max_leaf_size as f64),
            Some(LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: None,
            }) => (2, leaf_cost, 0.0),
            Some(LeafReason::LeafCheaper {
                leaf_cost,
                split_cost: Some(split_cost),
            }) => (3, leaf_cost, split_cost),
            Some(LeafReason::Inseparable { count }) => (4, count as f64, 0.0),
            Some(LeafReason::DepthLimit { limit }) => (5, limit as f64, 0.0),
            Some(LeafReason::GridCell) => (6, 0.0, 0.0),
        };
        out.bytes.push(tag);
        out.f64(a);
        out.f64(b);
    }
    let (center, radius) = built.sphere;
    for value in center.to_array().into_iter().chain([radius]) {
        out.f64(value);
    }
    out.u64(built.drawn.len() as u64);
    out.bytes.reserve(built.drawn.len() * 40);
    for triangle in &built.drawn {
        for value in triangle.corners.iter().flatten() {
            out.bytes.extend_from_slice(&value.to_le_bytes());
        }
        out.bytes.extend_from_slice(&triangle.color);
    }
    out.bytes
}

/// What [`pack`] made, back; or why the bytes are not that.
pub fn unpack(bytes: &[u8]) -> Result<MeshBuild, String> {
    let mut input = Reader { rest: bytes };
    if input.take(MAGIC.len())? != MAGIC {
        return Err("not a structure packed by this version of accelviz".to_owned());
    }
    let name_length = input.usize()?;
    let name = std::str::from_utf8(input.take(name_length)?)
        .map_err(|_| "the structure's name is not text".to_owned())?;
    let structure = Structure::parse(name).map_err(|error| error.to_string())?;
    let build_millis = input.f64()?;
    let root_triangles = input.usize()?;
    let mut counts = [0usize; 7];
    for count in &mut counts {
        *count = input.usize()?;
    }
    let [mean_leaf_size, empty_leaf_share, sah_cost] = [input.f64()?, input.f64()?, input.f64()?];
    let [
        node_count,
        leaf_count,
        max_depth,
        min_leaf_size,
        max_leaf_size,
        primitive_references,
        empty_leaf_count,
    ] = counts;
    let stats = TreeStats {
        node_count,
        leaf_count,
        max_depth,
        min_leaf_size,
        max_leaf_size,
        mean_leaf_size,
        primitive_references,
        empty_leaf_count,
        empty_leaf_share,
        sah_cost,
    };
    let tree = match input.u64()? {
        0 => {
            let nodes = input.items(|node: &[u8; 56]| BvhNode {
                bounds: aabb_at(node, 0),
                first: u32_at(node, 48),
                count: u32_at(node, 52),
            })?;
            let binary = Bvh {
                nodes,
                primitive_indices: input.u32s()?,
            };
            Tree::from_binary(binary, structure.width(), &SahCost::default())
        }
        1 => {
            let bounds = input.aabb()?;
            let nodes = input.items(|node: &[u8; 20]| KdNode {
                split: f64_at(node, 0),
                axis: u32_at(node, 8),
                first: u32_at(node, 12),
                count: u32_at(node, 16),
            })?;
            let primitive_indices = input.u32s()?;
            let depth_limit = input.usize()?;
            let leaves_at_depth_limit = input.usize()?;
            let (tag, usual, budget) = (input.u64()?, input.usize()?, input.usize()?);
            let lowered_from = match tag {
                0 => None,
                1 => Some((usual, KdBudgetExceeded::Nodes(budget))),
                2 => Some((usual, KdBudgetExceeded::References(budget))),
                _ => return Err(format!("unknown kD budget {tag}")),
            };
            Tree::Kd(KdTree {
                bounds,
                nodes,
                primitive_indices,
                limits: KdLimits {
                    depth_limit,
                    leaves_at_depth_limit,
                    lowered_from,
                },
            })
        }
        2 => {
            let bounds = input.aabb()?;
            let resolution = [input.u32()?, input.u32()?, input.u32()?];
            let limits = GridLimits {
                density_asked: input.f64()?,
                density_used: input.f64()?,
            };
            let places = input.usize()?;
            let dense = DenseCells {
                cell_start: input.u32s()?,
                references: input.u32s()?,
            };
            let cells = GridCells::with_resolution(bounds, resolution);
            if dense.cell_start.len() != cells.cell_count() + 1 {
                return Err("the grid's table does not fit its cells".to_owned());
            }
            match structure.family() {
                Family::HashedGrid => Tree::HashedGrid(Grid {
                    store: HashedCells::from_dense(&dense, cells.resolution, places),
                    cells,
                    limits,
                }),
                _ => Tree::Grid(Grid {
                    store: dense,
                    cells,
                    limits,
                }),
            }
        }
        3 => {
            let bounds = input.aabb()?;
            let nodes = input.items(|node: &[u8; 8]| OctreeNode {
                first: u32_at(node, 0),
                count: u32_at(node, 4),
            })?;
            let primitive_indices = input.u32s()?;
            let depth_limit = input.usize()?;
            let leaves_at_depth_limit = input.usize()?;
            let lowered_from = input.usize()?.checked_sub(1);
            Tree::Octree(Octree {
                bounds,
                nodes,
                primitive_indices,
                limits: OctreeLimits {
                    depth_limit,
                    leaves_at_depth_limit,
                    lowered_from,
                },
            })
        }
        other => return Err(format!("unknown tree kind {other}")),
    };
    let reasons = input.items(|reason: &[u8; 17]| {
        let (a, b) = (f64_at(reason, 1), f64_at(reason, 9));
        match reason[0] {
            1 => Some(LeafReason::SmallEnough {
                count: a as usize,
                max_leaf_size: b as usize,
            }),
            2 => Some(LeafReason::LeafCheaper {
                leaf_cost: a,
                split_cost: None,
            }),
            3 => Some(LeafReason::LeafCheaper {
                leaf_cost: a,
                split_cost: Some(b),
            }),
            4 => Some(LeafReason::Inseparable { count: a as usize }),
            5 => Some(LeafReason::DepthLimit { limit: a as usize }),
            6 => Some(LeafReason::GridCell),
            // 0, or a tag this version does not know: no reason given.
            _ => None,
        }
    })?;
    let sphere = (
        DVec3::new(input.f64()?, input.f64()?, input.f64()?),
        input.f64()?,
    );
    let drawn = input.items(|triangle: &[u8; 40]| {
        let corner = |at: usize| [0, 4, 8].map(|offset| f32_at(triangle, at + offset));
        DrawTriangle {
            corners: [corner(0), corner(12), corner(24)],
            color: [triangle[36], triangle[37], triangle[38], triangle[39]],
        }
    })?;
    if !input.rest.is_empty() {
        return Err(format!("{} bytes too many", input.rest.len()));
    }
    let facts = TreeFacts::with_leaf_reasons(&tree, reasons);
    Ok(MeshBuild {
        built: Built {
            structure,
            tree,
            facts,
        },
        stats,
        root_triangles,
        build_millis,
        sphere,
        drawn,
    })
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
