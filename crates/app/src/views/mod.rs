//! Drawings several lessons share: the scene's shapes and ray, a built tree on the canvas, the
//! tree as a diagram, and several trees of one scene side by side. Lessons draw with these and
//! never import from each other.

pub mod compare;
pub mod grid_walk;
pub mod number_lines;
pub mod scene_view;
pub mod tree_diagram;
pub mod tree_view;

/// The choice of a BVH's width (children per node: 2 as built, or collapsed to 4 or 8), for a
/// BVH structure; nothing for a kD-tree. Adds its widgets to `ui`'s own layout (call it in a
/// wrapping row).
pub fn width_ui(ui: &mut egui::Ui, structure: &mut accelviz_core::Structure) {
    use accelviz_core::{Family, Width};
    if structure.family() != Family::Bvh {
        return;
    }
    ui.label("Children per node");
    for width in Width::ALL {
        let hover = match width {
            Width::Binary => "The binary tree, as the builder made it".to_owned(),
            _ => format!(
                "The binary tree collapsed to {} children per node (Ylitie et al. 2017): a node's \
                 children are tested together",
                width.children()
            ),
        };
        if ui
            .selectable_label(structure.width() == width, width.children().to_string())
            .on_hover_text(hover)
            .clicked()
        {
            *structure = structure.with_width(width);
        }
    }
}
