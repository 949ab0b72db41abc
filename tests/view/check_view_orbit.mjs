// The page while its camera moves, in headless Chromium: demlink-bench-view serves 50,000
// particles; a mouse drags across the page (the camera orbits). While it moves the page
// draws every k-th splat, fewer than all, and does not choose its spheres again; once the
// mouse is released and the camera is still, it draws all of them and chooses again. The
// page's console must stay free of errors.
//
//   node check_view_orbit.mjs --fixture DEMLINK_BENCH_VIEW [--chromium PATH]
// Prints "N passed, M failed"; exits 1 on any failure.
import { evaluate } from './devtools_pipe.mjs';
import { args, check, collectPageErrors, deadline, finish, sleep, startBrowser, startFixture } from './check_harness.mjs';

const kParticles = 50000;
deadline(150);

async function main() {
  const url = await startFixture(['--particles', String(kParticles), '--serve', '120']);
  const devtools = startBrowser('demlink-view-orbit-');
  const page = await devtools.openPage('about:blank');
  const errors = collectPageErrors(devtools, new Set([page.sessionId]));
  await page('Runtime.enable');
  await page('Log.enable');
  await page('Page.navigate', { url });
  let shown = false;
  for (let k = 0; k < 600 && !shown; ++k) {
    try { shown = await evaluate(page, `window.demlinkView?.status?.shown === ${kParticles}`); } catch { /* loading */ }
    if (!shown) await sleep(100);
  }
  check(shown, `the page shows the ${kParticles} particles`);
  await sleep(1500);
  check(await evaluate(page, `!window.demlinkView.moving && window.demlinkView.splatsDrawn === ${kParticles}`),
    'still camera: every splat drawn');

  const mouse = (type, x) => page('Input.dispatchMouseEvent', { type, x, y: 350, button: 'left', buttons: 1, clickCount: 1 });
  await mouse('mousePressed', 300);
  const whileMoving = [];
  // Each move waits for the page to take it (a frame of 50,000 splats in SwiftShader).
  for (let x = 300; x < 600; x += 10) {
    await mouse('mouseMoved', x);
    await sleep(20);
    if (x % 50 === 0) {
      whileMoving.push(await evaluate(page, `({ moving: window.demlinkView.moving, drawn: window.demlinkView.splatsDrawn })`));
    }
  }
  await mouse('mouseReleased', 600);
  const subset = whileMoving.filter((r) => r.moving && r.drawn > 0 && r.drawn < kParticles);
  check(subset.length > 0, `moving camera: a subset of the splats drawn (readings ${JSON.stringify(whileMoving.slice(0, 6))})`);
  await sleep(1500);
  const still = await evaluate(page, `({ moving: window.demlinkView.moving, drawn: window.demlinkView.splatsDrawn })`);
  check(!still.moving && still.drawn === kParticles, `camera still again: every splat drawn (${JSON.stringify(still)})`);
  check(errors.length === 0, `no errors in the page's console (${errors.slice(0, 3).join('; ')})`);
}

main().catch((error) => check(false, `ran to the end (${error.stack ?? error})`)).finally(finish);
