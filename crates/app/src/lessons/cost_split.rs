//! Lesson 8, "Cost-Optimized Split": the teapot in a stadium. A dense cluster in a large, nearly
//! empty scene: middle splits spend levels cutting empty space in halves, median splits cut
//! through the cluster, the SAH isolates the cluster and cuts the empty space off in big chunks.

use accelviz_core::Aabb;
use egui::{RichText, Stroke};
use glam::DVec2;

use super::compare::{BuiltTree, Comparison, RULE_NAMES, Structure};
use super::{Lesson, LessonText};
use crate::canvas::faded;
use crate::editor::{EditableScene, Editing};

/// The colour of empty leaves: space cut off, where rays pass without a test.
const EMPTY_COLOR: egui::Color32 = egui::Color32::from_rgb(90, 200, 140);

/// The lesson.
pub struct CostSplitLesson {
    text: LessonText,
    scene: EditableScene,
    structure: Structure,
    comparison: Option<Comparison>,
    comparison_key: (u64, Structure),
}

impl CostSplitLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        let scene = EditableScene::new(text.scene.clone(), Editing::SHAPES);
        Self {
            text,
            scene,
            structure: Structure::Kd,
            comparison: None,
            comparison_key: (0, Structure::Kd),
        }
    }

    fn refresh(&mut self) {
        let key = (self.scene.revision, self.structure);
        if self.comparison.is_none() || self.comparison_key != key {
            self.comparison = Some(Comparison::new(&self.scene, self.structure));
            self.comparison_key = key;
        }
    }
}

/// The empty leaves' cells of a kD-tree, and the share of the root cell's area they cover.
fn empty_cells(tree: &BuiltTree) -> (Vec<Aabb<DVec2>>, f64) {
    let BuiltTree::Kd(built) = tree else {
        return (Vec::new(), 0.0);
    };
    let cells: Vec<Aabb<DVec2>> = built
        .tree
        .nodes
        .iter()
        .enumerate()
        .filter(|(_, node)| node.is_leaf() && node.count == 0)
        .map(|(index, _)| built.cells[index])
        .collect();
    let total = built.tree.bounds.measure();
    let empty: f64 = cells.iter().map(Aabb::measure).sum();
    (cells, if total > 0.0 { empty / total } else { 0.0 })
}

impl Lesson for CostSplitLesson {
    fn text(&self) -> &LessonText {
        &self.text
    }

    fn scene_mut(&mut self) -> Option<&mut EditableScene> {
        Some(&mut self.scene)
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.label("Compare");
            ui.selectable_value(&mut self.structure, Structure::Kd, "kD-trees");
            ui.selectable_value(&mut self.structure, Structure::Bvh, "BVHs");
        });
        self.refresh();
        let Some(comparison) = &self.comparison else {
            return;
        };
        ui.separator();
        egui::Grid::new("cost split table")
            .striped(true)
            .show(ui, |ui| {
                ui.strong("rule");
                ui.strong("SAH cost");
                ui.strong("depth");
                ui.strong("nodes/ray");
                ui.strong("tests/ray");
                if self.structure == Structure::Kd {
                    ui.strong("empty area");
                }
                ui.end_row();
                for (pane, rule) in RULE_NAMES.iter().enumerate() {
                    let stats = &comparison.stats[pane];
                    let counters = &comparison.counters[pane];
                    let rays = comparison.ray_count.max(1) as f64;
                    ui.label(*rule);
                    ui.label(format!("{:.2}", stats.sah_cost));
                    ui.label(stats.max_depth.to_string());
                    ui.label(format!("{:.1}", counters.nodes_visited as f64 / rays));
                    ui.label(format!("{:.1}", counters.primitive_tests as f64 / rays));
                    if self.structure == Structure::Kd {
                        ui.label(format!(
                            "{:.0} %",
                            empty_cells(&comparison.trees[pane]).1 * 100.0
                        ));
                    }
                    ui.end_row();
                }
            });
        ui.label(format!(
            "Measured on {} seeded rays through the scene.",
            comparison.ray_count
        ));
        ui.label(
            RichText::new("Green: empty leaves, space a ray crosses without a single test. The SAH makes them large.")
                .small()
                .weak(),
        );
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.scene.toolbar_ui(ui);
        self.refresh();
        let height = ui.available_height();
        let Some(comparison) = self.comparison.take() else {
            return;
        };
        let canvases = comparison.panes_ui(ui, &mut self.scene, height);
        for (pane, canvas) in canvases.iter().enumerate() {
            for cell in empty_cells(&comparison.trees[pane]).0 {
                canvas.box_outline(&cell, Stroke::NONE, Some(faded(EMPTY_COLOR, 40)));
            }
        }
        self.comparison = Some(comparison);
        let mut changed = false;
        for canvas in &canvases {
            changed |= self.scene.interact(ui, canvas);
        }
        if changed {
            self.refresh();
        }
    }
}
