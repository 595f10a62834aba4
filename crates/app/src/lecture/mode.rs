//! Lecture mode's side of the app: starting and leaving it, opening a slide, the frame it
//! draws (the slide under a bar of large controls) and what its keys and buttons do.

use egui::{RichText, Ui};

use super::script::{Slide, StartStep};
use super::{Action, Lecture, Outcome, Theme};
use crate::app::{AccelvizApp, INSPECTOR_WIDTH, Mode};
use crate::lesson::Lesson;
use crate::position::Position;

/// The share of the window a slide's panels take.
const LECTURE_PANEL_SHARE: f32 = 0.45;

impl AccelvizApp {
    /// Where lecture mode is: the slide and, on a question slide, the question's step; on a
    /// lesson slide, the lesson's own position after it.
    pub(crate) fn lecture_position(&self, lecture: &Lecture) -> Position {
        let slide = format!(
            "lecture slide {} of {}",
            lecture.slide + 1,
            lecture.script.slides.len()
        );
        let blank = if lecture.blank { ", blank" } else { "" };
        match lecture.question() {
            Some(session) => {
                let revealed = if session.is_revealed() {
                    ", revealed"
                } else {
                    ""
                };
                let step = lecture
                    .question_step_text()
                    .unwrap_or_else(|| "step 1 of 1".to_owned());
                let place = format!(
                    "{slide}: question {}, {step}{revealed}{blank}",
                    session.questions()[0].kind,
                );
                Position {
                    line: format!("accelviz: {place}"),
                    title: place,
                }
            }
            None => {
                let lesson = self.lesson_position();
                let line = lesson.line.trim_start_matches("accelviz: ");
                Position {
                    line: format!("accelviz: {slide}: {line}{blank}"),
                    title: format!("{slide}: {}{blank}", lesson.title),
                }
            }
        }
    }

    /// Starts lecture mode with the script, at its first slide.
    pub fn start_lecture(&mut self) {
        match &self.script {
            Ok(script) => {
                self.lecture = Some(Lecture::new(script.clone()));
                self.mode = Mode::Lecture;
                self.open_slide(0, false);
            }
            Err(problem) => {
                self.status = Some((format!("No lecture: {problem}"), true));
            }
        }
    }

    /// Leaves lecture mode for the lesson last shown.
    pub fn stop_lecture(&mut self, ctx: &egui::Context) {
        if self
            .lecture
            .as_ref()
            .is_some_and(|lecture| lecture.full_screen)
        {
            set_full_screen(ctx, false);
        }
        self.lecture = None;
        self.mode = Mode::Lessons;
    }

    /// Opens slide `index` of the lecture (at its last step when going back).
    pub fn open_slide(&mut self, index: usize, at_end: bool) {
        let Some(lecture) = &mut self.lecture else {
            return;
        };
        let Some((lesson, show)) = lecture.open(index, at_end) else {
            return;
        };
        let slide = lecture.slide + 1;
        let path = lecture.script.path.clone();
        self.selected = lesson.min(self.lessons.len().saturating_sub(1));
        // A slide opens on its whole scene (the view fits again whenever the canvas changes
        // size, unless the lecturer moves it).
        if let Some(scene) = self
            .lesson_mut()
            .and_then(|lesson| lesson.stage_mut().scene.as_flat())
        {
            scene.view.placed = false;
        }
        let mut problem = None;
        if let Some(name) = show
            && let Some(lesson) = self.lesson_mut()
            && !lesson.show_named(&name)
        {
            problem = Some(format!(
                "{path}: slide {slide}: this lesson has no ray or preset \"{name}\"; it has: {}",
                lesson.named().join(", ")
            ));
        }
        if let Some(lecture) = &mut self.lecture {
            lecture.message = problem.map(|problem| (problem, true));
        }
    }

    /// Lecture mode: the slide fills the window under a bar of large controls.
    pub(crate) fn lecture_ui(&mut self, ui: &mut Ui) {
        let ctx = ui.ctx().clone();
        // The clicker's keys first, so the frame shows where they lead.
        for action in Lecture::pressed(ui) {
            if !self.lecture_act(&ctx, action) {
                return;
            }
        }
        let on_lesson = matches!(
            self.lecture.as_ref().map(Lecture::current),
            Some(Slide::Lesson { .. })
        );
        if on_lesson && let Some(lesson) = self.lesson_mut() {
            lesson.update();
        }
        // A lesson slide's start step, once its animation knows its steps.
        let pending = self.lecture.as_ref().and_then(Lecture::pending);
        if let (true, Some(pending)) = (on_lesson, pending) {
            let ready = self
                .lesson()
                .map(|lesson| lesson.caption().is_none() || lesson.stage().timeline.len > 0);
            if ready == Some(true) {
                if let Some(lecture) = &mut self.lecture {
                    lecture.take_pending();
                }
                if let Some(lesson) = self.lesson_mut() {
                    let timeline = &mut lesson.stage_mut().timeline;
                    timeline.playing = false;
                    timeline.shown = match pending {
                        StartStep::At(step) => step.min(timeline.len),
                        StartStep::End => timeline.len,
                    };
                }
            }
        }
        egui::Panel::top("lecture bar").show(ui, |ui| self.lecture_bar_ui(ui));
        let caption = self
            .lesson()
            .filter(|_| on_lesson)
            .and_then(|lesson| lesson.caption());
        if let Some(caption) = caption {
            egui::Panel::bottom("lecture caption").show(ui, |ui| {
                ui.add_space(4.0);
                ui.label(RichText::new(caption).size(20.0));
                ui.add_space(4.0);
            });
        }
        let panels = self.lecture.as_ref().is_some_and(|lecture| lecture.panels);
        if on_lesson {
            if panels {
                // Wide enough for the kD pseudo-code's lines at lecture size: a panel of its
                // own (the lessons' inspector keeps its width).
                let width =
                    (ui.ctx().content_rect().width() * LECTURE_PANEL_SHARE).max(INSPECTOR_WIDTH.0);
                let panel = egui::Panel::right("lecture panels")
                    .resizable(true)
                    .default_size(width);
                // The lesson's panels without its text: the lecturer tells it, and at lecture
                // scale the text would push the panels off the screen.
                let shown = crate::app::scrolled_panel(panel, ui, |ui| {
                    let parts = self
                        .lecture
                        .as_ref()
                        .map(|lecture| lecture.parts().to_vec())
                        .unwrap_or_default();
                    self.lesson_panels_ui(ui, &parts);
                })
                .inner;
                self.last_layout.lecture_panels_overflow =
                    shown.content_size.y - shown.inner_rect.height();
            }
            self.lesson_canvas_ui(ui);
        } else if let Some(lecture) = &mut self.lecture {
            self.last_layout.canvas = egui::CentralPanel::default()
                .show(ui, |ui| lecture.question_ui(ui))
                .response
                .rect;
        }
        self.apply_file_events();
        self.file_panel_ui(&ctx);
        if let Some(lecture) = &self.lecture {
            if lecture.pointer {
                super::paint_pointer(&ctx);
            }
            if lecture.blank {
                super::paint_blank(&ctx);
            }
        }
        self.report_position(ui);
    }

    /// The lecture's bar: where the lecture is, and large buttons for what the keys do.
    fn lecture_bar_ui(&mut self, ui: &mut Ui) {
        let titles = self.titles();
        let step = self
            .lesson()
            .filter(|lesson| lesson.caption().is_some())
            .map(|lesson| (lesson.stage().timeline.shown, lesson.stage().timeline.len));
        let Some(lecture) = &mut self.lecture else {
            return;
        };
        let mut outcome = None;
        let mut open_script = false;
        let mut place_cut = false;
        let count = lecture.script.slides.len();
        // The counters first and the title last, so that on a narrow screen the cut falls on
        // the title (shown on hover), never on where the lecture stands.
        let place = match lecture.current() {
            Slide::Lesson { index, .. } => {
                let title = titles.get(*index).cloned().unwrap_or_default();
                // A 3D slide before its ray is clicked has no steps to count.
                match step {
                    Some((shown, len)) if len > 0 => format!(
                        "Slide {} of {count} · step {shown} of {len} · {title}",
                        lecture.slide + 1
                    ),
                    _ => format!("Slide {} of {count} · {title}", lecture.slide + 1),
                }
            }
            Slide::Question { kind, .. } => {
                let title = accelviz_quiz::KINDS
                    .iter()
                    .find(|entry| entry.name == *kind)
                    .map_or(*kind, |entry| entry.title);
                match lecture.question_step_text() {
                    Some(step) => {
                        format!("Slide {} of {count} · {step} · {title}", lecture.slide + 1)
                    }
                    None => format!("Slide {} of {count} · {title}", lecture.slide + 1),
                }
            }
        };
        // One row that never wraps: the buttons first, where the lecturer's hand expects
        // them on every slide, the setup in a menu, and the slide's place last, cut to what
        // is left (the whole of it on hover), so no slide moves the bar or the canvas.
        ui.horizontal(|ui| {
            for (label, action) in [
                ("Back", Action::Previous),
                ("Next", Action::Next),
                ("Reveal (R)", Action::Reveal),
                ("Blank (B)", Action::Blank),
                ("Full screen (F)", Action::FullScreen),
                ("Panels (I)", Action::Panels),
                ("Exit (Esc)", Action::Exit),
            ] {
                if ui.button(label).clicked() {
                    outcome = Some(action);
                }
            }
            ui.separator();
            ui.menu_button("Setup", |ui| {
                if ui
                    .button("Open script…")
                    .on_hover_text("A lecture script (a copy of assets/lecture.txt, edited): its slides replace these")
                    .clicked()
                {
                    open_script = true;
                    ui.close();
                }
                ui.separator();
                let problems = lecture.script.problems();
                if !problems.is_empty() {
                    ui.label(RichText::new("Lines of the script skipped:").strong());
                    for problem in &problems {
                        ui.label(RichText::new(problem).color(crate::canvas::readable(
                            ui,
                            crate::canvas::palette::MISS,
                        )));
                    }
                    ui.separator();
                }
                ui.checkbox(&mut lecture.pointer, "Pointer");
                ui.horizontal(|ui| {
                    let label = ui.label("Text size");
                    ui.add(
                        egui::Slider::new(&mut lecture.scale, 0.7..=1.6)
                            .step_by(0.1)
                            .custom_formatter(|value, _| format!("{:.0} %", value * 100.0))
                            .custom_parser(|text| {
                                text.trim_end_matches(['%', ' ']).parse::<f64>().ok().map(|v| v / 100.0)
                            }),
                    )
                    .labelled_by(label.id)
                    .on_hover_text("Relative to the slide fitted to the screen: 100 % lays a slide out on 1280 × 720 points, whatever the projector's pixels");
                });
                ui.horizontal(|ui| {
                    for theme in Theme::ALL {
                        if ui
                            .selectable_label(self.theme == theme, theme.name())
                            .clicked()
                        {
                            self.theme = theme;
                        }
                    }
                });
            });
            ui.separator();
            // Everything before the title: the counters, which must not be cut.
            let counters = place.rsplit_once(" · ").map_or(place.as_str(), |(head, _)| head);
            let counters_width = ui
                .fonts_mut(|fonts| {
                    fonts.layout_no_wrap(
                        counters.to_owned(),
                        egui::TextStyle::Body.resolve(ui.style()),
                        egui::Color32::WHITE,
                    )
                })
                .size()
                .x;
            place_cut = counters_width > ui.available_width();
            ui.add(egui::Label::new(RichText::new(&place).strong()).truncate())
                .on_hover_text(&place);
        });
        self.last_layout.lecture_place_cut = place_cut;
        // What went wrong with the script or the slide, below, in full: the skipped lines one
        // a row (the first few; Setup lists every one).
        let problems = lecture.script.problems();
        const SHOWN_PROBLEMS: usize = 3;
        if !problems.is_empty() {
            let count = problems.len();
            let heading = if count == 1 {
                "A line of the script was skipped:".to_owned()
            } else {
                format!("{count} lines of the script were skipped:")
            };
            crate::canvas::message_line(ui, &heading, true);
            for problem in problems.iter().take(SHOWN_PROBLEMS) {
                crate::canvas::message_line(ui, &format!("  {problem}"), true);
            }
            if count > SHOWN_PROBLEMS {
                crate::canvas::message_line(
                    ui,
                    &format!(
                        "  … and {} more: Setup lists every one",
                        count - SHOWN_PROBLEMS
                    ),
                    true,
                );
            }
        }
        if let Some((note, problem)) = lecture.message.clone() {
            crate::canvas::message_line(ui, &note, problem);
        }
        if open_script {
            self.open_script(&ui.ctx().clone());
        }
        if let Some(action) = outcome {
            self.lecture_act(&ui.ctx().clone(), action);
        }
    }

    /// Does what a lecture key or button asks; false once lecture mode is left.
    fn lecture_act(&mut self, ctx: &egui::Context, action: Action) -> bool {
        let on_lesson = matches!(
            self.lecture.as_ref().map(Lecture::current),
            Some(Slide::Lesson { .. })
        );
        let selected = self.selected;
        let lesson = if on_lesson {
            self.lessons
                .get_mut(selected)
                .and_then(|lesson| lesson.as_mut().ok())
                .map(|lesson| lesson.as_mut() as &mut dyn Lesson)
        } else {
            None
        };
        let Some(lecture) = &mut self.lecture else {
            return false;
        };
        match lecture.act(action, lesson) {
            Outcome::Stay => {}
            Outcome::Open(index, at_end) => self.open_slide(index, at_end),
            Outcome::FullScreen(on) => set_full_screen(ctx, on),
            Outcome::Exit => {
                self.stop_lecture(ctx);
                return false;
            }
        }
        true
    }
}

/// Full screen on or off: the window on the desktop, the page in the browser.
pub(crate) fn set_full_screen(ctx: &egui::Context, on: bool) {
    #[cfg(target_arch = "wasm32")]
    {
        let _ = ctx;
        crate::files::web_full_screen(on);
    }
    #[cfg(not(target_arch = "wasm32"))]
    ctx.send_viewport_cmd(egui::ViewportCommand::Fullscreen(on));
}
