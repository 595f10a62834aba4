// End-to-end test of the browser build (web/pkg, made by scripts/build-web) in headless
// Chromium: the page loads, the canvas shows the app (checked from a screenshot), a click on a
// lesson and on "step" change what is shown (every lesson is opened in turn), a scene is
// downloaded and uploaded, and no error reaches the console.
//
// The app reports its lesson and step in the page title and the console (app.rs,
// `report_position`); clicks go to fixed places of its layout at the viewport size below.

import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { fileURLToPath } from 'node:url';
import { dropFile, launchChromium, serve } from './browser.mjs';

const webDir = path.dirname(fileURLToPath(import.meta.url));
const shotDir = process.env.E2E_SHOTS ?? path.join(webDir, '..', 'target', 'e2e');
// E2E_VIEWPORT=WxH walks the same page at another size (1366x768, a projector's or a
// laptop's; 1920x1080): the checks are the same, the screenshots show how it fits.
const [viewportWidth, viewportHeight] = (process.env.E2E_VIEWPORT ?? '1280x800').split('x').map(Number);
const viewport = { width: viewportWidth, height: viewportHeight };

/** Decodes an 8-bit RGB or RGBA PNG (what Chromium's screenshots are) to pixels. */
function decodePng(buffer) {
  let offset = 8;
  let width = 0, height = 0, colorType = 0;
  const data = [];
  while (offset < buffer.length) {
    const length = buffer.readUInt32BE(offset);
    const type = buffer.toString('ascii', offset + 4, offset + 8);
    const chunk = buffer.subarray(offset + 8, offset + 8 + length);
    if (type === 'IHDR') {
      width = chunk.readUInt32BE(0);
      height = chunk.readUInt32BE(4);
      if (chunk[8] !== 8) throw new Error(`PNG bit depth ${chunk[8]} not handled`);
      colorType = chunk[9];
    } else if (type === 'IDAT') {
      data.push(chunk);
    }
    offset += 12 + length;
  }
  const channels = colorType === 6 ? 4 : colorType === 2 ? 3 : 0;
  if (!channels) throw new Error(`PNG colour type ${colorType} not handled`);
  const raw = zlib.inflateSync(Buffer.concat(data));
  const stride = width * channels;
  const pixels = Buffer.alloc(height * stride);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    const row = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; x++) {
      const left = x >= channels ? pixels[y * stride + x - channels] : 0;
      const up = y > 0 ? pixels[(y - 1) * stride + x] : 0;
      const upLeft = x >= channels && y > 0 ? pixels[(y - 1) * stride + x - channels] : 0;
      let value = row[x];
      if (filter === 1) value += left;
      else if (filter === 2) value += up;
      else if (filter === 3) value += (left + up) >> 1;
      else if (filter === 4) {
        const estimate = left + up - upLeft;
        const [a, b, c] = [Math.abs(estimate - left), Math.abs(estimate - up), Math.abs(estimate - upLeft)];
        value += a <= b && a <= c ? left : b <= c ? up : upLeft;
      }
      pixels[y * stride + x] = value & 255;
    }
  }
  return { width, height, channels, pixels };
}

/** Distinct colours and the share of pixels that differ between two screenshots. */
function colourCount(png) {
  const seen = new Set();
  for (let i = 0; i < png.pixels.length; i += png.channels) {
    seen.add((png.pixels[i] << 16) | (png.pixels[i + 1] << 8) | png.pixels[i + 2]);
  }
  return seen.size;
}

function differingShare(a, b) {
  let differing = 0;
  for (let i = 0; i < a.pixels.length; i += a.channels) {
    if (a.pixels[i] !== b.pixels[i] || a.pixels[i + 1] !== b.pixels[i + 1] || a.pixels[i + 2] !== b.pixels[i + 2]) {
      differing++;
    }
  }
  return differing / (a.width * a.height);
}

const failures = [];
function check(condition, message) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${message}`);
  if (!condition) failures.push(message);
}

const server = await serve(webDir);
const url = `http://127.0.0.1:${server.address().port}/`;
const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport, deviceScaleFactor: 1 });
  const consoleErrors = [];
  const logLines = [];
  page.on('console', (message) => {
    logLines.push(`${message.type()}: ${message.text()}`);
    if (message.type() === 'error') consoleErrors.push(message.text());
  });
  page.on('pageerror', (error) => consoleErrors.push(`page error: ${error.message}`));
  fs.mkdirSync(shotDir, { recursive: true });
  // The app arrives compressed (web/serve.mjs, as the README says to serve it): its
  // encoding and the bytes on the wire, read from the response.
  const wasmResponses = [];
  page.on('response', async (response) => {
    if (!response.url().endsWith('accelviz_bg.wasm')) return;
    const headers = await response.allHeaders();
    wasmResponses.push({ encoding: headers['content-encoding'] ?? 'identity', bytes: Number(headers['content-length']) });
  });

  // WebGPU made unavailable, so the app runs on WebGL2 (as in browsers without WebGPU).
  await page.addInitScript(() => {
    Object.defineProperty(Navigator.prototype, 'gpu', { get: () => undefined });
  });
  const loadStart = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => document.title.includes('step'), null, { timeout: 120_000 });
  check(true, `the app started in ${((Date.now() - loadStart) / 1000).toFixed(1)} s: "${await page.title()}"`);
  check(!(await page.$('#loading')), 'the loading note is gone');
  const wasm = wasmResponses[0];
  check(wasm && wasm.encoding !== 'identity',
    `the wasm arrives compressed: ${wasm ? `${wasm.encoding}, ${(wasm.bytes / 1e6).toFixed(2)} MB on the wire` : 'no response seen'}`);
  check(logLines.some((line) => line.includes('backend: Gl')), 'the app runs on WebGL2');
  await page.waitForTimeout(500);
  const first = decodePng(await page.screenshot({ path: path.join(shotDir, 'web-start.png') }));
  check(colourCount(first) > 50, `the canvas shows the app (${colourCount(first)} colours in the screenshot)`);

  // Every lesson of the list, in turn: each opens and draws (the 3D ones are 11 to 14).
  const lessonNumbers = Array.from({ length: 20 }, (_, index) => index + 1);
  for (let index = 0; index < lessonNumbers.length; index++) {
    await page.mouse.click(60, 65 + 23 * index);
    const wanted = `${lessonNumbers[index]}. `;
    await page.waitForFunction((text) => document.title.includes(text), wanted, { timeout: 20_000 })
      .catch(() => {});
    await page.waitForTimeout(200);
    const title = await page.title();
    const shot = decodePng(await page.screenshot({
      path: path.join(shotDir, `web-lesson-${String(index + 1).padStart(2, '0')}.png`),
    }));
    check(title.includes(wanted) && colourCount(shot) > 50,
      `lesson ${lessonNumbers[index]} opens and draws: "${title}" (${colourCount(shot)} colours)`);
  }

  // Lesson 14's heat maps are traced in a Web Worker (the page's one thread keeps drawing)
  // and the app logs when the last band is in, and where; the list went on past it, so it is
  // opened again.
  const heatIndex = lessonNumbers.indexOf(14);
  await page.mouse.click(60, 65 + 23 * heatIndex);
  await page.waitForFunction((text) => document.title.includes(text), '14. ', { timeout: 20_000 })
    .catch(() => {});
  check((await page.title()).includes('14. '), `the heat maps' lesson is open: "${await page.title()}"`);
  const heatStart = Date.now();
  for (let tries = 0; tries < 600 && !logLines.some((line) => line.includes('heat maps')); tries++) {
    await page.waitForTimeout(100);
  }
  const heatLine = logLines.find((line) => line.includes('heat maps')) ?? '';
  const heat = heatLine.match(/heat maps (\d+)x(\d+) traced in (\d+) ms/);
  check(heat !== null && /Web Worker/.test(heatLine), `the heat maps are traced in Web Workers: "${heatLine.replace(/^.*accelviz: /, '')}" (waited ${((Date.now() - heatStart) / 1000).toFixed(1)} s)`);
  await page.waitForTimeout(300);
  const heatShot = decodePng(await page.screenshot({ path: path.join(shotDir, 'web-heat-maps.png') }));
  check(colourCount(heatShot) > 200, `the heat maps are drawn (${colourCount(heatShot)} colours)`);

  // Lesson 16, the trade lab, measures every structure and switch on its built-in mesh in a
  // Web Worker, and shows its table: opened from a link with few rays and one round (its
  // 3,000 rays in three rounds take half a minute here, for the same check), under a query of
  // its own (a later link that differs only after the # would not reload the page).
  await page.goto(`${url}?lab#v=1&lesson=16&ray-count=300&rounds=1`);
  await page.waitForFunction((text) => document.title.includes(text), '16. ', { timeout: 120_000 })
    .catch(() => {});
  const tradeStart = Date.now();
  for (let tries = 0; tries < 1200 && !logLines.some((line) => line.includes('trade lab measured')); tries++) {
    await page.waitForTimeout(100);
  }
  const tradeLine = logLines.find((line) => line.includes('trade lab measured')) ?? '';
  check(/trade lab measured \d+ rows/.test(tradeLine), `the trade lab measures in the browser: "${tradeLine.replace(/^.*accelviz: /, '')}" (waited ${((Date.now() - tradeStart) / 1000).toFixed(1)} s)`);
  // Off the page's frame loop: timed between frames, the rounds spread by ±50 % and more.
  check(tradeLine.endsWith('in a Web Worker'), `the trade lab measures in a Web Worker, off the page's frames`);
  await page.waitForTimeout(300);
  const tradeShot = decodePng(await page.screenshot({ path: path.join(shotDir, 'web-trade-lab.png') }));
  check(colourCount(tradeShot) > 50, `the trade lab's table is drawn (${colourCount(tradeShot)} colours)`);

  // Lesson 17, cracks: its first ray, aimed at an edge two triangles share, slips through
  // the fast test in f32 and not in f64, by the core's own test compiled to WASM.
  const crackLine = logLines.find((line) => line.includes('accelviz: cracks:')) ?? '';
  check(/in f32 slips through, in f64 hits/.test(crackLine), `the cracks lesson's ray slips through in f32 only: "${crackLine.replace(/^.*accelviz: /, '')}"`);
  await page.mouse.click(60, 65 + 23 * lessonNumbers.indexOf(17));
  await page.waitForFunction((text) => document.title.includes(text), '17. ', { timeout: 20_000 })
    .catch(() => {});
  await page.waitForTimeout(300);
  const crackShot = decodePng(await page.screenshot({ path: path.join(shotDir, 'web-cracks.png') }));
  check(colourCount(crackShot) > 50, `the cracks lesson draws (${colourCount(crackShot)} colours)`);

  // An OBJ dropped onto the page opens in lesson 12.
  await page.mouse.click(60, 65 + 23 * 11);
  await page.waitForFunction(() => document.title.includes('12. '), null, { timeout: 20_000 }).catch(() => {});
  await page.waitForTimeout(500);
  const beforeDrop = decodePng(await page.screenshot());
  const obj = 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n';
  await dropFile(page, 'dropped.obj', obj);
  for (let tries = 0; tries < 100 && !logLines.some((line) => line.includes('opened dropped.obj')); tries++) {
    await page.waitForTimeout(100);
  }
  check(logLines.some((line) => line.includes('accelviz: opened dropped.obj')), 'an OBJ dropped onto the page opens');
  await page.waitForTimeout(500);
  const afterDrop = decodePng(await page.screenshot({ path: path.join(shotDir, 'web-dropped.png') }));
  check(differingShare(beforeDrop, afterDrop) > 0.02, `the dropped mesh is drawn (${(100 * differingShare(beforeDrop, afterDrop)).toFixed(1)} % of pixels changed)`);

  // A large OBJ (a grid of 134k triangles, 3.5 MB) is read and built in a Web Worker: the
  // page keeps drawing meanwhile (animation frames keep coming), and the mesh arrives.
  await page.evaluate(() => {
    window.frameGaps = [];
    let last = performance.now();
    const tick = (now) => { window.frameGaps.push(now - last); last = now; requestAnimationFrame(tick); };
    requestAnimationFrame(tick);
  });
  const side = 260;
  const lines = [];
  for (let y = 0; y < side; y++) {
    for (let x = 0; x < side; x++) lines.push(`v ${x} ${y} ${Math.sin(x / 9) * Math.cos(y / 7) * 8}`);
  }
  for (let y = 0; y + 1 < side; y++) {
    for (let x = 0; x + 1 < side; x++) {
      const corner = y * side + x + 1;
      lines.push(`f ${corner} ${corner + 1} ${corner + side}`, `f ${corner + 1} ${corner + side + 1} ${corner + side}`);
    }
  }
  const largeObj = lines.join('\n') + '\n';
  const largeStart = Date.now();
  await page.evaluate(() => { window.frameGaps = []; });
  await dropFile(page, 'large.obj', largeObj);
  const builtAside = () => logLines.find((line) => line.includes('built aside over 134162 triangles'));
  for (let tries = 0; tries < 600 && !builtAside(); tries++) await page.waitForTimeout(100);
  const gaps = await page.evaluate(() => window.frameGaps);
  check(builtAside() !== undefined,
    `a ${(largeObj.length / 1e6).toFixed(1)} MB OBJ is read and built in a Web Worker: "${(builtAside() ?? 'no such log line').replace(/^.*accelviz: /, '')}" (${((Date.now() - largeStart) / 1000).toFixed(1)} s)`);
  check(gaps.length >= 5,
    `the page kept drawing meanwhile: ${gaps.length} animation frames, the longest gap ${Math.max(...gaps, 0).toFixed(0)} ms`);
  await page.waitForTimeout(1000);
  await page.screenshot({ path: path.join(shotDir, 'web-large-mesh.png') });

  // The BVH lesson, fourth in the list, for the step test.
  await page.mouse.click(60, 65 + 23 * 3);
  await page.waitForFunction(() => document.title.includes('hierarchy'), null, { timeout: 10_000 })
    .catch(() => {});
  const lessonTitle = await page.title();
  check(lessonTitle.includes('Bounding volume hierarchy'), `a click on a lesson opens it: "${lessonTitle}"`);
  await page.waitForTimeout(300);
  const lesson = decodePng(await page.screenshot({ path: path.join(shotDir, 'web-lesson.png') }));
  check(differingShare(first, lesson) > 0.05, `the lesson changed the picture (${(100 * differingShare(first, lesson)).toFixed(1)} % of pixels)`);

  // The timeline's "step >" button, bottom left.
  await page.mouse.click(183, viewport.height - 43);
  await page.waitForFunction(() => document.title.includes('step 1 of'), null, { timeout: 10_000 }).catch(() => {});
  const stepTitle = await page.title();
  check(stepTitle.includes('step 1 of'), `a click on "step" advances the animation: "${stepTitle}"`);
  await page.waitForTimeout(300);
  const stepped = decodePng(await page.screenshot({ path: path.join(shotDir, 'web-step.png') }));
  check(differingShare(lesson, stepped) > 0.0005, `the step changed the picture (${(100 * differingShare(lesson, stepped)).toFixed(2)} % of pixels)`);

  // Download the scene: "Save scene…" in the top bar (its place with lesson 4's title). The
  // pointer rests on a button a moment before it clicks, as a person's does.
  await page.mouse.move(564, 12);
  await page.waitForTimeout(200);
  const [download] = await Promise.all([
    page.waitForEvent('download', { timeout: 10_000 }),
    page.mouse.click(564, 12),
  ]);
  const saved = fs.readFileSync(await download.path(), 'utf8');
  check(download.suggestedFilename() === 'scene.ron' && saved.includes('Segment(') && saved.includes('ray:'),
    `"Save scene…" downloads the scene (${download.suggestedFilename()}, ${saved.length} bytes)`);

  // Upload a scene: "Open scene…" opens the browser's file chooser.
  const upload = '(shapes: [Disc(center: (20, 20), radius: 5), Box(min: (40, 40), max: (60, 50))],' +
    ' ray: (origin: (0, 0), toward: (1, 1)))';
  const file = { name: 'upload.ron', mimeType: 'text/plain', buffer: Buffer.from(upload) };
  // The file chooser is intercepted only once Playwright has asked the browser to: listen
  // before the pointer even moves. A chooser the browser shows before that is cancelled at
  // once (the app logs "no file chosen"); then the click is repeated, as a person would.
  let chooser = null;
  let clicks = 0;
  for (; clicks < 3 && !chooser; clicks++) {
    const chooserEvent = page.waitForEvent('filechooser', { timeout: 15_000 }).catch(() => null);
    await page.waitForTimeout(300);
    await page.mouse.move(370, 12);
    await page.waitForTimeout(200);
    await page.mouse.click(370, 12);
    chooser = await chooserEvent;
  }
  if (!chooser) {
    await page.screenshot({ path: path.join(shotDir, 'web-open-failed.png') });
    console.log('console:\n  ' + logLines.join('\n  '));
    throw new Error('"Open scene…" showed no file chooser in three clicks');
  }
  await chooser.setFiles(file);
  for (let tries = 0; tries < 100 && !logLines.some((line) => line.includes('opened upload.ron')); tries++) {
    await page.waitForTimeout(100);
  }
  check(logLines.some((line) => line.includes('accelviz: opened upload.ron')),
    `"Open scene…" uploads a scene into the lesson (${clicks === 1 ? 'one click' : `${clicks} clicks`})`);
  const uploaded = decodePng(await page.screenshot({ path: path.join(shotDir, 'web-uploaded.png') }));
  check(differingShare(stepped, uploaded) > 0.02, `the uploaded scene is drawn (${(100 * differingShare(stepped, uploaded)).toFixed(1)} % of pixels changed)`);

  // The quiz: answer a few steps by keyboard, reload the page, find the progress there. Its
  // entry sits below the lesson list, one row (23 px) lower for each lesson past 14.
  const quizY = 470 + 23 * (lessonNumbers.length - 14);
  const quizTitle = () => page.title();
  await page.mouse.click(60, quizY);
  await page.waitForFunction(() => document.title.includes('quiz seed'), null, { timeout: 20_000 })
    .catch(() => {});
  check(/quiz seed 1, question 1 of \d+, step 1/.test(await quizTitle()), `the quiz opens at its start: "${await quizTitle()}"`);
  await page.screenshot({ path: path.join(shotDir, 'web-quiz.png') });
  for (let answer = 0; answer < 3; answer++) {
    // A moment for the step's controls (a number's field takes the keys once focused).
    await page.waitForTimeout(400);
    const before = await quizTitle();
    if (before.includes('(a number')) {
      await page.keyboard.type('1');
      await page.keyboard.press('Enter');
    } else {
      await page.keyboard.press('a');
    }
    await page.waitForFunction((text) => document.title !== text, before, { timeout: 10_000 }).catch(() => {});
    await page.waitForTimeout(100);
    const answered = await quizTitle();
    await page.keyboard.press('Enter');
    await page.waitForFunction((text) => document.title !== text, answered, { timeout: 10_000 }).catch(() => {});
  }
  const progressTitle = await quizTitle();
  check(progressTitle.includes('score') && progressTitle.includes('of 3'), `three steps answered by keyboard: "${progressTitle}"`);
  const stored = await page.evaluate(() => window.localStorage.getItem('accelviz-quiz-progress'));
  check(stored !== null && stored.includes('"responses"'), `the progress is in localStorage (${stored ? stored.length : 0} bytes)`);
  await page.reload();
  await page.waitForFunction(() => document.title.includes('step'), null, { timeout: 120_000 });
  await page.waitForTimeout(300);
  await page.mouse.click(60, quizY);
  await page.waitForFunction(() => document.title.includes('quiz seed'), null, { timeout: 20_000 })
    .catch(() => {});
  const reloadedTitle = await quizTitle();
  const place = (title) => title.replace(/^.*quiz /, '');
  check(place(reloadedTitle) === place(progressTitle), `after a reload the quiz is where it was: "${place(reloadedTitle)}"`);

  // A shared link opens exactly its view; a garbage one opens the first lesson and says why.
  await page.goto(`${url}?shared#v=1&lesson=4&step=3&structure=bvh:median`);
  await page.waitForFunction(() => document.title.includes('hierarchy, step 3 of'), null, { timeout: 120_000 })
    .catch(() => {});
  const sharedTitle = await page.title();
  check(sharedTitle.includes('4. Bounding volume hierarchy, step 3 of'), `a shared link opens its lesson at its step: "${sharedTitle}"`);
  check(logLines.some((line) => line.includes('opened a shared view of lesson 4')), 'the link\'s view was opened');
  await page.screenshot({ path: path.join(shotDir, 'web-shared.png') });
  await page.goto(`${url}?garbage#this-is-not-a-view`);
  await page.waitForFunction(() => document.title.includes('step'), null, { timeout: 120_000 });
  const garbageTitle = await page.title();
  check(garbageTitle.includes('1. The trivial loop'), `a garbage link opens the first lesson: "${garbageTitle}"`);
  check(logLines.some((line) => line.includes('shared view could not be opened')), 'and says why');
  // The garbage link's message is a warning, not an error.

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
  if (failures.length) console.log('console:\n  ' + logLines.join('\n  '));
} finally {
  await browser.close();
  server.close();
}
console.log(failures.length ? `e2e: ${failures.length} check(s) failed` : 'e2e: all checks passed');
process.exit(failures.length ? 1 : 0);
