//! Lesson 19, "Hashing": the lecture's "this is related to issues of hashing & indexing in
//! tables" made concrete. The uniform grid of lesson 18 keeps only the cells that hold
//! something, in a hash table (Teschner et al. 2003): each cell's place is computed from its
//! coordinates, a taken place sends it on to the next free one (linear probing), and a lookup
//! reads from the home place on until it finds the cell or an empty place. The canvas labels
//! each cell with its place, collisions in red; the table is drawn place by place with the
//! current lookup's reads; memory is weighed against the dense grid at every cell size, and
//! the walk (the core's, with its lookups) steps through as in lesson 18.

use std::sync::Arc;

use accelviz_core::format::{count, number};
use accelviz_core::grid::{Bucket, GridCells, HashedCells};
use accelviz_core::quality::Footprint;
use accelviz_core::{NoBuildObserver, ShapeSet, Step};
use accelviz_scene::document::SceneSettings;
use egui::{Align2, Color32, Rect, RichText, Sense, Stroke, StrokeKind, Vec2};
use egui_plot::{Legend, Line, LineStyle, PlotPoints, VLine};
use glam::DVec2;

use crate::background::{Cached, Derived};
use crate::canvas::{Canvas, faded, palette};
use crate::editor::Editing;
use crate::lesson::{self, Lesson, Parts};
use crate::lesson_file::LessonText;
use crate::stage::{SceneTree, Stage};
use crate::trace::Trace;
use crate::views::grid_walk::{
    CellChoice, GridWalk, MOST_ALONG, WalkRow, cell_name, cell_size_plot, cells_slider_ui,
    grid_structure, measured_sizes, shown_size_line,
};
use crate::views::tree_view::{node_outline, node_under};

/// Cells along the longer side the lesson opens with: fine enough that most cells are
/// empty, which is when a hash table pays.
pub const START_ALONG: u32 = 10;

/// The inspector's parts a lecture slide can name.
const TABLE_PART: lesson::Part =
    lesson::Part::new("table", "the cell size, the table's size and its places");
const NUMBERS_PART: lesson::Part =
    lesson::Part::new("numbers", "load, collisions, reads a lookup and memory");
const WALK_PART: lesson::Part =
    lesson::Part::new("walk", "the walk's cells with the places each lookup read");
const MEMORY_PART: lesson::Part = lesson::Part::new(
    "memory",
    "bytes of the dense and the hashed grid at every cell size",
);
const PARTS: [lesson::Part; 4] = [TABLE_PART, NUMBERS_PART, WALK_PART, MEMORY_PART];

/// The colour of a cell in its home place, and of one a collision moved on.
const AT_HOME: Color32 = palette::BOX;
const MOVED_ON: Color32 = palette::MISS;

/// Bytes of the dense and the hashed grid at one cell size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryPoint {
    /// Cells along the longer side.
    pub along: u32,
    /// All cells.
    pub cells: usize,
    /// Cells holding something.
    pub occupied: usize,
    /// The dense grid's bytes.
    pub dense_bytes: usize,
    /// The hashed grid's bytes (its default table).
    pub hashed_bytes: usize,
}

/// Memory at every cell size from 1 to [`MOST_ALONG`] along the longer side.
#[derive(Clone, Debug, PartialEq)]
pub struct MemoryCurve {
    /// One point per size measured ([`measured_sizes`]).
    pub points: Vec<MemoryPoint>,
}

impl MemoryCurve {
    /// Builds the hashed grid at every size over `shapes` and weighs it.
    pub fn measure(shapes: Arc<ShapeSet<DVec2>>, settings: SceneSettings) -> Self {
        let points = measured_sizes(shapes.shapes.len())
            .filter_map(|along| {
                let tree = SceneTree::build_with(
                    grid_structure(true),
                    shapes.clone(),
                    settings,
                    CellChoice {
                        along: Some(along),
                        places: None,
                    }
                    .params(),
                    &mut NoBuildObserver,
                );
                let numbers = TableNumbers::of(&tree)?;
                Some(MemoryPoint {
                    along,
                    cells: numbers.cells,
                    occupied: numbers.occupied,
                    dense_bytes: numbers.dense_bytes,
                    hashed_bytes: numbers.hashed_bytes,
                })
            })
            .collect();
        Self { points }
    }

    /// The fewest cells along the longer side from which the hash table takes less memory
    /// than the dense grid, and stays so at every finer size measured.
    pub fn hashing_pays_from(&self) -> Option<u32> {
        let last_dearer = self
            .points
            .iter()
            .rposition(|point| point.hashed_bytes >= point.dense_bytes);
        match last_dearer {
            None => self.points.first().map(|point| point.along),
            Some(index) => self.points.get(index + 1).map(|point| point.along),
        }
    }
}

/// The table's numbers, worked out once a grid (reading every cell's lookup is no work for
/// every frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableNumbers {
    /// All cells.
    pub cells: usize,
    /// Cells the table holds.
    pub occupied: usize,
    /// The table's places.
    pub places: usize,
    /// Cells that found their own place taken.
    pub collisions: usize,
    /// Places a lookup reads, on average: for a cell held, for an empty one.
    pub probes: (f64, f64),
    /// The hashed grid's bytes.
    pub hashed_bytes: usize,
    /// The same lists' bytes in a dense grid.
    pub dense_bytes: usize,
}

impl TableNumbers {
    /// The numbers of `tree`, if it is a hashed grid.
    pub fn of(tree: &SceneTree) -> Option<Self> {
        let accelviz_core::Tree::HashedGrid(grid) = &tree.built.tree else {
            return None;
        };
        let cells = grid.cells.cell_count();
        Some(Self {
            cells,
            occupied: grid.store.occupied(),
            places: grid.store.buckets.len(),
            collisions: grid.store.collisions,
            probes: grid.store.probes_per_lookup(cells),
            hashed_bytes: Footprint::of(&tree.built.tree).bytes,
            dense_bytes: grid.dense_bytes(),
        })
    }
}

/// The current lookup: the cell, its home place, the place where it stopped reading, and
/// whether it found the cell there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lookup {
    /// The cell's number.
    pub cell: u32,
    /// The place it hashes to.
    pub home: usize,
    /// The last place read.
    pub last: usize,
    /// Whether the cell was found there.
    pub found: bool,
}

/// The lookup the current frame makes (from the core's step), read against the table.
pub fn current_lookup(tree: &SceneTree, step: Option<&Step<f64>>) -> Option<Lookup> {
    let Some(Step::CellLookedUp { node, probes }) = step else {
        return None;
    };
    let table = tree.built.hashed_cells()?;
    let coordinates = tree.built.grid_coordinates(*node)?;
    let cell = node - 1;
    let home = table.home_of(coordinates);
    let places = table.buckets.len();
    let last = (home + *probes as usize - 1) % places;
    Some(Lookup {
        cell,
        home,
        last,
        found: table.buckets[last].cell == cell,
    })
}

/// The lesson.
pub struct HashLesson {
    stage: Stage,
    choice: CellChoice,
    mailboxing: bool,
    walk: GridWalk,
    numbers: Cached<u64, Option<TableNumbers>>,
    memory: Derived<(u64, ()), MemoryCurve>,
    /// The cell under the pointer (on the canvas or in the table).
    hovered_cell: Option<u32>,
}

impl HashLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::ALL),
            choice: CellChoice {
                along: Some(START_ALONG),
                places: None,
            },
            mailboxing: true,
            walk: GridWalk::default(),
            numbers: Cached::default(),
            memory: Derived::default(),
            hovered_cell: None,
        }
    }

    /// The hashed grid shown.
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

    /// Memory at every cell size, once weighed.
    pub fn memory(&self) -> Option<&Arc<MemoryCurve>> {
        self.memory.get()
    }

    /// Chooses the cells and the table's places (`None`: the density rule, the default size).
    pub fn choose(&mut self, choice: CellChoice) {
        self.choice = choice;
        self.stage.timeline.rewind();
    }

    /// The lookup the current frame makes.
    pub fn lookup(&self) -> Option<Lookup> {
        let trace = self.walk.trace()?;
        current_lookup(
            self.walk.tree()?,
            trace.frame(self.stage.timeline.shown).first(),
        )
    }

    fn table_ui(&mut self, ui: &mut egui::Ui) {
        self.stage.presets_ui(ui, "Scenes:");
        cells_slider_ui(
            ui,
            &mut self.choice,
            self.walk.tree(),
            &mut self.stage.timeline,
        );
        let Some(tree) = self.walk.tree().cloned() else {
            return;
        };
        let Some(table) = tree.built.hashed_cells() else {
            return;
        };
        let occupied = self
            .numbers
            .get()
            .copied()
            .flatten()
            .map_or_else(|| table.occupied(), |numbers| numbers.occupied);
        let default_places = HashedCells::default_places(occupied);
        let mut places = self.choice.places.unwrap_or(table.buckets.len());
        let most = (4 * default_places).max(occupied + 2);
        ui.horizontal_wrapped(|ui| {
            if ui
                .add(egui::Slider::new(&mut places, occupied + 1..=most).text("places in the table"))
                .changed()
            {
                self.choice.places = Some(places);
                self.stage.timeline.rewind();
            }
            if ui
                .selectable_label(self.choice.places.is_none(), "twice the cells, a power of two")
                .on_hover_text("The default: the smallest power of two at least twice the occupied cells, so the table is at most half full, and a power of two takes a mask instead of a division")
                .clicked()
            {
                self.choice.places = None;
                self.stage.timeline.rewind();
            }
        });
        let lit = self.lookup();
        let hovered = buckets_ui(ui, &tree, table, lit, self.hovered_cell);
        if hovered.is_some() {
            self.hovered_cell = hovered;
        }
        ui.label(
            RichText::new("Each place holds a cell (its coordinates) or nothing. Blue: the cell is in the place it hashes to; red: that place was taken, so it moved on to the next free one. Outlined: the places the current lookup reads.")
                .small()
                .weak(),
        );
    }

    fn numbers_ui(&self, ui: &mut egui::Ui) {
        let Some(TableNumbers {
            cells: cell_count,
            occupied,
            places,
            collisions,
            probes: (found, absent),
            hashed_bytes,
            dense_bytes,
        }) = self.numbers.get().copied().flatten()
        else {
            return;
        };
        egui::Grid::new("hash numbers").striped(true).show(ui, |ui| {
            let mut row = |name: &str, value: String, hover: &str| {
                ui.label(name).on_hover_text(hover);
                ui.label(value);
                ui.end_row();
            };
            row(
                "cells holding something",
                format!(
                    "{} of {} ({:.0} %)",
                    count(occupied),
                    count(cell_count),
                    100.0 * occupied as f64 / cell_count.max(1) as f64
                ),
                "Only these go in the table: memory follows what the scene fills, not its box.",
            );
            row(
                "load",
                format!(
                    "{} of {} places ({:.0} %)",
                    count(occupied),
                    count(places),
                    100.0 * occupied as f64 / places.max(1) as f64
                ),
                "The share of places taken: the fuller the table, the longer the runs of taken places a lookup reads through.",
            );
            row(
                "collisions",
                count(collisions),
                "Cells whose own place was taken when they were put in: they moved on to the next free place.",
            );
            row(
                "places a lookup reads",
                format!("{} held, {} empty (dense: 1)", number(found), number(absent)),
                "Averaged over every cell of the grid. Linear probing reads about (1 + 1/(1 − α))/2 places for a cell held and (1 + 1/(1 − α)²)/2 for one absent, at load α (Knuth 1998, §6.4).",
            );
            row(
                "memory",
                format!(
                    "{} B; dense {} B ({:.2}×)",
                    count(hashed_bytes),
                    count(dense_bytes),
                    hashed_bytes as f64 / dense_bytes.max(1) as f64
                ),
                "Hashed: 12 bytes a place (the cell, where its list starts, how long it is) and 4 a reference. Dense: 4 bytes a cell (where its list starts) and 4 a reference.",
            );
        });
    }

    fn walk_ui(&self, ui: &mut egui::Ui, fit_height: bool) {
        let frame = self.stage.timeline.shown;
        self.walk
            .table_ui(ui, "The walk, with its lookups", frame, fit_height);
        let reads: u32 = self.rows().iter().filter_map(|row| row.probes).sum();
        ui.label(format!(
            "This ray: {} looked up, {} read in all.",
            count_of(self.rows().len(), "cell", "cells"),
            count_of(reads as usize, "place", "places")
        ));
    }

    fn memory_ui(&self, ui: &mut egui::Ui) {
        ui.heading("Memory against the cell size");
        let Some(curve) = self.memory.get() else {
            ui.label("Weighing…");
            return;
        };
        let dense: PlotPoints = (curve.points.iter())
            .map(|point| [f64::from(point.along), point.dense_bytes as f64 / 1024.0])
            .collect();
        let hashed: PlotPoints = (curve.points.iter())
            .map(|point| [f64::from(point.along), point.hashed_bytes as f64 / 1024.0])
            .collect();
        let current = self
            .walk
            .tree()
            .and_then(|tree| tree.built.grid_cells())
            .map(GridCells::cells_along_longest);
        let height = 200.0;
        let plot_bg = ui.visuals().extreme_bg_color;
        cell_size_plot("hash memory", height, "KiB")
            .legend(Legend::default().position(egui_plot::Corner::LeftTop))
            .include_y(0.0)
            .show(ui, |plot| {
                plot.line(
                    Line::new("dense grid", dense)
                        .color(crate::canvas::ink_on(palette::X_AXIS, plot_bg))
                        .width(2.0),
                );
                plot.line(
                    Line::new("hashed grid", hashed)
                        .color(crate::canvas::ink_on(palette::CURRENT, plot_bg))
                        .width(2.0),
                );
                if let Some(from) = curve.hashing_pays_from() {
                    plot.vline(
                        VLine::new("hashing pays from here", f64::from(from))
                            .color(crate::canvas::ink_on(palette::HIT, plot_bg))
                            .style(LineStyle::dashed_dense()),
                    );
                }
                shown_size_line(plot, current, plot_bg);
            });
        let pays_from = curve
            .hashing_pays_from()
            .and_then(|from| curve.points.iter().find(|point| point.along == from));
        let verdict = match pays_from {
            Some(point) => format!(
                "From {} cells along the longer side the table is smaller: there {} of {} cells hold something ({:.0} %). A place costs three times a dense cell, so hashing pays once fewer than about one cell in six is filled (at a load of a half).",
                point.along,
                count(point.occupied),
                count(point.cells),
                100.0 * point.occupied as f64 / point.cells.max(1) as f64
            ),
            None => "At no size measured is the table smaller than the dense grid: the scene fills too many of its cells.".to_owned(),
        };
        ui.label(RichText::new(verdict).small());
    }
}

/// `n` and its noun.
fn count_of(n: usize, one: &str, many: &str) -> String {
    accelviz_core::format::counted(n, one, many)
}

/// Draws the table place by place: each place a square holding its cell's coordinates (where
/// they fit), blue when the cell is at home, red when a collision moved it on, empty places
/// dark; the current lookup's reads outlined, its last place thick (green found, red empty);
/// the hovered cell's place lit. Returns the cell whose place is under the pointer.
pub fn buckets_ui(
    ui: &mut egui::Ui,
    tree: &SceneTree,
    table: &HashedCells,
    lookup: Option<Lookup>,
    hovered: Option<u32>,
) -> Option<u32> {
    let places = table.buckets.len();
    let width = ui.available_width().max(120.0);
    let size = (width / 12.0).clamp(14.0, 44.0);
    let columns = ((width / size).floor() as usize).max(1);
    let rows = places.div_ceil(columns);
    let (rect, response) =
        ui.allocate_exact_size(Vec2::new(width, rows as f32 * size), Sense::hover());
    let painter = ui.painter_at(rect);
    let font = crate::canvas::font(ui.ctx(), if size >= 36.0 { 11.0 } else { 9.0 });
    let text_color = ui.visuals().strong_text_color();
    let reads: Vec<usize> = lookup.map_or_else(Vec::new, |lookup| {
        let mut place = lookup.home;
        let mut read = vec![place];
        while place != lookup.last {
            place = (place + 1) % places;
            read.push(place);
        }
        read
    });
    let mut under = None;
    let cells = tree.built.grid_cells();
    for (place, bucket) in table.buckets.iter().enumerate() {
        let (row, column) = (place / columns, place % columns);
        let square = Rect::from_min_size(
            rect.min + Vec2::new(column as f32 * size, row as f32 * size),
            Vec2::splat(size),
        )
        .shrink(1.5);
        let stored = bucket.cell != Bucket::EMPTY;
        let at_home = stored && table.home(bucket.cell) == place;
        let fill = match (stored, at_home) {
            (false, _) => ui.visuals().extreme_bg_color,
            (true, true) => faded(AT_HOME, 110),
            (true, false) => faded(MOVED_ON, 130),
        };
        painter.rect_filled(square, 2.0, fill);
        if stored && hovered == Some(bucket.cell) {
            painter.rect_stroke(
                square,
                2.0,
                Stroke::new(3.0, Color32::WHITE),
                StrokeKind::Inside,
            );
        }
        if let Some(at) = reads.iter().position(|&read| read == place) {
            let last = at + 1 == reads.len();
            let stroke = match (last, lookup.is_some_and(|lookup| lookup.found)) {
                (false, _) => Stroke::new(2.0, palette::CURRENT),
                (true, true) => Stroke::new(3.5, palette::HIT),
                (true, false) => Stroke::new(3.5, palette::MISS),
            };
            painter.rect_stroke(square, 2.0, stroke, StrokeKind::Inside);
        }
        if stored
            && size >= 30.0
            && let Some(cells) = cells
        {
            let [x, y, _] = cells.coordinates(bucket.cell);
            painter.text(
                square.center(),
                Align2::CENTER_CENTER,
                format!("{x},{y}"),
                font.clone(),
                text_color,
            );
        }
        if response.hover_pos().is_some_and(|pos| square.contains(pos)) {
            under = stored.then_some(bucket.cell);
            let text = match (stored, cells) {
                (true, Some(cells)) => format!(
                    "place {place}: cell {}, {} listed; {}",
                    cell_name(cells.coordinates(bucket.cell)),
                    bucket.count,
                    if at_home {
                        "its own place".to_owned()
                    } else {
                        format!(
                            "it hashes to place {}, which was taken",
                            table.home(bucket.cell)
                        )
                    }
                ),
                _ => format!("place {place}: empty"),
            };
            response.clone().on_hover_text_at_pointer(text);
        }
    }
    under
}

/// Labels each occupied cell on the canvas with its place (red where a collision moved it on),
/// where the cells are large enough to hold a label.
fn draw_places(canvas: &Canvas, tree: &SceneTree, table: &HashedCells) {
    let Some(cells) = tree.built.grid_cells() else {
        return;
    };
    for (place, bucket) in table.buckets.iter().enumerate() {
        if bucket.cell == Bucket::EMPTY {
            continue;
        }
        let bounds = cells.cell_bounds(cells.coordinates(bucket.cell));
        let rect = canvas.screen_rect(&bounds);
        let at_home = table.home(bucket.cell) == place;
        let color = if at_home { AT_HOME } else { MOVED_ON };
        if !at_home {
            canvas.painter.rect_stroke(
                rect.shrink(2.0),
                0.0,
                Stroke::new(2.0, faded(MOVED_ON, 200)),
                StrokeKind::Inside,
            );
        }
        // Inside its cell, on a plate over the shapes there, where no other label is; in a
        // cell too small for it, none (at lecture size the names overwrote each other).
        let text = if at_home {
            format!("#{place}")
        } else {
            format!("#{}->{place}", table.home(bucket.cell))
        };
        canvas.box_label(rect, false, &text, color);
    }
}

impl Lesson for HashLesson {
    crate::staged!(walk, memory);

    fn share(&self) -> Vec<(String, String)> {
        let places = self
            .choice
            .places
            .map_or_else(|| "default".to_owned(), |places| places.to_string());
        vec![self.choice.cells_value(), ("places".into(), places)]
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        match key {
            "cells" => self.choice.restore_cells(value),
            "places" => {
                self.choice.places = match value {
                    "default" => None,
                    places => Some(
                        places
                            .parse::<usize>()
                            .ok()
                            .filter(|&places| (1..=1 << 20).contains(&places))
                            .ok_or_else(|| {
                                format!("places '{value}' is not 'default' or a count of places")
                            })?,
                    ),
                };
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
        self.walk
            .update(&mut self.stage, true, self.choice, self.mailboxing);
        let scene = &self.stage.scene;
        // Built at every size: as much work as that many builds of the scene.
        self.memory.request(
            &(scene.shapes_revision, ()),
            scene.scene.shapes.shapes.len() * MOST_ALONG as usize,
            || {
                let shapes = Arc::new(scene.scene.shapes.clone());
                let settings = scene.scene.settings;
                move || MemoryCurve::measure(shapes, settings)
            },
        );
        let generation = self.walk.generation();
        let tree = self.walk.tree().cloned();
        self.numbers
            .get_or_make(generation, || tree.as_deref().and_then(TableNumbers::of));
        let cells = (self.walk.tree())
            .and_then(|tree| tree.built.grid_cells())
            .map_or(0, |cells| cells.cell_count()) as u32;
        self.hovered_cell = self.hovered_cell.filter(|&cell| cell < cells);
    }

    fn caption(&self) -> Option<String> {
        self.walk.caption(self.stage.timeline.shown)
    }

    fn parts(&self) -> &'static [lesson::Part] {
        &PARTS
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, parts: Parts<'_>) {
        if parts.show(&TABLE_PART) {
            self.table_ui(ui);
        }
        if parts.show(&NUMBERS_PART) {
            ui.separator();
            self.numbers_ui(ui);
        }
        if parts.show(&WALK_PART) {
            ui.separator();
            self.walk_ui(ui, parts.fit_screen());
        }
        if parts.show(&MEMORY_PART) {
            ui.separator();
            self.memory_ui(ui);
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let canvas = self.stage.scene.canvas_ui(ui, None);
        if canvas.response.hovered()
            && let Some(tree) = self.walk.tree()
        {
            self.hovered_cell = canvas
                .response
                .hover_pos()
                .and_then(|pos| node_under(&canvas, tree, pos, &(0..=usize::MAX)))
                .and_then(|node| node.checked_sub(1));
        }
        let legend = [
            ("#5: the cell's place in the table".to_owned(), AT_HOME),
            (
                "#3->5: its place 3 was taken, it moved on to 5".to_owned(),
                MOVED_ON,
            ),
        ];
        let (lookup, hovered) = (self.lookup(), self.hovered_cell);
        self.walk.draw(
            ui,
            &canvas,
            &self.stage,
            "the table",
            &legend,
            |canvas, tree| {
                if let Some(table) = tree.built.hashed_cells() {
                    draw_places(canvas, tree, table);
                }
                for (cell, stroke) in [
                    (
                        lookup.map(|lookup| lookup.cell),
                        Stroke::new(4.0, palette::CURRENT),
                    ),
                    (hovered, Stroke::new(3.0, Color32::WHITE)),
                ] {
                    if let Some(cell) = cell {
                        node_outline(canvas, tree, cell + 1, stroke, None);
                    }
                }
            },
        );
        canvas.finish();
    }
}
