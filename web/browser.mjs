// What the browser scripts share: a static server for web/ and headless Chromium started the
// way this machine can run it (software WebGL2 through SwiftShader; see TOOLCHAIN notes).

import { chromium } from 'playwright-core';

/** Serves `dir` (web/) on a free loopback port, compressed as `node web/serve.mjs` serves it. */
export { serve } from './serve.mjs';

/** Headless Chromium (`CHROMIUM`, else Debian's) drawing WebGL2 in software. */
export function launchChromium() {
  return chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking',
      '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
}

/** Drops a file named `name` holding `text` onto the app's canvas, as a person dragging it. */
export async function dropFile(page, name, text) {
  await page.evaluate(([fileName, fileText]) => {
    const transfer = new DataTransfer();
    transfer.items.add(new File([fileText], fileName, { type: 'text/plain' }));
    const canvas = document.getElementById('accelviz_canvas');
    for (const type of ['dragenter', 'dragover', 'drop']) {
      canvas.dispatchEvent(new DragEvent(type, { dataTransfer: transfer, bubbles: true, cancelable: true }));
    }
  }, [name, text]);
}
