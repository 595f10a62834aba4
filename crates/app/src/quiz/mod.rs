//! Quiz mode: the questions of a seed (the quiz engine, `accelviz-quiz`, shared with
//! `accelviz-cli quiz`), asked a step at a time beside their figure, graded at once, with the
//! explanation and the answer lit in the canvas; score, streak, and a review of mistakes in
//! which the student steps back and forth through the model answer.
//!
//! Every control is an ordinary labelled widget (buttons for choices, a text field for
//! numbers), so Tab, Space and Enter take a quiz without a mouse; letters pick a choice and
//! Enter moves on, as shortcuts. Progress is saved after every answer ([`store`]).

pub mod figure;
pub mod store;

use accelviz_quiz::{Expected, Level, Outcome, Response, Session, Verdict, option_letter};
use egui::{Color32, Key, RichText, Ui};

use crate::canvas::{View2d, palette, readable};
use crate::stage::SceneTree;
use figure::{FigureState, figure_ui, scene_tree};
use store::{Loaded, ProgressStore};

/// How many questions a quiz has unless the student asks for more or fewer: one of each kind.
pub const DEFAULT_COUNT: usize = accelviz_quiz::KINDS.len();

/// The mistake being reviewed, and how far through its model answer.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Review {
    /// Its place in the list of mistakes.
    mistake: usize,
    /// Traversal steps shown.
    frame: usize,
}

/// The quiz: its session, where it is saved, and what the panel is editing.
pub struct QuizMode {
    session: Option<Session>,
    store: ProgressStore,
    loaded: bool,
    /// The seed field.
    pub seed_text: String,
    /// The level chosen for the next quiz.
    pub level: Level,
    /// Questions in the next quiz.
    pub count: usize,
    /// The number being typed.
    pub number_text: String,
    /// Why the number typed could not be read, said under its field (which keeps the focus).
    number_problem: Option<String>,
    /// The step whose number field has been given focus (focus is given once per step).
    focused_step: Option<(usize, usize)>,
    /// The step whose "Next" button has been given focus.
    next_focused: Option<(usize, usize)>,
    /// "New quiz" was pressed while a quiz with answers was under way: it asks first.
    pub confirm_new: bool,
    /// The last message: text and whether it reports a problem.
    pub message: Option<(String, bool)>,
    view: View2d,
    view3d: crate::view3d::View3d,
    /// The question the view and the tree were made for.
    shown: Option<usize>,
    tree: Option<SceneTree>,
    review: Option<Review>,
}

impl QuizMode {
    /// A quiz saved where the platform keeps it.
    pub fn new() -> Self {
        Self::with_store(ProgressStore::platform())
    }

    /// A quiz saved in `store`.
    pub fn with_store(store: ProgressStore) -> Self {
        Self {
            session: None,
            store,
            loaded: false,
            seed_text: "1".into(),
            level: Level::Easy,
            count: DEFAULT_COUNT,
            number_text: String::new(),
            number_problem: None,
            focused_step: None,
            confirm_new: false,
            next_focused: None,
            message: None,
            view: View2d::default(),
            view3d: crate::view3d::View3d::default(),
            shown: None,
            tree: None,
            review: None,
        }
    }

    /// The quiz being taken (after the first frame shown, or a start).
    pub fn session(&self) -> Option<&Session> {
        self.session.as_ref()
    }

    /// Where the quiz is, for the log and the title: the seed, question, step, what the step
    /// wants (so a test driving the page by keys knows what to press: a letter for a choice,
    /// digits for a number) and the score.
    pub fn position(&self) -> crate::position::Position {
        let line = self.session().map_or_else(
            || "accelviz: quiz".to_owned(),
            |session| {
                if session.is_finished() {
                    return format!(
                        "accelviz: quiz seed {}, done, score {} of {}",
                        session.seed(),
                        session.score(),
                        session.answered()
                    );
                }
                let wants = match session.ask().map(|ask| &ask.expected) {
                    Some(accelviz_quiz::Expected::Number { .. }) => "a number",
                    Some(_) => "a choice",
                    None => "nothing",
                };
                let shown = if session.is_revealed() { ", answered" } else { "" };
                format!(
                    "accelviz: quiz seed {}, question {} of {}, step {} ({wants}{shown}), score {} of {}",
                    session.seed(),
                    (session.position() + 1).min(session.questions().len()),
                    session.questions().len(),
                    session.step() + 1,
                    session.score(),
                    session.answered()
                )
            },
        );
        crate::position::Position {
            title: line.trim_start_matches("accelviz: ").to_owned(),
            line,
        }
    }

    /// In the review of mistakes: which mistake, and how many steps of its model answer are
    /// shown.
    pub fn review(&self) -> Option<(usize, usize)> {
        self.review.map(|review| (review.mistake, review.frame))
    }

    /// Where progress is kept.
    pub fn store(&self) -> &ProgressStore {
        &self.store
    }

    /// Reads the saved quiz the first time the quiz is shown, or starts the default one.
    pub fn ensure_loaded(&mut self) {
        if self.loaded {
            return;
        }
        self.loaded = true;
        match self.store.load() {
            Loaded::Quiz(session) => {
                self.seed_text = session.seed().to_string();
                self.level = session.level();
                self.count = session.questions().len();
                self.message = Some((
                    format!(
                        "Carrying on with the quiz of seed {}, question {} of {}.",
                        session.seed(),
                        (session.position() + 1).min(session.questions().len()),
                        session.questions().len()
                    ),
                    false,
                ));
                self.session = Some(*session);
            }
            Loaded::SetAside(problem) => {
                self.message = Some((problem, true));
                self.start_quiz(false);
            }
            Loaded::Nothing => self.start_quiz(false),
        }
    }

    /// Starts the quiz the fields describe, replacing any other (and its saved progress).
    pub fn start(&mut self) {
        self.start_quiz(true);
    }

    /// Starts the quiz the fields describe, or, while a quiz with answers is under way, asks
    /// first (see [`confirm_new`](Self::confirm_new)).
    pub fn start_or_ask(&mut self) {
        let under_way = self
            .session
            .as_ref()
            .is_some_and(|session| session.answered() > 0 && !session.is_finished());
        if under_way {
            self.confirm_new = true;
        } else {
            self.start();
        }
    }

    fn start_quiz(&mut self, say_so: bool) {
        self.loaded = true;
        let Ok(seed) = self.seed_text.trim().parse::<u64>() else {
            self.message = Some((
                format!(
                    "The seed must be a whole number from 0 to {}; '{}' is not.",
                    u64::MAX,
                    self.seed_text.trim()
                ),
                true,
            ));
            return;
        };
        match Session::new(seed, self.level, self.count.clamp(1, 99), &[]) {
            Ok(session) => {
                self.session = Some(session);
                self.review = None;
                // The canvas makes its view and tree again for the new questions, and the
                // first step's answer takes the focus again.
                self.shown = None;
                self.focused_step = None;
                self.next_focused = None;
                self.number_text.clear();
                self.number_problem = None;
                if say_so {
                    self.message = Some((
                        format!(
                            "A new quiz: seed {seed}, {}, {} questions.",
                            self.level.name(),
                            self.count
                        ),
                        false,
                    ));
                }
                self.save();
            }
            Err(error) => self.message = Some((error.to_string(), true)),
        }
    }

    fn save(&mut self) {
        let Some(session) = &self.session else {
            return;
        };
        if let Err(problem) = self.store.save(&session.progress()) {
            self.message = Some((
                format!("Progress could not be saved: {problem}. The quiz goes on."),
                true,
            ));
        }
    }

    /// Answers the current step, and saves.
    pub fn answer(&mut self, response: Response) -> Option<Verdict> {
        let outcome = self.session.as_mut()?.answer(response);
        let Outcome::Graded(verdict) = outcome else {
            return None;
        };
        self.save();
        Some(verdict)
    }

    /// Moves on after an answer, and saves.
    pub fn move_on(&mut self) -> bool {
        let moved = self.session.as_mut().is_some_and(Session::move_on);
        if moved {
            self.number_text.clear();
            self.number_problem = None;
            // A note on how the quiz began ("carrying on with question 4") is out of date
            // once the quiz moves on; a problem stays until something replaces it.
            if self.message.as_ref().is_some_and(|(_, problem)| !problem) {
                self.message = None;
            }
            self.save();
        }
        moved
    }

    /// Keyboard shortcuts: a letter picks a choice, Enter moves on once answered; in the
    /// review, the arrows step through the model answer. Not while a text field has the keys.
    pub fn handle_keys(&mut self, ui: &Ui) {
        // Typing a number or a seed takes the keys; a focused button does not (Tab and Enter
        // still work on it as ever).
        if ui.ctx().text_edit_focused() {
            return;
        }
        let Some(session) = &self.session else {
            return;
        };
        if let Some(review) = self.review {
            let (back, forward) = ui.input(|input| {
                (
                    input.key_pressed(Key::ArrowLeft),
                    input.key_pressed(Key::ArrowRight),
                )
            });
            let frames = self.review_frames(review.mistake);
            if let Some(review) = &mut self.review {
                if back {
                    review.frame = review.frame.saturating_sub(1);
                }
                if forward {
                    review.frame = (review.frame + 1).min(frames);
                }
            }
            return;
        }
        if session.is_revealed() {
            if ui.input(|input| input.key_pressed(Key::Enter)) {
                self.move_on();
            }
            return;
        }
        let Some(ask) = session.ask() else {
            return;
        };
        let options = ask.expected.options().len();
        let letter = ui.input(|input| {
            (0..options.min(26)).find(|index| {
                letter_key(*index)
                    .is_some_and(|key| input.key_pressed(key) && input.modifiers.is_none())
            })
        });
        if let Some(index) = letter {
            self.answer(Response::Choice(index));
        }
    }

    /// How many steps the model answer of mistake `index` has.
    fn review_frames(&self, index: usize) -> usize {
        let Some(session) = &self.session else {
            return 0;
        };
        session
            .mistakes()
            .get(index)
            .and_then(|mistake| session.questions().get(mistake.question))
            .and_then(|question| match &question.figure {
                accelviz_quiz::Figure::Scene(scene) => scene.tree.as_ref().map(|t| t.steps.len()),
                accelviz_quiz::Figure::Grid(grid) => Some(grid.walked.len()),
                _ => None,
            })
            .unwrap_or(0)
    }

    /// The question the canvas shows: the current one, or the one reviewed.
    fn shown_question(&self) -> Option<usize> {
        let session = self.session.as_ref()?;
        match self.review {
            Some(review) => session.mistakes().get(review.mistake).map(|m| m.question),
            None => (!session.is_finished()).then(|| session.position()),
        }
    }

    /// The canvas: the question's figure, paused at the step asked (or, in the review, where
    /// the student has stepped to).
    pub fn canvas_ui(&mut self, ui: &mut Ui) {
        self.ensure_loaded();
        let Some(index) = self.shown_question() else {
            if let Some(session) = &self.session {
                finished_canvas_ui(ui, session);
            }
            return;
        };
        if self.shown != Some(index) {
            self.shown = Some(index);
            self.view = View2d::default();
            self.tree = self
                .session
                .as_ref()
                .and_then(|session| scene_tree(&session.questions()[index]));
        }
        let Some(session) = &self.session else {
            return;
        };
        let question = &session.questions()[index];
        let (ask, revealed, frame, exercise, response) = match self.review {
            Some(review) => {
                let mistake = session.mistakes()[review.mistake];
                let ask = session.asks_of(mistake.question).get(mistake.step);
                (ask, true, review.frame, None, Some(mistake.response))
            }
            None => {
                let ask = session.ask();
                let revealed = session.is_revealed();
                let frame = ask.map_or(0, |ask| {
                    if revealed {
                        ask.highlight.frame.unwrap_or(ask.frame)
                    } else {
                        ask.frame
                    }
                });
                let response = session.verdict().map(|verdict| verdict.response);
                (ask, revealed, frame, session.exercise(), response)
            }
        };
        let state = FigureState {
            question,
            ask,
            revealed,
            frame,
            exercise,
            tree: self.tree.as_ref(),
            picked: match response {
                Some(Response::Choice(chosen)) => Some(chosen),
                _ => None,
            },
        };
        let picked = figure_ui(ui, &mut self.view, &mut self.view3d, &state);
        if let Some(option) = picked {
            self.answer(Response::Choice(option));
        }
    }

    /// The panel: the quiz's settings, the step asked with its answer controls, the verdict
    /// and explanation, the score; the review once the quiz is done.
    pub fn panel_ui(&mut self, ui: &mut Ui) {
        self.ensure_loaded();
        ui.heading("Quiz");
        ui.label(
            RichText::new(
                "Predict each step, then see why. The same seed gives the same quiz everywhere: share it with a class.",
            )
            .weak(),
        );
        ui.add_space(4.0);
        self.settings_ui(ui);
        if let Some((message, problem)) = &self.message {
            let color = if *problem {
                palette::MISS
            } else {
                ui.visuals().weak_text_color()
            };
            ui.colored_label(crate::canvas::readable(ui, color), message);
        }
        ui.separator();
        let Some(session) = &self.session else {
            return;
        };
        if self.review.is_some() {
            self.review_ui(ui);
            return;
        }
        if session.is_finished() {
            self.finished_ui(ui);
            return;
        }
        self.step_ui(ui);
    }

    fn settings_ui(&mut self, ui: &mut Ui) {
        egui::Grid::new("quiz settings")
            .num_columns(2)
            .spacing([8.0, 6.0])
            .show(ui, |ui| {
                let label = ui.label("Seed");
                let seed = egui::TextEdit::singleline(&mut self.seed_text)
                    .desired_width(120.0)
                    .hint_text("a whole number");
                let seed = ui
                    .add(seed)
                    .labelled_by(label.id)
                    .on_hover_text("The quiz's seed: type the one your lecturer gives");
                if seed.lost_focus() && ui.input(|input| input.key_pressed(Key::Enter)) {
                    self.start_or_ask();
                }
                ui.end_row();
                ui.label("Level");
                ui.horizontal(|ui| {
                    for level in Level::ALL {
                        ui.selectable_value(&mut self.level, level, level.name());
                    }
                });
                ui.end_row();
                let label = ui.label("Questions");
                ui.add(egui::DragValue::new(&mut self.count).range(1..=99))
                    .labelled_by(label.id);
                ui.end_row();
            });
        if self.confirm_new {
            // A quiz with answers is not thrown away by one click.
            let progress = self.session.as_ref().map_or_else(String::new, |session| {
                format!(
                    " (question {} of {}, {})",
                    (session.position() + 1).min(session.questions().len()),
                    session.questions().len(),
                    Self::score_line(session).to_lowercase()
                )
            });
            ui.colored_label(
                crate::canvas::readable(ui, palette::RAY),
                format!("A new quiz replaces the one under way{progress}."),
            );
            ui.horizontal(|ui| {
                if ui.button("Replace it").clicked() {
                    self.confirm_new = false;
                    self.start();
                }
                if ui.button("Keep it").clicked() {
                    self.confirm_new = false;
                }
            });
        } else if ui
            .button("New quiz")
            .on_hover_text(
                "Start the quiz of this seed and level (asks first if a quiz is under way)",
            )
            .clicked()
        {
            self.start_or_ask();
        }
    }

    fn score_line(session: &Session) -> String {
        format!(
            "Score {} of {} · streak {} (best {})",
            session.score(),
            session.answered(),
            session.streak(),
            session.best_streak()
        )
    }

    fn step_ui(&mut self, ui: &mut Ui) {
        let Some(session) = &self.session else {
            return;
        };
        let question = session.question();
        let title = accelviz_quiz::KINDS
            .iter()
            .find(|entry| entry.name == question.kind)
            .map_or(question.kind, |entry| entry.title);
        ui.label(
            RichText::new(format!(
                "Question {} of {} · {title}",
                session.position() + 1,
                session.questions().len()
            ))
            .strong(),
        );
        ui.label(RichText::new(Self::score_line(session)).weak());
        ui.add_space(4.0);
        ui.label(&question.prompt);
        ui.add_space(6.0);
        // The step and its answers first, the numbers under them: a long list (a kD-tree's
        // every cell) would otherwise push the answers below the window.
        let numbers = question.numbers(session.step());
        let Some(ask) = session.ask().cloned() else {
            numbers_ui(ui, &numbers, None);
            return;
        };
        let place = (session.position(), session.step());
        let verdict = session.is_revealed().then(|| session.verdict().copied());
        ui.label(RichText::new(&ask.prompt).strong().size(15.0));
        ui.add_space(4.0);
        match verdict {
            Some(verdict) => self.verdict_ui(ui, &ask, verdict),
            None => self.answers_ui(ui, &ask, place),
        }
        ui.add_space(6.0);
        numbers_ui(ui, &numbers, None);
    }

    /// The step's answers: a number field, or its options (buttons, letters, or the node or
    /// shape clicked in the canvas or the tree).
    fn answers_ui(&mut self, ui: &mut Ui, ask: &accelviz_quiz::Ask, place: (usize, usize)) {
        match &ask.expected {
            Expected::Number { tolerance, .. } => {
                let mut submit = false;
                let within = *tolerance;
                let field = ui
                    .horizontal(|ui| {
                        let label = ui.label("Your answer:");
                        let field = ui
                            .add(
                                egui::TextEdit::singleline(&mut self.number_text)
                                    .desired_width(110.0)
                                    .hint_text("a number"),
                            )
                            .labelled_by(label.id);
                        if self.focused_step != Some(place) {
                            self.focused_step = Some(place);
                            field.request_focus();
                        }
                        if field.lost_focus() && ui.input(|input| input.key_pressed(Key::Enter)) {
                            submit = true;
                        }
                        if field.changed() {
                            self.number_problem = None;
                        }
                        ui.label(tolerance_text(within))
                            .on_hover_text("How far from the exact value an answer may be");
                        if ui.button("Check").clicked() {
                            submit = true;
                        }
                        field
                    })
                    .inner;
                if submit {
                    match parse_number(&self.number_text) {
                        Some(value) => {
                            self.answer(Response::Number(value));
                        }
                        None => {
                            // Said by the field, which keeps the focus: Enter had taken it
                            // away, and a keyboard user could not type again.
                            self.number_problem = Some(format!(
                                "'{}' is not a number: type one, such as 2.5",
                                self.number_text.trim()
                            ));
                            field.request_focus();
                        }
                    }
                }
                if let Some(problem) = &self.number_problem {
                    ui.colored_label(readable(ui, palette::MISS), problem);
                }
            }
            expected => {
                let options = expected.options();
                if options
                    .iter()
                    .any(|option| option.node.is_some() || option.shape.is_some())
                {
                    ui.label(
                        RichText::new("Pick below, press its letter, or click it in the canvas.")
                            .weak(),
                    );
                }
                ui.with_layout(egui::Layout::top_down_justified(egui::Align::LEFT), |ui| {
                    for (index, option) in options.iter().enumerate() {
                        let text = format!("({}) {}", option_letter(index), option.label);
                        // An id of its own, so the focus given stays on it as the panel
                        // above changes from frame to frame.
                        let button = ui
                            .push_id(("quiz answer", place, index), |ui| {
                                ui.add(egui::Button::new(text).wrap())
                            })
                            .inner;
                        // The first answer takes the focus once per step, so Tab goes on to
                        // the next answer and Space picks one (not a lesson of the list).
                        if index == 0 && self.focused_step != Some(place) {
                            self.focused_step = Some(place);
                            button.request_focus();
                            button.scroll_to_me(None);
                        }
                        if button.clicked() {
                            self.answer(Response::Choice(index));
                        }
                    }
                });
                // Nodes can be picked in the tree too, as the lessons' trees are clicked.
                if options.iter().any(|option| option.node.is_some())
                    && let Some(node) = self.tree_ui(ui, ask.frame)
                    && let Some(index) = options.iter().position(|option| option.node == Some(node))
                {
                    self.answer(Response::Choice(index));
                }
            }
        }
    }

    /// The question's tree as a diagram (nodes named by path, coloured by the traversal's
    /// steps shown so far); the node clicked, if any.
    fn tree_ui(&self, ui: &mut Ui, frame: usize) -> Option<u32> {
        let tree = self.tree.as_ref()?;
        let session = self.session.as_ref()?;
        let accelviz_quiz::Figure::Scene(scene) = &session.question().figure else {
            return None;
        };
        let steps = scene.tree.as_ref().map_or(&[][..], |figure| {
            &figure.steps[..frame.min(figure.steps.len())]
        });
        ui.add_space(6.0);
        ui.label(RichText::new("The tree (click a node):").weak());
        let facts = &tree.built.facts;
        let label = |node: u32| accelviz_quiz::node_label(facts, node);
        let (mut hovered, mut selected) = (None, None);
        crate::views::tree_diagram::diagram_ui(
            ui,
            facts,
            &label,
            steps,
            &mut hovered,
            &mut selected,
            false,
        );
        selected
    }

    fn verdict_ui(&mut self, ui: &mut Ui, ask: &accelviz_quiz::Ask, verdict: Option<Verdict>) {
        let right = verdict.is_some_and(|verdict| verdict.correct);
        if right {
            ui.colored_label(
                crate::canvas::readable(ui, palette::HIT),
                RichText::new("Right.").strong().size(16.0),
            );
        } else {
            let given = verdict.map_or_else(String::new, |verdict| {
                format!(" You said {}.", ask.expected.describe(&verdict.response))
            });
            ui.colored_label(
                crate::canvas::readable(ui, palette::MISS),
                RichText::new(format!("Not quite.{given}"))
                    .strong()
                    .size(16.0),
            );
            ui.label(format!("The answer: {}", ask.expected.model_answer()));
        }
        if let Expected::Costed { costs, .. } = &ask.expected
            && let Some(verdict) = verdict
            && let Response::Choice(picked) = verdict.response
            && let Some(cost) = costs.get(picked)
        {
            ui.label(format!("Your pick costs {}.", accelviz_quiz::num(*cost)));
            if let Some((choice, picked)) = self
                .session
                .as_ref()
                .and_then(Session::exercise)
                .and_then(|exercise| {
                    exercise
                        .decided()
                        .iter()
                        .rev()
                        .find(|(c, _)| c.picks.len() > 1)
                })
            {
                build_costs_ui(ui, choice, *picked);
            }
        }
        ui.add_space(4.0);
        ui.label(&ask.explanation);
        if let Some(exercise) = self.session.as_ref().and_then(Session::exercise)
            && exercise.is_done()
        {
            let score = exercise.score();
            ui.add_space(4.0);
            ui.label(
                RichText::new(format!(
                    "Your tree's SAH cost: {}; the SAH builder's: {}. Score {:.0} %.",
                    accelviz_quiz::num(score.student_cost),
                    accelviz_quiz::num(score.builder_cost),
                    100.0 * score.ratio
                ))
                .strong(),
            );
        }
        ui.add_space(8.0);
        let next = ui.button(RichText::new("Next").size(15.0));
        // Enter or Space on the focused button moves on; focused once per step, so Tab can
        // still leave it.
        let place = self
            .session
            .as_ref()
            .map(|session| (session.position(), session.step()));
        if self.next_focused != place && !ui.ctx().text_edit_focused() {
            self.next_focused = place;
            next.request_focus();
        }
        if next.clicked() {
            self.move_on();
        }
    }

    fn finished_ui(&mut self, ui: &mut Ui) {
        let Some(session) = &self.session else {
            return;
        };
        let total = session.answered().max(1);
        ui.label(
            RichText::new(format!(
                "Quiz done: {} of {} steps right ({:.0} %), best streak {}.",
                session.score(),
                session.answered(),
                100.0 * session.score() as f64 / total as f64,
                session.best_streak()
            ))
            .strong()
            .size(16.0),
        );
        let mistakes = session.mistakes();
        if mistakes.is_empty() {
            ui.label("No mistakes to review.");
            return;
        }
        ui.add_space(6.0);
        ui.label(RichText::new("Review your mistakes").strong());
        let mut open = None;
        ui.with_layout(egui::Layout::top_down_justified(egui::Align::LEFT), |ui| {
            for (index, mistake) in mistakes.iter().enumerate() {
                let ask = &session.asks_of(mistake.question)[mistake.step];
                let text = format!(
                    "Question {}, step {}: {}",
                    mistake.question + 1,
                    mistake.step + 1,
                    ask.prompt
                );
                if ui.add(egui::Button::new(text).wrap()).clicked() {
                    open = Some(index);
                }
            }
        });
        if let Some(index) = open {
            self.open_review(index);
        }
    }

    /// Opens the review of mistake `index`, at the step where it was made.
    pub fn open_review(&mut self, index: usize) {
        let Some(session) = &self.session else {
            return;
        };
        let Some(mistake) = session.mistakes().get(index).copied() else {
            return;
        };
        let ask = &session.asks_of(mistake.question)[mistake.step];
        let frame = ask.highlight.frame.unwrap_or(ask.frame);
        self.review = Some(Review {
            mistake: index,
            frame,
        });
    }

    fn review_ui(&mut self, ui: &mut Ui) {
        let (Some(session), Some(review)) = (&self.session, self.review) else {
            return;
        };
        let mistakes = session.mistakes();
        let Some(mistake) = mistakes.get(review.mistake).copied() else {
            self.review = None;
            return;
        };
        let ask = session.asks_of(mistake.question)[mistake.step].clone();
        ui.label(
            RichText::new(format!(
                "Mistake {} of {}: question {}, step {}",
                review.mistake + 1,
                mistakes.len(),
                mistake.question + 1,
                mistake.step + 1
            ))
            .strong(),
        );
        ui.label(RichText::new(&ask.prompt).strong());
        ui.colored_label(
            crate::canvas::readable(ui, palette::MISS),
            format!("You said {}.", ask.expected.describe(&mistake.response)),
        );
        ui.colored_label(
            crate::canvas::readable(ui, palette::HIT),
            format!("The answer: {}", ask.expected.model_answer()),
        );
        ui.label(&ask.explanation);
        let frames = self.review_frames(review.mistake);
        if frames > 0 {
            ui.add_space(6.0);
            ui.label(
                RichText::new("The model answer, step by step (the left and right arrow keys):")
                    .weak(),
            );
            let mut frame = review.frame;
            let position = ui
                .horizontal(|ui| {
                    if ui.button("Step back").clicked() {
                        frame = frame.saturating_sub(1);
                    }
                    if ui.button("Step forward").clicked() {
                        frame = (frame + 1).min(frames);
                    }
                    ui.label(format!("step {frame} of {frames}"))
                })
                .inner;
            ui.add(egui::Slider::new(&mut frame, 0..=frames).show_value(false))
                .labelled_by(position.id);
            if let Some(review) = &mut self.review {
                review.frame = frame;
            }
        }
        ui.add_space(8.0);
        ui.horizontal(|ui| {
            if review.mistake > 0 && ui.button("Previous mistake").clicked() {
                self.open_review(review.mistake - 1);
            }
            if review.mistake + 1 < mistakes.len() && ui.button("Next mistake").clicked() {
                self.open_review(review.mistake + 1);
            }
            if ui.button("Back to the score").clicked() {
                self.review = None;
            }
        });
    }
}

impl Default for QuizMode {
    fn default() -> Self {
        Self::new()
    }
}

/// Every option of a build step on its axis's cost curve, the leaf's cost as a level, the
/// builder's pick and the student's marked: how far from the best the pick was, and why.
fn build_costs_ui(ui: &mut Ui, choice: &accelviz_quiz::NodeChoice, picked: usize) {
    use egui_plot::{HLine, Legend, Plot, Points};
    let per_axis = |wanted: usize| -> Vec<[f64; 2]> {
        choice
            .picks
            .iter()
            .zip(&choice.costs)
            .filter_map(|(pick, cost)| match pick {
                accelviz_quiz::Pick::Split { axis, position } if *axis == wanted => {
                    Some([*position, *cost])
                }
                _ => None,
            })
            .collect()
    };
    let point = |index: usize| match choice.picks[index] {
        accelviz_quiz::Pick::Split { position, .. } => Some([position, choice.costs[index]]),
        accelviz_quiz::Pick::Leaf => None,
    };
    let (low, high) = choice
        .costs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), cost| {
            (low.min(*cost), high.max(*cost))
        });
    let plot_bg = ui.visuals().extreme_bg_color;
    Plot::new(("build costs", choice.path.as_str()))
        .height(220.0)
        // Headroom above the points for the legend.
        .include_y(high + (high - low).max(0.5) * 1.2)
        .include_y(low - (high - low).max(0.5) * 0.1)
        .legend(Legend::default().position(egui_plot::Corner::RightTop))
        .x_axis_label("split position")
        .y_axis_label("SAH cost")
        .allow_scroll(false)
        .allow_drag(false)
        .allow_zoom(false)
        .show(ui, |plot| {
            for axis in 0..2 {
                plot.points(
                    Points::new(format!("splits on {}", ["x", "y"][axis]), per_axis(axis))
                        .radius(3.0)
                        .color(crate::canvas::ink_on(palette::AXES[axis], plot_bg)),
                );
            }
            plot.hline(HLine::new("keep a leaf", choice.costs[0]).color(Color32::GRAY));
            if let Some(best) = point(choice.builder) {
                plot.points(
                    Points::new("the builder's pick", vec![best])
                        .radius(7.0)
                        .color(crate::canvas::ink_on(palette::HIT, plot_bg)),
                );
            } else {
                plot.hline(
                    HLine::new("the builder keeps a leaf", choice.costs[0])
                        .color(crate::canvas::ink_on(palette::HIT, plot_bg)),
                );
            }
            if let Some(mine) = point(picked) {
                plot.points(
                    Points::new("your pick", vec![mine])
                        .radius(5.0)
                        .color(crate::canvas::ink_on(palette::RAY, plot_bg)),
                );
            }
        });
}

/// The key of the letter that picks option `index` (`A` for the first).
pub fn letter_key(index: usize) -> Option<Key> {
    Key::from_name(&option_letter(index).to_ascii_uppercase().to_string())
}

/// A typed number: a decimal point or comma, an optional minus (or the − sign).
fn parse_number(text: &str) -> Option<f64> {
    let cleaned = text.trim().replace(',', ".").replace('−', "-");
    cleaned
        .parse::<f64>()
        .ok()
        .filter(|value| value.is_finite())
}

/// The canvas once the quiz is done: the score, large.
fn finished_canvas_ui(ui: &mut Ui, session: &Session) {
    ui.centered_and_justified(|ui| {
        ui.label(
            RichText::new(format!(
                "{} of {} right\nbest streak {}",
                session.score(),
                session.answered(),
                session.best_streak()
            ))
            .size(40.0)
            .color(if session.mistakes().is_empty() {
                palette::HIT
            } else {
                Color32::from_gray(200)
            }),
        );
    });
}

/// How close a typed number must be, said by its field: `± 0.02`, or `exactly` for a count.
pub fn tolerance_text(tolerance: f64) -> String {
    if tolerance == 0.0 {
        "exactly".to_owned()
    } else {
        format!("± {}", accelviz_quiz::num(tolerance))
    }
}

/// The figure's numbers for the step asked (coordinates, boxes, perimeters: what an answer is
/// worked out from, as [`accelviz_quiz::Question::numbers`] lists them), in a section open by
/// default; `size` sets the text size (lecture mode's is larger, and proportional: a line in
/// monospace at lecture size wraps, and the list ran off the screen).
pub fn numbers_ui(ui: &mut Ui, lines: &[String], size: Option<f32>) {
    if lines.is_empty() {
        return;
    }
    egui::CollapsingHeader::new(RichText::new("The numbers").size(size.unwrap_or(14.0)))
        .id_salt("the numbers")
        .default_open(true)
        .show(ui, |ui| {
            for line in lines {
                ui.label(match size {
                    Some(size) => RichText::new(line).size(size),
                    None => RichText::new(line).monospace(),
                });
            }
        });
    ui.add_space(4.0);
}
