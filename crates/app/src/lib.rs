//! # accelviz-app
//!
//! The interactive lessons: every idea of the bounding-volumes lecture as a 2D scene a student
//! can poke at. A lesson ([`lesson`], listed once in [`registry`]) keeps its text, scene and
//! timeline in a [`stage`]; it builds structures with the core's catalogue
//! ([`stage::SceneTree`], in the [`background`] on the desktop when large), records the one
//! traversal with a `Recorder` ([`trace`]), and draws with the shared [`views`] on a
//! [`canvas`]; the 3D lessons draw on the [`view3d`]. The same code runs on the desktop (eframe on wgpu) and in the browser (WASM;
//! WebGPU or WebGL2).

pub mod app;
pub mod background;
pub mod canvas;
pub mod editor;
pub mod files;
pub mod fonts;
pub mod lecture;
pub mod lesson;
pub mod lesson_file;
pub mod lessons;
pub mod mesh;
pub mod position;
pub mod quiz;
pub mod registry;
pub mod share;
pub mod stage;
pub mod timeline;
pub mod trace;
pub mod view3d;
pub mod views;
pub mod web_bench;

pub use app::AccelvizApp;
