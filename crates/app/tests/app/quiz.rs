//! Quiz mode: a whole quiz taken with the keyboard alone (a right answer, a wrong one, the
//! review, the next question), the score, progress saved after every answer and restored in a
//! new app, a damaged progress file set aside; snapshots of a question and of an explanation.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use crate::common;

use std::path::PathBuf;

use accelviz_app::AccelvizApp;
use accelviz_app::app::Mode;
use accelviz_app::quiz::store::ProgressStore;
use accelviz_app::quiz::{QuizMode, letter_key};
use accelviz_quiz::{Expected, Level, Session};
use egui::Key;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

/// A progress file of the test's own.
fn progress_file(name: &str) -> PathBuf {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("quiz");
    std::fs::create_dir_all(&folder).unwrap();
    // Nothing from an earlier run: not the file, nor what was set aside.
    for entry in std::fs::read_dir(&folder).unwrap().filter_map(Result::ok) {
        if entry
            .file_name()
            .to_string_lossy()
            .starts_with(&format!("{name}.json"))
        {
            let _ = std::fs::remove_file(entry.path());
        }
    }
    folder.join(format!("{name}.json"))
}

/// The whole app showing the quiz, its progress kept in `path`.
fn quiz_app(path: &std::path::Path) -> Harness<'static, AccelvizApp> {
    let mut harness = common::app_harness();
    harness.state_mut().quiz = QuizMode::with_store(ProgressStore::File(path.to_path_buf()));
    harness.state_mut().mode = Mode::Quiz;
    harness.run();
    harness
}

fn session(harness: &Harness<'_, AccelvizApp>) -> Session {
    harness.state().quiz.session().unwrap().clone()
}

/// Presses `key` alone, and lets the app answer.
fn press(harness: &mut Harness<'_, AccelvizApp>, key: Key) {
    harness.key_press(key);
    harness.run();
}

/// Types `text` into the focused field.
fn type_text(harness: &mut Harness<'_, AccelvizApp>, text: &str) {
    harness
        .input_mut()
        .events
        .push(egui::Event::Text(text.to_owned()));
    harness.run();
}

/// Answers the current step with the keyboard only: its letter, or the number typed into the
/// field (focused when the step appears) and Enter. `right` picks the right answer or not.
fn answer_by_keyboard(harness: &mut Harness<'_, AccelvizApp>, right: bool) {
    let ask = session(harness).ask().unwrap().clone();
    match &ask.expected {
        Expected::Number { value, tolerance } => {
            let given = if right {
                *value
            } else {
                value + 10.0 * tolerance + 3.0
            };
            type_text(harness, &format!("{given}"));
            press(harness, Key::Enter);
        }
        expected => {
            let correct = expected.correct_option().unwrap();
            let chosen = if right {
                correct
            } else {
                (correct + 1) % expected.options().len()
            };
            press(harness, letter_key(chosen).unwrap());
        }
    }
}

#[test]
fn a_whole_quiz_by_keyboard_alone_with_the_review() {
    let path = progress_file("keyboard");
    let mut harness = quiz_app(&path);
    {
        let quiz = &mut harness.state_mut().quiz;
        quiz.seed_text = "5".into();
        quiz.count = 3;
        quiz.start();
    }
    harness.run();
    let total = session(&harness).total_steps();
    assert!(total >= 3);
    // A right answer, then Enter to move on.
    answer_by_keyboard(&mut harness, true);
    let after_right = session(&harness);
    assert!(after_right.is_revealed());
    assert_eq!((after_right.score(), after_right.streak()), (1, 1));
    press(&mut harness, Key::Enter);
    assert!(!session(&harness).is_revealed());
    // A wrong answer: graded wrong, the model answer shown, and the quiz goes on.
    answer_by_keyboard(&mut harness, false);
    let after_wrong = session(&harness);
    assert_eq!((after_wrong.score(), after_wrong.streak()), (1, 0));
    assert_eq!(after_wrong.mistakes().len(), 1);
    harness.get_by_label_contains("Not quite");
    harness.get_by_label_contains("The answer:");
    press(&mut harness, Key::Enter);
    // Every other step right, to the end, through the next questions, but for the third
    // question's third step (the lecture's demonstration, a traversal to review).
    let mut questions_seen = vec![0];
    while !session(&harness).is_finished() {
        let (position, step) = (session(&harness).position(), session(&harness).step());
        if !questions_seen.contains(&position) {
            questions_seen.push(position);
        }
        // The answers come before the numbers, so however long those are (the lecture
        // question lists every cell of its kD-tree) they cannot push the answers off screen.
        if session(&harness)
            .ask()
            .unwrap()
            .expected
            .correct_option()
            .is_some()
        {
            let numbers = harness.get_by_label("The numbers").rect();
            let first: Vec<egui::Rect> = harness
                .query_all_by_label_contains("(a) ")
                .map(|node| node.rect())
                .collect();
            assert!(
                first.iter().any(|rect| rect.bottom() <= numbers.top()),
                "question {position}, step {step}: the first answer {first:?} is not above the numbers {numbers:?}"
            );
        }
        answer_by_keyboard(&mut harness, (position, step) != (2, 2));
        press(&mut harness, Key::Enter);
    }
    assert_eq!(questions_seen, vec![0, 1, 2]);
    assert_eq!(session(&harness).questions()[2].kind, "lecture");
    let done = session(&harness);
    assert_eq!(done.score(), done.answered() - 2);
    harness.get_by_label_contains("Quiz done");
    // The review, by keyboard: Tab to the mistake (through the quiz's settings), Enter opens
    // it; the arrows step the model answer.
    let mut tabs = 0;
    while !harness
        .get_by_label_contains("Question 1, step 2")
        .is_focused()
    {
        assert!(tabs < 40, "Tab never reached the mistake");
        press(&mut harness, Key::Tab);
        tabs += 1;
    }
    press(&mut harness, Key::Enter);
    harness.get_by_label_contains("Mistake 1 of 2");
    harness.get_by_label_contains("The answer:");
    // The next mistake has a traversal: the arrows step back and forth through it.
    harness.get_by_label("Next mistake").click();
    harness.run();
    harness.get_by_label_contains("Mistake 2 of 2");
    let frame = |harness: &Harness<'_, AccelvizApp>| harness.state().quiz.review().unwrap();
    let (mistake, at_end) = frame(&harness);
    assert_eq!(mistake, 1);
    press(&mut harness, Key::ArrowLeft);
    press(&mut harness, Key::ArrowLeft);
    assert_eq!(
        frame(&harness).1,
        at_end - 2,
        "the left arrow steps the model answer back"
    );
    press(&mut harness, Key::ArrowRight);
    assert_eq!(
        frame(&harness).1,
        at_end - 1,
        "the right arrow steps it forward"
    );
    harness.get_by_label_contains("the left and right arrow keys");
    harness.get_by_label("Back to the score").click();
    harness.run();
    harness.get_by_label_contains("Quiz done");
}

#[test]
fn progress_is_saved_after_every_answer_and_restored_in_a_new_app() {
    let path = progress_file("restore");
    let mut harness = quiz_app(&path);
    {
        let quiz = &mut harness.state_mut().quiz;
        quiz.seed_text = "12".into();
        quiz.level = Level::Medium;
        quiz.count = 4;
        quiz.start();
    }
    harness.run();
    for right in [true, false, true] {
        answer_by_keyboard(&mut harness, right);
        // Saved with the explanation showing: a crash now loses nothing.
        let saved = std::fs::read_to_string(&path).unwrap();
        assert!(saved.contains("\"revealed\": true"), "{saved}");
        press(&mut harness, Key::Enter);
    }
    let before = session(&harness);
    drop(harness);
    // A new app (a restart): the same quiz, at the same place, with the same score.
    let harness = quiz_app(&path);
    let after = session(&harness);
    assert_eq!(after.seed(), 12);
    assert_eq!(after.level(), Level::Medium);
    assert_eq!(
        (after.position(), after.step()),
        (before.position(), before.step())
    );
    assert_eq!(after.score(), before.score());
    assert_eq!(after.verdicts(), before.verdicts());
    harness.get_by_label_contains("Carrying on with the quiz of seed 12");
    // No temporary file is left beside it.
    assert!(!path.with_extension("json.saving").exists());
}

#[test]
fn a_damaged_progress_file_is_set_aside_and_reported() {
    let path = progress_file("damaged");
    std::fs::write(
        &path,
        "{\"format\": \"accelviz-quiz-progress\", \"version\": 1, \"seed\": ",
    )
    .unwrap();
    let harness = quiz_app(&path);
    // A new quiz starts, the message names where the old file went, and it is still there.
    assert!(harness.state().quiz.session().is_some());
    let (message, problem) = harness.state().quiz.message.clone().unwrap();
    assert!(problem, "{message}");
    assert!(message.contains("could not be used"), "{message}");
    let folder = path.parent().unwrap();
    let aside: Vec<_> = std::fs::read_dir(folder)
        .unwrap()
        .filter_map(|entry| entry.ok())
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .filter(|name| name.starts_with("damaged.json.unreadable-"))
        .collect();
    assert_eq!(aside.len(), 1, "{aside:?}");
    assert!(message.contains(&aside[0]), "{message}");
    let kept = std::fs::read_to_string(folder.join(&aside[0])).unwrap();
    assert!(kept.contains("\"seed\": "));
    // A foreign file is set aside too.
    let path = progress_file("foreign");
    std::fs::write(&path, "PNG\u{1a}not progress").unwrap();
    let harness = quiz_app(&path);
    let (message, _) = harness.state().quiz.message.clone().unwrap();
    assert!(message.contains("not a quiz progress file"), "{message}");
}

#[test]
fn a_question_and_an_explanation_match_their_snapshots() {
    let path = progress_file("snapshots");
    let mut harness = quiz_app(&path);
    {
        let quiz = &mut harness.state_mut().quiz;
        quiz.seed_text = "14".into();
        quiz.count = 9;
        quiz.start();
    }
    harness.run();
    // Seed 14 opens with a BVH traversal question: the tree paused before the first step.
    assert_eq!(session(&harness).question().kind, "visit-order");
    harness.run();
    let mut failures = Vec::new();
    if let Err(error) = harness.try_snapshot("quiz_question") {
        failures.push(error.to_string());
    }
    answer_by_keyboard(&mut harness, false);
    if let Err(error) = harness.try_snapshot("quiz_explanation") {
        failures.push(error.to_string());
    }
    // A hard slab question is in 3D: the box and ray in the 3D view, t_enter lit once given.
    {
        let quiz = &mut harness.state_mut().quiz;
        quiz.seed_text = "12".into();
        quiz.level = Level::Hard;
        quiz.start();
    }
    harness.run();
    assert_eq!(session(&harness).question().kind, "slab");
    answer_by_keyboard(&mut harness, true);
    press(&mut harness, Key::Enter);
    answer_by_keyboard(&mut harness, false);
    harness.run_steps(2);
    if let Err(error) = harness.try_snapshot("quiz_slab_3d") {
        failures.push(error.to_string());
    }
    // A leak question: two triangles seen along the ray, what the fast f32 test computed for
    // each listed; once answered, the ray marked as slipping through.
    {
        let quiz = &mut harness.state_mut().quiz;
        quiz.seed_text = "20".into();
        quiz.level = Level::Easy;
        quiz.start();
    }
    harness.run();
    assert_eq!(session(&harness).question().kind, "leak");
    if let Err(error) = harness.try_snapshot("quiz_leak_question") {
        failures.push(error.to_string());
    }
    answer_by_keyboard(&mut harness, true);
    harness.run_steps(2);
    if let Err(error) = harness.try_snapshot("quiz_leak_explanation") {
        failures.push(error.to_string());
    }
    // A grid walk: the grid with its cells' coordinates, the ray, the cells passed so far;
    // once answered, the next cell and the line crossed into it.
    for (seed, level, name) in [
        ("22", Level::Easy, "quiz_grid_walk"),
        ("34", Level::Hard, "quiz_grid_walk_3d"),
    ] {
        {
            let quiz = &mut harness.state_mut().quiz;
            quiz.seed_text = seed.into();
            quiz.level = level;
            quiz.start();
        }
        harness.run();
        assert_eq!(session(&harness).question().kind, "grid-walk");
        answer_by_keyboard(&mut harness, true);
        press(&mut harness, Key::Enter);
        answer_by_keyboard(&mut harness, false);
        harness.run_steps(2);
        if let Err(error) = harness.try_snapshot(name) {
            failures.push(error.to_string());
        }
    }
    // A quadtree, front to back: the cells cut at their middles, the child visited first lit.
    {
        let quiz = &mut harness.state_mut().quiz;
        quiz.seed_text = "21".into();
        quiz.level = Level::Medium;
        quiz.start();
    }
    harness.run();
    assert_eq!(session(&harness).question().kind, "octree-order");
    answer_by_keyboard(&mut harness, true);
    harness.run_steps(2);
    if let Err(error) = harness.try_snapshot("quiz_octree_order") {
        failures.push(error.to_string());
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// After Next, a choice step's first answer has the focus: Space picks it, and one Tab goes
/// on to the second answer (not back through the lesson list, where Space would leave).
#[test]
fn after_next_the_first_answer_has_the_focus() {
    let path = progress_file("focus");
    let mut harness = quiz_app(&path);
    {
        let quiz = &mut harness.state_mut().quiz;
        quiz.seed_text = "3".into();
        quiz.count = 9;
        quiz.start();
    }
    harness.run();
    let mut choice_steps = 0;
    while !session(&harness).is_finished() && choice_steps < 3 {
        let ask = session(&harness).ask().unwrap().clone();
        let options = ask.expected.options();
        if options.len() >= 2 && !matches!(ask.expected, Expected::Costed { .. }) {
            harness.run();
            let first = format!("(a) {}", options[0].label);
            assert!(
                harness.get_by_label(&first).is_focused(),
                "{first} has the focus"
            );
            press(&mut harness, Key::Tab);
            let second = format!("(b) {}", options[1].label);
            assert!(harness.get_by_label(&second).is_focused(), "Tab: {second}");
            press(&mut harness, Key::Space);
            assert_eq!(harness.state().mode, Mode::Quiz, "Space stays in the quiz");
            assert!(session(&harness).is_revealed(), "Space picked (b)");
            choice_steps += 1;
        } else {
            answer_by_keyboard(&mut harness, true);
        }
        press(&mut harness, Key::Enter);
    }
    assert_eq!(choice_steps, 3);
}

/// "New quiz" does not throw away a quiz under way: it asks, and "Keep it" keeps it.
#[test]
fn a_new_quiz_asks_before_it_replaces_one_under_way() {
    let path = progress_file("replace");
    let mut harness = quiz_app(&path);
    {
        let quiz = &mut harness.state_mut().quiz;
        quiz.seed_text = "4".into();
        quiz.start();
    }
    harness.run();
    answer_by_keyboard(&mut harness, true);
    let before = session(&harness);
    harness.get_by_label("New quiz").click();
    harness.run();
    harness.get_by_label_contains("replaces the one under way");
    harness.get_by_label("Keep it").click();
    harness.run();
    assert_eq!(session(&harness).verdicts(), before.verdicts());
    harness.get_by_label("New quiz").click();
    harness.run();
    harness.get_by_label("Replace it").click();
    harness.run();
    assert_eq!(session(&harness).answered(), 0);
}

/// A number that cannot be read is said under its field, and the field keeps the focus: Enter
/// had taken it away, and a keyboard user could type nothing more (found taking the quiz in
/// the desktop window).
#[test]
fn a_number_that_cannot_be_read_keeps_the_field_focused() {
    let path = progress_file("bad-number");
    let mut harness = quiz_app(&path);
    {
        let quiz = &mut harness.state_mut().quiz;
        quiz.seed_text = "1".into();
        quiz.count = 9;
        quiz.start();
    }
    harness.run();
    // To the first step that asks for a number.
    let mut steps = 0;
    let value = loop {
        let ask = session(&harness).ask().unwrap().clone();
        if let Expected::Number { value, .. } = ask.expected {
            break value;
        }
        answer_by_keyboard(&mut harness, true);
        press(&mut harness, Key::Enter);
        steps += 1;
        assert!(steps < 40, "a number step");
    };
    harness.run();
    type_text(&mut harness, "a2");
    press(&mut harness, Key::Enter);
    assert!(!session(&harness).is_revealed(), "nothing was answered");
    harness.get_by_label_contains("'a2' is not a number");
    harness.run();
    assert!(
        harness.get_by_label("Your answer:").is_focused(),
        "the field keeps the focus"
    );
    press(&mut harness, Key::Backspace);
    press(&mut harness, Key::Backspace);
    type_text(&mut harness, &format!("{value}"));
    press(&mut harness, Key::Enter);
    assert!(
        session(&harness).is_revealed(),
        "the number typed again is taken"
    );
    assert!(
        harness.query_by_label_contains("is not a number").is_none(),
        "and the problem is gone"
    );
}
