//! `accelviz-cli tradeoff`: every structure and every speed/accuracy switch on the same rays,
//! against the f64 brute-force answer; a table (Markdown, CSV) and two SVG plots.

use accelviz_core::bvh::BuildParams;
use accelviz_core::{
    Counters, HitTest, NoObserver, Order, PrimitiveSet, Query, Ray, Real, Structure, TraceOptions,
    TriangleSet, Vector3, brute_force,
};
use accelviz_scene::rays::{RaySpec, random_rays, surface_aim_rays};
use anyhow::{Context, Result, bail};
use clap::Args;
use glam::{DVec3, Vec3};

use crate::parallel::Workers;
use crate::plot::{Point, Scatter};
use crate::spec::{Accel, AccelSpec};
use crate::timing::interleaved;
use crate::{BuildArgs, convert_rays, load_mesh};

#[derive(Args, Debug)]
pub struct TradeoffArgs {
    #[arg(long, default_value = "builtin:lumpy-sphere", help = crate::mesh_help())]
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
    /// Rounds: every structure is built, and every row traced, once per round, the rounds
    /// interleaved; each figure is the median of its rounds, with the range it moved in.
    #[arg(long, default_value_t = 5)]
    repeat: usize,
    /// Threads tracing rays, in tiles of 256 (builds are single-threaded).
    #[arg(long, default_value_t = 1)]
    threads: usize,
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
    /// Half the range of the trace times, in percent of their median.
    trace_spread_percent: f64,
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
    let workers = Workers::new(args.threads)?;
    let single = Prepared::<Vec3>::new(&mesh.triangles, &ray_specs, &source)?;
    let double = Prepared::<DVec3>::new(&mesh.triangles, &ray_specs, &source)?;
    // Every structure built in both precisions once per round (a configuration is a structure
    // and a precision); the first round's trees are kept.
    let mut trees32: Vec<Option<Accel<Vec3, TriangleSet<Vec3>>>> =
        specs.iter().map(|_| None).collect();
    let mut trees64: Vec<Option<Accel<DVec3, TriangleSet<DVec3>>>> =
        specs.iter().map(|_| None).collect();
    let builds = interleaved(repeat, specs.len() * 2, |index| {
        let spec = &specs[index / 2];
        if index % 2 == 0 {
            let (tree, _) = spec.build(&single.triangles, &params);
            trees32[index / 2].get_or_insert(tree);
        } else {
            let (tree, _) = spec.build(&double.triangles, &params);
            trees64[index / 2].get_or_insert(tree);
        }
    });
    let trees32: Vec<_> = trees32.into_iter().flatten().collect();
    let trees64: Vec<_> = trees64.into_iter().flatten().collect();
    // Every row (a structure and a switch setting) traced once per round.
    let keys: Vec<(usize, usize)> = (0..specs.len())
        .flat_map(|spec| (0..VARIANTS.len()).map(move |variant| (spec, variant)))
        .collect();
    let traces = interleaved(repeat, keys.len(), |index| {
        let (spec, variant) = keys[index];
        let options = variant_options(VARIANTS[variant]);
        let hits = if VARIANTS[variant].1 {
            trees64[spec].count_hits(&double.rays, &options, &workers)
        } else {
            trees32[spec].count_hits(&single.rays, &options, &workers)
        };
        std::hint::black_box(hits);
    });
    let mut rows = Vec::with_capacity(keys.len());
    for (index, &(spec, variant)) in keys.iter().enumerate() {
        let (order, is_f64, watertight) = VARIANTS[variant];
        let options = variant_options(VARIANTS[variant]);
        let (stats, counters, wrong, missed) = if is_f64 {
            double.evaluate(&trees64[spec], &options, &reference, &params)
        } else {
            single.evaluate(&trees32[spec], &options, &reference, &params)
        };
        let count = ray_specs.len() as f64;
        let trace_ms = traces[index].median();
        rows.push(Row {
            structure: specs[spec].name(),
            order,
            f64: is_f64,
            watertight,
            build_ms: builds[2 * spec + usize::from(is_f64)].median(),
            sah_cost: stats.sah_cost,
            nodes_per_ray: counters.nodes_visited as f64 / count,
            primitives_per_ray: counters.primitive_tests as f64 / count,
            mrays_per_s: count / (trace_ms * 1e3),
            trace_spread_percent: traces[index].spread_percent(),
            wrong_per_million: wrong as f64 / count * 1e6,
            missed_per_million: missed as f64 / count * 1e6,
        });
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
        "{} ({} triangles), {} {} rays (seed {}), C_trav {}, C_isect {}, kD empty bonus {}, {} thread(s), median of {repeat} interleaved rounds (±: half their range; rows whose ranges overlap are not shown to differ)",
        args.mesh,
        mesh.triangles.len(),
        ray_specs.len(),
        if args.aimed { "aimed" } else { "random" },
        args.seed,
        params.cost.traversal_cost,
        params.cost.intersection_cost,
        params.cost.empty_bonus,
        args.threads,
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

/// The options of a switch setting `(order, f64, watertight)` (the precision is the tree's).
fn variant_options((order, _, watertight): (Order, bool, bool)) -> TraceOptions {
    let options = TraceOptions {
        order,
        query: Query::Closest,
        ..TraceOptions::default()
    }
    .with_robust(watertight);
    debug_assert_eq!(options.hit_test == HitTest::Watertight, watertight);
    options
}

/// The mesh and the rays in one precision.
struct Prepared<V: Vector3> {
    triangles: TriangleSet<V>,
    rays: Vec<Ray<V>>,
}

impl<V: Vector3> Prepared<V> {
    fn new(triangles: &[[[f64; 3]; 3]], ray_specs: &[RaySpec], source: &str) -> Result<Self> {
        Ok(Self {
            triangles: TriangleSet::from_f64(triangles),
            rays: convert_rays::<V>(ray_specs, source)?,
        })
    }

    /// Untimed: the tree's statistics, the work counted, and the rays answered wrongly or
    /// missed against `reference`.
    fn evaluate(
        &self,
        accel: &Accel<V, TriangleSet<V>>,
        options: &TraceOptions,
        reference: &[Answer],
        params: &BuildParams,
    ) -> (accelviz_core::TreeStats, Counters, usize, usize) {
        let stats = accel.stats(self.triangles.len(), &params.cost);
        let mut stacks = accelviz_core::TraversalStacks::default();
        let mut counters = Counters::default();
        let (mut wrong, mut missed) = (0usize, 0usize);
        for (ray, expected) in self.rays.iter().zip(reference) {
            let got = accel
                .trace(ray, options, &mut stacks, &mut counters)
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
        (stats, counters, wrong, missed)
    }
}

impl Row {
    /// The table's cells: rounded for reading, or every digit (for CSV).
    fn cells(&self, params: &BuildParams, rounded: bool) -> [String; 13] {
        let number = |value: f64, digits: usize| {
            if rounded {
                format!("{value:.digits$}")
            } else {
                format!("{value}")
            }
        };
        [
            self.structure.clone(),
            self.order.name().to_owned(),
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
            number(self.trace_spread_percent, 0),
            number(self.wrong_per_million, 0),
            number(self.missed_per_million, 0),
        ]
    }
}

fn markdown(rows: &[Row], heading: &str, params: &BuildParams) -> String {
    let mut out = format!(
        "{heading}. Wrong and missed: against brute force in f64 with the watertight test, per million rays. Measured cost: C_trav·nodes + C_isect·primitives per ray, comparable with the SAH cost.\n\n\
         | structure | order | precision | triangle test | build ms | SAH cost | measured cost | nodes/ray | prims/ray | Mrays/s | ±% | wrong /M | missed /M |\n\
         |---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    for row in rows {
        out.push_str(&format!("| {} |\n", row.cells(params, true).join(" | ")));
    }
    out
}

fn csv(rows: &[Row], params: &BuildParams) -> String {
    let mut out = String::from(
        "structure,order,precision,triangle_test,build_ms,sah_cost,measured_cost,nodes_per_ray,prims_per_ray,mrays_per_s,trace_spread_percent,wrong_per_million,missed_per_million\n",
    );
    for row in rows {
        out.push_str(&row.cells(params, false).join(","));
        out.push('\n');
    }
    out
}
