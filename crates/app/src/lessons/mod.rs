//! The lessons, one file each, in the lecture's order, registered in [`registry`].
//!
//! A lesson is a [`LessonFile`] (title, the slide it shows, what to read and try, its scene:
//! RON in `assets/lessons/`, embedded in the binary) and the code that shows it, which draws
//! from the core: a `Recorder` passed to the one traversal, the builders, the cost curves and
//! the shared `SahCost`. No lesson re-implements an algorithm.

use accelviz_scene::LoadError;
use accelviz_scene::document::{Scene2d, SceneDocument};
use serde::Deserialize;

use crate::editor::EditableScene;
use crate::timeline::Timeline;

pub mod bounding_volumes;
pub mod build_steps;
pub mod bvh;
pub mod common;
pub mod compare;
pub mod cost_split;
pub mod kd;
pub mod near_first;
pub mod slab;
pub mod splits;
pub mod tree_diagram;
pub mod trivial;

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
    /// The scene the lesson opens with.
    pub scene: SceneDocument,
}

/// A checked lesson file.
#[derive(Clone, Debug)]
pub struct LessonText {
    /// Title, slide, explanation and things to try.
    pub file: LessonFile,
    /// The lesson's starting scene.
    pub scene: Scene2d,
}

impl LessonText {
    /// Parses a lesson file; errors name `path`, the line and the problem.
    pub fn parse(text: &str, path: &str) -> Result<Self, LoadError> {
        let file: LessonFile = ron::from_str(text).map_err(|error| {
            LoadError::at_line(
                path,
                error.span.start.line,
                format!("column {}: {}", error.span.start.col, error.code),
            )
        })?;
        let scene = Scene2d::from_document(file.scene.clone(), path)?;
        Ok(Self { file, scene })
    }
}

/// What every lesson can do; the app draws the panels around it.
pub trait Lesson {
    /// The lesson's text.
    fn text(&self) -> &LessonText;

    /// The scene, for saving and opening; `None` if the lesson has none to save.
    fn scene_mut(&mut self) -> Option<&mut EditableScene>;

    /// Puts back the scene the lesson file starts with (after edits, or a scene opened).
    fn reset_scene(&mut self) {
        let scene = self.text().scene.clone();
        if let Some(editable) = self.scene_mut() {
            editable.replace(scene);
        }
    }

    /// The animation's timeline and a caption for its current step, if the lesson animates.
    fn timeline(&mut self) -> Option<(&mut Timeline, String)> {
        None
    }

    /// The lesson's part of the inspector (right): statistics, tables, the tree.
    fn inspector_ui(&mut self, ui: &mut egui::Ui);

    /// The canvas (middle), with the lesson's controls above it.
    fn canvas_ui(&mut self, ui: &mut egui::Ui);
}

/// The lesson files, embedded, in the lecture's order.
pub const LESSON_FILES: [(&str, &str); 9] = [
    (
        "assets/lessons/01-trivial.ron",
        include_str!("../../../../assets/lessons/01-trivial.ron"),
    ),
    (
        "assets/lessons/02-bounding-volumes.ron",
        include_str!("../../../../assets/lessons/02-bounding-volumes.ron"),
    ),
    (
        "assets/lessons/03-slab-test.ron",
        include_str!("../../../../assets/lessons/03-slab-test.ron"),
    ),
    (
        "assets/lessons/04-bvh.ron",
        include_str!("../../../../assets/lessons/04-bvh.ron"),
    ),
    (
        "assets/lessons/05-kd-tree.ron",
        include_str!("../../../../assets/lessons/05-kd-tree.ron"),
    ),
    (
        "assets/lessons/06-near-first.ron",
        include_str!("../../../../assets/lessons/06-near-first.ron"),
    ),
    (
        "assets/lessons/07-middle-median-sah.ron",
        include_str!("../../../../assets/lessons/07-middle-median-sah.ron"),
    ),
    (
        "assets/lessons/08-cost-optimised-split.ron",
        include_str!("../../../../assets/lessons/08-cost-optimised-split.ron"),
    ),
    (
        "assets/lessons/09-building-is-optimisation.ron",
        include_str!("../../../../assets/lessons/09-building-is-optimisation.ron"),
    ),
];

/// Every lesson, in the lecture's order, from the embedded lesson files. A lesson file that
/// fails to parse becomes an error entry naming the file and line, not a crash.
pub fn registry() -> Vec<Result<Box<dyn Lesson>, String>> {
    registry_from(None)
}

/// Every lesson, reading each lesson file from `assets_dir` (the folder holding `lessons/`)
/// where it exists there, so a lecturer can edit a lesson's text or scene and restart the app
/// without rebuilding it; the embedded file otherwise.
pub fn registry_from(assets_dir: Option<&std::path::Path>) -> Vec<Result<Box<dyn Lesson>, String>> {
    let makers: [fn(LessonText) -> Box<dyn Lesson>; 9] = [
        |text| Box::new(trivial::TrivialLoop::new(text)),
        |text| Box::new(bounding_volumes::BoundingVolumesLesson::new(text)),
        |text| Box::new(slab::SlabLesson::new(text)),
        |text| Box::new(bvh::BvhLesson::new(text)),
        |text| Box::new(kd::KdLesson::new(text)),
        |text| Box::new(near_first::NearFirstLesson::new(text)),
        |text| Box::new(splits::SplitsLesson::new(text)),
        |text| Box::new(cost_split::CostSplitLesson::new(text)),
        |text| Box::new(build_steps::BuildStepsLesson::new(text)),
    ];
    LESSON_FILES
        .iter()
        .zip(makers)
        .map(|((path, embedded), make)| {
            let on_disk = assets_dir.and_then(|dir| {
                let file = dir.join(path.trim_start_matches("assets/"));
                file.is_file().then(|| {
                    let shown = file.display().to_string();
                    accelviz_scene::error::read_text(&shown).map(|text| (shown, text))
                })
            });
            let parsed = match on_disk {
                Some(Ok((shown, text))) => LessonText::parse(&text, &shown),
                Some(Err(error)) => Err(error),
                None => LessonText::parse(embedded, path),
            };
            parsed.map(make).map_err(|error| error.to_string())
        })
        .collect()
}

/// The explanation and things to try, for the inspector's top.
pub fn text_ui(ui: &mut egui::Ui, text: &LessonText) {
    ui.label(egui::RichText::new(format!("Slide: {}", text.file.slide)).weak());
    for paragraph in &text.file.explanation {
        ui.label(paragraph);
    }
    if !text.file.try_this.is_empty() {
        ui.label(egui::RichText::new("Try this").strong());
        for item in &text.file.try_this {
            ui.label(format!("• {item}"));
        }
    }
}

/// Shows why there is no ray (an edit put its head on its origin) instead of the lesson's
/// drawing.
pub fn ray_problem_ui(ui: &mut egui::Ui, error: &accelviz_core::RayError) {
    ui.colored_label(
        crate::canvas::palette::MISS,
        format!("No ray to trace: {error}. Drag the ray's head away from its origin."),
    );
}
