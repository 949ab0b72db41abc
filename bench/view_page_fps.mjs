// The view page's drawing rate in headless Chromium (SwiftShader, no GPU) at a given
// particle count: starts `demlink-bench-view --serve`, opens the page, lets it draw for
// `--seconds`, and prints the median of the page's once-a-second frame-rate readings.
// With `--orbit 1` a mouse drags across the page all the while (the camera orbits, as a
// user turning the view does): the rate is then the page's interactivity.
//   node bench/view_page_fps.mjs --bench build/release/bench/demlink-bench-view --particles 100000
//        [--seconds 20] [--orbit 1] [--chromium /usr/bin/chromium]
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

import { DevTools, chromiumArguments, evaluate } from '../tests/view/devtools_pipe.mjs';

const args = Object.fromEntries(process.argv.slice(2).reduce((pairs, arg, i, all) => {
  if (arg.startsWith('--')) pairs.push([arg.slice(2), all[i + 1]]);
  return pairs;
}, []));
const seconds = Number(args.seconds ?? 20);
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

const server = spawn(args.bench, ['--particles', args.particles, '--serve', String(seconds + 120)], { stdio: ['ignore', 'pipe', 'inherit'] });
let log = '';
server.stdout.on('data', (d) => { log += d; });
while (!/view: (\S+)/.test(log)) {
  if (server.exitCode !== null) throw new Error(`the bench exited: ${log}`);
  await sleep(100);
}
const url = log.match(/view: (\S+)/)[1];
const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'demlink-view-fps-'));
const browser = spawn(args.chromium ?? '/usr/bin/chromium', chromiumArguments(profile), { stdio: ['ignore', 'ignore', 'ignore', 'pipe', 'pipe'] });
const devtools = new DevTools(browser);
const page = await devtools.openPage(url);
try {
  await page('Page.navigate', { url });
  for (let k = 0; k < 1200; ++k) {
    try { if (await evaluate(page, `window.demlinkView && window.demlinkView.status && window.demlinkView.status.shown > 0`)) break; } catch { /* loading */ }
    await sleep(100);
  }
  await sleep(3000);  // past the first frames' uploads
  const orbit = args.orbit === '1';
  let dragging = orbit;
  const drag = (async () => {
    if (!dragging) return;
    const mouse = (type, x) => page('Input.dispatchMouseEvent', { type, x, y: 350, button: 'left', buttons: 1, clickCount: 1 });
    await mouse('mousePressed', 300);
    for (let x = 300; dragging; x = x >= 600 ? 300 : x + 4) {
      await mouse('mouseMoved', x);
      await sleep(15);
    }
    await mouse('mouseReleased', 300);
  })();
  const readings = [];
  const drawnSplats = [];
  for (let k = 0; k < seconds; ++k) {
    await sleep(1000);
    readings.push(await evaluate(page, 'window.demlinkView.fps'));
    drawnSplats.push(await evaluate(page, 'window.demlinkView.splatsDrawn ?? -1'));
  }
  dragging = false;
  await drag;
  const state = await evaluate(page, `({ shown: window.demlinkView.status.shown, near: window.demlinkView.nearCount,
    received: window.demlinkView.framesReceived, bytes: window.demlinkView.bytes })`);
  readings.sort((a, b) => a - b);
  console.log(`particles ${args.particles}: page draws ${readings[Math.floor(readings.length / 2)].toFixed(1)} frames/s ` +
    `(median of ${readings.length} readings, range ${readings[0].toFixed(1)}-${readings[readings.length - 1].toFixed(1)}); ` +
    `${state.shown} shown, ${state.near} as spheres, ${state.received} frames received, last ${state.bytes} bytes` +
    (orbit ? `; orbiting, splats drawn (median) ${drawnSplats.sort((a, b) => a - b)[Math.floor(drawnSplats.length / 2)]}` : ''));
} finally {
  browser.kill('SIGTERM');
  server.kill('SIGTERM');
}
