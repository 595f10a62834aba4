//! `accelviz-cli heatmap`: the cost of every pixel of the benchmark's camera, as a PNG (and
//! a CSV of every counter), for slides and for checking the app's heat maps.

use std::path::Path;
use std::time::Instant;

use accelviz_core::camera::Camera;
use accelviz_core::heatmap::{Counter, HeatMap};
use accelviz_core::{NoObserver, Query, TraceOptions, TraversalStacks, TriangleSet, Vector3};
use accelviz_scene::output::{encode_png, write_all_or_nothing};
use accelviz_scene::rays::{RayKind, pixel_secondary_rays};
use anyhow::{Result, anyhow, bail};
use clap::{Args, ValueEnum};

use crate::args::{BuildArgs, Precision, TraceArgs};
use crate::json::JsonObject;
use crate::spec::AccelSpec;
use accelviz_scene::builtin::load_mesh;

/// A counter as the command line spells it.
#[derive(Clone, Copy, Debug, Default, ValueEnum, PartialEq, Eq)]
pub enum CounterArg {
    /// Nodes entered.
    #[default]
    Nodes,
    /// Ray/box slab tests.
    Boxes,
    /// Ray/primitive tests.
    Prims,
}

impl CounterArg {
    fn counter(self) -> Counter {
        match self {
            CounterArg::Nodes => Counter::Nodes,
            CounterArg::Boxes => Counter::Boxes,
            CounterArg::Prims => Counter::Prims,
        }
    }
}

#[derive(Args, Debug)]
pub struct HeatmapArgs {
    #[arg(long, default_value = "builtin:lumpy-sphere", help = crate::args::mesh_help())]
    mesh: String,
    #[arg(long, help = crate::args::structure_help("The structure"))]
    accel: String,
    /// The image size WIDTHxHEIGHT; the camera is `bench --camera`'s.
    #[arg(long, default_value = "512x512")]
    camera: String,
    /// What each pixel shows.
    #[arg(long, value_enum, default_value_t)]
    counter: CounterArg,
    /// Whose cost each pixel shows: camera (its own ray), or the secondary rays from its
    /// ray's hit: shadow (to a point light), ao (4 short rays), bounce (one diffuse bounce).
    /// Pixels that miss the mesh, or whose light is behind the surface, show nothing.
    #[arg(long, default_value = "camera", value_parser = RayKind::parse)]
    ray_kind: RayKind,
    /// Threads tracing rows of pixels.
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// Trace the camera's rays in packets of N: square tiles of pixels (4: 2x2, 16: 4x4,
    /// 64: 8x8) traced together, as `bench --camera --packet N` does; each pixel shows what
    /// the packet traversal did for its ray. 1: one ray at a time.
    #[arg(long, default_value_t = 1)]
    packet: usize,
    /// The PNG to write (0 darkest, the image's maximum lightest).
    #[arg(long)]
    out: String,
    /// Also write every pixel's counts: `x,y,nodes,boxes,prims`, one row per pixel.
    #[arg(long)]
    csv: Option<String>,
    #[command(flatten)]
    trace: TraceArgs,
    #[command(flatten)]
    build: BuildArgs,
    /// One JSON object instead of a line of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &HeatmapArgs) -> Result<String> {
    let spec = AccelSpec::parse(&args.accel)?;
    let params = args.build.params()?;
    if args.threads == 0 {
        bail!("--threads must be at least 1");
    }
    let tile = match args.packet {
        1 => 1,
        4 => 2,
        16 => 4,
        64 => 8,
        other => bail!("--packet {other}: packets are square tiles of 1, 4, 16 or 64 pixels"),
    };
    let (width, height) =
        accelviz_scene::rays::parse_resolution(&args.camera).map_err(anyhow::Error::msg)?;
    match args.ray_kind {
        RayKind::Camera => {}
        RayKind::Shadow | RayKind::Ao | RayKind::Bounce if tile == 1 => {}
        RayKind::Shadow | RayKind::Ao | RayKind::Bounce => bail!(
            "--packet {}: secondary rays start at scattered hits, so they are traced one at a time (--packet 1)",
            args.packet
        ),
        other => bail!(
            "--ray-kind {}: a heat map shows the camera's pixels: camera, shadow, ao or bounce",
            other.name()
        ),
    }
    let mesh = load_mesh(&args.mesh)?;
    let camera = Camera::framing(&mesh.bounds());
    let started = Instant::now();
    let map = match args.trace.precision {
        Precision::F32 => {
            trace::<glam::Vec3>(&spec, &params, &mesh, &camera, (width, height, tile), args)
        }
        Precision::F64 => {
            trace::<glam::DVec3>(&spec, &params, &mesh, &camera, (width, height, tile), args)
        }
    };
    let ms = started.elapsed().as_secs_f64() * 1e3;
    let counter = args.counter.counter();
    let summary = map.summary(counter);

    let png = encode_png(width, height, &map.colors(counter, summary.max))
        .map_err(|problem| anyhow!("{}: cannot make the image: {problem}", args.out))?;
    let csv = args.csv.as_ref().map(|_| csv_of(&map));
    let mut files: Vec<(&Path, &[u8])> = vec![(Path::new(&args.out), &png)];
    if let (Some(path), Some(text)) = (&args.csv, &csv) {
        files.push((Path::new(path), text.as_bytes()));
    }
    write_all_or_nothing(&files)?;

    let options = args.trace.options_for(Some(args.ray_kind));
    let order = options.order.name();
    let query = options.query.name();
    Ok(if args.json {
        let object = JsonObject::new()
            .string("accel", &spec.name())
            .string("ray_kind", args.ray_kind.name())
            .string("query", query)
            .integer("width", width as u64)
            .integer("height", height as u64)
            .string("counter", counter.name())
            .string("order", order)
            .integer("packet", args.packet as u64)
            .integer("total", summary.total)
            .integer("max", u64::from(summary.max))
            .number("mean", summary.mean)
            .number("ms", ms)
            .finish();
        format!("{object}\n")
    } else {
        let also = args
            .csv
            .as_ref()
            .map(|path| format!(" and {path}"))
            .unwrap_or_default();
        let packets = if tile > 1 {
            format!(" in {tile}x{tile} packets")
        } else {
            String::new()
        };
        format!(
            "{} on {} ({} triangles), {width}x{height} camera{packets}, {} rays, {query} hit, {order}: {} per pixel: \
             total {}, max {}, mean {:.2} ({ms:.1} ms); wrote {}{also}\n",
            spec.name(),
            mesh.name,
            mesh.triangles.len(),
            args.ray_kind.name(),
            counter.label(),
            summary.total,
            summary.max,
            summary.mean,
            args.out
        )
    })
}

/// Builds the structure and traces every pixel of a `width × height` image with the
/// benchmark's traversal, in packets of `tile × tile` pixels unless `tile` is 1.
fn trace<V: Vector3>(
    spec: &AccelSpec,
    params: &accelviz_core::params::BuildParams,
    mesh: &accelviz_scene::Mesh,
    camera: &Camera,
    (width, height, tile): (usize, usize, usize),
    args: &HeatmapArgs,
) -> HeatMap {
    let triangles = TriangleSet::<V>::from_f64(&mesh.triangles);
    let (accel, _) = spec.build(&triangles, params);
    let options = args.trace.options_for(Some(args.ray_kind));
    if args.ray_kind != RayKind::Camera {
        // Each pixel's ray finds its hit (uncounted); the secondary rays from there are
        // counted at that pixel (the same rays as lesson 14's maps).
        let bounds = mesh.bounds();
        let primary = TraceOptions {
            query: Query::Closest,
            ..options
        };
        return HeatMap::compute(
            camera,
            width,
            height,
            args.threads,
            &|ray: &accelviz_core::Ray<V>, stacks: &mut TraversalStacks<V::Scalar>, counters| {
                let Some(hit) = accel.trace(ray, &primary, stacks, &mut NoObserver) else {
                    return;
                };
                for secondary in pixel_secondary_rays(args.ray_kind, mesh, &bounds, ray, hit) {
                    accel.trace(&secondary, &options, stacks, counters);
                }
            },
        );
    }
    HeatMap::compute_in_packets(
        camera,
        width,
        height,
        args.threads,
        tile,
        &|rays, stacks: &mut TraversalStacks<V::Scalar>, counters| {
            let mut hits = [None; accelviz_core::bvh::MAX_PACKET];
            accel.trace_packet(rays, &options, stacks, counters, &mut hits[..rays.len()]);
        },
    )
}

/// `x,y,nodes,boxes,prims`, a header and one row per pixel.
fn csv_of(map: &HeatMap) -> String {
    let mut text = String::with_capacity(map.pixels.len() * 16 + 32);
    text.push_str("x,y,nodes,boxes,prims\n");
    for (index, cost) in map.pixels.iter().enumerate() {
        let (x, y) = (index % map.width.max(1), index / map.width.max(1));
        text.push_str(&format!(
            "{x},{y},{},{},{}\n",
            cost.nodes, cost.boxes, cost.prims
        ));
    }
    text
}
