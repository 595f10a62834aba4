//! Taking a quiz: grading step by step, score and streak, the review of mistakes, and
//! progress saved and restored (or refused, when the file is not progress).

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_quiz::{
    Expected, KINDS, Level, Outcome, Progress, ProgressError, Response, Session, SessionError,
};

/// The right response to the current step.
fn right(session: &Session) -> Response {
    match &session.ask().expect("asking").expected {
        Expected::Number { value, .. } => Response::Number(*value),
        choice => Response::Choice(choice.correct_option().unwrap()),
    }
}

/// A wrong response to the current step.
fn wrong(session: &Session) -> Response {
    match &session.ask().expect("asking").expected {
        Expected::Number { value, tolerance } => Response::Number(value + 10.0 * tolerance + 1.0),
        Expected::Costed { costs, .. } => {
            // The dearest option.
            let dearest = (0..costs.len()).max_by(|a, b| costs[*a].total_cmp(&costs[*b]));
            Response::Choice(dearest.unwrap())
        }
        Expected::Choice { correct, options } => Response::Choice((correct + 1) % options.len()),
    }
}

#[test]
fn steps_are_graded_one_at_a_time_with_score_and_streak() {
    let mut session = Session::new(5, Level::Easy, 3, &[]).unwrap();
    assert_eq!(session.answered(), 0);
    // Right, right, wrong, right.
    for (index, correct) in [true, true, false, true].into_iter().enumerate() {
        let response = if correct {
            right(&session)
        } else {
            wrong(&session)
        };
        let Outcome::Graded(verdict) = session.answer(response) else {
            panic!("step {index} was not graded")
        };
        assert_eq!(verdict.correct, correct);
        assert!(session.is_revealed());
        // A second answer to a revealed step is not graded.
        assert_eq!(session.answer(response), Outcome::NotAsking);
        assert!(session.move_on());
    }
    assert_eq!(session.score(), 3);
    assert_eq!(session.streak(), 1);
    assert_eq!(session.best_streak(), 2);
    let mistakes = session.mistakes();
    assert_eq!(mistakes.len(), 1);
    assert_eq!(mistakes[0].question * 100 + mistakes[0].step, {
        // The third answer's place.
        let verdicts = session.verdicts();
        verdicts[2].question * 100 + verdicts[2].step
    });
    // Nothing to move on from until the step is answered.
    assert!(!session.move_on());
}

#[test]
fn a_whole_quiz_ends_and_counts_every_step() {
    let mut session = Session::new(11, Level::Medium, KINDS.len(), &[]).unwrap();
    let kinds: Vec<&str> = session.questions().iter().map(|q| q.kind).collect();
    // Every kind once, cycling from where the seed starts.
    let mut sorted = kinds.clone();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(sorted.len(), KINDS.len());
    let mut answered = 0;
    let mut meant_right = 0;
    while !session.is_finished() {
        let right_now = answered % 3 != 2;
        let response = if right_now {
            right(&session)
        } else {
            wrong(&session)
        };
        let Outcome::Graded(verdict) = session.answer(response) else {
            panic!("not graded")
        };
        assert_eq!(verdict.correct, right_now);
        meant_right += usize::from(right_now);
        session.move_on();
        answered += 1;
    }
    // Every step, a build exercise's as they came, was asked once.
    assert_eq!(answered, session.total_steps());
    assert_eq!(session.score(), meant_right);
    assert!(session.ask().is_none());
    assert_eq!(session.answer(Response::Choice(0)), Outcome::NotAsking);
}

#[test]
fn the_same_seed_gives_the_same_quiz() {
    let a = Session::new(42, Level::Hard, 6, &[]).unwrap();
    let b = Session::new(42, Level::Hard, 6, &[]).unwrap();
    let json = |session: &Session| {
        session
            .questions()
            .iter()
            .map(|q| q.to_json())
            .collect::<Vec<_>>()
    };
    assert_eq!(json(&a), json(&b));
    let c = Session::new(43, Level::Hard, 6, &[]).unwrap();
    assert_ne!(json(&a), json(&c));
    // Question i is question 0 of seed + i.
    let shifted = Session::new(43, Level::Hard, 1, &[a.questions()[1].kind]).unwrap();
    assert_eq!(shifted.questions()[0].to_json(), a.questions()[1].to_json());
}

#[test]
fn progress_saved_after_every_answer_restores_the_same_place() {
    let mut session = Session::new(9, Level::Easy, 4, &["slab", "visit-order"]).unwrap();
    for index in 0..9 {
        let response = if index % 4 == 1 {
            wrong(&session)
        } else {
            right(&session)
        };
        session.answer(response);
        // Saved with the explanation showing, and after moving on.
        for _ in 0..2 {
            let text = session.progress().to_text();
            let restored = Session::restore(&Progress::parse(&text).unwrap()).unwrap();
            assert_eq!(restored.position(), session.position());
            assert_eq!(restored.step(), session.step());
            assert_eq!(restored.is_revealed(), session.is_revealed());
            assert_eq!(restored.score(), session.score());
            assert_eq!(restored.streak(), session.streak());
            assert_eq!(restored.verdicts(), session.verdicts());
            assert_eq!(restored.kinds(), session.kinds());
            session.move_on();
        }
    }
}

#[test]
fn foreign_and_corrupt_progress_is_refused_with_a_reason() {
    for text in ["", "not json", "[1, 2]", "{\"format\": \"something-else\"}"] {
        assert!(
            matches!(Progress::parse(text), Err(ProgressError::Foreign(_))),
            "{text:?}"
        );
    }
    let mut session = Session::new(3, Level::Easy, 2, &[]).unwrap();
    session.answer(right(&session));
    let good = session.progress().to_text();
    // A newer version's file is said to be newer, not damaged; a cut-off one is damaged.
    let newer = Progress::parse(&good.replace("\"version\": 1", "\"version\": 999")).unwrap_err();
    assert_eq!(newer, ProgressError::Newer(999));
    assert!(newer.to_string().contains("newer accelviz"), "{newer}");
    let cut = Progress::parse(&good[..200]).unwrap_err();
    assert!(matches!(cut, ProgressError::Corrupt(_)), "{cut}");
    assert!(cut.to_string().contains("ends early"), "{cut}");
    let broken = [
        good.replace("\"level\": \"easy\"", "\"level\": \"expert\""),
        good.replace("\"version\": 1", "\"version\": 0"),
        good.replace("\"seed\": 3", "\"seed\": -3"),
        good.replace("\"revealed\": true", "\"revealed\": 1"),
    ];
    for text in &broken {
        let error = Progress::parse(text).unwrap_err();
        assert!(matches!(error, ProgressError::Corrupt(_)), "{error} {text}");
    }
    // Parses, but the answers do not lead where the file says.
    let score = good.replace("\"score\": 1", "\"score\": 2");
    let error = Session::restore(&Progress::parse(&score).unwrap()).unwrap_err();
    assert!(matches!(error, SessionError::Mismatch { .. }), "{error}");
    let unknown = good.replace("\"kinds\": [", "\"kinds\": [\n    \"no-such-kind\",");
    assert!(Session::restore(&Progress::parse(&unknown).unwrap()).is_err());
}

#[test]
fn a_quiz_needs_a_question() {
    assert_eq!(
        Session::new(1, Level::Easy, 0, &[]).unwrap_err(),
        SessionError::Empty
    );
}

#[test]
fn a_tree_built_by_the_builders_picks_scores_one_and_a_lazy_one_less() {
    for seed in 0..30 {
        for level in Level::ALL {
            // The builder's picks: the student's tree is the builder's.
            let mut session = Session::new(seed, level, 1, &["build"]).unwrap();
            let mut steps = 0;
            while !session.is_finished() {
                session.answer(right(&session));
                session.move_on();
                steps += 1;
            }
            assert_eq!(session.score(), steps);
            // A finished quiz keeps no exercise; take the question again to see the tree.
            let mut again = Session::new(seed, level, 1, &["build"]).unwrap();
            while again.exercise().is_some_and(|e| !e.is_done()) {
                again.answer(right(&again));
                if again.exercise().is_some_and(|e| e.is_done()) {
                    break;
                }
                again.move_on();
            }
            let exercise = again.exercise().unwrap();
            exercise.validate().unwrap();
            let score = exercise.score();
            assert!((score.ratio - 1.0).abs() < 1e-9, "{score:?}");
            // A leaf at the root: one step, and the cost of testing every shape.
            let mut lazy = Session::new(seed, level, 1, &["build"]).unwrap();
            lazy.answer(Response::Choice(0));
            let exercise = lazy.exercise().unwrap();
            assert!(exercise.is_done());
            exercise.validate().unwrap();
            let score = exercise.score();
            let shapes = exercise.shapes().shapes.len() as f64;
            assert!((score.student_cost - shapes).abs() < 1e-9, "{score:?}");
            assert!(score.ratio < 1.0, "{score:?}");
        }
    }
}

#[test]
fn a_costly_pick_is_kept_and_the_next_node_asked() {
    let mut session = Session::new(4, Level::Medium, 1, &["build"]).unwrap();
    let before = session.total_steps();
    assert_eq!(before, 1);
    let response = wrong(&session);
    let Outcome::Graded(verdict) = session.answer(response) else {
        panic!("graded")
    };
    let exercise = session.exercise().unwrap();
    let (choice, picked) = &exercise.decided()[0];
    // The dearest pick is kept (the student's tree is the student's), and scored wrong
    // unless it was also the cheapest.
    assert_eq!(Response::Choice(*picked), response);
    assert_eq!(
        verdict.correct,
        choice.costs[*picked] <= choice.costs[choice.builder]
    );
    if !exercise.is_done() {
        assert_eq!(session.total_steps(), 2);
    }
}
