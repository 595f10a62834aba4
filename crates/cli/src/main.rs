//! `accelviz-cli`: the headless accelviz. Queries rays against a mesh, shows the slab test's
//! numbers, and measures build time, traversal cost and speed of every acceleration structure.
//!
//! Every error is one line on stderr naming the file, the line and the problem, with exit
//! status 2 and nothing on stdout: output is assembled whole and printed only on success.

mod args;
mod bench;
mod heatmap;
mod json;
mod parallel;
mod plot;
mod progress;
mod query;
mod quiz;
mod sah;
mod slab;
mod spec;
mod timing;
mod tradeoff;

use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

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
    Query(query::QueryArgs),
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

fn run(cli: Cli) -> Result<String> {
    match cli.command {
        Command::Query(args) => query::run(&args),
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
