//! The grid walk as lessons 18 and 19 show it: the core's walk (Amanatides & Woo 1987) read
//! into a row per cell passed (its part of the ray, the `t` to the next line on each axis, the
//! tests made, the places a hashed lookup read), told in words a step at a time, drawn on the
//! canvas (the cells passed, the current one, the ticks of its next lines) and tabled; the
//! cell-size choice both lessons share (a slider along the longer side, or the density rule).

use std::sync::Arc;

use accelviz_core::format::{count, number};
use accelviz_core::grid::{DEFAULT_DENSITY, GridCells};
use accelviz_core::{GridParams, NoBuildObserver, Order, ShapeSet, Step, Structure, TraceOptions};
use egui::{Color32, RichText, Stroke};
use egui_plot::{Plot, PlotUi, VLine};
use glam::DVec2;

use crate::background::{Cached, Derived};
use crate::canvas::{Canvas, faded, palette};
use crate::stage::{SceneTree, Stage, request_over_shapes};
use crate::trace::Trace;
use crate::views::scene_view::{
    building_note, draw_ray, draw_tested_shapes, narrow_x_axis, number_shapes,
};
use crate::views::tree_view::{TreeLook, draw_tree, node_outline};

/// A lesson's grid and its ray's walk: built (on a worker when large), traced, and read into
/// rows, kept up to date with the scene and the choices.
#[derive(Default)]
pub struct GridWalk {
    tree: Derived<(u64, CellChoice), SceneTree>,
    trace: Cached<(u64, u64, bool), Trace>,
    rows: Cached<(u64, u64, bool), Vec<WalkRow>>,
}

impl GridWalk {
    /// Brings the grid (dense or `hashed`, cut as `choice` says) and the walk of the stage's
    /// ray (with or without `mailboxing`) up to date, and the timeline's length with them.
    pub fn update(
        &mut self,
        stage: &mut Stage,
        hashed: bool,
        choice: CellChoice,
        mailboxing: bool,
    ) {
        let scene = &stage.scene;
        request_grid(&mut self.tree, scene, hashed, choice);
        let Some(tree) = self.tree.get().cloned() else {
            return;
        };
        let key = (self.tree.generation(), scene.revision, mailboxing);
        let trace = self.trace.get_or_make(key, || match scene.ray() {
            Ok(ray) => Trace::of_tree(
                &tree,
                &ray,
                &TraceOptions {
                    order: Order::NearFirst,
                    mailboxing,
                    ..TraceOptions::default()
                },
            ),
            Err(_) => Trace::default(),
        });
        stage.timeline.set_len(trace.frames());
        let trace = trace.clone();
        self.rows.get_or_make(key, || walk_rows(&trace, &tree));
    }

    /// The grid, once built.
    pub fn tree(&self) -> Option<&Arc<SceneTree>> {
        self.tree.get()
    }

    /// Bumped each time a new grid comes in: what is derived from the grid follows it.
    pub fn generation(&self) -> u64 {
        self.tree.generation()
    }

    /// How long a newer grid has been building, if one is.
    pub fn working_for(&self) -> Option<std::time::Duration> {
        self.tree.working_for()
    }

    /// The walk, as recorded.
    pub fn trace(&self) -> Option<&Trace> {
        self.trace.get()
    }

    /// The cells the walk passes.
    pub fn rows(&self) -> &[WalkRow] {
        self.rows.get().map_or(&[], |rows| rows.as_slice())
    }

    /// The caption of frame `frame`.
    pub fn caption(&self, frame: usize) -> Option<String> {
        Some(walk_caption(
            self.trace.get()?,
            self.rows(),
            self.tree.get()?,
            frame,
        ))
    }

    /// The walk's table at frame `frame`, under `heading`.
    pub fn table_ui(&self, ui: &mut egui::Ui, heading: &str, frame: usize, fit_height: bool) {
        ui.heading(heading);
        if let Some(trace) = self.trace.get() {
            walk_table_ui(ui, trace, self.rows(), frame, fit_height);
        }
    }

    /// Draws the stage's frame on `canvas`: the cells passed, the shapes as tested, the grid,
    /// then the lesson's own layer (`over`), the ray with the current cell's next lines, the
    /// handles, the `legend` and a note while `what` is building.
    pub fn draw(
        &self,
        ui: &egui::Ui,
        canvas: &Canvas,
        stage: &Stage,
        what: &str,
        legend: &[(String, Color32)],
        over: impl FnOnce(&Canvas, &SceneTree),
    ) {
        let scene = &stage.scene;
        let Some(tree) = self.tree.get() else {
            return;
        };
        let frame = stage.timeline.shown;
        let empty = Trace::default();
        let trace = self.trace.get().unwrap_or(&empty);
        let shown = trace.shown(frame);
        let current = match trace.frame(frame).first() {
            Some(Step::PrimitiveTested { primitive, .. }) => Some(*primitive),
            _ => None,
        };
        draw_walk(canvas, tree, trace, self.rows(), frame);
        draw_tested_shapes(ui, canvas, &tree.shapes, shown, current);
        draw_tree(
            canvas,
            tree,
            &TreeLook {
                mark_current: false,
                ..TreeLook::default()
            },
        );
        over(canvas, tree);
        // After the lesson's own labels, which come first where they compete for room.
        number_shapes(ui, canvas, &tree.shapes);
        match scene.ray() {
            Ok(ray) => {
                draw_ray(
                    canvas,
                    &ray,
                    crate::trace::closest_so_far(shown).map(|(_, t)| t),
                );
                draw_walk_marks(canvas, &ray, trace, self.rows(), frame);
                canvas.caption(legend);
            }
            Err(_) => canvas.caption(&[(
                "No ray: drag its head away from its origin".to_owned(),
                palette::MISS,
            )]),
        }
        scene.draw_handles(canvas);
        building_note(ui, canvas, self.tree.working_for(), what);
        scene.draw_footer(canvas);
    }
}

/// The most cells along the longer side the slider and the cost curve go to.
pub const MOST_ALONG: u32 = 64;

/// The axes' names, and what their lines are called.
const AXES: [&str; 2] = ["x", "y"];
const LINES: [&str; 2] = ["vertical", "horizontal"];

/// A grid's cells in a lesson: the density rule's, or so many along the longer side, and
/// (hashed) the table's size.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CellChoice {
    /// Cells along the longer side; `None`: the density rule.
    pub along: Option<u32>,
    /// Places of a hashed grid's table; `None`: the default.
    pub places: Option<usize>,
}

impl CellChoice {
    /// The cells as a shared link keeps them: a count along the longer side, or `rule`.
    pub fn cells_value(self) -> (String, String) {
        let value = self
            .along
            .map_or_else(|| "rule".to_owned(), |along| along.to_string());
        ("cells".into(), value)
    }

    /// Reads [`cells_value`](Self::cells_value)'s value back.
    pub fn restore_cells(&mut self, value: &str) -> Result<(), String> {
        self.along = match value {
            "rule" => None,
            count => Some(
                count
                    .parse::<u32>()
                    .ok()
                    .filter(|along| (1..=MOST_ALONG).contains(along))
                    .ok_or_else(|| {
                        format!("cells '{value}' is not 'rule' or a count from 1 to {MOST_ALONG}")
                    })?,
            ),
        };
        Ok(())
    }

    /// As the core's build parameters.
    pub fn params(self) -> GridParams {
        GridParams {
            cells_along_longest: self.along,
            hash_places: self.places,
        }
    }
}

/// The structure a grid lesson builds: the catalogue's grid at the default density.
pub fn grid_structure(hashed: bool) -> Structure {
    let density = DEFAULT_DENSITY as u16;
    if hashed {
        Structure::GridHashed { density }
    } else {
        Structure::GridUniform { density }
    }
}

/// Asks `derived` for the lesson's grid over the scene, with its cells as `choice` says.
fn request_grid(
    derived: &mut Derived<(u64, CellChoice), SceneTree>,
    scene: &crate::editor::EditableScene,
    hashed: bool,
    choice: CellChoice,
) {
    request_over_shapes(derived, scene, choice, move |shapes, settings| {
        SceneTree::build_with(
            grid_structure(hashed),
            shapes,
            settings,
            choice.params(),
            &mut NoBuildObserver,
        )
    });
}

/// The cells along the longer side the density rule gives the shapes.
pub fn rule_along(shapes: &ShapeSet<DVec2>) -> u32 {
    GridCells::for_primitives(shapes.bounding_box(), shapes.shapes.len(), DEFAULT_DENSITY)
        .cells_along_longest()
}

/// One cell the walk passes, with what it did there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkRow {
    /// The cell's node.
    pub node: u32,
    /// Its coordinates, counted from the grid's min corner.
    pub cell: [u32; 3],
    /// The ray's part in it.
    pub t_near: f64,
    /// Where the part ends.
    pub t_far: f64,
    /// Primitives listed in it.
    pub listed: usize,
    /// Primitive tests made in it.
    pub tests: usize,
    /// The `t` to the next line on each axis while the ray is in it (known on entering:
    /// the walk moves them on as it crosses), if the walk steps on from it.
    pub t_next: Option<[f64; 3]>,
    /// The axis whose line it crosses to leave, once it has.
    pub crossed: Option<usize>,
    /// The step of the trace that entered it.
    pub entered_at: usize,
    /// The step that stepped out of it.
    pub stepped_at: Option<usize>,
    /// Places of the hash table read to look it up (a hashed grid).
    pub probes: Option<u32>,
}

/// The cells of `trace` in the order the walk passes them.
fn walk_rows(trace: &Trace, tree: &SceneTree) -> Vec<WalkRow> {
    let mut rows: Vec<WalkRow> = Vec::new();
    let mut probes = None;
    for (index, step) in trace.steps.iter().enumerate() {
        match *step {
            Step::CellLookedUp { probes: read, .. } => probes = Some(read),
            Step::CellEntered {
                node,
                t_near,
                t_far,
            }
            | Step::CellSkipped {
                node,
                t_near,
                t_far,
            } => rows.push(WalkRow {
                node,
                cell: tree.built.grid_coordinates(node).unwrap_or_default(),
                t_near,
                t_far,
                listed: tree.built.facts.leaf_sizes[node as usize] as usize,
                tests: 0,
                t_next: None,
                crossed: None,
                entered_at: index,
                stepped_at: None,
                probes: probes.take(),
            }),
            Step::PrimitiveTested { .. } => {
                if let Some(row) = rows.last_mut() {
                    row.tests += 1;
                }
            }
            Step::GridStepped { axis, t_next } => {
                if let Some(row) = rows.last_mut() {
                    row.t_next = Some(t_next);
                    row.crossed = Some(usize::from(axis));
                    row.stepped_at = Some(index);
                }
            }
            _ => {}
        }
    }
    rows
}

/// A cell's coordinates as the lesson writes them: `(3, 1)`.
pub fn cell_name(cell: [u32; 3]) -> String {
    format!("({}, {})", cell[0], cell[1])
}

/// What step `step` (the `index`th of the trace) does, in words; `rows` are the walk's.
fn describe(step: &Step<f64>, index: usize, rows: &[WalkRow], tree: &SceneTree) -> String {
    let row_at = |index: usize| rows.iter().rev().find(|row| row.entered_at <= index);
    let name = |node: u32| {
        tree.built
            .grid_coordinates(node)
            .map_or_else(|| format!("node {node}"), cell_name)
    };
    match *step {
        Step::BoxTested {
            t_enter,
            t_exit,
            hit,
            ..
        } => {
            if hit {
                format!(
                    "The ray meets the grid's box over t in [{}, {}]: the walk starts in the cell that holds the point where it enters",
                    number(t_enter),
                    number(t_exit)
                )
            } else {
                "The ray misses the grid's box: nothing to walk".to_owned()
            }
        }
        Step::CellEntered {
            node,
            t_near,
            t_far,
        } => {
            let listed = tree.built.facts.leaf_sizes[node as usize] as usize;
            format!(
                "Cell {} (t in [{}, {}]) lists {}: test {}",
                name(node),
                number(t_near),
                number(t_far),
                count_of(listed, "primitive", "primitives"),
                if listed == 1 { "it" } else { "them" }
            )
        }
        Step::CellSkipped {
            node,
            t_near,
            t_far,
        } => format!(
            "Cell {} (t in [{}, {}]) is empty: nothing to test, on to the next",
            name(node),
            number(t_near),
            number(t_far)
        ),
        Step::GridStepped { axis, t_next } => {
            let axis = usize::from(axis).min(1);
            let next = rows.iter().find(|row| row.entered_at > index).map_or_else(
                || "out of the grid".to_owned(),
                |row| format!("into cell {}", cell_name(row.cell)),
            );
            format!(
                "The next vertical line is at t = {}, the next horizontal one at t = {}: the {} line is nearer, so the ray crosses it {next}",
                number(t_next[0]),
                number(t_next[1]),
                LINES[axis]
            )
        }
        Step::PrimitiveTested { primitive, t_hit } => {
            let row = row_at(index);
            let outcome = match (t_hit, row) {
                (Some(t), Some(row)) if t > row.t_far => format!(
                    "hit at t = {}, beyond this cell (it ends at t = {}): kept, but a primitive in a cell before that point could still be nearer, so the walk goes on",
                    number(t),
                    number(row.t_far)
                ),
                (Some(t), _) => format!("hit at t = {}", number(t)),
                (None, _) => "missed".to_owned(),
            };
            format!("Primitive {primitive}: {outcome}")
        }
        Step::PrimitiveSkipped { primitive } => format!(
            "Primitive {primitive} is listed here too, but the mailbox shows it was tested in an earlier cell: not tested again"
        ),
        Step::ClosestHitUpdated { primitive, t } => {
            format!(
                "Closest hit so far: primitive {primitive} at t = {}",
                number(t)
            )
        }
        Step::CellLookedUp { node, probes } => {
            let table = tree.built.hashed_cells();
            let cell = node.saturating_sub(1);
            let home = tree
                .built
                .grid_coordinates(node)
                .zip(table)
                .map(|(coordinates, table)| table.home_of(coordinates));
            let place = table.and_then(|table| table.place_of(cell));
            let reads = count_of(probes as usize, "place", "places");
            match (home, place) {
                (Some(home), Some(place)) if place == home => format!(
                    "Look up cell {}: it hashes to place {home}, and it is there ({reads} read)",
                    name(node)
                ),
                (Some(home), Some(place)) => format!(
                    "Look up cell {}: it hashes to place {home}, taken by another cell (a collision); reading on, it is at place {place} ({reads} read)",
                    name(node)
                ),
                (Some(home), None) => format!(
                    "Look up cell {}: it hashes to place {home}; reading on to an empty place without finding it ({reads} read), so the cell holds nothing",
                    name(node)
                ),
                _ => format!("Look up cell {}: {reads} read", name(node)),
            }
        }
        _ => crate::trace::describe_step(step, name),
    }
}

/// `n` and its noun.
fn count_of(n: usize, one: &str, many: &str) -> String {
    accelviz_core::format::counted(n, one, many)
}

/// Why the walk ended, for its last frame.
fn why_it_stopped(trace: &Trace, rows: &[WalkRow]) -> String {
    let last = rows.last();
    match (trace.hit, last) {
        (_, None) => String::new(),
        (Some(hit), Some(row)) if hit.t <= row.t_far => format!(
            "The closest hit (t = {}) lies inside cell {} (t up to {}): every cell after it lies further along the ray, so nothing there can be nearer. The walk stops.",
            number(hit.t),
            cell_name(row.cell),
            number(row.t_far)
        ),
        _ => "The ray leaves the grid: the walk is over.".to_owned(),
    }
}

/// The caption of frame `frame` of a grid walk: the step in words, and with the last, what
/// the walk did and why it stopped.
fn walk_caption(trace: &Trace, rows: &[WalkRow], tree: &SceneTree, frame: usize) -> String {
    let steps = trace.frame(frame);
    let Some(step) = steps.first() else {
        return if trace.frames() == 0 {
            "No ray to trace.".to_owned()
        } else {
            "Press step: the ray enters the grid's box.".to_owned()
        };
    };
    let index = trace.shown(frame).len() - steps.len();
    let said = describe(step, index, rows, tree);
    if frame < trace.frames() {
        return said;
    }
    let counters = accelviz_core::counters_of(&trace.steps);
    let answer = match trace.hit {
        Some(hit) => format!(
            "the closest hit is primitive {} at t = {}",
            hit.primitive,
            number(hit.t)
        ),
        None => "the ray hits nothing".to_owned(),
    };
    let saved = if counters.mailbox_skips > 0 {
        format!(
            ", {} saved by the mailbox",
            count(counters.mailbox_skips as usize)
        )
    } else {
        String::new()
    };
    format!(
        "{said}. Done: {answer}; {} passed ({} empty), {}{saved}. {}",
        count_of(rows.len(), "cell", "cells"),
        rows.iter().filter(|row| row.listed == 0).count(),
        count_of(
            counters.primitive_tests as usize,
            "primitive test",
            "primitive tests"
        ),
        why_it_stopped(trace, rows)
    )
}

/// The cell sizes a curve measures for `shape_count` shapes: every one from 1 to
/// [`MOST_ALONG`] along the longer side, or every fourth past 16 for a large scene (64 builds
/// of 100,000 shapes would keep the browser, which cannot build aside, busy for seconds).
pub fn measured_sizes(shape_count: usize) -> impl Iterator<Item = u32> {
    let step = if shape_count > 5_000 { 4 } else { 1 };
    (1..=MOST_ALONG).filter(move |&along| along <= 16 || (along - 16) % step == 0)
}

/// The cell-size slider and the density rule's button, for `tree` as built; rewinds
/// `timeline` when the choice changes.
pub fn cells_slider_ui(
    ui: &mut egui::Ui,
    choice: &mut CellChoice,
    tree: Option<&Arc<SceneTree>>,
    timeline: &mut crate::timeline::Timeline,
) {
    let built_along = tree
        .and_then(|tree| tree.built.grid_cells())
        .map_or(1, GridCells::cells_along_longest);
    let mut along = choice.along.unwrap_or(built_along);
    ui.horizontal_wrapped(|ui| {
        if ui
            .add(egui::Slider::new(&mut along, 1..=MOST_ALONG).text("cells along the longer side"))
            .changed()
        {
            choice.along = Some(along);
            timeline.rewind();
        }
        if ui
            .selectable_label(choice.along.is_none(), "density rule")
            .on_hover_text(format!(
                "Cleary & Wyvill's rule, as Ize et al. 2007 state it: n_x = d_x · (K·N / A)^(1/2) cells along each axis of length d_x, for N primitives in a box of area A, about K = {} cells per primitive",
                number(DEFAULT_DENSITY)
            ))
            .clicked()
        {
            choice.along = None;
            timeline.rewind();
        }
    });
}

/// The walk's table: a row per cell passed so far, with the `t` to the next line on each
/// axis (the nearer lit, and the line crossed once the walk crosses it).
fn walk_table_ui(
    ui: &mut egui::Ui,
    trace: &Trace,
    rows: &[WalkRow],
    frame: usize,
    fit_height: bool,
) {
    let shown = trace.shown(frame).len();
    let passed: Vec<&WalkRow> = rows.iter().filter(|row| row.entered_at < shown).collect();
    if passed.is_empty() {
        ui.label("Step to enter the grid.");
        return;
    }
    // The last rows: the walk's present, not its whole past, on a slide.
    let keep = if fit_height { 6 } else { 12 };
    let hidden = passed.len().saturating_sub(keep);
    if hidden > 0 {
        ui.label(
            RichText::new(format!(
                "… {} passed before",
                count_of(hidden, "cell", "cells")
            ))
            .small()
            .weak(),
        );
    }
    let strong = crate::canvas::readable(ui, palette::CURRENT);
    egui::ScrollArea::horizontal()
        .id_salt("grid walk table")
        .show(ui, |ui| {
            egui::Grid::new("grid walk").striped(true).show(ui, |ui| {
                let hashed = passed.iter().any(|row| row.probes.is_some());
                for heading in ["cell", "t in cell", "next x", "next y", "tested"] {
                    ui.strong(heading);
                }
                if hashed {
                    ui.strong("reads");
                }
                ui.end_row();
                for (index, row) in passed.iter().enumerate().skip(hidden) {
                    let current = index + 1 == passed.len();
                    let text = |text: String| {
                        let text = RichText::new(text).monospace();
                        if current { text.color(strong) } else { text }
                    };
                    ui.label(text(cell_name(row.cell)));
                    ui.label(text(format!(
                        "{}–{}",
                        number(row.t_near),
                        number(row.t_far)
                    )));
                    let stepped = row.stepped_at.is_some_and(|at| at < shown);
                    for axis in 0..2 {
                        match row.t_next {
                            Some(t_next) => {
                                let mut cell = text(number(t_next[axis]));
                                if row.crossed == Some(axis) && stepped {
                                    cell = cell.background_color(faded(palette::AXES[axis], 90));
                                }
                                ui.label(cell);
                            }
                            None => {
                                ui.label(text("–".to_owned()));
                            }
                        }
                    }
                    let tests_shown = trace.steps[row.entered_at..shown]
                        .iter()
                        .take_while(|step| !matches!(step, Step::GridStepped { .. }))
                        .filter(|step| matches!(step, Step::PrimitiveTested { .. }))
                        .count();
                    ui.label(text(format!("{tests_shown} of {}", row.listed)));
                    if hashed {
                        ui.label(text(
                            row.probes
                                .map_or_else(String::new, |probes| probes.to_string()),
                        ));
                    }
                    ui.end_row();
                }
            });
        });
    ui.label(
        RichText::new("next x, next y: the t at which the ray reaches the next vertical and horizontal line. The smaller is where it leaves the cell; lit once it crosses.")
            .small()
            .weak(),
    );
    let counters = trace.state(frame).counters;
    ui.label(format!(
        "So far: {} passed ({} empty), {}{}",
        count_of(passed.len(), "cell", "cells"),
        passed.iter().filter(|row| row.listed == 0).count(),
        count_of(
            counters.primitive_tests as usize,
            "primitive test",
            "primitive tests"
        ),
        if counters.mailbox_skips > 0 {
            format!(
                ", {} saved by the mailbox",
                count(counters.mailbox_skips as usize)
            )
        } else {
            String::new()
        }
    ));
}

/// Draws the walk so far on `canvas`: the cells passed (lit where something was listed, faint
/// where empty), the current cell outlined with its coordinates, and on the ray the `t` of
/// the next vertical and horizontal lines from the current cell.
fn draw_walk(canvas: &Canvas, tree: &SceneTree, trace: &Trace, rows: &[WalkRow], frame: usize) {
    let shown = trace.shown(frame).len();
    let passed: Vec<&WalkRow> = rows.iter().filter(|row| row.entered_at < shown).collect();
    for (index, row) in passed.iter().enumerate() {
        let current = index + 1 == passed.len();
        let color = if row.listed > 0 {
            palette::CURRENT
        } else {
            Color32::GRAY
        };
        let fill = faded(color, if current { 70 } else { 35 });
        let stroke = if current {
            Stroke::new(3.5, palette::CURRENT)
        } else {
            Stroke::new(1.0, faded(color, 120))
        };
        node_outline(canvas, tree, row.node, stroke, Some(fill));
    }
}

/// The current cell's name and the ticks of its next lines on the ray.
fn draw_walk_marks(
    canvas: &Canvas,
    ray: &accelviz_core::Ray<DVec2>,
    trace: &Trace,
    rows: &[WalkRow],
    frame: usize,
) {
    let shown = trace.shown(frame).len();
    let Some(row) = rows.iter().rev().find(|row| row.entered_at < shown) else {
        return;
    };
    canvas.label(
        ray.at(0.5 * (row.t_near + row.t_far)),
        &cell_name(row.cell),
        palette::CURRENT,
    );
    if let Some(t_next) = row.t_next {
        for axis in 0..2 {
            canvas.ray_mark_labeled(
                ray.origin,
                ray.direction,
                t_next[axis],
                palette::AXES[axis],
                &format!("next {} line: t = {}", AXES[axis], number(t_next[axis])),
                if axis == 0 { 1.0 } else { -1.0 },
            );
        }
    }
}

/// A plot against the cells along the longer side (1 to [`MOST_ALONG`]), `height` points
/// high, its values called `y_label`; fixed (no drag or zoom: it sits in a scrolled panel).
pub fn cell_size_plot<'a>(id: impl egui::AsIdSalt, height: f32, y_label: &str) -> Plot<'a> {
    Plot::new(id)
        .height(height)
        .default_x_bounds(0.0, f64::from(MOST_ALONG) + 1.0)
        .custom_x_axes(vec![narrow_x_axis("cells along the longer side")])
        .y_axis_label(y_label.to_owned())
        .allow_scroll(false)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_double_click_reset(false)
}

/// The size the lesson shows (`along` cells along the longer side), as a line on a
/// [`cell_size_plot`] whose background is `plot_bg`: white on a dark plot, black on a light
/// one.
pub fn shown_size_line(plot: &mut PlotUi<'_>, along: Option<u32>, plot_bg: Color32) {
    if let Some(along) = along {
        plot.vline(
            VLine::new("shown", f64::from(along))
                .color(shown_size_color(plot_bg))
                .width(1.5),
        );
    }
}

/// The colour of [`shown_size_line`] on `plot_bg`.
pub fn shown_size_color(plot_bg: Color32) -> Color32 {
    crate::canvas::ink_on(Color32::WHITE, plot_bg)
}
