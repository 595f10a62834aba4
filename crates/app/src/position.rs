//! Where the app is: each mode (the lessons, the quiz, lecture mode) says it in its own
//! position line, which the app logs once per change (the browser test reads it) and puts in
//! the window's or the page's title.

/// Where the app is, as one line for the log (`accelviz: lesson 4 (…), step 3 of 12`) and as
/// the window's or the page's title.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Position {
    /// The log's line.
    pub line: String,
    /// The title (the desktop's window keeps what comes before ", step").
    pub title: String,
}
