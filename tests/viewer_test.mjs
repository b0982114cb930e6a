// The browser viewer in a real headless Chromium (Debian's /usr/bin/chromium, driven by npm
// playwright-core; no browser is downloaded). Starts `lambert serve`, solves the bundled Cornell box
// through the service, opens the page on the job and checks it against the job's result JSON:
//   - the canvas is not blank (most pixels differ from the background, in many colours);
//   - the legend's range is the result's: log scale from max(E_max / 1000, E_min) to E_max over the
//     patches, and linear from 0 to L_max for luminance;
//   - a click on the floor's centre (seen from above) shows the illuminance of the floor patch that
//     contains the centre, and in "colour" mode the pixel there is that patch's srgb_encoded (the
//     colour the exported .glb carries);
//   - the probe grid's 81 numbers are the result's, and it has isolux lines inside its range;
//   - the same .glb dropped on the page (the file input) shows the same legend;
//   - no console error, page error or failed request.
// Usage: node tests/viewer_test.mjs REPO_ROOT LAMBERT_BINARY
import { spawn } from "node:child_process";
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, resolve } from "node:path";
import { pathToFileURL } from "node:url";

const [root, lambert] = process.argv.slice(2).map((p) => resolve(p));
const kChromium = "/usr/bin/chromium";
const kFlags = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
                "--disable-component-update", "--disable-sync"];
const kBackground = [0x20, 0x20, 0x20]; // view.js's clear colour

let failures = 0;
function check(ok, what) {
  console.log(`${ok ? "ok  " : "FAIL"} ${what}`);
  if (!ok) failures++;
}
const near = (a, b, rel) => Math.abs(a - b) <= rel * Math.max(Math.abs(a), Math.abs(b));

if (!existsSync(kChromium)) {
  console.error(`viewer_test: ${kChromium} is missing; run tools/install-deps.sh`);
  process.exit(1);
}
const { chromium } = await import(pathToFileURL(join(root, "tools/node_modules/playwright-core/index.mjs")).href);

// ---- the service, and the Cornell box solved through it ------------------------------------------

const work = mkdtempSync(join(tmpdir(), "lambert-viewer-test-"));
const server = spawn(lambert, ["serve", "--port", "0", "--threads", "1"], { stdio: ["ignore", "pipe", "inherit"] });
const url = await new Promise((resolveUrl, reject) => {
  let out = "";
  server.stdout.on("data", (d) => {
    out += d;
    const m = out.match(/http:\/\/[^\s]+/);
    if (m) resolveUrl(m[0]);
  });
  server.on("exit", (code) => reject(new Error(`lambert serve exited (${code})`)));
});
let browser = null;
try {
  const sceneText = readFileSync(join(root, "scenes/cornell-box.json"));
  const scene = JSON.parse(sceneText);
  const posted = await (await fetch(`${url}/v1/jobs`, { method: "POST", body: sceneText,
                                                      headers: { "Content-Type": "application/json" } })).json();
  const id = posted.id;
  check(typeof id === "string", `the service took the Cornell box as job ${id}`);

  browser = await chromium.launchPersistentContext(join(work, "profile"), {
    executablePath: kChromium, headless: true, args: kFlags, viewport: { width: 1280, height: 800 } });
  const page = browser.pages()[0] ?? await browser.newPage();
  const problems = [];
  page.on("console", (m) => m.type() === "error" && problems.push(`console: ${m.text()}`));
  page.on("pageerror", (e) => problems.push(`page error: ${e.message}`));
  page.on("requestfailed", (r) => problems.push(`request failed: ${r.url()} ${r.failure()?.errorText}`));
  page.on("response", (r) => r.status() >= 400 && problems.push(`HTTP ${r.status()}: ${r.url()}`));

  await page.goto(`${url}/?job=${id}`);
  await page.waitForSelector("body[data-state=ready], body[data-state=error]", { timeout: 60000 });
  check(await page.getAttribute("body", "data-state") === "ready", `the page opened the job: ${await page.textContent("#status")}`);

  const result = await (await fetch(`${url}/v1/jobs/${id}/result`)).json();
  await screenshot(page, "illuminance");
  await checkCanvas(page);
  await checkLegend(page, result);
  await checkPick(page, result, scene);
  await checkProbes(page, result);
  await checkDroppedFile(page, url, id);
  check(problems.length === 0, `no console error, page error or failed request${problems.length ? ":\n  " + problems.join("\n  ") : ""}`);
} catch (error) {
  check(false, `the test ran to its end: ${error.stack}`);
} finally {
  if (browser) await browser.close();
  server.kill("SIGTERM");
  rmSync(work, { recursive: true, force: true });
}
console.log(`${failures === 0 ? "viewer_test passed" : `viewer_test: ${failures} checks failed`}`);
process.exit(failures === 0 ? 0 : 1);

// ---- the checks -------------------------------------------------------------------------------------

// With LAMBERT_VIEWER_SCREENSHOTS=DIR, the page as the checks see it (for looking at, not checked).
async function screenshot(page, name) {
  const dir = process.env.LAMBERT_VIEWER_SCREENSHOTS;
  if (dir) await page.screenshot({ path: join(dir, `viewer-${name}.png`) });
}

// The canvas's pixels, read in the page (the WebGL canvas keeps its drawing buffer): the share of
// pixels that differ from the background and the number of distinct colours (5 bits a channel), or
// the pixel under the client point (x, y).
function canvasPixels(page, point = null) {
  return page.evaluate(([background, point]) => {
    const canvas = document.getElementById("canvas");
    const copy = document.createElement("canvas");
    copy.width = canvas.width;
    copy.height = canvas.height;
    const ctx = copy.getContext("2d");
    ctx.drawImage(canvas, 0, 0);
    if (point) {
      const rect = canvas.getBoundingClientRect(), scale = canvas.width / rect.width;
      const x = Math.round((point.x - rect.left) * scale), y = Math.round((point.y - rect.top) * scale);
      return Array.from(ctx.getImageData(x, y, 1, 1).data.slice(0, 3));
    }
    const data = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
    let drawn = 0;
    const colours = new Set();
    for (let i = 0; i < data.length; i += 4) {
      if (data[i] !== background[0] || data[i + 1] !== background[1] || data[i + 2] !== background[2]) drawn++;
      colours.add((data[i] >> 3) * 1024 + (data[i + 1] >> 3) * 32 + (data[i + 2] >> 3));
    }
    return { share: drawn / (data.length / 4), colours: colours.size };
  }, [kBackground, point]);
}

async function checkCanvas(page) {
  const { share, colours } = await canvasPixels(page);
  check(share > 0.2 && colours > 30, `the canvas is not blank: ${(100 * share).toFixed(1)} % of the pixels drawn, ${colours} colours`);
}

async function legendState(page) {
  return page.evaluate(() => {
    const legend = document.getElementById("legend");
    return { hidden: legend.hidden, ...legend.dataset, range: legend.querySelector(".legend-range")?.textContent,
             title: legend.querySelector(".legend-title")?.textContent,
             ticks: Array.from(legend.querySelectorAll(".legend-tick"), (t) => t.textContent) };
  });
}

async function checkLegend(page, result) {
  const E = result.patches.map((p) => p.illuminance_lx);
  const hi = Math.max(...E), lo = Math.max(hi / 1000, Math.min(...E.filter((v) => v > 0)));
  let legend = await legendState(page);
  check(!legend.hidden && legend.title === "Illuminance (lx)" && legend.scale === "log",
        `the legend shows illuminance on a log scale: "${legend.title}", ${legend.scale}`);
  check(near(Number(legend.hi), hi, 1e-6) && near(Number(legend.lo), lo, 1e-6),
        `the legend's range is the result's: ${legend.lo} to ${legend.hi} lx against ${lo} to ${hi} (float32)`);
  const shown = (legend.range ?? "").match(/scale (\S+) to (\S+) lx/);
  check(shown && near(Number(shown[1]), lo, 5e-3) && near(Number(shown[2]), hi, 5e-3),
        `the legend writes its ends to three digits: "${legend.range}"`);
  const ticks = legend.ticks.map(Number);
  check(ticks.length >= 2 && ticks.every((t) => t >= lo * (1 - 1e-9) && t <= hi * (1 + 1e-9)),
        `its ticks lie inside the range: ${legend.ticks.join(", ")}`);

  await page.selectOption("#quantity", "luminance");
  await page.selectOption("#scale", "linear");
  legend = await legendState(page);
  const Lmax = Math.max(...result.patches.map((p) => p.luminance_cd_m2));
  check(legend.title === "Luminance (cd/m²)" && legend.scale === "linear" && Number(legend.lo) === 0 && near(Number(legend.hi), Lmax, 1e-6),
        `luminance on a linear scale: ${legend.lo} to ${legend.hi} cd/m² against 0 to ${Lmax}`);
  await page.selectOption("#quantity", "illuminance");
  await page.selectOption("#scale", "log");
}

// The floor patches that contain the point (x, z) of the floor's plane (y = 0), scene units.
function floorPatchesAt(result, x, z) {
  const side = (a, b, px, pz) => (b[0] - a[0]) * (pz - a[2]) - (b[2] - a[2]) * (px - a[0]);
  return result.patches.filter((p) => {
    if (p.surface !== "floor") return false;
    const [a, b, c] = p.vertices;
    const s = [side(a, b, x, z), side(b, c, x, z), side(c, a, x, z)];
    return s.every((v) => v >= -1e-9) || s.every((v) => v <= 1e-9);
  });
}

async function checkPick(page, result, scene) {
  const unit = { m: 1, cm: 0.01, mm: 0.001 }[scene.units ?? "m"];
  const floor = result.patches.filter((p) => p.surface === "floor").flatMap((p) => p.vertices);
  const centre = [0, 2].map((c) => (Math.min(...floor.map((v) => v[c])) + Math.max(...floor.map((v) => v[c]))) / 2);
  const patches = floorPatchesAt(result, centre[0], centre[1]);
  check(patches.length >= 1, `the floor's centre (${centre.join(", ")} ${scene.units}) lies on ${patches.map((p) => `patch ${p.id}`).join(", ")}`);

  await page.click("#view-top");
  await page.uncheck("#show-probes"); // the grid's numbers lie over the floor
  const at = await page.evaluate((p) => window.lambertViewer.project(p), [centre[0] * unit, 0, centre[1] * unit]);
  await page.mouse.click(at.x, at.y);
  const field = (name) => page.evaluate((n) => {
    const dd = document.querySelector(`#pick-values dd[data-field="${n}"]`);
    return dd ? { text: dd.textContent, value: dd.dataset.value } : null;
  }, name);
  const surface = await field("surface"), E = await field("illuminance_lx");
  const match = patches.find((p) => E && near(Number(E.value), p.illuminance_lx, 1e-6));
  check(surface?.text === "floor" && match !== undefined,
        `picking the floor's centre shows ${E?.text} on ${surface?.text} (data ${E?.value}); the result's patch: ` +
        `${patches.map((p) => p.illuminance_lx).join(" or ")} lx`);
  check(E && match && near(parseFloat(E.text), match.illuminance_lx, 1e-4), `the panel writes it to four digits: "${E?.text}"`);

  // The colour the exported .glb carries (COLOR_0, shown unlit) is the result's srgb_encoded: read
  // at the patch's centroid, away from the highlight on its edges.
  await page.selectOption("#quantity", "colour");
  const patch = match ?? patches[0];
  const centroid = [0, 1, 2].map((c) => patch.vertices.reduce((sum, v) => sum + v[c] * unit / 3, 0));
  const inside = await page.evaluate((p) => window.lambertViewer.project(p), centroid);
  const rgb = await canvasPixels(page, inside);
  const expected = patch.srgb_encoded.map((c) => Math.round(255 * Math.min(1, c)));
  check(rgb.every((c, k) => Math.abs(c - expected[k]) <= 2),
        `in colour mode the patch is drawn ${rgb.join(",")}, its srgb_encoded ${expected.join(",")} (±2)`);
  await screenshot(page, "colour-top");
  await page.selectOption("#quantity", "illuminance");
  await page.check("#show-probes");
}

async function checkProbes(page, result) {
  const grid = result.probes.find((p) => p.nu > 1 && p.nv > 1);
  const labels = await page.$$eval(`.label-value`, (els) =>
    els.map((e) => ({ probe: e.dataset.probe, value: Number(e.dataset.value), text: e.textContent, shown: !e.hidden })));
  const mine = labels.filter((l) => l.probe === grid.name);
  check(mine.length === grid.nu * grid.nv && mine.every((l, q) => near(l.value, grid.illuminance_lx[q], 1e-6) &&
                                                          near(parseFloat(l.text), grid.illuminance_lx[q], 5e-3) ||
                                                          (grid.illuminance_lx[q] < 0.5 && parseFloat(l.text) === 0)),
        `the ${grid.name} grid's ${mine.length} numbers are the result's (three digits)`);
  const shown = mine.filter((l) => l.shown).length;
  check(shown >= grid.nu * grid.nv / 4, `${shown} of them are readable from above without overlapping`);
  await screenshot(page, "probes-top");
  await page.click("#view-front");
  await screenshot(page, "front"); // docs/viewer.png
  const info = await page.$eval(`.probe[data-probe="${grid.name}"]`, (e) => ({ ...e.dataset }));
  const levels = JSON.parse(info.levels);
  const min = Math.min(...grid.illuminance_lx), max = Math.max(...grid.illuminance_lx);
  check(levels.length > 0 && levels.every((v) => v > min && v < max) && Number(info.segments) > 0,
        `isolux lines at ${levels.join(", ")} lx (inside ${min.toFixed(0)} to ${max.toFixed(0)}): ${info.segments} segments`);
  const isolux = await page.$$eval(".label-isolux", (els) => els.map((e) => ({ text: e.textContent, shown: !e.hidden })));
  check(isolux.length === levels.length && isolux.filter((l) => l.shown).length >= levels.length / 2,
        `their values are written on them: ${isolux.filter((l) => l.shown).map((l) => l.text).join(", ")} shown`);
}

async function checkDroppedFile(page, url, id) {
  const file = join(work, "cornell-box.glb");
  writeFileSync(file, Buffer.from(await (await fetch(`${url}/v1/jobs/${id}/result.glb?shading=flat`)).arrayBuffer()));
  const before = await legendState(page);
  await page.evaluate(() => (document.body.dataset.state = "waiting"));
  await page.setInputFiles("#file", file);
  await page.waitForSelector("body[data-state=ready], body[data-state=error]", { timeout: 30000 });
  const status = await page.textContent("#status");
  const after = await legendState(page);
  check(status === "cornell-box.glb" && after.lo === before.lo && after.hi === before.hi,
        `the .glb chosen as a file shows the same legend (${after.lo} to ${after.hi}): "${status}"`);
}
