//! `query`: rays from a file traced against a mesh, one answer a line, in input order; the
//! file read a block at a time, checked whole before any answer is written.

use accelviz_core::params::BuildParams;
use accelviz_core::{NoObserver, TriangleSet, Vector3};
use accelviz_scene::Mesh;
use accelviz_scene::rays::{RayReader, RaySpec};
use anyhow::{Result, bail};
use clap::Args;

use crate::args::{BuildArgs, Precision, TraceArgs, convert_rays, mesh_help, structure_help};
use crate::parallel;
use crate::spec::AccelSpec;

#[derive(Args, Debug)]
pub struct QueryArgs {
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

/// Runs `query`: the answers go to stdout as they are made (nothing is returned to print).
pub fn run(args: &QueryArgs) -> Result<String> {
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
