// A Web Worker that reads and builds large meshes aside for the app, so the page keeps
// drawing meanwhile (crates/app/src/view3d/aside.rs). It runs the same WASM module as the
// page; the app starts one per job and stops it when the job is done or cancelled.
//
// Jobs (one message each):
//   {job: "read", name, bytes: Uint8Array}            -> {progress: per mille}..., {done: Float64Array}
//   {job: "build", structure, triangles: Float64Array} -> {done: Uint8Array}
// and {problem: text} when it fails.
import init, { read_obj_aside, build_tree_aside } from './pkg/accelviz.js';

const ready = init({ module_or_path: new URL('./pkg/accelviz_bg.wasm', import.meta.url) });

self.onmessage = async ({ data }) => {
  try {
    await ready;
    let done;
    if (data.job === 'read') {
      done = read_obj_aside(data.name, data.bytes, (permille) => self.postMessage({ progress: permille }));
    } else if (data.job === 'build') {
      done = build_tree_aside(data.triangles, data.structure);
    } else {
      throw new Error(`unknown job ${data.job}`);
    }
    self.postMessage({ done }, [done.buffer]);
  } catch (error) {
    self.postMessage({ problem: error && error.message ? error.message : String(error) });
  }
};
