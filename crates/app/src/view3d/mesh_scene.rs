//! A 3D lesson's scene: a mesh, built in or opened from an OBJ file.

use std::sync::Arc;

use accelviz_scene::Mesh;
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
}

impl MeshScene {
    /// The mesh a lesson file names (`builtin:NAME`).
    pub fn named(name: &str) -> Result<Self, String> {
        Self::builtin(name).map(|builtin| Self::new((builtin.make)()))
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

    /// A scene showing `mesh`.
    pub fn new(mesh: Mesh) -> Self {
        let name = mesh.name.clone();
        Self {
            mesh: Arc::new(mesh),
            revision: next_revision(),
            name,
        }
    }

    /// Shows `mesh` instead.
    pub fn replace(&mut self, mesh: Mesh) {
        *self = Self::new(mesh);
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

    fn filter(&self) -> FileFilter {
        FileFilter {
            name: "OBJ mesh",
            extensions: &["obj"],
        }
    }

    fn open(&mut self, name: &str, text: &str) -> Result<(), String> {
        let mesh = accelviz_scene::obj::parse_obj(text, name).map_err(|error| error.to_string())?;
        self.replace(mesh);
        Ok(())
    }

    fn save(&self) -> Option<(String, String)> {
        None
    }

    fn reset(&mut self, text: &LessonText) {
        if let Some(view) = &text.file.view3d
            && let Ok(scene) = Self::named(&view.mesh)
        {
            *self = scene;
        }
    }
}
