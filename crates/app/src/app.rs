//! The app's frame: lessons on the left, the canvas in the middle, the inspector on the right,
//! the timeline at the bottom, and a top bar to open and save scenes.

use accelviz_scene::document::Scene2d;
use egui::{RichText, Ui};

use crate::files::{FileChannel, FileEvent};
use crate::lessons::{self, Lesson};

/// The accelviz app.
pub struct AccelvizApp {
    lessons: Vec<Result<Box<dyn Lesson>, String>>,
    /// The lesson shown.
    pub selected: usize,
    /// The last message for the user: text and whether it reports a problem.
    pub status: Option<(String, bool)>,
    files: FileChannel,
    /// What was last reported to the log (lesson, step), so each change is logged once.
    reported: Option<(usize, usize, usize)>,
}

impl Default for AccelvizApp {
    fn default() -> Self {
        Self::new()
    }
}

impl AccelvizApp {
    /// The app on its default lesson, the lecture's first, with the embedded lesson files.
    pub fn new() -> Self {
        Self::with_lessons(lessons::registry())
    }

    /// The app with lesson files read from `assets_dir` where they exist there (see
    /// [`lessons::registry_from`]).
    pub fn with_assets(assets_dir: &std::path::Path) -> Self {
        Self::with_lessons(lessons::registry_from(Some(assets_dir)))
    }

    fn with_lessons(lessons: Vec<Result<Box<dyn Lesson>, String>>) -> Self {
        Self {
            lessons,
            selected: 0,
            status: None,
            files: FileChannel::default(),
            reported: None,
        }
    }

    /// How many lessons there are.
    pub fn lesson_count(&self) -> usize {
        self.lessons.len()
    }

    /// The selected lesson (if its file parsed).
    pub fn lesson_mut(&mut self) -> Option<&mut Box<dyn Lesson>> {
        self.lessons.get_mut(self.selected)?.as_mut().ok()
    }

    /// Lesson titles in order.
    pub fn titles(&self) -> Vec<String> {
        self.lessons
            .iter()
            .map(|lesson| match lesson {
                Ok(lesson) => lesson.text().file.title.clone(),
                Err(_) => "(lesson file broken)".to_owned(),
            })
            .collect()
    }

    /// Everything the app draws in a frame.
    pub fn contents_ui(&mut self, ui: &mut Ui) {
        self.selected = self.selected.min(self.lessons.len().saturating_sub(1));
        self.apply_file_events();
        egui::Panel::top("top bar").show(ui, |ui| self.top_bar_ui(ui));
        let selected = self.selected;
        // The lesson's timeline is asked for once a frame: its caption can cost a lookup.
        let mut position = (0, 0);
        if let Some((timeline, caption)) = self.lesson_mut().and_then(|lesson| lesson.timeline()) {
            egui::Panel::bottom("timeline").show(ui, |ui| {
                ui.add_space(4.0);
                timeline.ui(ui, &caption);
                ui.add_space(2.0);
            });
            position = (timeline.shown, timeline.len);
        }
        egui::Panel::left("lessons")
            .resizable(false)
            .exact_size(210.0)
            .show(ui, |ui| self.lesson_list_ui(ui));
        egui::Panel::right("inspector")
            .resizable(true)
            .default_size(340.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| match &mut self.lessons[selected] {
                    Ok(lesson) => {
                        lessons::text_ui(ui, lesson.text());
                        ui.separator();
                        lesson.inspector_ui(ui);
                    }
                    Err(error) => {
                        ui.colored_label(crate::canvas::palette::MISS, error.as_str());
                    }
                });
            });
        egui::CentralPanel::default().show(ui, |ui| {
            if let Some(lesson) = self.lesson_mut() {
                lesson.canvas_ui(ui);
            }
        });
        self.report_position(ui, position);
    }

    fn top_bar_ui(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            ui.label(RichText::new("accelviz").strong().size(16.0));
            ui.separator();
            if let Ok(lesson) = &self.lessons[self.selected] {
                ui.label(RichText::new(&lesson.text().file.title).size(16.0));
            }
            ui.separator();
            let has_scene = self
                .lesson_mut()
                .is_some_and(|lesson| lesson.scene_mut().is_some());
            if ui
                .add_enabled(has_scene, egui::Button::new("Open scene…"))
                .on_hover_text("Open a scene file (.ron) into this lesson")
                .clicked()
            {
                self.files.open();
            }
            if ui
                .add_enabled(has_scene, egui::Button::new("Reset scene"))
                .on_hover_text("Back to the lesson's own scene")
                .clicked()
                && let Some(lesson) = self.lesson_mut()
            {
                lesson.reset_scene();
                self.status = None;
            }
            if ui
                .add_enabled(has_scene, egui::Button::new("Save scene…"))
                .on_hover_text("Save this lesson's scene, ray and settings (.ron)")
                .clicked()
            {
                self.save_scene();
            }
            if let Some((message, problem)) = &self.status {
                let color = if *problem {
                    crate::canvas::palette::MISS
                } else {
                    ui.visuals().weak_text_color()
                };
                ui.colored_label(color, message);
            }
        });
    }

    fn lesson_list_ui(&mut self, ui: &mut Ui) {
        ui.add_space(6.0);
        ui.label(RichText::new("Lessons").strong());
        ui.add_space(4.0);
        // Full-width entries: easy to hit from a projector's remote mouse.
        ui.with_layout(egui::Layout::top_down_justified(egui::Align::LEFT), |ui| {
            for (index, title) in self.titles().into_iter().enumerate() {
                if ui.selectable_label(self.selected == index, title).clicked() {
                    self.selected = index;
                    self.status = None;
                }
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
    }

    fn save_scene(&mut self) {
        let Some(scene) = self.lesson_mut().and_then(|lesson| lesson.scene_mut()) else {
            return;
        };
        let text = scene.scene.to_ron();
        self.status = Some(match self.files.save("scene.ron", text) {
            Ok(Some(message)) => (message, false),
            Ok(None) => return,
            Err(message) => (message, true),
        });
    }

    fn apply_file_events(&mut self) {
        for event in self.files.take_events() {
            match event {
                FileEvent::Opened { name, text } => self.open_scene_text(&name, &text),
                FileEvent::Failed(message) => self.status = Some((message, true)),
            }
        }
    }

    /// Opens a scene document's text into the current lesson; a bad document leaves the
    /// scene as it was and says why (file, line, problem) in the status line.
    pub fn open_scene_text(&mut self, name: &str, text: &str) {
        match Scene2d::parse(text, name) {
            Ok(scene) => {
                if let Some(editable) = self.lesson_mut().and_then(|lesson| lesson.scene_mut()) {
                    editable.replace(scene);
                    log::info!("accelviz: opened {name}");
                    self.status = Some((format!("opened {name}"), false));
                }
            }
            Err(error) => {
                log::warn!("accelviz: {error}");
                self.status = Some((error.to_string(), true));
            }
        }
    }

    /// Logs each change of lesson or step once (the browser test reads these lines) and puts
    /// them in the page title on the web.
    fn report_position(&mut self, ui: &Ui, (shown, len): (usize, usize)) {
        let selected = self.selected;
        if self.reported == Some((selected, shown, len)) {
            return;
        }
        self.reported = Some((selected, shown, len));
        let title = self.titles().get(selected).cloned().unwrap_or_default();
        let line = format!(
            "accelviz: lesson {} ({title}), step {shown} of {len}",
            selected + 1
        );
        log::info!("{line}");
        // The desktop names the window; the browser's page title says the step as well.
        if cfg!(target_arch = "wasm32") {
            crate::files::set_page_title(&format!("accelviz: {title}, step {shown} of {len}"));
        } else {
            ui.ctx()
                .send_viewport_cmd(egui::ViewportCommand::Title(format!("accelviz: {title}")));
        }
    }
}

impl eframe::App for AccelvizApp {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        self.contents_ui(ui);
    }
}
