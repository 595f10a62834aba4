//! `accelviz-cli sah`: the SAH cost of every candidate split of one node, as text, JSON or CSV.

use accelviz_core::curve::{self, Candidate, CostCurve, Mark};
use accelviz_core::params::BuildParams;
use accelviz_core::{
    Aabb, Built, Family, NoBuildObserver, PrimitiveSet, ShapeSet, SplitRule, Structure,
    TriangleSet, Vector,
};
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use glam::{DVec2, DVec3, Vec2, Vec3};

use crate::args::{BuildArgs, Precision};
use crate::json::{JsonObject, number};
use accelviz_scene::builtin::load_mesh;

/// Which kind of tree.
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum StructureArg {
    /// Bounding volume hierarchy: candidates split the primitives by centroid.
    Bvh,
    /// kD-tree: candidates are planes through the primitives' bounds.
    Kd,
}

/// Which axes to list.
#[derive(Clone, Copy, Debug, Default, ValueEnum, PartialEq, Eq)]
pub enum AxisArg {
    X,
    Y,
    Z,
    #[default]
    All,
}

#[derive(Args, Debug)]
pub struct SahArgs {
    #[arg(
        long,
        required_unless_present = "scene2d",
        conflicts_with = "scene2d",
        help = crate::args::mesh_help()
    )]
    mesh: Option<String>,
    /// A 2D scene instead: a scene file (`disc CX CY R`, `box X0 Y0 X1 Y1`, `segment AX AY BX
    /// BY` per line) or `builtin:LAYOUT[:COUNT[:SEED]]` with LAYOUT uniform, clustered or
    /// teapot.
    #[arg(long)]
    scene2d: Option<String>,
    /// The kind of tree.
    #[arg(long, value_enum)]
    structure: StructureArg,
    /// The node: a path of L (left, below the plane) and R steps from the root, in the tree
    /// the exact SAH builder makes (bvh:sah-sweep, kd:sah). Default: the root.
    #[arg(long, default_value = "")]
    node: String,
    /// Only this axis's candidates.
    #[arg(long, value_enum, default_value_t)]
    axis: AxisArg,
    /// Also the candidates between this many equal bins (2 to 4096).
    #[arg(long)]
    bins: Option<usize>,
    /// Arithmetic precision of the scene and the build.
    #[arg(long, value_parser = crate::args::precision_parser(), default_value = "f32")]
    precision: Precision,
    #[command(flatten)]
    build: BuildArgs,
    /// One JSON object.
    #[arg(long, conflicts_with = "csv")]
    json: bool,
    /// One CSV row per candidate.
    #[arg(long)]
    csv: bool,
}

const AXIS_NAMES: [&str; 3] = ["x", "y", "z"];

pub fn run(args: &SahArgs) -> Result<String> {
    let params = args.build.params()?;
    if let Some(bins) = args.bins
        && !(2..=4096).contains(&bins)
    {
        bail!("--bins must be from 2 to 4096, not {bins}");
    }
    if let Some(scene) = &args.scene2d {
        if args.axis == AxisArg::Z {
            bail!("--axis z: a 2D scene has only x and y");
        }
        let shapes = accelviz_scene::scene2d::load_scene2d(scene)?;
        return match args.precision {
            Precision::F32 => curve_of(&to_f32(&shapes), &params, args),
            Precision::F64 => curve_of(&shapes, &params, args),
        };
    }
    let mesh = load_mesh(args.mesh.as_deref().unwrap_or_default())?;
    match args.precision {
        Precision::F32 => curve_of(
            &TriangleSet::<Vec3>::from_f64(&mesh.triangles),
            &params,
            args,
        ),
        Precision::F64 => curve_of(
            &TriangleSet::<DVec3>::from_f64(&mesh.triangles),
            &params,
            args,
        ),
    }
}

fn to_f32(shapes: &ShapeSet<DVec2>) -> ShapeSet<Vec2> {
    use accelviz_core::{Shape, Sphere};
    let point = |p: DVec2| p.as_vec2();
    ShapeSet {
        shapes: shapes
            .shapes
            .iter()
            .map(|shape| match *shape {
                Shape::Sphere(Sphere { center, radius }) => Shape::Sphere(Sphere {
                    center: point(center),
                    radius: radius as f32,
                }),
                Shape::Box(bounds) => Shape::Box(Aabb::new(point(bounds.min), point(bounds.max))),
                Shape::Segment([a, b]) => Shape::Segment([point(a), point(b)]),
            })
            .collect(),
    }
}

fn curve_of<V: Vector, P: PrimitiveSet<V>>(
    primitives: &P,
    params: &BuildParams,
    args: &SahArgs,
) -> Result<String> {
    let bounds = primitives.all_bounds();
    if bounds.is_empty() {
        bail!("the scene holds no primitives");
    }
    // The exact SAH builders make the tree the path walks.
    let family = match args.structure {
        StructureArg::Bvh => Family::Bvh,
        StructureArg::Kd => Family::Kd,
    };
    let structure = Structure::lecture(family, SplitRule::Sah);
    let built = Built::new(structure, primitives, params, &mut NoBuildObserver);
    let node = built.facts.node_at(&args.node).context("--node")?;
    let mut curve = curve::node_curve(&built, node, &bounds, &params.cost, args.bins);
    keep_axis(&mut curve, args.axis);
    let dimensions = V::DIM;
    Ok(if args.json {
        json(&curve, args, dimensions) + "\n"
    } else if args.csv {
        csv(&curve, dimensions)
    } else {
        text(&curve, args, params, dimensions)
    })
}

/// Drops the other axes' candidates; the minima are then over what is listed.
fn keep_axis(curve: &mut CostCurve, axis: AxisArg) {
    let keep = match axis {
        AxisArg::X => 0,
        AxisArg::Y => 1,
        AxisArg::Z => 2,
        AxisArg::All => return,
    };
    let filter = |axes: &mut Vec<Vec<Candidate>>| {
        for (index, candidates) in axes.iter_mut().enumerate() {
            if index != keep {
                candidates.clear();
            }
        }
    };
    filter(&mut curve.axes);
    curve.best = cheapest(&curve.axes);
    if let Some(binned) = &mut curve.binned {
        filter(&mut binned.axes);
        binned.best = cheapest(&binned.axes);
    }
}

fn cheapest(axes: &[Vec<Candidate>]) -> Option<Mark> {
    axes.iter()
        .flatten()
        .fold(None::<&Candidate>, |best, candidate| match best {
            Some(best) if best.cost <= candidate.cost => Some(best),
            _ => Some(candidate),
        })
        .map(Mark::from)
}

fn mark_json(mark: Option<Mark>) -> String {
    match mark {
        None => "null".into(),
        Some(mark) => JsonObject::new()
            .string("axis", AXIS_NAMES[mark.axis])
            .number("position", mark.position)
            .number("cost", mark.cost)
            .finish(),
    }
}

fn axes_json(axes: &[Vec<Candidate>], dimensions: usize) -> String {
    let mut object = JsonObject::new();
    for (axis, candidates) in axes.iter().enumerate().take(dimensions) {
        let list: Vec<String> = candidates
            .iter()
            .map(|c| {
                JsonObject::new()
                    .number("position", c.position)
                    .number("cost", c.cost)
                    .integer("n_left", c.count_left as u64)
                    .integer("n_right", c.count_right as u64)
                    .number("p_left", c.p_left)
                    .number("p_right", c.p_right)
                    .number("area_left", c.area_left)
                    .number("area_right", c.area_right)
                    .finish()
            })
            .collect();
        object = object.raw(AXIS_NAMES[axis], &format!("[{}]", list.join(",")));
    }
    object.finish()
}

fn json(curve: &CostCurve, args: &SahArgs, dimensions: usize) -> String {
    let model = &curve.cost_model;
    let mut object = JsonObject::new()
        .string(
            "structure",
            match args.structure {
                StructureArg::Bvh => "bvh",
                StructureArg::Kd => "kd",
            },
        )
        .string("node", &args.node)
        .integer("count", curve.count as u64)
        .number("area", curve.area)
        .number("c_trav", model.traversal_cost)
        .number("c_isect", model.intersection_cost);
    if args.structure == StructureArg::Kd {
        object = object.number("empty_bonus", model.empty_bonus);
    }
    object = object
        .raw("axes", &axes_json(&curve.axes, dimensions))
        .number("leaf_cost", curve.leaf_cost)
        .raw("middle", &mark_json(curve.middle))
        .raw("median", &mark_json(curve.median))
        .raw("best", &mark_json(curve.best));
    if let Some(binned) = &curve.binned {
        let binned_json = JsonObject::new()
            .integer("bins", binned.bins as u64)
            .raw("axes", &axes_json(&binned.axes, dimensions))
            .raw("best", &mark_json(binned.best))
            .finish();
        object = object.raw("binned", &binned_json);
    }
    object.finish()
}

fn csv(curve: &CostCurve, dimensions: usize) -> String {
    let mut out = String::from(
        "axis,kind,position,cost,n_left,n_right,p_left,p_right,area_left,area_right\n",
    );
    let mut rows = |axes: &[Vec<Candidate>], kind: &str| {
        for candidates in axes.iter().take(dimensions) {
            for c in candidates {
                out.push_str(&format!(
                    "{},{kind},{},{},{},{},{},{},{},{}\n",
                    AXIS_NAMES[c.axis],
                    number(c.position),
                    number(c.cost),
                    c.count_left,
                    c.count_right,
                    number(c.p_left),
                    number(c.p_right),
                    number(c.area_left),
                    number(c.area_right),
                ));
            }
        }
    };
    rows(&curve.axes, "exact");
    if let Some(binned) = &curve.binned {
        rows(&binned.axes, "binned");
    }
    out
}

fn text(curve: &CostCurve, args: &SahArgs, params: &BuildParams, dimensions: usize) -> String {
    let model = &curve.cost_model;
    let node = if args.node.is_empty() {
        "the root".to_owned()
    } else {
        format!("node {}", args.node)
    };
    let mut out = format!(
        "{} {node}: {} primitives, area {:.6e}, C_trav {}, C_isect {}\n",
        match args.structure {
            StructureArg::Bvh => "BVH",
            StructureArg::Kd => "kD-tree",
        },
        curve.count,
        curve.area,
        model.traversal_cost,
        model.intersection_cost,
    );
    let line = |name: &str, mark: Option<Mark>| match mark {
        Some(mark) => format!(
            "{name:<10} {} = {:<14.6e} cost {:.4}\n",
            AXIS_NAMES[mark.axis], mark.position, mark.cost
        ),
        None => format!("{name:<10} none\n"),
    };
    out.push_str(&format!("{:<10} cost {:.4}\n", "leaf", curve.leaf_cost));
    out.push_str(&line("middle", curve.middle));
    out.push_str(&line("median", curve.median));
    out.push_str(&line("SAH best", curve.best));
    if let Some(binned) = &curve.binned {
        out.push_str(&line(&format!("{} bins", binned.bins), binned.best));
    }
    for (axis, candidates) in curve.axes.iter().enumerate().take(dimensions) {
        if candidates.is_empty() {
            continue;
        }
        let low = candidates
            .iter()
            .map(|c| c.cost)
            .fold(f64::INFINITY, f64::min);
        let high = candidates
            .iter()
            .map(|c| c.cost)
            .fold(f64::NEG_INFINITY, f64::max);
        out.push_str(&format!(
            "axis {}: {} candidates, cost {low:.4} to {high:.4}\n",
            AXIS_NAMES[axis],
            candidates.len()
        ));
    }
    // The BVH builder splits every node above the leaf size, and smaller ones when a split
    // is cheaper; the kD builder splits when a cut is cheaper than the leaf.
    let small = args.structure == StructureArg::Kd || curve.count <= params.max_leaf_size;
    let verdict = match curve.best {
        Some(best) if best.cost < curve.leaf_cost => "split: the best cut is cheaper than the leaf",
        Some(_) if !small => "split: more primitives than --max-leaf-size",
        Some(_) => "leaf: no cut is cheaper than testing every primitive",
        None => "leaf: no candidate split",
    };
    out.push_str(&format!("the SAH builder's verdict: {verdict}\n"));
    out.push_str("(--json or --csv for every candidate)\n");
    out
}
