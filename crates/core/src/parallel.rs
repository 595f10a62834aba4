//! When the builders split their work between threads.
//!
//! They fork (`rayon::join`, parallel iterators) only where the current rayon pool has more
//! than one thread. On one thread, and in WebAssembly, where rayon runs every job on the
//! calling thread, forking would only cost: the work-splitting recursion's frames, which on
//! WebAssembly's 1 MiB stack without a guard page overflowed silently into memory (a
//! layout of 120,000 boxes did, and the test runner crashed after its tests had passed). The
//! trees are the same either way (tested).

/// Whether the current rayon pool has threads to share work with.
#[inline]
pub(crate) fn has_threads() -> bool {
    rayon::current_num_threads() > 1
}
