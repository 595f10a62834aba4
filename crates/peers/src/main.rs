//! `accelviz-peers`: times established BVH libraries from crates.io on exactly the triangles
//! and rays that `accelviz-cli bench` traces (same mesh loader, same seeded ray generator,
//! same ray files), single-threaded, and prints the same figures. Benchmark only: the core,
//! the scene crate and the app never depend on these libraries.
//!
//! - `obvhs` BVH2, built with PLOC (Meister & Bittner 2018) at its `medium_build` preset
//!   (PLOC + reinsertion + leaf collapsing), traced with its BVH2 traversal; the triangle test
//!   is obvhs's own, reached through `primitive_indices` as in its examples.
//! - `bvh` (svenstaro): its SAH build; its nearest-first iterator yields the candidate
//!   triangles, each tested with Möller–Trumbore (the library's own test culls back faces).
//! - `parry3d`: `TriMesh::new` (builds its BVH) and `cast_local_ray_and_get_normal`.
//! - `embree3`, `embree4`: Embree 3.13 and 4.4 (loaded at run time, see `accelviz_embree`),
//!   built at their default quality on one thread, traced one ray at a time
//!   (`rtcIntersect1`, or `rtcOccluded1` for any hit); `embree3-packet`, `embree4-packet`: the
//!   same scenes, the rays traced as coherent packets of 16 (camera rays in 4×4 pixels,
//!   `rtcIntersect16` / `rtcOccluded16`). `--isa avx2` limits Embree to AVX2.
//! - `tinybvh`: tinybvh's 8-wide `BVH8_CPU`, see [`tinybvh`] (needs an AVX2 build).
//!
//! Any-hit queries (`--query any`, the default for shadow and ambient occlusion rays) use each
//! library's occlusion query: Embree's `rtcOccluded*`, obvhs's `ray_traverse_miss`, parry3d's
//! `intersects_local_ray`, and for `bvh` the first hit its iterator's candidates give.
//! tinybvh's wrapper has none, so it answers them with its closest hit (said in its name).

mod tinybvh;

use std::time::{Duration, Instant};

use accelviz_core::Query;
use accelviz_embree::{Embree, Version};
use accelviz_scene::Mesh;
use accelviz_scene::rays::{RayKind, RaySource, RaySpec};
use anyhow::{Result, bail};
use clap::Parser;

/// Established BVH libraries on accelviz's triangles and rays.
#[derive(Parser, Debug)]
#[command(name = "accelviz-peers", version, about)]
struct Args {
    /// An OBJ file, or builtin:NAME.
    #[arg(long, default_value = "builtin:lumpy-sphere")]
    mesh: String,
    /// How many random rays (the generator of `accelviz-cli bench`).
    #[arg(long, default_value_t = 100_000)]
    rays: usize,
    /// Seed of the random rays.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Trace the rays of this file instead.
    #[arg(long, conflicts_with_all = ["camera", "ray_kind"])]
    rays_file: Option<String>,
    /// Trace the primary rays of a WIDTHxHEIGHT camera instead, or with a secondary ray kind
    /// the rays from every pixel's hit in 8×8 tiles (as `accelviz-cli bench --camera`).
    #[arg(long)]
    camera: Option<String>,
    /// What rays, as `accelviz-cli bench --ray-kind`: random, camera, aimed, shadow, ao,
    /// bounce. Default: camera with --camera, else random.
    #[arg(long, value_parser = RayKind::parse)]
    ray_kind: Option<RayKind>,
    /// closest, or any (is anything in the way?). Default: any for shadow and ao rays,
    /// closest otherwise.
    #[arg(long, value_parser = Query::parse)]
    query: Option<Query>,
    /// Which peers, comma-separated: obvhs, bvh, parry3d, embree3, embree4, embree3-packet,
    /// embree4-packet (16-wide coherent packets), tinybvh (its 8-wide BVH8_CPU; needs an
    /// AVX2 build).
    #[arg(long, default_value = "obvhs,bvh,parry3d")]
    peers: String,
    /// Limit Embree to this instruction set (Embree's names: sse2, sse4.2, avx, avx2,
    /// avx512); the others are compiled for this machine.
    #[arg(long)]
    isa: Option<String>,
    /// Build and trace this many times; report the median of each.
    #[arg(long, default_value_t = 1)]
    repeat: usize,
    /// One JSON object per peer, one per line.
    #[arg(long)]
    json: bool,
}

struct Figures {
    name: String,
    build_ms: f64,
    trace_ms: f64,
    hits: usize,
}

/// A ray's end as an f32 (an unbounded ray's is the largest f32).
fn t_max_f32(ray: &RaySpec) -> f32 {
    ray.t_max.min(f32::MAX as f64) as f32
}

fn to_f32(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| x as f32)
}

fn moller_trumbore(origin: glam::Vec3, direction: glam::Vec3, [a, b, c]: &[glam::Vec3; 3]) -> f32 {
    let edge1 = *b - *a;
    let edge2 = *c - *a;
    let p = direction.cross(edge2);
    let det = edge1.dot(p);
    if det == 0.0 {
        return f32::INFINITY;
    }
    let inv_det = 1.0 / det;
    let s = origin - *a;
    let u = s.dot(p) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return f32::INFINITY;
    }
    let q = s.cross(edge1);
    let v = direction.dot(q) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return f32::INFINITY;
    }
    let t = edge2.dot(q) * inv_det;
    if t >= 0.0 { t } else { f32::INFINITY }
}

fn run_obvhs(mesh: &Mesh, rays: &[RaySpec], query: Query) -> Figures {
    use obvhs::ray::{Ray, RayHit};
    let triangles: Vec<obvhs::triangle::Triangle> = mesh
        .triangles
        .iter()
        .map(|t| obvhs::triangle::Triangle {
            v0: glam::Vec3A::from_array(to_f32(t[0])),
            v1: glam::Vec3A::from_array(to_f32(t[1])),
            v2: glam::Vec3A::from_array(to_f32(t[2])),
        })
        .collect();
    let start = Instant::now();
    let bvh = obvhs::bvh2::builder::build_bvh2_from_tris(
        &triangles,
        obvhs::BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let rays: Vec<Ray> = rays
        .iter()
        .map(|r| {
            Ray::new(
                glam::Vec3A::from_array(to_f32(r.origin)),
                glam::Vec3A::from_array(to_f32(r.direction)),
                r.t_min as f32,
                t_max_f32(r),
            )
        })
        .collect();
    let start = Instant::now();
    let intersect =
        |ray: &Ray, id: usize| triangles[bvh.primitive_indices[id] as usize].intersect(ray);
    let hits = match query {
        Query::Any => rays
            .iter()
            .filter(|&&ray| !bvh.ray_traverse_miss(ray, intersect))
            .count(),
        _ => rays
            .iter()
            .filter(|&&ray| bvh.ray_traverse(ray, &mut RayHit::none(), intersect))
            .count(),
    };
    Figures {
        name: "obvhs:bvh2-ploc-medium".to_owned(),
        build_ms,
        trace_ms: start.elapsed().as_secs_f64() * 1e3,
        hits,
    }
}

struct BvhShape {
    corners: [glam::Vec3; 3],
    node_index: usize,
}

impl bvh::aabb::Bounded<f32, 3> for BvhShape {
    fn aabb(&self) -> bvh::aabb::Aabb<f32, 3> {
        let min = self.corners[0].min(self.corners[1]).min(self.corners[2]);
        let max = self.corners[0].max(self.corners[1]).max(self.corners[2]);
        bvh::aabb::Aabb::with_bounds(
            nalgebra::Point3::new(min.x, min.y, min.z),
            nalgebra::Point3::new(max.x, max.y, max.z),
        )
    }
}

impl bvh::bounding_hierarchy::BHShape<f32, 3> for BvhShape {
    fn set_bh_node_index(&mut self, index: usize) {
        self.node_index = index;
    }
    fn bh_node_index(&self) -> usize {
        self.node_index
    }
}

fn run_bvh(mesh: &Mesh, rays: &[RaySpec], query: Query) -> Figures {
    let mut shapes: Vec<BvhShape> = mesh
        .triangles
        .iter()
        .map(|t| BvhShape {
            corners: t.map(|c| glam::Vec3::from_array(to_f32(c))),
            node_index: 0,
        })
        .collect();
    let start = Instant::now();
    let tree = bvh::bvh::Bvh::build(&mut shapes);
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    let mut hits = 0;
    for r in rays {
        let (o, d) = (to_f32(r.origin), to_f32(r.direction));
        let ray = bvh::ray::Ray::new(
            nalgebra::Point3::new(o[0], o[1], o[2]),
            nalgebra::Vector3::new(d[0], d[1], d[2]),
        );
        let (origin, direction) = (glam::Vec3::from_array(o), glam::Vec3::from_array(d));
        let mut closest = t_max_f32(r);
        let mut found = false;
        for shape in tree.nearest_traverse_iterator(&ray, &shapes) {
            let t = moller_trumbore(origin, direction, &shape.corners);
            if t.is_finite() && t <= closest {
                closest = t;
                found = true;
                if query == Query::Any {
                    break;
                }
            }
        }
        hits += found as usize;
    }
    Figures {
        name: "bvh:sah".to_owned(),
        build_ms,
        trace_ms: start.elapsed().as_secs_f64() * 1e3,
        hits,
    }
}

fn run_parry(mesh: &Mesh, rays: &[RaySpec], query: Query) -> Result<Figures> {
    use parry3d::query::RayCast;
    let vertices: Vec<parry3d::math::Vector> = mesh
        .triangles
        .iter()
        .flatten()
        .map(|&c| {
            let c = to_f32(c);
            parry3d::math::Vector::new(c[0], c[1], c[2])
        })
        .collect();
    let indices: Vec<[u32; 3]> = (0..mesh.triangles.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let start = Instant::now();
    let trimesh = parry3d::shape::TriMesh::new(vertices, indices)
        .map_err(|error| anyhow::anyhow!("parry3d refused the mesh: {error:?}"))?;
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    let mut hits = 0;
    for r in rays {
        let (o, d) = (to_f32(r.origin), to_f32(r.direction));
        let ray = parry3d::query::Ray::new(
            parry3d::math::Vector::new(o[0], o[1], o[2]),
            parry3d::math::Vector::new(d[0], d[1], d[2]),
        );
        let hit = match query {
            Query::Any => trimesh.intersects_local_ray(&ray, t_max_f32(r)),
            _ => trimesh
                .cast_local_ray_and_get_normal(&ray, t_max_f32(r), false)
                .is_some(),
        };
        hits += hit as usize;
    }
    Ok(Figures {
        name: "parry3d:trimesh".to_owned(),
        build_ms,
        trace_ms: start.elapsed().as_secs_f64() * 1e3,
        hits,
    })
}

/// Embree `version`, one ray at a time or (`packets`: the rays' tiles of at most 16) in
/// coherent packets, limited to `isa` if given.
fn run_embree(
    mesh: &Mesh,
    rays: &[RaySpec],
    query: Query,
    (version, isa): (Version, Option<&str>),
    packets: Option<&[Vec<u32>]>,
) -> Result<Figures> {
    let triangles: Vec<[[f32; 3]; 3]> = mesh.triangles.iter().map(|t| t.map(to_f32)).collect();
    let start = Instant::now();
    let scene = Embree::build(version, &triangles, 1, isa)?;
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let rays: Vec<accelviz_embree::Ray> = rays
        .iter()
        .map(|r| accelviz_embree::Ray {
            origin: to_f32(r.origin),
            direction: to_f32(r.direction),
            t_max: t_max_f32(r),
        })
        .collect();
    let any = query == Query::Any;
    let start = Instant::now();
    let hits = match packets {
        None if any => rays.iter().filter(|ray| scene.occluded(ray)).count(),
        None => rays
            .iter()
            .filter(|ray| scene.closest(ray).is_some())
            .count(),
        Some(packets) => {
            let mut tracer = scene.packets();
            let mut hits = 0;
            let mut packet_rays = Vec::with_capacity(accelviz_embree::PACKET);
            let mut packet_hits = [None; accelviz_embree::PACKET];
            let mut packet_occluded = [false; accelviz_embree::PACKET];
            for packet in packets {
                packet_rays.clear();
                packet_rays.extend(packet.iter().map(|&index| rays[index as usize]));
                let lanes = packet.len();
                if any {
                    tracer.occluded(&packet_rays, &mut packet_occluded);
                    hits += packet_occluded[..lanes].iter().filter(|&&o| o).count();
                } else {
                    tracer.closest(&packet_rays, &mut packet_hits);
                    hits += packet_hits[..lanes].iter().flatten().count();
                }
            }
            hits
        }
    };
    let call = match (packets.is_some(), any) {
        (false, false) => "intersect1",
        (false, true) => "occluded1",
        (true, false) => "intersect16",
        (true, true) => "occluded16",
    };
    Ok(Figures {
        name: format!("{}:{call}", version.name()),
        build_ms,
        trace_ms: start.elapsed().as_secs_f64() * 1e3,
        hits,
    })
}

fn main() -> std::process::ExitCode {
    match run(Args::parse()) {
        Ok(text) => {
            print!("{text}");
            std::process::ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("accelviz-peers: error: {error:#}");
            std::process::ExitCode::from(2)
        }
    }
}

fn run(args: Args) -> Result<String> {
    let mesh = accelviz_scene::builtin::load_mesh(&args.mesh)?;
    let kind = args.ray_kind.unwrap_or(if args.camera.is_some() {
        RayKind::Camera
    } else {
        RayKind::Random
    });
    let source = RaySource::of_kind(
        args.rays_file.as_deref(),
        args.camera.as_deref(),
        kind,
        args.rays,
        args.seed,
    )
    .map_err(anyhow::Error::msg)?;
    let query = args.query.unwrap_or(kind.default_query());
    let rays = source.rays(&mesh)?;
    let ray_source = source.label();
    // Packets of 16: camera rays in tiles of 4×4 pixels; other rays 16 in the order made
    // (secondary rays from random pixels' hits are not neighbours: these packets are
    // incoherent, as a renderer's would be without sorting; from every pixel, in tiles of
    // 8×8 pixels, 16 in a row come from two rows of a tile: coherent).
    let packets: Vec<Vec<u32>> = match &source {
        RaySource::Camera { width, height } => {
            accelviz_scene::rays::pixel_tiles(*width, *height, 4, 4)
        }
        _ => (0..rays.len() as u32)
            .collect::<Vec<_>>()
            .chunks(accelviz_embree::PACKET)
            .map(<[u32]>::to_vec)
            .collect(),
    };
    let isa = args.isa.as_deref();
    let mut figures = Vec::new();
    for peer in args.peers.split(',') {
        // Each peer built and traced `repeat` times; its figures are the medians.
        let mut runs = Vec::new();
        for _ in 0..args.repeat.max(1) {
            runs.push(match peer.trim() {
                "obvhs" => run_obvhs(&mesh, &rays, query),
                "bvh" => run_bvh(&mesh, &rays, query),
                "parry3d" => run_parry(&mesh, &rays, query)?,
                "embree3" => run_embree(&mesh, &rays, query, (Version::Three, isa), None)?,
                "embree4" => run_embree(&mesh, &rays, query, (Version::Four, isa), None)?,
                "embree3-packet" => {
                    run_embree(&mesh, &rays, query, (Version::Three, isa), Some(&packets))?
                }
                "embree4-packet" => {
                    run_embree(&mesh, &rays, query, (Version::Four, isa), Some(&packets))?
                }
                "tinybvh" => tinybvh::run(&mesh, &rays, query)?,
                other => bail!(
                    "unknown peer '{other}'; peers are obvhs, bvh, parry3d, embree3, embree4, \
                     embree3-packet, embree4-packet, tinybvh"
                ),
            });
        }
        let median = |mut values: Vec<f64>| {
            values.sort_by(f64::total_cmp);
            values[values.len() / 2]
        };
        let build_ms = median(runs.iter().map(|run| run.build_ms).collect());
        let trace_ms = median(runs.iter().map(|run| run.trace_ms).collect());
        if let Some(first) = runs.into_iter().next() {
            figures.push(Figures {
                build_ms,
                trace_ms,
                ..first
            });
        }
    }
    let mut out = String::new();
    for f in &figures {
        let mrays = rays.len() as f64 / (f.trace_ms * 1e3);
        if args.json {
            out.push_str(&format!(
                "{{\"accel\":\"{}\",\"mesh\":\"{}\",\"triangles\":{},\"build_ms\":{},\"rays\":{},\"ray_source\":\"{ray_source}\",\"ray_kind\":\"{}\",\"query\":\"{}\",\"isa\":\"{}\",\"trace_ms\":{},\"mrays_per_s\":{mrays},\"hits\":{},\"threads\":1}}\n",
                f.name, mesh.name, mesh.triangles.len(), f.build_ms, rays.len(), kind.name(), query.name(), isa.unwrap_or("native"), f.trace_ms, f.hits
            ));
        } else {
            out.push_str(&format!(
                "{:<24} build {:>9.2} ms  trace {:>9.2} ms  {:>7.3} Mrays/s  {} hits of {} rays ({ray_source})\n",
                f.name, f.build_ms, f.trace_ms, mrays, f.hits, rays.len()
            ));
        }
    }
    Ok(out)
}
