// A Web Worker that does work aside for the app, so the page keeps drawing meanwhile: reads
// and builds large meshes (crates/app/src/mesh/aside.rs) and traces heat maps
// (crates/app/src/mesh/heat.rs). It runs the same WASM module as the page (the page sends its
// compiled module along); the app starts one per job and stops it when the job is done or
// cancelled.
//
// Jobs (one message each):
//   {job: "read", name, bytes: Uint8Array}            -> {progress: per mille}..., {done: Float64Array}
//   {job: "build", structure, triangles: Float64Array} -> {done: Uint8Array}
//   {job: "heat", tree: Uint8Array, triangles: Float64Array, key: Float64Array, first, step}
//                                                      -> {part: Uint32Array, at: band}..., {done: Uint8Array}
// and {problem: text} when it fails.
import init, { read_obj_aside, build_tree_aside, trace_heat_aside } from './pkg/accelviz.js';

let ready = null;

self.onmessage = async ({ data }) => {
  try {
    ready ??= init({ module_or_path: data.module ?? new URL('./pkg/accelviz_bg.wasm', import.meta.url) });
    await ready;
    let done;
    if (data.job === 'read') {
      done = read_obj_aside(data.name, data.bytes, (permille) => self.postMessage({ progress: permille }));
    } else if (data.job === 'build') {
      done = build_tree_aside(data.triangles, data.structure);
    } else if (data.job === 'heat') {
      trace_heat_aside(data.tree, data.triangles, data.key, data.first, data.step,
        (band, numbers) => self.postMessage({ part: numbers, at: band }, [numbers.buffer]));
      done = new Uint8Array(0);
    } else {
      throw new Error(`unknown job ${data.job}`);
    }
    self.postMessage({ done }, [done.buffer]);
  } catch (error) {
    self.postMessage({ problem: error && error.message ? error.message : String(error) });
  }
};
