// A Web Worker that does work aside for the app, so the page keeps drawing meanwhile: reads
// and builds large meshes (crates/app/src/mesh/aside.rs), and traces heat maps
// (crates/app/src/mesh/heat.rs). It runs the same WASM module as the page (the page sends its
// compiled module along).
//
// A read, a build or a measurement has a worker of its own, stopped when the job is done or
// cancelled:
//   {job: "read", name, bytes: Uint8Array}            -> {progress: per mille}..., {done: Float64Array}
//   {job: "build", structure, triangles: Float64Array} -> {done: Uint8Array}
//   {job: "trade", triangles: Float64Array, rays: Float64Array, query, rounds}
//       -> {tasks, of, doing, spent, left}..., {done: Uint8Array}   (the trade lab, off the page's frames;
//          spent and left in milliseconds, left NaN while unknown)
// Heat maps have a pool of workers that live as long as the page and keep the last tree:
//   {job: "heat-tree", tree: Uint8Array, triangles: Float64Array}   (kept; no answer)
//   {job: "heat-bands", id, key: Float64Array, first, step}
//       -> {part: Uint32Array, at: band, id}..., {done, id}; a newer job or
//   {job: "heat-cancel"} stops it between two bands.
// and {problem: text, id} when a job fails.
import init, { read_obj_aside, build_tree_aside, measure_trade_aside, HeatTracer } from './pkg/accelviz.js';

let ready = null;
let heatTracer = null;
let heatJob = null;

// Lets the messages that came meanwhile (a newer job, a cancel) be heard: a message to itself
// (a timer would wait at least 4 ms once nested).
const channel = new MessageChannel();
const heard = () => new Promise((resolve) => {
  channel.port1.onmessage = () => resolve();
  channel.port2.postMessage(null);
});

async function traceBands({ id, key, first, step }) {
  heatJob = id;
  const count = HeatTracer.band_count(key);
  for (let band = first; band < count; band += step) {
    await heard();
    if (heatJob !== id) return;
    const part = heatTracer.trace_band(key, band);
    self.postMessage({ part, at: band, id }, [part.buffer]);
  }
  self.postMessage({ done: true, id });
}

self.onmessage = async ({ data }) => {
  try {
    ready ??= init({ module_or_path: data.module ?? new URL('./pkg/accelviz_bg.wasm', import.meta.url) });
    await ready;
    if (data.job === 'heat-tree') {
      heatTracer?.free();
      heatTracer = null;
      heatTracer = new HeatTracer(data.tree, data.triangles);
      return;
    } else if (data.job === 'heat-bands') {
      if (!heatTracer) throw new Error('no heat map tree was sent');
      await traceBands(data);
      return;
    } else if (data.job === 'heat-cancel') {
      heatJob = null;
      return;
    }
    let done;
    if (data.job === 'read') {
      done = read_obj_aside(data.name, data.bytes, (permille) => self.postMessage({ progress: permille }));
    } else if (data.job === 'build') {
      done = build_tree_aside(data.triangles, data.structure);
    } else if (data.job === 'trade') {
      done = measure_trade_aside(data.triangles, data.rays, data.query, data.rounds,
        (tasks, of, doing, spent, left) => self.postMessage({ tasks, of, doing, spent, left }));
    } else {
      throw new Error(`unknown job ${data.job}`);
    }
    self.postMessage({ done }, [done.buffer]);
  } catch (error) {
    self.postMessage({ problem: error && error.message ? error.message : String(error), id: data.id });
  }
};
