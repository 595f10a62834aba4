//! `accelviz-cli tradeoff`: every structure and every speed/accuracy switch on the same rays,
//! each ray's answer held to a reference on the same rounded inputs
//! ([`accelviz_core::outcome`]); a table (Markdown, CSV, JSON), two SVG plots, and an example
//! ray of each outcome.

use accelviz_core::break_even::{BreakEven, plotted};
use accelviz_core::outcome::{Outcome, Reference};
use accelviz_core::params::BuildParams;
use accelviz_core::quality::{NodeEntries, SahCheck};
use accelviz_core::trade::{Precision, Switches, TradeRow, TradeScene, TreeQuality, contenders};
use accelviz_core::trade_lab::structures_a_group;
use accelviz_core::{Query, Structure, TriangleSet, Vector3};
use accelviz_scene::rays::{RayKind, RaySpec, parse_resolution, ray_line};
use anyhow::{Context, Result, bail};
use clap::Args;
use glam::{DVec3, Vec3};

use crate::args::{BuildArgs, convert_rays};
use crate::json::JsonObject;
use crate::parallel::Workers;
use crate::plot::{Lines, Point, Scatter};
use crate::spec::{Accel, AccelSpec};
use crate::timing::interleaved;
use accelviz_scene::builtin::load_mesh;

#[derive(Args, Debug)]
pub struct TradeoffArgs {
    #[arg(long, default_value = "builtin:lumpy-sphere", help = crate::args::mesh_help())]
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
    /// f32 slip through: a seeded random sample of `--rays` of the 18 a triangle), shadow (from camera hits to a point light), ao (short rays from
    /// camera hits), bounce (a diffuse bounce from each camera hit).
    #[arg(long, default_value = "random", value_parser = RayKind::parse)]
    ray_kind: RayKind,
    /// The same as `--ray-kind aimed`.
    #[arg(long, conflicts_with = "ray_kind")]
    aimed: bool,
    /// The camera image for `--ray-kind camera`, WIDTHxHEIGHT (else about `--rays` pixels);
    /// for shadow, ao and bounce rays, the rays from every pixel's hit, in 8×8 tiles of pixels
    /// (else about `--rays` from random pixels).
    #[arg(long)]
    camera: Option<String>,
    /// closest or any (is anything in the way?). Default: any for shadow and ao rays, closest
    /// otherwise.
    #[arg(long, value_parser = Query::parse)]
    query: Option<Query>,
    /// Write tradeoff.md, tradeoff.csv and the plots build-vs-traversal.svg,
    /// predicted-vs-measured.svg, total-vs-rays.svg and sah-assumption.svg here (created if
    /// missing). Without it, the table goes to stdout.
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
    /// interleaved; each figure is the median of its rounds, with the range it moved in
    /// (with one round, the range says nothing and no winner is named).
    #[arg(long, default_value_t = 5, value_parser = crate::args::parse_rounds)]
    repeat: usize,
    /// Threads tracing rays, in tiles of 256 (builds are single-threaded).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    #[command(flatten)]
    build: BuildArgs,
}

/// The trees whose SAH assumption the report checks against the rays.
const SAH_CHECKED: [&str; 2] = ["bvh:sah-binned:16", "kd:sah"];

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
    let specs: Vec<Structure> = Structure::compared();
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
    let rays = convert_rays::<DVec3>(&ray_specs, &source)?;
    let single = TradeScene::<Vec3>::new(&mesh.triangles, &rays);
    let double = TradeScene::<DVec3>::new(&mesh.triangles, &rays);
    let (reference32, reference64) = (references(&single)?, references(&double)?);
    // The structures in groups whose trees fit the core's memory budget (all of them at once
    // on a small mesh): within a group, every structure built in both precisions once per
    // round (a configuration is a structure and a precision, the first round's trees kept),
    // then every row (a structure and a switch setting) traced once per round, judged, and
    // the group's trees let go. All nineteen structures' trees of a 269k-triangle mesh at
    // once took 2 GB.
    let group = structures_a_group(mesh.triangles.len(), specs.len());
    let groups = specs.len().div_ceil(group);
    let mut rows = Vec::with_capacity(specs.len() * Switches::ALL.len());
    let mut checks: Vec<(String, SahCheck)> = Vec::new();
    for (number, first) in (0..specs.len()).step_by(group).enumerate() {
        let members: Vec<usize> = (first..(first + group).min(specs.len())).collect();
        let part = if groups == 1 {
            String::new()
        } else {
            format!(" (group {} of {groups})", number + 1)
        };
        let mut trees32: Vec<Option<Accel<Vec3, TriangleSet<Vec3>>>> =
            members.iter().map(|_| None).collect();
        let mut trees64: Vec<Option<Accel<DVec3, TriangleSet<DVec3>>>> =
            members.iter().map(|_| None).collect();
        let builds = interleaved(
            &format!("tradeoff: builds{part}"),
            repeat,
            members.len() * 2,
            |index| {
                let spec = AccelSpec::Tree(specs[members[index / 2]]);
                if index % 2 == 0 {
                    let (tree, _) = spec.build(&single.triangles, &params);
                    trees32[index / 2].get_or_insert(tree);
                } else {
                    let (tree, _) = spec.build(&double.triangles, &params);
                    trees64[index / 2].get_or_insert(tree);
                }
            },
        );
        let trees32: Vec<_> = trees32.into_iter().flatten().collect();
        let trees64: Vec<_> = trees64.into_iter().flatten().collect();
        let keys: Vec<(usize, Switches)> = (0..members.len())
            .flat_map(|member| Switches::ALL.map(|switches| (member, switches)))
            .collect();
        let traces = interleaved(
            &format!("tradeoff: traces{part}"),
            repeat,
            keys.len(),
            |index| {
                let (member, switches) = keys[index];
                let options = switches.options(query);
                let hits = match switches.precision {
                    Precision::F64 => trees64[member].count_hits(&double.rays, &options, &workers),
                    Precision::F32 => trees32[member].count_hits(&single.rays, &options, &workers),
                };
                std::hint::black_box(hits);
            },
        );
        // Each tree's end-point overlap and memory, once (every switch setting of a tree
        // shares them).
        let quality32: Vec<TreeQuality> = trees32
            .iter()
            .map(|accel| quality(accel, single.triangles.triangles(), &params))
            .collect();
        let quality64: Vec<TreeQuality> = trees64
            .iter()
            .map(|accel| quality(accel, double.triangles.triangles(), &params))
            .collect();
        for (index, &(member, switches)) in keys.iter().enumerate() {
            crate::progress::report(
                &format!("tradeoff: each row's rays judged{part}"),
                index,
                keys.len(),
            );
            let options = switches.options(query);
            let (evaluation, quality) = match switches.precision {
                Precision::F64 => {
                    let Accel::Tree(tree, ordered) = &trees64[member] else {
                        bail!("the tradeoff compares trees only")
                    };
                    (
                        double.evaluate(tree, ordered, &options, &reference64, &params),
                        quality64[member],
                    )
                }
                Precision::F32 => {
                    let Accel::Tree(tree, ordered) = &trees32[member] else {
                        bail!("the tradeoff compares trees only")
                    };
                    (
                        single.evaluate(tree, ordered, &options, &reference32, &params),
                        quality32[member],
                    )
                }
            };
            let builds = &builds[2 * member + usize::from(switches.precision == Precision::F64)];
            rows.push(TradeRow::new(
                (specs[members[member]], switches),
                (builds, &traces[index]),
                evaluation,
                quality,
                rays.len(),
            ));
        }
        // The SAH's chances against these rays', for the binned SAH's BVH and the kD SAH
        // tree, while their trees are here.
        for (member, &spec) in members.iter().enumerate() {
            let name = specs[spec].name();
            if !SAH_CHECKED.contains(&name.as_str()) {
                continue;
            }
            let accel = &trees32[member];
            let Some(facts) = accel.binary_facts() else {
                continue;
            };
            let mut entries = NodeEntries::new(facts.bounds.len());
            let mut stacks = accelviz_core::TraversalStacks::default();
            let options = Switches::BASE.options(query);
            for ray in &single.rays {
                accel.trace(ray, &options, &mut stacks, &mut entries);
            }
            checks.push((
                name.to_string(),
                SahCheck::of(&facts, &entries, &params.cost),
            ));
        }
    }
    checks.sort_by_key(|(name, _)| SAH_CHECKED.iter().position(|checked| checked == name));
    // Structures interleave with the others of their group only, measured one group after
    // another: said, since a drift between groups is not spread over every row.
    let grouping = if groups == 1 {
        String::new()
    } else {
        format!(", structures in groups of {group} to bound memory (interleaved within a group)")
    };
    let heading = format!(
        "{} ({} triangles), {} {} rays (seed {}), {} hit, C_trav {}, C_isect {}, kD empty bonus {}, {} thread(s), median of {repeat} interleaved rounds{grouping} (±: half their range; rows whose ranges overlap are not shown to differ)",
        args.mesh,
        mesh.triangles.len(),
        ray_specs.len(),
        kind.name(),
        args.seed,
        query.name(),
        params.cost.traversal_cost,
        params.cost.intersection_cost,
        params.cost.empty_bonus,
        args.threads,
    );
    if let Some(dir) = &args.examples {
        write_examples(dir, &rows, &heading)?;
    }
    let break_even = BreakEvenReport::of(&rows, repeat);
    if args.json {
        let mut lines: Vec<String> = rows
            .iter()
            .map(|row| json(row, &params, kind, query))
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
    let base: Vec<&TradeRow> = rows
        .iter()
        .filter(|row| row.switches == Switches::BASE)
        .collect();
    // Every family the rows hold, in the catalogue's order, a colour each.
    let present: Vec<accelviz_core::Family> = accelviz_core::Family::ALL
        .into_iter()
        .filter(|family| base.iter().any(|row| row.structure.family() == *family))
        .collect();
    let family = |row: &TradeRow| {
        present
            .iter()
            .position(|family| *family == row.structure.family())
            .unwrap_or(0)
    };
    let families: Vec<String> = present
        .iter()
        .map(|family| family.label().to_owned())
        .collect();
    let cost_label = "cost per ray: C_trav·nodes + C_isect·primitives";
    // One point per structure: `x` of the row against its measured cost.
    let points = |x: fn(&TradeRow) -> f64| -> Vec<Point> {
        base.iter()
            .map(|row| Point {
                x: x(row),
                y: row.measured_cost(&params),
                label: row.structure.name(),
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
        ("tradeoff.csv", accelviz_core::trade::csv(&rows, &params)),
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

/// A built tree's quality (the tradeoff builds trees only).
fn quality<V: Vector3>(
    accel: &Accel<V, TriangleSet<V>>,
    triangles: &[[V; 3]],
    params: &BuildParams,
) -> TreeQuality {
    match accel {
        Accel::Tree(tree, _) => TreeQuality::of(tree, triangles, params),
        Accel::Brute(_) => TreeQuality {
            epo: None,
            footprint: accel.footprint().0,
        },
    }
}

/// The reference's answer for every ray of `scene`, on the machine's cores.
fn references<V: Vector3>(scene: &TradeScene<V>) -> Result<Vec<Option<Reference>>> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = scene.rays.len().div_ceil(threads).max(1);
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..scene.rays.len())
            .step_by(chunk)
            .map(|start| {
                let end = (start + chunk).min(scene.rays.len());
                scope.spawn(move || scene.references(start..end))
            })
            .collect();
        let mut all = Vec::with_capacity(scene.rays.len());
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

/// Writes each row's example rays to `dir`, one ray file per row.
fn write_examples(dir: &str, rows: &[TradeRow], heading: &str) -> Result<()> {
    let dir = std::path::Path::new(dir);
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the directory", dir.display()))?;
    for row in rows {
        let switches = row.switches;
        let mut text = format!(
            "# accelviz-cli tradeoff: one ray of each outcome of {} {} {} {}\n# {heading}\n",
            row.structure.name(),
            switches.order.name(),
            switches.precision.name(),
            switches.test_name()
        );
        for (outcome, example) in Outcome::ALL.iter().zip(&row.examples) {
            if let Some(ray) = example {
                // The ray as the row's precision rounded it: the ray file names exactly it.
                let spec = RaySpec {
                    line: 0,
                    origin: ray.origin.to_array(),
                    direction: ray.direction.to_array(),
                    t_min: ray.t_min,
                    t_max: ray.t_max,
                };
                text.push_str(&format!(
                    "# {}: {}\n{}\n",
                    outcome.name(),
                    outcome.about(),
                    ray_line(&spec)
                ));
            }
        }
        let name = format!(
            "{}_{}_{}_{}.rays",
            row.structure.name().replace(':', "-"),
            switches.order.name(),
            switches.precision.name(),
            switches.test_name()
        );
        let path = dir.join(name);
        std::fs::write(&path, text)
            .with_context(|| format!("{}: cannot write the file", path.display()))?;
    }
    Ok(())
}

/// The table's cells of `row`, rounded for reading.
fn cells(row: &TradeRow, params: &BuildParams) -> Vec<String> {
    let switches = row.switches;
    let mut cells = vec![
        row.structure.name(),
        switches.order.name().to_owned(),
        switches.precision.name().to_owned(),
        switches.test_name().to_owned(),
        format!("{:.1}", row.build_ms),
        format!("{:.1}", row.sah_cost),
        row.epo.map_or_else(String::new, |epo| format!("{epo:.1}")),
        format!("{:.1}", row.measured_cost(params)),
        format!("{:.1}", row.nodes_per_ray),
        format!("{:.1}", row.primitives_per_ray),
        format!("{:.2}", row.mrays_per_s),
        format!("{:.0}", row.trace_spread_percent),
    ];
    cells.extend(
        Outcome::ALL
            .iter()
            .map(|&outcome| format!("{:.0}", row.outcomes.per_million(outcome))),
    );
    cells
}

/// `row` as one JSON object.
fn json(row: &TradeRow, params: &BuildParams, kind: RayKind, query: Query) -> String {
    let outcomes = crate::json::outcomes_json(&row.outcomes);
    JsonObject::new()
        .string("structure", &row.structure.name())
        .string("order", row.switches.order.name())
        .string("precision", row.switches.precision.name())
        .string("test", row.switches.test_name())
        .string("ray_kind", kind.name())
        .string("query", query.name())
        .number("build_ms", row.build_ms)
        .number("sah_cost", row.sah_cost)
        .number("epo", row.epo.unwrap_or(f64::NAN))
        .number("bytes", row.bytes as f64)
        .number("measured_cost", row.measured_cost(params))
        .number("nodes_per_ray", row.nodes_per_ray)
        .number("prims_per_ray", row.primitives_per_ray)
        .number("mrays_per_s", row.mrays_per_s)
        .number("spread_pct", row.trace_spread_percent)
        .raw("outcomes", &outcomes)
        .finish()
}

/// The outcome columns' headings, in [`Outcome::ALL`]'s order.
const OUTCOME_HEADINGS: [&str; 6] = ["agree", "tie", "graze", "leak", "false hit", "wrong"];

fn markdown(rows: &[TradeRow], heading: &str, params: &BuildParams) -> String {
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
        out.push_str(&format!("| {} |\n", cells(row, params).join(" | ")));
    }
    let summary = accelviz_core::trade_summary::summary(rows);
    if !summary.is_empty() {
        out.push('\n');
        out.push_str(&summary.join(" "));
        out.push('\n');
    }
    out
}

/// Which structure is fastest overall (its build, then every ray) for each number of rays,
/// with the default switches (near first, f32, fast test): the core's break-even of the rows'
/// own figures, written out.
struct BreakEvenReport(BreakEven);

impl BreakEvenReport {
    fn of(rows: &[TradeRow], rounds: usize) -> Self {
        let (contenders, _) = contenders(rows);
        Self(BreakEven::of(contenders, rounds))
    }

    fn name(&self, index: usize) -> &str {
        self.0.name(index)
    }

    fn markdown(&self) -> String {
        let mut out = String::from(
            "\nBreak-even: the total time of a build and N rays (build ms + N / (Mrays/s · 1000)), near first, f32, fast test; the fastest structure for each N by the medians, how much slower the next is, and the structures whose rounds' ranges overlap the fastest's (then no winner is clear).\n\n| rays | fastest | total ms | next fastest | slower by | within the spread |\n|---:|---|---:|---|---:|---|\n",
        );
        for row in &self.0.fastest {
            let (next, ratio) = row.runner_up.map_or(("", String::new()), |(next, ratio)| {
                (self.name(next), format!("{ratio:.2}×"))
            });
            let tied: Vec<&str> = row
                .within_spread
                .iter()
                .map(|&index| self.name(index))
                .collect();
            let fastest = if row.is_clear() {
                self.name(row.fastest).to_owned()
            } else {
                format!(
                    "no clear winner ({} by the medians)",
                    self.name(row.fastest)
                )
            };
            out.push_str(&format!(
                "| {:.0e} | {fastest} | {:.1} | {next} | {ratio} | {} |\n",
                row.rays,
                row.total_ms,
                tied.join(", ")
            ));
        }
        let verdict = self.0.verdict();
        if !verdict.is_empty() {
            out.push('\n');
            out.push_str(&verdict.join(" "));
            out.push('\n');
        }
        out
    }

    /// `{"break_even": [{"rays", "fastest", "clear", "within_spread", "total_ms"}, ...],
    /// "crossovers": [{"rays", "from", "to", "clear_between"}], "verdict": [...]}`.
    fn json(&self) -> String {
        let rows: Vec<String> = self
            .0
            .fastest
            .iter()
            .map(|row| {
                let tied: Vec<String> = row
                    .within_spread
                    .iter()
                    .map(|&index| crate::json::string(self.name(index)))
                    .collect();
                JsonObject::new()
                    .number("rays", row.rays)
                    .string("fastest", self.name(row.fastest))
                    .boolean("clear", row.is_clear())
                    .raw("within_spread", &format!("[{}]", tied.join(",")))
                    .number("total_ms", row.total_ms)
                    .finish()
            })
            .collect();
        let crossings: Vec<String> = self
            .0
            .crossovers
            .iter()
            .map(|crossing| {
                let clear = crossing.clear_between.map_or_else(
                    || "null".to_owned(),
                    |(low, high)| {
                        format!(
                            "[{},{}]",
                            crate::json::number(low),
                            crate::json::number(high)
                        )
                    },
                );
                JsonObject::new()
                    .number("rays", crossing.rays)
                    .string("from", self.name(crossing.from))
                    .string("to", self.name(crossing.to))
                    .raw("clear_between", &clear)
                    .finish()
            })
            .collect();
        let verdict: Vec<String> = self
            .0
            .verdict()
            .iter()
            .map(|s| crate::json::string(s))
            .collect();
        JsonObject::new()
            .raw("break_even", &format!("[{}]", rows.join(",")))
            .raw("crossovers", &format!("[{}]", crossings.join(",")))
            .raw("verdict", &format!("[{}]", verdict.join(",")))
            .finish()
    }

    /// Total time against rays: the structures fastest somewhere, and the lecture's three
    /// rules' BVHs for comparison, with the crossovers the rounds tell apart marked.
    fn plot(&self, mesh: &str) -> Lines {
        let shown = plotted(&self.0);
        let samples: Vec<f64> = (0..=60)
            .map(|step| 10f64.powf(3.0 + 0.1 * step as f64))
            .collect();
        Lines {
            title: format!("Build + N rays, medians of the rounds ({mesh})"),
            x_label: "rays traced (log scale)".into(),
            y_label: "total time, ms (log scale)".into(),
            lines: shown
                .iter()
                .map(|&index| {
                    let contender = &self.0.contenders[index];
                    let points = samples
                        .iter()
                        .map(|&rays| (rays, contender.total_ms(rays)))
                        .collect();
                    (contender.name.clone(), points)
                })
                .collect(),
            marks: self
                .0
                .crossovers
                .iter()
                .filter(|crossing| crossing.clear_between.is_some())
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
