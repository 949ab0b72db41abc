// What every browser check of the view shares: its command line, its tally of checks,
// the children it started (stopped at the end) and its overall deadline.

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
