//! The quiz engine's integration tests, one module a subject, in one test binary.

mod answers;
mod fairness;
mod session;
