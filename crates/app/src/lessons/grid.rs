//! Lesson 18, "The uniform grid": the core's grid walk (Amanatides & Woo 1987) stepped cell by
//! cell, with the table it keeps, the `t` at which the ray reaches the next vertical and the
//! next horizontal line, filled as it goes (as lesson 3 fills its Near/Far table); the cell
//! size chosen by a slider or by the density rule, and the cost per ray measured at every
//! cell size, so the rule's choice can be seen against the curve. Lesson 19 stores the same
//! grid in a hash table; both draw the walk with [`crate::views::grid_walk`].

use std::sync::Arc;

use accelviz_core::format::{count, number};
use accelviz_core::grid::GridCells;
use accelviz_core::{NoBuildObserver, ShapeSet, TraceOptions};
use accelviz_scene::document::SceneSettings;
use egui::RichText;
use egui_plot::{Line, LineStyle, PlotPoints, VLine};
use glam::DVec2;

use crate::background::Derived;
use crate::canvas::palette;
use crate::editor::Editing;
use crate::lesson::{self, Lesson, Parts};
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage};
use crate::trace::Trace;
use crate::views::compare::{count_rays, interior_rays};
use crate::views::grid_walk::{
    CellChoice, GridWalk, MOST_ALONG, WalkRow, cell_size_plot, cells_slider_ui, grid_structure,
    measured_sizes, rule_along, shown_size_color, shown_size_line,
};
use crate::views::scene_view::t_hint_ui;

/// The inspector's parts a lecture slide can name.
const CELLS_PART: lesson::Part =
    lesson::Part::new("cells", "the cell size, the density rule and mailboxing");
const WALK_PART: lesson::Part =
    lesson::Part::new("walk", "the table of t to the next line, cell by cell");
const COST_PART: lesson::Part = lesson::Part::new("cost", "the cost per ray against the cell size");
const PARTS: [lesson::Part; 3] = [CELLS_PART, WALK_PART, COST_PART];

/// The cost of the grid at one cell size, measured and predicted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostPoint {
    /// Cells along the longer side.
    pub along: u32,
    /// The cells per axis.
    pub resolution: [u32; 2],
    /// Cells passed per measured ray.
    pub cells_per_ray: f64,
    /// Primitive tests per measured ray.
    pub tests_per_ray: f64,
    /// `C_trav · cells + C_isect · tests` per ray.
    pub cost_per_ray: f64,
    /// The cost model's prediction (Ize et al. 2007: every cell a line through the box
    /// crosses, with the SAH's chance of crossing it; no early stop).
    pub predicted: f64,
}

/// The grid's cost at every cell size from 1 to [`MOST_ALONG`] along the longer side.
#[derive(Clone, Debug, PartialEq)]
pub struct CostCurve {
    /// One point per cell size.
    pub points: Vec<CostPoint>,
    /// The density rule's cells along the longer side.
    pub rule_along: u32,
    /// Rays measured.
    pub ray_count: usize,
}

impl CostCurve {
    /// Builds the grid at every size over `shapes` and traces the same seeded rays through
    /// each, from random points inside the scene in random directions.
    pub fn measure(
        shapes: Arc<ShapeSet<DVec2>>,
        settings: SceneSettings,
        mailboxing: bool,
    ) -> Self {
        let rays = interior_rays(&shapes);
        let cost = settings.cost();
        let options = TraceOptions {
            mailboxing,
            ..TraceOptions::default()
        };
        let points = measured_sizes(shapes.shapes.len())
            .map(|along| {
                let tree = SceneTree::build_with(
                    grid_structure(false),
                    shapes.clone(),
                    settings,
                    CellChoice {
                        along: Some(along),
                        places: None,
                    }
                    .params(),
                    &mut NoBuildObserver,
                );
                let counters = count_rays(&tree, &rays, &options);
                let per_ray = |value: u64| value as f64 / rays.len().max(1) as f64;
                let (cells, tests) = (
                    per_ray(counters.nodes_visited),
                    per_ray(counters.primitive_tests),
                );
                let resolution = tree
                    .built
                    .grid_cells()
                    .map_or([1, 1], |cells| [cells.resolution[0], cells.resolution[1]]);
                CostPoint {
                    along,
                    resolution,
                    cells_per_ray: cells,
                    tests_per_ray: tests,
                    cost_per_ray: cost.per_ray(cells, tests),
                    predicted: tree.stats.sah_cost,
                }
            })
            .collect();
        Self {
            points,
            rule_along: rule_along(&shapes),
            ray_count: rays.len(),
        }
    }

    /// The cheapest point measured.
    pub fn cheapest(&self) -> Option<&CostPoint> {
        self.points
            .iter()
            .min_by(|a, b| a.cost_per_ray.total_cmp(&b.cost_per_ray))
    }
}

/// The lesson.
pub struct GridLesson {
    stage: Stage,
    choice: CellChoice,
    mailboxing: bool,
    walk: GridWalk,
    curve: Derived<(u64, bool), CostCurve>,
}

impl GridLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::ALL),
            choice: CellChoice::default(),
            mailboxing: true,
            walk: GridWalk::default(),
            curve: Derived::default(),
        }
    }

    /// The grid shown.
    pub fn tree(&self) -> Option<&Arc<SceneTree>> {
        self.walk.tree()
    }

    /// The recorded walk.
    pub fn trace(&self) -> Option<&Trace> {
        self.walk.trace()
    }

    /// The cells the walk passes.
    pub fn rows(&self) -> &[WalkRow] {
        self.walk.rows()
    }

    /// The cost curve, once measured.
    pub fn curve(&self) -> Option<&Arc<CostCurve>> {
        self.curve.get()
    }

    /// Chooses the cells: `Some(n)` along the longer side, `None` for the density rule.
    pub fn set_cells_along(&mut self, along: Option<u32>) {
        self.choice.along = along.map(|along| along.clamp(1, MOST_ALONG));
        self.stage.timeline.rewind();
    }

    fn cells_ui(&mut self, ui: &mut egui::Ui) {
        self.stage.presets_ui(ui, "Scenes:");
        cells_slider_ui(
            ui,
            &mut self.choice,
            self.walk.tree(),
            &mut self.stage.timeline,
        );
        if ui
            .checkbox(
                &mut self.mailboxing,
                "mailboxing: test a primitive once per ray",
            )
            .on_hover_text("A primitive that reaches several cells is listed in each; a per-ray note of those already tested skips it in the next (the core's TraceOptions::mailboxing)")
            .changed()
        {
            self.stage.timeline.rewind();
        }
        if let Some(tree) = self.walk.tree() {
            grid_numbers_ui(ui, tree);
        }
    }

    fn cost_ui(&self, ui: &mut egui::Ui) {
        ui.heading("Cost per ray against the cell size");
        let Some(curve) = self.curve.get() else {
            ui.label("Measuring…");
            return;
        };
        let current = self
            .walk
            .tree()
            .and_then(|tree| tree.built.grid_cells())
            .map(GridCells::cells_along_longest);
        cost_plot_ui(ui, curve, current);
        let settings = self.stage.scene.scene.settings;
        ui.label(
            RichText::new(format!(
                "Measured on {} seeded rays from random points in the scene in random directions, the grid built at each size. Cost = C_trav · cells passed + C_isect · tests, with C_trav = {} and C_isect = {}. The model counts every cell a line through the box crosses (the SAH's chances, Ize et al. 2007); the walk stops at the first hit, so it does less.",
                curve.ray_count,
                number(settings.traversal_cost),
                number(settings.intersection_cost)
            ))
            .small()
            .weak(),
        );
    }
}

/// The grid's numbers: its cells, how many hold something, references per primitive.
pub fn grid_numbers_ui(ui: &mut egui::Ui, tree: &SceneTree) {
    let Some(cells) = tree.built.grid_cells() else {
        return;
    };
    let shapes = tree.shapes.shapes.len();
    let cell_count = cells.cell_count();
    let stats = &tree.stats;
    ui.label(format!(
        "{} × {} = {} cells for {} shapes ({} a shape); {} hold something; {} references ({} a shape)",
        cells.resolution[0],
        cells.resolution[1],
        count(cell_count),
        count(shapes),
        number(cell_count as f64 / shapes.max(1) as f64),
        count(cell_count - stats.empty_leaf_count),
        count(stats.primitive_references),
        number(stats.primitive_references as f64 / shapes.max(1) as f64),
    ))
    .on_hover_text("A primitive is listed in every cell it reaches (an exact overlap test, not its bounding box).");
}

/// The measured and the predicted cost per ray at every cell size, the size shown and the
/// density rule's marked.
pub fn cost_plot_ui(ui: &mut egui::Ui, curve: &CostCurve, current: Option<u32>) {
    let measured: PlotPoints = curve
        .points
        .iter()
        .map(|point| [f64::from(point.along), point.cost_per_ray])
        .collect();
    let cells: PlotPoints = curve
        .points
        .iter()
        .map(|point| [f64::from(point.along), point.cells_per_ray])
        .collect();
    let tests: PlotPoints = curve
        .points
        .iter()
        .map(|point| [f64::from(point.along), point.tests_per_ray])
        .collect();
    let predicted: PlotPoints = curve
        .points
        .iter()
        .map(|point| [f64::from(point.along), point.predicted])
        .collect();
    // The plot sits in a scrolled panel: its own height, not what is left under the table
    // (that left it 130 points high, a third of it under the legend).
    let height = 220.0;
    // Up to a few times the cheapest cost, so the valley shows: one cell, where every ray
    // tests everything, can be far above (said below the plot).
    let highest = curve
        .points
        .iter()
        .map(|point| point.cost_per_ray.max(point.predicted))
        .fold(1.0, f64::max);
    let y_top = curve
        .cheapest()
        .map_or(highest, |cheapest| (4.0 * cheapest.cost_per_ray).max(12.0))
        .min(highest * 1.05);
    // A new id for new bounds: a plot keeps the bounds it showed first.
    let plot_bg = ui.visuals().extreme_bg_color;
    let ink = |color| crate::canvas::ink_on(color, plot_bg);
    let keys = [
        ("measured cost", ink(palette::CURRENT), "—"),
        ("cells passed", ink(palette::X_AXIS), "—"),
        ("primitive tests", ink(palette::HIT), "—"),
        ("model's cost", ink(palette::SPHERE), "- -"),
        ("density rule", ink(palette::RAY), "¦"),
        ("shown", shown_size_color(plot_bg), "|"),
    ];
    cell_size_plot(("grid cost curve", y_top.to_bits()), height, "per ray")
        .default_y_bounds(0.0, y_top)
        .show(ui, |plot| {
            plot.line(Line::new(keys[0].0, measured).color(keys[0].1).width(2.5));
            plot.line(Line::new(keys[1].0, cells).color(keys[1].1).width(1.5));
            plot.line(Line::new(keys[2].0, tests).color(keys[2].1).width(1.5));
            plot.line(
                Line::new(keys[3].0, predicted)
                    .color(keys[3].1)
                    .style(LineStyle::dashed_loose())
                    .width(1.5),
            );
            plot.vline(
                VLine::new(keys[4].0, f64::from(curve.rule_along))
                    .color(keys[4].1)
                    .style(LineStyle::dashed_dense()),
            );
            shown_size_line(plot, current, plot_bg);
        });
    // The key under the plot, where it covers no curve.
    ui.horizontal_wrapped(|ui| {
        for (name, color, mark) in keys {
            ui.label(
                RichText::new(format!("{mark} {name}")).color(crate::canvas::readable(ui, color)),
            );
        }
    });
    if let Some(one) = curve.points.first().filter(|one| one.cost_per_ray > y_top) {
        ui.label(
            RichText::new(format!(
                "With one cell, a ray tests every primitive: {} per ray, above the plot.",
                number(one.cost_per_ray)
            ))
            .small(),
        );
    }
    if let Some(cheapest) = curve.cheapest() {
        let rule = curve
            .points
            .iter()
            .find(|point| point.along == curve.rule_along);
        ui.label(format!(
            "Cheapest measured: {} along ({} × {}), {} per ray{}.",
            cheapest.along,
            cheapest.resolution[0],
            cheapest.resolution[1],
            number(cheapest.cost_per_ray),
            rule.map_or(String::new(), |rule| format!(
                "; the density rule's {} along: {} per ray",
                rule.along,
                number(rule.cost_per_ray)
            ))
        ));
    }
}

impl Lesson for GridLesson {
    crate::staged!(walk, curve);

    fn share(&self) -> Vec<(String, String)> {
        vec![
            self.choice.cells_value(),
            ("mailbox".into(), self.mailboxing.to_string()),
        ]
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        match key {
            "cells" => self.choice.restore_cells(value),
            "mailbox" => {
                self.mailboxing = value
                    .parse()
                    .map_err(|_| format!("mailbox '{value}' is not true or false"))?;
                Ok(())
            }
            _ => Err(format!("this lesson keeps no '{key}'")),
        }
    }

    fn show_named(&mut self, name: &str) -> bool {
        self.stage.show_named_preset(name)
    }

    fn named(&self) -> Vec<String> {
        self.stage.preset_names()
    }

    fn update(&mut self) {
        let mailboxing = self.mailboxing;
        self.walk
            .update(&mut self.stage, false, self.choice, mailboxing);
        let scene = &self.stage.scene;
        // Built at every size: as much work as that many builds of the scene.
        self.curve.request(
            &(scene.shapes_revision, mailboxing),
            scene.scene.shapes.shapes.len() * MOST_ALONG as usize,
            || {
                let shapes = Arc::new(scene.scene.shapes.clone());
                let settings = scene.scene.settings;
                move || CostCurve::measure(shapes, settings, mailboxing)
            },
        );
    }

    fn caption(&self) -> Option<String> {
        self.walk.caption(self.stage.timeline.shown)
    }

    fn parts(&self) -> &'static [lesson::Part] {
        &PARTS
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, parts: Parts<'_>) {
        if parts.show(&CELLS_PART) {
            self.cells_ui(ui);
        }
        if parts.show(&WALK_PART) {
            ui.separator();
            let frame = self.stage.timeline.shown;
            self.walk
                .table_ui(ui, "The walk, cell by cell", frame, parts.fit_screen());
            t_hint_ui(ui);
        }
        if parts.show(&COST_PART) {
            ui.separator();
            self.cost_ui(ui);
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let canvas = self.stage.scene.canvas_ui(ui, None);
        let legend = [
            (
                "cells passed: blue listed something, grey empty".to_owned(),
                palette::CURRENT,
            ),
            ("next x line".to_owned(), palette::X_AXIS),
            ("next y line".to_owned(), palette::Y_AXIS),
        ];
        self.walk
            .draw(ui, &canvas, &self.stage, "the grid", &legend, |_, _| {});
        canvas.finish();
    }
}
