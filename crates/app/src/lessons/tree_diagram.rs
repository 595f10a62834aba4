//! A tree drawn as a diagram: leaves side by side in tree order, each parent above the middle
//! of its children. Hovering a node reports it (the canvas lights its box up), clicking selects
//! it; the canvas reports its own hovering back, so the link works both ways.

use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, Vec2};

use crate::canvas::{depth_color, palette};

/// A tree's shape: each node's children (none for a leaf) and depth, from a flat node array
/// whose root is node 0.
#[derive(Clone, Debug, Default)]
pub struct TreeShape {
    /// Children per node.
    pub children: Vec<Option<[u32; 2]>>,
    /// Depth per node (root 0).
    pub depth: Vec<usize>,
    /// Parent per node (the root has none).
    pub parent: Vec<Option<u32>>,
    /// Horizontal place per node, in leaf widths.
    column: Vec<f32>,
    /// Leaves in the tree.
    leaf_count: usize,
}

impl TreeShape {
    /// The shape of a tree given each node's children.
    pub fn new(children: Vec<Option<[u32; 2]>>) -> Self {
        let count = children.len();
        let mut shape = Self {
            depth: vec![0; count],
            parent: vec![None; count],
            column: vec![0.0; count],
            children,
            leaf_count: 0,
        };
        if count > 0 {
            shape.place(0, 0);
        }
        shape
    }

    /// Depth-first, left to right: leaves take the next column, parents sit between.
    fn place(&mut self, node: u32, depth: usize) -> f32 {
        self.depth[node as usize] = depth;
        let column = match self.children[node as usize] {
            None => {
                self.leaf_count += 1;
                (self.leaf_count - 1) as f32
            }
            Some([left, right]) => {
                self.parent[left as usize] = Some(node);
                self.parent[right as usize] = Some(node);
                (self.place(left, depth + 1) + self.place(right, depth + 1)) * 0.5
            }
        };
        self.column[node as usize] = column;
        column
    }

    /// The path from the root to `node`: `L` or `R` per step (the core's node paths).
    pub fn path_to(&self, node: u32) -> String {
        let mut steps = Vec::new();
        let mut current = node;
        while let Some(parent) = self.parent[current as usize] {
            let right = self.children[parent as usize].is_some_and(|[_, right]| right == current);
            steps.push(if right { 'R' } else { 'L' });
            current = parent;
        }
        steps.iter().rev().collect()
    }

    /// The deepest level.
    pub fn max_depth(&self) -> usize {
        self.depth.iter().copied().max().unwrap_or(0)
    }

    /// Draws the diagram at the available width. `label` names a node, `emphasis` gives a
    /// node a highlight colour (visited, culled, current). Returns the node under the
    /// pointer; a click on a node selects it.
    pub fn ui(
        &self,
        ui: &mut egui::Ui,
        label: impl Fn(u32) -> String,
        emphasis: impl Fn(u32) -> Option<Color32>,
        hovered: Option<u32>,
        selected: &mut Option<u32>,
    ) -> Option<u32> {
        if self.children.is_empty() {
            return None;
        }
        let row_height = 34.0;
        let width = ui.available_width().max(120.0);
        // Levels too crowded to tell nodes apart (a few points each) are left out.
        let mut per_depth = vec![0usize; self.max_depth() + 1];
        for &depth in &self.depth {
            per_depth[depth] += 1;
        }
        let shown_depth = per_depth
            .iter()
            .position(|&count| count as f32 * 4.0 > width)
            .map_or(self.max_depth(), |crowded| crowded.saturating_sub(1));
        let height = (shown_depth + 1) as f32 * row_height + 10.0;
        let (rect, response) = ui.allocate_exact_size(Vec2::new(width, height), Sense::click());
        let painter = ui.painter_at(rect);
        let column_width = (width - 20.0) / self.leaf_count.max(1) as f32;
        let position = |node: u32| -> Pos2 {
            Pos2::new(
                rect.left() + 10.0 + (self.column[node as usize] + 0.5) * column_width,
                rect.top() + 14.0 + self.depth[node as usize] as f32 * row_height,
            )
        };
        let line_color = ui.visuals().weak_text_color();
        for (node, children) in self.children.iter().enumerate() {
            if self.depth[node] >= shown_depth {
                continue;
            }
            if let Some(children) = children {
                for child in children {
                    painter.line_segment(
                        [position(node as u32), position(*child)],
                        Stroke::new(1.0, line_color),
                    );
                }
            }
        }
        let widest = per_depth[..=shown_depth]
            .iter()
            .copied()
            .max()
            .unwrap_or(1)
            .max(1);
        let radius = ((width - 20.0) / widest as f32 * 0.42)
            .min(column_width * 0.42)
            .clamp(3.0, 11.0);
        let pointer = response.hover_pos();
        let mut under_pointer = None;
        for node in 0..self.children.len() as u32 {
            if self.depth[node as usize] > shown_depth {
                continue;
            }
            let center = position(node);
            let base = depth_color(self.depth[node as usize]);
            let fill = emphasis(node).unwrap_or(base);
            painter.circle_filled(center, radius, fill);
            if hovered == Some(node) || *selected == Some(node) {
                let color = if *selected == Some(node) {
                    palette::CURRENT
                } else {
                    Color32::WHITE
                };
                painter.circle_stroke(center, radius + 3.0, Stroke::new(2.5, color));
            }
            // A label only where its level leaves room for one under each node.
            if radius >= 8.0 && per_depth[self.depth[node as usize]] as f32 * 64.0 <= width {
                painter.text(
                    center + Vec2::new(0.0, radius + 6.0),
                    Align2::CENTER_CENTER,
                    label(node),
                    FontId::proportional(11.0),
                    ui.visuals().text_color(),
                );
            }
            if let Some(pointer) = pointer
                && Rect::from_center_size(center, Vec2::splat(radius * 2.0 + 6.0)).contains(pointer)
            {
                under_pointer = Some(node);
            }
        }
        if shown_depth < self.max_depth() {
            painter.text(
                rect.right_bottom() - Vec2::new(4.0, 2.0),
                Align2::RIGHT_BOTTOM,
                format!(
                    "depths {}..{} not drawn: too many nodes",
                    shown_depth + 1,
                    self.max_depth()
                ),
                FontId::proportional(10.0),
                ui.visuals().weak_text_color(),
            );
        }
        if response.clicked() {
            *selected = under_pointer.or(*selected);
        }
        if let Some(node) = under_pointer {
            response.on_hover_text(label(node));
        }
        under_pointer
    }
}
