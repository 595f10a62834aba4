//! What a quiz saves after every answer: the seed, level, kinds and count that make its
//! questions again, every response in order, where the student is, and the score (checked
//! when the responses are given again). JSON with a format name and version, so a foreign or
//! corrupt file is recognised and reported, never taken for progress.

use serde_json::{Map, Value, json};

use crate::generate::Level;
use crate::question::Response;

/// The `format` field of a progress file.
pub const PROGRESS_FORMAT: &str = "accelviz-quiz-progress";

/// The version written, and the only one read.
const VERSION: u64 = 1;

/// A quiz's saved state.
#[derive(Clone, Debug, PartialEq)]
pub struct Progress {
    /// The quiz's seed.
    pub seed: u64,
    /// Its level.
    pub level: Level,
    /// How many questions.
    pub count: usize,
    /// The kinds it cycles through.
    pub kinds: Vec<String>,
    /// Every response, in the order given.
    pub responses: Vec<Response>,
    /// The question and step the student is at.
    pub position: (usize, usize),
    /// Whether that step is answered and its explanation shown.
    pub revealed: bool,
    /// Steps answered right.
    pub score: usize,
}

/// Why saved text is not progress.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ProgressError {
    /// Not JSON, or JSON of another shape.
    #[error("not a quiz progress file: {0}")]
    Foreign(String),
    /// A progress file with a field missing or wrong, or cut off.
    #[error("a damaged quiz progress file: {0}")]
    Corrupt(String),
    /// A progress file a newer accelviz wrote, in a format this one does not know.
    #[error(
        "a quiz progress file from a newer accelviz (format version {0}; this one reads version {VERSION}): it is kept for that version"
    )]
    Newer(u64),
}

impl Progress {
    /// The JSON text saved.
    pub fn to_text(&self) -> String {
        let responses: Vec<Value> = self
            .responses
            .iter()
            .map(|response| match response {
                Response::Choice(index) => json!({"choice": index}),
                // JSON has no infinity or NaN; such an answer is wrong anyway, kept as null.
                Response::Number(value) => json!({"number": value.is_finite().then_some(*value)}),
            })
            .collect();
        let value = json!({
            "format": PROGRESS_FORMAT,
            "version": VERSION,
            "seed": self.seed,
            "level": self.level.name(),
            "count": self.count,
            "kinds": self.kinds,
            "responses": responses,
            "position": [self.position.0, self.position.1],
            "revealed": self.revealed,
            "score": self.score,
        });
        let mut text = serde_json::to_string_pretty(&value).unwrap_or_default();
        text.push('\n');
        text
    }

    /// Reads saved progress.
    pub fn parse(text: &str) -> Result<Self, ProgressError> {
        let value: Value = serde_json::from_str(text).map_err(|error| {
            if error.is_eof() && !text.trim().is_empty() {
                // JSON that stops mid-way was progress being written when it was cut off.
                ProgressError::Corrupt(format!("it ends early ({error})"))
            } else {
                ProgressError::Foreign(error.to_string())
            }
        })?;
        let Some(object) = value.as_object() else {
            return Err(ProgressError::Foreign("not a JSON object".into()));
        };
        if object.get("format").and_then(Value::as_str) != Some(PROGRESS_FORMAT) {
            return Err(ProgressError::Foreign(format!(
                "its \"format\" is not \"{PROGRESS_FORMAT}\""
            )));
        }
        let corrupt = |what: &str| ProgressError::Corrupt(what.to_owned());
        let field = |key: &str| {
            object
                .get(key)
                .ok_or_else(|| corrupt(&format!("no \"{key}\"")))
        };
        let unsigned = |key: &str| {
            field(key)?
                .as_u64()
                .ok_or_else(|| corrupt(&format!("\"{key}\" is not a whole number")))
        };
        let version = unsigned("version")?;
        if version > VERSION {
            return Err(ProgressError::Newer(version));
        }
        if version != VERSION {
            return Err(corrupt(&format!(
                "version {version}; this accelviz reads version {VERSION}"
            )));
        }
        let level = field("level")?
            .as_str()
            .and_then(|name| Level::parse(name).ok())
            .ok_or_else(|| corrupt("\"level\" is not easy, medium or hard"))?;
        let kinds = field("kinds")?
            .as_array()
            .and_then(|kinds| {
                kinds
                    .iter()
                    .map(|kind| kind.as_str().map(str::to_owned))
                    .collect::<Option<Vec<_>>>()
            })
            .ok_or_else(|| corrupt("\"kinds\" is not a list of names"))?;
        let responses = field("responses")?
            .as_array()
            .ok_or_else(|| corrupt("\"responses\" is not a list"))?
            .iter()
            .map(response)
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| corrupt("a response is neither {\"choice\": n} nor {\"number\": x}"))?;
        let position = field("position")?
            .as_array()
            .filter(|pair| pair.len() == 2)
            .and_then(|pair| Some((pair[0].as_u64()? as usize, pair[1].as_u64()? as usize)))
            .ok_or_else(|| corrupt("\"position\" is not [question, step]"))?;
        Ok(Self {
            seed: unsigned("seed")?,
            level,
            count: unsigned("count")? as usize,
            kinds,
            responses,
            position,
            revealed: field("revealed")?
                .as_bool()
                .ok_or_else(|| corrupt("\"revealed\" is not true or false"))?,
            score: unsigned("score")? as usize,
        })
    }
}

fn response(value: &Value) -> Option<Response> {
    let object: &Map<String, Value> = value.as_object()?;
    if let Some(index) = object.get("choice") {
        return Some(Response::Choice(index.as_u64()? as usize));
    }
    match object.get("number")? {
        Value::Null => Some(Response::Number(f64::NAN)),
        number => Some(Response::Number(number.as_f64()?)),
    }
}
