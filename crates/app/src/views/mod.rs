//! Drawings several lessons share: the scene's shapes and ray, a built tree on the canvas, the
//! tree as a diagram, and several trees of one scene side by side. Lessons draw with these and
//! never import from each other.

pub mod compare;
pub mod number_lines;
pub mod scene_view;
pub mod tree_diagram;
pub mod tree_view;
