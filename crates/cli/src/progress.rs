//! What a long run is doing, on stderr, for a person watching it: only when stderr is a
//! terminal (a pipe, a file or a test hears nothing, so every output stays as it was), at
//! most a few times a second, each line over the last, and gone when the run ends. A run of
//! a minute on a large mesh or a ray file of millions otherwise printed nothing until its
//! end.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How often the line changes at most.
const EVERY: Duration = Duration::from_millis(250);

/// When the run started, and when the line last changed (`None` until then, or when stderr
/// is no terminal).
struct State {
    started: Instant,
    shown: Option<Instant>,
}

static STATE: Mutex<Option<State>> = Mutex::new(None);

/// Says that `what` has done `done` of `total` (with the run's time, and the time left at
/// this pace).
pub fn report(what: &str, done: usize, total: usize) {
    if !std::io::stderr().is_terminal() {
        return;
    }
    let Ok(mut state) = STATE.lock() else { return };
    let now = Instant::now();
    let state = state.get_or_insert(State {
        started: now,
        shown: None,
    });
    if state.shown.is_some_and(|shown| now - shown < EVERY) && done < total {
        return;
    }
    state.shown = Some(now);
    let elapsed = (now - state.started).as_secs_f64();
    let left = if done > 0 && done < total {
        format!(
            ", about {:.0} s left",
            elapsed / done as f64 * (total - done) as f64
        )
    } else {
        String::new()
    };
    let percent = done as f64 / total.max(1) as f64 * 100.0;
    let mut stderr = std::io::stderr().lock();
    let _ = write!(
        stderr,
        "\r\x1b[2K{what}: {done} of {total} ({percent:.0} %), {elapsed:.0} s{left}"
    );
    let _ = stderr.flush();
}

/// Takes the line away (the run's output follows on stdout).
pub fn clear() {
    if let Ok(mut state) = STATE.lock()
        && state.as_ref().is_some_and(|state| state.shown.is_some())
    {
        let mut stderr = std::io::stderr().lock();
        let _ = write!(stderr, "\r\x1b[2K");
        let _ = stderr.flush();
        *state = None;
    }
}
