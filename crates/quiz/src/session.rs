//! A quiz being taken: the questions of one seed, graded a step at a time.
//!
//! Grading follows JSAV's default grader with its "fix" mode (Karavirta & Shaffer, JSAV,
//! ITiCSE 2013): each step is compared with the model's; a wrong step scores nothing, its
//! model answer is shown, and the question goes on from the model's state, so one slip does
//! not cost the rest of the question.

use crate::build::BuildExercise;
use crate::generate::Level;
use crate::kinds::{KINDS, KindError, generate};
use crate::progress::Progress;
use crate::question::{Ask, Figure, Question, Response};

fn exercise_of(question: &Question) -> Option<BuildExercise> {
    match &question.figure {
        Figure::Build(exercise) => Some((**exercise).clone()),
        _ => None,
    }
}

/// One answered step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Verdict {
    /// The question's number in the quiz.
    pub question: usize,
    /// The step's number in the question.
    pub step: usize,
    /// What was answered.
    pub response: Response,
    /// Whether it was right.
    pub correct: bool,
}

/// What [`Session::answer`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    /// The step was graded; its explanation is now shown.
    Graded(Verdict),
    /// Nothing is being asked: the step is already answered (move on first) or the quiz is
    /// over.
    NotAsking,
}

/// Why a quiz could not be made or restored.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SessionError {
    /// A kind that does not exist, or a seed that gave no question.
    #[error(transparent)]
    Kind(#[from] KindError),
    /// A quiz needs at least one question.
    #[error("a quiz needs at least one question")]
    Empty,
    /// Saved answers that do not fit the questions of the saved seed.
    #[error("the saved answers do not fit the quiz of seed {seed}: {problem}")]
    Mismatch {
        /// The seed.
        seed: u64,
        /// What did not fit.
        problem: String,
    },
}

/// A quiz: its questions, where the student is, and every answer so far.
#[derive(Clone, Debug)]
pub struct Session {
    seed: u64,
    level: Level,
    kinds: Vec<&'static str>,
    questions: Vec<Question>,
    /// Each question's steps so far: a build exercise's grow as the student picks.
    asks: Vec<Vec<Ask>>,
    /// The build exercise of the current question, as the student has built it so far.
    exercise: Option<BuildExercise>,
    position: usize,
    step: usize,
    revealed: bool,
    verdicts: Vec<Verdict>,
    streak: u32,
    best_streak: u32,
}

impl Session {
    /// The quiz of `seed`: `count` questions at `level`, cycling through `kinds` (every kind
    /// when empty), question `i` made from seed `seed + i`. The same arguments give the same
    /// quiz on every machine, so a class can take one quiz.
    pub fn new(
        seed: u64,
        level: Level,
        count: usize,
        kinds: &[&str],
    ) -> Result<Self, SessionError> {
        if count == 0 {
            return Err(SessionError::Empty);
        }
        let kinds: Vec<&'static str> = if kinds.is_empty() {
            KINDS.iter().map(|entry| entry.name).collect()
        } else {
            kinds
                .iter()
                .map(|name| crate::kinds::entry(name).map(|entry| entry.name))
                .collect::<Result<_, _>>()?
        };
        let questions = (0..count)
            .map(|index| {
                // Start the cycle at a kind the seed picks, so quizzes of different seeds do
                // not all open with the same kind.
                // (In u64: `usize` is 32 bits in the browser.)
                let start = (seed % kinds.len() as u64) as usize;
                let kind = kinds[(start + index) % kinds.len()];
                generate(kind, seed.wrapping_add(index as u64), level)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let asks = questions.iter().map(|q| q.asks.clone()).collect();
        let exercise = exercise_of(&questions[0]);
        Ok(Self {
            seed,
            level,
            kinds,
            asks,
            exercise,
            questions,
            position: 0,
            step: 0,
            revealed: false,
            verdicts: Vec::new(),
            streak: 0,
            best_streak: 0,
        })
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The level.
    pub fn level(&self) -> Level {
        self.level
    }

    /// The kinds the quiz cycles through.
    pub fn kinds(&self) -> &[&'static str] {
        &self.kinds
    }

    /// Every question.
    pub fn questions(&self) -> &[Question] {
        &self.questions
    }

    /// The question being taken (the last one once the quiz is over).
    pub fn question(&self) -> &Question {
        &self.questions[self.position.min(self.questions.len() - 1)]
    }

    /// The question's number, from 0.
    pub fn position(&self) -> usize {
        self.position
    }

    /// The step's number in the question, from 0.
    pub fn step(&self) -> usize {
        self.step
    }

    /// The step being asked or just answered, unless the quiz is over.
    pub fn ask(&self) -> Option<&Ask> {
        self.asks
            .get(self.position)
            .and_then(|asks| asks.get(self.step))
    }

    /// The steps of question `index` so far (a build exercise's grow as the student picks).
    pub fn asks_of(&self, index: usize) -> &[Ask] {
        self.asks.get(index).map_or(&[], Vec::as_slice)
    }

    /// The current question's build exercise, as built so far.
    pub fn exercise(&self) -> Option<&BuildExercise> {
        self.exercise.as_ref()
    }

    /// True once the current step is answered and its explanation is shown.
    pub fn is_revealed(&self) -> bool {
        self.revealed
    }

    /// The verdict on the current step, once it is answered.
    pub fn verdict(&self) -> Option<&Verdict> {
        self.revealed.then(|| self.verdicts.last()).flatten()
    }

    /// True when every step of every question is answered.
    pub fn is_finished(&self) -> bool {
        self.position >= self.questions.len()
    }

    /// Steps answered right.
    pub fn score(&self) -> usize {
        self.verdicts
            .iter()
            .filter(|verdict| verdict.correct)
            .count()
    }

    /// Steps answered.
    pub fn answered(&self) -> usize {
        self.verdicts.len()
    }

    /// Steps in the whole quiz, as far as they are known (a build exercise has as many as
    /// the student's tree has nodes to decide).
    pub fn total_steps(&self) -> usize {
        self.asks.iter().map(Vec::len).sum()
    }

    /// Right answers in a row, up to now.
    pub fn streak(&self) -> u32 {
        self.streak
    }

    /// The longest run of right answers.
    pub fn best_streak(&self) -> u32 {
        self.best_streak
    }

    /// Every answer given, in order.
    pub fn verdicts(&self) -> &[Verdict] {
        &self.verdicts
    }

    /// The wrong answers, for the review.
    pub fn mistakes(&self) -> Vec<Verdict> {
        self.verdicts
            .iter()
            .copied()
            .filter(|verdict| !verdict.correct)
            .collect()
    }

    /// Grades `response` to the current step and shows its explanation.
    pub fn answer(&mut self, response: Response) -> Outcome {
        if self.revealed {
            return Outcome::NotAsking;
        }
        let Some(ask) = self.ask() else {
            return Outcome::NotAsking;
        };
        let verdict = Verdict {
            question: self.position,
            step: self.step,
            response,
            correct: ask.expected.accepts(&response),
        };
        if verdict.correct {
            self.streak += 1;
            self.best_streak = self.best_streak.max(self.streak);
        } else {
            self.streak = 0;
        }
        self.verdicts.push(verdict);
        self.revealed = true;
        // A build exercise takes the student's pick, right or not, and asks the next node.
        if let (Some(exercise), Response::Choice(index)) = (&mut self.exercise, response)
            && exercise.pick(index)
            && let Some(next) = exercise.next_ask()
        {
            self.asks[self.position].push(next);
        }
        Outcome::Graded(verdict)
    }

    /// After an answer: on to the next step (from the model's state, right or wrong), or the
    /// next question. False when there is nothing to move on from.
    pub fn move_on(&mut self) -> bool {
        if !self.revealed || self.is_finished() {
            return false;
        }
        self.revealed = false;
        self.step += 1;
        if self.step >= self.asks[self.position].len() {
            self.step = 0;
            self.position += 1;
            self.exercise = self.questions.get(self.position).and_then(exercise_of);
        }
        true
    }

    /// What is saved after every answer.
    pub fn progress(&self) -> Progress {
        Progress {
            seed: self.seed,
            level: self.level,
            count: self.questions.len(),
            kinds: self.kinds.iter().map(|kind| (*kind).to_owned()).collect(),
            responses: self
                .verdicts
                .iter()
                .map(|verdict| verdict.response)
                .collect(),
            position: (self.position, self.step),
            revealed: self.revealed,
            score: self.score(),
        }
    }

    /// The quiz that `progress` was saved from, with its answers given again in order.
    pub fn restore(progress: &Progress) -> Result<Self, SessionError> {
        let kinds: Vec<&str> = progress.kinds.iter().map(String::as_str).collect();
        let mut session = Self::new(progress.seed, progress.level, progress.count, &kinds)?;
        let mismatch = |problem: String| SessionError::Mismatch {
            seed: progress.seed,
            problem,
        };
        for (index, response) in progress.responses.iter().enumerate() {
            if session.revealed {
                session.move_on();
            }
            if session.answer(*response) == Outcome::NotAsking {
                return Err(mismatch(format!(
                    "answer {} comes after the last question",
                    index + 1
                )));
            }
        }
        if session.revealed && !progress.revealed {
            session.move_on();
        }
        if (session.position, session.step) != progress.position
            || session.revealed != progress.revealed
        {
            return Err(mismatch(format!(
                "the answers lead to question {} step {}, the file says question {} step {}",
                session.position + 1,
                session.step + 1,
                progress.position.0 + 1,
                progress.position.1 + 1
            )));
        }
        if session.score() != progress.score {
            return Err(mismatch(format!(
                "the answers score {}, the file says {}",
                session.score(),
                progress.score
            )));
        }
        Ok(session)
    }
}
