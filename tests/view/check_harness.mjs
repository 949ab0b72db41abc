// What every browser check of the view shares: its command line, its tally of checks,
// the children it started (stopped at the end), its overall deadline, and starting the
// view fixture and a headless Chromium on a fresh profile.
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

import { DevTools, chromiumArguments } from './devtools_pipe.mjs';


/// `--name value` pairs of the command line.
export const args = Object.fromEntries(process.argv.slice(2).reduce((pairs, arg, i, all) => {
  if (arg.startsWith('--')) pairs.push([arg.slice(2), all[i + 1]]);
  return pairs;
}, []));

let passed = 0, failed = 0;
export function check(ok, what) {
  if (ok) { passed += 1; console.log(`ok: ${what}`); } else { failed += 1; console.log(`FAILED: ${what}`); }
}
export const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
/// Processes to stop when the check ends.
export const children = [];
/// Stops the children, prints "N passed, M failed" and exits 1 on any failure (or none passed).
export function finish() {
  for (const child of children) if (child.exitCode === null) child.kill('SIGTERM');
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed === 0 && passed > 0 ? 0 : 1);
}
/// Fails and finishes the check if it has not finished within `seconds`.
export function deadline(seconds) {
  setTimeout(() => { check(false, `finished within ${seconds} s`); finish(); }, seconds * 1000).unref();
}
/// Starts the view fixture with `fixtureArguments`; resolves to the view's URL once the
/// fixture prints it (at most 60 s), and throws with its output if it exits first.
export async function startFixture(fixtureArguments) {
  let log = '';
  const fixture = spawn(args.fixture, fixtureArguments, { stdio: ['ignore', 'pipe', 'pipe'] });
  children.push(fixture);
  fixture.stdout.on('data', (d) => { log += d; });
  fixture.stderr.on('data', (d) => { log += d; });
  for (let k = 0; k < 600 && !/view: (\S+)/.test(log); ++k) {
    if (fixture.exitCode !== null) throw new Error(`the fixture exited (${fixture.exitCode}): ${log}`);
    await sleep(100);
  }
  return log.match(/view: (\S+)/)[1];
}
/// The errors of the pages whose DevTools session ids are in `sessions` (a Set; more may be
/// added): exceptions, console.error calls and error log entries, collected as they come
/// (the pages need Runtime.enable and Log.enable).
export function collectPageErrors(devtools, sessions) {
  const errors = [];
  devtools.listeners.push((message) => {
    if (!sessions.has(message.sessionId)) return;
    if (message.method === 'Runtime.exceptionThrown') errors.push(`${message.params.exceptionDetails.text} ${message.params.exceptionDetails.exception?.description ?? ''}`);
    if (message.method === 'Runtime.consoleAPICalled' && message.params.type === 'error') errors.push(JSON.stringify(message.params.args));
    if (message.method === 'Log.entryAdded' && message.params.entry.level === 'error') errors.push(message.params.entry.text);
  });
  return errors;
}
/// Starts headless Chromium (--chromium, else /usr/bin/chromium) on a fresh profile named
/// after `profilePrefix`; returns its DevTools connection.
export function startBrowser(profilePrefix) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), profilePrefix));
  const browser = spawn(args.chromium ?? '/usr/bin/chromium', chromiumArguments(profile),
    { stdio: ['ignore', 'ignore', 'ignore', 'pipe', 'pipe'] });
  children.push(browser);
  return new DevTools(browser);
}
