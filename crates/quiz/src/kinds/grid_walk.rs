//! The grid walk (Amanatides & Woo 1987): which cells does the ray pass through, in order?
//! Asked a cell at a time: from the cell the ray is in, which does it enter next, across which
//! line, or does it leave the grid? The student compares the `t` at which the ray reaches the
//! next vertical and the next horizontal line (and the next depth plane in 3D): the walk's
//! `t_next`. The cells are the core's walk, recorded; rays never pass within a pencil's width
//! of a cell corner or edge, where two lines are reached at once.

use accelviz_core::grid::{self, GridCells};
use accelviz_core::{
    Aabb, Query, Ray, Recorder, ShapeSet, Step, TraceOptions, TraversalStacks, Tree, Vector,
};
use glam::{DVec2, DVec3};
use serde_json::json;

use super::Draft;
use crate::generate::{AXES, Gen, Level, num};
use crate::question::{Ask, Choice, Expected, Figure, GridFigure, Highlight};

/// The most steps a question asks (the rest of the walk is shown with the last answer).
const MOST_ASKED: usize = 6;

/// How far from a line, in cells, the ray must be where it crosses another line (or enters
/// the grid, or starts): a tie a pencil cannot tell apart is not asked.
const CLEARANCE: f64 = 0.08;

pub(super) fn generate(generator: &mut Gen) -> Option<Draft> {
    let dimensions = if generator.level == Level::Hard { 3 } else { 2 };
    // The grid: round corners, a few cells of round sizes along each axis.
    let mut cells = [1u32; 3];
    let mut size = [1.0f64; 3];
    let mut min = [0.0f64; 3];
    for axis in 0..dimensions {
        let (count, sizes, offset): (i64, &[f64], i64) = match generator.level {
            Level::Easy => (4, &[1.0, 2.0], 0),
            Level::Medium => (generator.integer(3, 6), &[1.0, 1.5, 2.0, 2.5], 3),
            Level::Hard => (generator.integer(3, 4), &[1.0, 2.0], 3),
        };
        cells[axis] = count as u32;
        size[axis] = sizes[generator.index(sizes.len())];
        if generator.level == Level::Easy && axis == 1 {
            size[1] = size[0];
        }
        min[axis] = generator.integer(-offset, offset) as f64;
    }
    let max: [f64; 3] = std::array::from_fn(|axis| min[axis] + f64::from(cells[axis]) * size[axis]);
    // The ray: from a point around the grid (outside it, mostly) towards a point inside.
    let inside = generator.index(4) == 0 && generator.level != Level::Easy;
    let mut origin = [0.0f64; 3];
    let mut target = [0.0f64; 3];
    for axis in 0..dimensions {
        let margin = if inside { 0.0 } else { 2.0 * size[axis] };
        origin[axis] = generator.coordinate(min[axis] - margin, max[axis] + margin);
        target[axis] = generator.coordinate(min[axis], max[axis]);
    }
    let direction: [f64; 3] =
        std::array::from_fn(|axis| generator.round(target[axis] - origin[axis]));
    if direction[..dimensions].iter().all(|&d| d == 0.0) {
        return None;
    }
    let walk = match dimensions {
        2 => walk_of::<DVec2>(min, max, cells, origin, direction)?,
        _ => walk_of::<DVec3>(min, max, cells, origin, direction)?,
    };
    let longest = if generator.level == Level::Easy {
        7
    } else {
        12
    };
    if !(3..=longest).contains(&walk.len())
        || !clear_of_corners(&walk, &origin, &direction, dimensions, &min, &size, &cells)
    {
        return None;
    }
    let coordinates = |cell: [u32; 3]| -> String {
        let values: Vec<String> = cell[..dimensions].iter().map(|c| c.to_string()).collect();
        format!("({})", values.join(", "))
    };
    let plane = |axis: usize, index: u32| min[axis] + f64::from(index) * size[axis];
    let t_at = |axis: usize, position: f64| (position - origin[axis]) / direction[axis];
    let cell_number = |cell: [u32; 3]| cell[0] + cells[0] * (cell[1] + cells[1] * cell[2]);
    let mut asks = Vec::new();
    for (index, &(cell, t_near, _)) in walk.iter().enumerate().take(MOST_ASKED) {
        // The next line along each axis the ray moves on, and when the ray reaches it.
        let moving: Vec<(usize, f64, f64)> = (0..dimensions)
            .filter(|&axis| direction[axis] != 0.0)
            .map(|axis| {
                let next = if direction[axis] > 0.0 {
                    cell[axis] + 1
                } else {
                    cell[axis]
                };
                let position = plane(axis, next);
                (axis, position, t_at(axis, position))
            })
            .collect();
        let &(first_axis, first_position, t_cross) =
            moving.iter().min_by(|a, b| a.2.total_cmp(&b.2))?;
        let next = walk.get(index + 1).map(|&(cell, _, _)| cell);
        // The options: every neighbour across one of the cell's lines (inside the grid),
        // axis by axis, below then above, and leaving the grid.
        let mut options = Vec::new();
        let mut correct = None;
        for axis in 0..dimensions {
            for step in [-1i64, 1] {
                let moved = i64::from(cell[axis]) + step;
                if !(0..i64::from(cells[axis])).contains(&moved) {
                    continue;
                }
                let mut neighbour = cell;
                neighbour[axis] = moved as u32;
                if Some(neighbour) == next {
                    correct = Some(options.len());
                }
                let line = if step > 0 { cell[axis] + 1 } else { cell[axis] };
                options.push(Choice {
                    label: format!(
                        "cell {}, across {} = {}",
                        coordinates(neighbour),
                        AXES[axis],
                        num(plane(axis, line))
                    ),
                    node: Some(cell_number(neighbour)),
                    shape: None,
                });
            }
        }
        if next.is_none() {
            correct = Some(options.len());
        }
        options.push(Choice::text("none: it leaves the grid"));
        let correct = correct?;
        let bounds: Vec<String> = (0..dimensions)
            .map(|axis| {
                format!(
                    "{} from {} to {}",
                    AXES[axis],
                    num(plane(axis, cell[axis])),
                    num(plane(axis, cell[axis] + 1))
                )
            })
            .collect();
        let entered = if index == 0 {
            if t_near > 0.0 {
                format!("enters the grid in cell {}", coordinates(cell))
            } else {
                format!("starts in cell {}", coordinates(cell))
            }
        } else {
            format!("is in cell {}", coordinates(cell))
        };
        let reaches: Vec<String> = moving
            .iter()
            .map(|&(axis, position, t)| {
                // A negative number in parentheses, where it follows a sign or divides.
                let term = |value: f64| match value < 0.0 {
                    true => format!("({})", num(value)),
                    false => num(value),
                };
                format!(
                    "{} = {} at t = ({} − {}) / {} = {}",
                    AXES[axis],
                    num(position),
                    num(position),
                    term(origin[axis]),
                    term(direction[axis]),
                    num(t)
                )
            })
            .collect();
        let outcome = match next {
            Some(next) => format!(
                "so it crosses into cell {} at t = {}",
                coordinates(next),
                num(t_cross)
            ),
            None => format!(
                "the grid's side: it leaves the grid at t = {}",
                num(t_cross)
            ),
        };
        asks.push(Ask {
            prompt: format!(
                "The ray {entered} ({}) at t = {}. Which cell does it enter next?",
                bounds.join(", "),
                num(t_near.max(0.0))
            ),
            expected: Expected::Choice { options, correct },
            explanation: format!(
                "The ray o + t·d reaches the next line on each axis: {}. The first is {} = {}, {outcome}.",
                reaches.join("; "),
                AXES[first_axis],
                num(first_position)
            ),
            highlight: Highlight {
                nodes: next.map(cell_number).into_iter().collect(),
                axis: Some(first_axis),
                t: Some(t_cross),
                t_label: format!("{} = {}, t = {}", AXES[first_axis], num(first_position), num(t_cross)),
                frame: Some(index + 2),
                ..Highlight::default()
            },
            frame: index + 1,
            needs: [
                origin[..dimensions].to_vec(),
                direction[..dimensions].to_vec(),
                moving.iter().map(|&(_, position, _)| position).collect(),
            ]
            .concat(),
        });
    }
    let walked: Vec<[u32; 3]> = walk.iter().map(|&(cell, _, _)| cell).collect();
    let answer: Vec<Vec<u32>> = walked
        .iter()
        .map(|cell| cell[..dimensions].to_vec())
        .collect();
    let corner = |values: &[f64; 3]| values[..dimensions].to_vec();
    Some(Draft {
        prompt: format!(
            "A uniform grid of {} cells and a ray o + t·d: which cells does the ray pass through, in order? Compare when it reaches the next line on each axis.",
            cells[..dimensions]
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(" × ")
        ),
        figure: Figure::Grid(Box::new(GridFigure {
            min: corner(&min),
            max: corner(&max),
            cells: cells[..dimensions].to_vec(),
            origin: corner(&origin),
            direction: corner(&direction),
            walked,
            parts: walk
                .iter()
                .map(|&(_, t_near, t_far)| (t_near, t_far))
                .collect(),
        })),
        asks,
        fields: [
            (
                "grid".to_owned(),
                json!({"min": corner(&min), "max": corner(&max), "cells": cells[..dimensions]}),
            ),
            (
                "ray".to_owned(),
                json!({"origin": corner(&origin), "direction": corner(&direction)}),
            ),
        ]
        .into_iter()
        .collect(),
        answer: json!({ "cells": answer }),
    })
}

/// The cells the core's grid walk passes, with the ray's part of each, from where the ray
/// enters the grid (or starts in it) until it leaves: the walk over a grid that lists
/// nothing, so nothing stops it. `None` when the ray misses the grid.
fn walk_of<V: Vector>(
    min: [f64; 3],
    max: [f64; 3],
    cells: [u32; 3],
    origin: [f64; 3],
    direction: [f64; 3],
) -> Option<Vec<([u32; 3], f64, f64)>> {
    let bounds = Aabb::new(V::from_f64_slice(&min), V::from_f64_slice(&max));
    let empty = ShapeSet::<V> { shapes: Vec::new() };
    let grid = grid::build_with_cells(&empty, GridCells::with_resolution(bounds, cells));
    let ray = Ray::try_new(V::from_f64_slice(&origin), V::from_f64_slice(&direction)).ok()?;
    let options = TraceOptions {
        query: Query::Closest,
        ..TraceOptions::default()
    };
    let mut recorder = Recorder::default();
    let cells_of = grid.cells.clone();
    Tree::Grid(grid).trace(
        &empty,
        &ray,
        &options,
        &mut TraversalStacks::default(),
        &mut recorder,
    );
    let walk: Vec<([u32; 3], f64, f64)> = recorder
        .steps
        .iter()
        .filter_map(|step| match *step {
            Step::CellEntered {
                node,
                t_near,
                t_far,
            }
            | Step::CellSkipped {
                node,
                t_near,
                t_far,
            } => {
                use accelviz_core::Real;
                Some((
                    cells_of.coordinates(node - 1),
                    t_near.to_f64(),
                    t_far.to_f64(),
                ))
            }
            _ => None,
        })
        .collect();
    (!walk.is_empty()).then_some(walk)
}

/// Whether the ray keeps clear of every cell corner and edge: where it starts, where it
/// enters the grid and wherever it crosses a line, its other coordinates lie at least
/// [`CLEARANCE`] of a cell from every line of theirs (and its start is not on a line).
fn clear_of_corners(
    walk: &[([u32; 3], f64, f64)],
    origin: &[f64; 3],
    direction: &[f64; 3],
    dimensions: usize,
    min: &[f64; 3],
    size: &[f64; 3],
    cells: &[u32; 3],
) -> bool {
    // The distance, in cells, from `value` to the nearest line of `axis` (the grid's sides
    // included).
    let off_lines = |axis: usize, value: f64| {
        let at = (value - min[axis]) / size[axis];
        let nearest = at.round().clamp(0.0, f64::from(cells[axis]));
        (at - nearest).abs()
    };
    let point =
        |t: f64| -> [f64; 3] { std::array::from_fn(|axis| origin[axis] + t * direction[axis]) };
    // Each cell's start, and the last cell's end: every place the ray crosses a line.
    let mut crossings: Vec<f64> = walk.iter().map(|&(_, t_near, _)| t_near).collect();
    crossings.extend(walk.last().map(|&(_, _, t_far)| t_far));
    crossings.iter().all(|&t| {
        let at = point(t.max(0.0));
        // The line crossed there is the one the point lies on; every other must be clear.
        let on: Vec<usize> = (0..dimensions)
            .filter(|&axis| off_lines(axis, at[axis]) < 1e-9)
            .collect();
        let starts_inside = t <= 0.0;
        match (starts_inside, on.len()) {
            (true, 0) => (0..dimensions).all(|axis| off_lines(axis, at[axis]) >= CLEARANCE),
            (false, 1) => (0..dimensions)
                .filter(|axis| !on.contains(axis))
                .all(|axis| off_lines(axis, at[axis]) >= CLEARANCE),
            _ => false,
        }
    })
}
