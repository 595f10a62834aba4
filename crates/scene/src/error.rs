//! Load errors that name the file, the line and the problem.

use std::fmt;

/// Where in which file something is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// The file's path as given.
    pub path: String,
    /// The 1-based line, when one line is to blame.
    pub line: Option<usize>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{line}", self.path),
            None => write!(f, "{}", self.path),
        }
    }
}

/// Why a file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be opened or read.
    #[error("{path}: cannot read the file: {cause}")]
    Io {
        /// The path.
        path: String,
        /// What the system said. (Not a `source`: the message already says it, and error
        /// chains would print it twice.)
        cause: std::io::Error,
    },
    /// `builtin:NAME` names no built-in mesh; the message lists them.
    #[error(
        "unknown built-in mesh '{name}'; built-in meshes are: {}",
        crate::builtin::names().join(", ")
    )]
    UnknownBuiltin {
        /// The name after `builtin:`.
        name: String,
    },
    /// The content is wrong at a place.
    #[error("{location}: {problem}")]
    Invalid {
        /// Where.
        location: Location,
        /// What is wrong.
        problem: String,
    },
}

impl LoadError {
    /// An error at `line` (1-based) of `path`.
    pub fn at_line(path: &str, line: usize, problem: impl Into<String>) -> Self {
        Self::Invalid {
            location: Location {
                path: path.to_owned(),
                line: Some(line),
            },
            problem: problem.into(),
        }
    }

    /// An error about the whole of `path`.
    pub fn in_file(path: &str, problem: impl Into<String>) -> Self {
        Self::Invalid {
            location: Location {
                path: path.to_owned(),
                line: None,
            },
            problem: problem.into(),
        }
    }
}

/// The largest file accelviz reads (1 GiB): larger ones are refused before reading.
pub const MAX_FILE_BYTES: u64 = 1 << 30;

/// Reads a text file whole, refusing huge files and non-UTF-8 content with a clear error.
pub fn read_text(path: &str) -> Result<String, LoadError> {
    let io = |cause| LoadError::Io {
        path: path.to_owned(),
        cause,
    };
    let size = std::fs::metadata(path).map_err(io)?.len();
    if size > MAX_FILE_BYTES {
        return Err(LoadError::in_file(
            path,
            format!("the file is {size} bytes; the limit is {MAX_FILE_BYTES}"),
        ));
    }
    let bytes = std::fs::read(path).map_err(io)?;
    String::from_utf8(bytes).map_err(|error| {
        let offset = error.utf8_error().valid_up_to();
        let line = error.as_bytes()[..offset]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1;
        LoadError::at_line(path, line, "the file is not UTF-8 text")
    })
}
