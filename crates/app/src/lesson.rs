//! What a lesson is: its text and scene (a RON file in `assets/lessons/`) and the code that
//! shows it, behind the small [`Lesson`] trait the app draws its panels around.

use accelviz_scene::LoadError;
use accelviz_scene::document::{RayEntry, Scene2d, SceneDocument};
use serde::Deserialize;

use crate::stage::{SceneFile, Stage};

/// A lesson's text and scene, as written in `assets/lessons/NAME.ron`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LessonFile {
    /// Shown in the lesson list and above the canvas.
    pub title: String,
    /// The lecture slide(s) the lesson brings to life.
    pub slide: String,
    /// What to read: short paragraphs.
    pub explanation: Vec<String>,
    /// What to try, one action per entry.
    #[serde(default)]
    pub try_this: Vec<String>,
    /// Rays the lesson can switch to by name, besides the scene's own (the slide's r1, r2).
    #[serde(default)]
    pub named_rays: Vec<NamedRay>,
    /// Scenes the lesson offers by name, besides its own.
    #[serde(default)]
    pub presets: Vec<Preset>,
    /// The 2D scene the lesson opens with (2D lessons).
    #[serde(default)]
    pub scene: Option<SceneDocument>,
    /// The structure a 2D lesson builds first, by its catalogue name (`bvh4:sah-sweep`); a 3D
    /// lesson names it in `view3d`.
    #[serde(default)]
    pub structure: Option<String>,
    /// What a 3D lesson opens with: its mesh and structure (3D lessons).
    #[serde(default)]
    pub view3d: Option<View3dFile>,
}

/// What a 3D lesson opens with.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct View3dFile {
    /// The mesh: `builtin:NAME`.
    #[serde(default)]
    pub mesh: Option<String>,
    /// The structure, by its catalogue name (`bvh:sah-binned`).
    #[serde(default)]
    pub structure: Option<String>,
    /// A box and a ray (the 3D slab test).
    #[serde(default)]
    pub slab: Option<SlabFile>,
}

/// A box and a ray, as a 3D lesson file gives them.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlabFile {
    /// The box's lower corner.
    pub min: (f64, f64, f64),
    /// Its upper corner.
    pub max: (f64, f64, f64),
    /// Where the ray starts.
    pub origin: (f64, f64, f64),
    /// A point it passes at t = 1.
    pub toward: (f64, f64, f64),
}

/// A scene a lesson offers by name.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Preset {
    /// Its name, on its button.
    pub name: String,
    /// What it shows, as the button's hint.
    pub about: String,
    /// The scene.
    pub scene: SceneDocument,
}

/// A ray with a name, as a slide labels it.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NamedRay {
    /// Its name: "r2".
    pub name: String,
    /// Where it starts and where it heads.
    pub ray: RayEntry,
}

/// A checked lesson file.
#[derive(Clone, Debug)]
pub struct LessonText {
    /// Title, slide, explanation and things to try.
    pub file: LessonFile,
    /// A 2D lesson's starting scene (a 3D lesson's is empty: its mesh is in `file.view3d`).
    pub scene: Scene2d,
}

impl LessonText {
    /// Parses a lesson file; errors name `path`, the line and the problem.
    pub fn parse(text: &str, path: &str) -> Result<Self, LoadError> {
        // `scene: (…)` and `view3d: (…)` are written without `Some(…)`.
        let options = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
        let file: LessonFile = options.from_str(text).map_err(|error| {
            LoadError::at_line(
                path,
                error.span.start.line,
                format!("column {}: {}", error.span.start.col, error.code),
            )
        })?;
        let scene = match (&file.scene, &file.view3d) {
            (Some(document), None) => Scene2d::from_document(document.clone(), path)?,
            (None, Some(view)) => {
                if let Some(mesh) = &view.mesh {
                    crate::view3d::mesh_scene::MeshScene::builtin(mesh)
                        .map_err(|problem| LoadError::in_file(path, problem))?;
                }
                if let Some(structure) = &view.structure {
                    accelviz_core::Structure::parse(structure)
                        .map_err(|problem| LoadError::in_file(path, problem.to_string()))?;
                }
                if let Some(slab) = &view.slab {
                    let numbers = [slab.min, slab.max, slab.origin, slab.toward]
                        .into_iter()
                        .flat_map(|(x, y, z)| [x, y, z]);
                    if numbers.clone().any(|x| !x.is_finite())
                        || [
                            slab.min.0 > slab.max.0,
                            slab.min.1 > slab.max.1,
                            slab.min.2 > slab.max.2,
                        ]
                        .into_iter()
                        .any(|inverted| inverted)
                    {
                        return Err(LoadError::in_file(
                            path,
                            "the slab box needs finite corners with min <= max, and a finite ray",
                        ));
                    }
                }
                // Never shown: a 3D lesson's scene is its mesh.
                Scene2d {
                    shapes: Default::default(),
                    ray_origin: glam::DVec2::ZERO,
                    ray_toward: glam::DVec2::X,
                    settings: Default::default(),
                    generator: None,
                }
            }
            _ => {
                return Err(LoadError::in_file(
                    path,
                    "a lesson has either a 2D `scene` or a 3D `view3d`, not both or neither",
                ));
            }
        };
        for preset in &file.presets {
            Scene2d::from_document(preset.scene.clone(), path)?;
        }
        if let Some(structure) = &file.structure {
            accelviz_core::Structure::parse(structure)
                .map_err(|problem| LoadError::in_file(path, problem.to_string()))?;
        }
        Ok(Self { file, scene })
    }

    /// The lesson's first structure, as its file names it (a 3D lesson in `view3d`).
    pub fn structure(&self) -> Option<accelviz_core::Structure> {
        let name = match &self.file.view3d {
            Some(view) => view.structure.as_ref()?,
            None => self.file.structure.as_ref()?,
        };
        accelviz_core::Structure::parse(name).ok()
    }

    /// The lesson's title.
    pub fn title(&self) -> &str {
        &self.file.title
    }
}

/// What every lesson can do; the app draws the panels around it. The shared state (text,
/// scene, timeline) is the lesson's [`Stage`]; what it derives from the scene it keeps itself.
pub trait Lesson {
    /// The shared state.
    fn stage(&self) -> &Stage<dyn SceneFile>;

    /// The shared state, to change.
    fn stage_mut(&mut self) -> &mut Stage<dyn SceneFile>;

    /// Brings what the lesson derives from its scene up to date. Called once a frame, before
    /// anything is drawn, so every panel shows the same state.
    fn update(&mut self) {}

    /// What the current step of the animation is, in words; `None` if the lesson does not
    /// animate (then no timeline is shown).
    fn caption(&self) -> Option<String> {
        None
    }

    /// Shows the lesson file's named ray or preset `name` (a lecture script's `show NAME`);
    /// false when the lesson has none by that name.
    fn show_named(&mut self, _name: &str) -> bool {
        false
    }

    /// The names [`show_named`](Self::show_named) takes.
    fn named(&self) -> Vec<String> {
        Vec::new()
    }

    /// What a shared link keeps of this lesson beyond its scene and step: its choices
    /// (structure, camera, mesh), as key and value ([`crate::share`]).
    fn share(&self) -> Vec<(String, String)> {
        Vec::new()
    }

    /// Restores one of [`share`](Self::share)'s pairs; the error says what was wrong.
    fn restore(&mut self, key: &str, _value: &str) -> Result<(), String> {
        Err(format!("this lesson keeps no '{key}'"))
    }

    /// The lesson's part of the inspector (right): statistics, tables, the tree.
    fn inspector_ui(&mut self, ui: &mut egui::Ui);

    /// The canvas (middle), with the lesson's controls above it.
    fn canvas_ui(&mut self, ui: &mut egui::Ui);

    /// Where a generated scene's ray goes (origin, toward), so that it shows what the lesson
    /// is about; `None` keeps the generator's own placement.
    fn place_generated_ray(&self, _scene: &Scene2d) -> Option<(glam::DVec2, glam::DVec2)> {
        None
    }

    /// How long a newer build of what the lesson shows has been running on a worker thread,
    /// if one is (what is shown meanwhile is the last build).
    fn building(&self) -> Option<std::time::Duration> {
        None
    }

    /// A file the lesson made to be saved (a PNG of its view), once: the app saves it
    /// through the system's dialog, or as a download in the browser.
    fn take_export(&mut self) -> Option<crate::view3d::Export> {
        None
    }

    /// The lesson's text.
    fn text(&self) -> &LessonText {
        &self.stage().text
    }
}

/// Implements [`Lesson::stage`], [`Lesson::stage_mut`] and [`Lesson::building`] for a lesson
/// whose `stage` field is its [`Stage`] and whose named fields are the [`Derived`] values it
/// builds (`staged!(tree, traces)`).
///
/// [`Derived`]: crate::background::Derived
#[macro_export]
macro_rules! staged {
    () => {
        fn stage(&self) -> &$crate::stage::Stage<dyn $crate::stage::SceneFile> {
            &self.stage
        }

        fn stage_mut(&mut self) -> &mut $crate::stage::Stage<dyn $crate::stage::SceneFile> {
            &mut self.stage
        }
    };
    ($($derived:ident),+) => {
        $crate::staged!();

        fn building(&self) -> Option<std::time::Duration> {
            [$(self.$derived.working_for()),+].into_iter().flatten().max()
        }
    };
}
