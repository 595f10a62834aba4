//! Work that can take a while (building three kD-trees over 100,000 shapes) runs on a worker
//! thread on the desktop, so the UI keeps drawing the last result and says it is building.
//! The browser has no threads: there large work waits one frame, so the frame that asks can
//! say "building…" before the page is busy. In tests the work is done at once, so a test
//! sees the result in the frame that asked for it.
//!
//! A [`Derived`] value is remade when its key changes (the scene's revision, the lesson's
//! choices). At most one job runs per value; a key that changes while it runs waits for it,
//! and only the newest waiting key is made next, so dragging a slider does not queue a build
//! per frame.

use std::cell::Cell;
use std::sync::Arc;
use std::time::Duration;

use web_time::Instant;

thread_local! {
    /// Whether work of some size that this thread asks for goes to worker threads: a setting
    /// of the thread that runs the UI (the desktop app's main thread), off until it is turned
    /// on, so tests on other threads of the same process each choose for themselves.
    static BACKGROUND: Cell<bool> = const { Cell::new(false) };
}

/// Work on fewer primitives than this is done at once even in the background mode: it takes
/// a few milliseconds, and a result in the same frame keeps small scenes flicker-free.
pub const AT_ONCE_BELOW: usize = 3_000;

/// Turns worker threads on (the desktop app) or off (the default: the browser, tests) for
/// the work the calling thread asks for.
pub fn set_background(on: bool) {
    BACKGROUND.set(on && cfg!(not(target_arch = "wasm32")));
}

/// How many worker threads work that can be shared out may use: every core on the desktop,
/// none (0: work a slice a frame on the UI thread) in the browser and in tests.
pub fn worker_threads() -> usize {
    if BACKGROUND.get() {
        std::thread::available_parallelism().map_or(1, usize::from)
    } else {
        0
    }
}

/// Whether work of `size` primitives goes to a worker thread.
fn in_background(size: usize) -> bool {
    size >= AT_ONCE_BELOW && BACKGROUND.get()
}

/// Whether work of `size` primitives waits a frame (the browser, which cannot run it aside).
fn deferred(size: usize) -> bool {
    size >= AT_ONCE_BELOW && cfg!(target_arch = "wasm32")
}

/// Work that makes a `T`.
type Work<T> = Box<dyn FnOnce() -> T + Send>;

/// A job on a worker thread (or elsewhere: a Web Worker, kept going by `handle`).
struct Job<K, T> {
    key: K,
    started: Instant,
    result: std::sync::mpsc::Receiver<T>,
    /// Keeps work done elsewhere going; dropped, it stops it.
    _handle: Option<Box<dyn std::any::Any>>,
}

/// A value made from a key, remade when the key changes.
pub struct Derived<K, T> {
    current: Option<(K, Arc<T>)>,
    /// Bumped every time `current` changes, so what is made from the value knows to follow.
    generation: u64,
    running: Option<Job<K, T>>,
    waiting: Option<(K, Work<T>)>,
    /// Work put off to the next frame (the browser), with when it was asked for.
    put_off: Option<(K, Work<T>, Instant)>,
}

impl<K, T> Default for Derived<K, T> {
    fn default() -> Self {
        Self {
            current: None,
            generation: 0,
            running: None,
            waiting: None,
            put_off: None,
        }
    }
}

impl<K: Clone + PartialEq + Send + 'static, T: Send + Sync + 'static> Derived<K, T> {
    /// Makes sure the value for `key` exists or is being made. `work` is asked for the work
    /// only when the key is new (so it can clone its inputs then, not every frame); `size`
    /// (primitives) decides whether it runs at once or on a worker thread.
    pub fn request<W: FnOnce() -> T + Send + 'static>(
        &mut self,
        key: &K,
        size: usize,
        work: impl FnOnce() -> W,
    ) {
        self.poll();
        let known = self.current.as_ref().is_some_and(|(made, _)| made == key)
            || self.running.as_ref().is_some_and(|job| job.key == *key)
            || self
                .waiting
                .as_ref()
                .is_some_and(|(waiting, _)| waiting == key)
            || self
                .put_off
                .as_ref()
                .is_some_and(|(put_off, _, _)| put_off == key);
        if known {
            return;
        }
        let work: Work<T> = Box::new(work());
        if deferred(size) {
            self.put_off = Some((key.clone(), work, Instant::now()));
            return;
        }
        if !in_background(size) {
            // At once: anything running or waiting is for an older key.
            self.waiting = None;
            self.running = None;
            self.set(key.clone(), work());
            return;
        }
        if self.running.is_some() {
            self.waiting = Some((key.clone(), work));
        } else {
            self.start(key.clone(), work);
        }
    }

    /// Like [`Derived::request`], for work done elsewhere (a Web Worker in the browser):
    /// `start` is given where to send the value, and returns a handle that keeps the work
    /// going; a newer key or [`Derived::cancel`] drops it, which stops the work. Returns
    /// whether the work runs (or is known already).
    pub fn request_elsewhere<H: 'static>(
        &mut self,
        key: &K,
        start: impl FnOnce(std::sync::mpsc::Sender<T>) -> Result<H, String>,
    ) -> bool {
        self.poll();
        let known = self.current.as_ref().is_some_and(|(made, _)| made == key)
            || self.running.as_ref().is_some_and(|job| job.key == *key);
        if known {
            return true;
        }
        let (sender, result) = std::sync::mpsc::channel();
        match start(sender) {
            Ok(handle) => {
                self.waiting = None;
                self.put_off = None;
                self.running = Some(Job {
                    key: key.clone(),
                    started: Instant::now(),
                    result,
                    _handle: Some(Box::new(handle)),
                });
                true
            }
            Err(problem) => {
                log::error!("accelviz: cannot work aside: {problem}");
                false
            }
        }
    }

    /// Takes a finished job's result, and starts the waiting one; does work put off by the
    /// frame before.
    pub fn poll(&mut self) {
        if let Some((key, work, _)) = self.put_off.take() {
            self.set(key, work());
        }
        let Some(job) = &self.running else { return };
        match job.result.try_recv() {
            Ok(value) => {
                let key = job.key.clone();
                self.running = None;
                self.set(key, value);
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => return,
            // The worker panicked: nothing will come. Keep the last value.
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                log::error!("accelviz: a background build failed");
                self.running = None;
            }
        }
        if let Some((key, work)) = self.waiting.take() {
            self.start(key, work);
        }
    }

    fn set(&mut self, key: K, value: T) {
        self.current = Some((key, Arc::new(value)));
        self.generation += 1;
    }

    fn start(&mut self, key: K, work: Work<T>) {
        let (sender, result) = std::sync::mpsc::channel();
        let spawned = std::thread::Builder::new()
            .name("accelviz build".into())
            .spawn(move || {
                let _ = sender.send(work());
            });
        match spawned {
            Ok(_) => {
                self.running = Some(Job {
                    key,
                    started: Instant::now(),
                    result,
                    _handle: None,
                })
            }
            Err(error) => log::error!("accelviz: cannot start a worker thread: {error}"),
        }
    }

    /// Gives up on the work running and waiting: the current value stays, and what the
    /// worker makes is thrown away when it is done.
    pub fn cancel(&mut self) {
        self.running = None;
        self.waiting = None;
        self.put_off = None;
    }

    /// The newest value made (possibly for an older key while a newer one is being made).
    pub fn get(&self) -> Option<&Arc<T>> {
        self.current.as_ref().map(|(_, value)| value)
    }

    /// The key the current value was made for.
    pub fn key(&self) -> Option<&K> {
        self.current.as_ref().map(|(key, _)| key)
    }

    /// Changes whenever the value does.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// How long the running (or put off) job has been waited for, if one is.
    pub fn working_for(&self) -> Option<Duration> {
        self.running
            .as_ref()
            .map(|job| job.started.elapsed())
            .or_else(|| self.put_off.as_ref().map(|(_, _, asked)| asked.elapsed()))
    }
}

/// Something made from a key at once, remade when the key changes (the cheap derived state:
/// a traversal recorded on the current ray).
pub struct Cached<K, T> {
    current: Option<(K, T)>,
}

impl<K, T> Default for Cached<K, T> {
    fn default() -> Self {
        Self { current: None }
    }
}

impl<K: PartialEq, T> Cached<K, T> {
    /// The value for `key`, made by `make` if the key changed.
    pub fn get_or_make(&mut self, key: K, make: impl FnOnce() -> T) -> &mut T {
        if self.current.as_ref().is_none_or(|(made, _)| *made != key) {
            self.current = Some((key, make()));
        }
        &mut self
            .current
            .as_mut()
            .unwrap_or_else(|| unreachable!("set above"))
            .1
    }

    /// The value, whatever key it was made for.
    pub fn get(&self) -> Option<&T> {
        self.current.as_ref().map(|(_, value)| value)
    }

    /// Forgets the value, so the next [`get_or_make`](Self::get_or_make) makes it again.
    pub fn clear(&mut self) {
        self.current = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_work_is_done_at_once_and_redone_only_for_a_new_key() {
        let mut derived: Derived<u32, u32> = Derived::default();
        derived.request(&1, 10, || || 10);
        assert_eq!(derived.get().map(|value| **value), Some(10));
        let generation = derived.generation();
        derived.request(&1, 10, || -> fn() -> u32 { panic!("the key is known") });
        assert_eq!(derived.generation(), generation);
        derived.request(&2, 10, || || 20);
        assert_eq!(derived.get().map(|value| **value), Some(20));
        assert_eq!(derived.key(), Some(&2));
    }
}
