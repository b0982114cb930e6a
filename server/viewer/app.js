// The page served by `lambert serve` at /: opens a job's result from the service (?job=ID, or the
// job box) or a file dropped on the page (an exported .glb is shown; a scene is sent to the service
// and solved first), and ties the controls to the view (view.js), the legend (legend.js) and the
// probes (probes.js, labels.js). The state is written on <body data-state> (loading, ready, error).

import { ResultView, Quantity } from "./view.js";
import { drawLegend, hideLegend } from "./legend.js";
import { buildProbes } from "./probes.js";
import { LabelLayer } from "./labels.js";
import { tickLabel } from "./colour_scale.js";

const $ = (id) => document.getElementById(id);
const view = new ResultView($("canvas"));
const labels = new LabelLayer($("labels"));
let source = null; // {job} or {file}: what is shown, so that a change of shading can fetch it again

// At least four significant digits, without exponents: "41924", "123.5", "0.01234".
function formatValue(v) {
  if (v === 0 || !Number.isFinite(v)) return String(v);
  const digits = Math.max(0, 3 - Math.floor(Math.log10(Math.abs(v))));
  return v.toFixed(Math.min(digits, 8));
}

function setState(state, message) {
  document.body.dataset.state = state;
  $("status").textContent = message;
  $("status").className = state === "error" ? "error" : "";
}

// ---- drawing --------------------------------------------------------------------------------------

function redraw() {
  if (!view.root) return;
  const quantity = Quantity[$("quantity").value] ?? null;
  if (quantity) {
    const { scale, range } = view.scaleOf(quantity, $("scale").value);
    view.colour(quantity, scale);
    drawLegend($("legend"), scale, range, quantity.title, quantity.unit);
  } else {
    view.colour(null);
    hideLegend($("legend"));
  }
  const probes = buildProbes(view.probes, $("scale").value);
  view.setProbeOverlay($("show-probes").checked ? probes.group : null);
  labels.set(probes.labels);
  listProbes(probes.grids);
  view.render();
}

function updateLabels() {
  const rect = $("canvas").getBoundingClientRect();
  labels.update(view.camera, rect.width, rect.height, $("show-probes").checked);
}
view.onRender = updateLabels;

function textElement(tag, className, text) {
  const e = document.createElement(tag);
  e.className = className;
  e.textContent = text;
  return e;
}

function listProbes(grids) {
  const list = $("probe-list");
  list.replaceChildren();
  if (grids.length === 0) list.textContent = "none in this result";
  for (const g of grids) {
    const item = textElement("div", "probe", "");
    Object.assign(item.dataset, { probe: g.name, min: String(g.min), max: String(g.max),
                                  levels: JSON.stringify(g.levels), segments: String(g.segments) });
    item.append(textElement("div", "probe-name", `${g.name} (${g.isGrid ? `${g.nu} × ${g.nv} grid` : "point"})`),
                textElement("div", "probe-values", `min ${tickLabel(g.min)} · mean ${tickLabel(g.mean)} · ` +
                                                   `max ${tickLabel(g.max)} lx · U0 = min/mean ${g.uniformity.toFixed(2)}`));
    if (g.isGrid) {
      const levels = g.levels.length > 0 ? `${g.levels.map(tickLabel).join(", ")} lx` : "none (no round value inside its range)";
      item.append(textElement("div", "probe-levels", `isolux lines: ${levels}`));
    }
    list.append(item);
  }
}

function showPick(event) {
  const picked = view.pick(event.clientX, event.clientY);
  const list = $("pick-values");
  list.replaceChildren();
  if (!picked) {
    list.textContent = "no surface there";
    return;
  }
  const smooth = view.extras?.shading === "smooth";
  const rows = [
    ["surface", picked.surface, picked.surface],
    [smooth ? "illuminance (interpolated)" : "illuminance", `${formatValue(picked.illuminance)} lx`, picked.illuminance, "illuminance_lx"],
    [smooth ? "luminance (interpolated)" : "luminance", `${formatValue(picked.luminance)} cd/m²`, picked.luminance, "luminance_cd_m2"],
    ["colour (sRGB)", picked.colour, picked.colour, "colour"],
    ["point (m)", picked.point.toArray().map((x) => x.toFixed(4)).join(", "), picked.point.toArray().join(","), "point_m"],
    ["patch area", `${formatValue(picked.area)} m²`, picked.area, "area_m2"],
  ];
  for (const [title, text, value, field] of rows) {
    const dt = textElement("dt", "", title);
    const dd = textElement("dd", "", text);
    dd.dataset.field = field ?? title;
    dd.dataset.value = String(value);
    list.append(dt, dd);
  }
}

// ---- loading --------------------------------------------------------------------------------------

async function show(bytes, description) {
  await view.load(bytes);
  const shading = view.extras?.shading;
  if (shading) $("shading").value = shading;
  $("shading").disabled = !source?.job;
  redraw();
  view.setView("front");
  setState("ready", description);
}

async function fetchJson(url, init) {
  const response = await fetch(url, init);
  const body = await response.json().catch(() => ({}));
  if (!response.ok) throw new Error(body.error?.message ?? `${url}: HTTP ${response.status}`);
  return body;
}

async function openJob(id) {
  source = { job: id };
  history.replaceState(null, "", `?job=${encodeURIComponent(id)}`);
  const url = `/v1/jobs/${encodeURIComponent(id)}`;
  for (;;) {
    const status = await fetchJson(url);
    if (status.state === "done") break;
    if (status.state === "failed" || status.state === "cancelled")
      throw new Error(`job ${id} ${status.state}${status.error ? `: ${status.error}` : ""}`);
    setState("loading", `job ${id}: ${status.state}, ${Math.round(100 * status.progress)} %`);
    await new Promise((resolve) => setTimeout(resolve, 500));
  }
  const response = await fetch(`${url}/result.glb?shading=${$("shading").value}`);
  if (!response.ok) throw new Error((await response.json().catch(() => ({}))).error?.message ?? `HTTP ${response.status}`);
  await show(await response.arrayBuffer(), `job ${id}`);
}

// A dropped or chosen file: an exported result (.glb) is shown; a scene (JSON with surfaces) is
// sent to the service as a job and opened when solved; a result JSON is explained.
async function openFile(file) {
  const bytes = await file.arrayBuffer();
  const head = new Uint8Array(bytes, 0, Math.min(4, bytes.byteLength));
  if (String.fromCharCode(...head) === "glTF") {
    source = { file: file.name };
    history.replaceState(null, "", location.pathname);
    return show(bytes, file.name);
  }
  let document_;
  try {
    document_ = JSON.parse(new TextDecoder().decode(bytes));
  } catch {
    throw new Error(`${file.name} is neither a .glb nor JSON`);
  }
  if (document_?.patches)
    throw new Error(`${file.name} is a result (JSON): export it with "lambert export ${file.name} -o result.glb" and drop the .glb`);
  if (!document_?.surfaces) throw new Error(`${file.name} is neither a scene nor an exported result`);
  setState("loading", `sending ${file.name} to the service`);
  const job = await fetchJson("/v1/jobs", { method: "POST", headers: { "Content-Type": "application/json" }, body: bytes });
  $("job-id").value = job.id;
  return openJob(job.id);
}

function run(task) {
  setState("loading", "loading…");
  task().catch((error) => setState("error", error.message));
}

// ---- controls -------------------------------------------------------------------------------------

$("open-job").addEventListener("submit", (event) => {
  event.preventDefault();
  const id = $("job-id").value.trim();
  if (id) run(() => openJob(id));
});
$("file").addEventListener("change", () => {
  if ($("file").files.length > 0) run(() => openFile($("file").files[0]));
});
for (const id of ["quantity", "scale", "show-probes"]) $(id).addEventListener("change", redraw);
$("shading").addEventListener("change", () => {
  if (source?.job) run(() => openJob(source.job));
});
$("view-front").addEventListener("click", () => view.setView("front"));
$("view-top").addEventListener("click", () => view.setView("top"));
$("save").addEventListener("click", () => {
  const link = document.createElement("a");
  link.download = "lambert-view.png";
  link.href = $("canvas").toDataURL("image/png");
  link.click();
});

window.addEventListener("dragover", (event) => event.preventDefault());
window.addEventListener("drop", (event) => {
  event.preventDefault();
  const file = event.dataTransfer?.files?.[0];
  if (file) run(() => openFile(file));
});

// A click (not the end of a drag that orbits) picks the patch under the pointer.
let down = null;
$("canvas").addEventListener("pointerdown", (event) => (down = { x: event.clientX, y: event.clientY }));
$("canvas").addEventListener("pointerup", (event) => {
  if (down && Math.hypot(event.clientX - down.x, event.clientY - down.y) < 4 && view.root) showPick(event);
  down = null;
});

const resize = () => {
  const rect = $("view").getBoundingClientRect();
  view.resize(rect.width, rect.height);
};
new ResizeObserver(resize).observe($("view"));
resize();

// For scripts and the browser test: client coordinates of a point in metres.
window.lambertViewer = { project: (point) => view.project(point) };

const job = new URLSearchParams(location.search).get("job");
if (job) {
  $("job-id").value = job;
  run(() => openJob(job));
} else {
  setState("empty", "open a job, or drop a scene or an exported .glb on the page");
}
