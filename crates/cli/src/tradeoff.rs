//! `accelviz-cli tradeoff`: every structure and every speed/accuracy switch on the same rays,
//! against the f64 brute-force answer; a table (Markdown, CSV) and two SVG plots.

use std::time::Instant;

use accelviz_core::bvh::BuildParams;
use accelviz_core::{
    Counters, HitTest, NoObserver, Order, PrimitiveSet, Query, Ray, Real, Structure, TraceOptions,
    TriangleSet, Vector3, brute_force,
};
use accelviz_scene::rays::{RaySpec, random_rays, surface_aim_rays};
use anyhow::{Context, Result, bail};
use clap::Args;
use glam::{DVec3, Vec3};

use crate::plot::{Point, Scatter};
use crate::spec::AccelSpec;
use crate::{BuildArgs, convert_rays, load_mesh};

#[derive(Args, Debug)]
pub struct TradeoffArgs {
    /// The mesh: an OBJ file, or builtin:NAME (default: the built-in lumpy sphere).
    #[arg(long, default_value = "builtin:lumpy-sphere")]
    mesh: String,
    /// How many random rays (origins outside the mesh's box, aimed at random points in it).
    /// Every one is also traced by brute force in f64, which takes rays × triangles tests.
    #[arg(long, default_value_t = 10_000)]
    rays: usize,
    /// Seed of the random rays.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Instead of random rays, rays aimed exactly at triangle corners and edge points (the
    /// watertightness test's rays, every k-th of them to make `--rays`): where fast triangle
    /// tests and f32 slip through.
    #[arg(long)]
    aimed: bool,
    /// Write tradeoff.md, tradeoff.csv, build-vs-traversal.svg and predicted-vs-measured.svg
    /// here (created if missing). Without it, the Markdown table goes to stdout.
    #[arg(long)]
    out: Option<String>,
    /// Build and trace this many times; the fastest of each is reported.
    #[arg(long, default_value_t = 3)]
    repeat: usize,
    #[command(flatten)]
    build: BuildArgs,
}

/// The switches, each against the first (near-first, f32, fast): `(order, f64, watertight)`.
const VARIANTS: [(Order, bool, bool); 5] = [
    (Order::NearFirst, false, false),
    (Order::FileOrder, false, false),
    (Order::NearFirst, false, true),
    (Order::NearFirst, true, false),
    (Order::NearFirst, true, true),
];

/// One row of the table.
struct Row {
    structure: String,
    order: Order,
    f64: bool,
    watertight: bool,
    build_ms: f64,
    sah_cost: f64,
    nodes_per_ray: f64,
    primitives_per_ray: f64,
    mrays_per_s: f64,
    wrong_per_million: f64,
    missed_per_million: f64,
}

impl Row {
    /// What a ray cost, in the SAH's units: `C_trav·nodes + C_isect·primitives`.
    fn measured_cost(&self, params: &BuildParams) -> f64 {
        params.cost.traversal_cost * self.nodes_per_ray
            + params.cost.intersection_cost * self.primitives_per_ray
    }
}

/// A hit as compared: the primitive and the distance.
type Answer = Option<(u32, f64)>;

pub fn run(args: &TradeoffArgs) -> Result<String> {
    let params = args.build.params()?;
    if args.rays == 0 {
        bail!("--rays must be at least 1");
    }
    let mesh = load_mesh(&args.mesh)?;
    if mesh.triangles.is_empty() {
        bail!("{}: the mesh has no triangles", args.mesh);
    }
    // Every structure of the catalogue (the binned SAH at a few bin counts).
    let specs: Vec<AccelSpec> = Structure::compared()
        .into_iter()
        .map(AccelSpec::Tree)
        .collect();
    let (ray_specs, source) = if args.aimed {
        let all = surface_aim_rays(&mesh.triangles, args.seed);
        let stride = all.len().div_ceil(args.rays).max(1);
        let chosen: Vec<RaySpec> = all.into_iter().step_by(stride).collect();
        let source = format!("aimed:{}:seed{}", chosen.len(), args.seed);
        (chosen, source)
    } else {
        let rays = random_rays(&mesh.bounds(), args.rays, args.seed);
        (rays, format!("random:{}:seed{}", args.rays, args.seed))
    };
    let reference = brute_force_answers(&mesh.triangles, &ray_specs, &source)?;
    let repeat = args.repeat.max(1);
    let mut rows = Vec::new();
    let setup = Setup {
        triangles: &mesh.triangles,
        ray_specs: &ray_specs,
        source: &source,
        params: &params,
        reference: &reference,
        repeat,
    };
    for spec in &specs {
        rows.extend(measure::<Vec3>(spec, &setup)?);
        rows.extend(measure::<DVec3>(spec, &setup)?);
    }
    // Table order: by structure, then the variants in their listed order.
    rows.sort_by_key(|row| {
        let structure = specs.iter().position(|spec| spec.name() == row.structure);
        let variant = VARIANTS
            .iter()
            .position(|v| *v == (row.order, row.f64, row.watertight));
        (structure, variant)
    });
    let heading = format!(
        "{} ({} triangles), {} {} rays (seed {}), C_trav {}, C_isect {}, kD empty bonus {}, single thread, best of {repeat}",
        args.mesh,
        mesh.triangles.len(),
        ray_specs.len(),
        if args.aimed { "aimed" } else { "random" },
        args.seed,
        params.cost.traversal_cost,
        params.cost.intersection_cost,
        params.cost.empty_bonus,
    );
    let markdown = markdown(&rows, &heading, &params);
    let Some(out) = &args.out else {
        return Ok(markdown);
    };
    let dir = std::path::Path::new(out);
    std::fs::create_dir_all(dir).with_context(|| format!("{out}: cannot create the directory"))?;
    let base: Vec<&Row> = rows
        .iter()
        .filter(|row| (row.order, row.f64, row.watertight) == VARIANTS[0])
        .collect();
    let family = |row: &Row| usize::from(row.structure.starts_with("kd:"));
    let families = ["BVH".to_owned(), "kD-tree".to_owned()];
    let cost_label = "cost per ray: C_trav·nodes + C_isect·primitives";
    // One point per structure: `x` of the row against its measured cost.
    let points = |x: fn(&Row) -> f64| -> Vec<Point> {
        base.iter()
            .map(|row| Point {
                x: x(row),
                y: row.measured_cost(&params),
                label: row.structure.clone(),
                family: family(row),
            })
            .collect()
    };
    let build_plot = Scatter {
        title: format!(
            "Build time against traversal cost ({})",
            short_name(&args.mesh)
        ),
        x_label: "build time (ms, single thread, log scale)".into(),
        y_label: cost_label.into(),
        families: families.clone(),
        points: points(|row| row.build_ms),
        diagonal: false,
        log_x: true,
    };
    let sah_plot = Scatter {
        title: format!(
            "Predicted SAH cost against measured cost ({})",
            short_name(&args.mesh)
        ),
        x_label: "predicted SAH cost of the tree".into(),
        y_label: cost_label.into(),
        families,
        points: points(|row| row.sah_cost),
        diagonal: true,
        log_x: false,
    };
    let files = [
        ("tradeoff.md", markdown.clone()),
        ("tradeoff.csv", csv(&rows, &params)),
        ("build-vs-traversal.svg", build_plot.to_svg()),
        ("predicted-vs-measured.svg", sah_plot.to_svg()),
    ];
    for (name, content) in &files {
        let path = dir.join(name);
        std::fs::write(&path, content)
            .with_context(|| format!("{}: cannot write the file", path.display()))?;
    }
    let written: Vec<String> = files
        .iter()
        .map(|(name, _)| dir.join(name).display().to_string())
        .collect();
    Ok(format!("{markdown}\nwrote {}\n", written.join(", ")))
}

fn short_name(mesh: &str) -> &str {
    mesh.rsplit('/').next().unwrap_or(mesh)
}

/// The closest hit of every ray by brute force in f64 with the watertight test: the answer
/// every configuration is held to. Split over the machine's cores.
fn brute_force_answers(
    triangles: &[[[f64; 3]; 3]],
    ray_specs: &[RaySpec],
    source: &str,
) -> Result<Vec<Answer>> {
    let triangles = TriangleSet::<DVec3>::from_f64(triangles);
    let rays = convert_rays::<DVec3>(ray_specs, source)?;
    let options = TraceOptions {
        query: Query::Closest,
        ..TraceOptions::default()
    }
    .with_robust(true);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = rays.len().div_ceil(threads).max(1);
    let answers = std::thread::scope(|scope| {
        let workers: Vec<_> = rays
            .chunks(chunk)
            .map(|rays| {
                let triangles = &triangles;
                scope.spawn(move || {
                    rays.iter()
                        .map(|ray| {
                            brute_force(triangles, ray, &options, &mut NoObserver)
                                .map(|hit| (hit.primitive, hit.t))
                        })
                        .collect::<Vec<Answer>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|worker| worker.join())
            .collect::<Result<Vec<_>, _>>()
    });
    let answers = answers.map_err(|_| anyhow::anyhow!("a brute-force thread failed"))?;
    Ok(answers.into_iter().flatten().collect())
}

/// Builds `spec` in precision `V` and traces every variant of that precision.
/// What every measurement shares: the mesh, the rays and their reference answers.
struct Setup<'a> {
    triangles: &'a [[[f64; 3]; 3]],
    ray_specs: &'a [RaySpec],
    source: &'a str,
    params: &'a BuildParams,
    reference: &'a [Answer],
    repeat: usize,
}

fn measure<V: Vector3>(spec: &AccelSpec, setup: &Setup<'_>) -> Result<Vec<Row>> {
    let Setup {
        triangles,
        ray_specs,
        source,
        params,
        reference,
        repeat,
    } = *setup;
    let is_f64 = size_of::<V::Scalar>() == 8;
    let triangles = TriangleSet::<V>::from_f64(triangles);
    let rays: Vec<Ray<V>> = convert_rays::<V>(ray_specs, source)?;
    let (mut accel, mut build_ms) = spec.build(&triangles, params);
    for _ in 1..repeat {
        let (again, again_ms) = spec.build(&triangles, params);
        if again_ms < build_ms {
            (accel, build_ms) = (again, again_ms);
        }
    }
    let sah_cost = accel.stats(triangles.len(), &params.cost).sah_cost;
    let mut rows = Vec::new();
    for &(order, variant_f64, watertight) in VARIANTS.iter().filter(|v| v.1 == is_f64) {
        let options = TraceOptions {
            order,
            query: Query::Closest,
            ..TraceOptions::default()
        }
        .with_robust(watertight);
        debug_assert_eq!(options.hit_test == HitTest::Watertight, watertight);
        let mut stacks = accelviz_core::TraversalStacks::default();
        let mut trace_ms = f64::INFINITY;
        for _ in 0..repeat {
            let start = Instant::now();
            let hits = rays
                .iter()
                .filter(|ray| {
                    accel
                        .trace(ray, &options, &mut stacks, &mut NoObserver)
                        .is_some()
                })
                .count();
            std::hint::black_box(hits);
            trace_ms = trace_ms.min(start.elapsed().as_secs_f64() * 1e3);
        }
        let mut counters = Counters::default();
        let (mut wrong, mut missed) = (0usize, 0usize);
        for (ray, expected) in rays.iter().zip(reference) {
            let got = accel
                .trace(ray, &options, &mut stacks, &mut counters)
                .map(|hit| (hit.primitive, hit.t.to_f64()));
            match (got, expected) {
                (None, Some(_)) => missed += 1,
                (Some(_), None) => wrong += 1,
                (Some((primitive, t)), Some((expected_primitive, expected_t))) => {
                    // Another primitive at the same distance (a shared edge) is a tie, not
                    // an error; the tolerance covers f32 rounding of t.
                    let same_t = (t - expected_t).abs() <= 1e-5 * expected_t.abs().max(1e-30);
                    if primitive != *expected_primitive && !same_t {
                        wrong += 1;
                    }
                }
                (None, None) => {}
            }
        }
        let count = rays.len() as f64;
        rows.push(Row {
            structure: spec.name(),
            order,
            f64: variant_f64,
            watertight,
            build_ms,
            sah_cost,
            nodes_per_ray: counters.nodes_visited as f64 / count,
            primitives_per_ray: counters.primitive_tests as f64 / count,
            mrays_per_s: count / (trace_ms * 1e3),
            wrong_per_million: wrong as f64 / count * 1e6,
            missed_per_million: missed as f64 / count * 1e6,
        });
    }
    Ok(rows)
}

fn order_name(order: Order) -> &'static str {
    match order {
        Order::NearFirst => "near-first",
        Order::FileOrder => "file-order",
    }
}

impl Row {
    /// The table's cells: rounded for reading, or every digit (for CSV).
    fn cells(&self, params: &BuildParams, rounded: bool) -> [String; 12] {
        let number = |value: f64, digits: usize| {
            if rounded {
                format!("{value:.digits$}")
            } else {
                format!("{value}")
            }
        };
        [
            self.structure.clone(),
            order_name(self.order).to_owned(),
            (if self.f64 { "f64" } else { "f32" }).to_owned(),
            (if self.watertight {
                "watertight"
            } else {
                "fast"
            })
            .to_owned(),
            number(self.build_ms, 1),
            number(self.sah_cost, 1),
            number(self.measured_cost(params), 1),
            number(self.nodes_per_ray, 1),
            number(self.primitives_per_ray, 1),
            number(self.mrays_per_s, 2),
            number(self.wrong_per_million, 0),
            number(self.missed_per_million, 0),
        ]
    }
}

fn markdown(rows: &[Row], heading: &str, params: &BuildParams) -> String {
    let mut out = format!(
        "{heading}. Wrong and missed: against brute force in f64 with the watertight test, per million rays. Measured cost: C_trav·nodes + C_isect·primitives per ray, comparable with the SAH cost.\n\n\
         | structure | order | precision | triangle test | build ms | SAH cost | measured cost | nodes/ray | prims/ray | Mrays/s | wrong /M | missed /M |\n\
         |---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    for row in rows {
        out.push_str(&format!("| {} |\n", row.cells(params, true).join(" | ")));
    }
    out
}

fn csv(rows: &[Row], params: &BuildParams) -> String {
    let mut out = String::from(
        "structure,order,precision,triangle_test,build_ms,sah_cost,measured_cost,nodes_per_ray,prims_per_ray,mrays_per_s,wrong_per_million,missed_per_million\n",
    );
    for row in rows {
        out.push_str(&row.cells(params, false).join(","));
        out.push('\n');
    }
    out
}
