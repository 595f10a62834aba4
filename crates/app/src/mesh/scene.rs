//! A 3D lesson's scene: a mesh, built in or opened from an OBJ file (a large one read aside,
//! [`super::aside`]), and what it asks to be built over it.

use std::sync::Arc;

use accelviz_core::Structure;
use accelviz_core::trade::Precision;
use accelviz_scene::Mesh;

use super::aside::MeshLoad;
use super::tree::MeshTree;
use crate::background::Derived;
use crate::files::FileFilter;
use crate::lesson_file::LessonText;
use crate::stage::SceneFile;

/// What a tree over a lesson's mesh is made of: the mesh's revision, the structure, and the
/// precision it is built in.
pub type TreeKey = (u64, Structure, Precision);

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
    /// How the last file read in the background ended (its name, or why it could not be
    /// opened), until the app takes it for its status line.
    read_outcome: Option<Result<String, String>>,
}

/// Files larger than this (bytes) are read on a worker thread where there are workers, in a
/// Web Worker in the browser.
const READ_ASIDE_ABOVE: usize = 2 << 20;

impl MeshScene {
    /// Takes in a file read aside if it has arrived, then asks `derived` for `structure`
    /// built over the scene's mesh (on a worker thread on the desktop when the mesh is large).
    /// Called before anything is drawn, so a read that ends becomes a build in the same frame
    /// and [`loading_ui`](super::loading_ui) never draws a frame with neither (a click on its cancel button would
    /// be lost).
    pub fn request_tree(&mut self, derived: &mut Derived<TreeKey, MeshTree>, structure: Structure) {
        self.request_tree_in(derived, structure, Precision::F64);
    }

    /// [`request_tree`](Self::request_tree) in `precision` (f32: as a trade row builds it).
    pub fn request_tree_in(
        &mut self,
        derived: &mut Derived<TreeKey, MeshTree>,
        structure: Structure,
        precision: Precision,
    ) {
        self.poll();
        let mesh = self.mesh.clone();
        let key = (self.revision, structure, precision);
        // A Web Worker builds in f64 (an f32 tree, the trade lab's rows', is asked for on
        // its meshes, small enough for the page).
        #[cfg(target_arch = "wasm32")]
        if precision == Precision::F64
            && mesh.triangles.len() >= super::aside::BUILD_ASIDE_FROM
            && derived.request_elsewhere(&key, |sender| {
                super::aside::build_in_worker(mesh.clone(), structure, sender)
            })
        {
            return;
        }
        derived.request(&key, mesh.triangles.len(), || {
            move || MeshTree::build_in(mesh, structure, precision)
        });
    }

    /// The mesh a lesson file names (`builtin:NAME`).
    pub fn named(name: &str) -> Result<Self, String> {
        accelviz_scene::builtin::named(name).map(|builtin| {
            let mut scene = Self::new((builtin.make)());
            // Called by the catalogue's name (the mesh's own may say more, as
            // `builtin:icosphere-4`), as the mesh menu and shared links call it.
            scene.name = name.to_owned();
            scene
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
            read_outcome: None,
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
        match loading.take_result() {
            None => {}
            Some(Ok(mesh)) => {
                let name = loading.name.clone();
                self.replace(mesh);
                self.read_outcome = Some(Ok(name));
            }
            Some(Err(problem)) => {
                self.loading = None;
                self.read_outcome = Some(Err(problem));
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
        self.read_outcome = None;
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

    fn can_save(&self) -> bool {
        false
    }

    fn reading(&self) -> Option<f32> {
        self.loading.as_ref().map(MeshLoad::progress)
    }

    fn take_read_outcome(&mut self) -> Option<Result<String, String>> {
        self.read_outcome.take()
    }

    fn reset(&mut self, text: &LessonText) {
        *self = Self::of_lesson(text);
    }
}
