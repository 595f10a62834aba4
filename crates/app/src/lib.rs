//! # accelviz-app
//!
//! The interactive lessons: every idea of the bounding-volumes lecture as a 2D scene a student
//! can poke at. A lesson edits a scene ([`editor`]), hands it to the core's builders and
//! traversals with a `Recorder` observer, and draws what was recorded on a [`canvas`], stepped
//! through by a [`timeline`]. The same code runs on the desktop (eframe on wgpu) and in the
//! browser (WASM; WebGPU or WebGL2).

pub mod app;
pub mod canvas;
pub mod editor;
pub mod files;
pub mod lessons;
pub mod timeline;

pub use app::AccelvizApp;
