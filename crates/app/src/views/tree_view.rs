//! A built tree on the canvas: a BVH's boxes coloured by depth, each nested box drawn a little
//! inside its parent (as the slide draws them), or a kD-tree's split lines across their cells.
//! What a traversal has done so far, and the nodes lit by hovering or selection, stand out in
//! colours and widths readable on a projector.

use std::ops::RangeInclusive;

use accelviz_core::{Aabb, Family, Step};
use egui::{Color32, Pos2, Rect, Stroke, StrokeKind, Vec2};
use glam::DVec2;

use crate::canvas::{BATCH_ABOVE, Canvas, SMALLEST_DRAWN, faded, palette};
use crate::stage::SceneTree;

/// What to draw of a tree, and what stands out.
pub struct TreeLook<'a> {
    /// The depths whose boxes or splits are drawn.
    pub depths: RangeInclusive<usize>,
    /// The node under the pointer: thick, filled, with a white halo.
    pub hovered: Option<u32>,
    /// The selected node: thick, with a white halo (not filled, so a big selected box does
    /// not hide what it holds).
    pub selected: Option<u32>,
    /// The steps of a traversal shown so far: tested boxes turn green (hit) or red (missed),
    /// skipped nodes red, the current node blue.
    pub steps: &'a [Step<f64>],
    /// How opaque the boxes or splits in their depth colours are drawn: 230 plainly, less
    /// when a traversal is the point, 0 not at all (only the traversal and the lit nodes).
    pub structure_alpha: u8,
    /// Whether the node of the last step shown is marked as the current one (a quiz asking
    /// which node comes next does not give it away).
    pub mark_current: bool,
}

impl Default for TreeLook<'_> {
    fn default() -> Self {
        Self {
            depths: 0..=usize::MAX,
            hovered: None,
            selected: None,
            steps: &[],
            structure_alpha: 230,
            mark_current: true,
        }
    }
}

/// How far a box at `depth` is drawn inside its true outline, in points: enough to tell a
/// child from its parent where they share an edge, never more than a fifth of the box.
fn inset(rect: Rect, depth: usize) -> Rect {
    let amount = (depth as f32 * 3.0).min(rect.width().min(rect.height()) * 0.2);
    rect.shrink(amount.max(0.0))
}

/// Draws `tree` on `canvas` as `look` says.
pub fn draw_tree(canvas: &Canvas, tree: &SceneTree, look: &TreeLook) {
    let facts = &tree.built.facts;
    let shown = |node: usize| look.depths.contains(&(facts.depth[node] as usize));
    let alpha = look.structure_alpha;
    match tree.built.tree.family() {
        _ if alpha == 0 => {}
        Family::Bvh => {
            let count = facts.node_count();
            if count > BATCH_ABOVE {
                let key = (tree.id, alpha, look.depths.start(), look.depths.end());
                canvas.cached_batch("tree boxes", key, |batch| {
                    // Shallowest first: if the budget runs out, the deepest levels are left out.
                    for node in facts
                        .by_depth
                        .iter()
                        .map(|&node| node as usize)
                        .filter(|&node| shown(node))
                    {
                        let screen = canvas.screen_rect(&facts.bounds[node]);
                        if screen.width().max(screen.height()) < SMALLEST_DRAWN
                            || !canvas.rect.intersects(screen)
                        {
                            continue;
                        }
                        let color = faded(canvas.depth_color(facts.depth[node] as usize), alpha);
                        batch.rect_outline(inset(screen, facts.depth[node] as usize), 1.0, color);
                    }
                });
            } else {
                for node in (0..count).filter(|&node| shown(node)) {
                    let depth = facts.depth[node] as usize;
                    let color = faded(canvas.depth_color(depth), alpha);
                    node_outline(canvas, tree, node as u32, Stroke::new(1.5, color), None);
                }
            }
        }
        Family::Kd | Family::Octree => {
            canvas.box_outline(
                &tree.built.root_bounds(),
                Stroke::new(1.5, faded(canvas.depth_color(0), alpha)),
                None,
            );
            // Shallowest first: if the budget runs out, the deepest levels are left out.
            let splits = || {
                facts
                    .by_depth
                    .iter()
                    .map(|&node| node as usize)
                    .filter(|&node| !facts.is_leaf(node as u32) && shown(node))
                    .flat_map(|node| {
                        let color =
                            faded(canvas.depth_color(facts.depth[node] as usize + 1), alpha);
                        let cell = facts.bounds[node];
                        tree.built
                            .cuts(node as u32)
                            .into_iter()
                            .map(move |(axis, position)| {
                                (cell, axis, position, Stroke::new(1.5, color))
                            })
                    })
            };
            if facts.node_count() > BATCH_ABOVE {
                let key = (tree.id, alpha, look.depths.start(), look.depths.end());
                canvas.cached_batch("split lines", key, |batch| {
                    canvas.batch_split_lines(batch, splits());
                });
            } else {
                canvas.split_lines(splits());
            }
        }
        Family::Grid | Family::HashedGrid => {
            let bounds = tree.built.root_bounds();
            canvas.box_outline(
                &bounds,
                Stroke::new(1.5, faded(canvas.depth_color(0), alpha)),
                None,
            );
            // Every line between cells, across the whole grid (the cells' depth is 1).
            if look.depths.contains(&1) {
                let stroke = Stroke::new(1.0, faded(canvas.depth_color(1), alpha));
                let lines = tree
                    .built
                    .grid_planes()
                    .into_iter()
                    .flat_map(|(axis, planes)| {
                        planes
                            .into_iter()
                            .map(move |position| (bounds, axis, position, stroke))
                    });
                let key = (tree.id, alpha, look.depths.start(), look.depths.end());
                canvas.cached_batch("grid lines", key, |batch| {
                    canvas.batch_split_lines(batch, lines);
                });
            }
        }
    }
    draw_traversal(canvas, tree, look);
    for (node, filled) in [(look.selected, false), (look.hovered, true)] {
        if let Some(node) = node.filter(|&node| (node as usize) < facts.node_count()) {
            light(canvas, tree, node, filled);
        }
    }
}

/// Where `node`'s box is drawn on screen: a BVH node's moved in by its depth so nested
/// boxes stay apart, a kD cell as it is; at least a point wide. `None` when it is empty or
/// off the canvas.
pub fn node_rect(canvas: &Canvas, tree: &SceneTree, node: u32) -> Option<Rect> {
    let facts = &tree.built.facts;
    let bounds = &facts.bounds[node as usize];
    if bounds.is_empty() {
        return None;
    }
    let screen = canvas.screen_rect(bounds);
    if !canvas.rect.intersects(screen.expand(4.0)) {
        return None;
    }
    let rect = match tree.built.tree.family() {
        Family::Bvh => inset(screen, facts.depth[node as usize] as usize),
        Family::Kd | Family::Grid | Family::HashedGrid | Family::Octree => screen,
    };
    // A flat box still shows: at least one point wide on screen.
    Some(rect.union(Rect::from_center_size(screen.center(), Vec2::splat(1.0))))
}

/// Outlines `node`'s box (inset by its depth) or cell, optionally filled.
pub fn node_outline(
    canvas: &Canvas,
    tree: &SceneTree,
    node: u32,
    stroke: Stroke,
    fill: Option<Color32>,
) {
    let Some(rect) = node_rect(canvas, tree, node) else {
        return;
    };
    if let Some(fill) = fill {
        canvas.painter.rect_filled(rect, 0.0, fill);
    }
    canvas
        .painter
        .rect_stroke(rect, 0.0, stroke, StrokeKind::Middle);
}

/// A node lit by hovering or selection: a white halo under a thick blue outline, filled when
/// `filled`. Bright and thick enough to see on a projector.
pub fn light(canvas: &Canvas, tree: &SceneTree, node: u32, filled: bool) {
    node_outline(canvas, tree, node, Stroke::new(7.0, Color32::WHITE), None);
    node_outline(
        canvas,
        tree,
        node,
        Stroke::new(4.0, palette::CURRENT),
        filled.then(|| faded(palette::CURRENT, 60)),
    );
}

/// What the traversal shown so far did: boxes tested green or red, skipped nodes red, and the
/// node of the current step blue. Only nodes in the depth range are drawn.
fn draw_traversal(canvas: &Canvas, tree: &SceneTree, look: &TreeLook) {
    let facts = &tree.built.facts;
    let in_range = |node: u32| {
        (node as usize) < facts.node_count()
            && look.depths.contains(&(facts.depth[node as usize] as usize))
    };
    for step in look.steps {
        let (node, color, fill) = match *step {
            Step::BoxTested { node, hit, .. } if tree.built.tree.family() == Family::Bvh => {
                let color = if hit { palette::HIT } else { palette::MISS };
                (node, color, None)
            }
            Step::NodeCulled { node, .. } => (node, palette::MISS, Some(faded(palette::MISS, 30))),
            _ => continue,
        };
        if in_range(node) {
            node_outline(
                canvas,
                tree,
                node,
                Stroke::new(2.5, faded(color, 210)),
                fill,
            );
        }
    }
    let current = look
        .steps
        .last()
        .filter(|_| look.mark_current)
        .and_then(crate::trace::step_node);
    if let Some(node) = current.filter(|&node| in_range(node)) {
        node_outline(canvas, tree, node, Stroke::new(4.0, palette::CURRENT), None);
    }
}

/// The node under a screen point: the deepest BVH box in the depth range holding it, or the
/// kD leaf cell holding it.
pub fn node_under(
    canvas: &Canvas,
    tree: &SceneTree,
    pos: Pos2,
    depths: &RangeInclusive<usize>,
) -> Option<u32> {
    let at: DVec2 = canvas.to_world(pos);
    let facts = &tree.built.facts;
    let holds = |node: u32| facts.bounds[node as usize].contains_point(at);
    match tree.built.tree.family() {
        Family::Bvh => (0..facts.node_count() as u32)
            .filter(|&node| depths.contains(&(facts.depth[node as usize] as usize)) && holds(node))
            .max_by_key(|&node| facts.depth[node as usize]),
        Family::Kd | Family::Grid | Family::HashedGrid | Family::Octree => {
            // Walk down from the root through the cells holding the point.
            let mut node = 0u32;
            if facts.node_count() == 0 || !holds(0) {
                return None;
            }
            while let Some(children) = facts.children[node as usize] {
                node = children.into_iter().find(|&child| holds(child))?;
            }
            Some(node)
        }
    }
}

/// The world box a canvas should fit to show `tree` and the scene around it.
pub fn tree_bounds(tree: &SceneTree) -> Aabb<DVec2> {
    tree.built.root_bounds()
}
