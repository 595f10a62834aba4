//! Lesson 10, "Recap": "BVH is inefficient in empty space"; kD-trees are "very commonly used".
//! A SAH BVH and a SAH kD-tree over the same scene, measured on the same rays: when do the
//! kD-tree's empty cells beat the BVH, and when do its straddling primitives, tested in every
//! cell they reach, cost more than they save? Beside them the structures the lecture names
//! but does not choose (the uniform grid, the hashed grid, the quadtree), measured on the same
//! rays. Presets show each case; any scene can be measured, and the verdict is written from
//! the numbers.

use std::sync::Arc;

use accelviz_core::format::{count, number};
use accelviz_core::{Family, ShapeSet, SplitRule, Structure};
use accelviz_scene::document::SceneSettings;
use egui::{Color32, RichText};
use glam::DVec2;

use crate::background::Derived;
use crate::canvas::palette;
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::{Stage, request_over_shapes};
use crate::views::compare::{Comparison, Measured, interior_rays};

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

/// The recap's measurement: the five structures over the scene, counted on rays from around
/// it and on rays from points inside it in every direction (a camera in the scene, a bounce;
/// the comparison's `inside`): in a walled scene a ray from outside stops at the wall,
/// whatever the structure, and only rays from inside show how each finds its way through.
pub struct Recap {
    /// The structures and their counts on both sets of rays.
    pub comparison: Comparison,
}

impl Recap {
    /// Builds the five structures over `shapes` and counts both sets of rays through them.
    pub fn build(shapes: Arc<ShapeSet<DVec2>>, settings: SceneSettings) -> Self {
        let comparison = Comparison::build(&structures(&settings), shapes.clone(), settings)
            .with_inside(&interior_rays(&shapes));
        Self { comparison }
    }

    /// The five structures' figures on both sets of rays, in pane order.
    pub fn figures(&self) -> Figures {
        let comparison = &self.comparison;
        Figures {
            outside: [0, 1, 2, 3, 4].map(|pane| comparison.measured(pane)),
            inside: [0, 1, 2, 3, 4].map(|pane| match &comparison.inside {
                Some(inside) => {
                    comparison.measured_with(pane, &inside.counters[pane], inside.ray_count)
                }
                None => comparison.measured(pane),
            }),
        }
    }
}

/// The five structures' figures, in pane order, on rays from outside the scene and from
/// inside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Figures {
    /// On rays from around the scene to points in it.
    pub outside: [Measured; 5],
    /// On rays from points inside it, in every direction.
    pub inside: [Measured; 5],
}

/// The structures cheapest first by `figures`' cost per ray, each with its cost.
fn ranked(figures: &[Measured; 5]) -> String {
    let mut ranked: Vec<(usize, f64)> = figures
        .iter()
        .enumerate()
        .map(|(pane, figure)| (pane, figure.cost_per_ray))
        .collect();
    ranked.sort_by(|a, b| a.1.total_cmp(&b.1));
    let order: Vec<String> = ranked
        .iter()
        .map(|&(pane, cost)| format!("{} {}", family_name(FAMILIES[pane]), number(cost)))
        .collect();
    order.join(", ")
}

/// The verdict, a sentence at a time, each from the numbers: the lecture's question first
/// (BVH or kD-tree: who wins, by how much, and where the difference comes from) on rays from
/// outside, then on rays from inside, the five ranked on each, and where the grids and the
/// quadtree stand and why, said only where the figures show it.
pub fn verdict(figures: &Figures) -> Vec<String> {
    let [bvh, kd, grid, hashed, quadtree] = figures.outside;
    let [bvh_in, kd_in, grid_in, _, quadtree_in] = figures.inside;
    let mut said = vec![
        format!("From outside the scene, {}", lecture_verdict(bvh, kd)),
        format!(
            "From inside it (a camera in the scene, a bounce): {}",
            lecture_outcome(bvh_in, kd_in)
        ),
        format!(
            "Of all five, cheapest first, from outside: {}; from inside: {}.",
            ranked(&figures.outside),
            ranked(&figures.inside)
        ),
    ];
    // The grid, from outside: a ray that stops in the first cell it meets stopped at the
    // scene's edge, the same for every structure.
    if grid.nodes_per_ray <= 1.5 && grid_in.nodes_per_ray >= 2.0 * grid.nodes_per_ray.max(1.0) {
        said.push(format!(
            "From outside, the uniform grid's rays stop in about the first cell they reach ({:.1} cells a ray): the scene's outer shapes line its edge, and the first cell holds the hit; from inside, the same grid walks {:.1} cells a ray.",
            grid.nodes_per_ray, grid_in.nodes_per_ray
        ));
    }
    // The grid, from inside: where it steps and what it tests, against the trees.
    let trees_nodes = kd_in.nodes_per_ray.max(bvh_in.nodes_per_ray);
    let trees_tests = kd_in.tests_per_ray.min(bvh_in.tests_per_ray);
    let empty = grid_in.empty_share * 100.0;
    said.push(if grid_in.nodes_per_ray > 2.0 * trees_nodes {
        format!(
            "From inside, the uniform grid steps through {:.1} cells a ray against the trees' {:.1} nodes at most: its cells are one size everywhere, and {empty:.0} % of the scene lies in cells that hold nothing, which a ray crosses one by one.",
            grid_in.nodes_per_ray, trees_nodes
        )
    } else if grid_in.tests_per_ray > 1.5 * trees_tests {
        format!(
            "From inside, the uniform grid tests {:.1} primitives a ray against the trees' {:.1}: cells sized for the average hold many where the scene is dense.",
            grid_in.tests_per_ray, trees_tests
        )
    } else if empty < 30.0 {
        format!(
            "From inside, the uniform grid keeps up ({:.1} cells and {:.1} tests a ray): the scene fills its cells evenly ({empty:.0} % of the area in empty cells), the case its density rule assumes.",
            grid_in.nodes_per_ray, grid_in.tests_per_ray
        )
    } else {
        format!(
            "From inside, the uniform grid keeps up ({:.1} cells and {:.1} tests a ray), though {empty:.0} % of the area lies in empty cells.",
            grid_in.nodes_per_ray, grid_in.tests_per_ray
        )
    });
    said.push(format!(
        "The hashed grid walks the dense grid's cells and tests the same primitives ({} a ray from outside, as the grid's {}), and adds a table lookup for each cell.",
        number(hashed.cost_per_ray),
        number(grid.cost_per_ray)
    ));
    said.push(if quadtree_in.cost_per_ray > kd_in.cost_per_ray * 1.05 {
        format!(
            "The quadtree trails the SAH kD-tree from inside ({} against {} a ray): it cuts at the middle of both axes whatever the cell holds.",
            number(quadtree_in.cost_per_ray),
            number(kd_in.cost_per_ray)
        )
    } else {
        format!(
            "The quadtree keeps up with the SAH kD-tree from inside ({} against {} a ray).",
            number(quadtree_in.cost_per_ray),
            number(kd_in.cost_per_ray)
        )
    });
    let _ = quadtree;
    said
}

/// Who wins between the BVH and the kD-tree, by how much.
fn lecture_outcome(bvh: Measured, kd: Measured) -> String {
    let ratio = bvh.cost_per_ray / kd.cost_per_ray.max(1e-12);
    if ratio > 1.05 {
        format!(
            "the kD-tree wins, {} against the BVH's {} per ray ({ratio:.2}×).",
            number(kd.cost_per_ray),
            number(bvh.cost_per_ray)
        )
    } else if ratio < 1.0 / 1.05 {
        format!(
            "the BVH wins, {} against the kD-tree's {} per ray ({:.2}×).",
            number(bvh.cost_per_ray),
            number(kd.cost_per_ray),
            1.0 / ratio
        )
    } else {
        format!(
            "they are even, {} (BVH) and {} (kD-tree) per ray.",
            number(bvh.cost_per_ray),
            number(kd.cost_per_ray)
        )
    }
}

/// The lecture's question, from the numbers: BVH or kD-tree, who wins, by how much, and where
/// the difference comes from (the node visits and the primitive tests, each with what causes
/// it).
pub fn lecture_verdict(bvh: Measured, kd: Measured) -> String {
    let outcome = lecture_outcome(bvh, kd);
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
    recap: Derived<(u64, ()), Recap>,
}

impl RecapLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::ALL),
            recap: Derived::default(),
        }
    }

    /// The figures of the five structures on the current scene, once measured.
    pub fn measured(&self) -> Option<Figures> {
        Some(self.recap.get()?.figures())
    }

    /// Each pane's caption under its structure's name, as drawn (once measured).
    pub fn pane_captions(&self) -> Option<Vec<Vec<String>>> {
        let comparison = &self.recap.get()?.comparison;
        Some(
            (0..comparison.trees.len())
                .map(|pane| comparison.summary(pane))
                .collect(),
        )
    }

    /// Opens preset `index` of the lesson file's presets (its scene and name).
    pub fn show_preset(&mut self, index: usize) {
        self.stage.show_preset(index);
    }
}

impl Lesson for RecapLesson {
    crate::staged!(recap);

    fn show_named(&mut self, name: &str) -> bool {
        self.stage.show_named_preset(name)
    }

    fn named(&self) -> Vec<String> {
        self.stage.preset_names()
    }

    fn update(&mut self) {
        let scene = &self.stage.scene;
        request_over_shapes(&mut self.recap, scene, (), Recap::build);
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        ui.label(RichText::new("Scenes that make the point").strong());
        self.stage.presets_ui(ui, "");
        let Some(recap) = self.recap.get().cloned() else {
            ui.label("Building…");
            return;
        };
        let figures = recap.figures();
        let comparison = &recap.comparison;
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
                    let per_ray: [(&str, FigureOf); 3] = [
                        ("nodes a ray", |m| format!("{:.1}", m.nodes_per_ray)),
                        ("tests a ray", |m| format!("{:.1}", m.tests_per_ray)),
                        ("cost a ray", |m| number(m.cost_per_ray)),
                    ];
                    for (set, about, measured) in [
                        (
                            "rays from outside",
                            "From around the scene to points in it: a camera outside",
                            &figures.outside,
                        ),
                        (
                            "rays from inside",
                            "From points inside the scene, every direction: a camera in it, a bounce",
                            &figures.inside,
                        ),
                    ] {
                        ui.strong(set).on_hover_text(about);
                        ui.end_row();
                        for (name, value) in per_ray {
                            ui.label(name)
                                .on_hover_text("nodes: or cells, for the grids and the quadtree");
                            for figure in measured {
                                ui.label(value(figure));
                            }
                            ui.end_row();
                        }
                    }
                    let held: [(&str, FigureOf); 2] = [
                        ("references", |m| {
                            format!("{:.2}", m.references_per_primitive)
                        }),
                        ("area empty", |m| {
                            format!("{:.0} %", m.empty_share * 100.0)
                        }),
                    ];
                    for (name, value) in held {
                        ui.label(name);
                        for figure in &figures.outside {
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
                "Measured on {} seeded rays from around the scene to points in it (a camera outside), and {} from points inside it in every direction (a camera in the scene, a bounce). Cost per ray = C_trav · nodes (or cells) + C_isect · tests, with C_trav = {} and C_isect = {}.",
                comparison.ray_count,
                comparison.inside.as_ref().map_or(0, |inside| inside.ray_count),
                number(settings.traversal_cost),
                number(settings.intersection_cost)
            ))
            .small()
            .weak(),
        );
        ui.separator();
        let color = crate::canvas::readable(ui, palette::CURRENT);
        for sentence in verdict(&figures) {
            ui.label(RichText::new(sentence).color(color));
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.stage.scene.toolbar_ui(ui);
        let height = ui.available_height();
        match self.recap.get() {
            Some(recap) => recap.comparison.panes_ui(
                ui,
                &mut self.stage.scene,
                self.recap.working_for(),
                height,
                3,
                |_| Color32::WHITE,
                |_, _, _| {},
            ),
            None => {
                ui.label("Building…");
            }
        }
    }
}
