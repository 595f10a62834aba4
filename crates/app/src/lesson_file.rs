//! The lesson file's format: a lesson's text and scene, a RON file in `assets/lessons/`,
//! checked whole when it is read ([`LessonText::parse`]). The code that shows a lesson is
//! behind the [`Lesson`](crate::lesson::Lesson) trait.

use accelviz_scene::LoadError;
use accelviz_scene::document::{RayEntry, Scene2d, SceneDocument};
use serde::Deserialize;

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
                    accelviz_scene::builtin::named(mesh)
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
