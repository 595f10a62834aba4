//! # accelviz-quiz
//!
//! Quizzes on ray-tracing acceleration structures, for the app's quiz mode and the CLI's
//! `quiz` command alike. No question is written by hand: each is generated from a seed, and
//! its answers are what the core's own algorithms compute (the slab record, brute force, the
//! traversal with a `Recorder`, the builders and their cost curves), so every answer is
//! correct by construction and the same on every machine.
//!
//! Watching an animation teaches little; predicting the next step and being shown why teaches
//! a lot (Hundhausen, Douglas & Stasko 2002; Naps et al. 2002; Byrne, Catrambone & Stasko
//! 1999). So a question is a sequence of [`Ask`]s, graded one at a time (as JSAV's default
//! grader: the first wrong step stops the question and shows the model answer), each with an
//! explanation and what the canvas should mark when it is revealed.
//!
//! - [`kinds`]: the table of question kinds (`slab`, `first-hit`, `visit-order`, …), one
//!   generator each.
//! - [`Question`], [`Ask`], [`Expected`], [`Figure`]: what a generated question holds.
//! - [`Session`]: a quiz being taken: the questions of a seed, the answers given, score,
//!   streak, and the mistakes to review; [`Progress`] is what is saved after every answer.
//!
//! No file IO and no UI: the app saves progress where its platform can, the CLI prints.

pub mod build;
mod generate;
pub mod kinds;
mod progress;
mod question;
mod session;

pub use build::{BuildExercise, BuildScore, NodeChoice, Pick};
pub use generate::{Level, LevelError, num};
pub use kinds::{KINDS, KindEntry, KindError, generate, kind_names};
pub use progress::{PROGRESS_FORMAT, Progress, ProgressError};
pub use question::{
    Ask, Choice, CrackFigure, Expected, Figure, GridFigure, Highlight, Question, Response,
    SceneFigure, TreeFigure, node_label, option_letter,
};
pub use session::{Outcome, Session, SessionError, Verdict};
