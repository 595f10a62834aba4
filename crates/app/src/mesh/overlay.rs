//! What a recorded traversal adds to a 3D view: the triangles it tested, its closest hit so
//! far, and the ray.

use glam::DVec3;

use super::tree::MeshTree;
use crate::view3d::{DrawTriangle, Instance, relative};

/// What a view draws over the mesh: highlighted triangles, and segments (rays, markers).
pub type Overlay = (Vec<DrawTriangle>, Vec<Instance>);

/// What a recorded traversal of `ray` adds to the view after `steps`: the triangles tested
/// so far (orange) and the closest hit so far (green) drawn over the mesh, and the ray from
/// its origin to that hit (or through the scene).
pub fn trace_overlay(
    tree: &MeshTree,
    ray: &accelviz_core::Ray<DVec3>,
    steps: &[accelviz_core::Step<f64>],
) -> Overlay {
    let closest = crate::trace::closest_so_far(steps);
    let mut highlights = Vec::new();
    for step in steps {
        if let accelviz_core::Step::PrimitiveTested { primitive, .. } = *step
            && let Some(triangle) = tree.build.drawn.get(primitive as usize)
        {
            highlights.push(DrawTriangle {
                color: [255, 170, 30, 255],
                ..*triangle
            });
        }
    }
    if let Some((primitive, _)) = closest
        && let Some(triangle) = tree.build.drawn.get(primitive as usize)
    {
        highlights.push(DrawTriangle {
            color: [60, 220, 90, 255],
            ..*triangle
        });
    }
    let (center, radius) = tree.build.sphere;
    let far = (ray.origin - center).length() + radius;
    let end = closest.map_or(far / ray.direction.length(), |(_, t)| t);
    let color = crate::canvas::palette::RAY;
    let segments = vec![Instance {
        a: relative(ray.origin, tree.build.sphere),
        b: relative(ray.at(end), tree.build.sphere),
        color: [color.r(), color.g(), color.b(), 255],
    }];
    (highlights, segments)
}

/// The boxes (kD cells) a recorded traversal has met after `steps`, coloured as the tree
/// diagram colours them (entered green, missed or skipped red), and the box of the step
/// shown (`current`) in the current step's blue: the stepped picture lesson 12 draws.
pub fn trace_boxes(
    tree: &MeshTree,
    steps: &[accelviz_core::Step<f64>],
    current: Option<u32>,
) -> Vec<Instance> {
    let facts = &tree.build.built.facts;
    let emphasis = crate::views::tree_diagram::traversal_emphasis(steps, facts.node_count());
    let instance = |node: u32, color: egui::Color32| {
        let bounds = facts.bounds[node as usize];
        Instance {
            a: relative(bounds.min, tree.build.sphere),
            b: relative(bounds.max, tree.build.sphere),
            color: color.to_array(),
        }
    };
    let mut boxes: Vec<Instance> = (0..facts.node_count() as u32)
        .filter(|&node| Some(node) != current)
        .filter_map(|node| Some(instance(node, emphasis[node as usize]?)))
        .collect();
    boxes.extend(current.map(|node| instance(node, crate::canvas::palette::CURRENT)));
    boxes
}
