//! A small JSON writer: numbers as Rust prints them (shortest round-trip), and ±∞ as
//! `1e999` / `-1e999`, which is valid JSON syntax that JavaScript and Python read as ±Infinity.

use std::fmt::Write;

/// One JSON object, written field by field.
#[derive(Default)]
pub struct JsonObject {
    text: String,
}

impl JsonObject {
    /// An empty object.
    pub fn new() -> Self {
        Self::default()
    }

    fn key(&mut self, key: &str) -> &mut String {
        self.text.push(if self.text.is_empty() { '{' } else { ',' });
        let _ = write!(self.text, "\"{key}\":");
        &mut self.text
    }

    /// A number field.
    pub fn number(mut self, key: &str, value: f64) -> Self {
        let formatted = number(value);
        self.key(key).push_str(&formatted);
        self
    }

    /// An integer field.
    pub fn integer(mut self, key: &str, value: u64) -> Self {
        let _ = write!(self.key(key), "{value}");
        self
    }

    /// A string field (the value must need no escaping beyond quotes and backslashes).
    pub fn string(mut self, key: &str, value: &str) -> Self {
        self.key(key).push_str(&string(value));
        self
    }

    /// A boolean field.
    pub fn boolean(mut self, key: &str, value: bool) -> Self {
        let _ = write!(self.key(key), "{value}");
        self
    }

    /// A field holding already-written JSON.
    pub fn raw(mut self, key: &str, json: &str) -> Self {
        self.key(key).push_str(json);
        self
    }

    /// The finished object.
    pub fn finish(mut self) -> String {
        if self.text.is_empty() {
            self.text.push('{');
        }
        self.text.push('}');
        self.text
    }
}

/// A string as JSON (it must need no escaping beyond quotes and backslashes).
pub fn string(value: &str) -> String {
    let escaped = value.replace('\\', "\\\\").replace('"', "\\\"");
    format!("\"{escaped}\"")
}

/// A number as JSON.
pub fn number(value: f64) -> String {
    if value == f64::INFINITY {
        "1e999".into()
    } else if value == f64::NEG_INFINITY {
        "-1e999".into()
    } else if value.is_nan() {
        "null".into()
    } else {
        format!("{value}")
    }
}

/// `{"agree": …, "tie": …, …}`: each outcome per million rays.
pub fn outcomes_json(outcomes: &accelviz_core::outcome::OutcomeCounts) -> String {
    accelviz_core::outcome::Outcome::ALL
        .iter()
        .fold(JsonObject::new(), |object, &outcome| {
            object.number(outcome.name(), outcomes.per_million(outcome))
        })
        .finish()
}
