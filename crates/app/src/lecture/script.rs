//! A lecture script: the slides of a lecture, one a line, in the order they are shown. A
//! lecturer copies `assets/lecture.txt`, edits it, and opens it (or starts the app with it);
//! every error names the file, the line and the problem.
//!
//! ```text
//! # comments and blank lines are skipped
//! lesson 3                      the slab test, from its first step
//! lesson 4 step 5 show r2       the BVH lesson on its ray "r2", at step 5
//! lesson 10 show "dust in a room"   a preset of the lesson, by its name
//! lesson 6 step end             at the last step
//! lesson 5 panels on            with the lesson's panels (its pseudo-code, costs, tree)
//! lesson 5 panels code,tree     with those of its panels only (the rest would not fit)
//! question lecture seed 7       a quiz question (answers hidden until R)
//! question slab seed 3 level hard
//! ```

use accelviz_quiz::Level;

use crate::lesson::Part;

/// Where a lesson slide starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StartStep {
    /// This step (0: before the first).
    At(usize),
    /// The animation's last step.
    End,
}

/// One slide.
#[derive(Clone, Debug, PartialEq)]
pub enum Slide {
    /// A lesson of the app.
    Lesson {
        /// Its number in the app's list, from 0.
        index: usize,
        /// Where its animation starts.
        step: StartStep,
        /// A named ray or preset of the lesson file to show.
        show: Option<String>,
        /// The lesson's panels the slide opens with beside the canvas (its inspector: a
        /// kD-tree's pseudo-code, a builder's costs, the tree).
        panels: Panels,
    },
    /// A quiz question.
    Question {
        /// The kind.
        kind: &'static str,
        /// The seed.
        seed: u64,
        /// The level.
        level: Level,
    },
}

/// Which of a lesson's panels a slide opens with.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Panels {
    /// None: the canvas fills the screen.
    #[default]
    Off,
    /// The whole inspector.
    All,
    /// The inspector's parts by these names ([`Part::name`]), in the inspector's order.
    Only(Vec<&'static str>),
}

impl Panels {
    /// Whether any panel is shown.
    pub fn on(&self) -> bool {
        *self != Panels::Off
    }
}

/// A parsed script.
#[derive(Clone, Debug, PartialEq)]
pub struct LectureScript {
    /// Where it came from (for messages).
    pub path: String,
    /// The slides, in order.
    pub slides: Vec<Slide>,
    /// The lines that could not be read, each with its place: skipped, so one bad line does
    /// not stop a lecture (lecture mode reports them).
    pub problems: Vec<ScriptError>,
}

/// A problem in a script, with its place.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}: {problem}", place(path, *line))]
pub struct ScriptError {
    /// The file.
    pub path: String,
    /// The line, from 1 (0: the file as a whole).
    pub line: usize,
    /// What is wrong.
    pub problem: String,
}

/// `file:line`, or the file alone for a problem of the file as a whole (line 0).
fn place(path: &str, line: usize) -> String {
    if line == 0 {
        path.to_owned()
    } else {
        format!("{path}:{line}")
    }
}

/// The built-in script, following the lecture.
pub const DEFAULT_SCRIPT: &str = include_str!("../../../../assets/lecture.txt");

/// Its path in the repository.
pub const DEFAULT_SCRIPT_PATH: &str = "assets/lecture.txt";

impl LectureScript {
    /// Reads a script for an app whose lessons have these inspector parts (one entry a
    /// lesson, in order; [`crate::lesson::Lesson::parts`]). A line that cannot be read is
    /// skipped and kept in [`problems`](Self::problems) with its place; the error is for a
    /// script with no slide left (its first bad line, or "no slides").
    pub fn parse(
        text: &str,
        path: &str,
        lesson_parts: &[&'static [Part]],
    ) -> Result<Self, ScriptError> {
        let mut slides = Vec::new();
        let mut problems = Vec::new();
        for (number, line) in text.lines().enumerate() {
            let fail = |problem: String| ScriptError {
                path: path.to_owned(),
                line: number + 1,
                problem,
            };
            let slide = tokens(line).and_then(|words| {
                let words: Vec<&str> = words.iter().map(String::as_str).collect();
                let Some((first, rest)) = words.split_first() else {
                    return Ok(None);
                };
                match *first {
                    "lesson" => lesson_slide(rest, lesson_parts).map(Some),
                    "question" => question_slide(rest).map(Some),
                    other => Err(format!(
                        "'{other}' is not a slide; a line starts with 'lesson' or 'question'"
                    )),
                }
            });
            match slide {
                Ok(Some(slide)) => slides.push(slide),
                Ok(None) => {}
                Err(problem) => problems.push(fail(problem)),
            }
        }
        if slides.is_empty() {
            return Err(problems.into_iter().next().unwrap_or_else(|| ScriptError {
                path: path.to_owned(),
                line: 0,
                problem: "the script has no slides".into(),
            }));
        }
        Ok(Self {
            path: path.to_owned(),
            slides,
            problems,
        })
    }

    /// What lecture mode says of the skipped lines: how many, and each with its place.
    pub fn problems_line(&self) -> Option<String> {
        let first = self.problems.first()?;
        let count = self.problems.len();
        let all: Vec<String> = self.problems.iter().map(ToString::to_string).collect();
        Some(if count == 1 {
            format!("A line of the script was skipped: {first}")
        } else {
            format!(
                "{count} lines of the script were skipped: {}",
                all.join("; ")
            )
        })
    }

    /// Each skipped line with its place and problem, one a line (a bar that says them all on
    /// one line cut off the third).
    pub fn problems(&self) -> Vec<String> {
        self.problems.iter().map(ToString::to_string).collect()
    }

    /// The built-in script, for lessons with these inspector parts (as [`parse`](Self::parse)).
    pub fn default_for(lesson_parts: &[&'static [Part]]) -> Result<Self, ScriptError> {
        Self::parse(DEFAULT_SCRIPT, DEFAULT_SCRIPT_PATH, lesson_parts)
    }
}

/// The words of a line up to a `#`; a "quoted phrase" is one word.
fn tokens(line: &str) -> Result<Vec<String>, String> {
    let mut words = Vec::new();
    let mut word = String::new();
    let mut quoted = false;
    for character in line.chars() {
        match character {
            '"' => {
                if quoted {
                    words.push(std::mem::take(&mut word));
                }
                quoted = !quoted;
            }
            '#' if !quoted => break,
            space if space.is_whitespace() && !quoted => {
                if !word.is_empty() {
                    words.push(std::mem::take(&mut word));
                }
            }
            other => word.push(other),
        }
    }
    if quoted {
        return Err("a quote is not closed".into());
    }
    if !word.is_empty() {
        words.push(word);
    }
    Ok(words)
}

/// Pairs of words after the slide's first: `step K`, `show NAME`, `seed S`, `level L`.
fn options<'a>(words: &[&'a str]) -> Result<Vec<(&'a str, &'a str)>, String> {
    words
        .chunks(2)
        .map(|pair| match pair {
            [key, value] => Ok((*key, *value)),
            [key] => Err(format!("'{key}' needs a value after it")),
            _ => Err("empty option".into()),
        })
        .collect()
}

fn lesson_slide(words: &[&str], lesson_parts: &[&'static [Part]]) -> Result<Slide, String> {
    let lesson_count = lesson_parts.len();
    let Some((number, rest)) = words.split_first() else {
        return Err(format!(
            "which lesson? write 'lesson N' with N from 1 to {lesson_count}"
        ));
    };
    let index = number
        .parse::<usize>()
        .ok()
        .filter(|number| (1..=lesson_count).contains(number))
        .ok_or_else(|| format!("'{number}' is not a lesson; lessons are 1 to {lesson_count}"))?
        - 1;
    let mut step = StartStep::At(0);
    let mut show = None;
    let mut panels = Panels::Off;
    for (key, value) in options(rest)? {
        match key {
            "step" => {
                step =
                    if value == "end" {
                        StartStep::End
                    } else {
                        StartStep::At(value.parse().map_err(|_| {
                            format!("step '{value}' is not a whole number or 'end'")
                        })?)
                    };
            }
            "show" => show = Some(value.to_owned()),
            "panels" => {
                panels = match value {
                    "on" => Panels::All,
                    "off" => Panels::Off,
                    _ => Panels::Only(part_names(value, index, lesson_parts[index])?),
                };
            }
            other => {
                return Err(format!(
                    "'{other}' is not an option of a lesson slide; they are: step, show, panels"
                ));
            }
        }
    }
    Ok(Slide::Lesson {
        index,
        step,
        show,
        panels,
    })
}

/// The parts `list` names (`code,tree`) as lesson `index`'s [`Part`]s spell them, in the
/// inspector's order; an error names what the lesson has.
fn part_names(
    list: &str,
    index: usize,
    parts: &'static [Part],
) -> Result<Vec<&'static str>, String> {
    let known = || {
        parts
            .iter()
            .map(|part| format!("{} ({})", part.name, part.what))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if parts.is_empty() {
        return Err(format!(
            "panels '{list}': lesson {}'s panels are one whole; write 'panels on' or 'panels off'",
            index + 1
        ));
    }
    let names: Vec<&str> = list.split(',').map(str::trim).collect();
    if let Some(unknown) = names
        .iter()
        .find(|name| !parts.iter().any(|part| part.name == **name))
    {
        return Err(format!(
            "lesson {} has no panel '{unknown}'; write 'on', 'off' or some of: {}",
            index + 1,
            known()
        ));
    }
    Ok(parts
        .iter()
        .filter(|part| names.contains(&part.name))
        .map(|part| part.name)
        .collect())
}

fn question_slide(words: &[&str]) -> Result<Slide, String> {
    let names = accelviz_quiz::kind_names();
    let Some((kind, rest)) = words.split_first() else {
        return Err(format!(
            "which kind of question? the kinds are: {}",
            names.join(", ")
        ));
    };
    let kind = names
        .iter()
        .copied()
        .find(|name| name == kind)
        .ok_or_else(|| {
            format!(
                "unknown question kind '{kind}'; the kinds are: {}",
                names.join(", ")
            )
        })?;
    let mut seed = 1;
    let mut level = Level::Easy;
    for (key, value) in options(rest)? {
        match key {
            "seed" => {
                seed = value
                    .parse()
                    .map_err(|_| format!("seed '{value}' is not a whole number"))?;
            }
            "level" => level = Level::parse(value).map_err(|error| error.to_string())?,
            other => {
                return Err(format!(
                    "'{other}' is not an option of a question slide; they are: seed, level"
                ));
            }
        }
    }
    Ok(Slide::Question { kind, seed, level })
}
