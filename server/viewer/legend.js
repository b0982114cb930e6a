// The viewer's false-colour legend, as HTML: the quantity with its unit and the scale, a bar of the
// ramp (low at the bottom), ticks at scaleTicks' values (the rules of server/legend.h's PNG legend)
// and the scale's ends. Values beyond the ends are drawn in the end colours, and the legend says so.

import { falseColourRamp, scaleTicks, tickLabel, ScaleKind } from "./colour_scale.js";

const kTickSpacingEm = 1.6; // labels at least this many font sizes apart, as server/legend.cpp

// A CSS gradient that is the ramp itself: the ramp is piecewise linear in sRGB bytes between t = k/5,
// and so is a CSS gradient between its stops; 51 stops include all six corners.
function rampGradient() {
  const stops = [];
  for (let i = 0; i <= 50; ++i) {
    const [r, g, b] = falseColourRamp(i / 50);
    stops.push(`rgb(${r}, ${g}, ${b}) ${i * 2}%`);
  }
  return `linear-gradient(to top, ${stops.join(", ")})`;
}

function element(tag, className, text) {
  const e = document.createElement(tag);
  if (className) e.className = className;
  if (text !== undefined) e.textContent = text;
  return e;
}

// Fills `container` with the legend of `scale` for values `range` = {min, max} (the data's own
// extremes). quantity: "Illuminance", unit: "lx".
export function drawLegend(container, scale, range, quantity, unit) {
  container.replaceChildren();
  container.hidden = false;
  container.dataset.quantity = quantity.toLowerCase();
  container.dataset.scale = scale.kind;
  container.dataset.lo = String(scale.lo);
  container.dataset.hi = String(scale.hi);
  container.append(element("div", "legend-title", `${quantity} (${unit})`),
                   element("div", "legend-subtitle", scale.kind === ScaleKind.Log ? "log scale" : "linear scale"));
  const body = element("div", "legend-body");
  const bar = element("div", "legend-bar");
  bar.style.background = rampGradient();
  const ticks = element("div", "legend-ticks");
  body.append(bar, ticks);
  container.append(body);

  const height = bar.getBoundingClientRect().height;
  const fontPx = parseFloat(getComputedStyle(ticks).fontSize);
  const maxTicks = Math.max(2, Math.floor(height / (kTickSpacingEm * fontPx)) + 1);
  for (const tick of scaleTicks(scale, maxTicks)) {
    const label = element("span", "legend-tick", tick.label);
    label.style.bottom = `${scale.position(tick.value) * height}px`;
    ticks.append(label);
  }
  container.append(element("div", "legend-range", `scale ${tickLabel(scale.lo)} to ${tickLabel(scale.hi)} ${unit}`));
  if (range.min < scale.lo) {
    const below = range.min > 0 ? tickLabel(range.min) : "0";
    container.append(element("div", "legend-note",
                             `values down to ${below} ${unit} are below the scale and drawn in its bottom colour`));
  }
}

export function hideLegend(container) {
  container.hidden = true;
  container.replaceChildren();
}
