//! A 3D lesson's scene: a mesh, built in or opened from an OBJ file; and a structure built
//! over it ([`MeshTree`]), what 3D lessons draw, trace and measure.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

use accelviz_core::bvh::BuildParams;
use accelviz_core::camera::bounding_sphere_of_box;
use accelviz_core::{Built, LeafOrdered, NoBuildObserver, Structure, TriangleSet};
use accelviz_scene::Mesh;
use glam::DVec3;
use web_time::Instant;

use super::aside::MeshBuild;
use super::{DrawTriangle, relative};
use crate::background::Derived;
use crate::stage::KD_BUDGET;
use accelviz_scene::builtin::{BUILTINS, Builtin};

use crate::files::FileFilter;
use crate::lesson::LessonText;
use crate::stage::SceneFile;

/// The mesh a 3D lesson shows, and a revision that changes whenever it is replaced.
pub struct MeshScene {
    /// The mesh.
    pub mesh: Arc<Mesh>,
    /// Changes with every new mesh.
    pub revision: u64,
    /// Its name: `builtin:NAME` or the file's name.
    pub name: String,
    /// A large file being read on a worker thread.
    pub loading: Option<MeshLoad>,
    /// The mesh shown before the last one (mesh, revision, name), to go back to when its
    /// build is cancelled.
    previous: Option<(Arc<Mesh>, u64, String)>,
    /// Why the last file read in the background could not be opened.
    pub problem: Option<String>,
}

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
    let started = super::aside::worker::start(
        &[
            ("job", "read".into()),
            ("name", name.into()),
            ("bytes", bytes.into()),
        ],
        &[buffer.into()],
        move |permille| progress.store(permille, Ordering::Relaxed),
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
    fn start(name: &str, text: &str) -> Option<Self> {
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
}

/// Files larger than this (bytes) are read on a worker thread where there are workers, in a
/// Web Worker in the browser.
const READ_ASIDE_ABOVE: usize = 2 << 20;

/// In the browser, structures over this many triangles or more are built in a Web Worker (on
/// the page, the bunny's 70k took about 0.2 s: the page would stop for that long).
#[cfg(target_arch = "wasm32")]
const BUILD_ASIDE_FROM: usize = 50_000;

/// Builds `structure` over `mesh` in a Web Worker, sending the tree to `sender` when it is
/// back; if the worker fails, on the page instead (slow, but the lesson gets its tree).
#[cfg(target_arch = "wasm32")]
fn build_in_worker(
    mesh: Arc<Mesh>,
    structure: Structure,
    sender: std::sync::mpsc::Sender<MeshTree>,
) -> Result<super::aside::worker::WorkerJob, String> {
    use super::aside::{flat_triangles, unpack};
    let triangles = js_sys::Float64Array::from(flat_triangles(&mesh.triangles));
    let buffer = triangles.buffer();
    super::aside::worker::start(
        &[
            ("job", "build".into()),
            ("structure", structure.name().into()),
            ("triangles", triangles.into()),
        ],
        &[buffer.into()],
        |_| {},
        move |outcome| {
            let started = Instant::now();
            let unpacked =
                outcome.and_then(|bytes| unpack(&js_sys::Uint8Array::new(&bytes).to_vec()));
            let tree = match unpacked {
                Ok(aside) => {
                    let triangles = TriangleSet::<DVec3>::from_f64(&mesh.triangles);
                    MeshTree::with_built(mesh, triangles, aside)
                }
                Err(problem) => {
                    log::error!(
                        "accelviz: the build aside failed ({problem}); building on the page"
                    );
                    MeshTree::build(mesh, structure)
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

impl MeshScene {
    /// The mesh a lesson file names (`builtin:NAME`).
    pub fn named(name: &str) -> Result<Self, String> {
        Self::builtin(name).map(|builtin| {
            let mut scene = Self::new((builtin.make)());
            // Called by the catalogue's name (the mesh's own may say more, as
            // `builtin:icosphere-4`), as the mesh menu and shared links call it.
            scene.name = name.to_owned();
            scene
        })
    }

    /// The built-in mesh `builtin:NAME`, or why there is none.
    pub fn builtin(name: &str) -> Result<&'static Builtin, String> {
        name.strip_prefix("builtin:")
            .and_then(|name| BUILTINS.iter().find(|builtin| builtin.name == name))
            .ok_or_else(|| {
                format!(
                    "'{name}' is not a built-in mesh (builtin:{})",
                    BUILTINS
                        .iter()
                        .map(|builtin| builtin.name)
                        .collect::<Vec<_>>()
                        .join(", builtin:")
                )
            })
    }

    /// The mesh a 3D lesson's file names (the teapot if it names none).
    pub fn of_lesson(text: &LessonText) -> Self {
        text.file
            .view3d
            .as_ref()
            .and_then(|view| view.mesh.as_ref())
            .and_then(|name| Self::named(name).ok())
            .unwrap_or_else(|| Self::new(accelviz_scene::builtin::teapot()))
    }

    /// A scene showing `mesh`.
    pub fn new(mesh: Mesh) -> Self {
        let name = mesh.name.clone();
        Self {
            mesh: Arc::new(mesh),
            revision: next_revision(),
            name,
            loading: None,
            previous: None,
            problem: None,
        }
    }

    /// Shows `mesh` instead (the one shown now can be gone back to, see
    /// [`MeshScene::go_back`]).
    pub fn replace(&mut self, mesh: Mesh) {
        let previous = (self.mesh.clone(), self.revision, self.name.clone());
        *self = Self::new(mesh);
        self.previous = Some(previous);
    }

    /// Shows the mesh before the last one again, with its revision (so what was built for
    /// it is still good); stops a file being read.
    pub fn go_back(&mut self) {
        self.loading = None;
        if let Some((mesh, revision, name)) = self.previous.take() {
            self.mesh = mesh;
            self.revision = revision;
            self.name = name;
        }
    }

    /// Takes in a file read on a worker thread, once it is read.
    pub fn poll(&mut self) {
        let Some(loading) = &self.loading else { return };
        let result = loading
            .result
            .lock()
            .ok()
            .and_then(|mut result| result.take());
        match result {
            None => {}
            Some(Ok(mesh)) => {
                self.replace(mesh);
                self.problem = None;
            }
            Some(Err(problem)) => {
                self.loading = None;
                self.problem = Some(problem);
            }
        }
    }
}

/// A revision no mesh had before, so a replaced mesh is never mistaken for an older one.
fn next_revision() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl SceneFile for MeshScene {
    fn noun(&self) -> &'static str {
        "mesh"
    }

    fn filter(&self) -> Option<FileFilter> {
        Some(FileFilter {
            name: "OBJ mesh",
            extensions: &["obj"],
            max_bytes: accelviz_scene::error::MAX_FILE_BYTES,
        })
    }

    fn open(&mut self, name: &str, text: &str) -> Result<(), String> {
        self.problem = None;
        if text.len() > READ_ASIDE_ABOVE
            && let Some(loading) = MeshLoad::start(name, text)
        {
            // A large file is read aside; the lesson shows how far, and can cancel it.
            self.loading = Some(loading);
            return Ok(());
        }
        let mesh = accelviz_scene::obj::parse_obj(text, name).map_err(|error| error.to_string())?;
        self.replace(mesh);
        Ok(())
    }

    fn save(&self) -> Option<(String, String)> {
        None
    }

    fn reading(&self) -> Option<f32> {
        self.loading.as_ref().map(MeshLoad::progress)
    }

    fn reset(&mut self, text: &LessonText) {
        *self = Self::of_lesson(text);
    }
}

/// The mesh's colour (sRGB).
const MESH_COLOR: [u8; 4] = [178, 188, 204, 255];

/// A structure built over a mesh, with what the view draws of the mesh.
pub struct MeshTree {
    /// The mesh.
    pub mesh: Arc<Mesh>,
    /// Its triangles as the core traces them.
    pub triangles: TriangleSet<DVec3>,
    /// The structure, what was measured of it, and the mesh as drawn.
    pub build: MeshBuild,
    /// The triangles in the tree's leaf order, made when first asked for (only the heat
    /// maps trace that many rays).
    ordered: OnceLock<LeafOrdered<TriangleSet<DVec3>>>,
}

impl MeshTree {
    /// Builds `structure` over `mesh`.
    pub fn build(mesh: Arc<Mesh>, structure: Structure) -> Self {
        let triangles = TriangleSet::<DVec3>::from_f64(&mesh.triangles);
        let built = Self::build_structure(&mesh, &triangles, structure);
        Self::with_built(mesh, triangles, built)
    }

    /// What a build does on the builder's thread: the structure over `triangles` (`mesh`'s),
    /// what is measured of it, and the mesh as drawn (the part a Web Worker does in the
    /// browser, see [`super::aside`]).
    pub fn build_structure(
        mesh: &Mesh,
        triangles: &TriangleSet<DVec3>,
        structure: Structure,
    ) -> MeshBuild {
        let params = BuildParams {
            kd_budget: KD_BUDGET,
            ..BuildParams::default()
        };
        let started = Instant::now();
        let built = Built::new(structure, triangles, &params, &mut NoBuildObserver);
        let build_millis = started.elapsed().as_secs_f64() * 1e3;
        let sphere = bounding_sphere_of_box(&mesh.bounds());
        let drawn = mesh
            .triangles
            .iter()
            .map(|triangle| DrawTriangle {
                corners: triangle.map(|corner| relative(DVec3::from_array(corner), sphere)),
                color: MESH_COLOR,
            })
            .collect();
        MeshBuild {
            stats: built.stats(0, &params.cost),
            root_triangles: built.primitives_below(0).len(),
            built,
            build_millis,
            sphere,
            drawn,
        }
    }

    /// The mesh with a structure built over its `triangles`.
    pub fn with_built(mesh: Arc<Mesh>, triangles: TriangleSet<DVec3>, build: MeshBuild) -> Self {
        Self {
            mesh,
            triangles,
            build,
            ordered: OnceLock::new(),
        }
    }

    /// The triangles in the tree's leaf order, for tracing many rays fast.
    pub fn ordered(&self) -> &LeafOrdered<TriangleSet<DVec3>> {
        self.ordered
            .get_or_init(|| self.build.built.tree.leaf_ordered(&self.triangles))
    }

    /// Takes in a file read aside if it has arrived, then asks `derived` for `structure`
    /// built over the scene's mesh (on a worker thread on the desktop when the mesh is large).
    /// Called before anything is drawn, so a read that ends becomes a build in the same frame
    /// and [`loading_ui`] never draws a frame with neither (a click on its cancel button would
    /// be lost).
    pub fn request(
        derived: &mut Derived<(u64, Structure), MeshTree>,
        scene: &mut MeshScene,
        structure: Structure,
    ) {
        scene.poll();
        let mesh = scene.mesh.clone();
        let key = (scene.revision, structure);
        #[cfg(target_arch = "wasm32")]
        if mesh.triangles.len() >= BUILD_ASIDE_FROM
            && derived.request_elsewhere(&key, |sender| {
                build_in_worker(mesh.clone(), structure, sender)
            })
        {
            return;
        }
        derived.request(&key, mesh.triangles.len(), || {
            move || MeshTree::build(mesh, structure)
        });
    }

    /// The timeline's caption for a clicked pixel's `trace` at `frame`, or `idle` before a
    /// pixel is clicked.
    pub fn caption(&self, trace: Option<&crate::trace::Trace>, frame: usize, idle: &str) -> String {
        match trace {
            None => idle.to_owned(),
            Some(trace) => trace.caption(
                frame,
                "Press step: the traversal starts by testing the root's box.",
                |step| crate::trace::describe_step(step, |node| self.node_name(node)),
            ),
        }
    }

    /// A node's name: its path from the root (`root`, `LRL`).
    pub fn node_name(&self, node: u32) -> String {
        match self.build.built.facts.path_to(node) {
            path if path.is_empty() => "the root".to_owned(),
            path => format!("node {path}"),
        }
    }
}

/// The mesh and structure choosers every 3D lesson with a mesh shows. Returns whether the
/// mesh was replaced (a traced ray then no longer fits it).
pub fn mesh_and_structure_ui(
    ui: &mut egui::Ui,
    scene: &mut MeshScene,
    structure: &mut Structure,
) -> bool {
    let mut replaced = false;
    let current = scene.name.clone();
    egui::ComboBox::from_label("mesh")
        .selected_text(current.trim_start_matches("builtin:").to_owned())
        .show_ui(ui, |ui| {
            for builtin in BUILTINS {
                let name = format!("builtin:{}", builtin.name);
                if ui
                    .selectable_label(current == name, builtin.name)
                    .on_hover_text(builtin.about)
                    .clicked()
                {
                    scene.replace((builtin.make)());
                    scene.name = name;
                    replaced = true;
                }
            }
        });
    ui.separator();
    egui::ComboBox::from_label("structure")
        .selected_text(structure.name())
        .show_ui(ui, |ui| {
            for entry in accelviz_core::CATALOGUE {
                let chosen = structure.entry().name == entry.name;
                if ui
                    .selectable_label(chosen, format!("{} {}", entry.label, entry.family.label()))
                    .on_hover_text(entry.about)
                    .clicked()
                {
                    *structure = entry.structure.with_width(structure.width());
                }
            }
        });
    crate::views::width_ui(ui, structure);
    replaced
}

/// While a large mesh is read or its structure built: a progress line with a cancel button
/// that goes back to the mesh shown before (the UI keeps drawing meanwhile). Also says why the
/// last file read aside could not be opened.
pub fn loading_ui(
    ui: &mut egui::Ui,
    scene: &mut MeshScene,
    tree: &mut Derived<(u64, Structure), MeshTree>,
) {
    if let Some(problem) = &scene.problem {
        ui.colored_label(crate::canvas::palette::MISS, problem);
    }
    let building = tree.working_for();
    let line = match (&scene.loading, building) {
        (Some(loading), _) => Some((
            format!("reading {}", loading.name),
            Some(loading.progress()),
        )),
        (None, Some(working)) => Some((
            format!(
                "building the structure over {} triangles… {:.1} s",
                scene.mesh.triangles.len(),
                working.as_secs_f64()
            ),
            None,
        )),
        (None, None) => None,
    };
    let Some((text, progress)) = line else { return };
    ui.horizontal(|ui| {
        // The button first, so it stays where it is when reading turns into building.
        if ui
            .button("cancel")
            .on_hover_text("Stop, and go back to the mesh shown before")
            .clicked()
        {
            tree.cancel();
            scene.go_back();
        }
        match progress {
            Some(progress) => ui.add(
                egui::ProgressBar::new(progress)
                    .desired_width(260.0)
                    .text(format!("{text}: {:.0} %", progress * 100.0)),
            ),
            None => {
                ui.add(egui::Spinner::new());
                ui.label(text)
            }
        };
    });
    ui.ctx().request_repaint();
}
