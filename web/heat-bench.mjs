// How long the browser build takes to trace lesson 14's heat maps (both orders, every
// counter) of a mesh dropped onto the page, in headless Chromium (WebGL2 on SwiftShader), and
// how the page kept drawing meanwhile. Prints one JSON line per round.
//
//   scripts/build-web && node web/heat-bench.mjs [--mesh FILE] [--viewport WxH] [--rounds N]
//       [--cores N] [--on-page yes]
//
// `--cores N` tells the page it has N cores (the app starts a heat-map worker per core but
// one);
// `--on-page yes` refuses the page its heat-map workers, so it traces a slice a frame itself
// (what it falls back to).
//
// Each round loads the page afresh, opens lesson 14, drops the mesh (read and built in a Web
// Worker), and reads the app's log line "heat maps WxH traced in N ms" that follows the
// mesh's arrival: the time from the job's start to its last band, and the animation frames'
// longest gap from the mesh's arrival to then. The default viewport, 1720×1340, gives maps
// of about 512×512.

import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { dropFile, launchChromium, serve } from './browser.mjs';

const webDir = path.dirname(fileURLToPath(import.meta.url));
const options = {
  mesh: path.join(webDir, '..', '..', 'shared', 'meshes', 'stanford-bunny.obj'),
  viewport: '1720x1340',
  rounds: '3',
  cores: 'all',
  'on-page': 'no',
};
const argv = process.argv.slice(2);
for (let i = 0; i < argv.length; i += 2) {
  const name = argv[i].replace(/^--/, '');
  if (!(name in options) || argv[i + 1] === undefined) {
    throw new Error(`unknown or incomplete option '${argv[i]}'; options: ${Object.keys(options).map((o) => `--${o}`).join(' ')}`);
  }
  options[name] = argv[i + 1];
}
const [width, height] = options.viewport.split('x').map(Number);
const text = fs.readFileSync(options.mesh, 'utf8');
const meshName = path.basename(options.mesh);

const server = await serve(webDir);
const url = `http://127.0.0.1:${server.address().port}/`;
const browser = await launchChromium();
const waitFor = async (lines, test, seconds) => {
  for (let tries = 0; tries < seconds * 10; tries++) {
    const line = lines.find(test);
    if (line) return line;
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
  throw new Error(`waited ${seconds} s in vain; the log:\n  ${lines.join('\n  ')}`);
};
try {
  for (let round = 0; round < Number(options.rounds); round++) {
    const page = await browser.newPage({ viewport: { width, height }, deviceScaleFactor: 1 });
    const lines = [];
    page.on('console', (message) => lines.push(`${message.type()}: ${message.text()}`));
    await page.addInitScript(([cores, onPage]) => {
      Object.defineProperty(Navigator.prototype, 'gpu', { get: () => undefined });
      if (cores !== 'all') {
        Object.defineProperty(Navigator.prototype, 'hardwareConcurrency', { get: () => Number(cores) });
      }
      if (onPage === 'yes') {
        const post = Worker.prototype.postMessage;
        Worker.prototype.postMessage = function (message, transfer) {
          if (message && String(message.job).startsWith('heat')) throw new Error('heat-map workers refused (--on-page yes)');
          return post.call(this, message, transfer);
        };
      }
    }, [options.cores, options['on-page']]);
    await page.goto(url);
    await page.waitForFunction(() => document.title.includes('step'), null, { timeout: 120_000 });
    await page.mouse.click(60, 65 + 23 * 13);
    await page.waitForFunction(() => document.title.includes('14. '), null, { timeout: 20_000 });
    // The built-in mesh's maps first, so the dropped mesh's job is the only one running.
    await waitFor(lines, (line) => /heat maps \d+x\d+ traced in/.test(line), 120);
    await dropFile(page, meshName, text);
    const arrived = await waitFor(lines, (line) => line.includes('built aside over'), 120);
    const arrivedAt = lines.indexOf(arrived);
    await page.evaluate(() => {
      window.frameGaps = [];
      let last = performance.now();
      const tick = (now) => { window.frameGaps.push(now - last); last = now; requestAnimationFrame(tick); };
      requestAnimationFrame(tick);
    });
    const traced = await waitFor(lines, (line, at) => at > arrivedAt && /heat maps \d+x\d+ traced in/.test(line), 120);
    const match = traced.match(/heat maps (\d+)x(\d+) traced in (\d+) ms/);
    const gaps = await page.evaluate(() => window.frameGaps);
    if (round === 0) await page.screenshot({ path: path.join(webDir, '..', 'target', 'heat-bench.png') });
    console.log(JSON.stringify({
      mesh: meshName,
      width: Number(match[1]),
      height: Number(match[2]),
      millis: Number(match[3]),
      frames: gaps.length,
      longest_frame_gap_ms: Math.round(Math.max(...gaps, 0)),
      cores: options.cores,
      on_page: options['on-page'],
      errors: lines.filter((line) => line.startsWith('error') && !line.includes('refused (--on-page')),
    }));
    await page.close();
  }
} finally {
  await browser.close();
  server.close();
}
