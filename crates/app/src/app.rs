//! The app's frame: lessons on the left, the canvas in the middle, the inspector on the right,
//! the timeline at the bottom, and a top bar to open and save scenes.

use egui::{RichText, Ui};

use crate::files::{
    DialogOutcome, FileChannel, FileEvent, FileFilter, FilePanel, PanelAction, PanelMode,
};
use crate::lecture::script::LectureScript;
use crate::lecture::{Lecture, Theme};
use crate::lesson::{Lesson, Parts};
use crate::position::Position;
use crate::registry::{self, BrokenLesson};

/// The inspector's widths: it may be widened by hand, but content never pushes it.
pub(crate) const INSPECTOR_WIDTH: (f32, f32, f32) = (280.0, 400.0, 560.0);

/// The side panels' widths for a window `width` points wide: their usual sizes on a large
/// window, and shares of a small one (or of a large one zoomed in, as Ctrl + does), so the
/// canvas keeps at least half the width and the layout stays whole.
/// Returns (lesson list, inspector default, inspector min, inspector max).
fn panel_widths(width: f32) -> (f32, f32, f32, f32) {
    let list = (width * 0.17).clamp(120.0, 210.0);
    let inspector = (width * 0.29).clamp(180.0, INSPECTOR_WIDTH.1);
    let least = INSPECTOR_WIDTH.0.min(inspector);
    // A width the user dragged to is kept, within a share of the window.
    let most = (width * 0.38).clamp(least, INSPECTOR_WIDTH.2);
    (list, inspector, least, most)
}

/// The inspector: a panel at the right of the window, resizable by hand, holding `contents`
/// ([`scrolled_panel`]: its width is its own, never its content's). The test harnesses draw
/// their inspector with it too.
pub fn inspector_panel<R>(
    ui: &mut Ui,
    contents: impl FnOnce(&mut Ui) -> R,
) -> egui::InnerResponse<egui::scroll_area::ScrollAreaOutput<R>> {
    let (_, default, least, most) = panel_widths(ui.ctx().content_rect().width());
    let panel = egui::Panel::right("inspector")
        .resizable(true)
        .default_size(default)
        .min_size(least)
        .max_size(most);
    scrolled_panel(panel, ui, contents)
}

/// `panel` holding `contents` in a scroll area that fills it. The panel's width is its own
/// (its default, or the width the user dragged it to), never its content's: what is wider
/// scrolls sideways and what is longer scrolls down. A panel that grew with its content kept
/// the width of the widest thing it had ever shown (a long name measured once), and a lesson's
/// layout then depended on what came before it.
pub fn scrolled_panel<R>(
    panel: egui::Panel,
    ui: &mut Ui,
    contents: impl FnOnce(&mut Ui) -> R,
) -> egui::InnerResponse<egui::scroll_area::ScrollAreaOutput<R>> {
    panel.show(ui, |ui| {
        egui::ScrollArea::both()
            .auto_shrink([false, false])
            .show(ui, contents)
    })
}

/// The accelviz app.
pub struct AccelvizApp {
    pub(crate) lessons: Vec<Result<Box<dyn Lesson>, BrokenLesson>>,
    /// The lesson shown.
    pub selected: usize,
    /// The last message for the user: text and whether it reports a problem.
    pub status: Option<(String, bool)>,
    files: FileChannel,
    /// The in-app file panel, when open.
    pub file_panel: Option<FilePanel>,
    /// What was last reported to the log (lesson or quiz, and step), so each change is logged
    /// once.
    reported: Option<String>,
    /// Where the last frame put the inspector and the canvas's panel.
    pub last_layout: FrameLayout,
    /// What the window shows: the lessons or the quiz.
    pub mode: Mode,
    /// The quiz (read from where it was saved the first time it is shown).
    pub quiz: crate::quiz::QuizMode,
    /// The lecture being given, in lecture mode.
    pub lecture: Option<Lecture>,
    /// The lecture script lecture mode starts with (the built-in one, or `assets/lecture.txt`
    /// on disk), or why the one on disk could not be read.
    pub script: Result<LectureScript, String>,
    /// The colours.
    pub theme: Theme,
    /// What the style was last set to (theme, lecture text sizes), so it is set on change.
    styled: Option<(Theme, bool)>,
    /// The step a shared view opens at, once its lesson's animation knows its steps.
    pub(crate) pending_step: Option<usize>,
    /// The share window, when open: the text typed to open a shared view.
    pub share_window: Option<String>,
}

/// What the window shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mode {
    /// The selected lesson.
    #[default]
    Lessons,
    /// The quiz.
    Quiz,
    /// A lecture: the script's slides, full screen, driven by a clicker.
    Lecture,
}

/// Where a frame put its panels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameLayout {
    /// The inspector (right).
    pub inspector: egui::Rect,
    /// The middle, where the lesson draws its canvas.
    pub canvas: egui::Rect,
    /// The window's width (points) in that frame.
    pub window_width: Option<f32>,
    /// The inspector's width the user dragged it to, kept across window resizes.
    pub inspector_choice: Option<f32>,
    /// How much taller than the screen a lecture slide's panels were (points; 0 or less:
    /// they fit without scrolling).
    pub lecture_panels_overflow: f32,
    /// Whether the lecture bar cut where the lecture stands (the slide and step counters; the
    /// title after them may be cut).
    pub lecture_place_cut: bool,
}

impl Default for AccelvizApp {
    fn default() -> Self {
        Self::new()
    }
}

/// Each lesson's inspector parts, in the lessons' order (a broken lesson has none).
fn parts_of(
    lessons: &[Result<Box<dyn Lesson>, BrokenLesson>],
) -> Vec<&'static [crate::lesson::Part]> {
    lessons
        .iter()
        .map(|lesson| lesson.as_ref().map_or(&[][..], |lesson| lesson.parts()))
        .collect()
}

impl AccelvizApp {
    /// The app on its default lesson, the lecture's first, with the embedded lesson files.
    pub fn new() -> Self {
        Self::from_lessons(registry::registry())
    }

    /// The app with lesson files read from `assets_dir` where they exist there (see
    /// [`registry::registry_from`]).
    pub fn with_assets(assets_dir: &std::path::Path) -> Self {
        let mut app = Self::from_lessons(registry::registry_from(Some(assets_dir)));
        // The lecture script: assets/lecture.txt where it exists (a lecturer edits it in
        // place), else the built-in one.
        let on_disk = assets_dir.join("lecture.txt");
        if on_disk.is_file() {
            let shown = on_disk.display().to_string();
            // Every bad line is skipped and reported; a file with no slide left (or none to
            // read) leaves the built-in lecture, with the reason shown in lecture mode.
            let problem = match accelviz_scene::error::read_text(&shown) {
                Ok(text) => match LectureScript::parse(&text, &shown, &app.lesson_parts()) {
                    Ok(script) => {
                        app.script = Ok(script);
                        None
                    }
                    Err(error) => Some(error),
                },
                Err(error) => Some(crate::lecture::script::ScriptError {
                    path: shown.clone(),
                    line: 0,
                    problem: error.to_string(),
                }),
            };
            if let (Some(problem), Ok(script)) = (problem, &mut app.script) {
                script.problems.push(crate::lecture::script::ScriptError {
                    problem: format!(
                        "{} (the built-in lecture is given instead)",
                        problem.problem
                    ),
                    ..problem
                });
            }
        }
        app
    }

    /// The app with these lessons.
    pub fn from_lessons(lessons: Vec<Result<Box<dyn Lesson>, BrokenLesson>>) -> Self {
        let lesson_parts = parts_of(&lessons);
        Self {
            lessons,
            selected: 0,
            status: None,
            files: FileChannel::default(),
            file_panel: None,
            reported: None,
            last_layout: FrameLayout {
                inspector: egui::Rect::NOTHING,
                canvas: egui::Rect::NOTHING,
                window_width: None,
                inspector_choice: None,
                lecture_panels_overflow: 0.0,
                lecture_place_cut: false,
            },
            mode: Mode::Lessons,
            quiz: crate::quiz::QuizMode::new(),
            lecture: None,
            script: LectureScript::default_for(&lesson_parts).map_err(|error| error.to_string()),
            theme: Theme::Dark,
            styled: None,
            pending_step: None,
            share_window: None,
        }
    }

    /// How many lessons there are.
    pub fn lesson_count(&self) -> usize {
        self.lessons.len()
    }

    /// The selected lesson.
    pub fn lesson_mut(&mut self) -> Option<&mut Box<dyn Lesson>> {
        self.lessons.get_mut(self.selected)?.as_mut().ok()
    }

    /// The selected lesson, to read.
    pub fn lesson(&self) -> Option<&dyn Lesson> {
        self.lessons
            .get(self.selected)?
            .as_ref()
            .ok()
            .map(|lesson| lesson.as_ref())
    }

    /// Lesson titles in order.
    pub fn titles(&self) -> Vec<String> {
        self.lessons
            .iter()
            .map(|lesson| match lesson {
                Ok(lesson) => lesson.text().title().to_owned(),
                Err(broken) => broken.title.clone(),
            })
            .collect()
    }

    /// Everything the app draws in a frame.
    pub fn contents_ui(&mut self, ui: &mut Ui) {
        self.selected = self.selected.min(self.lessons.len().saturating_sub(1));
        self.apply_style(ui.ctx());
        self.fit_lecture_zoom(ui.ctx());
        match self.mode {
            Mode::Quiz => self.quiz_ui(ui),
            Mode::Lecture if self.lecture.is_some() => self.lecture_ui(ui),
            Mode::Lecture | Mode::Lessons => self.lessons_ui(ui),
        }
    }

    /// The lessons mode: the lesson list, the lesson's canvas and inspector, its timeline.
    fn lessons_ui(&mut self, ui: &mut Ui) {
        self.take_export();
        self.take_show_ray();
        self.take_dropped_files(ui.ctx());
        self.apply_file_events();
        if let Some(lesson) = self.lesson_mut() {
            // A freshly generated scene gets the ray the lesson wants for it.
            let generated = lesson
                .stage_mut()
                .scene
                .as_flat()
                .and_then(|scene| scene.take_generated().then(|| scene.scene.clone()));
            if let Some(generated) = generated
                && let Some((origin, toward)) = lesson.place_generated_ray(&generated)
                && let Some(scene) = lesson.stage_mut().scene.as_flat()
            {
                scene.scene.ray_origin = origin;
                scene.scene.ray_toward = toward;
                scene.touch_ray();
            }
            // Derived state first, so every panel draws the same step.
            lesson.update();
        }
        self.apply_pending_step();
        self.take_read_outcome();
        egui::Panel::top("top bar").show(ui, |ui| self.top_bar_ui(ui));
        let caption = self.lesson().and_then(|lesson| lesson.caption());
        if let (Some(caption), Some(lesson)) = (caption, self.lesson_mut()) {
            let timeline = &mut lesson.stage_mut().timeline;
            egui::Panel::bottom("timeline").show(ui, |ui| {
                ui.add_space(4.0);
                timeline.ui(ui, &caption);
                ui.add_space(2.0);
            });
        }
        self.side_panels_ui(ui, |app, ui| app.lesson_inspector_ui(ui));
        self.lesson_canvas_ui(ui);
        self.file_panel_ui(ui.ctx());
        self.share_window_ui(ui.ctx());
        self.report_position(ui);
    }

    /// The lesson list on the left and the inspector on the right, at their shares of the
    /// window (every mode but lecture mode has them); `inspector` fills the inspector.
    fn side_panels_ui(&mut self, ui: &mut Ui, inspector: impl FnOnce(&mut Self, &mut Ui)) {
        let window = ui.ctx().content_rect().width();
        let (list_width, inspector_width, inspector_min, inspector_max) = panel_widths(window);
        // egui keeps a panel's width in points: a window made small and large again would
        // keep the small window's inspector. On a resize it takes the width the user chose
        // (or its default) again, within the new window's range.
        // The key egui keeps the panel's state under (its `Panel::id`).
        let inspector_id = ui.scope_id().with_salt(egui::IdSalt::new("inspector"));
        let resized = self
            .last_layout
            .window_width
            .is_some_and(|before| (before - window).abs() > 0.5);
        if resized
            && let Some(mut state) =
                egui::containers::panel::PanelState::load(ui.ctx(), inspector_id)
        {
            let wanted = self
                .last_layout
                .inspector_choice
                .unwrap_or(inspector_width)
                .clamp(inspector_min, inspector_max);
            state.outer_rect.min.x = state.outer_rect.max.x - wanted;
            ui.ctx()
                .data_mut(|data| data.insert_persisted(inspector_id, state));
        }
        let inspector_before = self.last_layout.inspector.width();
        egui::Panel::left("lessons")
            .resizable(false)
            .exact_size(list_width)
            .show(ui, |ui| self.lesson_list_ui(ui));
        self.last_layout.inspector = inspector_panel(ui, |ui| inspector(self, ui)).response.rect;
        // A width that changed with the window the same size was dragged there by the user.
        let width = self.last_layout.inspector.width();
        if !resized
            && self.last_layout.window_width.is_some()
            && (width - inspector_before).abs() > 0.5
        {
            self.last_layout.inspector_choice = Some(width);
        }
        self.last_layout.window_width = Some(window);
    }

    /// The selected lesson's inspector: a notice, its text, its own part; or why it did not
    /// load.
    pub(crate) fn lesson_inspector_ui(&mut self, ui: &mut Ui) {
        self.lesson_side_ui(ui, true, Parts::All);
    }

    /// The selected lesson's panels (its inspector) without its text, as lecture mode shows
    /// them: the `parts` a slide names, or all (none named).
    pub(crate) fn lesson_panels_ui(&mut self, ui: &mut Ui, parts: &[&'static str]) {
        let parts = if parts.is_empty() {
            Parts::All
        } else {
            Parts::Only(parts)
        };
        self.lesson_side_ui(ui, false, parts);
    }

    /// Each lesson's inspector parts, in the lessons' order (what a lecture script may name).
    pub fn lesson_parts(&self) -> Vec<&'static [crate::lesson::Part]> {
        parts_of(&self.lessons)
    }

    fn lesson_side_ui(&mut self, ui: &mut Ui, with_text: bool, parts: Parts<'_>) {
        match &mut self.lessons[self.selected] {
            Ok(lesson) => {
                if let Some(notice) = &lesson.stage().notice {
                    ui.colored_label(
                        crate::canvas::readable(ui, crate::canvas::palette::RAY),
                        notice,
                    );
                    ui.separator();
                }
                if with_text {
                    text_ui(ui, lesson.text());
                    ui.separator();
                }
                lesson.inspector_ui(ui, parts);
            }
            Err(broken) => {
                ui.colored_label(
                    crate::canvas::readable(ui, crate::canvas::palette::MISS),
                    broken.message.as_str(),
                );
            }
        }
    }

    /// The selected lesson's canvas, filling what the panels leave.
    pub(crate) fn lesson_canvas_ui(&mut self, ui: &mut Ui) {
        self.last_layout.canvas = egui::CentralPanel::default()
            .show(ui, |ui| {
                if let Some(lesson) = self.lesson_mut() {
                    lesson.canvas_ui(ui);
                }
            })
            .response
            .rect;
    }

    /// Sets the theme's colours and, in lecture mode, the lecture's text sizes and zoom; only
    /// when they change, so the user's own zoom (Ctrl +) is kept otherwise.
    fn apply_style(&mut self, ctx: &egui::Context) {
        let lecturing = self.mode == Mode::Lecture && self.lecture.is_some();
        let wanted = (self.theme, lecturing);
        if self.styled == Some(wanted) {
            return;
        }
        let was_lecturing = self.styled.is_some_and(|(_, lecturing)| lecturing);
        self.styled = Some(wanted);
        let defaults = egui::Style::default();
        ctx.all_styles_mut(|style| {
            style.visuals = self.theme.visuals();
            if lecturing {
                crate::lecture::lecture_text_styles(style);
            } else {
                style.text_styles = defaults.text_styles.clone();
                style.spacing = defaults.spacing.clone();
                // Hints and footnotes at 12 points, not egui's 9: nobody reads 9-point grey.
                if let Some(small) = style.text_styles.get_mut(&egui::TextStyle::Small) {
                    small.size = small.size.max(SMALL_TEXT_POINTS);
                }
            }
        });
        if was_lecturing && !lecturing {
            ctx.set_zoom_factor(1.0);
        }
    }

    /// In lecture mode, the zoom that fits a slide to the screen as it is now (a window
    /// resized, full screen entered) at the lecturer's text size; set only when it changes.
    fn fit_lecture_zoom(&self, ctx: &egui::Context) {
        let Some(lecture) = self.lecture.as_ref().filter(|_| self.mode == Mode::Lecture) else {
            return;
        };
        let zoom = ctx.zoom_factor();
        let wanted = crate::lecture::lecture_zoom(ctx.content_rect().size() * zoom, lecture.scale);
        if (wanted - zoom).abs() > 0.005 {
            ctx.set_zoom_factor(wanted);
        }
    }

    /// The quiz: its panel on the right, its figure in the middle.
    fn quiz_ui(&mut self, ui: &mut Ui) {
        egui::Panel::top("top bar").show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.label(RichText::new("accelviz").strong().size(16.0));
                ui.separator();
                ui.label(RichText::new("Quiz").size(16.0));
            });
        });
        self.quiz.handle_keys(ui);
        self.side_panels_ui(ui, |app, ui| app.quiz.panel_ui(ui));
        self.last_layout.canvas = egui::CentralPanel::default()
            .show(ui, |ui| self.quiz.canvas_ui(ui))
            .response
            .rect;
        self.report_position(ui);
    }

    fn top_bar_ui(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            ui.label(RichText::new("accelviz").strong().size(16.0));
            ui.separator();
            if let Some(lesson) = self.lesson() {
                ui.label(RichText::new(lesson.text().title()).size(16.0));
            }
            ui.separator();
            let scene = self.lesson().map(|lesson| {
                let scene = &lesson.stage().scene;
                (
                    scene.noun(),
                    scene.filter().is_some(),
                    scene.can_save(),
                )
            });
            let has_scene = scene.is_some();
            let (noun, can_open, can_save) = scene.unwrap_or(("scene", false, false));
            if ui
                .add_enabled(can_open, egui::Button::new(format!("Open {noun}…")))
                .on_hover_text(format!("Open a {noun} file into this lesson"))
                .clicked()
            {
                self.open_scene(ui.ctx());
            }
            if ui
                .add_enabled(has_scene, egui::Button::new(format!("Reset {noun}")))
                .on_hover_text(format!("Back to the lesson's own {noun}"))
                .clicked()
                && let Some(lesson) = self.lesson_mut()
            {
                lesson.stage_mut().reset_scene();
                self.status = None;
            }
            if can_save
                && ui
                    .button(format!("Save {noun}…"))
                    .on_hover_text(format!("Save this lesson's {noun}, ray and settings"))
                    .clicked()
            {
                self.save_scene();
            }
            if ui
                .button("Share…")
                .on_hover_text("A link to exactly this view (lesson, scene, ray, choices, step), and a field to open one")
                .clicked()
            {
                self.share_window = Some(String::new());
            }
            if let Some(working) = self.lesson().and_then(|lesson| lesson.building()) {
                ui.add(egui::Spinner::new());
                ui.label(format!("building… {:.1} s", working.as_secs_f64()));
            }
            if let Some((message, problem)) = &self.status {
                crate::canvas::message_line(ui, message, *problem);
            }
        });
    }

    fn lesson_list_ui(&mut self, ui: &mut Ui) {
        // Scrolls when scaled up past what the window holds.
        egui::ScrollArea::vertical().show(ui, |ui| self.lesson_list_contents_ui(ui));
    }

    fn lesson_list_contents_ui(&mut self, ui: &mut Ui) {
        ui.add_space(6.0);
        ui.label(RichText::new("Lessons").strong());
        ui.add_space(4.0);
        // Full-width entries: easy to hit from a projector's remote mouse.
        ui.with_layout(egui::Layout::top_down_justified(egui::Align::LEFT), |ui| {
            for (index, title) in self.titles().into_iter().enumerate() {
                let current = self.mode == Mode::Lessons && self.selected == index;
                if ui.selectable_label(current, title).clicked() {
                    self.selected = index;
                    self.mode = Mode::Lessons;
                    self.status = None;
                }
            }
            ui.add_space(8.0);
            ui.label(RichText::new("Teach").strong());
            if ui
                .selectable_label(self.mode == Mode::Lecture, "Lecture mode (projector)")
                .on_hover_text(
                    "The lecture's slides full screen, large, stepped with a clicker: Page Down, Page Up, B blanks, R reveals",
                )
                .clicked()
            {
                self.start_lecture();
            }
            ui.add_space(8.0);
            ui.label(RichText::new("Test yourself").strong());
            if ui
                .selectable_label(self.mode == Mode::Quiz, "Quiz: predict each step")
                .on_hover_text("Questions made from a seed, graded step by step")
                .clicked()
            {
                self.mode = Mode::Quiz;
            }
        });
        ui.add_space(12.0);
        ui.label(
            RichText::new(
                "Scroll to zoom, right-drag to pan. Space plays and pauses, the arrow keys step.",
            )
            .weak()
            .small(),
        );
        ui.add_space(12.0);
        ui.label(RichText::new("Display").strong());
        ui.horizontal_wrapped(|ui| {
            for theme in Theme::ALL {
                if ui
                    .selectable_label(self.theme == theme, theme.name())
                    .on_hover_text("Colours: dark, light for lit rooms, or high contrast")
                    .clicked()
                {
                    self.theme = theme;
                }
            }
        });
        let mut zoom = ui.ctx().zoom_factor();
        ui.horizontal(|ui| {
            let label = ui.label("Scale");
            let slider = ui
                .add(egui::Slider::new(&mut zoom, 0.75..=2.0).step_by(0.05))
                .labelled_by(label.id)
                .on_hover_text("Everything larger or smaller (as Ctrl + and Ctrl −)");
            // Set once the drag ends: the slider itself moves as everything scales.
            if slider.drag_stopped() || (slider.changed() && !slider.dragged()) {
                ui.ctx().set_zoom_factor(zoom);
            }
        });
    }

    /// Opens a scene: the system's dialog, or the in-app panel when there is none.
    pub fn open_scene(&mut self, ctx: &egui::Context) {
        let Some(filter) = self
            .lesson()
            .and_then(|lesson| lesson.stage().scene.filter())
        else {
            return;
        };
        log::info!("accelviz: asking for a file to open");
        match self.files.open(ctx, filter) {
            DialogOutcome::Done | DialogOutcome::Cancelled => {}
            DialogOutcome::Unavailable(reason) => {
                log::warn!("accelviz: no file dialog: {reason}");
                self.file_panel = Some(FilePanel::new(PanelMode::Open, filter, Some(reason)));
            }
        }
    }

    /// Saves the scene: the system's dialog (a download in the browser), or the in-app panel
    /// when there is none.
    pub fn save_scene(&mut self) {
        let Some(((name, text), filter)) = self.lesson().and_then(|lesson| {
            let scene = &lesson.stage().scene;
            Some((scene.save()?, scene.filter()?))
        }) else {
            return;
        };
        self.save_file(&name, text.into_bytes(), filter);
    }

    /// Saves `bytes` as `name` through the system's dialog (a download in the browser), or
    /// the in-app panel when there is none; says how it went in the status line.
    pub fn save_file(&mut self, name: &str, bytes: Vec<u8>, filter: FileFilter) {
        self.status = match self.files.save(name, &bytes, filter) {
            Ok(Some(Ok(message))) => Some((message, false)),
            Ok(Some(Err(message))) => Some((message, true)),
            Ok(None) => return,
            Err(reason) => {
                log::warn!("accelviz: no file dialog: {reason}");
                self.file_panel = Some(FilePanel::saving(filter, name, bytes, reason));
                return;
            }
        };
    }

    pub(crate) fn file_panel_ui(&mut self, ctx: &egui::Context) {
        // A panel opening a file opens it into the lesson it was opened for: once the lesson
        // shown reads other files (a 2D lesson, not an OBJ mesh), or none, it closes.
        let wanted = self
            .lesson()
            .and_then(|lesson| lesson.stage().scene.filter());
        let lecturing = self.mode == Mode::Lecture && self.lecture.is_some();
        if self.file_panel.as_ref().is_some_and(|panel| {
            let for_here = if panel.filter == SCRIPT_FILTER {
                lecturing
            } else {
                self.mode == Mode::Lessons && wanted == Some(panel.filter)
            };
            panel.mode == PanelMode::Open && !for_here
        }) {
            self.file_panel = None;
        }
        let Some(panel) = &mut self.file_panel else {
            return;
        };
        match panel.ui(ctx) {
            PanelAction::None => {}
            PanelAction::Close => self.file_panel = None,
            PanelAction::Open(path) => match crate::files::read_text_file(&path, panel.filter) {
                FileEvent::Opened { name, text, filter } => {
                    if self.open_text(filter, &name, &text) {
                        self.file_panel = None;
                    }
                }
                FileEvent::Failed(message) => self.status = Some((message, true)),
            },
            PanelAction::Save(path) => match crate::files::write_file(&path, &panel.content) {
                Ok(message) => {
                    self.status = Some((message, false));
                    self.file_panel = None;
                }
                Err(message) => self.status = Some((message, true)),
            },
        }
    }

    /// Opens the lesson a lesson asked to show a ray in (the trade lab's "show me"), on
    /// that ray.
    fn take_show_ray(&mut self) {
        let Some(request) = self.lesson_mut().and_then(|lesson| lesson.take_show_ray()) else {
            return;
        };
        let index = registry::LESSONS
            .iter()
            .position(|entry| entry.path.ends_with(request.lesson));
        let shown = index.and_then(|index| {
            let lesson = self.lessons.get_mut(index)?.as_mut().ok()?;
            lesson.show_ray(&request).then_some(index)
        });
        match shown {
            Some(index) => {
                self.selected = index;
                self.mode = Mode::Lessons;
                self.status = None;
            }
            None => {
                self.status = Some((
                    format!("no lesson {} to show the ray in", request.lesson),
                    true,
                ))
            }
        }
    }

    /// Saves what the lesson made to be saved (a PNG of its view).
    fn take_export(&mut self) {
        let Some(export) = self.lesson_mut().and_then(|lesson| lesson.take_export()) else {
            return;
        };
        match export {
            Ok((name, bytes)) => {
                let filter = if name.ends_with(".csv") {
                    CSV_FILTER
                } else {
                    PNG_FILTER
                };
                self.save_file(&name, bytes, filter)
            }
            Err(problem) => {
                self.status = Some((format!("cannot save the picture: {problem}"), true))
            }
        }
    }

    /// Opens files dropped onto the window (or the page) into the current lesson.
    fn take_dropped_files(&mut self, ctx: &egui::Context) {
        let dropped = ctx.input(|input| input.raw.dropped_files.clone());
        if dropped.is_empty() {
            return;
        }
        let Some(filter) = self
            .lesson()
            .and_then(|lesson| lesson.stage().scene.filter())
        else {
            self.status = Some(("this lesson opens no files".to_owned(), true));
            return;
        };
        for file in dropped {
            self.files.dropped(ctx, file, filter);
        }
    }

    pub(crate) fn apply_file_events(&mut self) {
        for event in self.files.take_events() {
            match event {
                FileEvent::Opened { name, text, filter } => {
                    self.open_text(filter, &name, &text);
                }
                FileEvent::Failed(message) => self.status = Some((message, true)),
            }
        }
    }

    /// Generates the lesson's 2D scene from `generator`, as the toolbar's "generate" does;
    /// false if the lesson has no 2D scene.
    pub fn generate_scene(&mut self, generator: accelviz_scene::document::GeneratorEntry) -> bool {
        let Some(scene) = self
            .lesson_mut()
            .and_then(|lesson| lesson.stage_mut().scene.as_flat())
        else {
            return false;
        };
        scene.generator = generator;
        scene.generate();
        true
    }

    /// Opens a file's text as what it was opened as: a lecture script, or the lesson's scene.
    fn open_text(&mut self, filter: FileFilter, name: &str, text: &str) -> bool {
        if filter == SCRIPT_FILTER {
            self.open_script_text(name, text)
        } else {
            self.open_scene_text(name, text)
        }
    }

    /// Asks for a lecture script to open: the system's dialog (an upload in the browser), or
    /// the in-app panel when there is none.
    pub fn open_script(&mut self, ctx: &egui::Context) {
        match self.files.open(ctx, SCRIPT_FILTER) {
            DialogOutcome::Done | DialogOutcome::Cancelled => {}
            DialogOutcome::Unavailable(reason) => {
                log::warn!("accelviz: no file dialog: {reason}");
                self.file_panel =
                    Some(FilePanel::new(PanelMode::Open, SCRIPT_FILTER, Some(reason)));
            }
        }
    }

    /// Takes a lecture script's text as the lecture, from its first slide when lecture mode
    /// is on: its bad lines are skipped and reported in the lecture bar (file and line); a
    /// script with no slide keeps the lecture as it was and says why. Returns whether it
    /// opened.
    pub fn open_script_text(&mut self, name: &str, text: &str) -> bool {
        match LectureScript::parse(text, name, &self.lesson_parts()) {
            Ok(script) => {
                let slides = script.slides.len();
                log::info!("accelviz: opened the lecture script {name}: {slides} slides");
                self.script = Ok(script);
                if self.mode == Mode::Lecture && self.lecture.is_some() {
                    self.start_lecture();
                }
                let message = format!(
                    "opened the lecture script {name}: {}",
                    accelviz_core::format::counted(slides, "slide", "slides")
                );
                if let Some(lecture) = &mut self.lecture {
                    lecture.message = Some((message.clone(), false));
                }
                self.status = Some((message, false));
                true
            }
            Err(error) => {
                let message = format!("{error} (the lecture stays as it was)");
                log::warn!("accelviz: {message}");
                if let Some(lecture) = &mut self.lecture {
                    lecture.message = Some((message.clone(), true));
                }
                self.status = Some((message, true));
                false
            }
        }
    }

    /// Opens a scene document's text into the current lesson; a bad document leaves the
    /// scene as it was and says why (file, line, problem) in the status line. Returns whether
    /// it opened.
    pub fn open_scene_text(&mut self, name: &str, text: &str) -> bool {
        let Some(lesson) = self.lesson_mut() else {
            return false;
        };
        let stage = lesson.stage_mut();
        match stage.scene.open(name, text) {
            Ok(()) => {
                stage.timeline.rewind();
                // A large file is read aside: how that ends comes later
                // ([`AccelvizApp::take_read_outcome`]).
                self.status = Some(if stage.scene.reading().is_some() {
                    (format!("reading {name}…"), false)
                } else {
                    log::info!("accelviz: opened {name}");
                    (format!("opened {name}"), false)
                });
                true
            }
            Err(message) => {
                log::warn!("accelviz: {message}");
                self.status = Some((message, true));
                false
            }
        }
    }

    /// Says in the status line how a file read aside ended (opened, or why not): one message
    /// in one place, as for a file opened at once, replaced by the next.
    pub(crate) fn take_read_outcome(&mut self) {
        let Some(outcome) = self
            .lesson_mut()
            .and_then(|lesson| lesson.stage_mut().scene.take_read_outcome())
        else {
            return;
        };
        self.status = Some(match outcome {
            Ok(name) => {
                log::info!("accelviz: opened {name}");
                (format!("opened {name}"), false)
            }
            Err(problem) => {
                log::warn!("accelviz: {problem}");
                (problem, true)
            }
        });
    }

    /// Logs each change of lesson or step once (the browser test reads these lines) and puts
    /// them in the page title on the web. Each mode says where it is.
    pub(crate) fn report_position(&mut self, ui: &Ui) {
        // Read at the end of the frame: a click in the lesson list may have changed the lesson.
        let position = self.position();
        if self.reported.as_deref() == Some(position.line.as_str()) {
            return;
        }
        log::info!("{}", position.line);
        if cfg!(target_arch = "wasm32") {
            crate::files::set_page_title(&format!("accelviz: {}", position.title));
        } else {
            ui.ctx()
                .send_viewport_cmd(egui::ViewportCommand::Title(self.window_title()));
        }
        self.reported = Some(position.line);
    }

    /// Where the app is, in the mode shown.
    fn position(&self) -> Position {
        match (self.mode, &self.lecture) {
            (Mode::Quiz, _) => self.quiz.position(),
            (Mode::Lecture, Some(lecture)) => self.lecture_position(lecture),
            (Mode::Lecture | Mode::Lessons, _) => self.lesson_position(),
        }
    }

    /// The desktop window's title. A playing lesson's step changes ten times a second: the
    /// window keeps the lesson's name. A lecture's slide, question step, reveal and blank
    /// change at the lecturer's pace, and the window says each (it was cut at the step, so
    /// neither a reveal nor a blank showed); the browser's page title says the step as well.
    pub fn window_title(&self) -> String {
        let title = self.position().title;
        let name = if self.mode == Mode::Lecture {
            title.as_str()
        } else {
            title.split(", step").next().unwrap_or(&title)
        };
        format!("accelviz: {name}")
    }

    /// Where the lessons mode is: the lesson and its step.
    pub(crate) fn lesson_position(&self) -> Position {
        let (shown, len) = self
            .lesson()
            .filter(|lesson| lesson.caption().is_some())
            .map_or((0, 0), |lesson| {
                let timeline = &lesson.stage().timeline;
                (timeline.shown, timeline.len)
            });
        let title = self
            .titles()
            .get(self.selected)
            .cloned()
            .unwrap_or_default();
        Position {
            line: format!(
                "accelviz: lesson {} ({title}), step {shown} of {len}",
                self.selected + 1
            ),
            title: format!("{title}, step {shown} of {len}"),
        }
    }
}

impl AccelvizApp {
    /// One frame of `size` points, laid out and tessellated into the triangles a renderer would
    /// draw, without a renderer: what the frame bench times and the bounds test counts.
    pub fn tessellated_frame(
        &mut self,
        ctx: &egui::Context,
        size: egui::Vec2,
    ) -> Vec<egui::ClippedPrimitive> {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, size)),
            ..Default::default()
        };
        let mut output = ctx.run_ui(input, |ui| self.contents_ui(ui));
        // No renderer takes the font texture's updates here.
        output.textures_delta.clear();
        ctx.tessellate(output.shapes, output.pixels_per_point)
    }
}

impl eframe::App for AccelvizApp {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        self.contents_ui(ui);
    }
}

/// The smallest text outside lecture mode (hints, footnotes), in points.
pub const SMALL_TEXT_POINTS: f32 = 12.0;

/// Lecture scripts, opened from lecture mode ("Open script…").
pub const SCRIPT_FILTER: FileFilter = FileFilter {
    name: "lecture script",
    extensions: &["txt"],
    max_bytes: 1 << 20,
};

/// Pictures saved for slides.
const PNG_FILTER: FileFilter = FileFilter {
    name: "PNG image",
    extensions: &["png"],
    max_bytes: 0,
};

/// Tables saved for spreadsheets (the trade lab's).
const CSV_FILTER: FileFilter = FileFilter {
    name: "CSV table",
    extensions: &["csv"],
    max_bytes: 0,
};

/// The slide, the explanation and things to try, for the inspector's top.
pub fn text_ui(ui: &mut Ui, text: &crate::lesson_file::LessonText) {
    ui.label(RichText::new(format!("Slide: {}", text.file.slide)).weak());
    for paragraph in &text.file.explanation {
        ui.label(paragraph);
    }
    if !text.file.try_this.is_empty() {
        ui.label(RichText::new("Try this").strong());
        for item in &text.file.try_this {
            ui.label(format!("• {item}"));
        }
    }
}
