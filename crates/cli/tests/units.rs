//! The unit tests of the CLI's modules that stand alone (the SVG plots, the worker threads):
//! their files compiled here with their `#[cfg(test)]` tests, so the CLI itself is not
//! compiled a second time as a test harness (its `[[bin]]` has `test = false`).

#[allow(dead_code)]
#[path = "../src/plot.rs"]
mod plot;

#[allow(dead_code)]
#[path = "../src/parallel.rs"]
mod parallel;
