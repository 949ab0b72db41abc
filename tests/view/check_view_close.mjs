// A page whose simulation closes, in headless Chromium: the view fixture steps two scenes
// at once (3 x 3 spheres until the test ends, and 2 x 2 spheres that close after 20
// simulated seconds, paced at real time). The page picks the brief one and must show its
// frames; once it closes, the page must follow the other (the default): its list holds that
// one alone and selects it, and the overlay's particle count is that one's. The page's
// console must stay free of errors.
//
//   node check_view_close.mjs --fixture DEMLINK_VIEW_FIXTURE --scenes LASTING,BRIEF [--chromium PATH]
// Prints "N passed, M failed"; exits 1 on any failure.
import path from 'node:path';

import { evaluate } from './devtools_pipe.mjs';
import { args, check, collectPageErrors, deadline, finish, sleep, startBrowser, startFixture } from './check_harness.mjs';

const scenes = args.scenes.split(',');
const lasting = { name: path.basename(scenes[0], '.json'), particles: 9 };
const brief = { name: path.basename(scenes[1], '.json'), particles: 4 };

deadline(100);

async function main() {
  const url = await startFixture(['90', ...scenes]);
  const devtools = startBrowser('demlink-view-close-');
  const page = await devtools.openPage('about:blank');
  const errors = collectPageErrors(devtools, new Set([page.sessionId]));
  await page('Runtime.enable');
  await page('Log.enable');
  await page('Page.navigate', { url });
  const waitFor = async (expression, seconds) => {
    for (let k = 0; k < seconds * 10; ++k) {
      try { if (await evaluate(page, expression)) return true; } catch { /* the page is still loading */ }
      await sleep(100);
    }
    return false;
  };
  const listedBoth = await waitFor(`window.demlinkView && window.demlinkView.status && window.demlinkView.simulations.length === 2`, 15);
  check(listedBoth, 'the page lists both simulations before the brief one closes');
  if (!listedBoth) return;
  const simulations = await evaluate(page, `window.demlinkView.simulations`);
  for (const wanted of [lasting, brief]) wanted.id = simulations.find((s) => s.name === wanted.name)?.id;
  // What the page shows: overlay, the simulation it follows, its list and selection.
  const shown = () => evaluate(page, `({
    particles: Number(document.getElementById('particles').textContent),
    followed: window.demlinkView.followed,
    listed: window.demlinkView.simulations.map((s) => s.name).join(),
    selected: document.getElementById('simulation').value,
    choiceShown: getComputedStyle(document.getElementById('simulation-choice')).display !== 'none',
  })`);
  await evaluate(page, `(() => {
    const select = document.getElementById('simulation');
    select.value = '${brief.id}';
    select.dispatchEvent(new Event('change'));
  })()`);
  await waitFor(`Number(document.getElementById('particles').textContent) === ${brief.particles}`, 10);
  const before = await shown();
  check(before.particles === brief.particles && before.followed === brief.id,
    `picked ${brief.name} (id ${brief.id}): overlay ${before.particles} particles (expected ${brief.particles}), followed ${before.followed}`);
  // It closes after 20 simulated seconds; the page must be moved to the lasting one.
  await waitFor(`window.demlinkView.simulations.length === 1 && window.demlinkView.followed === ${lasting.id} && ` +
    `Number(document.getElementById('particles').textContent) === ${lasting.particles}`, 40);
  await sleep(1500);  // later frames must stay the default's
  const after = await shown();
  check(after.listed === lasting.name, `the list holds ${lasting.name} alone once ${brief.name} closed (${after.listed})`);
  check(after.followed === lasting.id && after.selected === String(lasting.id),
    `the page follows and selects the default, ${lasting.name} (id ${lasting.id}): followed ${after.followed}, selected ${after.selected}`);
  check(after.particles === lasting.particles, `the overlay shows the default's ${lasting.particles} particles: ${after.particles}`);
  check(!after.choiceShown, 'with one simulation left the choice is hidden');
  check(errors.length === 0, `no errors in the page's console${errors.length ? ': ' + errors.join('; ') : ''}`);
  await devtools.send('Browser.close').catch(() => {});
}

main().then(finish, (error) => { check(false, error.stack ?? String(error)); finish(); });
