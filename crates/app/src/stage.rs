//! What every lesson has: its text, its editable scene, its timeline, and the structures it
//! builds over the scene ([`SceneTree`]), made by the core's catalogue with the app's budget.

use std::sync::Arc;

use accelviz_core::params::{BuildParams, GridParams, KdBudget};
use accelviz_core::{BuildObserver, Built, NoBuildObserver, ShapeSet, Structure, TreeStats};
use accelviz_scene::document::{Scene2d, SceneSettings};
use glam::DVec2;
use web_time::Instant;

use crate::background::Derived;
use crate::editor::{EditableScene, Editing, SceneOrigin};
use crate::files::FileFilter;
use crate::lesson_file::LessonText;
use crate::timeline::Timeline;

/// How large a kD-tree a lesson builds: enough for every scene the generator makes to be cut
/// as its rule wants, small enough to draw in a frame and to hold a few at once. A build that
/// would pass it is made shallower, and the lesson says so (`KdLimits`).
pub const KD_BUDGET: KdBudget = KdBudget {
    max_nodes: Some(200_000),
    max_references: Some(1_000_000),
};

/// The shared state of a lesson: its text, its timeline, and the scene it shows (`S`: a 2D
/// [`EditableScene`], or a 3D mesh view). The app sees every lesson's scene as a
/// [`SceneFile`] (`Stage<dyn SceneFile>`: the scene is the last field, so a lesson's own
/// `&Stage<EditableScene>` turns into one).
pub struct Stage<S: ?Sized = EditableScene> {
    /// The lesson's text and starting scene.
    pub text: LessonText,
    /// The animation's position.
    pub timeline: Timeline,
    /// Why the lesson file on disk was not used (the built-in copy is shown instead).
    pub notice: Option<String>,
    /// The scene being looked at and edited.
    pub scene: S,
}

/// What the app's top bar does with a lesson's scene: open a file into it, save it, put the
/// lesson's own back.
pub trait SceneFile {
    /// What the scene is called in the top bar's buttons and messages ("scene", "mesh").
    fn noun(&self) -> &'static str;

    /// The files it opens, for the open dialog's filter; `None` if it opens none.
    fn filter(&self) -> Option<FileFilter>;

    /// Replaces the scene with the file `name` holding `text`; on a bad file the scene stays
    /// and the error names the file, the line and the problem.
    fn open(&mut self, name: &str, text: &str) -> Result<(), String>;

    /// The scene as a file to save (suggested name, content); `None` if it cannot be saved.
    fn save(&self) -> Option<(String, String)>;

    /// Whether [`save`](Self::save) makes a file, without making it (the top bar asks every
    /// frame: writing 100,000 shapes as RON takes a tenth of a second).
    fn can_save(&self) -> bool;

    /// Puts back the scene the lesson's file starts with.
    fn reset(&mut self, text: &LessonText);

    /// How far a file being read aside has got (0 to 1), while one is.
    fn reading(&self) -> Option<f32> {
        None
    }

    /// How a file read aside ended, once: `Ok(name)` opened, or why it could not be. The app
    /// says it in its one status line (as for a file opened at once).
    fn take_read_outcome(&mut self) -> Option<Result<String, String>> {
        None
    }

    /// The 2D scene, for what the app does with 2D scenes only (placing a generated ray).
    fn as_flat(&mut self) -> Option<&mut EditableScene> {
        None
    }

    /// The 2D scene, to read.
    fn flat(&self) -> Option<&EditableScene> {
        None
    }
}

impl SceneFile for EditableScene {
    fn noun(&self) -> &'static str {
        "scene"
    }

    fn filter(&self) -> Option<FileFilter> {
        Some(FileFilter {
            name: "accelviz scene",
            extensions: &["ron"],
            max_bytes: accelviz_scene::document::MAX_DOCUMENT_BYTES as u64,
        })
    }

    fn open(&mut self, name: &str, text: &str) -> Result<(), String> {
        let scene = Scene2d::parse(text, name).map_err(|error| error.to_string())?;
        self.replace(scene);
        self.origin = SceneOrigin::File;
        Ok(())
    }

    fn save(&self) -> Option<(String, String)> {
        Some(("scene.ron".to_owned(), self.scene.to_ron()))
    }

    fn can_save(&self) -> bool {
        true
    }

    fn reset(&mut self, text: &LessonText) {
        self.replace(text.scene.clone());
    }

    fn as_flat(&mut self) -> Option<&mut EditableScene> {
        Some(self)
    }

    fn flat(&self) -> Option<&EditableScene> {
        Some(self)
    }
}

impl Stage {
    /// A lesson's stage with its file's scene and these editing rights.
    pub fn new(text: LessonText, editing: Editing) -> Self {
        let scene = EditableScene::new(text.scene.clone(), editing);
        Self::with_scene(text, scene)
    }

    /// The scene's settings.
    pub fn settings(&self) -> &SceneSettings {
        &self.scene.scene.settings
    }

    /// Shows the lesson file's preset `index` (its scene, under its name) from the first step;
    /// false when there is none.
    pub fn show_preset(&mut self, index: usize) -> bool {
        let Some(preset) = self.text.file.presets.get(index) else {
            return false;
        };
        let Ok(scene) = Scene2d::from_document(preset.scene.clone(), &preset.name) else {
            return false;
        };
        self.scene.replace(scene);
        self.timeline.rewind();
        true
    }

    /// Shows the preset called `name` (a lecture script's `show NAME`).
    pub fn show_named_preset(&mut self, name: &str) -> bool {
        let presets = &self.text.file.presets;
        presets
            .iter()
            .position(|preset| preset.name == name)
            .is_some_and(|index| self.show_preset(index))
    }

    /// The presets' names.
    pub fn preset_names(&self) -> Vec<String> {
        let presets = &self.text.file.presets;
        presets.iter().map(|preset| preset.name.clone()).collect()
    }

    /// A button for each preset (its description on hover), after `label`; a click shows it.
    pub fn presets_ui(&mut self, ui: &mut egui::Ui, label: &str) {
        let presets: Vec<(String, String)> = (self.text.file.presets.iter())
            .map(|preset| (preset.name.clone(), preset.about.clone()))
            .collect();
        if presets.is_empty() {
            return;
        }
        ui.horizontal_wrapped(|ui| {
            if !label.is_empty() {
                ui.label(label);
            }
            for (index, (name, about)) in presets.iter().enumerate() {
                if ui.button(name).on_hover_text(about).clicked() {
                    self.show_preset(index);
                }
            }
        });
    }
}

impl<S> Stage<S> {
    /// A stage showing `scene`.
    pub fn with_scene(text: LessonText, scene: S) -> Self {
        Self {
            text,
            timeline: Timeline::default(),
            notice: None,
            scene,
        }
    }
}

impl<S: SceneFile + ?Sized> Stage<S> {
    /// Puts back the scene the lesson file starts with, and rewinds.
    pub fn reset_scene(&mut self) {
        self.scene.reset(&self.text);
        self.timeline.rewind();
    }
}

/// The parameters every builder gets from a scene's settings, with the app's kD budget.
pub fn build_params(settings: &SceneSettings) -> BuildParams {
    BuildParams {
        max_leaf_size: settings.max_leaf_size,
        cost: settings.cost(),
        kd_budget: KD_BUDGET,
        grid: GridParams::default(),
    }
}

/// The structure a lesson builds with its settings: the binned SAH takes the scene's bins
/// (a grid keeps its density, an octree its leaf size).
pub fn with_settings(structure: Structure, settings: &SceneSettings) -> Structure {
    match structure {
        Structure::BvhSahBinned { .. } => {
            structure.with_parameter(settings.bins.clamp(2, u16::MAX as usize) as u16)
        }
        other => other,
    }
}

/// A structure built over the scene's shapes as they were then: what a lesson draws, traces
/// and measures. The shapes are kept with it, so a tree still being replaced by a newer build
/// is drawn with the shapes it was built over.
pub struct SceneTree {
    /// The shapes it was built over.
    pub shapes: Arc<ShapeSet<DVec2>>,
    /// The settings it was built with.
    pub settings: SceneSettings,
    /// The tree and its facts.
    pub built: Built<DVec2>,
    /// Its statistics under the settings' cost model.
    pub stats: TreeStats,
    /// How long the build took.
    pub build_millis: f64,
    /// A number no other tree of the process has: what is drawn of it can be kept between
    /// frames under it ([`crate::canvas::Canvas::cached_batch`]).
    pub id: u64,
}

/// A new [`SceneTree::id`].
pub fn next_tree_id() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl SceneTree {
    /// Builds `structure` over `shapes`.
    pub fn build(
        structure: Structure,
        shapes: Arc<ShapeSet<DVec2>>,
        settings: SceneSettings,
    ) -> Self {
        Self::build_observed(structure, shapes, settings, &mut NoBuildObserver)
    }

    /// Builds `structure` over `shapes`, telling `observer` about each node.
    pub fn build_observed(
        structure: Structure,
        shapes: Arc<ShapeSet<DVec2>>,
        settings: SceneSettings,
        observer: &mut impl BuildObserver,
    ) -> Self {
        Self::build_with(structure, shapes, settings, GridParams::default(), observer)
    }

    /// Builds `structure` over `shapes` with a grid's cells and table as `grid` chooses (the
    /// grid lessons' sliders), telling `observer` about each node.
    pub fn build_with(
        structure: Structure,
        shapes: Arc<ShapeSet<DVec2>>,
        settings: SceneSettings,
        grid: GridParams,
        observer: &mut impl BuildObserver,
    ) -> Self {
        let structure = with_settings(structure, &settings);
        let started = Instant::now();
        let built = Built::new(
            structure,
            shapes.as_ref(),
            &BuildParams {
                grid,
                ..build_params(&settings)
            },
            observer,
        );
        let build_millis = started.elapsed().as_secs_f64() * 1e3;
        let stats = built.stats(0, &settings.cost());
        Self {
            shapes,
            settings,
            built,
            stats,
            build_millis,
            id: next_tree_id(),
        }
    }

    /// The kD build's limits, when a limit changed the tree: what the lesson must say.
    pub fn limits_note(&self) -> Option<String> {
        let limits = self.built.tree.kd_limits()?;
        limits
            .reached()
            .then(|| format!("{}: {limits}", self.built.structure.title()))
    }
}

/// Asks `derived` for what `make` builds over the scene's shapes and settings, for the shapes'
/// revision and the lesson's `choice` (a structure, a family): the shapes are copied only when
/// a new build is wanted, which runs on a worker thread if the scene is large.
pub fn request_over_shapes<C, T, F>(
    derived: &mut Derived<(u64, C), T>,
    scene: &EditableScene,
    choice: C,
    make: F,
) where
    C: Clone + PartialEq + Send + 'static,
    T: Send + Sync + 'static,
    F: FnOnce(Arc<ShapeSet<DVec2>>, SceneSettings) -> T + Send + 'static,
{
    derived.request(
        &(scene.shapes_revision, choice),
        scene.scene.shapes.shapes.len(),
        || {
            let shapes = Arc::new(scene.scene.shapes.clone());
            let settings = scene.scene.settings;
            move || make(shapes, settings)
        },
    );
}

/// Asks `derived` for `structure` built over the scene (see [`request_over_shapes`]).
pub fn request_tree(
    derived: &mut Derived<(u64, Structure), SceneTree>,
    scene: &EditableScene,
    structure: Structure,
) {
    request_over_shapes(derived, scene, structure, move |shapes, settings| {
        SceneTree::build(structure, shapes, settings)
    });
}
