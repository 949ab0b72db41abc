// End-to-end check of the live view as a person sees it: runs a small scene with
// `demlink-run --view`, opens the page in headless Chromium through the DevTools protocol,
// and checks the screenshots' pixels (the 16 spheres of a known grid drawn where the scene
// has them, empty space empty, a moving box in a different place in two frames), the
// overlay's figures against the run's own outputs, and that the page logged no error.
//
//   node check_view_in_browser.mjs --run DEMLINK_RUN --scene SCENE
//        --out DIR [--chromium PATH] [--screenshot PNG]
// Prints "N passed, M failed"; exits 1 on any failure.
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';

import { DevTools, chromiumArguments } from './devtools_pipe.mjs';
import { args, check, children, collectPageErrors, deadline, finish, sleep } from './check_harness.mjs';

const chromiumPath = args.chromium ?? '/usr/bin/chromium';
const outDir = path.resolve(args.out);
fs.rmSync(outDir, { recursive: true, force: true });
fs.mkdirSync(outDir, { recursive: true });

// The scene's known arrangement (view_scene.json).
const kGrid = [];
for (let i = 0; i < 4; ++i) for (let j = 0; j < 4; ++j) kGrid.push([0.04 * i, 0.04 * j, 0.0]);
const kRadius = 0.01, kDensity = 2500, kEndTime = 16.0;
const kBoxStart = [-0.15, 0.06, 0.1], kBoxVelocity = [0.02, 0, 0];
const kBackground = [0x1e, 0x21, 0x26];

deadline(240);

/// Waits until `pattern` appears in the output a child wrote so far; returns the match.
function waitForOutput(child, text, pattern, seconds) {
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`no ${pattern} within ${seconds} s`)), seconds * 1000);
    const poll = setInterval(() => {
      const match = text().match(pattern);
      if (match) { clearTimeout(timer); clearInterval(poll); resolve(match); }
      if (child.exitCode !== null && !match) {
        clearTimeout(timer); clearInterval(poll);
        reject(new Error(`process exited (${child.exitCode}) before ${pattern}:\n${text()}`));
      }
    }, 100);
  });
}

// ---- PNG (8-bit RGB or RGBA, as Chromium writes them) ----
function decodePng(buffer) {
  let offset = 8, width = 0, height = 0, colourType = 0;
  const idat = [];
  while (offset < buffer.length) {
    const length = buffer.readUInt32BE(offset);
    const type = buffer.toString('ascii', offset + 4, offset + 8);
    const data = buffer.subarray(offset + 8, offset + 8 + length);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0); height = data.readUInt32BE(4); colourType = data[9];
      if (data[8] !== 8 || data[12] !== 0 || (colourType !== 2 && colourType !== 6)) throw new Error('unsupported PNG');
    } else if (type === 'IDAT') idat.push(data);
    offset += 12 + length;
  }
  const channels = colourType === 6 ? 4 : 3;
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const pixels = Buffer.alloc(height * stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    for (let x = 0; x < stride; ++x) {
      const value = raw[y * (stride + 1) + 1 + x];
      const a = x >= channels ? pixels[y * stride + x - channels] : 0;
      const b = y > 0 ? pixels[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? pixels[(y - 1) * stride + x - channels] : 0;
      let predicted = 0;
      if (filter === 1) predicted = a;
      else if (filter === 2) predicted = b;
      else if (filter === 3) predicted = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        predicted = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      pixels[y * stride + x] = (value + predicted) & 0xff;
    }
  }
  return { width, height, pixel: (x, y) => {
    const at = Math.round(y) * stride + Math.round(x) * channels;
    return [pixels[at], pixels[at + 1], pixels[at + 2]];
  } };
}
const distance = (p, q) => Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
/// Whether anything but background is drawn within 1 px of (x, y).
function drawnAt(image, x, y) {
  for (const [dx, dy] of [[0, 0], [1, 0], [-1, 0], [0, 1], [0, -1]]) {
    if (distance(image.pixel(x + dx, y + dy), kBackground) > 30) return true;
  }
  return false;
}

async function main() {
  // The run, on a free port, at most 1 simulated second per wall second.
  let runLog = '';
  const run = spawn(args.run, [args.scene, '--output', path.join(outDir, 'run'), '--view', '127.0.0.1:0',
    '--view-linger', '120', '--pace', '1'], { stdio: ['ignore', 'pipe', 'pipe'] });
  children.push(run);
  run.stdout.on('data', (d) => { runLog += d; });
  run.stderr.on('data', (d) => { runLog += d; });
  const [, url] = await waitForOutput(run, () => runLog, /view: (http:\/\/127\.0\.0\.1:\d+\/)/, 60);
  check(true, `the run serves its view at ${url}`);

  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'demlink-view-chromium-'));
  let browserLog = '';
  const browser = spawn(chromiumPath, chromiumArguments(profile), { stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
  children.push(browser);
  browser.stderr.on('data', (d) => { browserLog += d; });
  browser.on('exit', (code) => { if (code) console.log(`chromium exited with ${code}:\n${browserLog.slice(-2000)}`); });
  const devtools = new DevTools(browser);
  const { targetId } = await devtools.send('Target.createTarget', { url: 'about:blank' });
  const { sessionId } = await devtools.send('Target.attachToTarget', { targetId, flatten: true });
  const page = (method, params) => devtools.send(method, params, sessionId);
  const errors = collectPageErrors(devtools, new Set([sessionId]));
  await page('Runtime.enable');
  await page('Log.enable');
  await page('Page.enable');
  await page('Emulation.setDeviceMetricsOverride', { width: 900, height: 700, deviceScaleFactor: 1, mobile: false });
  await page('Page.navigate', { url });
  const evaluate = async (expression) => {
    const { result, exceptionDetails } = await page('Runtime.evaluate', { expression, returnByValue: true, awaitPromise: true });
    if (exceptionDetails) throw new Error(`${expression}: ${exceptionDetails.text}`);
    return result.value;
  };
  const waitFor = async (expression, seconds, what) => {
    for (let k = 0; k < seconds * 10; ++k) {
      try { if (await evaluate(expression)) return true; } catch { /* the page is still loading */ }
      await sleep(100);
    }
    throw new Error(`timed out waiting for ${what}`);
  };
  await waitFor('window.demlinkView && window.demlinkView.status && window.demlinkView.status.time > 0.5', 90,
    'a frame past t = 0.5 s');

  // Freezes the view (the run goes on), waits for a drawn frame, reads it, screenshots it.
  const look = async () => {
    await evaluate(`document.getElementById('pause').click()`);
    await sleep(400);
    const seen = await evaluate(`(() => {
      const v = window.demlinkView;
      const project = (p) => v.project(p[0], p[1], p[2]);
      return { time: v.status.time, particles: v.status.particles, shown: v.status.shown, fps: v.fps,
        grid: ${JSON.stringify(kGrid)}.map(project),
        below: ${JSON.stringify(kGrid)}.map((p) => project([p[0], p[1], p[2] - 0.12])) };
    })()`);
    const { data } = await page('Page.captureScreenshot', { format: 'png' });
    const png = Buffer.from(data, 'base64');
    await evaluate(`document.getElementById('pause').click()`);
    return { ...seen, png, image: decodePng(png) };
  };
  const boxAt = (time) => kBoxStart.map((x, k) => x + kBoxVelocity[k] * time);
  const projectIn = async (point) => evaluate(`window.demlinkView.project(${point.join(',')})`);

  const first = await look();
  fs.writeFileSync(path.join(outDir, 'view_first.png'), first.png);
  check(first.particles === 16 && first.shown === 16, `first frame: 16 particles, 16 shown (got ${first.particles}, ${first.shown})`);
  const missing = first.grid.filter((p) => !drawnAt(first.image, p.x, p.y));
  check(missing.length === 0, `every grid sphere is drawn at its projected place (${16 - missing.length} of 16)`);
  const filled = first.below.filter((p) => drawnAt(first.image, p.x, p.y));
  check(filled.length === 0, `empty space below the grid stays empty (${filled.length} of 16 points drawn)`);

  // The box (0.06 m wide) moves at 0.02 m/s: 4 s later it is 0.08 m further along x. The
  // camera has not moved since the first look, so projecting now gives the first look's pixels.
  const boxFirst = await projectIn(boxAt(first.time));
  await waitFor(`window.demlinkView.status.time > ${first.time + 4.0}`, 60, 'a frame 4 s later');
  const second = await look();
  fs.writeFileSync(path.join(outDir, 'view_second.png'), second.png);
  const boxSecond = await projectIn(boxAt(second.time));
  const onScreen = (p) => p.x >= 0 && p.x < first.image.width && p.y >= 0 && p.y < first.image.height;
  check(onScreen(boxFirst) && onScreen(boxSecond) && Math.hypot(boxFirst.x - boxSecond.x, boxFirst.y - boxSecond.y) > 20,
    `the box's two places are apart on screen (${boxFirst.x.toFixed(0)},${boxFirst.y.toFixed(0)} and ${boxSecond.x.toFixed(0)},${boxSecond.y.toFixed(0)})`);
  check(drawnAt(first.image, boxFirst.x, boxFirst.y) && !drawnAt(first.image, boxSecond.x, boxSecond.y),
    `first frame (t = ${first.time.toFixed(2)} s): the box is drawn where it was, not where it will be`);
  check(drawnAt(second.image, boxSecond.x, boxSecond.y) && !drawnAt(second.image, boxFirst.x, boxFirst.y),
    `second frame (t = ${second.time.toFixed(2)} s): the box is drawn where it went, not where it was`);

  // The run ends; the view keeps its final state. The overlay must say what the run wrote.
  await waitForOutput(run, () => runLog, /view: serving the final state/, 120);
  await waitFor(`window.demlinkView.status.time >= ${kEndTime - 1e-9}`, 30, 'the final frame');
  await sleep(300);
  const overlay = await evaluate(`Object.fromEntries(['time', 'particles', 'mass', 'inserted', 'removed', 'balance', 'rtf', 'steprate', 'fps']
      .map((id) => [id, document.getElementById(id).textContent]))`);
  const finalCsv = fs.readFileSync(path.join(outDir, 'run', 'particles_final.csv'), 'utf8').trim().split('\n')
    .filter((line) => line && !line.startsWith('#'));
  const header = finalCsv[0].split(',');
  const rows = finalCsv.slice(1).map((line) => line.split(','));
  const radiusColumn = header.indexOf('radius');
  const runMass = rows.reduce((sum, row) => sum + 4 / 3 * Math.PI * Number(row[radiusColumn]) ** 3 * kDensity, 0);
  const summary = fs.readFileSync(path.join(outDir, 'run', 'summary.csv'), 'utf8').trim().split('\n');
  const summaryHeader = summary[0].split(',');
  const lastRow = summary[summary.length - 1].split(',');
  const summaryTime = Number(lastRow[summaryHeader.findIndex((name) => name.startsWith('time'))]);
  check(overlay.time === kEndTime.toFixed(6) && Math.abs(summaryTime - kEndTime) < 1e-9,
    `overlay time ${overlay.time} s = the run's last summary row (${summaryTime} s)`);
  check(Number(overlay.particles) === rows.length, `overlay particles ${overlay.particles} = rows of particles_final.csv (${rows.length})`);
  check(radiusColumn >= 0 && Math.abs(Number(overlay.mass) - runMass) <= 1e-5 * runMass,
    `overlay mass ${overlay.mass} kg = the final particles' mass ${runMass.toPrecision(6)} kg`);
  check(Number(overlay.balance) === 0 && Number(overlay.inserted) === 0 && Number(overlay.removed) === 0,
    `mass balance: inserted ${overlay.inserted}, removed ${overlay.removed}, error ${overlay.balance} kg`);
  check(Number(overlay.fps) > 0, `the page draws (${overlay.fps} frames/s)`);
  check(errors.length === 0, `no errors in the page's console${errors.length ? ': ' + errors.join('; ') : ''}`);
  if (args.screenshot) fs.copyFileSync(path.join(outDir, 'view_first.png'), args.screenshot);
  await devtools.send('Browser.close').catch(() => {});
}

main().then(finish, (error) => { check(false, error.stack ?? String(error)); finish(); });
