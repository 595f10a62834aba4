//! Lesson 10, "Recap": "BVH is inefficient in empty space"; kD-trees are "very commonly used".
//! A SAH BVH and a SAH kD-tree over the same scene, measured on the same rays: when do the
//! kD-tree's empty cells beat the BVH, and when do its straddling primitives, tested in every
//! cell they reach, cost more than they save? Beside them the structures the lecture names
//! but does not choose (the uniform grid, the hashed grid, the quadtree), measured on the same
//! rays. Presets show each case; any scene can be measured, and the verdict is written from
//! the numbers.

use accelviz_core::format::{count, number};
use accelviz_core::{Family, SplitRule, Structure};
use accelviz_scene::document::SceneSettings;
use egui::{Color32, RichText};

use crate::background::Derived;
use crate::canvas::palette;
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::{Stage, request_over_shapes};
use crate::views::compare::{Comparison, Measured, comparison_ui};

/// The five families, in pane order: the lecture's two first.
pub const FAMILIES: [Family; 5] = [
    Family::Bvh,
    Family::Kd,
    Family::Grid,
    Family::HashedGrid,
    Family::Octree,
];

/// A family's name in this 2D lesson (an octree in 2D is a quadtree).
pub fn family_name(family: Family) -> &'static str {
    match family {
        Family::Octree => "quadtree",
        family => family.label(),
    }
}

/// Short column headings for the table, in pane order.
const HEADINGS: [&str; 5] = ["SAH BVH", "SAH kD", "grid", "hashed", "quadtree"];

/// The structure of each family the recap measures: the SAH BVH and kD-tree, the grids at
/// their default density, the quadtree with the scene's leaf size (the trees' own).
pub fn structures(settings: &SceneSettings) -> [Structure; 5] {
    FAMILIES.map(|family| match family {
        Family::Octree => Structure::Octree {
            leaf: settings.max_leaf_size.clamp(1, usize::from(u16::MAX)) as u16,
        },
        family => Structure::lecture(family, SplitRule::Sah),
    })
}

/// The five structures' figures, in pane order.
pub fn measure(comparison: &Comparison) -> [Measured; 5] {
    [0, 1, 2, 3, 4].map(|pane| comparison.measured(pane))
}

/// The verdict, from the numbers: the lecture's question first (BVH or kD-tree: who wins, by
/// how much, and where the difference comes from), then where the other three stand.
pub fn verdict(figures: [Measured; 5]) -> String {
    let [bvh, kd, grid, hashed, quadtree] = figures;
    let mut ranked: Vec<(usize, f64)> = figures
        .iter()
        .enumerate()
        .map(|(pane, figure)| (pane, figure.cost_per_ray))
        .collect();
    ranked.sort_by(|a, b| a.1.total_cmp(&b.1));
    let name = |pane: usize| family_name(FAMILIES[pane]);
    let order: Vec<String> = ranked
        .iter()
        .map(|&(pane, cost)| format!("{} {}", name(pane), number(cost)))
        .collect();
    let grid_why = if grid.nodes_per_ray > 2.0 * kd.nodes_per_ray.max(bvh.nodes_per_ray) {
        format!(
            "The uniform grid steps through {:.1} cells per ray: its cells are one size everywhere, so a ray crosses many empty ones where the scene is sparse",
            grid.nodes_per_ray
        )
    } else if grid.tests_per_ray > 1.5 * kd.tests_per_ray.min(bvh.tests_per_ray) {
        format!(
            "The uniform grid tests {:.1} primitives per ray: cells sized for the average hold many where the scene is dense",
            grid.tests_per_ray
        )
    } else {
        format!(
            "The uniform grid keeps up here ({:.1} cells and {:.1} tests per ray): the scene fills its cells evenly, the case its density rule assumes",
            grid.nodes_per_ray, grid.tests_per_ray
        )
    };
    let quadtree_why = if quadtree.cost_per_ray > kd.cost_per_ray * 1.05 {
        "the quadtree trails the SAH kD-tree: it cuts at the middle of both axes whatever the cell holds"
    } else {
        "the quadtree keeps up with the SAH kD-tree: the middle of each cell happens to be a good place to cut"
    };
    format!(
        "{} Of all five, cheapest first: {}. {grid_why}; the hashed grid walks the same cells and tests the same primitives ({} per ray), and adds a lookup for each cell; {quadtree_why}.",
        lecture_verdict(bvh, kd),
        order.join(", "),
        number(hashed.cost_per_ray)
    )
}

/// The lecture's question, from the numbers: BVH or kD-tree, who wins, by how much, and where
/// the difference comes from (the node visits and the primitive tests, each with what causes
/// it).
pub fn lecture_verdict(bvh: Measured, kd: Measured) -> String {
    let ratio = bvh.cost_per_ray / kd.cost_per_ray.max(1e-12);
    let outcome = if ratio > 1.05 {
        format!(
            "Here the kD-tree wins: {} against the BVH's {} per ray ({ratio:.2}×).",
            number(kd.cost_per_ray),
            number(bvh.cost_per_ray)
        )
    } else if ratio < 1.0 / 1.05 {
        format!(
            "Here the BVH wins: {} against the kD-tree's {} per ray ({:.2}×).",
            number(bvh.cost_per_ray),
            number(kd.cost_per_ray),
            1.0 / ratio
        )
    } else {
        format!(
            "Here they are even: {} (BVH) and {} (kD-tree) per ray.",
            number(bvh.cost_per_ray),
            number(kd.cost_per_ray)
        )
    };
    let empty = if kd.empty_share >= 0.05 {
        format!(
            "; the kD-tree's empty cells, {:.0} % of the scene, are crossed without a test",
            kd.empty_share * 100.0
        )
    } else {
        String::new()
    };
    let nodes = if kd.nodes_per_ray < bvh.nodes_per_ray {
        format!(
            "The kD-tree visits {:.1} cells per ray against the BVH's {:.1} nodes: its cells do not overlap, so a ray is in one at a time and the first hit ends the search{empty}, while a BVH box big enough to hold something long also holds the empty space around it.",
            kd.nodes_per_ray, bvh.nodes_per_ray
        )
    } else {
        format!(
            "The BVH visits {:.1} nodes per ray against the kD-tree's {:.1} cells: a ray that misses a box skips everything inside it, while a ray goes down through the kD-tree's cells level by level{empty}.",
            bvh.nodes_per_ray, kd.nodes_per_ray
        )
    };
    let straddlers = if kd.references_per_primitive >= 1.1 {
        format!(
            ", and a primitive is listed in {:.1} cells on average and tested again in each",
            kd.references_per_primitive
        )
    } else {
        String::new()
    };
    if kd.node_count == 1 {
        return format!(
            "{outcome} The kD-tree is a single leaf: no cut is cheaper than the leaf, since each would leave most primitives on both sides, so a ray tests all {:.0} against the BVH's {:.1}.",
            kd.tests_per_ray, bvh.tests_per_ray
        );
    }
    let tests = if kd.tests_per_ray > bvh.tests_per_ray {
        format!(
            " It tests {:.1} primitives per ray against the BVH's {:.1}: a kD cell cannot shrink around what it holds, so a ray through it tests primitives it passes far from{straddlers}.",
            kd.tests_per_ray, bvh.tests_per_ray
        )
    } else {
        format!(
            " It tests {:.1} primitives per ray against the BVH's {:.1}.",
            kd.tests_per_ray, bvh.tests_per_ray
        )
    };
    format!("{outcome} {nodes}{tests}")
}

/// Writes one figure of a structure.
type FigureOf = fn(&Measured) -> String;

/// The lesson.
pub struct RecapLesson {
    stage: Stage,
    comparison: Derived<(u64, ()), Comparison>,
}

impl RecapLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::ALL),
            comparison: Derived::default(),
        }
    }

    /// The figures of the five structures on the current scene, once measured.
    pub fn measured(&self) -> Option<[Measured; 5]> {
        Some(measure(self.comparison.get()?))
    }

    /// Opens preset `index` of the lesson file's presets (its scene and name).
    pub fn show_preset(&mut self, index: usize) {
        self.stage.show_preset(index);
    }
}

impl Lesson for RecapLesson {
    crate::staged!(comparison);

    fn show_named(&mut self, name: &str) -> bool {
        self.stage.show_named_preset(name)
    }

    fn named(&self) -> Vec<String> {
        self.stage.preset_names()
    }

    fn update(&mut self) {
        let scene = &self.stage.scene;
        request_over_shapes(&mut self.comparison, scene, (), |shapes, settings| {
            Comparison::build(&structures(&settings), shapes, settings)
        });
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        ui.label(RichText::new("Scenes that make the point").strong());
        self.stage.presets_ui(ui, "");
        let Some(comparison) = self.comparison.get().cloned() else {
            ui.label("Building…");
            return;
        };
        let figures = measure(&comparison);
        ui.separator();
        // A table keeps its columns: in a narrow panel (the app scaled up) it scrolls
        // sideways rather than widen the panel.
        egui::ScrollArea::horizontal()
            .id_salt("recap table columns")
            .show(ui, |ui| {
                egui::Grid::new("recap table").striped(true).show(ui, |ui| {
                    ui.label("");
                    for (heading, tree) in HEADINGS.iter().zip(&comparison.trees) {
                        ui.strong(*heading)
                            .on_hover_text(tree.built.structure.name());
                    }
                    ui.end_row();
                    let rows: [(&str, FigureOf); 5] = [
                        ("nodes or cells a ray", |m| {
                            format!("{:.1}", m.nodes_per_ray)
                        }),
                        ("tests a ray", |m| format!("{:.1}", m.tests_per_ray)),
                        ("cost a ray", |m| number(m.cost_per_ray)),
                        ("references a primitive", |m| {
                            format!("{:.2}", m.references_per_primitive)
                        }),
                        ("area left empty", |m| {
                            format!("{:.0} %", m.empty_share * 100.0)
                        }),
                    ];
                    for (name, value) in rows {
                        ui.label(name);
                        for figure in &figures {
                            ui.label(value(figure));
                        }
                        ui.end_row();
                    }
                    ui.label("nodes");
                    for tree in &comparison.trees {
                        ui.label(count(tree.stats.node_count));
                    }
                    ui.end_row();
                });
            });
        let settings = self.stage.scene.scene.settings;
        ui.label(
            RichText::new(format!(
                "Measured on {} seeded rays from around the scene to points in it. Cost per ray = C_trav · nodes (or cells) + C_isect · tests, with C_trav = {} and C_isect = {}. A ray from outside a walled scene meets the wall in the first cell a grid looks at.",
                comparison.ray_count,
                number(settings.traversal_cost),
                number(settings.intersection_cost)
            ))
            .small()
            .weak(),
        );
        ui.separator();
        ui.label(
            RichText::new(verdict(figures)).color(crate::canvas::readable(ui, palette::CURRENT)),
        );
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
            |_| Color32::WHITE,
            |_, _, _| {},
        );
    }
}
