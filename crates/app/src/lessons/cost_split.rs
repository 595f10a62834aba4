//! Lesson 8, "Cost-Optimized Split": the teapot in a stadium. A dense cluster in a large, nearly
//! empty scene: middle splits spend levels cutting empty space in halves, median splits cut
//! through the cluster, the SAH isolates the cluster and cuts the empty space off in big chunks.
//! The empty leaves and their share of the scene are the core's `TreeStats`.

use accelviz_core::format::number;
use accelviz_core::{Family, Structure};
use egui::{Color32, RichText};

use crate::background::Derived;
use crate::canvas::faded;
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::Stage;
use crate::views::compare::{
    Comparison, LECTURE_RULES as RULES, comparison_ui, request_comparison, rule_color,
};

/// The colour of empty leaves: space cut off, where rays pass without a test.
const EMPTY_COLOR: Color32 = Color32::from_rgb(90, 200, 140);

/// The lesson.
pub struct CostSplitLesson {
    stage: Stage,
    family: Family,
    comparison: Derived<(u64, Family), Comparison>,
}

impl CostSplitLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::SHAPES),
            family: Family::Kd,
            comparison: Derived::default(),
        }
    }
}

impl Lesson for CostSplitLesson {
    crate::staged!(comparison);

    fn update(&mut self) {
        let scene = &self.stage.scene;
        let family = self.family;
        let structures = RULES.map(|rule| Structure::lecture(family, rule));
        request_comparison(&mut self.comparison, scene, family, structures);
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        ui.horizontal(|ui| {
            ui.label("Compare");
            for family in [Family::Kd, Family::Bvh] {
                ui.selectable_value(&mut self.family, family, format!("{}s", family.label()));
            }
        });
        let Some(comparison) = self.comparison.get().cloned() else {
            ui.label("Building…");
            return;
        };
        let kd = self.family == Family::Kd;
        ui.separator();
        // A table keeps its columns: in a narrow panel (the app scaled up) it scrolls
        // sideways rather than widen the panel.
        egui::ScrollArea::horizontal()
            .id_salt("cost split table columns")
            .show(ui, |ui| {
                egui::Grid::new("cost split table")
                    .striped(true)
                    .show(ui, |ui| {
                        ui.strong("rule");
                        ui.strong("SAH cost");
                        ui.strong("depth");
                        ui.strong("nodes/ray");
                        ui.strong("tests/ray");
                        if kd {
                            ui.strong("empty area");
                        }
                        ui.end_row();
                        for (pane, rule) in RULES.iter().enumerate() {
                            let stats = &comparison.trees[pane].stats;
                            ui.colored_label(
                                crate::canvas::readable(ui, rule_color(*rule)),
                                rule.label(),
                            );
                            ui.label(number(stats.sah_cost));
                            ui.label(stats.max_depth.to_string());
                            ui.label(format!(
                                "{:.1}",
                                comparison.per_ray(pane, |c| c.nodes_visited)
                            ));
                            ui.label(format!(
                                "{:.1}",
                                comparison.per_ray(pane, |c| c.primitive_tests)
                            ));
                            if kd {
                                ui.label(format!("{:.0} %", stats.empty_leaf_share * 100.0));
                            }
                            ui.end_row();
                        }
                    });
            });
        ui.label(format!(
            "Measured on {} seeded rays through the scene.",
            comparison.ray_count
        ));
        if kd {
            ui.label(
                RichText::new("Green: empty leaves, space a ray crosses without a single test. The SAH makes them large.")
                    .small()
                    .weak(),
            );
        } else {
            ui.label(
                RichText::new("A BVH has no empty leaves: its boxes shrink around what they hold, and the space between them is what a ray skips.")
                    .small()
                    .weak(),
            );
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.stage.scene.toolbar_ui(ui);
        let height = ui.available_height();
        comparison_ui(
            ui,
            &self.comparison,
            &mut self.stage.scene,
            height,
            3,
            |pane| rule_color(RULES[pane]),
            |_, tree, canvas| {
                let facts = &tree.built.facts;
                if tree.built.tree.family() != Family::Kd {
                    return;
                }
                let empty = (0..facts.node_count())
                    .filter(|&node| facts.is_leaf(node as u32) && facts.leaf_sizes[node] == 0);
                let mut batch = canvas.batch();
                for node in empty {
                    let screen = canvas.screen_rect(&facts.bounds[node]);
                    if canvas.rect.intersects(screen) {
                        batch.rect(screen, faded(EMPTY_COLOR, 40));
                    }
                }
                canvas.draw_batch(batch);
            },
        );
    }
}
