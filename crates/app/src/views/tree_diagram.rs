//! A tree drawn as a diagram from the core's [`TreeFacts`]: leaves side by side in tree order,
//! each parent above the middle of its children. Hovering a node reports it (the canvas lights
//! its box), clicking selects it; the canvas reports its own hovering back, so the link works
//! both ways. Levels too crowded to tell nodes apart are left out and the diagram says so;
//! labels sit on plates, never on each other, and only where they fit.

use accelviz_core::{Step, TreeFacts, Vector};
use egui::{Align2, Color32, Pos2, Rect, Sense, Stroke, Vec2};

use crate::canvas::{Labels, depth_color, faded, palette};

/// A level's height in the diagram when there is room, and the least it is squeezed to.
const ROW_HEIGHT: f32 = 36.0;
const MIN_ROW_HEIGHT: f32 = 22.0;
/// Nodes drawn smaller than this are not labelled: a label would not fit beside them.
const MIN_LABELLED_RADIUS: f32 = 6.0;

/// Each shown node's column (in leaf widths) when the tree is cut at `bottom`: nodes at that
/// depth count as leaves. Depth first, left to right: leaves take the next column, parents
/// sit between their children.
fn columns<V: Vector>(facts: &TreeFacts<V>, bottom: usize) -> (Vec<f32>, usize) {
    let mut column = vec![f32::NAN; facts.node_count()];
    let mut leaves = 0usize;
    // An explicit stack: (node, whether its children are placed).
    let mut pending = vec![(0u32, false)];
    while let Some((node, children_done)) = pending.pop() {
        let children = facts.children[node as usize]
            .filter(|_| (facts.depth[node as usize] as usize) < bottom);
        match (children, children_done) {
            (None, _) => {
                column[node as usize] = leaves as f32;
                leaves += 1;
            }
            (Some(children), true) => {
                // Between its first and its last child.
                let (first, last) = (children.first, children.first + children.count - 1);
                column[node as usize] = (column[first as usize] + column[last as usize]) * 0.5;
            }
            (Some(children), false) => {
                pending.push((node, true));
                pending.extend(children.iter().rev().map(|child| (child, false)));
            }
        }
    }
    (column, leaves)
}

/// Draws the diagram at the available width, each node named by `label` and coloured by what
/// the traversal's `steps` did to it (green entered, red missed or skipped); with
/// `fit_height`, its levels squeezed into the height left (a lecture slide's panel). Linked to
/// the canvas both ways: `hovered` (lit from the canvas) is lit here and set to the node under
/// the pointer; a click selects a node.
pub fn diagram_ui<V: Vector>(
    ui: &mut egui::Ui,
    facts: &TreeFacts<V>,
    label: &dyn Fn(u32) -> String,
    steps: &[Step<f64>],
    hovered: &mut Option<u32>,
    selected: &mut Option<u32>,
    fit_height: bool,
) {
    if facts.node_count() == 0 {
        return;
    }
    let emphasis = traversal_emphasis(steps, facts.node_count());
    let width = ui.available_width().max(120.0);
    // Levels too crowded to tell nodes apart (a few points each) are left out.
    let shown_depth = facts
        .nodes_per_depth
        .iter()
        .position(|&count| count as f32 * 4.0 > width)
        .map_or(facts.max_depth(), |crowded| crowded.saturating_sub(1));
    let (column, leaf_count) = columns(facts, shown_depth);
    let column_width = (width - 20.0) / leaf_count.max(1) as f32;
    let widest = facts.nodes_per_depth[..=shown_depth]
        .iter()
        .copied()
        .max()
        .unwrap_or(1)
        .max(1);
    // As large as the widest level leaves room for; labels only on nodes that large.
    let widest_radius = ((width - 20.0) / widest as f32 * 0.42).min(column_width * 0.42);
    let labelled = widest_radius >= MIN_LABELLED_RADIUS;
    // Room below the last row for its labels, or for the note on the depths left out; to
    // fit the height, rows as tall as the room left allows, down to a readable minimum (a
    // lecture slide's panel shows the tree below the ray's numbers without scrolling).
    let bottom_room = if labelled { 30.0 } else { 16.0 };
    let row_height = if fit_height {
        // And room after it for the notes lessons put under it (what the colours mean, the
        // selected leaf): two lines of body text.
        let notes_room =
            2.0 * ui.text_style_height(&egui::TextStyle::Body) + 2.0 * ui.spacing().item_spacing.y;
        ((ui.available_height() - bottom_room - notes_room) / (shown_depth + 1) as f32)
            .clamp(MIN_ROW_HEIGHT, ROW_HEIGHT)
    } else {
        ROW_HEIGHT
    };
    let height = (shown_depth + 1) as f32 * row_height + bottom_room;
    let (rect, response) = ui.allocate_exact_size(Vec2::new(width, height), Sense::click());
    let painter = ui.painter_at(rect);
    let position = |node: u32| -> Pos2 {
        Pos2::new(
            rect.left() + 10.0 + (column[node as usize] + 0.5) * column_width,
            rect.top() + 12.0 + facts.depth[node as usize] as f32 * row_height,
        )
    };
    let visible = |node: u32| (facts.depth[node as usize] as usize) <= shown_depth;
    let line_color = ui.visuals().weak_text_color();
    for node in (0..facts.node_count() as u32).filter(|&node| visible(node)) {
        if (facts.depth[node as usize] as usize) >= shown_depth {
            continue;
        }
        if let Some(children) = facts.children[node as usize] {
            for child in children {
                painter.line_segment(
                    [position(node), position(child)],
                    Stroke::new(1.0, line_color),
                );
            }
        }
    }
    let radius = widest_radius.min(row_height * 0.3).clamp(3.0, 11.0);
    let pointer = response.hover_pos();
    let mut under_pointer = None;
    let mut labels = Labels::new(rect);
    let dark_mode = ui.visuals().dark_mode;
    // Nodes first, then labels, which keep clear of the nodes and of each other.
    for node in (0..facts.node_count() as u32).filter(|&node| visible(node)) {
        let center = position(node);
        let base = depth_color(facts.depth[node as usize] as usize, dark_mode);
        let fill = emphasis[node as usize].unwrap_or(base);
        painter.circle_filled(center, radius, fill);
        labels.reserve(Rect::from_center_size(center, Vec2::splat(radius * 2.0)));
        let lit = *hovered == Some(node) || *selected == Some(node);
        if lit {
            let color = if *selected == Some(node) {
                palette::CURRENT
            } else {
                Color32::WHITE
            };
            painter.circle_stroke(center, radius + 3.0, Stroke::new(3.0, color));
        }
        if let Some(pointer) = pointer
            && Rect::from_center_size(center, Vec2::splat(radius * 2.0 + 6.0)).contains(pointer)
        {
            under_pointer = Some(node);
        }
    }
    // (A radius this large means the widest level left room: `labelled`.)
    if radius >= MIN_LABELLED_RADIUS {
        let plate = ui.visuals().panel_fill;
        let below = radius + 8.0;
        for node in (0..facts.node_count() as u32).filter(|&node| visible(node)) {
            labels.place(
                &painter,
                &label(node),
                crate::canvas::font(ui.ctx(), 11.0),
                ui.visuals().text_color(),
                position(node),
                &[
                    Vec2::new(0.0, below),
                    Vec2::new(-radius * 2.5, below * 0.6),
                    Vec2::new(radius * 2.5, below * 0.6),
                ],
                Some(plate),
            );
        }
    }
    if shown_depth < facts.max_depth() {
        painter.text(
            rect.right_bottom() - Vec2::new(4.0, 2.0),
            Align2::RIGHT_BOTTOM,
            format!(
                "depths {}..{} not drawn: too many nodes to tell apart",
                shown_depth + 1,
                facts.max_depth()
            ),
            crate::canvas::font(ui.ctx(), 11.0),
            ui.visuals().weak_text_color(),
        );
    }
    if response.clicked() {
        *selected = under_pointer.or(*selected);
    }
    if let Some(node) = under_pointer {
        *hovered = Some(node);
        response.on_hover_text(label(node));
    }
}

/// Two sliders for the depths whose boxes are drawn: a range, so one level can be shown at a
/// time. Dragging one past the other moves both; the deepest stays "all the way down"
/// (`usize::MAX`) when the tree grows.
pub fn depth_range_ui(ui: &mut egui::Ui, range: &mut (usize, usize), max_depth: usize) {
    let (mut low, mut high) = *range;
    high = high.min(max_depth);
    low = low.min(high);
    ui.add(egui::Slider::new(&mut low, 0..=max_depth).text("shallowest depth shown"));
    ui.add(egui::Slider::new(&mut high, 0..=max_depth).text("deepest depth shown"));
    if low > high {
        if low != range.0 {
            high = low;
        } else {
            low = high;
        }
    }
    *range = (low, if high >= max_depth { usize::MAX } else { high });
}

/// A tree node's colour after the steps shown: green if it was entered, red if its box was
/// missed, the ray does not reach its cell, or it was skipped; grey for a grid cell passed
/// empty.
pub fn traversal_emphasis(steps: &[Step<f64>], node_count: usize) -> Vec<Option<Color32>> {
    let missed = faded(palette::MISS, 200);
    let mut emphasis = vec![None; node_count];
    for step in steps {
        let (node, color) = match *step {
            Step::NodeEntered { node } | Step::CellEntered { node, .. } => (node, palette::HIT),
            // A grid's empty cell, passed without a test.
            Step::CellSkipped { node, .. } => (node, faded(Color32::GRAY, 220)),
            Step::BoxTested {
                node, hit: false, ..
            }
            | Step::NodeCulled { node, .. }
            | Step::CellMissed { node } => (node, missed),
            _ => continue,
        };
        if let Some(entry) = emphasis.get_mut(node as usize) {
            // A miss or a skip is final; an entry does not hide it.
            if *entry != Some(missed) {
                *entry = Some(color);
            }
        }
    }
    emphasis
}

#[cfg(test)]
mod tests {
    use super::*;
    use accelviz_core::params::BuildParams;
    use accelviz_core::{Built, NoBuildObserver, Shape, ShapeSet, Sphere, Structure, Width};

    /// Leaves take columns left to right; a parent sits between its children; a cut-off node
    /// takes one column for its whole subtree.
    #[test]
    fn parents_sit_between_their_children() {
        let shapes = ShapeSet {
            shapes: (0..4)
                .map(|index| {
                    Shape::Sphere(Sphere {
                        center: glam::DVec2::new(index as f64 * 4.0, 0.0),
                        radius: 1.0,
                    })
                })
                .collect(),
        };
        let params = BuildParams {
            max_leaf_size: 1,
            ..BuildParams::default()
        };
        let built = Built::new(
            Structure::BvhMedian {
                width: Width::Binary,
            },
            &shapes,
            &params,
            &mut NoBuildObserver,
        );
        let facts = &built.facts;
        let (column, leaves) = columns(facts, facts.max_depth());
        assert_eq!(leaves, 4);
        let [left, right] = facts.children[0]
            .and_then(|children| children.as_pair())
            .unwrap_or_else(|| unreachable!());
        assert_eq!(
            column[0],
            (column[left as usize] + column[right as usize]) * 0.5
        );
        let (column, leaves) = columns(facts, 1);
        assert_eq!(leaves, 2, "the second level stands for its subtrees");
        assert_eq!(column[0], 0.5);
    }
}
