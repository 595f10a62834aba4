//! A 3D lesson's model, apart from the widget that draws it ([`crate::view3d`]): the mesh
//! ([`scene`]: built in, or an OBJ opened, a large one read aside), a catalogue structure
//! built over it ([`tree`]), the work done aside for large meshes ([`aside`]: worker threads on
//! the desktop, a Web Worker in the browser, which runs [`work`] and sends its results back as
//! bytes, [`packed`]; the browser's worker plumbing in `worker`), the heat
//! maps' jobs ([`heat`]), the trade lab's measurement ([`trade`]), what a traced ray adds to
//! the view ([`overlay`]), and the choosers and progress line every 3D lesson shows ([`ui`]).
//!
//! The layers point one way: `tree` ← `packed` ← `work`, `worker` ← `aside` ← `scene` ← `ui`;
//! `heat`, `trade` and `overlay` read a `tree`.

pub mod aside;
pub mod heat;
pub mod overlay;
pub mod packed;
pub mod scene;
pub mod trade;
pub mod tree;
pub mod ui;
pub mod work;
#[cfg(target_arch = "wasm32")]
pub mod worker;

pub use overlay::{Overlay, trace_boxes, trace_overlay};
pub use scene::MeshScene;
pub use tree::{MeshBuild, MeshTree};
pub use ui::{loading_ui, mesh_and_structure_ui};
