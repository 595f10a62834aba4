//! Lesson 16, "The speed/accuracy trade": every structure of the catalogue and every switch
//! (near first or file order, f32 or f64, the fast or the watertight triangle test) measured
//! on the mesh shown and a chosen kind of rays, in the background ([`crate::mesh::trade`]:
//! the core's `trade_lab::Lab`, what `accelviz-cli tradeoff` runs), with its progress and a
//! cancel; a sortable table of what each costs and how often each is wrong; the plots (build
//! against traversal, the SAH's prediction against the measured cost, the total time of a
//! build and N rays with its crossovers); for each outcome of a row, "show me": that ray
//! opened in lesson 12, stepped, with the triangle test's numbers. CSV and PNG export.

use std::sync::Arc;

use accelviz_core::break_even::plotted;
use accelviz_core::format::{count, number};
use accelviz_core::outcome::Outcome;
use accelviz_core::trade::{Switches, TradeRow};
use accelviz_core::{Family, Ray};
use accelviz_scene::rays::RayKind;
use egui::{Color32, RichText};
use egui_plot::{Legend, Line, MarkerShape, Plot, PlotPoint, PlotPoints, Points, VLine};
use glam::DVec3;

use crate::background::worker_threads;
use crate::canvas::palette;
use crate::lesson::{Lesson, Parts, ShowRay};
use crate::lesson_file::LessonText;
use crate::mesh::trade::{TradeJob, TradeKey, TradeProgress, TradeResult};
use crate::mesh::{MeshScene, ui::mesh_ui};
use crate::stage::Stage;
use crate::view3d::Export;
use crate::views::scene_view::{narrow_x_axis, power_of_ten_label, powers_of_ten};

/// The lesson that steps a shown ray.
const SHOWN_IN: &str = "12-mesh-bvh.ron";

/// Rays a measurement traces by default: enough for outcomes per million to mean something on
/// aimed rays, few enough that the browser measures a small mesh in seconds.
const DEFAULT_RAYS: usize = 3_000;

/// The ray counts offered.
const RAY_COUNTS: [usize; 5] = [1_000, 3_000, 10_000, 30_000, 100_000];

/// What the canvas shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// The table of every row.
    Table,
    /// Build time against traversal cost.
    BuildVsTraversal,
    /// The SAH's predicted cost against the measured one.
    PredictedVsMeasured,
    /// Total time of a build and N rays.
    TotalVsRays,
}

impl View {
    /// The views, in their tab order.
    pub const ALL: [View; 4] = [
        View::Table,
        View::BuildVsTraversal,
        View::PredictedVsMeasured,
        View::TotalVsRays,
    ];

    /// Its tab's name.
    pub fn name(self) -> &'static str {
        match self {
            View::Table => "table",
            View::BuildVsTraversal => "build vs traversal",
            View::PredictedVsMeasured => "predicted vs measured",
            View::TotalVsRays => "total vs rays",
        }
    }
}

/// A column of the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Column {
    /// The structure's catalogue name.
    Structure,
    /// Near first or file order.
    Order,
    /// f32 or f64.
    Precision,
    /// Fast or watertight.
    Test,
    /// Build time.
    BuildMs,
    /// The tree's SAH cost.
    Sah,
    /// End-point overlap.
    Epo,
    /// The measured cost per ray.
    Measured,
    /// Millions of rays a second.
    Mrays,
    /// One outcome, per million rays.
    Outcome(Outcome),
    /// Memory.
    Bytes,
}

/// The table's columns, in order.
pub const COLUMNS: [Column; 16] = [
    Column::Structure,
    Column::Order,
    Column::Precision,
    Column::Test,
    // Speed beside accuracy: what a switch buys, then what it gets wrong.
    Column::Mrays,
    Column::BuildMs,
    Column::Outcome(Outcome::Leak),
    Column::Outcome(Outcome::Wrong),
    Column::Outcome(Outcome::FalseHit),
    Column::Outcome(Outcome::Graze),
    Column::Outcome(Outcome::Tie),
    Column::Outcome(Outcome::Agree),
    Column::Measured,
    Column::Sah,
    Column::Epo,
    Column::Bytes,
];

impl Column {
    /// Its heading.
    pub fn heading(self) -> &'static str {
        match self {
            Column::Structure => "structure",
            Column::Order => "order",
            Column::Precision => "precision",
            Column::Test => "test",
            Column::BuildMs => "build ms",
            Column::Sah => "SAH",
            Column::Epo => "EPO",
            Column::Measured => "measured",
            Column::Mrays => "Mrays/s ±%",
            Column::Outcome(outcome) => match outcome {
                Outcome::Agree => "agree/M",
                Outcome::Tie => "tie/M",
                Outcome::Graze => "graze/M",
                Outcome::Leak => "leak/M",
                Outcome::FalseHit => "false hit/M",
                Outcome::Wrong => "wrong/M",
            },
            Column::Bytes => "bytes",
        }
    }

    /// What it means (the heading's hover).
    pub fn about(self) -> &'static str {
        match self {
            Column::Structure => "The structure, as the CLI names it",
            Column::Order => "Near first: the nearer child first. File order: as stored.",
            Column::Precision => "The tree, triangles and rays in f32 or f64",
            Column::Test => {
                "Fast: Möller–Trumbore and the plain slab test. Watertight: Woop et al. 2013 with the conservative slab test (Ize 2013)."
            }
            Column::BuildMs => "The build's median time over the rounds, one thread",
            Column::Sah => "The tree's SAH cost: what the heuristic predicts a ray costs",
            Column::Epo => {
                "End-point overlap (Aila, Karras & Laine 2013): the surface inside boxes that is not theirs, in the SAH's units. BVHs only: a kD-tree's cells do not overlap."
            }
            Column::Measured => "What a ray cost: C_trav·nodes + C_isect·primitives, per ray",
            Column::Mrays => {
                "Millions of rays a second (median round, one thread), ± half the range of the rounds: rows whose ranges overlap are not shown to differ"
            }
            Column::Outcome(outcome) => outcome.about(),
            Column::Bytes => "Memory of the nodes and primitive lists traversal reads",
        }
    }

    /// The cell of `row`.
    pub fn text(self, row: &TradeRow, result: &TradeResult) -> String {
        match self {
            Column::Structure => row.structure.name(),
            Column::Order => row.switches.order.name().to_owned(),
            Column::Precision => row.switches.precision.name().to_owned(),
            Column::Test => row.switches.test_name().to_owned(),
            Column::BuildMs => format!("{:.2}", row.build_ms),
            Column::Sah => format!("{:.1}", row.sah_cost),
            Column::Epo => row.epo.map_or("-".to_owned(), |epo| format!("{epo:.1}")),
            Column::Measured => format!("{:.1}", row.measured_cost(&result.params)),
            Column::Mrays => format!("{:.2} ±{:.0}", row.mrays_per_s, row.trace_spread_percent),
            Column::Outcome(outcome) => format!("{:.0}", row.outcomes.per_million(outcome)),
            Column::Bytes => count(row.bytes),
        }
    }

    /// The value it sorts by (text columns sort by their text).
    fn value(self, row: &TradeRow, result: &TradeResult) -> Option<f64> {
        match self {
            Column::Structure | Column::Order | Column::Precision | Column::Test => None,
            Column::BuildMs => Some(row.build_ms),
            Column::Sah => Some(row.sah_cost),
            Column::Epo => Some(row.epo.unwrap_or(f64::NEG_INFINITY)),
            Column::Measured => Some(row.measured_cost(&result.params)),
            Column::Mrays => Some(row.mrays_per_s),
            Column::Outcome(outcome) => Some(row.outcomes.per_million(outcome)),
            Column::Bytes => Some(row.bytes as f64),
        }
    }
}

/// The order of `result`'s rows sorted by `column` (`descending` or not), ties in the
/// measurement's order.
pub fn sorted_rows(result: &TradeResult, column: Column, descending: bool) -> Vec<usize> {
    let mut order: Vec<usize> = (0..result.rows.len()).collect();
    order.sort_by(|&a, &b| {
        let (row_a, row_b) = (&result.rows[a], &result.rows[b]);
        let by = match (column.value(row_a, result), column.value(row_b, result)) {
            // The structures in the catalogue's order, as the measurement made the rows.
            _ if column == Column::Structure => a.cmp(&b),
            (Some(x), Some(y)) => x.total_cmp(&y),
            _ => column.text(row_a, result).cmp(&column.text(row_b, result)),
        };
        let by = if descending { by.reverse() } else { by };
        by.then(a.cmp(&b))
    });
    order
}

/// The rows a table shows: every switch, or the base switches only (one row a structure).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rows {
    /// Every row.
    All,
    /// Near first, f32, fast: one row a structure.
    Base,
}

/// The lesson.
pub struct TradeLesson {
    stage: Stage<MeshScene>,
    /// The rays' kind.
    pub ray_kind: RayKind,
    /// About how many rays.
    pub ray_count: usize,
    /// Timed rounds.
    pub rounds: usize,
    job: Option<TradeJob>,
    result: Option<Arc<TradeResult>>,
    /// Why the last measurement could not start (no rays of the kind, say).
    problem: Option<String>,
    /// The key last asked for (a cancelled one is not asked again until something changes).
    asked: Option<TradeKey>,
    /// What the canvas shows.
    pub view: View,
    /// The column the table is sorted by, and whether descending.
    pub sort: (Column, bool),
    /// Which rows the table shows.
    pub rows: Rows,
    /// The row the inspector shows (its index in the result's rows).
    pub selected: Option<usize>,
    show_ray: Option<ShowRay>,
    export: Option<Export>,
    /// A PNG of the plot asked for: the plot's rectangle, waiting for the screenshot.
    plot_png: Option<egui::Rect>,
    /// Where the plot was drawn last.
    pub plot_rect: Option<egui::Rect>,
    /// The window's picture, when it arrives (the integration reads it after a frame).
    screenshot: Arc<std::sync::Mutex<Option<Arc<egui::ColorImage>>>>,
}

impl TradeLesson {
    /// The lesson with its file's mesh.
    pub fn new(text: LessonText) -> Self {
        let scene = MeshScene::of_lesson(&text);
        Self {
            stage: Stage::with_scene(text, scene),
            ray_kind: RayKind::Aimed,
            ray_count: DEFAULT_RAYS,
            rounds: 3,
            job: None,
            result: None,
            problem: None,
            asked: None,
            view: View::Table,
            sort: (Column::Structure, false),
            rows: Rows::All,
            selected: None,
            show_ray: None,
            export: None,
            plot_png: None,
            plot_rect: None,
            screenshot: Arc::default(),
        }
    }

    /// What a measurement now would be of.
    fn key(&self) -> TradeKey {
        TradeKey {
            mesh_revision: self.stage.scene.revision,
            ray_kind: self.ray_kind,
            ray_count: self.ray_count,
            seed: 1,
            rounds: self.rounds,
        }
    }

    /// The mesh on screen, to open another.
    pub fn scene_mut(&mut self) -> &mut MeshScene {
        &mut self.stage.scene
    }

    /// The finished measurement shown.
    pub fn result(&self) -> Option<&TradeResult> {
        self.result.as_deref()
    }

    /// Shows `result` as if it had just been measured (its key is taken as asked for, so it
    /// is not measured again until a choice changes).
    pub fn show_result(&mut self, result: TradeResult) {
        self.cancel();
        self.ray_kind = result.key.ray_kind;
        self.ray_count = result.key.ray_count;
        self.rounds = result.key.rounds;
        self.asked = Some(result.key.clone());
        self.result = Some(Arc::new(result));
    }

    /// How far the measurement under way is.
    pub fn progress(&self) -> Option<TradeProgress> {
        self.job.as_ref().map(TradeJob::progress)
    }

    /// Measures again, now (the same choices).
    pub fn measure(&mut self) {
        self.job = None;
        self.asked = None;
        self.result = None;
    }

    /// Stops the measurement under way; the last result stays.
    pub fn cancel(&mut self) {
        if let Some(job) = self.job.take() {
            job.cancel();
        }
    }

    /// Starts the measurement of `key`.
    fn start(&mut self, key: TradeKey) {
        self.asked = Some(key.clone());
        self.problem = None;
        let mesh = self.stage.scene.mesh.clone();
        let specs = match self.ray_kind.rays(&mesh, self.ray_count, key.seed, None) {
            Ok(specs) => specs,
            Err(problem) => {
                self.problem = Some(problem);
                return;
            }
        };
        let rays: Vec<Ray<DVec3>> = specs.iter().filter_map(|spec| spec.to_ray().ok()).collect();
        if rays.is_empty() || mesh.triangles.is_empty() {
            self.problem = Some(format!(
                "no {} rays on this mesh to measure with",
                self.ray_kind.name()
            ));
            return;
        }
        self.job = Some(TradeJob::start(
            key,
            (mesh, self.stage.scene.name.clone()),
            &rays,
            self.ray_kind.default_query(),
            worker_threads(),
        ));
    }

    /// The rows the table shows, in its order.
    pub fn shown_rows(&self) -> Vec<usize> {
        let Some(result) = self.result() else {
            return Vec::new();
        };
        sorted_rows(result, self.sort.0, self.sort.1)
            .into_iter()
            .filter(|&row| self.rows == Rows::All || result.rows[row].switches == Switches::BASE)
            .collect()
    }

    /// Asks lesson 12 to show row `row`'s example ray of `outcome`.
    pub fn show_me(&mut self, row: usize, outcome: Outcome) -> bool {
        let Some(result) = self.result() else {
            return false;
        };
        let Some(trade_row) = result.rows.get(row) else {
            return false;
        };
        let Some(ray) = trade_row.example(outcome) else {
            return false;
        };
        // The result's own mesh: a table left from another mesh steps its ray on that mesh.
        self.show_ray = Some(ShowRay {
            lesson: SHOWN_IN,
            mesh: result.mesh.clone(),
            mesh_name: result.mesh_name.clone(),
            structure: trade_row.structure,
            ray: *ray,
            switches: trade_row.switches,
            query: result.query,
            outcome,
        });
        true
    }

    /// The table as CSV (the CLI's `tradeoff.csv`), to save.
    pub fn export_csv(&mut self) {
        if let Some(result) = self.result() {
            let name = format!(
                "tradeoff-{}-{}.csv",
                short_name(&result.mesh_name),
                result.key.ray_kind.name()
            );
            let text = accelviz_core::trade::csv(&result.rows, &result.params);
            self.export = Some(Ok((name, text.into_bytes())));
        }
    }

    fn controls_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            mesh_ui(ui, &mut self.stage.scene);
            ui.separator();
            egui::ComboBox::from_label("rays")
                .selected_text(self.ray_kind.name())
                .show_ui(ui, |ui| {
                    for kind in RayKind::ALL {
                        ui.selectable_value(&mut self.ray_kind, kind, kind.name())
                            .on_hover_text(kind.about());
                    }
                });
            egui::ComboBox::from_id_salt("ray count")
                .selected_text(count(self.ray_count))
                .show_ui(ui, |ui| {
                    for rays in RAY_COUNTS {
                        ui.selectable_value(&mut self.ray_count, rays, count(rays));
                    }
                })
                .response
                .on_hover_text("About how many rays of the kind (every row traces all of them)");
        });
        ui.horizontal_wrapped(|ui| {
            let label = ui.label("rounds");
            ui.add(egui::DragValue::new(&mut self.rounds).range(1..=9))
                .labelled_by(label.id)
                .on_hover_text(
                    "Every structure is built, and every row traced, once a round, the rounds interleaved; each figure is the median, ± half the range",
                );
            if self.job.is_none() && ui.button("measure again").clicked() {
                self.measure();
            }
            ui.separator();
            self.export_ui(ui);
        });
        crate::mesh::ui::reading_ui(ui, &mut self.stage.scene);
        if let Some(progress) = self.progress() {
            ui.horizontal_wrapped(|ui| {
                ui.add(
                    egui::ProgressBar::new(progress.fraction())
                        .desired_width(260.0)
                        .show_percentage(),
                );
                if ui.button("cancel").clicked() {
                    self.cancel();
                }
                ui.label(format!(
                    "{} so far, {}",
                    crate::mesh::trade::duration_text(progress.spent_ms),
                    progress.left_text()
                ));
            });
            ui.label(RichText::new(&progress.doing).weak());
            ui.ctx().request_repaint();
        }
        if let Some(problem) = &self.problem {
            ui.colored_label(ui.visuals().error_fg_color, problem);
        }
        ui.horizontal_wrapped(|ui| {
            for view in View::ALL {
                ui.selectable_value(&mut self.view, view, view.name());
            }
        });
    }

    /// The CSV and PNG buttons.
    fn export_ui(&mut self, ui: &mut egui::Ui) {
        ui.add_enabled_ui(self.result.is_some(), |ui| {
            if ui
                .button("save CSV")
                .on_hover_text("The table with every digit, as accelviz-cli tradeoff writes it")
                .clicked()
            {
                self.export_csv();
            }
            if self.view != View::Table
                && ui
                    .button("save PNG")
                    .on_hover_text("This plot as a picture")
                    .clicked()
            {
                self.plot_png = self.plot_rect;
                let (arrived, ctx) = (self.screenshot.clone(), ui.ctx().clone());
                ui.ctx().request_screenshot(move |image| {
                    if let Ok(mut slot) = arrived.lock() {
                        *slot = Some(image);
                    }
                    ctx.request_repaint();
                });
            }
        });
    }

    /// A plot's picture, once the screenshot asked for arrives.
    fn take_screenshot(&mut self, ui: &egui::Ui) {
        let Some(rect) = self.plot_png else {
            return;
        };
        let Some(image) = self.screenshot.lock().ok().and_then(|mut slot| slot.take()) else {
            return;
        };
        self.plot_png = None;
        let region = image.region(&rect, Some(ui.ctx().pixels_per_point()));
        let pixels: Vec<[u8; 4]> = region.pixels.iter().map(|pixel| pixel.to_array()).collect();
        let [width, height] = region.size;
        let name = format!("tradeoff-{}.png", self.view.name().replace(' ', "-"));
        self.export = Some(
            accelviz_scene::output::encode_png(width, height, &pixels).map(|bytes| (name, bytes)),
        );
    }

    fn table_ui(&mut self, ui: &mut egui::Ui, result: &TradeResult) {
        ui.horizontal_wrapped(|ui| {
            ui.selectable_value(&mut self.rows, Rows::All, "every switch");
            ui.selectable_value(&mut self.rows, Rows::Base, "near first, f32, fast only");
            ui.label(RichText::new("Click a heading to sort by it, a row to inspect it.").weak());
        });
        let shown = self.shown_rows();
        egui::ScrollArea::both()
            .auto_shrink([false, false])
            .show(ui, |ui| {
                egui::Grid::new("trade table")
                    .striped(true)
                    .spacing([10.0, 3.0])
                    .show(ui, |ui| {
                        for column in COLUMNS {
                            let arrow = match self.sort {
                                (sorted, false) if sorted == column => " ^",
                                (sorted, true) if sorted == column => " v",
                                _ => "",
                            };
                            let heading =
                                RichText::new(format!("{}{arrow}", column.heading())).strong();
                            if ui
                                .add(egui::Label::new(heading).sense(egui::Sense::click()))
                                .on_hover_text(column.about())
                                .clicked()
                            {
                                self.sort = if self.sort.0 == column {
                                    (column, !self.sort.1)
                                } else {
                                    // Numbers read best largest first; names A to Z, and the
                                    // structures in the catalogue's order.
                                    (column, column.value(&result.rows[0], result).is_some())
                                };
                            }
                        }
                        ui.end_row();
                        for row in shown {
                            let trade_row = &result.rows[row];
                            let selected = self.selected == Some(row);
                            for column in COLUMNS {
                                let mut text = RichText::new(column.text(trade_row, result));
                                if let Column::Outcome(outcome) = column
                                    && outcome.is_error()
                                    && trade_row.outcomes.count(outcome) > 0
                                {
                                    text = text
                                        .color(crate::canvas::readable_in_table(ui, palette::MISS))
                                        .strong();
                                }
                                if ui.selectable_label(selected, text).clicked() {
                                    self.selected = Some(row);
                                }
                            }
                            ui.end_row();
                        }
                    });
            });
    }

    fn plot_ui(&mut self, ui: &mut egui::Ui, result: &TradeResult) {
        let base: Vec<&TradeRow> = result
            .rows
            .iter()
            .filter(|row| row.switches == Switches::BASE)
            .collect();
        let cost = |row: &TradeRow| row.measured_cost(&result.params);
        let height = ui.available_height() - 36.0;
        let response = match self.view {
            View::Table => return,
            View::BuildVsTraversal => {
                ui.label("Each structure near first, f32, fast: a build that takes longer should buy a cheaper ray. Lower left is best.");
                scatter_ui(
                    ui,
                    "build vs traversal",
                    height,
                    &base,
                    "build time, ms (log scale)",
                    true,
                    |row| row.build_ms,
                    cost,
                    false,
                )
            }
            View::PredictedVsMeasured => {
                ui.label("The SAH's cost of each tree against what its rays cost. On the diagonal the heuristic's assumption held: rays from outside, uniformly spread, never stopped early.");
                scatter_ui(
                    ui,
                    "predicted vs measured",
                    height,
                    &base,
                    "SAH cost of the tree (predicted)",
                    false,
                    |row| row.sah_cost,
                    cost,
                    true,
                )
            }
            View::TotalVsRays => {
                ui.label("A build once, then every ray: the total for N rays. The lowest line is the structure to build; dashed lines mark where it changes.");
                total_vs_rays_ui(ui, height, result)
            }
        };
        self.plot_rect = Some(response.rect);
    }

    fn row_ui(&mut self, ui: &mut egui::Ui, result: &TradeResult) {
        let Some(row) = self.selected.filter(|&row| row < result.rows.len()) else {
            ui.label("Click a row of the table to see its outcomes and a ray of each.");
            return;
        };
        let trade_row = &result.rows[row];
        ui.label(
            RichText::new(format!(
                "{} · {} · {} · {} test",
                trade_row.structure.name(),
                trade_row.switches.order.name(),
                trade_row.switches.precision.name(),
                trade_row.switches.test_name()
            ))
            .strong(),
        );
        ui.label(format!(
            "build {} ms (±{:.0} %), {} Mrays/s (±{:.0} %), {} nodes and {} triangles a ray",
            number(trade_row.build_ms),
            trade_row.build_spread_percent,
            number(trade_row.mrays_per_s),
            trade_row.trace_spread_percent,
            number(trade_row.nodes_per_ray),
            number(trade_row.primitives_per_ray),
        ));
        let mut show = None;
        egui::Grid::new("outcomes").striped(true).show(ui, |ui| {
            for outcome in Outcome::ALL {
                let rays = trade_row.outcomes.count(outcome);
                let name = RichText::new(outcome.name().replace('_', " "));
                ui.label(if outcome.is_error() && rays > 0 {
                    name.color(crate::canvas::readable_in_table(ui, palette::MISS))
                        .strong()
                } else {
                    name
                })
                .on_hover_text(outcome.about());
                ui.label(format!("{} rays", count(rays as usize)));
                ui.label(format!("{:.0}/M", trade_row.outcomes.per_million(outcome)));
                if ui
                    .add_enabled(rays > 0, egui::Button::new("show me"))
                    .on_hover_text("This row's first ray of this outcome, stepped in lesson 12 with the triangle tests' numbers")
                    .clicked()
                {
                    show = Some(outcome);
                }
                ui.end_row();
            }
        });
        if let Some(outcome) = show {
            self.show_me(row, outcome);
        }
    }

    fn break_even_ui(ui: &mut egui::Ui, result: &TradeResult) {
        let break_even = &result.break_even;
        ui.label(RichText::new("Which structure should this scene get?").strong());
        ui.label(
            RichText::new("A build and N rays, near first, f32, fast: the fastest in all, where the rounds' ranges tell it.").weak(),
        );
        egui::Grid::new("break even").striped(true).show(ui, |ui| {
            ui.label(RichText::new("rays").strong());
            ui.label(RichText::new("fastest").strong());
            ui.label(RichText::new("total").strong());
            ui.label(RichText::new("next").strong())
                .on_hover_text("How much slower the next fastest is (its name on hover)");
            ui.end_row();
            for fastest in &break_even.fastest {
                ui.label(count(fastest.rays as usize));
                let name = break_even.name(fastest.fastest);
                if fastest.is_clear() {
                    ui.label(name);
                } else {
                    let tied: Vec<&str> = fastest
                        .within_spread
                        .iter()
                        .map(|&index| break_even.name(index))
                        .collect();
                    ui.label(RichText::new("no clear winner").italics())
                        .on_hover_text(format!(
                            "{name} by the medians, but the rounds' ranges of {} overlap its own",
                            tied.join(", ")
                        ));
                }
                ui.label(format!("{} ms", number(fastest.total_ms)));
                match fastest.runner_up {
                    Some((next, ratio)) => {
                        ui.label(format!("{ratio:.2}×"))
                            .on_hover_text(break_even.name(next));
                    }
                    None => {
                        ui.label("-");
                    }
                }
                ui.end_row();
            }
        });
        for sentence in break_even.verdict() {
            ui.label(sentence);
        }
    }
}

fn short_name(mesh: &str) -> &str {
    let name = mesh.rsplit(['/', '\\']).next().unwrap_or(mesh);
    name.trim_start_matches("builtin:")
}

/// The family of a row, for a plot's colours.
fn family_color(row: &TradeRow) -> Color32 {
    color_of(row.structure.family())
}

/// A family's colour in the lab's plots.
fn color_of(family: Family) -> Color32 {
    match family {
        Family::Bvh => palette::HIT,
        Family::Kd => palette::RAY,
        Family::Grid => palette::SPHERE,
        Family::HashedGrid => palette::BOX,
        Family::Octree => palette::Z_AXIS,
    }
}

/// One point a structure, labelled with its name, coloured by family.
#[allow(clippy::too_many_arguments)]
fn scatter_ui(
    ui: &mut egui::Ui,
    id: &str,
    height: f32,
    rows: &[&TradeRow],
    x_label: &str,
    log_x: bool,
    x: impl Fn(&TradeRow) -> f64,
    y: impl Fn(&TradeRow) -> f64,
    diagonal: bool,
) -> egui::Response {
    let at = |row: &TradeRow| {
        let value = x(row);
        [
            if log_x {
                value.max(1e-6).log10()
            } else {
                value
            },
            y(row),
        ]
    };
    let mut plot = Plot::new(id)
        .height(height.max(160.0))
        .legend(Legend::default().position(egui_plot::Corner::LeftTop))
        .y_axis_label("measured cost per ray")
        .y_axis_min_width(40.0)
        .include_y(0.0)
        .allow_scroll(false);
    if log_x {
        plot = plot
            .x_grid_spacer(powers_of_ten)
            .custom_x_axes(vec![narrow_x_axis(x_label).formatter(power_of_ten_label)]);
    } else {
        plot = plot
            .include_x(0.0)
            .custom_x_axes(vec![narrow_x_axis(x_label)]);
    }
    let shown = plot.show(ui, |plot| {
        if diagonal {
            let top = rows
                .iter()
                .map(|row| at(row)[0].max(at(row)[1]))
                .fold(0.0, f64::max);
            plot.line(
                Line::new(
                    "predicted = measured",
                    PlotPoints::new(vec![[0.0, 0.0], [top, top]]),
                )
                .color(Color32::GRAY)
                .style(egui_plot::LineStyle::dashed_dense()),
            );
        }
        for family in Family::ALL {
            let name = family.label();
            let points: Vec<[f64; 2]> = rows
                .iter()
                .filter(|row| row.structure.family() == family)
                .map(|row| at(row))
                .collect();
            if points.is_empty() {
                continue;
            }
            let color = color_of(family);
            plot.points(
                Points::new(name, PlotPoints::new(points))
                    .shape(MarkerShape::Circle)
                    .radius(4.0)
                    .color(color),
            );
        }
    });
    // The names beside their points, none over another, a point or the legend: at lecture
    // size egui_plot's own texts piled the BVHs' names into one smear and ran off the right
    // edge. A name with no free spot is left out, and said on hover.
    let transform = shown.transform;
    let frame = *transform.frame();
    let painter = ui.painter_at(frame);
    let font = egui::TextStyle::Small.resolve(ui.style());
    let mut labels = crate::canvas::Labels::new(frame.shrink(2.0));
    let legend_rows = Family::ALL
        .iter()
        .filter(|family| rows.iter().any(|row| row.structure.family() == **family))
        .count() as f32;
    let legend_row = ui.text_style_height(&egui::TextStyle::Body) + 4.0;
    labels.reserve(egui::Rect::from_min_size(
        frame.left_top(),
        egui::vec2(11.0 * font.size + 24.0, legend_rows * legend_row + 12.0),
    ));
    let spots: Vec<egui::Pos2> = rows
        .iter()
        .map(|row| {
            let [px, py] = at(row);
            transform.position_from_point(&PlotPoint::new(px, py))
        })
        .collect();
    for spot in &spots {
        labels.reserve(egui::Rect::from_center_size(*spot, egui::Vec2::splat(9.0)));
    }
    let plate = ui.visuals().extreme_bg_color;
    let mut left_out = Vec::new();
    for (row, spot) in rows.iter().zip(&spots) {
        let name = row.structure.name();
        let size = painter
            .layout_no_wrap(name.to_string(), font.clone(), Color32::WHITE)
            .size();
        let offsets = label_offsets(size);
        let placed = labels.place(
            &painter,
            &name,
            font.clone(),
            crate::canvas::readable_on(family_color(row), plate),
            *spot,
            &offsets,
            Some(plate),
        );
        if placed.is_none() {
            left_out.push((name, *spot));
        }
    }
    let response = shown.response;
    if let Some(pointer) = response.hover_pos() {
        let near: Vec<String> = rows
            .iter()
            .zip(&spots)
            .filter(|(_, spot)| spot.distance(pointer) < 8.0)
            .map(|(row, _)| row.structure.name().to_string())
            .collect();
        if !near.is_empty() {
            response.clone().on_hover_text_at_pointer(near.join(", "));
        }
    }
    if !left_out.is_empty() {
        painter.text(
            frame.right_bottom() - egui::vec2(6.0, 4.0),
            egui::Align2::RIGHT_BOTTOM,
            format!(
                "{} left unnamed where names would overlap: hover a point",
                accelviz_core::format::counted(left_out.len(), "point", "points")
            ),
            font,
            ui.visuals().weak_text_color(),
        );
    }
    response
}

/// Where a point's name of `size` may go, nearest first: right of it, left, above, below,
/// then the diagonals (the offsets of the name's centre from the point).
fn label_offsets(size: egui::Vec2) -> Vec<egui::Vec2> {
    let (x, y) = (size.x / 2.0 + 7.0, size.y / 2.0 + 5.0);
    vec![
        egui::vec2(x, 0.0),
        egui::vec2(-x, 0.0),
        egui::vec2(0.0, -y),
        egui::vec2(0.0, y),
        egui::vec2(x, -y),
        egui::vec2(x, y),
        egui::vec2(-x, -y),
        egui::vec2(-x, y),
    ]
}

/// Total time against rays, log-log: the structures fastest somewhere and the lecture's
/// three rules' BVHs, with the crossovers marked.
fn total_vs_rays_ui(ui: &mut egui::Ui, height: f32, result: &TradeResult) -> egui::Response {
    let break_even = &result.break_even;
    let shown = plotted(break_even);
    let colors = [
        palette::HIT,
        palette::RAY,
        palette::MISS,
        Color32::from_rgb(170, 120, 230),
        Color32::from_rgb(90, 190, 190),
        Color32::from_rgb(220, 200, 80),
        Color32::from_rgb(200, 130, 170),
        Color32::GRAY,
    ];
    Plot::new("total vs rays")
        .height(height.max(160.0))
        .legend(Legend::default().position(egui_plot::Corner::LeftTop))
        .custom_x_axes(vec![
            narrow_x_axis("rays traced (log scale)").formatter(power_of_ten_label),
        ])
        .y_axis_label("build + rays, ms (log scale)")
        .y_axis_min_width(56.0)
        .x_grid_spacer(powers_of_ten)
        .y_grid_spacer(powers_of_ten)
        .y_axis_formatter(power_of_ten_label)
        .allow_scroll(false)
        .show(ui, |plot| {
            for (slot, &index) in shown.iter().enumerate() {
                let contender = &break_even.contenders[index];
                let points: Vec<[f64; 2]> = (0..=60)
                    .map(|step| {
                        let rays = 10f64.powf(3.0 + 0.1 * step as f64);
                        [rays.log10(), contender.total_ms(rays).max(1e-6).log10()]
                    })
                    .collect();
                plot.line(
                    Line::new(contender.name.clone(), PlotPoints::new(points))
                        .color(colors[slot % colors.len()])
                        .width(2.0),
                );
            }
            // Only the crossovers the rounds' ranges tell apart.
            for crossing in &break_even.crossovers {
                if crossing.clear_between.is_none() {
                    continue;
                }
                plot.vline(
                    VLine::new(
                        format!(
                            "{} gives way to {} at {}",
                            break_even.name(crossing.from),
                            break_even.name(crossing.to),
                            number(crossing.rays)
                        ),
                        crossing.rays.log10(),
                    )
                    .color(Color32::GRAY)
                    .style(egui_plot::LineStyle::dashed_loose()),
                );
            }
        })
        .response
}

impl Lesson for TradeLesson {
    crate::staged!();

    fn update(&mut self) {
        self.stage.scene.poll();
        if let Some(job) = &self.job {
            job.advance();
            if let Some(result) = job.take_result() {
                // The browser test waits for this line.
                log::info!(
                    "accelviz: trade lab measured {} rows of {} {} rays on {} in {} ms {}",
                    result.rows.len(),
                    result.rays,
                    result.key.ray_kind.name(),
                    result.mesh_name,
                    result.millis.round(),
                    result.place
                );
                self.result = Some(Arc::new(result));
                self.job = None;
                let rows = self.result().map_or(0, |result| result.rows.len());
                if self.selected.is_some_and(|row| row >= rows) {
                    self.selected = None;
                }
            }
        }
        // What is shown, under way, or cancelled was asked for: a new choice asks again.
        let key = self.key();
        if self.asked.as_ref() != Some(&key) {
            self.cancel();
            self.start(key);
        }
    }

    /// The mesh, the rays' kind and count, and the rounds.
    fn share(&self) -> Vec<(String, String)> {
        let mut values = Vec::from_iter(crate::share::mesh_value(&self.stage.scene));
        values.push(("rays".into(), self.ray_kind.name().into()));
        values.push(("ray-count".into(), self.ray_count.to_string()));
        values.push(("rounds".into(), self.rounds.to_string()));
        values
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        let whole = |low: usize, high: usize| {
            value
                .parse::<usize>()
                .ok()
                .filter(|n| (low..=high).contains(n))
                .ok_or_else(|| {
                    format!("{key} must be a whole number from {low} to {high}, not '{value}'")
                })
        };
        match key {
            "mesh" => crate::share::restore_mesh(&mut self.stage.scene, value)?,
            "rays" => {
                self.ray_kind = RayKind::from_name(value)
                    .ok_or_else(|| format!("'{value}' is not a ray kind"))?
            }
            "ray-count" => self.ray_count = whole(1, 1_000_000)?,
            "rounds" => self.rounds = whole(1, 9)?,
            _ => return Err(format!("this lesson keeps no '{key}'")),
        }
        Ok(())
    }

    /// The views by their tabs' names: a lecture slide opens the one that carries its point
    /// (`lesson 16 show "total vs rays"`), not a table of every row.
    fn show_named(&mut self, name: &str) -> bool {
        match View::ALL.into_iter().find(|view| view.name() == name) {
            Some(view) => {
                self.view = view;
                true
            }
            None => false,
        }
    }

    fn named(&self) -> Vec<String> {
        View::ALL
            .iter()
            .map(|view| view.name().to_owned())
            .collect()
    }

    fn take_show_ray(&mut self) -> Option<ShowRay> {
        self.show_ray.take()
    }

    fn take_export(&mut self) -> Option<Export> {
        self.export.take()
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: Parts<'_>) {
        let Some(result) = self.result.clone() else {
            ui.label("Measuring…");
            return;
        };
        ui.label(format!(
            "{} ({} triangles), {} {} rays, {} hit; {}, measured in {:.1} s {}.",
            short_name(&result.mesh_name),
            count(result.triangles),
            count(result.rays),
            result.key.ray_kind.name(),
            result.query.name(),
            accelviz_core::format::counted(result.key.rounds, "round", "rounds"),
            result.millis / 1e3,
            result.place,
        ));
        ui.separator();
        self.row_ui(ui, &result);
        ui.separator();
        Self::break_even_ui(ui, &result);
        ui.separator();
        for sentence in accelviz_core::trade_summary::summary(&result.rows) {
            ui.label(sentence);
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.take_screenshot(ui);
        self.controls_ui(ui);
        ui.separator();
        let Some(result) = self.result.clone() else {
            ui.label(if self.job.is_some() {
                "Measuring every structure and switch: the table appears when every round is in."
            } else {
                "Nothing measured yet."
            });
            return;
        };
        if let Some(note) = self.stale_note(&result) {
            ui.label(
                RichText::new(note)
                    .strong()
                    .color(crate::canvas::readable(ui, palette::MISS)),
            );
        }
        match self.view {
            View::Table => self.table_ui(ui, &result),
            _ => self.plot_ui(ui, &result),
        }
    }
}

impl TradeLesson {
    /// What to say over a result that is not of the mesh on screen (another was opened, and
    /// its measurement is under way or was cancelled): whose numbers these are.
    pub fn stale_note(&self, result: &TradeResult) -> Option<String> {
        if result.key.mesh_revision == self.stage.scene.revision {
            return None;
        }
        let then = format!(
            "These are the numbers of {} ({} triangles), not of {}, the mesh on screen",
            short_name(&result.mesh_name),
            count(result.triangles),
            short_name(&self.stage.scene.name)
        );
        Some(if self.job.is_some() {
            format!("{then}: it is being measured.")
        } else {
            format!(
                "{then}: press \"measure again\" to measure it. \"Show me\" steps a ray on {}.",
                short_name(&result.mesh_name)
            )
        })
    }
}
