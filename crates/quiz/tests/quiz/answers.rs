//! Every kind of question, made for hundreds of seeds at every level, with each answer
//! checked against a computation written here from the question's JSON alone: the slab test,
//! ray/shape intersections, both traversal orders over the listed nodes, the lecture's kD
//! traversal, SAH costs from perimeters and counts. None of it calls the code that made the
//! question, so a wrong answer or a wrong field in the JSON shows up as a mismatch.

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use accelviz_quiz::{Ask, Expected, Figure, KINDS, Level, generate};
use serde_json::Value;

const SEEDS_PER_LEVEL: u64 = 250;

fn numbers(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .expect("an array")
        .iter()
        .map(|number| number.as_f64().expect("a number"))
        .collect()
}

fn indices(value: &Value) -> Vec<u64> {
    value
        .as_array()
        .expect("an array")
        .iter()
        .map(|number| number.as_u64().expect("an index"))
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}

/// A ray: origin and direction, `t` from 0 with no end.
#[derive(Clone, Copy, Debug)]
struct Ray {
    origin: [f64; 2],
    direction: [f64; 2],
}

fn ray_of(question: &Value) -> Ray {
    let origin = numbers(&question["ray"]["origin"]);
    let direction = numbers(&question["ray"]["direction"]);
    Ray {
        origin: [origin[0], origin[1]],
        direction: [direction[0], direction[1]],
    }
}

/// The slab test of a box `[min.., max..]` in any dimension: (t_near per axis, t_far per
/// axis).
fn slab(corners: &[f64], origin: &[f64], direction: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let dimensions = origin.len();
    let mut near = Vec::new();
    let mut far = Vec::new();
    for axis in 0..dimensions {
        let a = (corners[axis] - origin[axis]) / direction[axis];
        let b = (corners[axis + dimensions] - origin[axis]) / direction[axis];
        near.push(a.min(b));
        far.push(a.max(b));
    }
    (near, far)
}

/// Where the ray enters a box `[x0, y0, x1, y1]` within `[0, t_max]`, if it does.
fn box_interval(corners: &[f64], ray: &Ray, t_max: f64) -> Option<f64> {
    let (near, far) = slab(corners, &ray.origin, &ray.direction);
    let t_enter = near.iter().copied().fold(0.0, f64::max);
    let t_exit = far.iter().copied().fold(t_max, f64::min);
    (t_enter <= t_exit).then_some(t_enter)
}

/// Where the ray first meets a solid shape (`t ≥ 0`).
fn shape_hit(shape: &Value, ray: &Ray) -> Option<f64> {
    let [ox, oy] = ray.origin;
    let [dx, dy] = ray.direction;
    if let Some(disc) = shape.get("disc") {
        let [cx, cy, r] = numbers(disc)[..] else {
            panic!("a disc has three numbers")
        };
        let (px, py) = (ox - cx, oy - cy);
        let a = dx * dx + dy * dy;
        let b = 2.0 * (px * dx + py * dy);
        let c = px * px + py * py - r * r;
        let discriminant = b * b - 4.0 * a * c;
        if discriminant < 0.0 {
            return None;
        }
        let t0 = (-b - discriminant.sqrt()) / (2.0 * a);
        let t1 = (-b + discriminant.sqrt()) / (2.0 * a);
        if t1 < 0.0 { None } else { Some(t0.max(0.0)) }
    } else if let Some(corners) = shape.get("box") {
        box_interval(&numbers(corners), ray, f64::INFINITY)
    } else {
        let [ax, ay, bx, by] = numbers(&shape["segment"])[..] else {
            panic!("a segment has four numbers")
        };
        // o + t·d = a + s·(b − a), by Cramer's rule.
        let (ex, ey) = (bx - ax, by - ay);
        let denominator = dx * (-ey) - dy * (-ex);
        if denominator == 0.0 {
            return None;
        }
        let (rx, ry) = (ax - ox, ay - oy);
        let t = (rx * (-ey) - ry * (-ex)) / denominator;
        let s = (dx * ry - dy * rx) / denominator;
        (t >= 0.0 && (0.0..=1.0).contains(&s)).then_some(t)
    }
}

fn closest(shapes: &[Value], candidates: &[u64], ray: &Ray, found: &mut Option<(u64, f64)>) {
    for &shape in candidates {
        if let Some(t) = shape_hit(&shapes[shape as usize], ray)
            && found.is_none_or(|(_, best)| t < best)
        {
            *found = Some((shape, t));
        }
    }
}

/// A BVH traversal over JSON nodes as the lecture describes it: test both children's boxes
/// (against what is left of the ray), visit the nearer (or the left one, in file order) and
/// keep the other on a stack; skip a node whose box starts beyond the closest hit.
fn traverse_bvh(
    nodes: &[Value],
    shapes: &[Value],
    ray: &Ray,
    near_first: bool,
) -> (Vec<u64>, Option<(u64, f64)>) {
    let mut visited = Vec::new();
    let mut hit: Option<(u64, f64)> = None;
    let Some(t_root) = box_interval(&numbers(&nodes[0]["box"]), ray, f64::INFINITY) else {
        return (visited, hit);
    };
    let mut stack = vec![(0u64, t_root)];
    while let Some((node, t_enter)) = stack.pop() {
        let t_closest = hit.map_or(f64::INFINITY, |(_, t)| t);
        if t_enter > t_closest {
            continue;
        }
        visited.push(node);
        let entry = &nodes[node as usize];
        if let Some(leaf) = entry.get("shapes") {
            closest(shapes, &indices(leaf), ray, &mut hit);
            continue;
        }
        let [left, right] = indices(&entry["children"])[..] else {
            panic!("two children")
        };
        let enter =
            |child: u64| box_interval(&numbers(&nodes[child as usize]["box"]), ray, t_closest);
        match (enter(left), enter(right)) {
            (Some(l), Some(r)) => {
                if near_first && r < l {
                    stack.push((left, l));
                    stack.push((right, r));
                } else {
                    stack.push((right, r));
                    stack.push((left, l));
                }
            }
            (Some(l), None) => stack.push((left, l)),
            (None, Some(r)) => stack.push((right, r)),
            (None, None) => {}
        }
    }
    (visited, hit)
}

/// What becomes of a cell's far child.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FarChild {
    /// Searched with its part of the ray.
    Searched,
    /// The pseudo-code came to it, and its part of the ray is empty (`if empty(ray) return`);
    /// or, culling, it was dropped as empty at once.
    Empty,
    /// The pseudo-code never came to it: the near child gave an intersection. Culling: it
    /// started beyond the closest hit.
    NotSearched,
}

impl FarChild {
    fn name(self) -> &'static str {
        match self {
            FarChild::Searched => "searched",
            FarChild::Empty => "empty",
            FarChild::NotSearched => "not searched",
        }
    }
}

/// A kD traversal over the question's JSON, written here from the lecture's slide
/// ("Traversing a kD-tree") as it reads, recursively:
///
/// ```text
/// intersect(ray, node): if empty(ray) return
///   if leaf(node): intersect node's objects with ray   (ray: clipped to the node's cell)
///   else: rayNear = clip ray to near side; intersect(rayNear, nearChild)
///         if (no intersection): rayFar = clip ray to far side; intersect(rayFar, farChild)
/// ```
///
/// The near side is the one the ray meets first, or in file order the side below the plane.
/// With `culling`, the variant instead: no `If(no intersection)`, every side searched unless
/// it starts beyond the closest hit so far, and a leaf keeps every hit it finds. Records the
/// cells entered in order, the hit, and per interior cell entered (cell, the child searched
/// first, what became of the other).
struct KdWalk<'a> {
    nodes: &'a [Value],
    shapes: &'a [Value],
    ray: Ray,
    near_first: bool,
    culling: bool,
    visited: Vec<u64>,
    hit: Option<(u64, f64)>,
    cells: Vec<(u64, u64, FarChild)>,
}

impl<'a> KdWalk<'a> {
    fn new(question: &'a Value, near_first: bool, culling: bool) -> Self {
        Self {
            nodes: question["nodes"].as_array().unwrap(),
            shapes: question["shapes"].as_array().unwrap(),
            ray: ray_of(question),
            near_first,
            culling,
            visited: Vec::new(),
            hit: None,
            cells: Vec::new(),
        }
    }

    /// The closest hit so far.
    fn t_hit(&self) -> f64 {
        self.hit.map_or(f64::INFINITY, |(_, t)| t)
    }

    fn intersect(&mut self, node: u64, t_near: f64, t_far: f64) {
        if t_near > t_far || (self.culling && t_near > self.t_hit()) {
            return;
        }
        self.visited.push(node);
        let entry = &self.nodes[node as usize];
        if let Some(leaf) = entry.get("shapes") {
            for shape in indices(leaf) {
                if let Some(t) = shape_hit(&self.shapes[shape as usize], &self.ray)
                    && (self.culling || (t_near..=t_far).contains(&t))
                    && t < self.t_hit()
                {
                    self.hit = Some((shape, t));
                }
            }
            return;
        }
        let axis = entry["axis"].as_u64().expect("an axis") as usize;
        let split = entry["split"].as_f64().expect("a split");
        let [below, above] = indices(&entry["children"])[..] else {
            panic!("two children")
        };
        let (origin, direction) = (self.ray.origin[axis], self.ray.direction[axis]);
        if origin == split {
            // The ray starts in the plane: both sides, the one it moves into all along, the
            // other at its start only (the core's convention; no question asks about it).
            let (into, other) = if direction <= 0.0 {
                (below, above)
            } else {
                (above, below)
            };
            let other_end = if direction == 0.0 { t_far } else { t_near };
            if self.culling || direction == 0.0 {
                self.intersect(into, t_near, t_far);
                self.intersect(other, t_near, other_end);
            } else {
                self.intersect(other, t_near, other_end);
                if self.hit.is_none() {
                    self.intersect(into, t_near, t_far);
                }
            }
            return;
        }
        // The side the ray meets first (by the sign of 1/d, so that −0 moves down).
        let (first, second) = if (1.0 / direction) < 0.0 {
            (above, below)
        } else {
            (below, above)
        };
        let t_plane = (split - origin) / direction;
        let first_part = (t_near, t_far.min(t_plane));
        let second_part = (t_near.max(t_plane), t_far);
        let ((near, near_part), (far, far_part)) = if self.near_first || first == below {
            ((first, first_part), (second, second_part))
        } else {
            ((second, second_part), (first, first_part))
        };
        let at = self.cells.len();
        self.cells.push((node, near, FarChild::NotSearched));
        self.intersect(near, near_part.0, near_part.1);
        if !self.culling && self.hit.is_some() {
            return;
        }
        let fate = if far_part.0 > far_part.1 {
            FarChild::Empty
        } else if self.culling && far_part.0 > self.t_hit() {
            FarChild::NotSearched
        } else {
            FarChild::Searched
        };
        self.cells[at].2 = fate;
        self.intersect(far, far_part.0, far_part.1);
    }

    /// The walk done, from the root cell.
    fn walked(mut self) -> Self {
        let (t_near, t_far) = root_part(self.nodes, &self.ray);
        self.intersect(0, t_near, t_far);
        self
    }
}

/// The ray's part in the root cell.
fn root_part(nodes: &[Value], ray: &Ray) -> (f64, f64) {
    let root = numbers(&nodes[0]["cell"]);
    let (near, far) = slab(&root, &ray.origin, &ray.direction);
    (
        near.iter().copied().fold(0.0, f64::max),
        far.iter().copied().fold(f64::INFINITY, f64::min),
    )
}

/// The lecture's quiz on a kD-tree: near first returns the closest hit, file order under the
/// pseudo-code's rule stops at a farther one, and the variant that culls by the closest hit
/// finds the closest again, entering the cells listed.
fn check_lecture(question: &Value) {
    let structure = question["structure"].as_str().unwrap();
    assert!(structure.starts_with("kd:"), "{question}");
    let shapes = question["shapes"].as_array().unwrap();
    let ray = ray_of(question);
    let (near, file, culled) = (
        KdWalk::new(question, true, false).walked(),
        KdWalk::new(question, false, false).walked(),
        KdWalk::new(question, false, true).walked(),
    );
    let mut everything = None;
    closest(
        shapes,
        &(0..shapes.len() as u64).collect::<Vec<_>>(),
        &ray,
        &mut everything,
    );
    let shape = |walk: &KdWalk| walk.hit.map(|hit| hit.0);
    let answer = &question["answer"];
    assert_eq!(shape(&near), everything.map(|hit| hit.0), "{question}");
    assert_eq!(answer["shape"].as_u64(), shape(&near), "{question}");
    assert_eq!(
        answer["file_order_returns"].as_u64(),
        shape(&file),
        "{question}"
    );
    assert!(file.hit.unwrap().1 > near.hit.unwrap().1, "{question}");
    assert!(
        answer["file_order"]
            .as_str()
            .unwrap()
            .contains("not the closest"),
        "{question}"
    );
    assert_eq!(
        indices(&answer["near_first_visited"]),
        near.visited,
        "{question}"
    );
    assert_eq!(
        indices(&answer["file_order_visited"]),
        file.visited,
        "{question}"
    );
    assert_eq!(shape(&culled), shape(&near), "{question}");
    assert_eq!(
        indices(&answer["culled_file_order_visited"]),
        culled.visited,
        "{question}"
    );
    // The explanation's cell and part: where file order stops, and the hit lies in it.
    let stop = &answer["file_order_stops"];
    assert_eq!(stop["cell"].as_u64(), file.visited.last().copied());
    let [t_near, t_far] = numbers(&stop["part"])[..] else {
        panic!("a part: {question}")
    };
    let t_stop = file.hit.unwrap().1;
    assert!(close(stop["t"].as_f64().unwrap(), t_stop), "{question}");
    assert!(t_near <= t_stop && t_stop <= t_far, "{question}");
}

fn check_slab(question: &Value) {
    let corners = numbers(&question["box"]);
    let origin = numbers(&question["ray"]["origin"]);
    let direction = numbers(&question["ray"]["direction"]);
    assert_eq!(corners.len(), 2 * origin.len());
    assert_eq!(direction.len(), origin.len());
    let (near, far) = slab(&corners, &origin, &direction);
    let t_enter = near.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let t_exit = far.iter().copied().fold(f64::INFINITY, f64::min);
    let answer = &question["answer"];
    assert!(
        close(answer["t_enter"].as_f64().unwrap(), t_enter),
        "{question}"
    );
    assert!(
        close(answer["t_exit"].as_f64().unwrap(), t_exit),
        "{question}"
    );
    let hit = t_enter.max(0.0) <= t_exit;
    assert_eq!(answer["hit"].as_bool(), Some(hit), "{question}");
    let axis = answer["enter_axis"].as_u64().unwrap() as usize;
    assert_eq!(near[axis], t_enter, "{question}");
}

fn check_first_hit(question: &Value) {
    let shapes = question["shapes"].as_array().unwrap();
    let ray = ray_of(question);
    let mut hit = None;
    closest(
        shapes,
        &(0..shapes.len() as u64).collect::<Vec<_>>(),
        &ray,
        &mut hit,
    );
    let answer = &question["answer"];
    match hit {
        Some((shape, t)) => {
            assert_eq!(answer["shape"].as_u64(), Some(shape), "{question}");
            assert!(
                (answer["t"].as_f64().unwrap() - t).abs() < 1e-9,
                "{question}"
            );
        }
        None => assert!(
            answer["shape"].is_null() && answer["t"].is_null(),
            "{question}"
        ),
    }
}

/// Every shape is in exactly one leaf, and every child's box lies in its parent's.
fn check_bvh_nodes(question: &Value) {
    let nodes = question["nodes"].as_array().unwrap();
    let shape_count = question["shapes"].as_array().unwrap().len();
    let mut seen = vec![0; shape_count];
    for node in nodes {
        let bounds = numbers(&node["box"]);
        if let Some(leaf) = node.get("shapes") {
            for shape in indices(leaf) {
                seen[shape as usize] += 1;
            }
        } else {
            for child in indices(&node["children"]) {
                let inner = numbers(&nodes[child as usize]["box"]);
                assert!(
                    bounds[0] <= inner[0]
                        && bounds[1] <= inner[1]
                        && inner[2] <= bounds[2]
                        && inner[3] <= bounds[3],
                    "{question}"
                );
            }
        }
    }
    assert!(seen.iter().all(|count| *count == 1), "{question}");
}

fn check_visit_order(question: &Value) {
    check_bvh_nodes(question);
    let near_first = match question["order"].as_str() {
        Some("near-first") => true,
        Some("file-order") => false,
        other => panic!("order {other:?}"),
    };
    let (visited, hit) = traverse_bvh(
        question["nodes"].as_array().unwrap(),
        question["shapes"].as_array().unwrap(),
        &ray_of(question),
        near_first,
    );
    let answer = &question["answer"];
    assert_eq!(indices(&answer["visited"]), visited, "{question}");
    assert_eq!(
        answer["shape"].as_u64(),
        hit.map(|(shape, _)| shape),
        "{question}"
    );
}

fn check_near_vs_file(question: &Value) {
    check_bvh_nodes(question);
    let nodes = question["nodes"].as_array().unwrap();
    let shapes = question["shapes"].as_array().unwrap();
    let ray = ray_of(question);
    let (near, near_hit) = traverse_bvh(nodes, shapes, &ray, true);
    let (file, file_hit) = traverse_bvh(nodes, shapes, &ray, false);
    assert_eq!(near_hit.map(|hit| hit.0), file_hit.map(|hit| hit.0));
    let answer = &question["answer"];
    assert_eq!(indices(&answer["near_first"]), near, "{question}");
    assert_eq!(indices(&answer["file_order"]), file, "{question}");
    assert_eq!(
        answer["shape"].as_u64(),
        near_hit.map(|hit| hit.0),
        "{question}"
    );
    if let Some(skipped) = answer.get("skipped") {
        let expected: Vec<u64> = file.iter().copied().filter(|n| !near.contains(n)).collect();
        assert_eq!(indices(skipped), expected, "{question}");
        assert!(!expected.is_empty());
    }
}

/// The kD traversal question against the pseudo-code near first: cells entered, the hit, and
/// per cell asked about, its near child and what became of its far child, with the reason
/// the model answer gives being the one the pseudo-code acts on.
fn check_kd_traversal(question: &Value, asks: &[Ask]) {
    let walk = KdWalk::new(question, true, false).walked();
    let answer = &question["answer"];
    assert_eq!(indices(&answer["visited"]), walk.visited, "{question}");
    assert_eq!(
        answer["shape"].as_u64(),
        walk.hit.map(|hit| hit.0),
        "{question}"
    );
    let cells = answer["cells"].as_array().unwrap();
    assert!(!cells.is_empty());
    let mut asked = 0;
    for cell in cells {
        let node = cell["node"].as_u64().unwrap();
        let found = walk.cells.iter().find(|(at, ..)| *at == node);
        let (_, near, far) = found.unwrap_or_else(|| panic!("cell {node}: {question}"));
        assert_eq!(cell["near"].as_u64(), Some(*near), "{question}");
        assert_eq!(cell["far"].as_str(), Some(far.name()), "{question}");
        let Some(reason) = cell.get("reason").and_then(Value::as_str) else {
            continue;
        };
        asked += 1;
        // The model answer says what the pseudo-code did, and only it is true.
        let says = |text: &str| match text {
            _ if text.contains("gave no hit, and") => Some(FarChild::Searched),
            _ if text.contains("gave no hit, but") => Some(FarChild::Empty),
            _ if text.contains("gave a hit") => Some(FarChild::NotSearched),
            _ => None,
        };
        assert_eq!(says(reason), Some(*far), "{reason}: {question}");
        let ask = asks
            .iter()
            .find(|ask| {
                matches!(&ask.expected, Expected::Choice { options, correct }
                    if options[*correct].label == reason && ask.prompt.starts_with("Is the far child"))
            })
            .unwrap_or_else(|| panic!("no step asks {reason}: {question}"));
        let Expected::Choice { options, correct } = &ask.expected else {
            unreachable!()
        };
        for (index, option) in options.iter().enumerate() {
            if index != *correct {
                assert_ne!(says(&option.label), Some(*far), "{question}");
            }
        }
    }
    assert!(asked > 0, "{question}");
}

/// The perimeter of the box around `members`' boxes.
fn perimeter_of(shapes: &[Value], members: &[u64]) -> f64 {
    let mut bounds = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for &member in members {
        let b = shape_box(&shapes[member as usize]);
        bounds = [
            bounds[0].min(b[0]),
            bounds[1].min(b[1]),
            bounds[2].max(b[2]),
            bounds[3].max(b[3]),
        ];
    }
    2.0 * ((bounds[2] - bounds[0]) + (bounds[3] - bounds[1]))
}

fn shape_box(shape: &Value) -> [f64; 4] {
    if let Some(disc) = shape.get("disc") {
        let [x, y, r] = numbers(disc)[..] else {
            panic!()
        };
        [x - r, y - r, x + r, y + r]
    } else if let Some(corners) = shape.get("box") {
        let c = numbers(corners);
        [c[0], c[1], c[2], c[3]]
    } else {
        let [ax, ay, bx, by] = numbers(&shape["segment"])[..] else {
            panic!()
        };
        [ax.min(bx), ay.min(by), ax.max(bx), ay.max(by)]
    }
}

fn centre(shape: &Value, axis: usize) -> f64 {
    let b = shape_box(shape);
    0.5 * (b[axis] + b[axis + 2])
}

/// The split cost by the JSON's rule: shapes with centres below the position go left.
fn split_cost(question: &Value, axis: usize, position: f64) -> (f64, usize) {
    let shapes = question["shapes"].as_array().unwrap();
    let members = indices(&question["node_shapes"]);
    let cost = &question["cost"];
    let (c_trav, c_isect) = (
        cost["c_trav"].as_f64().unwrap(),
        cost["c_isect"].as_f64().unwrap(),
    );
    let (left, right): (Vec<u64>, Vec<u64>) = members
        .iter()
        .partition(|member| centre(&shapes[**member as usize], axis) < position);
    let node = perimeter_of(shapes, &members);
    let side = |side: &[u64]| {
        if side.is_empty() {
            0.0
        } else {
            perimeter_of(shapes, side) / node * side.len() as f64
        }
    };
    (c_trav + (side(&left) + side(&right)) * c_isect, left.len())
}

fn check_sah_split(question: &Value) {
    let axis = question["axis"].as_u64().unwrap() as usize;
    let candidates = numbers(&question["candidates"]);
    let answer = &question["answer"];
    let costs = numbers(&answer["costs"]);
    assert_eq!(costs.len(), candidates.len());
    let mut best = 0;
    for (index, position) in candidates.iter().enumerate() {
        let (cost, _) = split_cost(question, axis, *position);
        assert!(
            close(cost, costs[index]),
            "candidate {index}: {cost} {question}"
        );
        if cost < split_cost(question, axis, candidates[best]).0 {
            best = index;
        }
    }
    assert_eq!(answer["best"].as_u64(), Some(best as u64), "{question}");
    // The node box bounds the node's shapes.
    let shapes = question["shapes"].as_array().unwrap();
    let members = indices(&question["node_shapes"]);
    let node_box = numbers(&question["node_box"]);
    assert!(close(
        perimeter_of(shapes, &members),
        2.0 * ((node_box[2] - node_box[0]) + (node_box[3] - node_box[1]))
    ));
    // Middle: the middle of the centres' extent; median: half the shapes on the left.
    let centres: Vec<f64> = members
        .iter()
        .map(|m| centre(&shapes[*m as usize], axis))
        .collect();
    let low = centres.iter().copied().fold(f64::INFINITY, f64::min);
    let high = centres.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let middle = candidates[answer["middle"].as_u64().unwrap() as usize];
    let below = |at: f64| centres.iter().filter(|c| **c < at).count();
    assert_eq!(below(middle), below(0.5 * (low + high)), "{question}");
    let median = candidates[answer["median"].as_u64().unwrap() as usize];
    assert_eq!(below(median), members.len() / 2, "{question}");
}

fn check_leaf_or_split(question: &Value) {
    let shapes = question["shapes"].as_array().unwrap();
    let members = indices(&question["node_shapes"]);
    let cost = &question["cost"];
    let c_isect = cost["c_isect"].as_f64().unwrap();
    let leaf_cost = members.len() as f64 * c_isect;
    // Every split by centres on either axis, tried between each pair of neighbours.
    let mut best = f64::INFINITY;
    for axis in 0..2 {
        let mut centres: Vec<f64> = members
            .iter()
            .map(|m| centre(&shapes[*m as usize], axis))
            .collect();
        centres.sort_by(f64::total_cmp);
        for pair in centres.windows(2) {
            if pair[0] < pair[1] {
                best = best.min(split_cost(question, axis, 0.5 * (pair[0] + pair[1])).0);
            }
        }
    }
    let answer = &question["answer"];
    assert!(
        close(answer["leaf_cost"].as_f64().unwrap(), leaf_cost),
        "{question}"
    );
    assert!(
        close(answer["best_split_cost"].as_f64().unwrap(), best),
        "{question}"
    );
    assert_eq!(
        answer["leaf"].as_bool(),
        Some(best >= leaf_cost),
        "{question}"
    );
}

/// The builder's tree in the JSON is greedy SAH: at every node the cheapest of the leaf and
/// every split by centres (recomputed here), and its SAH cost is the sum over its nodes.
fn check_build(question: &Value) {
    let shapes = question["shapes"].as_array().unwrap();
    let all: Vec<u64> = (0..shapes.len() as u64).collect();
    let root_perimeter = perimeter_of(shapes, &all);
    let cost = &question["cost"];
    let (c_trav, c_isect) = (
        cost["c_trav"].as_f64().unwrap(),
        cost["c_isect"].as_f64().unwrap(),
    );
    let nodes = question["answer"]["nodes"].as_array().unwrap();
    assert_eq!(indices(&nodes[0]["shapes"]), all);
    let mut total = 0.0;
    for node in nodes {
        let members = indices(&node["shapes"]);
        let weight = perimeter_of(shapes, &members) / root_perimeter;
        // The cheapest split, tried between every two neighbouring centres on each axis.
        let node_question = serde_json::json!({
            "shapes": shapes, "node_shapes": members, "cost": cost,
        });
        let mut best = f64::INFINITY;
        for axis in 0..2 {
            let mut centres: Vec<f64> = members
                .iter()
                .map(|m| centre(&shapes[*m as usize], axis))
                .collect();
            centres.sort_by(f64::total_cmp);
            for pair in centres.windows(2) {
                if pair[0] < pair[1] {
                    best = best.min(split_cost(&node_question, axis, 0.5 * (pair[0] + pair[1])).0);
                }
            }
        }
        let leaf_cost = members.len() as f64 * c_isect;
        if node.get("leaf").is_some() {
            assert!(members.len() == 1 || best >= leaf_cost, "{question}");
            total += weight * leaf_cost;
        } else {
            let axis = node["axis"].as_u64().unwrap() as usize;
            let (split, _) = split_cost(&node_question, axis, node["position"].as_f64().unwrap());
            assert!(close(split, best) && split < leaf_cost, "{question}");
            total += weight * c_trav;
        }
    }
    assert!(
        close(question["answer"]["sah_cost"].as_f64().unwrap(), total),
        "{question}"
    );
}

/// What every question has: the fixed fields, steps with a right answer among the options,
/// and the same question again from the same seed.
/// The leak question: traced again through a BVH (not the generator's brute force) in the
/// stated precision and test, the answer is the same; the reference on the same rounded
/// inputs says the ray meets the surface where it goes on (a shared edge), so a miss is a
/// leak, and the watertight test never misses.
fn check_leak(question: &Value) {
    use accelviz_core::outcome::{Outcome, ReferenceScene, SurfacePoint};
    use accelviz_core::{HitTest, Ray, Structure, TraceOptions, TraversalStacks, TriangleSet};
    fn trace<V: accelviz_core::Vector3>(question: &Value, test: HitTest) -> (bool, Outcome) {
        let triangles: Vec<[[f64; 3]; 3]> =
            serde_json::from_value(question["triangles"].clone()).unwrap();
        let vector = |value: &Value| {
            let values: Vec<f64> = serde_json::from_value(value.clone()).unwrap();
            V::from_f64_slice(&values)
        };
        let set = TriangleSet::<V>::from_f64(&triangles);
        let ray = Ray::try_new(
            vector(&question["ray"]["origin"]),
            vector(&question["ray"]["direction"]),
        )
        .unwrap();
        let tree = Structure::BvhMedian {
            width: accelviz_core::Width::Binary,
        }
        .build(&set, &Default::default());
        let options = TraceOptions {
            hit_test: test,
            ..TraceOptions::default()
        };
        let hit = tree.trace(
            &set,
            &ray,
            &options,
            &mut TraversalStacks::default(),
            &mut accelviz_core::NoObserver,
        );
        let reference = ReferenceScene::new(&set);
        let found = reference
            .reference(&ray)
            .expect("the ray meets the triangles");
        assert_eq!(
            found.point,
            SurfacePoint::Crossing,
            "aimed at the shared edge"
        );
        let outcome = reference.classify(
            &ray,
            Some(&found),
            hit.map(|hit| hit.primitive),
            accelviz_core::Query::Closest,
        );
        (hit.is_some(), outcome)
    }
    let test = match question["test"].as_str() {
        Some("fast") => HitTest::Fast,
        Some("watertight") => HitTest::Watertight,
        other => panic!("test {other:?}"),
    };
    let (hit, outcome) = match question["precision"].as_str() {
        Some("f32") => trace::<glam::Vec3>(question, test),
        Some("f64") => trace::<glam::DVec3>(question, test),
        other => panic!("precision {other:?}"),
    };
    assert_eq!(question["answer"]["hit"].as_bool(), Some(hit), "{question}");
    if hit {
        assert!(
            matches!(outcome, Outcome::Agree | Outcome::Tie),
            "{outcome:?}"
        );
    } else {
        assert_eq!(
            test,
            HitTest::Fast,
            "the watertight test never slips through"
        );
        assert_eq!(outcome, Outcome::Leak);
    }
}

/// The grid walk written here from the JSON alone: the ray clipped to the grid's box, its
/// first cell where it starts or enters, then every line it crosses inside the box, in the
/// order it crosses them, each moving the cell by one along its axis.
fn check_grid_walk(
    question: &Value,
    figure: &accelviz_quiz::GridFigure,
    asks: &[accelviz_quiz::Ask],
) {
    let (min, max) = (
        numbers(&question["grid"]["min"]),
        numbers(&question["grid"]["max"]),
    );
    let cells: Vec<i64> = indices(&question["grid"]["cells"])
        .into_iter()
        .map(|n| n as i64)
        .collect();
    let origin = numbers(&question["ray"]["origin"]);
    let direction = numbers(&question["ray"]["direction"]);
    let dimensions = min.len();
    assert!(
        cells.len() == dimensions && origin.len() == dimensions && direction.len() == dimensions
    );
    let size: Vec<f64> = (0..dimensions)
        .map(|axis| (max[axis] - min[axis]) / cells[axis] as f64)
        .collect();
    let corners = [min.clone(), max.clone()].concat();
    let (near, far) = slab(&corners, &origin, &direction);
    let t_enter = near.iter().fold(0.0f64, |a, &b| a.max(b));
    let t_exit = far.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    assert!(t_enter < t_exit, "the ray meets the grid");
    let start: Vec<f64> = (0..dimensions)
        .map(|axis| origin[axis] + t_enter * direction[axis])
        .collect();
    let mut cell: Vec<i64> = (0..dimensions)
        .map(|axis| {
            (((start[axis] - min[axis]) / size[axis]).floor() as i64).clamp(0, cells[axis] - 1)
        })
        .collect();
    let mut crossings: Vec<(f64, usize)> = Vec::new();
    for axis in 0..dimensions {
        if direction[axis] == 0.0 {
            continue;
        }
        for line in 1..cells[axis] {
            let position = min[axis] + line as f64 * size[axis];
            let t = (position - origin[axis]) / direction[axis];
            if t > t_enter && t < t_exit {
                crossings.push((t, axis));
            }
        }
    }
    crossings.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut expected = vec![cell.clone()];
    for (_, axis) in crossings {
        cell[axis] += if direction[axis] > 0.0 { 1 } else { -1 };
        expected.push(cell.clone());
    }
    let answer: Vec<Vec<i64>> = question["answer"]["cells"]
        .as_array()
        .unwrap()
        .iter()
        .map(|cell| indices(cell).into_iter().map(|n| n as i64).collect())
        .collect();
    assert_eq!(answer, expected, "{question}");
    // Each step's answer is the next cell (a cell's number), or leaving the grid.
    for (index, ask) in asks.iter().enumerate() {
        let Expected::Choice { options, correct } = &ask.expected else {
            panic!("a choice");
        };
        match expected.get(index + 1) {
            Some(next) => {
                let coordinates = [0, 1, 2].map(|axis| next.get(axis).copied().unwrap_or(0) as u32);
                assert_eq!(
                    options[*correct].node,
                    Some(figure.cell_number(coordinates))
                );
            }
            None => assert!(options[*correct].node.is_none() && *correct == options.len() - 1),
        }
    }
}

/// The quadtree's order written here from the JSON alone: at each cell whose order the answer
/// lists, the ray's part of its box, the child holding the entry point (by its sides of the
/// box's middle), then each middle line crossed inside the part, in order, flipping that
/// side.
fn check_octree_order(question: &Value) {
    let ray = ray_of(question);
    let nodes = question["nodes"].as_array().unwrap();
    for entry in question["answer"]["orders"].as_array().unwrap() {
        let node = entry["node"].as_u64().unwrap() as usize;
        let corners = numbers(&nodes[node]["box"]);
        let children = indices(&nodes[node]["children"]);
        assert_eq!(children.len(), 4, "{question}");
        let (near, far) = slab(&corners, &ray.origin, &ray.direction);
        let t_near = near.iter().fold(0.0f64, |a, &b| a.max(b));
        let t_far = far.iter().fold(f64::INFINITY, |a, &b| a.min(b));
        let middle = [
            0.5 * (corners[0] + corners[2]),
            0.5 * (corners[1] + corners[3]),
        ];
        let at = |t: f64| [0, 1].map(|axis| ray.origin[axis] + t * ray.direction[axis]);
        let entry_point = at(t_near);
        let mut child = (0..2)
            .filter(|&axis| entry_point[axis] > middle[axis])
            .fold(0usize, |child, axis| child | 1 << axis);
        let mut crossings: Vec<(f64, usize)> = (0..2)
            .filter(|&axis| ray.direction[axis] != 0.0)
            .map(|axis| {
                (
                    (middle[axis] - ray.origin[axis]) / ray.direction[axis],
                    axis,
                )
            })
            .filter(|&(t, _)| t > t_near && t < t_far)
            .collect();
        crossings.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut expected = vec![children[child]];
        for (_, axis) in crossings {
            child ^= 1 << axis;
            expected.push(children[child]);
        }
        assert_eq!(indices(&entry["order"]), expected, "{question}");
    }
}

fn check_common(kind: &str, seed: u64, level: Level) -> Value {
    let question = generate(kind, seed, level).expect("a question");
    let text = question.to_json();
    assert!(!text.contains('\n'));
    let json: Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(json["kind"], kind);
    assert_eq!(json["seed"].as_u64(), Some(seed));
    assert!(json["prompt"].as_str().is_some_and(|p| !p.is_empty()));
    assert!(json.get("answer").is_some());
    assert!(!question.asks.is_empty());
    for ask in &question.asks {
        assert!(!ask.prompt.is_empty() && !ask.explanation.is_empty());
        match &ask.expected {
            Expected::Choice { options, correct } => {
                assert!(
                    *correct < options.len() && options.len() >= 2,
                    "{kind} {seed}"
                );
            }
            Expected::Costed { options, costs } => {
                assert!(options.len() == costs.len() && options.len() >= 2);
            }
            Expected::Number { value, tolerance } => {
                assert!(value.is_finite() && *tolerance >= 0.0)
            }
        }
    }
    if let Figure::Scene(scene) = &question.figure
        && let Some(tree) = &scene.tree
    {
        tree.built
            .structure
            .validate(&tree.built.tree, &scene.shapes)
            .expect("a valid tree");
        for ask in &question.asks {
            assert!(ask.frame <= tree.steps.len());
        }
    }
    assert_eq!(generate(kind, seed, level).expect("again").to_json(), text);
    json
}

#[test]
fn every_kind_is_right_for_hundreds_of_seeds() {
    for entry in KINDS {
        for level in Level::ALL {
            for seed in 0..SEEDS_PER_LEVEL {
                let question = check_common(entry.name, seed, level);
                if entry.name == "grid-walk" {
                    let made = generate(entry.name, seed, level).unwrap();
                    let Figure::Grid(figure) = &made.figure else {
                        panic!("a grid figure")
                    };
                    check_grid_walk(&question, figure, &made.asks);
                    assert_eq!(
                        numbers(&question["grid"]["min"]).len(),
                        if level == Level::Hard { 3 } else { 2 },
                        "3D at hard"
                    );
                    continue;
                }
                match entry.name {
                    "slab" => check_slab(&question),
                    "first-hit" => check_first_hit(&question),
                    "visit-order" => check_visit_order(&question),
                    "near-vs-file" => check_near_vs_file(&question),
                    "lecture" => check_lecture(&question),
                    "kd-traversal" => {
                        let made = generate(entry.name, seed, level).unwrap();
                        check_kd_traversal(&question, &made.asks)
                    }
                    "sah-split" => check_sah_split(&question),
                    "leaf-or-split" => check_leaf_or_split(&question),
                    "build" => check_build(&question),
                    "leak" => check_leak(&question),
                    "octree-order" => check_octree_order(&question),
                    other => panic!("no independent check for kind {other}"),
                }
            }
        }
    }
}

#[test]
fn the_answers_in_the_json_are_the_steps_answers() {
    for seed in 0..40 {
        let question = generate("slab", seed, Level::Easy).unwrap();
        let json: Value = serde_json::from_str(&question.to_json()).unwrap();
        let Expected::Number { value, .. } = question.asks[1].expected else {
            panic!("t_enter is a number")
        };
        assert_eq!(json["answer"]["t_enter"].as_f64(), Some(value));
        let Expected::Choice { correct, .. } = question.asks[0].expected else {
            panic!("the axis is a choice")
        };
        assert_eq!(json["answer"]["enter_axis"].as_u64(), Some(correct as u64));
    }
}

#[test]
fn hard_slab_questions_are_in_3d_and_easy_ones_round() {
    for seed in 0..50 {
        let hard: Value =
            serde_json::from_str(&generate("slab", seed, Level::Hard).unwrap().to_json()).unwrap();
        assert_eq!(numbers(&hard["box"]).len(), 6);
        let easy: Value =
            serde_json::from_str(&generate("first-hit", seed, Level::Easy).unwrap().to_json())
                .unwrap();
        for shape in easy["shapes"].as_array().unwrap() {
            for value in shape_box(shape) {
                assert_eq!((value * 2.0).fract(), 0.0, "{shape}");
            }
        }
    }
}

/// A question's numbers written down: the same seed must give the same question in every
/// version (a class shares a seed) and on every machine (the browser runs the same code).
#[test]
fn a_seed_gives_the_question_written_down() {
    let question = generate("slab", 8, Level::Easy).unwrap();
    let json: Value = serde_json::from_str(&question.to_json()).unwrap();
    assert_eq!(numbers(&json["box"]), [2.0, -2.0, 5.5, 0.5]);
    assert_eq!(numbers(&json["ray"]["origin"]), [9.0, 5.0]);
    assert_eq!(numbers(&json["ray"]["direction"]), [-2.0, -2.0]);
    assert_eq!(json["answer"]["t_enter"].as_f64(), Some(2.25));
    assert_eq!(json["answer"]["t_exit"].as_f64(), Some(3.5));
    assert_eq!(json["answer"]["enter_axis"].as_u64(), Some(1));
}

#[test]
fn unknown_kinds_and_levels_list_the_valid_ones() {
    let error = generate("slabs", 1, Level::Easy).unwrap_err().to_string();
    for entry in KINDS {
        assert!(error.contains(entry.name), "{error}");
    }
    let error = Level::parse("expert").unwrap_err().to_string();
    assert!(error.contains("easy, medium, hard"), "{error}");
}
