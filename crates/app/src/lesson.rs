//! What a lesson is: the code that shows a lesson's file ([`crate::lesson_file`]), behind the
//! small [`Lesson`] trait the app draws its panels around.

use accelviz_scene::document::Scene2d;

use crate::lesson_file::LessonText;
use crate::stage::{SceneFile, Stage};

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

    /// The parts of [`inspector_ui`](Self::inspector_ui) a lecture slide can show on their
    /// own (`panels code,tree`), in the order it draws them; none: it is one part.
    fn parts(&self) -> &'static [Part] {
        &[]
    }

    /// The lesson's part of the inspector (right): statistics, tables, the tree; of its
    /// [`parts`](Self::parts) those `parts` shows.
    fn inspector_ui(&mut self, ui: &mut egui::Ui, parts: Parts<'_>);

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

    /// A ray this lesson asks another lesson to show (the trade lab's "show me"), once: the
    /// app opens that lesson and hands it over ([`show_ray`](Self::show_ray)).
    fn take_show_ray(&mut self) -> Option<ShowRay> {
        None
    }

    /// Shows the ray another lesson asked for (its mesh, structure and switches); false when
    /// this lesson shows no such rays.
    fn show_ray(&mut self, _request: &ShowRay) -> bool {
        false
    }

    /// The lesson's text.
    fn text(&self) -> &LessonText {
        &self.stage().text
    }
}

/// One ray of a measured outcome to be shown stepped in a 3D lesson: the mesh, the structure
/// and the switches it was traced with, and what the trade lab found.
#[derive(Clone, Debug)]
pub struct ShowRay {
    /// The end of the file name of the lesson that shows it (`"12-mesh-bvh.ron"`).
    pub lesson: &'static str,
    /// The mesh, as the asking lesson has it.
    pub mesh: std::sync::Arc<accelviz_scene::Mesh>,
    /// Its name (`builtin:icosphere`, or a file's).
    pub mesh_name: String,
    /// The structure the row traced.
    pub structure: accelviz_core::Structure,
    /// The ray, as the row's precision rounded it (exactly, in f64).
    pub ray: accelviz_core::Ray<glam::DVec3>,
    /// The row's switches.
    pub switches: accelviz_core::trade::Switches,
    /// The query the row answered.
    pub query: accelviz_core::Query,
    /// What the row's answer was, judged by the reference.
    pub outcome: accelviz_core::outcome::Outcome,
}

/// A part of a lesson's inspector that a lecture slide can show without the rest, so that
/// what carries the slide's point fits the screen at lecture scale without scrolling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Part {
    /// Its name in a lecture script.
    pub name: &'static str,
    /// What it holds, for the script's messages.
    pub what: &'static str,
}

/// Which [`Part`]s of an inspector to draw.
#[derive(Clone, Copy, Debug)]
pub enum Parts<'a> {
    /// All of it: the lessons' own inspector, and a slide's `panels on`.
    All,
    /// The parts a slide names (`panels code,tree`).
    Only(&'a [&'static str]),
}

impl Part {
    /// The part `name` (in a script), holding `what`.
    pub const fn new(name: &'static str, what: &'static str) -> Self {
        Self { name, what }
    }
}

impl Parts<'_> {
    /// Whether the parts are squeezed to fit the screen (a slide's named parts, shown without
    /// scrolling) rather than drawn at their natural height in a scrolled inspector.
    pub fn fit_screen(&self) -> bool {
        matches!(self, Parts::Only(_))
    }

    /// Whether `part` is drawn.
    pub fn show(&self, part: &Part) -> bool {
        match self {
            Parts::All => true,
            Parts::Only(names) => names.contains(&part.name),
        }
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
