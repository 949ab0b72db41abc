// Choosing among a server's simulations in the page, in headless Chromium: the view fixture
// steps three scenes at once (3 x 3 spheres, 5 x 5 spheres, and a mass-spring sheet of two
// triangles and five springs, one of which tears at the first step), the page must list
// them, and picking one in its list must bring that simulation's frames: the overlay's
// particle count follows the choice, each way. The sheet is drawn with its four intact
// springs and the one triangle the torn spring leaves supported. Then a second page opens:
// it follows the default until it picks, and a pick in either page moves no other. The
// pages' consoles must stay free of errors.
//
//   node check_view_choice.mjs --fixture DEMLINK_VIEW_FIXTURE --scenes SMALL,LARGE,SHEET [--chromium PATH]
// Prints "N passed, M failed"; exits 1 on any failure.
import path from 'node:path';

import { evaluate } from './devtools_pipe.mjs';
import { args, check, collectPageErrors, deadline, finish, sleep, startBrowser, startFixture } from './check_harness.mjs';

const scenes = args.scenes.split(',');
const kExpected = {
  [path.basename(scenes[0], '.json')]: { particles: 9 },
  [path.basename(scenes[1], '.json')]: { particles: 25 },
  [path.basename(scenes[2], '.json')]: { particles: 0, surfaces: [{ triangles: 1, springs: 4 }] },
};

deadline(150);

async function main() {
  const url = await startFixture(['140', ...scenes]);
  const devtools = startBrowser('demlink-view-choice-');
  const page = await devtools.openPage('about:blank');
  const sessions = new Set([page.sessionId]);
  const errors = collectPageErrors(devtools, sessions);
  await page('Runtime.enable');
  await page('Log.enable');
  await page('Page.navigate', { url });
  const waitIn = async (target, expression, seconds, what) => {
    for (let k = 0; k < seconds * 10; ++k) {
      try { if (await evaluate(target, expression)) return true; } catch { /* the page is still loading */ }
      await sleep(100);
    }
    throw new Error(`timed out waiting for ${what}${errors.length ? '; the page logged: ' + errors.slice(0, 3).join('; ') : ''}`);
  };
  const waitFor = (expression, seconds, what) => waitIn(page, expression, seconds, what);
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
  const overlayParticles = (target = page) => evaluate(target, `Number(document.getElementById('particles').textContent)`);
  const choose = (target, simulation) => evaluate(target, `(() => {
    const select = document.getElementById('simulation');
    select.value = '${simulation.id}';
    select.dispatchEvent(new Event('change'));
  })()`);
  // Each in turn, the one not shown first: the overlay's particle count must follow.
  const firstShown = await overlayParticles();
  const order = [...listed.simulations].sort((a, b) => (a.particles === firstShown) - (b.particles === firstShown));
  for (const simulation of [...order, ...order]) {
    await choose(page, simulation);
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

  // A second page: the default until it picks; a pick in either page moves no other.
  const second = await devtools.openPage('about:blank');
  sessions.add(second.sessionId);
  await second('Runtime.enable');
  await second('Log.enable');
  await second('Page.navigate', { url });
  await waitIn(second, `window.demlinkView && window.demlinkView.status && window.demlinkView.simulations.length === 3`, 60,
    'the second page\'s first frame and list');
  const defaultId = await evaluate(second, `window.demlinkView.followed`);
  const byId = (id) => listed.simulations.find((s) => s.id === id);
  const others = listed.simulations.filter((s) => s.id !== defaultId);
  check(byId(defaultId) !== undefined && others.length === 2, `the second page follows the default (${defaultId})`);
  // The pages' states, read after frames have had time to arrive.
  const shows = async (target, simulation) => {
    await waitIn(target, `Number(document.getElementById('particles').textContent) === ${simulation.particles}`, 20,
      `${simulation.name}'s frames`).catch(() => {});
    await sleep(1500);
    const shown = await overlayParticles(target);
    const followed = await evaluate(target, `window.demlinkView.followed`);
    return { ok: shown === simulation.particles && followed === simulation.id, text: `overlay ${shown} particles, followed ${followed}` };
  };
  const plan = [[page, others[0], second, byId(defaultId)], [second, others[1], page, others[0]]];
  for (const [picking, picked, other, kept] of plan) {
    await choose(picking, picked);
    const mine = await shows(picking, picked);
    check(mine.ok, `${picking === page ? 'first' : 'second'} page chose ${picked.name}: ${mine.text}`);
    const theirs = await shows(other, kept);
    check(theirs.ok, `${other === page ? 'first' : 'second'} page stays on ${kept.name} (${kept.particles} particles, id ${kept.id}): ${theirs.text}`);
  }
  check(errors.length === 0, `no errors in the pages' consoles${errors.length ? ': ' + errors.join('; ') : ''}`);
  await devtools.send('Browser.close').catch(() => {});
}

main().then(finish, (error) => { check(false, error.stack ?? String(error)); finish(); });
