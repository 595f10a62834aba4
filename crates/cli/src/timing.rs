//! Honest timings on a shared machine: every configuration is timed once per round, the rounds
//! run one after another (so drift and a busy neighbour hit every configuration alike), and a
//! figure is the median of its rounds with the range it moved in. The rounds and their
//! figures are the core's ([`accelviz_core::trade`]); the clock is this process's.

use std::sync::LazyLock;
use std::time::Instant;

pub use accelviz_core::trade::Samples;

/// When this process first asked the time.
static START: LazyLock<Instant> = LazyLock::new(Instant::now);

/// Milliseconds since [`START`].
pub fn now_ms() -> f64 {
    START.elapsed().as_secs_f64() * 1e3
}

/// Runs `rounds` rounds of `count` configurations, interleaved, timing each
/// ([`accelviz_core::trade::interleaved`]); `what` they are is said on a terminal as they go
/// ([`crate::progress`]).
pub fn interleaved(
    what: &str,
    rounds: usize,
    count: usize,
    run: impl FnMut(usize),
) -> Vec<Samples> {
    accelviz_core::trade::interleaved(rounds, count, now_ms, run, |done, total| {
        crate::progress::report(what, done, total)
    })
}
