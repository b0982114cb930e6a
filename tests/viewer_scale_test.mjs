// The browser viewer's colour scale, ramp, tick labels and isolux lines (server/viewer/
// colour_scale.js, isolines.js) against the C++ that draws Lambert's PNG legends and grid maps
// (server/colour_scale.h, server/isolines.h, answered by tests/viewer_scale_reference.cpp) on the
// same inputs: random values over eighteen decades, exact decades, the ramp's corners and random
// grids. A legend in the browser must show the same range, ticks and labels as `lambert render`.
// Ranges, ticks, labels, colours and segments must agree exactly; positions (a quotient of two
// logarithms) to 1e-12.
// Usage: node tests/viewer_scale_test.mjs REPO_ROOT viewer_scale_reference
import { spawnSync } from "node:child_process";
import { join, resolve } from "node:path";
import { pathToFileURL } from "node:url";

const [root, reference] = process.argv.slice(2).map((p) => resolve(p));
const load = (file) => import(pathToFileURL(join(root, "server/viewer", file)).href);
const { colourScale, scaleTicks, tickLabel, falseColourRamp } = await load("colour_scale.js");
const { isolines } = await load("isolines.js");

// A fixed pseudo-random sequence (mulberry32), so that a failure can be replayed.
let seed = 38;
function random() {
  seed = (seed + 0x6d2b79f5) | 0;
  let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
  t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
  return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
}
const logUniform = (from, to) => 10 ** (from + (to - from) * random());

// ---- the cases ---------------------------------------------------------------------------------------

const kMaxTicks = [2, 3, 5, 8, 12, 20];
const scales = [];
for (let k = 0; k < 200; ++k) {
  const top = -6 + 15 * random(), span = 6 * random();
  const values = Array.from({ length: 1 + Math.floor(20 * random()) }, () => logUniform(top - span, top));
  if (k % 5 === 0) values.push(0);
  if (k % 7 === 0) values.push(-values[0]);
  for (const kind of ["log", "linear"]) scales.push({ values, kind, max_ticks: kMaxTicks });
}
for (let e = -7; e <= 9; ++e) { // exact decades and their neighbours at both ends of a scale
  for (const kind of ["log", "linear"]) {
    scales.push({ values: [10 ** e], kind, max_ticks: kMaxTicks });
    scales.push({ values: [10 ** e, 10 ** (e + 3)], kind, max_ticks: kMaxTicks });
    scales.push({ values: [2.5 * 10 ** e, 7 * 10 ** (e + 1)], kind, max_ticks: kMaxTicks });
  }
}
scales.push({ values: [], kind: "log", max_ticks: kMaxTicks }, { values: [0, -1], kind: "linear", max_ticks: kMaxTicks });

const labels = [0, 1, 0.001, 999999, 1e6, 0.25, 12000, 2.5e-7, 1.5e-4, -3.75, 123456.7];
for (let k = 0; k < 1000; ++k) labels.push((random() < 0.2 ? -1 : 1) * logUniform(-9, 12));
for (let e = -9; e <= 12; ++e) labels.push(10 ** e, 2 * 10 ** e, 5 * 10 ** e);

const ramp = [-1, 0, 0.2, 0.4, 0.6, 0.8, 1, 2, NaN];
for (let k = 0; k <= 1000; ++k) ramp.push(k / 1000);

const grids = [];
for (let k = 0; k < 60; ++k) {
  const nu = 1 + Math.floor(12 * random()), nv = 1 + Math.floor(12 * random());
  const values = Array.from({ length: nu * nv }, () => Math.round(1000 * random()) / 10);
  grids.push({ values, nu, nv, level: values[Math.floor(random() * values.length)] }); // lands on samples too
  grids.push({ values, nu, nv, level: 100 * random() });
}

// ---- the reference answers, and the comparison -------------------------------------------------------

// JSON has no NaN: the C++ is asked for 0 where the JavaScript gets NaN (both take a NaN as 0).
const input = JSON.stringify({ scales, labels, ramp: ramp.map((t) => (Number.isNaN(t) ? 0 : t)), isolines: grids });
const run = spawnSync(reference, { input, maxBuffer: 1 << 28 });
if (run.status !== 0) {
  console.error(`viewer_scale_test: ${reference} failed: ${run.stderr}`);
  process.exit(1);
}
const expected = JSON.parse(run.stdout);

let checks = 0, failures = 0;
function check(ok, what) {
  checks++;
  if (!ok && ++failures <= 20) console.log(`FAIL ${what}`);
}
const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);

scales.forEach((s, k) => {
  const scale = colourScale(s.values, s.kind);
  const want = expected.scales[k];
  check(scale.lo === want.lo && scale.hi === want.hi, `scale ${k} (${s.kind} of ${s.values}): ${scale.lo}..${scale.hi}, C++ ${want.lo}..${want.hi}`);
  s.values.forEach((v, q) => check(Math.abs(scale.position(v) - want.positions[q]) <= 1e-12,
                                   `position of ${v} on scale ${k}: ${scale.position(v)}, C++ ${want.positions[q]}`));
  s.max_ticks.forEach((n, q) => {
    const ticks = scaleTicks(scale, n).map((t) => [t.value, t.label]);
    check(same(ticks, want.ticks[q].map((t) => [t.value, t.label])), `ticks of scale ${k} (${scale.lo}..${scale.hi}, ${s.kind}) at most ${n}: ` +
                                      `${JSON.stringify(ticks)}, C++ ${JSON.stringify(want.ticks[q])}`);
  });
});
labels.forEach((v, k) => check(tickLabel(v) === expected.labels[k], `label of ${v}: "${tickLabel(v)}", C++ "${expected.labels[k]}"`));
ramp.forEach((t, k) => check(same(falseColourRamp(t), expected.ramp[k]), `ramp at ${t}: ${falseColourRamp(t)}, C++ ${expected.ramp[k]}`));
let segments = 0;
grids.forEach((g, k) => {
  const mine = isolines(g.values, g.nu, g.nv, g.level).map(([a, b]) => [...a, ...b]);
  segments += mine.length;
  check(same(mine, expected.isolines[k]), `isolines of grid ${k} (${g.nu} × ${g.nv}) at ${g.level}: ` +
                                          `${mine.length} segments, C++ ${expected.isolines[k].length}`);
});
check(segments > 500, `the grids cross their levels (${segments} segments)`);
console.log(`${checks - failures} passed, ${failures} failed`);
process.exit(failures === 0 ? 0 : 1);
