//! `accelviz-cli bench`: build each structure, trace the same rays, report the figures.

use accelviz_core::outcome::{Outcome, OutcomeCounts, ReferenceScene};
use accelviz_core::params::BuildParams;
use accelviz_core::quality::{NodeEntries, SahCheck};
use accelviz_core::simd::Isa;
use accelviz_core::{Counters, MaxStack, NoObserver, Ray, TraceOptions, TriangleSet, Vector3};
use accelviz_scene::Mesh;
use accelviz_scene::rays::{RayKind, RaySource, pixel_tiles};
use anyhow::{Result, bail};
use clap::Args;

use crate::args::{BuildArgs, Precision, TraceArgs};
use crate::json::JsonObject;
use crate::parallel::Workers;
use crate::spec::{Accel, AccelSpec};
use crate::timing::{Samples, interleaved};
use accelviz_scene::builtin::load_mesh;

/// Builds timed for one sample of a structure's build time, at least: the sample is their
/// median. With one build a sample, the bunny's two-thread
/// builds ranged from 10.6 to 37.7 ms around a median of 17 (the second vCPU is shared, and
/// one build the machine interrupts moved a round by half).
const BUILDS_PER_SAMPLE: usize = 5;

#[derive(Args, Debug)]
pub struct BenchArgs {
    #[arg(long, default_value = "builtin:lumpy-sphere", help = crate::args::mesh_help())]
    mesh: String,
    #[arg(long, help = crate::args::structure_help("Comma-separated structures (bvh:sah-binned:8,kd:sah)"))]
    accel: String,
    /// How many rays: random ones (origins outside the mesh's box, aimed at random points in
    /// it), or of `--ray-kind`.
    #[arg(long, default_value_t = 100_000, conflicts_with = "rays_file")]
    rays: usize,
    /// Trace the rays of this file (the `query` format) instead: read a line at a time, each
    /// ray held as the precision traces it (32 bytes in f32: 10 million rays in 320 MB).
    #[arg(long, conflicts_with_all = ["camera", "aimed"])]
    rays_file: Option<String>,
    /// Trace rays aimed exactly at triangle corners and edges instead (the watertightness
    /// test's rays, 18 a triangle: a seeded random sample of `--rays` of them, or all if there
    /// are fewer). Each is judged against a reference on the same rounded triangles: one that
    /// passes through the surface where it should hit counts as a leak (errors/M; `outcomes`
    /// in the JSON). On a closed mesh a leaking ray mostly hits the surface behind, so it is
    /// no miss: `rays - hits` does not count leaks. The same as `--ray-kind aimed`.
    #[arg(long, conflicts_with = "camera")]
    aimed: bool,
    /// Trace the primary rays of a WIDTHxHEIGHT pinhole camera looking at the mesh instead
    /// (coherent rays, as a renderer traces them); with `--ray-kind shadow`, `ao` or
    /// `bounce`, the rays from every pixel's hit, the pixels in 8×8 tiles (coherent too).
    #[arg(long)]
    camera: Option<String>,
    /// Seed of the random rays.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// What rays: random, camera, aimed, shadow (from camera hits to a point light), ao
    /// (short rays from camera hits), bounce (a diffuse bounce from each camera hit).
    /// Default: camera with --camera, aimed with --aimed, else random.
    #[arg(long, value_parser = RayKind::parse, conflicts_with = "rays_file")]
    ray_kind: Option<RayKind>,
    #[command(flatten)]
    trace: TraceArgs,
    #[command(flatten)]
    build: BuildArgs,
    /// Rounds: every structure is built and traced once per round, the rounds interleaved,
    /// and each figure is the median of its rounds with the range it moved in (`±%`).
    #[arg(long, default_value_t = 5, value_parser = crate::args::parse_rounds)]
    repeat: usize,
    /// Comma-separated instruction sets to trace with, each measured in the same rounds:
    /// portable, avx2, avx512 (x86-64), simd128 (WebAssembly). Default: the best this
    /// machine has.
    #[arg(long)]
    isa: Option<String>,
    /// Threads building (the binned SAH builder builds big nodes' sides at once) and tracing
    /// rays (in tiles of 256 rays); a comma-separated list (`1,2`) measures each in the same
    /// rounds.
    #[arg(long, default_value = "1")]
    threads: String,
    /// Trace rays N at a time as packets (a wide BVH traces a packet together; other
    /// structures ray by ray): consecutive rays, or a camera's pixels in tiles (8x8 for 64,
    /// 4x4 for 16). A comma-separated list (`1,64`) measures each in the same rounds; 1 is
    /// one ray at a time, in the rays' own order. At most 64.
    #[arg(long, default_value = "1")]
    packet: String,
    /// One JSON object per structure, one per line.
    #[arg(long)]
    json: bool,
}

/// The figures of one structure traced with one instruction set.
struct Figures {
    accel: String,
    isa: Isa,
    threads: usize,
    packet: usize,
    triangles: usize,
    build: Samples,
    nodes: usize,
    leaves: usize,
    max_depth: usize,
    mean_leaf_size: f64,
    max_leaf_size: usize,
    sah_cost: f64,
    epo: Option<f64>,
    bytes: usize,
    fill_rate: Option<f64>,
    /// Leaves of each size (element `k`: leaves of `k` primitives).
    leaf_sizes: Vec<u64>,
    rays: usize,
    trace: Samples,
    counters: Counters,
    /// The deepest traversal stack a ray needed (one ray at a time).
    max_stack: usize,
    /// The SAH's chances against the rays' (binary trees).
    sah_check: Option<SahCheck>,
    /// Every ray's answer against the reference.
    outcomes: OutcomeCounts,
    hits: usize,
}

/// Parses a comma-separated list of whole numbers from `min` to `max` (`--threads 1,2`).
fn parse_counts(list: &str, flag: &str, min: usize, max: usize) -> Result<Vec<usize>> {
    list.split(',')
        .map(|count| match count.trim().parse::<usize>() {
            Ok(count) if (min..=max).contains(&count) => Ok(count),
            _ if max == usize::MAX => {
                bail!("{flag} must be at least {min} (or a list of such numbers, e.g. 1,2)")
            }
            _ => bail!("{flag} must be a whole number from {min} to {max} (or a list of them)"),
        })
        .collect()
}

/// Parses `--isa`: the sets named, each one this machine can run.
fn parse_isas(list: Option<&str>) -> Result<Vec<Isa>> {
    let Some(list) = list else {
        return Ok(vec![Isa::active()]);
    };
    list.split(',')
        .map(|name| {
            let name = name.trim();
            let isa = Isa::parse(name).ok_or_else(|| {
                let valid: Vec<_> = Isa::ALL.iter().map(|isa| isa.name()).collect();
                anyhow::anyhow!(
                    "unknown instruction set '{name}'; valid ones are: {}",
                    valid.join(", ")
                )
            })?;
            if !isa.is_available() {
                bail!(
                    "this machine cannot run {} kernels; it has: {}",
                    isa.name(),
                    Isa::ALL
                        .iter()
                        .filter(|isa| isa.is_available())
                        .map(|isa| isa.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                );
            }
            Ok(isa)
        })
        .collect()
}

pub fn run(args: &BenchArgs) -> Result<String> {
    let specs = AccelSpec::parse_list(&args.accel)?;
    let isas = parse_isas(args.isa.as_deref())?;
    let params = args.build.params()?;
    let threads = parse_counts(&args.threads, "--threads", 1, usize::MAX)?;
    let packets = parse_counts(&args.packet, "--packet", 1, accelviz_core::bvh::MAX_PACKET)?;
    let mesh = load_mesh(&args.mesh)?;
    let kind = args.ray_kind.unwrap_or(match (&args.camera, args.aimed) {
        (Some(_), _) => RayKind::Camera,
        (None, true) => RayKind::Aimed,
        (None, false) => RayKind::Random,
    });
    let source = RaySource::of_kind(
        args.rays_file.as_deref(),
        args.camera.as_deref(),
        kind,
        args.rays,
        args.seed,
    )
    .map_err(anyhow::Error::msg)?;
    let ray_source = source.label();
    let axes = Axes {
        isas: &isas,
        threads: &threads,
        packets: &packets,
        source: &source,
    };
    let figures = match args.trace.precision {
        Precision::F32 => measure::<glam::Vec3>(&specs, &axes, &params, &mesh, args)?,
        Precision::F64 => measure::<glam::DVec3>(&specs, &axes, &params, &mesh, args)?,
    };
    let options = args.trace.options_for(source.kind());
    let mut output = String::new();
    if !args.json {
        output.push_str(&format!(
            "mesh {} ({} triangles), {} rays ({ray_source}), {} hit, {} order, {}, {}, median of {} interleaved rounds (±: half their range); errors/M: leaks, false hits and wrong answers per million rays against the reference (the JSON has every outcome)\n",
            mesh.name,
            mesh.triangles.len(),
            figures.first().map_or(0, |figures| figures.rays),
            options.query.name(),
            options.order.name(),
            Precision::name(args.trace.precision),
            if args.trace.robust { "robust" } else { "fast" },
            args.repeat.max(1)
        ));
        output.push_str(&format!(
            "{:<22} {:<8} {:>7} {:>6} {:>10} {:>8} {:>8} {:>6} {:>9} {:>10} {:>6} {:>9} {:>11} {:>11} {:>8} {:>9}\n",
            "accel",
            "isa",
            "threads",
            "packet",
            "build ms",
            "nodes",
            "leaves",
            "depth",
            "SAH cost",
            "trace ms",
            "±%",
            "Mrays/s",
            "nodes/ray",
            "prims/ray",
            "hits",
            "errors/M"
        ));
    }
    for f in &figures {
        let rays = f.rays.max(1) as f64;
        let trace_ms = f.trace.median();
        let mrays_per_s = f.rays as f64 / (trace_ms * 1e3);
        let avg_nodes = f.counters.nodes_visited as f64 / rays;
        let avg_prims = f.counters.primitive_tests as f64 / rays;
        if args.json {
            let object = JsonObject::new()
                .string("accel", &f.accel)
                .string("isa", f.isa.name())
                .string("mesh", &mesh.name)
                .integer("triangles", f.triangles as u64)
                .number("build_ms", f.build.median())
                .number("build_ms_min", f.build.min())
                .number("build_ms_max", f.build.max())
                .integer("nodes", f.nodes as u64)
                .integer("leaves", f.leaves as u64)
                .integer("max_depth", f.max_depth as u64)
                .number("mean_leaf_size", f.mean_leaf_size)
                .integer("max_leaf_size", f.max_leaf_size as u64)
                .number("sah_cost", f.sah_cost)
                .number("epo", f.epo.unwrap_or(f64::NAN))
                .integer("bytes", f.bytes as u64)
                .number(
                    "bytes_per_primitive",
                    f.bytes as f64 / f.triangles.max(1) as f64,
                )
                .number("fill_rate", f.fill_rate.unwrap_or(f64::NAN))
                .raw("leaf_sizes", &format!("{:?}", f.leaf_sizes))
                .integer("rays", f.rays as u64)
                .string("ray_source", &ray_source)
                .string("ray_kind", source.kind().map_or("file", RayKind::name))
                .string("query", options.query.name())
                .number("trace_ms", trace_ms)
                .number("trace_ms_min", f.trace.min())
                .number("trace_ms_max", f.trace.max())
                .number("trace_spread_percent", f.trace.spread_percent())
                .number("mrays_per_s", mrays_per_s)
                .number("avg_nodes_visited", avg_nodes)
                .number("avg_box_tests", f.counters.box_tests as f64 / rays)
                .number("avg_prims_tested", avg_prims)
                .number("avg_mailbox_skips", f.counters.mailbox_skips as f64 / rays)
                .integer("max_stack", f.max_stack as u64)
                .raw("outcomes", &crate::json::outcomes_json(&f.outcomes))
                .raw(
                    "sah_check",
                    &f.sah_check
                        .as_ref()
                        .map_or_else(|| "null".to_owned(), sah_check_json),
                )
                .integer("hits", f.hits as u64)
                .integer("misses", (f.rays - f.hits) as u64)
                .string("order", options.order.name())
                .string("precision", Precision::name(args.trace.precision))
                .boolean("robust", args.trace.robust)
                .boolean("mailbox", args.trace.mailbox)
                .integer("threads", f.threads as u64)
                .integer("packet", f.packet as u64)
                .integer("repeat", args.repeat.max(1) as u64)
                .finish();
            output.push_str(&object);
            output.push('\n');
        } else {
            output.push_str(&format!(
                "{:<22} {:<8} {:>7} {:>6} {:>10.2} {:>8} {:>8} {:>6} {:>9.2} {:>10.2} {:>6.1} {:>9.3} {:>11.2} {:>11.2} {:>8} {:>9.0}\n",
                f.accel,
                f.isa.name(),
                f.threads,
                f.packet,
                f.build.median(),
                f.nodes,
                f.leaves,
                f.max_depth,
                f.sah_cost,
                trace_ms,
                f.trace.spread_percent(),
                mrays_per_s,
                avg_nodes,
                avg_prims,
                f.hits,
                Outcome::ALL
                    .iter()
                    .filter(|outcome| outcome.is_error())
                    .map(|&outcome| f.outcomes.per_million(outcome))
                    .sum::<f64>()
            ));
        }
    }
    Ok(output)
}

/// What each structure is measured across, every combination in the same rounds.
struct Axes<'a> {
    isas: &'a [Isa],
    threads: &'a [usize],
    packets: &'a [usize],
    source: &'a RaySource,
}

fn measure<V: Vector3>(
    specs: &[AccelSpec],
    axes: &Axes<'_>,
    params: &BuildParams,
    mesh: &Mesh,
    args: &BenchArgs,
) -> Result<Vec<Figures>> {
    let triangles = TriangleSet::<V>::from_f64(&mesh.triangles);
    let rays = crate::args::rays_of::<V>(axes.source, mesh)?;
    let options = args.trace.options_for(axes.source.kind());
    let rounds = args.repeat.max(1);
    let workers = axes
        .threads
        .iter()
        .map(|&count| Workers::new(count))
        .collect::<Result<Vec<_>>>()?;
    // The rays of each packet size: in their order, or a camera's in tiles of pixels.
    let packets: Vec<Vec<std::ops::Range<usize>>> = axes
        .packets
        .iter()
        .map(|&size| packet_ranges(rays.len(), size))
        .collect();
    let tiled: Vec<Option<Vec<Ray<V>>>> = axes
        .packets
        .iter()
        .map(|&size| match axes.source {
            RaySource::Camera { width, height } if size > 1 => {
                // Square tiles where the size is a square (4x4 for 16), else rows of 8.
                let side = size.isqrt();
                let tile_width = if side * side == size {
                    side
                } else {
                    size.min(8)
                };
                let tiles = pixel_tiles(*width, *height, tile_width, size / tile_width);
                Some(
                    tiles
                        .iter()
                        .flatten()
                        .map(|&pixel| rays[pixel as usize])
                        .collect(),
                )
            }
            _ => None,
        })
        .collect();
    // Build every structure once per round on each number of threads (a rayon pool of that
    // many: the binned SAH builder forks onto it); keep the first build.
    let pools = axes
        .threads
        .iter()
        .map(|&count| rayon::ThreadPoolBuilder::new().num_threads(count).build())
        .collect::<Result<Vec<_>, _>>()?;
    // Each build timed alone, at least `BUILDS_PER_SAMPLE` times and until a sample has built
    // for `MIN_SAMPLE_MS`; the sample is their median. The builds after the first are dropped
    // outside the timing (as a peer's scene outlives its build's), in the rounds' interleaved
    // order.
    let configurations = specs.len() * pools.len();
    let mut accels: Vec<Option<Accel<V, TriangleSet<V>>>> = specs.iter().map(|_| None).collect();
    let mut builds = vec![Samples::default(); configurations];
    for round in 0..rounds {
        for step in 0..configurations {
            let index = accelviz_core::trade::interleaved_index(round, step, configurations);
            let (spec, pool) = (index / pools.len(), index % pools.len());
            let (mut sample, mut built_ms) = (Samples::default(), 0.0);
            while sample.len() < BUILDS_PER_SAMPLE || built_ms < accelviz_core::trade::MIN_SAMPLE_MS
            {
                let (accel, ms) = pools[pool].install(|| specs[spec].build(&triangles, params));
                sample.push(ms);
                built_ms += ms;
                if accels[spec].is_none() {
                    accels[spec] = Some(accel);
                }
            }
            builds[index].push(sample.median());
            crate::progress::report(
                "bench: builds",
                round * configurations + step + 1,
                rounds * configurations,
            );
        }
    }
    let accels: Vec<_> = accels.into_iter().flatten().collect();
    // Trace with every combination once per round.
    let mut configurations = Vec::new();
    for spec in 0..specs.len() {
        for &isa in axes.isas {
            for threads in 0..axes.threads.len() {
                for packet in 0..axes.packets.len() {
                    configurations.push((spec, isa, threads, packet));
                }
            }
        }
    }
    let mut hits = vec![0; configurations.len()];
    let traces = interleaved("bench: traces", rounds, configurations.len(), |index| {
        let (spec, isa, threads, packet) = configurations[index];
        Isa::set_active(isa).unwrap_or_else(|_| unreachable!("checked by parse_isas"));
        let rays = tiled[packet].as_deref().unwrap_or(&rays);
        hits[index] = if axes.packets[packet] == 1 {
            accels[spec].count_hits(rays, &options, &workers[threads])
        } else {
            trace_packets(
                &accels[spec],
                rays,
                &packets[packet],
                &options,
                &workers[threads],
            )
        };
    });
    Isa::set_active(Isa::detect()).unwrap_or_else(|_| unreachable!("detected"));
    // Count in a separate, untimed pass, one ray at a time (the counts are the same whatever
    // the kernels and threads).
    // ... with the deepest stack, and how often each node of a binary tree was entered (the
    // SAH's chances, checked).
    // Each ray's answer is held to the reference on the same rounded inputs, decided once.
    let reference = ReferenceScene::new(&triangles);
    let facts: Vec<_> = accels.iter().map(|accel| accel.binary_facts()).collect();
    let mut observers: Vec<(Counters, (MaxStack, NodeEntries))> = facts
        .iter()
        .map(|facts| {
            let nodes = facts.as_ref().map_or(0, |facts| facts.bounds.len());
            (
                Counters::default(),
                (MaxStack::default(), NodeEntries::new(nodes)),
            )
        })
        .collect();
    let mut outcomes = vec![OutcomeCounts::default(); accels.len()];
    let mut stack = accelviz_core::TraversalStacks::default();
    // Ray by ray: its reference decided once, then every structure's answer judged, so no
    // ray's reference is kept (a file of millions of rays holds no more than its rays).
    for (index, ray) in rays.iter().enumerate() {
        if index % 4096 == 0 {
            crate::progress::report("bench: each ray judged", index, rays.len());
        }
        let expected = reference.reference(ray);
        for ((accel, observer), outcomes) in accels.iter().zip(&mut observers).zip(&mut outcomes) {
            let got = accel.trace(ray, &options, &mut stack, observer);
            outcomes.add(reference.classify(
                ray,
                expected.as_ref(),
                got.map(|hit| hit.primitive),
                options.query,
            ));
        }
    }
    let counted: Vec<(Counters, (MaxStack, NodeEntries), OutcomeCounts)> = observers
        .into_iter()
        .zip(outcomes)
        .map(|((counters, entries), outcomes)| (counters, entries, outcomes))
        .collect();
    let sah_checks: Vec<Option<SahCheck>> = facts
        .iter()
        .zip(&counted)
        .map(|(facts, (_, (_, entries), _))| {
            facts
                .as_ref()
                .map(|facts| SahCheck::of(facts, entries, &params.cost))
        })
        .collect();
    let epos: Vec<Option<f64>> = accels
        .iter()
        .map(|accel| accel.epo(triangles.triangles(), &params.cost))
        .collect();
    let mut all = Vec::with_capacity(configurations.len());
    for (index, &(spec, isa, threads, packet)) in configurations.iter().enumerate() {
        let stats = accels[spec].stats(triangles.triangles().len(), &params.cost);
        let (footprint, leaf_sizes) = accels[spec].footprint();
        all.push(Figures {
            accel: specs[spec].name(),
            isa,
            threads: axes.threads[threads],
            packet: axes.packets[packet],
            triangles: triangles.triangles().len(),
            build: builds[spec * axes.threads.len() + threads].clone(),
            nodes: stats.node_count,
            leaves: stats.leaf_count,
            max_depth: stats.max_depth,
            mean_leaf_size: stats.mean_leaf_size,
            max_leaf_size: stats.max_leaf_size,
            sah_cost: stats.sah_cost,
            epo: epos[spec],
            bytes: footprint.bytes,
            fill_rate: footprint.fill_rate,
            leaf_sizes,
            rays: rays.len(),
            trace: traces[index].clone(),
            counters: counted[spec].0,
            max_stack: counted[spec].1.0.0,
            sah_check: sah_checks[spec].clone(),
            outcomes: counted[spec].2,
            hits: hits[index],
        });
    }
    Ok(all)
}

/// Consecutive groups of `size` of `count` rays.
fn packet_ranges(count: usize, size: usize) -> Vec<std::ops::Range<usize>> {
    (0..count)
        .step_by(size.max(1))
        .map(|start| start..(start + size).min(count))
        .collect()
}

/// Traces `rays` in the packets `ranges` on `workers`; returns the number of hits.
#[inline(never)]
fn trace_packets<V: Vector3>(
    accel: &Accel<V, TriangleSet<V>>,
    rays: &[Ray<V>],
    ranges: &[std::ops::Range<usize>],
    options: &TraceOptions,
    workers: &Workers,
) -> usize {
    // Tiles of about `TILE` rays, as single rays are taken.
    let packet_size = ranges.first().map_or(1, |range| range.len().max(1));
    let counts = workers.map_in_tiles(
        ranges,
        crate::parallel::TILE / packet_size,
        || {
            let hits = vec![None; accelviz_core::bvh::MAX_PACKET];
            let observers = vec![NoObserver; accelviz_core::bvh::MAX_PACKET];
            (accelviz_core::TraversalStacks::default(), hits, observers)
        },
        |(stacks, hits, observers), range| {
            let packet = &rays[range.clone()];
            accel.trace_packet(packet, options, stacks, observers, hits);
            hits[..packet.len()].iter().flatten().count()
        },
    );
    counts.into_iter().sum()
}

/// `{"rays_entering", "sah_cost", "measured_chance_cost", "per_depth": [[depth, predicted,
/// measured], ...]}`.
pub fn sah_check_json(check: &SahCheck) -> String {
    let depths: Vec<String> = check
        .per_depth
        .iter()
        .map(|(depth, predicted, measured)| {
            format!(
                "[{depth},{},{}]",
                crate::json::number(*predicted),
                crate::json::number(*measured)
            )
        })
        .collect();
    JsonObject::new()
        .integer("rays_entering", check.rays_entering)
        .number("sah_cost", check.sah_cost)
        .number("measured_chance_cost", check.measured_chance_cost)
        .raw("per_depth", &format!("[{}]", depths.join(",")))
        .finish()
}
