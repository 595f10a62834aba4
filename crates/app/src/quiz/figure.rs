//! A question's figure on the canvas, with the shared drawings the lessons use: the slab
//! test's box, planes and intervals; a scene with its tree and the traversal paused at the
//! step asked about (nodes not yet reached hidden when the question says so); a node's
//! candidate splits, lettered as the choices are; a tree being built. A click on a node, a
//! shape or a split picks the option that names it.

use std::sync::Arc;

use accelviz_core::{Aabb, Ray, ShapeSet, Step, TreeFacts, slab_record};
use accelviz_quiz::{Ask, BuildExercise, Figure, Highlight, Pick, Question, option_letter};
use egui::{Color32, Stroke, Ui, Vec2};
use glam::{DVec2, DVec3};

use crate::canvas::{Canvas, View2d, faded, palette, readable_on};
use crate::stage::SceneTree;
use crate::views::number_lines::{IntervalRow, number_lines_height, number_lines_ui};
use crate::views::scene_view::{draw_ray_colored, draw_tested_shapes};
use crate::views::tree_view::{TreeLook, draw_tree, light, node_outline, node_rect};

/// What the figure shows this frame.
pub struct FigureState<'a> {
    /// The question.
    pub question: &'a Question,
    /// The step asked (or reviewed).
    pub ask: Option<&'a Ask>,
    /// Whether the step's answer is shown: its highlight is drawn.
    pub revealed: bool,
    /// How many recorded traversal steps are shown (while asking, the step's own frame; once
    /// answered, its highlight's; in a review, where the student has stepped to).
    pub frame: usize,
    /// The tree being built, for a build question.
    pub exercise: Option<&'a BuildExercise>,
    /// The question's tree, wrapped for the shared tree drawing.
    pub tree: Option<&'a SceneTree>,
    /// The option the student picked, once answered (a wrong one is marked in the figure).
    pub picked: Option<usize>,
}

/// The question's tree as the shared drawing wants it.
pub fn scene_tree(question: &Question) -> Option<SceneTree> {
    let Figure::Scene(scene) = &question.figure else {
        return None;
    };
    let tree = scene.tree.as_ref()?;
    let settings = accelviz_scene::document::SceneSettings::default();
    let stats = tree.built.stats(0, &accelviz_core::SahCost::default());
    Some(SceneTree {
        shapes: Arc::new(scene.shapes.clone()),
        settings,
        built: tree.built.clone(),
        stats,
        build_millis: 0.0,
        id: crate::stage::next_tree_id(),
    })
}

/// The world every quiz scene lies in (shapes in [0, 20]², rays from just outside).
fn scene_bounds() -> Aabb<DVec2> {
    Aabb::new(DVec2::splat(-1.5), DVec2::splat(21.5))
}

/// Draws the figure; returns the option a click picked, if any.
pub fn figure_ui(
    ui: &mut Ui,
    view: &mut View2d,
    view3d: &mut crate::view3d::View3d,
    state: &FigureState,
) -> Option<usize> {
    match &state.question.figure {
        Figure::Slab {
            min,
            max,
            origin,
            direction,
        } => {
            slab_ui(ui, view, view3d, state, min, max, origin, direction);
            None
        }
        Figure::Scene(scene) => {
            let canvas = Canvas::allocate(ui, ui.available_size(), view, &scene_bounds(), true);
            let picked = scene_ui(ui, &canvas, state, scene);
            canvas.finish();
            picked
        }
        Figure::Build(_) => {
            let canvas = Canvas::allocate(ui, ui.available_size(), view, &scene_bounds(), true);
            let picked = state
                .exercise
                .and_then(|exercise| build_ui(ui, &canvas, state, exercise));
            canvas.finish();
            picked
        }
        Figure::Crack(crack) => {
            let canvas = Canvas::allocate(ui, ui.available_size(), view, &scene_bounds(), true);
            crack_ui(&canvas, state, crack);
            canvas.finish();
            None
        }
        Figure::Grid(grid) => grid_ui(ui, view, view3d, state, grid),
    }
}

/// The grid walk: the grid with every cell's coordinates, the ray, the cells passed so far
/// (the one the ray is in lit), and once answered the next cell and the line crossed into it.
/// A click on a cell picks the option that names it. In 3D, the grid's cells as boxes in the
/// 3D view, the cells passed lit.
fn grid_ui(
    ui: &mut Ui,
    view: &mut View2d,
    view3d: &mut crate::view3d::View3d,
    state: &FigureState,
    grid: &accelviz_quiz::GridFigure,
) -> Option<usize> {
    let lit = highlight(state);
    let shown = state.frame.min(grid.walked.len());
    let passed = &grid.walked[..shown];
    let reach = grid.parts.last().map_or(1.0, |&(_, t_far)| t_far) + 0.5;
    if grid.min.len() == 3 {
        grid_3d_ui(ui, view3d, lit, grid, passed, reach);
        return None;
    }
    let point = |values: &[f64]| DVec2::new(values[0], values[1]);
    let (low, high) = (point(&grid.min), point(&grid.max));
    let (o, d) = (point(&grid.origin), point(&grid.direction));
    let bounds = Aabb::new(low, high);
    let fit = bounds.union(Aabb::from_points([o, o + d * reach]));
    let margin = DVec2::splat(0.05 * fit.extent().max_element().max(1.0));
    let fit = Aabb::new(fit.min - margin, fit.max + margin);
    let canvas = Canvas::allocate(ui, ui.available_size(), view, &fit, true);
    let cell_rect = |cell: [u32; 3]| {
        let (a, b) = grid.cell_box(cell);
        Aabb::new(point(&a), point(&b))
    };
    // The cells passed, the last (where the ray is) lit.
    for (index, cell) in passed.iter().enumerate() {
        let last = index + 1 == passed.len();
        let color = if last { palette::CURRENT } else { palette::BOX };
        canvas.box_outline(
            &cell_rect(*cell),
            Stroke::NONE,
            Some(faded(color, if last { 70 } else { 35 })),
        );
    }
    // Once answered: the next cell, and the line crossed into it.
    if let Some(lit) = lit {
        for &cell in &lit.nodes {
            canvas.box_outline(
                &cell_rect(grid.coordinates(cell)),
                Stroke::new(3.0, palette::HIT),
                Some(faded(palette::HIT, 60)),
            );
        }
    }
    // The grid's lines, in their axis's colour, the one crossed strong.
    for (axis, size) in grid.cell_size().into_iter().enumerate() {
        for line in 0..=grid.cells[axis] {
            let position = grid.min[axis] + f64::from(line) * size;
            let crossed = lit.is_some_and(|lit| {
                lit.axis == Some(axis)
                    && lit.t.is_some_and(|t| {
                        (grid.origin[axis] + t * grid.direction[axis] - position).abs()
                            < 1e-9 * (1.0 + position.abs())
                    })
            });
            let stroke = if crossed {
                Stroke::new(3.0, palette::AXES[axis])
            } else {
                Stroke::new(1.2, faded(palette::AXES[axis], 150))
            };
            canvas.split_line(&bounds, axis, position, stroke);
        }
    }
    // Each cell's coordinates, where they fit.
    let font = crate::canvas::font(ui.ctx(), 11.0);
    let label_color = ui.visuals().weak_text_color();
    for y in 0..grid.cells[1] {
        for x in 0..grid.cells[0] {
            let rect = cell_rect([x, y, 0]);
            if canvas.screen_rect(&rect).width() >= 34.0 {
                canvas.painter.text(
                    canvas.to_screen(rect.center()),
                    egui::Align2::CENTER_CENTER,
                    grid.describe_cell([x, y, 0]),
                    font.clone(),
                    label_color,
                );
            }
        }
    }
    canvas.ray(o, d, f64::INFINITY, Stroke::new(2.5, palette::RAY));
    canvas.label(o, "o", palette::RAY);
    if let Some(t) = lit.and_then(|lit| lit.t) {
        canvas.ray_mark(o, d, t, palette::HIT, "", 0.0);
        canvas.label(
            o + d * t,
            &lit.map(|lit| lit.t_label.clone()).unwrap_or_default(),
            palette::HIT,
        );
    }
    // A click on a cell picks the option naming it.
    let picked = state
        .ask
        .filter(|_| !state.revealed && canvas.response.clicked())
        .and_then(|ask| {
            let at = canvas.to_world(canvas.response.interact_pointer_pos()?);
            ask.expected.options().iter().position(|option| {
                option
                    .node
                    .is_some_and(|cell| cell_rect(grid.coordinates(cell)).contains_point(at))
            })
        });
    canvas.finish();
    picked
}

/// The 3D grid walk: every cell a faint box, the cells passed lit (the last strongest), the
/// answer's cell once shown, and the ray.
fn grid_3d_ui(
    ui: &mut Ui,
    view3d: &mut crate::view3d::View3d,
    lit: Option<&Highlight>,
    grid: &accelviz_quiz::GridFigure,
    passed: &[[u32; 3]],
    reach: f64,
) {
    use crate::view3d::{Content, HiddenEdges, Instance, relative, revision_of};
    let rgba = |color: Color32, alpha: u8| [color.r(), color.g(), color.b(), alpha];
    let (low, high) = (DVec3::from_slice(&grid.min), DVec3::from_slice(&grid.max));
    let (o, d) = (
        DVec3::from_slice(&grid.origin),
        DVec3::from_slice(&grid.direction),
    );
    let everything = Aabb::new(
        low.min(o).min(o + d * reach),
        high.max(o).max(o + d * reach),
    );
    let sphere = (
        everything.center(),
        (everything.extent().length() * 0.5).max(1e-6),
    );
    let cell_box = |cell: [u32; 3], color: [u8; 4]| {
        let (a, b) = grid.cell_box(cell);
        Instance {
            a: relative(DVec3::from_slice(&a), sphere),
            b: relative(DVec3::from_slice(&b), sphere),
            color,
        }
    };
    let mut boxes = Vec::new();
    for z in 0..grid.cells[2] {
        for y in 0..grid.cells[1] {
            for x in 0..grid.cells[0] {
                boxes.push(cell_box([x, y, z], rgba(Color32::GRAY, 90)));
            }
        }
    }
    for (index, &cell) in passed.iter().enumerate() {
        let color = if index + 1 == passed.len() {
            palette::CURRENT
        } else {
            palette::BOX
        };
        boxes.push(cell_box(cell, rgba(color, 255)));
    }
    if let Some(lit) = lit {
        boxes.extend(
            lit.nodes
                .iter()
                .map(|&cell| cell_box(grid.coordinates(cell), rgba(palette::HIT, 255))),
        );
    }
    boxes.push(Instance {
        a: relative(low, sphere),
        b: relative(high, sphere),
        color: rgba(palette::BOX, 255),
    });
    let segments = [Instance {
        a: relative(o, sphere),
        b: relative(o + d * reach, sphere),
        color: rgba(palette::RAY, 255),
    }];
    let key = revision_of((
        [&grid.min, &grid.max, &grid.origin, &grid.direction]
            .map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>()),
        passed.to_vec(),
        lit.map(|lit| lit.nodes.clone()),
    ));
    view3d.ui(
        ui,
        ui.available_size().max(Vec2::splat(80.0)),
        &Content {
            sphere,
            mesh: (0, &[]),
            highlights: (0, &[]),
            boxes: (key, &boxes),
            segments: (key, &segments),
            quads: (0, &[]),
            hidden_edges: HiddenEdges::Dimmed,
            wireframe: false,
        },
    );
}

/// The two triangles seen along the ray, the ray a point where they meet; once answered, the
/// triangle hit lit, or the ray marked as slipping through.
fn crack_ui(canvas: &Canvas, state: &FigureState, crack: &accelviz_quiz::CrackFigure) {
    let lit = highlight(state);
    let colours = [palette::BOX, palette::SPHERE];
    for (index, (corners, colour)) in crack.seen.iter().zip(colours).enumerate() {
        let hit = lit.is_some_and(|lit| lit.shapes.contains(&(index as u32)));
        let points: Vec<egui::Pos2> = corners
            .iter()
            .map(|&corner| canvas.to_screen(corner))
            .collect();
        let stroke = if hit {
            Stroke::new(4.0, palette::HIT)
        } else {
            Stroke::new(2.0, colour)
        };
        canvas.painter.add(egui::Shape::convex_polygon(
            points,
            faded(colour, 40),
            stroke,
        ));
        let centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
        canvas.label(centroid, ["A", "B"][index], colour);
    }
    let ray = canvas.to_screen(crack.ray_at);
    let (colour, said) = match lit {
        Some(lit) if lit.shapes.is_empty() => (palette::MISS, "the ray slips through"),
        Some(_) => (palette::HIT, "the ray: a hit"),
        None => (palette::RAY, "the ray, seen along itself"),
    };
    canvas.painter.circle_filled(ray, 6.0, colour);
    canvas.label(crack.ray_at + DVec2::new(0.0, -1.2), said, colour);
    canvas.note(&format!(
        "seen along the ray · {} test in {}",
        crack.test.name(),
        crack.precision
    ));
}

/// The step's highlight, once answered, and only once the traversal shown has reached what it
/// marks (in the review of a mistake, stepping back hides it again).
fn highlight<'a>(state: &'a FigureState) -> Option<&'a Highlight> {
    state
        .revealed
        .then(|| state.ask.map(|ask| &ask.highlight))
        .flatten()
        .filter(|lit| lit.frame.is_none_or(|frame| state.frame >= frame))
}

/// The option whose node, shape or split lies under a click.
fn clicked_option(
    canvas: &Canvas,
    state: &FigureState,
    shapes: &ShapeSet<DVec2>,
    candidates: &[(usize, f64)],
    cell: &Aabb<DVec2>,
) -> Option<usize> {
    let ask = state.ask?;
    if state.revealed || !canvas.response.clicked() {
        return None;
    }
    let at = canvas.to_world(canvas.response.interact_pointer_pos()?);
    let reach = canvas.world_length(8.0);
    let options = ask.expected.options();
    // A node: the deepest offered one whose box holds the click.
    if let Some(tree) = state.tree {
        let facts = &tree.built.facts;
        let node = options
            .iter()
            .enumerate()
            .filter_map(|(index, option)| Some((index, option.node?)))
            .filter(|(_, node)| facts.bounds[*node as usize].contains_point(at))
            .max_by_key(|(_, node)| facts.depth[*node as usize]);
        if let Some((index, _)) = node {
            return Some(index);
        }
    }
    // A shape: one whose box (grown a little, for thin segments) holds the click.
    let shape = options.iter().position(|option| {
        option.shape.is_some_and(|shape| {
            shapes.shapes.get(shape as usize).is_some_and(|shape| {
                let bounds = shape.bounds();
                Aabb::new(
                    bounds.min - DVec2::splat(reach),
                    bounds.max + DVec2::splat(reach),
                )
                .contains_point(at)
            })
        })
    });
    if shape.is_some() {
        return shape;
    }
    // A split line near the click, within the cell.
    if !cell.contains_point(at) {
        return None;
    }
    candidates
        .iter()
        .enumerate()
        .map(|(index, (axis, position))| (index, (at[*axis] - position).abs()))
        .filter(|(_, distance)| *distance <= reach)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(index, _)| index)
}

fn scene_ui(
    ui: &Ui,
    canvas: &Canvas,
    state: &FigureState,
    scene: &accelviz_quiz::SceneFigure,
) -> Option<usize> {
    let lit = highlight(state);
    let figure_tree = scene.tree.as_ref();
    let steps: &[Step<f64>] =
        figure_tree.map_or(&[], |tree| &tree.steps[..state.frame.min(tree.steps.len())]);
    // The node asked about, and its candidate splits.
    let cell = scene
        .node
        .as_ref()
        .map_or_else(scene_bounds, |(bounds, _)| *bounds);
    if let Some((bounds, _)) = &scene.node {
        canvas.box_outline(
            bounds,
            Stroke::new(2.0, faded(palette::CURRENT, 200)),
            Some(faded(palette::CURRENT, 18)),
        );
    }
    // The tree, with what the traversal has done so far (its names drawn over the shapes).
    let mut node_labels = Vec::new();
    if let (Some(tree), Some(figure_tree)) = (state.tree, figure_tree) {
        let facts = &tree.built.facts;
        // The nodes seen so far, as the step's numbers list them.
        let visible = figure_tree.visible(state.frame);
        if figure_tree.reveal_as_reached {
            for &node in &visible {
                let color = canvas.depth_color(facts.depth[node as usize] as usize);
                node_outline(
                    canvas,
                    tree,
                    node,
                    Stroke::new(1.5, faded(color, 200)),
                    None,
                );
            }
        }
        let look = TreeLook {
            steps,
            structure_alpha: if figure_tree.reveal_as_reached {
                0
            } else {
                150
            },
            mark_current: state.revealed,
            ..TreeLook::default()
        };
        draw_tree(canvas, tree, &look);
        if let Some(lit) = lit {
            for &node in &lit.nodes {
                if (node as usize) < facts.node_count() {
                    light(canvas, tree, node, false);
                }
            }
        }
        // Nodes named by their paths, so "node LR" can be found: every visible BVH node, at
        // its box's top left corner moved in by its depth as the boxes are; of a kD-tree (whose
        // cells share corners) the nodes the step names and their parents.
        let named: Vec<u32> = match tree.built.tree.family() {
            accelviz_core::Family::Bvh => visible.clone(),
            accelviz_core::Family::Kd
            | accelviz_core::Family::Grid
            | accelviz_core::Family::HashedGrid
            | accelviz_core::Family::Octree => {
                let mut named: Vec<u32> = state
                    .ask
                    .map(|ask| {
                        ask.expected
                            .options()
                            .iter()
                            .filter_map(|o| o.node)
                            .collect()
                    })
                    .unwrap_or_default();
                named.extend(lit.map(|lit| lit.nodes.clone()).unwrap_or_default());
                let parents: Vec<u32> = named
                    .iter()
                    .filter_map(|node| facts.parent[*node as usize])
                    .collect();
                named.extend(parents);
                named.sort_unstable();
                named.dedup();
                named
            }
        };
        if facts.node_count() <= 63 {
            for &node in &named {
                if let Some(rect) = node_rect(canvas, tree, node) {
                    let depth = facts.depth[node as usize] as usize;
                    // A parent named with its children takes its name outside its box, the
                    // children inside theirs: no name reads as a neighbour's.
                    let parent = named
                        .iter()
                        .any(|&other| facts.parent[other as usize] == Some(node));
                    node_labels.push((
                        rect,
                        parent,
                        accelviz_quiz::node_label(facts, node),
                        readable_on(canvas.depth_color(depth), canvas.background()),
                    ));
                }
            }
        }
    }
    // The shapes, coloured by the tests shown, numbered.
    draw_tested_shapes(ui, canvas, &scene.shapes, steps, None);
    let inside = scene.node.as_ref().map(|(_, members)| members);
    for (index, shape) in scene.shapes.shapes.iter().enumerate() {
        let faint = inside.is_some_and(|members| !members.contains(&(index as u32)));
        let color = if faint {
            Color32::from_gray(120)
        } else {
            ui.visuals().strong_text_color()
        };
        canvas.label(shape.bounds().center(), &index.to_string(), color);
    }
    if let Some(ray) = &scene.ray {
        canvas.reserve_ray(ray.origin, ray.direction);
    }
    // In tree order, parents first: a parent's spot outside its box is taken before a
    // child's name inside.
    for (rect, parent, name, color) in &node_labels {
        canvas.box_label(*rect, *parent, name, *color);
    }
    if let Some(lit) = lit {
        for &shape in &lit.shapes {
            if let Some(shape) = scene.shapes.shapes.get(shape as usize) {
                canvas.shape(
                    shape,
                    faded(palette::HIT, 120),
                    Stroke::new(3.5, palette::HIT),
                );
            }
        }
    }
    // Once answered, the lit split's two children's boxes: what its cost is made of.
    if let Some(index) = lit.and_then(|lit| lit.candidate)
        && let Some(sides) = scene.candidate_boxes.get(index)
    {
        for (side, color) in sides.iter().zip([palette::X_AXIS, palette::SPHERE]) {
            canvas.box_outline(side, Stroke::new(2.5, color), Some(faded(color, 40)));
        }
    }
    // The candidate splits, lettered as the choices.
    let candidates: &[(usize, f64)] = if scene.candidates_before_answer || lit.is_some() {
        &scene.candidates
    } else {
        &[]
    };
    for (index, (axis, position)) in candidates.iter().enumerate() {
        let chosen = lit.and_then(|lit| lit.candidate) == Some(index);
        let (width, color) = if chosen {
            (4.0, palette::HIT)
        } else {
            (2.0, palette::AXES[*axis])
        };
        canvas.split_line(&cell, *axis, *position, Stroke::new(width, color));
        let end = if *axis == 0 {
            DVec2::new(*position, cell.max.y)
        } else {
            DVec2::new(cell.max.x, *position)
        };
        canvas.label(end, &format!("({})", option_letter(index)), color);
    }
    // The ray: solid up to the hit so far, labelled for what it is; the point the answer
    // marks, labelled for what it is (a plane crossing is no hit).
    if let Some(ray) = &scene.ray {
        let closest = crate::trace::closest_so_far(steps).map(|(_, t)| t);
        let finished = figure_tree.is_some_and(|tree| steps.len() == tree.steps.len());
        let hit_label = match figure_tree.map(|tree| tree.query) {
            Some(accelviz_core::Query::FirstInCell) => "hit found",
            _ if finished => "closest",
            _ => "closest so far",
        };
        let lit_point = lit.and_then(|lit| {
            let t = lit.t?;
            let label = if lit.t_label.is_empty() {
                format!("t = {}", accelviz_quiz::num(t))
            } else {
                lit.t_label.clone()
            };
            Some((t, label))
        });
        match lit_point {
            // The marked point is the hit so far: one mark, with the answer's words.
            Some((t, label)) if Some(t) == closest => {
                draw_ray_colored(canvas, ray, closest, palette::RAY, &label);
            }
            _ => {
                draw_ray_colored(canvas, ray, closest, palette::RAY, hit_label);
                if let Some((t, label)) = lit_point {
                    canvas.ray_mark_labeled(
                        ray.origin,
                        ray.direction,
                        t,
                        palette::CURRENT,
                        &label,
                        -1.0,
                    );
                }
            }
        }
    }
    wrong_pick_ui(canvas, state, scene);
    clicked_option(canvas, state, &scene.shapes, &scene.candidates, &cell)
}

/// A wrong pick, once answered, marked where it is in the figure (its node, shape or split)
/// beside the right answer's highlight, so the student sees what they chose.
fn wrong_pick_ui(canvas: &Canvas, state: &FigureState, scene: &accelviz_quiz::SceneFigure) {
    let (Some(ask), Some(chosen), true) = (state.ask, state.picked, state.revealed) else {
        return;
    };
    if ask
        .expected
        .accepts(&accelviz_quiz::Response::Choice(chosen))
    {
        return;
    }
    let Some(option) = ask.expected.options().get(chosen) else {
        return;
    };
    let stroke = Stroke::new(3.0, palette::MISS);
    if let (Some(node), Some(tree)) = (option.node, state.tree) {
        node_outline(canvas, tree, node, stroke, None);
        let bounds = &tree.built.facts.bounds[node as usize];
        canvas.label(bounds.max, "your pick", palette::MISS);
    } else if let Some(shape) = option
        .shape
        .and_then(|shape| scene.shapes.shapes.get(shape as usize))
    {
        canvas.shape(shape, faded(palette::MISS, 60), stroke);
        canvas.label(shape.bounds().max, "your pick", palette::MISS);
    } else if scene.candidates.len() == ask.expected.options().len()
        && let (Some((axis, position)), Some((cell, _))) =
            (scene.candidates.get(chosen), &scene.node)
    {
        canvas.split_line(cell, *axis, *position, stroke);
    }
}

fn build_ui(
    ui: &Ui,
    canvas: &Canvas,
    state: &FigureState,
    exercise: &BuildExercise,
) -> Option<usize> {
    let shapes = exercise.shapes();
    // The student's tree so far, by depth.
    let tree = exercise.tree();
    let facts = TreeFacts::of(&tree);
    for node in 0..facts.node_count() {
        let color = canvas.depth_color(facts.depth[node] as usize);
        let bounds = facts.bounds[node];
        let grow = DVec2::splat(canvas.world_length(3.0) * (4.0 - facts.depth[node].min(4) as f64));
        canvas.box_outline(
            &Aabb::new(bounds.min - grow, bounds.max + grow),
            Stroke::new(1.5, faded(color, 200)),
            None,
        );
    }
    draw_tested_shapes(ui, canvas, shapes, &[], None);
    for (index, shape) in shapes.shapes.iter().enumerate() {
        canvas.label(
            shape.bounds().center(),
            &index.to_string(),
            ui.visuals().strong_text_color(),
        );
    }
    // The node asked about (or, once answered, the one just decided) with its splits.
    let (choice, picked) = if state.revealed {
        // The node just decided (not the one-shape leaves decided with it).
        let (choice, picked) = exercise
            .decided()
            .iter()
            .rev()
            .find(|(choice, _)| choice.picks.len() > 1)?;
        (choice.clone(), Some(*picked))
    } else {
        (exercise.next_choice()?, None)
    };
    canvas.box_outline(
        &choice.bounds,
        Stroke::new(2.5, palette::CURRENT),
        Some(faded(palette::CURRENT, 18)),
    );
    let mut lines = Vec::new();
    for (index, pick) in choice.picks.iter().enumerate() {
        let Pick::Split { axis, position } = *pick else {
            continue;
        };
        lines.push((axis, position));
        let (width, color) = if picked.is_some() && index == choice.builder {
            (4.0, palette::HIT)
        } else if picked == Some(index) {
            (4.0, palette::RAY)
        } else {
            (1.5, faded(palette::AXES[axis], 200))
        };
        canvas.split_line(&choice.bounds, axis, position, Stroke::new(width, color));
        let end = if axis == 0 {
            DVec2::new(position, choice.bounds.max.y)
        } else {
            DVec2::new(choice.bounds.max.x, position)
        };
        canvas.label(end, &format!("({})", option_letter(index)), color);
    }
    // Lines are the options after the leaf.
    clicked_option(canvas, state, shapes, &lines, &choice.bounds).map(|line| line + 1)
}

/// The slab test's numbers, from the core's record.
struct SlabNumbers {
    t_near: Vec<f64>,
    t_far: Vec<f64>,
    t_enter: f64,
    t_exit: f64,
}

fn slab_numbers(
    min: &[f64],
    max: &[f64],
    origin: &[f64],
    direction: &[f64],
) -> Option<SlabNumbers> {
    fn record<V: accelviz_core::Vector<Scalar = f64>>(
        min: &[f64],
        max: &[f64],
        origin: &[f64],
        direction: &[f64],
    ) -> Option<SlabNumbers> {
        let ray = Ray::try_new(V::from_f64_slice(origin), V::from_f64_slice(direction)).ok()?;
        let bounds = Aabb::new(V::from_f64_slice(min), V::from_f64_slice(max));
        let record = slab_record(&bounds, &ray, false);
        let dimensions = min.len();
        Some(SlabNumbers {
            t_near: record.t_near.to_f64_array()[..dimensions].to_vec(),
            t_far: record.t_far.to_f64_array()[..dimensions].to_vec(),
            t_enter: record.t_enter,
            t_exit: record.t_exit,
        })
    }
    if min.len() == 3 {
        record::<DVec3>(min, max, origin, direction)
    } else {
        record::<DVec2>(min, max, origin, direction)
    }
}

#[allow(clippy::too_many_arguments)] // The slab's four vectors, as the figure holds them.
fn slab_ui(
    ui: &mut Ui,
    view: &mut View2d,
    view3d: &mut crate::view3d::View3d,
    state: &FigureState,
    min: &[f64],
    max: &[f64],
    origin: &[f64],
    direction: &[f64],
) {
    let lit = highlight(state);
    let numbers = slab_numbers(min, max, origin, direction);
    let rows = min.len() + 1;
    let intervals = lit.is_some_and(|lit| lit.intervals);
    let lines_height = if intervals {
        number_lines_height(rows)
    } else {
        0.0
    };
    let axis_names = ["x slab", "y slab", "z slab"];
    if min.len() == 2 {
        let (o, d) = (
            DVec2::new(origin[0], origin[1]),
            DVec2::new(direction[0], direction[1]),
        );
        let bounds = Aabb::new(DVec2::new(min[0], min[1]), DVec2::new(max[0], max[1]));
        let reach = numbers
            .as_ref()
            .map_or(1.0, |n| n.t_exit.max(n.t_enter).max(1.0));
        let fit = bounds.union(Aabb::from_points([o, o + d * (reach + 0.5)]));
        let fit = Aabb::new(fit.min - DVec2::splat(1.0), fit.max + DVec2::splat(1.0));
        let size = ui.available_size() - Vec2::new(0.0, lines_height + 8.0);
        let canvas = Canvas::allocate(ui, size.max(Vec2::splat(80.0)), view, &fit, true);
        // The slabs: each axis's two planes across the view, the box where they overlap.
        let far = Aabb::new(fit.min - DVec2::splat(1e3), fit.max + DVec2::splat(1e3));
        for axis in 0..2 {
            let strong = lit.and_then(|lit| lit.axis) == Some(axis);
            let stroke = Stroke::new(
                if strong { 3.0 } else { 1.2 },
                faded(palette::AXES[axis], if strong { 255 } else { 150 }),
            );
            for position in [min[axis], max[axis]] {
                canvas.split_line(&far, axis, position, stroke);
            }
        }
        canvas.box_outline(
            &bounds,
            Stroke::new(2.5, palette::BOX),
            Some(faded(palette::BOX, 30)),
        );
        canvas.ray(o, d, f64::INFINITY, Stroke::new(2.5, palette::RAY));
        canvas.label(o, "o", palette::RAY);
        if let (Some(lit), Some(numbers)) = (lit, &numbers) {
            // The crossings this step has found, in their axis's colour.
            for axis in 0..2 {
                for t in [numbers.t_near[axis], numbers.t_far[axis]] {
                    if lit.marks.contains(&t) {
                        canvas.ray_mark(o, d, t, palette::AXES[axis], "", 0.0);
                    }
                }
            }
            if let Some(t) = lit.t {
                canvas.ray_mark(o, d, t, palette::HIT, "", 0.0);
                canvas.label(
                    o + d * t,
                    &format!("t = {}", accelviz_quiz::num(t)),
                    palette::HIT,
                );
            }
        }
        canvas.finish();
    } else {
        // In 3D: the box and the ray in the 3D view (orbit with a drag), the numbers beside.
        ui.label(
            egui::RichText::new(format!(
                "Box from ({}) to ({}); ray from ({}) in direction ({})",
                list(min),
                list(max),
                list(origin),
                list(direction)
            ))
            .strong(),
        );
        let size = ui.available_size() - Vec2::new(0.0, lines_height + 8.0);
        slab_3d_ui(
            ui,
            view3d,
            size.max(Vec2::splat(80.0)),
            lit,
            min,
            max,
            origin,
            direction,
        );
    }
    if let (true, Some(numbers)) = (intervals, &numbers) {
        ui.add_space(8.0);
        let mut rows: Vec<IntervalRow> = (0..min.len())
            .map(|axis| IntervalRow {
                name: axis_names[axis],
                color: palette::AXES[axis],
                interval: (numbers.t_near[axis], numbers.t_far[axis]),
                visible: true,
            })
            .collect();
        rows.push(IntervalRow {
            name: "all slabs",
            color: palette::BOX,
            interval: (numbers.t_enter, numbers.t_exit),
            visible: true,
        });
        number_lines_ui(ui, &rows, lines_height);
    }
}

/// The 3D slab figure: the box, the ray from its origin to past the box, and the crossings
/// this step has found as small cubes in their axis's colour (the answer's point larger).
#[allow(clippy::too_many_arguments)] // The slab's four vectors, as the figure holds them.
fn slab_3d_ui(
    ui: &mut Ui,
    view3d: &mut crate::view3d::View3d,
    size: Vec2,
    lit: Option<&Highlight>,
    min: &[f64],
    max: &[f64],
    origin: &[f64],
    direction: &[f64],
) {
    use crate::view3d::{Content, HiddenEdges, Instance, relative, revision_of};
    let rgba = |color: Color32| [color.r(), color.g(), color.b(), 255];
    let (low, high) = (DVec3::from_slice(min), DVec3::from_slice(max));
    let (o, d) = (DVec3::from_slice(origin), DVec3::from_slice(direction));
    let numbers = slab_numbers(min, max, origin, direction);
    let reach = numbers
        .as_ref()
        .map_or(1.0, |n| n.t_exit.max(n.t_enter).max(1.0))
        + 0.5;
    let everything = Aabb::new(
        low.min(o).min(o + d * reach),
        high.max(o).max(o + d * reach),
    );
    let sphere = (
        everything.center(),
        (everything.extent().length() * 0.5).max(1e-6),
    );
    let mut boxes = vec![Instance {
        a: relative(low, sphere),
        b: relative(high, sphere),
        color: rgba(palette::BOX),
    }];
    let cube = |t: f64, color: Color32, scale: f64| {
        let half = DVec3::splat(sphere.1 * scale);
        let at = o + d * t;
        Instance {
            a: relative(at - half, sphere),
            b: relative(at + half, sphere),
            color: rgba(color),
        }
    };
    if let (Some(lit), Some(numbers)) = (lit, &numbers) {
        for axis in 0..3 {
            for t in [numbers.t_near[axis], numbers.t_far[axis]] {
                if lit.marks.contains(&t) {
                    boxes.push(cube(t, palette::AXES[axis], 0.015));
                }
            }
        }
        if let Some(t) = lit.t {
            boxes.push(cube(t, palette::HIT, 0.03));
        }
    }
    let segments = [Instance {
        a: relative(o, sphere),
        b: relative(o + d * reach, sphere),
        color: rgba(palette::RAY),
    }];
    let key = revision_of((
        [min, max, origin, direction].map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>()),
        lit.map(|lit| {
            (
                lit.marks.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
                lit.t.map(f64::to_bits),
            )
        }),
    ));
    view3d.ui(
        ui,
        size,
        &Content {
            sphere,
            mesh: (0, &[]),
            highlights: (0, &[]),
            boxes: (key, &boxes),
            segments: (key, &segments),
            quads: (0, &[]),
            hidden_edges: HiddenEdges::Dimmed,
            wireframe: false,
        },
    );
}

fn list(values: &[f64]) -> String {
    values
        .iter()
        .map(|value| accelviz_quiz::num(*value))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.
    fn a_review_lights_the_answer_only_once_the_traversal_reaches_it() {
        let question =
            accelviz_quiz::generate("visit-order", 1, accelviz_quiz::Level::Easy).unwrap();
        // The last step: the closest hit, lit at the traversal's end.
        let ask = question.asks.last().unwrap();
        let lit_at = ask.highlight.frame.unwrap();
        let state = |frame| FigureState {
            question: &question,
            ask: Some(ask),
            revealed: true,
            frame,
            exercise: None,
            tree: None,
            picked: None,
        };
        assert!(highlight(&state(0)).is_none());
        assert!(highlight(&state(lit_at - 1)).is_none());
        assert!(highlight(&state(lit_at)).is_some());
    }
}
