// Choosing among a server's simulations in the page, in headless Chromium: the view fixture
// steps three scenes at once (3 x 3 spheres, 5 x 5 spheres, and a mass-spring sheet of two
// triangles and five springs, one of which tears at the first step), the page must list
// them, and picking one in its list must bring that simulation's frames: the overlay's
// particle count follows the choice, each way. The sheet is drawn with its four intact
// springs and the one triangle the torn spring leaves supported. The page's console must
// stay free of errors.
//
//   node check_view_choice.mjs --fixture DEMLINK_VIEW_FIXTURE --scenes SMALL,LARGE,SHEET [--chromium PATH]
// Prints "N passed, M failed"; exits 1 on any failure.
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

import { DevTools, chromiumArguments, evaluate } from './devtools_pipe.mjs';
import { args, check, children, deadline, finish, sleep } from './check_harness.mjs';

const scenes = args.scenes.split(',');
const kExpected = {
  [path.basename(scenes[0], '.json')]: { particles: 9 },
  [path.basename(scenes[1], '.json')]: { particles: 25 },
  [path.basename(scenes[2], '.json')]: { particles: 0, surfaces: [{ triangles: 1, springs: 4 }] },
};

deadline(150);

async function main() {
  let log = '';
  const fixture = spawn(args.fixture, ['140', ...scenes], { stdio: ['ignore', 'pipe', 'pipe'] });
  children.push(fixture);
  fixture.stdout.on('data', (d) => { log += d; });
  fixture.stderr.on('data', (d) => { log += d; });
  for (let k = 0; k < 600 && !/view: (\S+)/.test(log); ++k) {
    if (fixture.exitCode !== null) throw new Error(`the fixture exited (${fixture.exitCode}): ${log}`);
    await sleep(100);
  }
  const url = log.match(/view: (\S+)/)[1];

  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'demlink-view-choice-'));
  const browser = spawn(args.chromium ?? '/usr/bin/chromium', chromiumArguments(profile), { stdio: ['ignore', 'ignore', 'ignore', 'pipe', 'pipe'] });
  children.push(browser);
  const devtools = new DevTools(browser);
  const page = await devtools.openPage('about:blank');
  const errors = [];
  devtools.listeners.push((message) => {
    if (message.sessionId !== page.sessionId) return;
    if (message.method === 'Runtime.exceptionThrown') errors.push(`${message.params.exceptionDetails.text} ${message.params.exceptionDetails.exception?.description ?? ''}`);
    if (message.method === 'Runtime.consoleAPICalled' && message.params.type === 'error') errors.push(JSON.stringify(message.params.args));
    if (message.method === 'Log.entryAdded' && message.params.entry.level === 'error') errors.push(message.params.entry.text);
  });
  await page('Runtime.enable');
  await page('Log.enable');
  await page('Page.navigate', { url });
  const waitFor = async (expression, seconds, what) => {
    for (let k = 0; k < seconds * 10; ++k) {
      try { if (await evaluate(page, expression)) return true; } catch { /* the page is still loading */ }
      await sleep(100);
    }
    throw new Error(`timed out waiting for ${what}${errors.length ? '; the page logged: ' + errors.slice(0, 3).join('; ') : ''}`);
  };
  await waitFor(`window.demlinkView && window.demlinkView.status && window.demlinkView.simulations.length === 3`, 60,
    'a frame and a list of three simulations');
  const listed = await evaluate(page, `(() => {
    const choice = document.getElementById('simulation-choice');
    return { visible: getComputedStyle(choice).display !== 'none',
      options: Array.from(document.getElementById('simulation').options, (o) => ({ id: o.value, text: o.textContent })),
      simulations: window.demlinkView.simulations };
  })()`);
  check(listed.visible, 'the page shows its list of simulations');
  check(listed.simulations.every((s) => kExpected[s.name]?.particles === s.particles) && listed.options.length === 3,
    `the list names each with its particle count (${listed.options.map((o) => o.text).join('; ')})`);
  const overlayParticles = () => evaluate(page, `Number(document.getElementById('particles').textContent)`);
  // Each in turn, the one not shown first: the overlay's particle count must follow.
  const firstShown = await overlayParticles();
  const order = [...listed.simulations].sort((a, b) => (a.particles === firstShown) - (b.particles === firstShown));
  for (const simulation of [...order, ...order]) {
    await evaluate(page, `(() => {
      const select = document.getElementById('simulation');
      select.value = '${simulation.id}';
      select.dispatchEvent(new Event('change'));
    })()`);
    await waitFor(`Number(document.getElementById('particles').textContent) === ${simulation.particles}`, 20,
      `${simulation.name}'s frames`).catch(() => {});
    await sleep(1500);  // later frames must stay the chosen simulation's, and the list say so
    const shown = await overlayParticles();
    const followed = await evaluate(page, `window.demlinkView.followed`);
    const selected = await evaluate(page, `document.getElementById('simulation').value`);
    check(shown === simulation.particles && followed === simulation.id && selected === String(simulation.id),
      `chose ${simulation.name}: overlay ${shown} particles (expected ${simulation.particles}), followed ${followed}, selected ${selected}`);
    const surfaces = JSON.stringify(await evaluate(page, `window.demlinkView.surfaces`));
    const expected = JSON.stringify(kExpected[simulation.name].surfaces ?? []);
    check(surfaces === expected, `${simulation.name} draws surfaces ${surfaces} (expected ${expected}: torn springs and the triangles they held are not drawn)`);
  }
  check(errors.length === 0, `no errors in the page's console${errors.length ? ': ' + errors.join('; ') : ''}`);
  await devtools.send('Browser.close').catch(() => {});
}

main().then(finish, (error) => { check(false, error.stack ?? String(error)); finish(); });
