//! Lecture mode: the app driven from a projector and a presentation clicker. A lecture script
//! ([`script`]) lists the slides (lessons at a step, on a named ray or preset; quiz
//! questions); the clicker's keys step each lesson's animation and then move to the next
//! slide, as reveal.js and PowerPoint do; B or `.` blanks the screen; answers stay hidden
//! until R. Text is large (none under 24 px at the default scale on a 1920×1080 screen), the
//! side panels are hidden so the canvas fills the screen, and the pointer can be lit.
//!
//! The keys are listed once, in [`LECTURE_KEYS`]; the README's table is made from it (and a
//! test holds the two together).

pub mod mode;
pub mod script;

use accelviz_quiz::{Expected, Response, Session};
use egui::{Color32, Key, RichText, Ui};

use crate::canvas::{View2d, palette};
use crate::quiz::figure::{FigureState, figure_ui, scene_tree};
use crate::stage::SceneTree;
use script::{LectureScript, Panels, Slide, StartStep};

/// What a key does in lecture mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// The next step of the animation (or question), then the next slide.
    Next,
    /// The step before, then the slide before (at its last step).
    Previous,
    /// The slide's first step.
    First,
    /// The slide's last step.
    Last,
    /// Blank the screen, or show it again.
    Blank,
    /// Show the answer and its explanation.
    Reveal,
    /// Full screen on or off.
    FullScreen,
    /// The side panels on or off.
    Panels,
    /// Leave lecture mode.
    Exit,
}

/// Keys and what they do.
pub struct KeyBinding {
    /// The keys (any of them).
    pub keys: &'static [Key],
    /// What they do.
    pub action: Action,
    /// In words, for the README and the help.
    pub what: &'static str,
}

/// Every lecture key, once. Presentation clickers send Page Down / Page Up (most), the arrows,
/// B or `.` (their "blank" button; reveal.js and PowerPoint use both).
pub const LECTURE_KEYS: &[KeyBinding] = &[
    KeyBinding {
        keys: &[
            Key::PageDown,
            Key::ArrowRight,
            Key::ArrowDown,
            Key::N,
            Key::Space,
        ],
        action: Action::Next,
        what: "the next step of the animation; after the last, the next slide",
    },
    KeyBinding {
        keys: &[Key::PageUp, Key::ArrowLeft, Key::ArrowUp, Key::P],
        action: Action::Previous,
        what: "the step before; before the first, the slide before",
    },
    KeyBinding {
        keys: &[Key::Home],
        action: Action::First,
        what: "the slide's first step",
    },
    KeyBinding {
        keys: &[Key::End],
        action: Action::Last,
        what: "the slide's last step",
    },
    KeyBinding {
        keys: &[Key::B, Key::Period],
        action: Action::Blank,
        what: "blank the screen; again to show it (other keys wait meanwhile)",
    },
    KeyBinding {
        keys: &[Key::R],
        action: Action::Reveal,
        what: "reveal a question's answer and explanation",
    },
    KeyBinding {
        keys: &[Key::F],
        action: Action::FullScreen,
        what: "full screen on or off",
    },
    KeyBinding {
        keys: &[Key::I],
        action: Action::Panels,
        what: "the side panels on or off",
    },
    KeyBinding {
        keys: &[Key::Escape],
        action: Action::Exit,
        what: "leave lecture mode",
    },
];

/// A key's name as the README writes it.
pub fn key_name(key: Key) -> &'static str {
    match key {
        Key::PageDown => "Page Down",
        Key::PageUp => "Page Up",
        Key::ArrowRight => "→",
        Key::ArrowLeft => "←",
        Key::ArrowDown => "↓",
        Key::ArrowUp => "↑",
        Key::Space => "Space",
        Key::Period => ".",
        Key::Escape => "Esc",
        other => other.name(),
    }
}

/// The key table as Markdown rows (the README's "Running a lecture" table).
pub fn key_table() -> String {
    let mut table = String::from("| keys | what they do |\n|---|---|\n");
    for binding in LECTURE_KEYS {
        let keys: Vec<String> = binding
            .keys
            .iter()
            .map(|key| format!("`{}`", key_name(*key)))
            .collect();
        table.push_str(&format!("| {} | {} |\n", keys.join(", "), binding.what));
    }
    table
}

/// The colours of the whole app.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Theme {
    /// Light on dark (the default).
    #[default]
    Dark,
    /// Dark on light, for lit rooms.
    Light,
    /// Black on white with heavy lines, for washed-out projectors.
    HighContrast,
}

impl Theme {
    /// Every theme.
    pub const ALL: [Theme; 3] = [Theme::Dark, Theme::Light, Theme::HighContrast];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Theme::Dark => "dark",
            Theme::Light => "light",
            Theme::HighContrast => "high contrast",
        }
    }

    /// Its visuals.
    pub fn visuals(self) -> egui::Visuals {
        // Weak text (hints, footnotes) at 4.5:1 or more: egui's own is the text colour at 60 %,
        // 2.7:1 on the dark panels.
        let weak = |mut visuals: egui::Visuals, gray: u8| {
            visuals.weak_text_color = Some(Color32::from_gray(gray));
            visuals
        };
        match self {
            Theme::Dark => weak(egui::Visuals::dark(), 150),
            Theme::Light => weak(egui::Visuals::light(), 100),
            Theme::HighContrast => {
                let mut visuals = egui::Visuals::light();
                visuals.override_text_color = Some(Color32::BLACK);
                visuals.panel_fill = Color32::WHITE;
                visuals.window_fill = Color32::WHITE;
                visuals.extreme_bg_color = Color32::WHITE;
                visuals.faint_bg_color = Color32::from_gray(235);
                for widget in [
                    &mut visuals.widgets.noninteractive,
                    &mut visuals.widgets.inactive,
                    &mut visuals.widgets.hovered,
                    &mut visuals.widgets.active,
                    &mut visuals.widgets.open,
                ] {
                    widget.fg_stroke = egui::Stroke::new(2.0, Color32::BLACK);
                    widget.bg_stroke = egui::Stroke::new(1.5, Color32::BLACK);
                }
                // Text is black everywhere (override_text_color), selected text too: a light
                // blue behind it (13:1), not a dark one (black on dark blue was 2.7:1).
                visuals.selection.bg_fill = Color32::from_rgb(160, 200, 255);
                visuals.selection.stroke = egui::Stroke::new(2.0, Color32::BLACK);
                weak(visuals, 70)
            }
        }
    }
}

/// The screen a lecture lays its slides out on, in points, whatever the projector's pixels:
/// a slide fills a 1366×768 projector as it fills a 1920×1080 one (there at a zoom of 1.5, the
/// smallest text, 16 points, 24 pixels), so what carries its point is on screen at both.
pub const LECTURE_LAYOUT: egui::Vec2 = egui::vec2(1280.0, 720.0);

/// The zoom that fits [`LECTURE_LAYOUT`] to a screen of `unzoomed` points (its size at a
/// zoom of 1), times the lecturer's `scale` (Setup's text size, 1 by default).
pub fn lecture_zoom(unzoomed: egui::Vec2, scale: f32) -> f32 {
    let fit = (unzoomed.x / LECTURE_LAYOUT.x).min(unzoomed.y / LECTURE_LAYOUT.y);
    // A window too small to lecture from is still readable, if cramped.
    (fit * scale).max(0.75)
}

/// Text sizes in lecture mode, in points: the smallest is 16 (24 px on a 1920×1080 screen,
/// see [`LECTURE_LAYOUT`]).
pub fn lecture_text_styles(style: &mut egui::Style) {
    use egui::{FontFamily, FontId, TextStyle};
    for (text_style, size) in [
        (TextStyle::Small, 16.0),
        (TextStyle::Body, 18.0),
        (TextStyle::Button, 18.0),
        (TextStyle::Monospace, 17.0),
        (TextStyle::Heading, 26.0),
    ] {
        let family = if text_style == TextStyle::Monospace {
            FontFamily::Monospace
        } else {
            FontFamily::Proportional
        };
        style
            .text_styles
            .insert(text_style, FontId::new(size, family));
    }
    style.spacing.interact_size.y = 30.0;
    style.spacing.button_padding = egui::vec2(8.0, 4.0);
}

/// A lecture being given: its script, the slide, and the projector's settings.
pub struct Lecture {
    /// The script.
    pub script: LectureScript,
    /// The slide shown.
    pub slide: usize,
    /// The screen is blanked.
    pub blank: bool,
    /// The side panels are shown.
    pub panels: bool,
    /// The pointer is lit.
    pub pointer: bool,
    /// The lecturer's text size, relative to the slide fitted to the screen (see
    /// [`lecture_zoom`]).
    pub scale: f32,
    /// The last message: text and whether it reports a problem.
    pub message: Option<(String, bool)>,
    /// Where a lesson slide is to start, once the lesson knows its steps.
    pending: Option<StartStep>,
    /// A question slide: its quiz of one question (answered with the model answer as the
    /// lecturer reveals and moves on).
    question: Option<Session>,
    view: View2d,
    view3d: crate::view3d::View3d,
    tree: Option<SceneTree>,
    /// Whether full screen was asked for.
    pub full_screen: bool,
}

impl Lecture {
    /// A lecture through `script`, from its first slide.
    pub fn new(script: LectureScript) -> Self {
        Self {
            script,
            slide: 0,
            blank: false,
            panels: false,
            pointer: true,
            scale: 1.0,
            message: None,
            pending: None,
            question: None,
            view: View2d::default(),
            view3d: crate::view3d::View3d::default(),
            tree: None,
            full_screen: false,
        }
    }

    /// The slide shown.
    pub fn current(&self) -> &Slide {
        &self.script.slides[self.slide.min(self.script.slides.len() - 1)]
    }

    /// The inspector's parts the slide names (`panels code,tree`); empty: all of it.
    pub fn parts(&self) -> &[&'static str] {
        match self.current() {
            Slide::Lesson {
                panels: Panels::Only(parts),
                ..
            } => parts,
            _ => &[],
        }
    }

    /// The question of a question slide.
    pub fn question(&self) -> Option<&Session> {
        self.question.as_ref()
    }

    /// Where the question is, in words: `step 2 of 4`; for a build question, whose steps
    /// come as the tree grows, `node 3, 2 waiting`.
    pub fn question_step_text(&self) -> Option<String> {
        let session = self.question.as_ref()?;
        if let Some(exercise) = session.exercise() {
            let node = exercise.decided().len() + usize::from(!exercise.is_done());
            let waiting = exercise.waiting().saturating_sub(1);
            return Some(match (exercise.is_done(), waiting) {
                (true, _) => format!("all {} nodes decided", exercise.decided().len()),
                (false, 0) => format!("node {node}, none waiting"),
                (false, waiting) => format!("node {node}, {waiting} waiting"),
            });
        }
        let (step, count) = self.question_step()?;
        Some(format!("step {step} of {count}"))
    }

    /// On a question slide, the step shown (from 1) and how many the question has: the last
    /// once every step is done (after End, or coming back from the next slide).
    pub fn question_step(&self) -> Option<(usize, usize)> {
        let session = self.question.as_ref()?;
        let count = session.asks_of(0).len();
        let shown = if session.is_finished() {
            count
        } else {
            session.step() + 1
        };
        Some((shown.min(count), count))
    }

    /// Whether the question's answer is shown.
    pub fn revealed(&self) -> bool {
        self.question.as_ref().is_some_and(Session::is_revealed)
    }

    /// Where a lesson slide will start, until its lesson knows its steps.
    pub fn pending(&self) -> Option<StartStep> {
        self.pending
    }

    /// Takes the pending start of a lesson slide (the app applies it once the lesson's
    /// animation has its steps).
    pub fn take_pending(&mut self) -> Option<StartStep> {
        self.pending.take()
    }

    /// Opens slide `index`, at its first step or (going back) its last. Returns the lesson
    /// to show and the named ray or preset to put on it, for a lesson slide.
    pub fn open(&mut self, index: usize, at_end: bool) -> Option<(usize, Option<String>)> {
        self.slide = index.min(self.script.slides.len() - 1);
        self.blank = false;
        self.question = None;
        self.tree = None;
        self.view = View2d::default();
        match self.current().clone() {
            Slide::Lesson {
                index,
                step,
                show,
                panels,
            } => {
                self.pending = Some(if at_end { StartStep::End } else { step });
                // The panels the slide's point is in; I still turns them on or off.
                self.panels = panels.on();
                Some((index, show))
            }
            Slide::Question { kind, seed, level } => {
                self.pending = None;
                match Session::new(seed, level, 1, &[kind]) {
                    Ok(session) => {
                        self.tree = scene_tree(&session.questions()[0]);
                        self.question = Some(session);
                        if at_end {
                            self.question_to_last();
                        }
                    }
                    Err(error) => self.message = Some((error.to_string(), true)),
                }
                None
            }
        }
    }

    /// Reveals the question's answer: the model answer is given, so the explanation and what
    /// it lights in the canvas show.
    pub fn reveal(&mut self) {
        if let Some(session) = &mut self.question
            && !session.is_revealed()
            && let Some(response) = session.ask().map(|ask| model_response(&ask.expected))
        {
            session.answer(response);
        }
    }

    /// The question's next step (its answer given first, if the lecturer skipped revealing
    /// it); false when it has none left.
    fn question_next(&mut self) -> bool {
        self.reveal();
        self.question.as_mut().is_some_and(|session| {
            session.move_on();
            !session.is_finished()
        })
    }

    /// The question's asks, answered up to `steps` of them (not revealed); returns how many
    /// were answered (fewer when the question has fewer steps).
    fn question_at(&mut self, steps: usize) -> usize {
        let Some(session) = &self.question else {
            return 0;
        };
        let question = &session.questions()[0];
        let Ok(mut fresh) = Session::new(question.seed, question.level, 1, &[question.kind]) else {
            return 0;
        };
        let mut answered = 0;
        while answered < steps {
            let Some(response) = fresh.ask().map(|ask| model_response(&ask.expected)) else {
                break;
            };
            fresh.answer(response);
            fresh.move_on();
            answered += 1;
        }
        self.question = Some(fresh);
        answered
    }

    /// The question's last step, asked and its answer hidden (R reveals it): every step
    /// before it answered. (With every step answered there would be nothing left to reveal.)
    fn question_to_last(&mut self) {
        let steps = self.question_at(usize::MAX / 2);
        self.question_at(steps.saturating_sub(1));
    }

    /// What the app must do after an action.
    pub fn act(
        &mut self,
        action: Action,
        lesson: Option<&mut dyn crate::lesson::Lesson>,
    ) -> Outcome {
        if self.blank && action != Action::Blank {
            // As reveal.js: while blank, only the blank key does anything.
            return Outcome::Stay;
        }
        let animated = lesson
            .as_ref()
            .is_some_and(|lesson| lesson.caption().is_some());
        let timeline = lesson.map(|lesson| &mut lesson.stage_mut().timeline);
        match action {
            Action::Blank => {
                self.blank = !self.blank;
                Outcome::Stay
            }
            Action::Reveal => {
                self.reveal();
                Outcome::Stay
            }
            Action::FullScreen => {
                self.full_screen = !self.full_screen;
                Outcome::FullScreen(self.full_screen)
            }
            Action::Panels => {
                self.panels = !self.panels;
                Outcome::Stay
            }
            Action::Exit => Outcome::Exit,
            Action::Next => {
                if self.question.is_some() {
                    if self.question_next() {
                        return Outcome::Stay;
                    }
                } else if let Some(timeline) = timeline.filter(|_| animated)
                    && timeline.shown < timeline.len
                {
                    timeline.playing = false;
                    timeline.step_forward();
                    return Outcome::Stay;
                }
                if self.slide + 1 < self.script.slides.len() {
                    Outcome::Open(self.slide + 1, false)
                } else {
                    Outcome::Stay
                }
            }
            Action::Previous => {
                if let Some(session) = &self.question {
                    // Revealed: back to the same step, hidden; else to the step before.
                    let done = session.answered();
                    if done > 0 {
                        self.question_at(done - 1);
                        return Outcome::Stay;
                    }
                } else if let Some(timeline) = timeline.filter(|_| animated)
                    && timeline.shown > 0
                {
                    timeline.playing = false;
                    timeline.step_back();
                    return Outcome::Stay;
                }
                if self.slide > 0 {
                    Outcome::Open(self.slide - 1, true)
                } else {
                    Outcome::Stay
                }
            }
            Action::First => {
                if self.question.is_some() {
                    self.question_at(0);
                } else if let Some(timeline) = timeline {
                    timeline.playing = false;
                    timeline.rewind();
                }
                Outcome::Stay
            }
            Action::Last => {
                if self.question.is_some() {
                    self.question_to_last();
                } else if let Some(timeline) = timeline {
                    timeline.playing = false;
                    timeline.shown = timeline.len;
                }
                Outcome::Stay
            }
        }
    }

    /// The lecture keys pressed this frame, taken from egui so no widget also acts on them.
    pub fn pressed(ui: &Ui) -> Vec<Action> {
        ui.input_mut(|input| {
            let mut actions = Vec::new();
            for binding in LECTURE_KEYS {
                for key in binding.keys {
                    // Every press, not one a frame: a clicker pressed quickly on a slow
                    // machine sends several before the next frame.
                    let presses = input.count_and_consume_key(egui::Modifiers::NONE, *key);
                    actions.extend(std::iter::repeat_n(binding.action, presses));
                }
            }
            actions
        })
    }

    /// A question slide: the figure on the left, the question on the right, the answer and
    /// explanation only once revealed.
    pub fn question_ui(&mut self, ui: &mut Ui) {
        let Some(session) = &self.question else {
            return;
        };
        let question = &session.questions()[0];
        let revealed = session.is_revealed();
        let ask = session.ask().or_else(|| session.asks_of(0).last());
        let frame = ask.map_or(0, |ask| {
            if revealed {
                ask.highlight.frame.unwrap_or(ask.frame)
            } else {
                ask.frame
            }
        });
        egui::Panel::right("lecture question")
            .resizable(false)
            // Half the width, less a little: the figure stays large, and a line of the
            // numbers (a kD node's box, cut and children) stays on one line.
            .exact_size((ui.available_width() * 0.48).max(320.0))
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    ui.label(RichText::new(&question.prompt).size(20.0));
                    ui.add_space(10.0);
                    let Some(ask) = ask else {
                        return;
                    };
                    ui.label(RichText::new(&ask.prompt).strong().size(24.0));
                    if let Expected::Number { tolerance, .. } = ask.expected {
                        ui.label(
                            RichText::new(format!(
                                "A number, {}",
                                crate::quiz::tolerance_text(tolerance)
                            ))
                            .size(18.0),
                        );
                    }
                    ui.add_space(8.0);
                    let correct = ask.expected.correct_option();
                    for (index, option) in ask.expected.options().iter().enumerate() {
                        let text =
                            format!("({}) {}", accelviz_quiz::option_letter(index), option.label);
                        let right = revealed && correct == Some(index);
                        let text = if right {
                            RichText::new(text)
                                .size(20.0)
                                .strong()
                                .color(crate::canvas::readable(ui, palette::HIT))
                        } else {
                            RichText::new(text).size(20.0)
                        };
                        ui.label(text);
                    }
                    // The answer right below the options, where the class is looking; the
                    // numbers after it, those this step names first (they stay on screen
                    // at 1280 × 720 points; the rest may scroll).
                    ui.add_space(10.0);
                    if revealed {
                        if let Expected::Number { .. } = ask.expected {
                            ui.label(
                                RichText::new(format!("Answer: {}", ask.expected.model_answer()))
                                    .size(22.0)
                                    .strong()
                                    .color(crate::canvas::readable(ui, palette::HIT)),
                            );
                        }
                        ui.label(RichText::new(&ask.explanation).size(19.0));
                    } else {
                        ui.label(
                            RichText::new("Press R to reveal the answer.")
                                .size(18.0)
                                .weak(),
                        );
                    }
                    ui.add_space(10.0);
                    let step = session.step().min(question.asks.len().saturating_sub(1));
                    let (named, rest) = question.numbers_named_by(step);
                    crate::quiz::numbers_ui(ui, &named, Some(18.0));
                    if !rest.is_empty() {
                        egui::CollapsingHeader::new(RichText::new("The other numbers").size(16.0))
                            .id_salt("the other numbers")
                            .default_open(true)
                            .show(ui, |ui| {
                                for line in &rest {
                                    ui.label(RichText::new(line).size(16.0));
                                }
                            });
                    }
                });
            });
        let state = FigureState {
            question,
            ask,
            revealed,
            frame,
            exercise: session.exercise(),
            tree: self.tree.as_ref(),
            picked: None,
        };
        egui::CentralPanel::default().show(ui, |ui| {
            figure_ui(ui, &mut self.view, &mut self.view3d, &state);
        });
    }
}

/// What the app does after a lecture action.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Nothing more.
    Stay,
    /// Open slide `0`, at its end if `1`.
    Open(usize, bool),
    /// Full screen on or off.
    FullScreen(bool),
    /// Leave lecture mode.
    Exit,
}

/// The model answer to a step, as a response.
fn model_response(expected: &Expected) -> Response {
    match expected {
        Expected::Number { value, .. } => Response::Number(*value),
        choice => Response::Choice(choice.correct_option().unwrap_or(0)),
    }
}

/// Paints the screen black (a blanked projector).
pub fn paint_blank(ctx: &egui::Context) {
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Foreground,
        egui::Id::unique("lecture blank"),
    ));
    painter.rect_filled(ctx.content_rect().expand(4.0), 0.0, Color32::BLACK);
}

/// A ring around the pointer, visible from the back of a hall.
pub fn paint_pointer(ctx: &egui::Context) {
    let Some(at) = ctx.pointer_latest_pos() else {
        return;
    };
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Tooltip,
        egui::Id::unique("lecture pointer"),
    ));
    painter.circle(
        at,
        22.0,
        Color32::from_rgba_unmultiplied(255, 40, 40, 50),
        egui::Stroke::new(3.0, Color32::from_rgb(255, 60, 60)),
    );
}
