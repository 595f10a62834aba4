//! `accelviz-cli`: the headless accelviz. Queries rays against a mesh, shows the slab test's
//! numbers, and measures build time, traversal cost and speed of every acceleration structure.
//!
//! Every error is one line on stderr naming the file, the line and the problem, with exit
//! status 2 and nothing on stdout: output is assembled whole and printed only on success.

mod bench;
mod heatmap;
mod json;
mod parallel;
mod plot;
mod progress;
mod quiz;
mod sah;
mod slab;
mod spec;
mod timing;
mod tradeoff;

use std::process::ExitCode;

use accelviz_core::params::BuildParams;
use accelviz_core::{NoObserver, Order, TraceOptions, TriangleSet, Vector3};
use accelviz_scene::Mesh;
use accelviz_scene::rays::{RayReader, RaySpec};
use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::spec::AccelSpec;

/// Ray-tracing acceleration structures, measured.
#[derive(Parser, Debug)]
#[command(name = "accelviz-cli", version, about, arg_required_else_help = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Trace rays from a file; print `HIT <triangle> <t>` or `MISS` per ray, in input order.
    Query(QueryArgs),
    /// The slab test of one ray and one box, axis by axis.
    Slab(slab::SlabArgs),
    /// Build and trace with each structure; report build time, cost and speed.
    Bench(bench::BenchArgs),
    /// The SAH cost of every candidate split of one node (exact and binned), with the leaf
    /// cost and where the middle, median and SAH rules cut.
    Sah(sah::SahArgs),
    /// Every structure and every speed/accuracy switch on the same rays, each ray's answer
    /// judged by a reference on the same rounded inputs: a table (Markdown, CSV), the
    /// break-even, and four SVG plots.
    Tradeoff(tradeoff::TradeoffArgs),
    /// The cost of every pixel of the benchmark's camera (nodes visited, box tests or
    /// primitive tests) as a PNG, with every pixel's counts as CSV if asked.
    Heatmap(heatmap::HeatmapArgs),
    /// Quiz questions made from a seed, with their answers: as text to print, or as JSON
    /// (one object per line). The app's quiz mode asks the same questions.
    Quiz(quiz::QuizArgs),
}

/// Traversal order.
#[derive(Clone, Copy, Debug, Default, ValueEnum, PartialEq, Eq)]
pub enum OrderArg {
    /// The child the ray enters first.
    #[default]
    NearFirst,
    /// Children in memory order.
    FileOrder,
}

/// Arithmetic precision: the core's, one for the whole project.
pub use accelviz_core::trade::Precision;

/// `--precision`'s values, parsed into the core's [`Precision`] (it knows nothing of clap).
fn precision_parser() -> impl clap::builder::TypedValueParser<Value = Precision> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    PossibleValuesParser::new([
        PossibleValue::new("f32").help("32-bit floats (fast)"),
        PossibleValue::new("f64").help("64-bit floats (accurate)"),
    ])
    .map(|name| match name.as_str() {
        "f64" => Precision::F64,
        _ => Precision::F32,
    })
}

/// Switches shared by `query` and `bench`.
#[derive(Args, Debug, Clone, Copy)]
pub struct TraceArgs {
    /// Child order when the ray hits both children. Default: near-first for the closest
    /// hit, file-order for any hit (ordering buys an occlusion query nothing, as in Embree's).
    #[arg(long, value_enum)]
    order: Option<OrderArg>,
    /// Arithmetic precision of the structure, the triangles and the rays.
    #[arg(long, value_parser = precision_parser(), default_value = "f32")]
    precision: Precision,
    /// Watertight triangle test (Woop et al. 2013) and conservative box test (Ize 2013).
    #[arg(long)]
    robust: bool,
    /// kD-trees: test a primitive listed in several leaves once per ray (a mailbox).
    #[arg(long)]
    mailbox: bool,
    /// closest, or any (is anything in the way?). Default: any for shadow and ao rays,
    /// closest otherwise.
    #[arg(long, value_parser = accelviz_core::Query::parse)]
    query: Option<accelviz_core::Query>,
}

/// The build parameters shared by `query` and `bench`.
#[derive(Args, Debug, Clone, Copy)]
pub struct BuildArgs {
    /// Nodes with more primitives are always split (SAH builders may stop earlier).
    #[arg(long, default_value_t = BuildParams::default().max_leaf_size)]
    max_leaf_size: usize,
    /// SAH cost of visiting an interior node, C_trav.
    #[arg(long, default_value_t = BuildParams::default().cost.traversal_cost)]
    traversal_cost: f64,
    /// SAH cost of one ray/triangle test, C_isect.
    #[arg(long, default_value_t = BuildParams::default().cost.intersection_cost)]
    intersection_cost: f64,
    /// kD SAH: the share by which a cut leaving one side empty is made cheaper (0 to 1).
    #[arg(long, default_value_t = BuildParams::default().cost.empty_bonus)]
    empty_bonus: f64,
}

impl BuildArgs {
    /// The core's parameters, checked.
    pub fn params(&self) -> Result<BuildParams> {
        let costs = [self.traversal_cost, self.intersection_cost];
        if costs.iter().any(|cost| !cost.is_finite() || *cost <= 0.0) {
            anyhow::bail!("--traversal-cost and --intersection-cost must be positive numbers");
        }
        if !(0.0..=1.0).contains(&self.empty_bonus) {
            anyhow::bail!("--empty-bonus must be a number from 0 to 1");
        }
        if self.max_leaf_size == 0 {
            anyhow::bail!("--max-leaf-size must be at least 1");
        }
        Ok(BuildParams {
            max_leaf_size: self.max_leaf_size,
            cost: accelviz_core::SahCost {
                traversal_cost: self.traversal_cost,
                intersection_cost: self.intersection_cost,
                empty_bonus: self.empty_bonus,
            },
            ..BuildParams::default()
        })
    }
}

impl Default for BuildArgs {
    fn default() -> Self {
        let params = BuildParams::default();
        Self {
            max_leaf_size: params.max_leaf_size,
            traversal_cost: params.cost.traversal_cost,
            intersection_cost: params.cost.intersection_cost,
            empty_bonus: params.cost.empty_bonus,
        }
    }
}

impl TraceArgs {
    /// The core's options, with `--query` or else the closest hit.
    pub fn options(&self) -> TraceOptions {
        self.options_for(None)
    }

    /// The core's options for rays of `kind`: `--query`, or else the query such rays ask.
    pub fn options_for(&self, kind: Option<accelviz_scene::rays::RayKind>) -> TraceOptions {
        let query = self
            .query
            .or(kind.map(|kind| kind.default_query()))
            .unwrap_or_default();
        TraceOptions {
            query,
            order: match self.order {
                Some(OrderArg::NearFirst) => Order::NearFirst,
                Some(OrderArg::FileOrder) => Order::FileOrder,
                None => query.default_order(),
            },
            mailboxing: self.mailbox,
            ..TraceOptions::default()
        }
        .with_robust(self.robust)
    }
}

#[derive(Args, Debug)]
struct QueryArgs {
    // The help of `--mesh` and `--accel` is written from the built-in mesh table and the
    // structure catalogue, so it lists every one there is.
    #[arg(long, help = mesh_help())]
    mesh: String,
    #[arg(long, help = structure_help("The structure"))]
    accel: String,
    /// Ray file: `ox oy oz dx dy dz [tmin tmax]` per line, `#` starts a comment. Read twice,
    /// a line at a time: first every line is checked (a bad line is reported and nothing is
    /// written), then rays are traced and answered in batches, so a file of any size takes
    /// little memory.
    #[arg(long)]
    rays: String,
    /// Threads tracing each batch of rays, in tiles of 256 (the answers are the same, in the
    /// same order).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    #[command(flatten)]
    trace: TraceArgs,
    #[command(flatten)]
    build: BuildArgs,
}

/// `--mesh`'s help: every built-in mesh, from the scene crate's table.
pub fn mesh_help() -> String {
    let names: Vec<&str> = accelviz_scene::builtin::BUILTINS
        .iter()
        .map(|builtin| builtin.name)
        .collect();
    format!(
        "The mesh: an OBJ file, or builtin:NAME, NAME one of {}",
        names.join(", ")
    )
}

/// Parses `--repeat`: at least one round.
pub fn parse_rounds(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(0) => Err("at least one round is needed".to_owned()),
        Ok(rounds) => Ok(rounds),
        Err(_) => Err(format!("'{text}' is not a number of rounds")),
    }
}

/// `--accel`'s help (`what` names it): every structure of the catalogue.
pub fn structure_help(what: &str) -> String {
    format!(
        "{what}: brute (every triangle), or {}; a BVH of 4 or 8 children as bvh4:… or bvh8:… (bvh8:sah-binned)",
        accelviz_core::structure::valid_names()
    )
}

/// Converts rays to the chosen precision, naming the line of any that cannot be.
pub fn convert_rays<V: Vector3>(
    rays: &[RaySpec],
    source: &str,
) -> Result<Vec<accelviz_core::Ray<V>>> {
    rays.iter()
        .map(|spec| {
            spec.to_ray::<V>()
                .with_context(|| format!("{source}:{}: bad ray", spec.line))
        })
        .collect()
}

/// The rays of `source` for `mesh`, in `V`'s precision. A ray file is read a line at a time,
/// each ray kept only as `V` has it (32 bytes in f32: 10 million rays in 320 MB, where the
/// file's text and its rays in f64 took 2 GB); generated rays are made, then converted.
pub fn rays_of<V: Vector3>(
    source: &accelviz_scene::rays::RaySource,
    mesh: &Mesh,
) -> Result<Vec<accelviz_core::Ray<V>>> {
    match source {
        accelviz_scene::rays::RaySource::File(path) => {
            let mut rays = Vec::new();
            for spec in RayReader::open(path)? {
                let spec = spec?;
                rays.push(
                    spec.to_ray::<V>()
                        .with_context(|| format!("{path}:{}: bad ray", spec.line))?,
                );
            }
            Ok(rays)
        }
        _ => convert_rays(&source.rays(mesh)?, &source.label()),
    }
}

/// Bytes of the ray file read, parsed, traced and answered at a time by `query` (about
/// 40,000 rays).
const QUERY_BLOCK_BYTES: usize = 1 << 21;

/// The rays of one block of a ray file (lines from `first_line` on), parsed on `workers`;
/// the first bad line's error if any.
fn parse_block(
    workers: &parallel::Workers,
    first_line: usize,
    text: &str,
    path: &str,
) -> Result<Vec<RaySpec>> {
    let lines: Vec<(usize, &str)> = (first_line..).zip(text.lines()).collect();
    let parsed = workers.map(
        &lines,
        || (),
        |_, &(number, line)| accelviz_scene::rays::parse_ray_line(line, number, path),
    );
    let mut rays = Vec::with_capacity(parsed.len());
    for ray in parsed {
        rays.extend(ray?);
    }
    Ok(rays)
}

fn query(args: &QueryArgs) -> Result<String> {
    let spec = AccelSpec::parse(&args.accel)?;
    let params = args.build.params()?;
    let workers = parallel::Workers::new(args.threads)?;
    let mesh = accelviz_scene::builtin::load_mesh(&args.mesh)?;
    // The first pass checks every line, so that bad input stops the query before any output.
    let mut ray_count = 0usize;
    let mut reader = RayReader::open(&args.rays)?;
    while let Some(block) = reader.next_block(QUERY_BLOCK_BYTES) {
        let (first_line, text) = block?;
        ray_count += parse_block(&workers, first_line, &text, &args.rays)?.len();
    }
    let mut out = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
    let written = match args.trace.precision {
        Precision::F32 => query_in::<glam::Vec3>(spec, &params, &mesh, &workers, args, &mut out),
        Precision::F64 => query_in::<glam::DVec3>(spec, &params, &mesh, &workers, args, &mut out),
    };
    let written = written.and_then(|count| {
        use std::io::Write;
        out.flush()?;
        Ok(count)
    });
    match written {
        Ok(count) if count != ray_count => bail!(
            "{}: the file changed while it was read ({ray_count} rays, then {count})",
            args.rays
        ),
        Ok(_) => Ok(String::new()),
        // A closed pipe (e.g. `| head`) is not an error worth reporting.
        Err(error)
            if error
                .downcast_ref::<std::io::Error>()
                .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe) =>
        {
            Ok(String::new())
        }
        Err(error) => Err(error),
    }
}

/// Traces the rays of `args.rays` block by block, writing one line per ray; returns how many.
fn query_in<V: Vector3>(
    spec: AccelSpec,
    params: &BuildParams,
    mesh: &Mesh,
    workers: &parallel::Workers,
    args: &QueryArgs,
    out: &mut impl std::io::Write,
) -> Result<usize> {
    let triangles = TriangleSet::<V>::from_f64(&mesh.triangles);
    let (accel, _) = spec.build(&triangles, params);
    let options = args.trace.options();
    // f32 needs 9 significant digits to round-trip, f64 17.
    let digits = if size_of::<V::Scalar>() == 4 { 8 } else { 16 };
    let mut reader = RayReader::open(&args.rays)?;
    let mut count = 0;
    let mut text = String::new();
    while let Some(block) = reader.next_block(QUERY_BLOCK_BYTES) {
        let (first_line, block) = block?;
        let batch = parse_block(workers, first_line, &block, &args.rays)?;
        let rays = convert_rays::<V>(&batch, &args.rays)?;
        let answers = workers.map(
            &rays,
            accelviz_core::TraversalStacks::default,
            |stacks, ray| accel.trace(ray, &options, stacks, &mut NoObserver),
        );
        text.clear();
        for answer in answers {
            use std::fmt::Write;
            match answer {
                Some(hit) => {
                    let t = accelviz_core::Real::to_f64(hit.t);
                    let _ = writeln!(text, "HIT {} {t:.digits$e}", hit.primitive);
                }
                None => text.push_str("MISS\n"),
            }
        }
        out.write_all(text.as_bytes())?;
        count += batch.len();
    }
    Ok(count)
}

fn run(cli: Cli) -> Result<String> {
    match cli.command {
        Command::Query(args) => query(&args),
        Command::Slab(args) => slab::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Sah(args) => sah::run(&args),
        Command::Tradeoff(args) => tradeoff::run(&args),
        Command::Heatmap(args) => heatmap::run(&args),
        Command::Quiz(args) => quiz::run(&args),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = run(cli);
    progress::clear();
    match result {
        Ok(output) => {
            use std::io::Write;
            let mut stdout = std::io::stdout().lock();
            // A closed pipe (e.g. `| head`) is not an error worth a panic.
            let _ = stdout.write_all(output.as_bytes());
            let _ = stdout.flush();
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("accelviz-cli: error: {error:#}");
            ExitCode::from(2)
        }
    }
}
