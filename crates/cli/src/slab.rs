//! `accelviz-cli slab`: the slab test's numbers for one box and one ray, in 2D or 3D.

use accelviz_core::{Aabb, Ray, Real, SlabRecord, Vector, slab_record};
use anyhow::{Context, Result, bail};
use clap::Args;

use crate::args::Precision;
use crate::json::{JsonObject, number};

#[derive(Args, Debug)]
pub struct SlabArgs {
    /// The box: "x0 y0 z0 x1 y1 z1" (3D) or "x0 y0 x1 y1" (2D).
    #[arg(long = "box", allow_hyphen_values = true)]
    bounds: String,
    /// The ray: "ox oy oz dx dy dz" (3D) or "ox oy dx dy" (2D); its interval is [0, +inf).
    #[arg(long, allow_hyphen_values = true)]
    ray: String,
    /// Print one JSON object (±infinity is written 1e999 / -1e999).
    #[arg(long)]
    json: bool,
    /// Arithmetic precision.
    #[arg(long, value_parser = crate::args::precision_parser(), default_value = "f64")]
    precision: Precision,
    /// Widen every t_far conservatively (Ize 2013).
    #[arg(long)]
    robust: bool,
}

fn numbers(text: &str, what: &str) -> Result<Vec<f64>> {
    text.split_whitespace()
        .map(|word| {
            word.parse::<f64>()
                .ok()
                .filter(|value| value.is_finite())
                .with_context(|| format!("--{what}: '{word}' is not a finite number"))
        })
        .collect()
}

pub fn run(args: &SlabArgs) -> Result<String> {
    let bounds = numbers(&args.bounds, "box")?;
    let ray = numbers(&args.ray, "ray")?;
    match (bounds.len(), ray.len(), args.precision) {
        (6, 6, Precision::F64) => report::<glam::DVec3>(&bounds, &ray, args),
        (6, 6, Precision::F32) => report::<glam::Vec3>(&bounds, &ray, args),
        (4, 4, Precision::F64) => report::<glam::DVec2>(&bounds, &ray, args),
        (4, 4, Precision::F32) => report::<glam::Vec2>(&bounds, &ray, args),
        (b, r, _) => {
            bail!("--box has {b} numbers and --ray has {r}: give 6 and 6 (3D) or 4 and 4 (2D)")
        }
    }
}

fn report<V: Vector>(bounds: &[f64], ray: &[f64], args: &SlabArgs) -> Result<String> {
    let dim = V::DIM;
    let (min, max) = (
        V::from_f64_slice(&bounds[..dim]),
        V::from_f64_slice(&bounds[dim..]),
    );
    if (0..dim).any(|axis| min[axis] > max[axis]) {
        bail!("--box: each minimum must be at most its maximum (\"x0 y0 .. x1 y1 ..\")");
    }
    let ray = Ray::try_new(
        V::from_f64_slice(&ray[..dim]),
        V::from_f64_slice(&ray[dim..]),
    )
    .map_err(|error| anyhow::anyhow!("--ray: {error}"))?;
    let record = slab_record(&Aabb::new(min, max), &ray, args.robust);
    Ok(if args.json {
        as_json(&record)
    } else {
        as_text(&record)
    })
}

const AXES: [&str; 3] = ["x", "y", "z"];

fn as_text<V: Vector>(record: &SlabRecord<V>) -> String {
    let mut text = String::new();
    for (axis, name) in AXES.iter().enumerate().take(V::DIM) {
        text.push_str(&format!(
            "{name}: t_near = {}, t_far = {}\n",
            record.t_near[axis].to_f64(),
            record.t_far[axis].to_f64()
        ));
    }
    text.push_str(&format!(
        "t_enter = {} (max of the nears)\nt_exit = {} (min of the fars)\n{}\n",
        record.t_enter.to_f64(),
        record.t_exit.to_f64(),
        if record.hit { "HIT" } else { "MISS" }
    ));
    text
}

fn as_json<V: Vector>(record: &SlabRecord<V>) -> String {
    let axes: Vec<String> = (0..V::DIM)
        .map(|axis| {
            JsonObject::new()
                .number("t_near", record.t_near[axis].to_f64())
                .number("t_far", record.t_far[axis].to_f64())
                .finish()
        })
        .collect();
    let object = JsonObject::new()
        .raw("axes", &format!("[{}]", axes.join(",")))
        .raw("t_enter", &number(record.t_enter.to_f64()))
        .raw("t_exit", &number(record.t_exit.to_f64()))
        .boolean("hit", record.hit)
        .finish();
    object + "\n"
}
