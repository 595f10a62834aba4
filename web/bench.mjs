// accelviz's WebAssembly traversal against three-mesh-bvh (the web's usual BVH, `raycastFirst`,
// as `firstHitOnly` raycasts use it), in Node, one thread, on the same triangles and rays.
// Prints one JSON line per tracer and ray set.
//
//   scripts/build-web && node web/bench.mjs [--mesh FILE] [--rays N] [--camera WxH]
//       [--repeat N] [--accel bvh8:sah-binned,bvh:sah-binned] [--check yes]
//
// The rays are the ones `accelviz-cli bench` traces (its generators, exported by the wasm
// build; directions normalised so both tracers report distances). Each round traces every
// ray with every tracer, in an order reversed every other round; a tracer's figure is the
// median of its rounds (after an untimed warm-up), with the spread (half the range) in per cent. Every tracer's
// distances are checked against the first accelviz tracer's; with `--check yes` (what
// `scripts/test` runs, on few rays, for the answers and not the speed) the script fails when
// another accelviz tracer differs on any ray, or three-mesh-bvh on more than 1 ray in 1,000
// (a ray through a shared edge or corner may hit either triangle in f32).

import { readFileSync } from 'node:fs';
import { cpus } from 'node:os';
import { performance } from 'node:perf_hooks';
import { BufferAttribute, BufferGeometry, DoubleSide, Ray } from 'three';
import { CENTER, MeshBVH, SAH } from 'three-mesh-bvh';
import { BenchTracer, bench_rays, initSync, read_obj_aside } from './pkg/accelviz.js';

const here = new URL('.', import.meta.url);

function parseArgs(argv) {
  const options = {
    mesh: new URL('../../shared/meshes/stanford-bunny.obj', here).pathname,
    rays: 262144,
    camera: '512x512',
    repeat: 5,
    accel: 'bvh8:sah-binned,bvh4:sah-binned,bvh:sah-binned',
    check: 'no',
  };
  for (let i = 0; i < argv.length; i += 2) {
    const name = argv[i].replace(/^--/, '');
    if (!(name in options) || argv[i + 1] === undefined) {
      throw new Error(`unknown or incomplete option '${argv[i]}'; options: ${Object.keys(options).map((o) => `--${o}`).join(' ')}`);
    }
    options[name] = typeof options[name] === 'number' ? Number(argv[i + 1]) : argv[i + 1];
    if (typeof options[name] === 'number' && !(options[name] > 0)) {
      throw new Error(`--${name} must be a positive number, not '${argv[i + 1]}'`);
    }
  }
  return options;
}

// accelviz: the wasm build's BenchTracer.
function accelvizTracer(triangles, structure) {
  const tracer = new BenchTracer(triangles, structure);
  return {
    name: `accelviz ${structure} (wasm simd128)`,
    buildMillis: tracer.build_millis(),
    trace: (rays, distances) => tracer.trace(rays, distances),
  };
}

// three-mesh-bvh over a non-indexed geometry of the same triangles in f32, tested from both
// sides as accelviz's triangles are.
function threeMeshBvhTracer(triangles, strategyName, strategy) {
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(Float32Array.from(triangles), 3));
  const started = performance.now();
  const bvh = new MeshBVH(geometry, { strategy });
  const buildMillis = performance.now() - started;
  const ray = new Ray();
  return {
    name: `three-mesh-bvh ${strategyName} (raycastFirst)`,
    buildMillis,
    trace: (rays, distances) => {
      let hits = 0;
      for (let i = 0, n = distances.length; i < n; i++) {
        const o = 6 * i;
        ray.origin.set(rays[o], rays[o + 1], rays[o + 2]);
        ray.direction.set(rays[o + 3], rays[o + 4], rays[o + 5]);
        const hit = bvh.raycastFirst(ray, DoubleSide);
        if (hit) {
          distances[i] = hit.distance;
          hits++;
        } else {
          distances[i] = Infinity;
        }
      }
      return hits;
    },
  };
}

const median = (values) => {
  const sorted = [...values].sort((a, b) => a - b);
  const middle = sorted.length >> 1;
  return sorted.length % 2 ? sorted[middle] : (sorted[middle - 1] + sorted[middle]) / 2;
};

// Rays whose answers differ: one hits and the other misses, or the distances differ by more
// than f32 rounding allows (three.js intersects in f64).
function disagreements(reference, distances) {
  let count = 0;
  for (let i = 0; i < reference.length; i++) {
    const a = reference[i];
    const b = distances[i];
    if (a === b) continue;
    if (!Number.isFinite(a) || !Number.isFinite(b) || Math.abs(a - b) > 1e-4 * Math.max(1, a)) count++;
  }
  return count;
}

function measure(label, rays, tracers, repeat) {
  const rayCount = rays.length / 6;
  const runs = tracers.map(() => ({ millis: [], distances: new Float32Array(rayCount), hits: 0 }));
  // A warm-up on a few rays, untimed: the engine compiles hot code again, optimised, after it
  // has run a while (V8's tiers, for JavaScript and WebAssembly alike).
  const warmUp = rays.subarray(0, 6 * Math.min(rayCount, 4096));
  tracers.forEach((tracer, index) => tracer.trace(warmUp, runs[index].distances.subarray(0, warmUp.length / 6)));
  for (let round = 0; round < repeat; round++) {
    const order = tracers.map((_, index) => index);
    if (round % 2) order.reverse();
    for (const index of order) {
      const run = runs[index];
      const started = performance.now();
      run.hits = tracers[index].trace(rays, run.distances);
      run.millis.push(performance.now() - started);
    }
  }
  const reference = runs[0].distances;
  const threeBest = Math.min(
    ...tracers.map((tracer, index) => (tracer.name.startsWith('three') ? median(runs[index].millis) : Infinity)),
  );
  const problems = [];
  tracers.forEach((tracer, index) => {
    const run = runs[index];
    const disagreeing = disagreements(reference, run.distances);
    const allowed = tracer.name.startsWith('accelviz') ? 0 : Math.floor(rayCount / 1000);
    if (disagreeing > allowed) {
      problems.push(`${tracer.name} on ${label}: ${disagreeing} rays differ from ${tracers[0].name} (${allowed} allowed)`);
    }
    const millis = median(run.millis);
    const spread = (Math.max(...run.millis) - Math.min(...run.millis)) / 2 / millis;
    console.log(JSON.stringify({
      tracer: tracer.name,
      rays: label,
      ray_count: rayCount,
      hit_fraction: +(run.hits / rayCount).toFixed(4),
      build_ms: +tracer.buildMillis.toFixed(1),
      trace_ms: +millis.toFixed(1),
      mrays_per_s: +(rayCount / millis / 1e3).toFixed(3),
      spread_percent: +(100 * spread).toFixed(1),
      vs_best_three_mesh_bvh: +(threeBest / millis).toFixed(2),
      disagreements_with_first: disagreeing,
      repeat,
    }));
  });
  return problems;
}

function main() {
  const options = parseArgs(process.argv.slice(2));
  initSync({ module: readFileSync(new URL('./pkg/accelviz_bg.wasm', here)) });
  const triangles = read_obj_aside(options.mesh, readFileSync(options.mesh), () => {});
  console.error(
    `${options.mesh}: ${triangles.length / 9} triangles; node ${process.version}; ${cpus()[0]?.model ?? 'unknown CPU'}`,
  );
  const tracers = [
    ...options.accel.split(',').map((structure) => accelvizTracer(triangles, structure.trim())),
    threeMeshBvhTracer(triangles, 'SAH', SAH),
    threeMeshBvhTracer(triangles, 'CENTER (default)', CENTER),
  ];
  const problems = [
    ...measure(`random:${options.rays}:seed1`, bench_rays(triangles, undefined, options.rays, 1n), tracers, options.repeat),
    ...measure(`camera:${options.camera}`, bench_rays(triangles, options.camera, 0, 1n), tracers, options.repeat),
  ];
  if (options.check === 'yes' && problems.length > 0) {
    throw new Error(`answers differ:\n  ${problems.join('\n  ')}`);
  }
}

try {
  main();
} catch (error) {
  console.error(`web/bench.mjs: ${error && error.message ? error.message : error}`);
  process.exit(1);
}
