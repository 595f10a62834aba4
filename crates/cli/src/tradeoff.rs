//! `accelviz-cli tradeoff`: every structure and every speed/accuracy switch on the same rays,
//! each ray's answer held to a reference on the same rounded inputs
//! ([`accelviz_core::outcome`]); a table (Markdown, CSV, JSON), two SVG plots, and an example
//! ray of each outcome.

use accelviz_core::break_even::{Contender, Crossover, Fastest, crossovers, fastest_at};
use accelviz_core::bvh::BuildParams;
use accelviz_core::outcome::{Outcome, OutcomeCounts, Reference, ReferenceScene};
use accelviz_core::quality::{NodeEntries, SahCheck};
use accelviz_core::{
    Counters, HitTest, Order, PrimitiveSet, Query, Ray, Structure, TraceOptions, TriangleSet,
    Vector3,
};
use accelviz_scene::rays::{RayKind, RaySpec, parse_resolution, ray_line};
use anyhow::{Context, Result, bail};
use clap::Args;
use glam::{DVec3, Vec3};

use crate::json::JsonObject;
use crate::parallel::Workers;
use crate::plot::{Lines, Point, Scatter};
use crate::spec::{Accel, AccelSpec};
use crate::timing::interleaved;
use crate::{BuildArgs, convert_rays, load_mesh};

#[derive(Args, Debug)]
pub struct TradeoffArgs {
    #[arg(long, default_value = "builtin:lumpy-sphere", help = crate::mesh_help())]
    mesh: String,
    /// How many rays of the kind (`--ray-kind`). Every one is also decided by the reference
    /// in each precision.
    #[arg(long, default_value_t = 10_000)]
    rays: usize,
    /// Seed of the rays.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// What rays: random (from around the scene into its box), camera (the benchmark
    /// camera's), aimed (exactly at triangle corners and edge points, where fast tests and
    /// f32 slip through), shadow (from camera hits to a point light), ao (short rays from
    /// camera hits), bounce (a diffuse bounce from each camera hit).
    #[arg(long, default_value = "random", value_parser = parse_ray_kind)]
    ray_kind: RayKind,
    /// The same as `--ray-kind aimed`.
    #[arg(long, conflicts_with = "ray_kind")]
    aimed: bool,
    /// The camera image for `--ray-kind camera`, WIDTHxHEIGHT (else about `--rays` pixels).
    #[arg(long)]
    camera: Option<String>,
    /// closest or any (is anything in the way?). Default: any for shadow and ao rays, closest
    /// otherwise.
    #[arg(long, value_parser = parse_query)]
    query: Option<Query>,
    /// Write tradeoff.md, tradeoff.csv, build-vs-traversal.svg and predicted-vs-measured.svg
    /// here (created if missing). Without it, the table goes to stdout.
    #[arg(long)]
    out: Option<String>,
    /// Print one JSON object per row instead of the table.
    #[arg(long)]
    json: bool,
    /// Write one ray of each outcome per row here, as ray files
    /// (`STRUCTURE_ORDER_PRECISION_TEST.rays`, a `# outcome` comment before each ray), to open
    /// in the app or trace with `query`.
    #[arg(long)]
    examples: Option<String>,
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

/// Parses `--ray-kind`.
pub fn parse_ray_kind(name: &str) -> Result<RayKind, String> {
    RayKind::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = RayKind::ALL.iter().map(|kind| kind.name()).collect();
        format!(
            "'{name}' is not a ray kind; ray kinds are {}",
            names.join(", ")
        )
    })
}

/// Parses `--query`.
pub fn parse_query(name: &str) -> Result<Query, String> {
    match name {
        "closest" => Ok(Query::Closest),
        "any" => Ok(Query::Any),
        _ => Err(format!("'{name}' is not a query; queries are closest, any")),
    }
}

/// A query's name as `--query` spells it.
pub fn query_name(query: Query) -> &'static str {
    match query {
        Query::Any => "any",
        _ => "closest",
    }
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
    /// End-point overlap (BVHs only).
    epo: Option<f64>,
    nodes_per_ray: f64,
    primitives_per_ray: f64,
    mrays_per_s: f64,
    /// Half the range of the trace times, in percent of their median.
    trace_spread_percent: f64,
    outcomes: OutcomeCounts,
    /// The first ray of each outcome (in [`Outcome::ALL`]'s order), as the row's precision
    /// rounded it.
    examples: [Option<RaySpec>; 6],
}

impl Row {
    /// What a ray cost, in the SAH's units: `C_trav·nodes + C_isect·primitives`.
    fn measured_cost(&self, params: &BuildParams) -> f64 {
        params.cost.traversal_cost * self.nodes_per_ray
            + params.cost.intersection_cost * self.primitives_per_ray
    }
}

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
    let kind = if args.aimed {
        RayKind::Aimed
    } else {
        args.ray_kind
    };
    let query = args.query.unwrap_or(kind.default_query());
    let camera = args
        .camera
        .as_deref()
        .map(|text| parse_resolution(text).map_err(|error| anyhow::anyhow!("--camera: {error}")))
        .transpose()?;
    let ray_specs = kind
        .rays(&mesh, args.rays, args.seed, camera)
        .map_err(|problem| anyhow::anyhow!("{}: {problem}", args.mesh))?;
    let source = format!("{}:{}:seed{}", kind.name(), ray_specs.len(), args.seed);
    let repeat = args.repeat.max(1);
    let workers = Workers::new(args.threads)?;
    let single = Prepared::<Vec3>::new(&mesh.triangles, &ray_specs, &source)?;
    let double = Prepared::<DVec3>::new(&mesh.triangles, &ray_specs, &source)?;
    let (reference32, reference64) = (single.references()?, double.references()?);
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
        let options = variant_options(VARIANTS[variant], query);
        let hits = if VARIANTS[variant].1 {
            trees64[spec].count_hits(&double.rays, &options, &workers)
        } else {
            trees32[spec].count_hits(&single.rays, &options, &workers)
        };
        std::hint::black_box(hits);
    });
    // Each tree's end-point overlap, once (every switch setting of a tree shares it).
    let epo32: Vec<Option<f64>> = trees32
        .iter()
        .map(|tree| tree.epo(single.triangles.triangles(), &params.cost))
        .collect();
    let epo64: Vec<Option<f64>> = trees64
        .iter()
        .map(|tree| tree.epo(double.triangles.triangles(), &params.cost))
        .collect();
    let mut rows = Vec::with_capacity(keys.len());
    for (index, &(spec, variant)) in keys.iter().enumerate() {
        let (order, is_f64, watertight) = VARIANTS[variant];
        let options = variant_options(VARIANTS[variant], query);
        let evaluated = if is_f64 {
            double.evaluate(&trees64[spec], &options, &reference64, &params)
        } else {
            single.evaluate(&trees32[spec], &options, &reference32, &params)
        };
        let count = ray_specs.len() as f64;
        let trace_ms = traces[index].median();
        rows.push(Row {
            structure: specs[spec].name(),
            order,
            f64: is_f64,
            watertight,
            build_ms: builds[2 * spec + usize::from(is_f64)].median(),
            sah_cost: evaluated.stats.sah_cost,
            epo: if is_f64 { epo64[spec] } else { epo32[spec] },
            nodes_per_ray: evaluated.counters.nodes_visited as f64 / count,
            primitives_per_ray: evaluated.counters.primitive_tests as f64 / count,
            mrays_per_s: count / (trace_ms * 1e3),
            trace_spread_percent: traces[index].spread_percent(),
            outcomes: evaluated.outcomes,
            examples: evaluated.examples,
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
        "{} ({} triangles), {} {} rays (seed {}), {} hit, C_trav {}, C_isect {}, kD empty bonus {}, {} thread(s), median of {repeat} interleaved rounds (±: half their range; rows whose ranges overlap are not shown to differ)",
        args.mesh,
        mesh.triangles.len(),
        ray_specs.len(),
        kind.name(),
        args.seed,
        query_name(query),
        params.cost.traversal_cost,
        params.cost.intersection_cost,
        params.cost.empty_bonus,
        args.threads,
    );
    if let Some(dir) = &args.examples {
        write_examples(dir, &rows, &heading)?;
    }
    let break_even = BreakEven::of(&rows);
    // The SAH's chances against these rays', for the binned SAH's BVH and the kD SAH tree.
    let checks: Vec<(String, SahCheck)> = ["bvh:sah-binned:16", "kd:sah"]
        .iter()
        .filter_map(|name| {
            let index = specs.iter().position(|spec| spec.name() == *name)?;
            let accel = &trees32[index];
            let facts = accel.binary_facts()?;
            let mut entries = NodeEntries::new(facts.bounds.len());
            let mut stacks = accelviz_core::TraversalStacks::default();
            let options = variant_options(VARIANTS[0], query);
            for ray in &single.rays {
                accel.trace(ray, &options, &mut stacks, &mut entries);
            }
            Some((
                (*name).to_owned(),
                SahCheck::of(&facts, &entries, &params.cost),
            ))
        })
        .collect();
    if args.json {
        let mut lines: Vec<String> = rows
            .iter()
            .map(|row| row.json(&params, kind, query))
            .collect();
        lines.push(break_even.json());
        return Ok(lines.join("\n") + "\n");
    }
    let markdown =
        markdown(&rows, &heading, &params) + &break_even.markdown() + &sah_checks_markdown(&checks);
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
        (
            "total-vs-rays.svg",
            break_even.plot(short_name(&args.mesh)).to_svg(),
        ),
        (
            "sah-assumption.svg",
            sah_checks_plot(&checks, short_name(&args.mesh), kind).to_svg(),
        ),
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

/// The options of a switch setting `(order, f64, watertight)` (the precision is the tree's).
fn variant_options((order, _, watertight): (Order, bool, bool), query: Query) -> TraceOptions {
    let options = TraceOptions {
        order,
        query,
        ..TraceOptions::default()
    }
    .with_robust(watertight);
    debug_assert_eq!(options.hit_test == HitTest::Watertight, watertight);
    options
}

/// The mesh and the rays in one precision, and the reference that decides their outcomes.
struct Prepared<V: Vector3> {
    triangles: TriangleSet<V>,
    rays: Vec<Ray<V>>,
    reference: ReferenceScene,
}

/// What an untimed pass over a row's rays found.
struct Evaluated {
    stats: accelviz_core::TreeStats,
    counters: Counters,
    outcomes: OutcomeCounts,
    examples: [Option<RaySpec>; 6],
}

impl<V: Vector3> Prepared<V> {
    fn new(triangles: &[[[f64; 3]; 3]], ray_specs: &[RaySpec], source: &str) -> Result<Self> {
        let triangles = TriangleSet::from_f64(triangles);
        let reference = ReferenceScene::new(&triangles);
        Ok(Self {
            triangles,
            rays: convert_rays::<V>(ray_specs, source)?,
            reference,
        })
    }

    /// The reference's answer for every ray, on the machine's cores.
    fn references(&self) -> Result<Vec<Option<Reference>>> {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let chunk = self.rays.len().div_ceil(threads).max(1);
        std::thread::scope(|scope| {
            let workers: Vec<_> = self
                .rays
                .chunks(chunk)
                .map(|rays| {
                    scope.spawn(move || {
                        rays.iter()
                            .map(|ray| self.reference.reference(ray))
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            let mut all = Vec::with_capacity(self.rays.len());
            for worker in workers {
                all.extend(
                    worker
                        .join()
                        .map_err(|_| anyhow::anyhow!("a reference thread failed"))?,
                );
            }
            Ok(all)
        })
    }

    /// Untimed: the tree's statistics, the work counted, and every ray's outcome against
    /// `references`, with the first ray of each.
    fn evaluate(
        &self,
        accel: &Accel<V, TriangleSet<V>>,
        options: &TraceOptions,
        references: &[Option<Reference>],
        params: &BuildParams,
    ) -> Evaluated {
        let stats = accel.stats(self.triangles.len(), &params.cost);
        let mut stacks = accelviz_core::TraversalStacks::default();
        let mut counters = Counters::default();
        let mut outcomes = OutcomeCounts::default();
        let mut examples: [Option<RaySpec>; 6] = Default::default();
        for (ray, reference) in self.rays.iter().zip(references) {
            let got = accel
                .trace(ray, options, &mut stacks, &mut counters)
                .map(|hit| hit.primitive);
            let outcome = self
                .reference
                .classify(ray, reference.as_ref(), got, options.query);
            outcomes.add(outcome);
            let slot = &mut examples[outcome.index()];
            if slot.is_none() {
                // The ray as this precision rounded it: the ray file names exactly it.
                let exact = ray.cast::<DVec3>();
                *slot = Some(RaySpec {
                    line: 0,
                    origin: exact.origin.to_array(),
                    direction: exact.direction.to_array(),
                    t_min: exact.t_min,
                    t_max: exact.t_max,
                });
            }
        }
        Evaluated {
            stats,
            counters,
            outcomes,
            examples,
        }
    }
}

/// Writes each row's example rays to `dir`, one ray file per row.
fn write_examples(dir: &str, rows: &[Row], heading: &str) -> Result<()> {
    let dir = std::path::Path::new(dir);
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the directory", dir.display()))?;
    for row in rows {
        let mut text = format!(
            "# accelviz-cli tradeoff: one ray of each outcome of {} {} {} {}\n# {heading}\n",
            row.structure,
            row.order.name(),
            row.precision(),
            row.test()
        );
        for (outcome, example) in Outcome::ALL.iter().zip(&row.examples) {
            if let Some(ray) = example {
                text.push_str(&format!(
                    "# {}: {}\n{}\n",
                    outcome.name(),
                    outcome.about(),
                    ray_line(ray)
                ));
            }
        }
        let name = format!(
            "{}_{}_{}_{}.rays",
            row.structure.replace(':', "-"),
            row.order.name(),
            row.precision(),
            row.test()
        );
        let path = dir.join(name);
        std::fs::write(&path, text)
            .with_context(|| format!("{}: cannot write the file", path.display()))?;
    }
    Ok(())
}

impl Row {
    fn precision(&self) -> &'static str {
        if self.f64 { "f64" } else { "f32" }
    }

    fn test(&self) -> &'static str {
        if self.watertight {
            "watertight"
        } else {
            "fast"
        }
    }

    /// The table's cells: rounded for reading, or every digit (for CSV).
    fn cells(&self, params: &BuildParams, rounded: bool) -> Vec<String> {
        let number = |value: f64, digits: usize| {
            if rounded {
                format!("{value:.digits$}")
            } else {
                format!("{value}")
            }
        };
        let mut cells = vec![
            self.structure.clone(),
            self.order.name().to_owned(),
            self.precision().to_owned(),
            self.test().to_owned(),
            number(self.build_ms, 1),
            number(self.sah_cost, 1),
            self.epo.map_or_else(|| "".to_owned(), |epo| number(epo, 1)),
            number(self.measured_cost(params), 1),
            number(self.nodes_per_ray, 1),
            number(self.primitives_per_ray, 1),
            number(self.mrays_per_s, 2),
            number(self.trace_spread_percent, 0),
        ];
        cells.extend(
            Outcome::ALL
                .iter()
                .map(|&outcome| number(self.outcomes.per_million(outcome), 0)),
        );
        cells
    }

    /// The row as one JSON object.
    fn json(&self, params: &BuildParams, kind: RayKind, query: Query) -> String {
        let outcomes = crate::bench::outcomes_json(&self.outcomes);
        JsonObject::new()
            .string("structure", &self.structure)
            .string("order", self.order.name())
            .string("precision", self.precision())
            .string("test", self.test())
            .string("ray_kind", kind.name())
            .string("query", query_name(query))
            .number("build_ms", self.build_ms)
            .number("sah_cost", self.sah_cost)
            .number("epo", self.epo.unwrap_or(f64::NAN))
            .number("measured_cost", self.measured_cost(params))
            .number("nodes_per_ray", self.nodes_per_ray)
            .number("prims_per_ray", self.primitives_per_ray)
            .number("mrays_per_s", self.mrays_per_s)
            .number("spread_pct", self.trace_spread_percent)
            .raw("outcomes", &outcomes)
            .finish()
    }
}

/// The outcome columns' headings, in [`Outcome::ALL`]'s order.
const OUTCOME_HEADINGS: [&str; 6] = ["agree", "tie", "graze", "leak", "false hit", "wrong"];

fn markdown(rows: &[Row], heading: &str, params: &BuildParams) -> String {
    let outcomes: Vec<String> = OUTCOME_HEADINGS
        .iter()
        .map(|name| format!("{name} /M"))
        .collect();
    let mut out = format!(
        "{heading}. Outcomes per million rays, against a reference on the same rounded inputs: agree, tie (another triangle at the same point), graze (a silhouette point missed: rounding decides), leak (slipped through the surface), false hit, wrong. EPO: end-point overlap (Aila, Karras & Laine 2013), the cost of the surface inside boxes that is not theirs, in the SAH's units (BVHs, a wide one's that of the binary tree it was collapsed from; a kD-tree's cells do not overlap, so it has none). Measured cost: C_trav·nodes + C_isect·primitives per ray, comparable with the SAH cost.\n\n\
         | structure | order | precision | triangle test | build ms | SAH cost | EPO | measured cost | nodes/ray | prims/ray | Mrays/s | ±% | {} |\n\
         |---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|{}\n",
        outcomes.join(" | "),
        "---:|".repeat(Outcome::ALL.len())
    );
    for row in rows {
        out.push_str(&format!("| {} |\n", row.cells(params, true).join(" | ")));
    }
    out
}

fn csv(rows: &[Row], params: &BuildParams) -> String {
    let mut out = String::from(
        "structure,order,precision,triangle_test,build_ms,sah_cost,epo,measured_cost,nodes_per_ray,prims_per_ray,mrays_per_s,trace_spread_percent",
    );
    for outcome in Outcome::ALL {
        out.push_str(&format!(",{}_per_million", outcome.name()));
    }
    out.push('\n');
    for row in rows {
        out.push_str(&row.cells(params, false).join(","));
        out.push('\n');
    }
    out
}

/// The numbers of rays the break-even is reported at: 10³ to 10⁹.
const BREAK_EVEN_RAYS: [f64; 7] = [1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// Which structure is fastest overall (its build, then every ray) for each number of rays,
/// with the default switches (near first, f32, fast test): the rows' own figures.
struct BreakEven {
    contenders: Vec<Contender>,
    fastest: Vec<Fastest>,
    crossovers: Vec<Crossover>,
}

impl BreakEven {
    fn of(rows: &[Row]) -> Self {
        let contenders: Vec<Contender> = rows
            .iter()
            .filter(|row| (row.order, row.f64, row.watertight) == VARIANTS[0])
            .map(|row| Contender {
                name: row.structure.clone(),
                build_ms: row.build_ms,
                // Mrays/s is rays per microsecond: a thousand of them a millisecond.
                ms_per_ray: 1.0 / (row.mrays_per_s * 1e3),
            })
            .collect();
        let fastest = fastest_at(&contenders, &BREAK_EVEN_RAYS);
        let crossovers = crossovers(
            &contenders,
            BREAK_EVEN_RAYS[0],
            BREAK_EVEN_RAYS[BREAK_EVEN_RAYS.len() - 1],
        );
        Self {
            contenders,
            fastest,
            crossovers,
        }
    }

    fn name(&self, index: usize) -> &str {
        &self.contenders[index].name
    }

    fn markdown(&self) -> String {
        let mut out = String::from(
            "\nBreak-even: the total time of a build and N rays (build ms + N / (Mrays/s · 1000)), near first, f32, fast test; the fastest structure for each N and how much slower the next is.\n\n| rays | fastest | total ms | next fastest | slower by |\n|---:|---|---:|---|---:|\n",
        );
        for row in &self.fastest {
            let (next, ratio) = row.runner_up.map_or(("", String::new()), |(next, ratio)| {
                (self.name(next), format!("{ratio:.2}×"))
            });
            out.push_str(&format!(
                "| {:.0e} | {} | {:.1} | {next} | {ratio} |\n",
                row.rays,
                self.name(row.fastest),
                row.total_ms
            ));
        }
        if !self.crossovers.is_empty() {
            out.push_str("\nCrossovers: ");
            let said: Vec<String> = self
                .crossovers
                .iter()
                .map(|crossing| {
                    format!(
                        "{} gives way to {} at {:.3e} rays",
                        self.name(crossing.from),
                        self.name(crossing.to),
                        crossing.rays
                    )
                })
                .collect();
            out.push_str(&said.join("; "));
            out.push_str(".\n");
        }
        out
    }

    /// `{"break_even": [{"rays", "fastest", "total_ms"}, ...], "crossovers": [...]}`.
    fn json(&self) -> String {
        let rows: Vec<String> = self
            .fastest
            .iter()
            .map(|row| {
                JsonObject::new()
                    .number("rays", row.rays)
                    .string("fastest", self.name(row.fastest))
                    .number("total_ms", row.total_ms)
                    .finish()
            })
            .collect();
        let crossings: Vec<String> = self
            .crossovers
            .iter()
            .map(|crossing| {
                JsonObject::new()
                    .number("rays", crossing.rays)
                    .string("from", self.name(crossing.from))
                    .string("to", self.name(crossing.to))
                    .finish()
            })
            .collect();
        JsonObject::new()
            .raw("break_even", &format!("[{}]", rows.join(",")))
            .raw("crossovers", &format!("[{}]", crossings.join(",")))
            .finish()
    }

    /// Total time against rays: the structures fastest somewhere, and the lecture's three
    /// rules' BVHs for comparison, with the crossovers marked.
    fn plot(&self, mesh: &str) -> Lines {
        let mut shown: Vec<usize> = self.fastest.iter().map(|row| row.fastest).collect();
        shown.extend(
            self.crossovers
                .iter()
                .flat_map(|crossing| [crossing.from, crossing.to]),
        );
        for name in ["bvh:middle", "bvh:median", "bvh:sah-sweep", "kd:sah"] {
            if let Some(index) = self.contenders.iter().position(|c| c.name == name) {
                shown.push(index);
            }
        }
        shown.sort_unstable();
        shown.dedup();
        let samples: Vec<f64> = (0..=60)
            .map(|step| 10f64.powf(3.0 + 0.1 * step as f64))
            .collect();
        Lines {
            title: format!("Build + N rays: the fastest overall ({mesh})"),
            x_label: "rays traced (log scale)".into(),
            y_label: "total time, ms (log scale)".into(),
            lines: shown
                .iter()
                .map(|&index| {
                    let contender = &self.contenders[index];
                    let points = samples
                        .iter()
                        .map(|&rays| (rays, contender.total_ms(rays)))
                        .collect();
                    (contender.name.clone(), points)
                })
                .collect(),
            marks: self
                .crossovers
                .iter()
                .map(|crossing| {
                    (
                        crossing.rays,
                        format!("{:.2e}: {}", crossing.rays, self.name(crossing.to)),
                    )
                })
                .collect(),
            log: true,
        }
    }
}

/// The SAH's assumption against the rays: nodes entered per depth, predicted and measured.
fn sah_checks_markdown(checks: &[(String, SahCheck)]) -> String {
    let mut out = String::from(
        "\nThe SAH's assumption, checked (near first, f32, fast test): the nodes a ray entering the root enters at each depth, as the SAH predicts from the areas (rays from outside, uniformly spread, crossing the whole tree) and as these rays did; and the SAH cost again with the measured chances.\n\n",
    );
    for (name, check) in checks {
        out.push_str(&format!(
            "{name}: SAH cost {:.1}; with the measured chances {:.1} ({} rays entered the root).\n\n| depth | predicted | measured |\n|---:|---:|---:|\n",
            check.sah_cost, check.measured_chance_cost, check.rays_entering
        ));
        for (depth, predicted, measured) in &check.per_depth {
            out.push_str(&format!("| {depth} | {predicted:.2} | {measured:.2} |\n"));
        }
        out.push('\n');
    }
    out
}

fn sah_checks_plot(checks: &[(String, SahCheck)], mesh: &str, kind: RayKind) -> Lines {
    let mut lines = Vec::new();
    for (name, check) in checks {
        for (what, pick) in [
            (
                "SAH",
                (|entry: &(usize, f64, f64)| entry.1) as fn(&(usize, f64, f64)) -> f64,
            ),
            ("rays", |entry: &(usize, f64, f64)| entry.2),
        ] {
            lines.push((
                format!("{name} {what}"),
                check
                    .per_depth
                    .iter()
                    .map(|entry| (entry.0 as f64, pick(entry)))
                    .collect(),
            ));
        }
    }
    Lines {
        title: format!("Nodes per depth: SAH and {} rays ({mesh})", kind.name()),
        x_label: "depth".into(),
        y_label: "nodes entered at that depth, per ray".into(),
        lines,
        marks: Vec::new(),
        log: false,
    }
}
