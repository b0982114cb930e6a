// The false-colour scale of Lambert's pictures, for the browser: the same rules as
// server/colour_scale.h (which draws the PNG legends), so that the viewer's legend shows the same
// range and ticks as `lambert render`. tests/viewer_scale_test.mjs checks this file against the C++
// on the same values.

export const ScaleKind = Object.freeze({ Linear: "linear", Log: "log" });

// The log scale spans three decades at most below the largest value.
export const kLogScaleDecades = 3;

// 10^k for an integer k, correctly rounded (as C's pow(10.0, k) on glibc): powers up to 10^22 are
// exact doubles, and one division of two exact numbers rounds once.
export function pow10(k) {
  return k >= 0 ? 10 ** k : 1 / 10 ** -k;
}

export class ColourScale {
  constructor(kind, lo, hi) {
    this.kind = kind;
    this.lo = lo; // log: 0 < lo ≤ hi; linear: lo = 0 ≤ hi
    this.hi = hi;
  }

  // Where v sits on the scale, in [0, 1] (clamped): log(v/lo)/log(hi/lo), or v/hi. Values ≤ 0 on a
  // log scale sit at 0.
  position(v) {
    const clamp = (t) => Math.min(1, Math.max(0, t));
    if (!(this.hi > 0) || !Number.isFinite(v)) return 0;
    if (this.kind === ScaleKind.Linear) return clamp(v / this.hi);
    if (!(v > 0)) return 0;
    return this.hi > this.lo ? clamp(Math.log(v / this.lo) / Math.log(this.hi / this.lo)) : 1;
  }
}

// The log scale runs from the largest value down to the smallest positive one or to a thousandth of
// the largest, whichever is higher; the linear scale from 0 to the largest value. {kind, 0, 0} when
// no value is positive. `values` is any iterable of numbers (a Float32Array too).
export function colourScale(values, kind) {
  let hi = 0;
  let loPositive = Infinity;
  for (const v of values) {
    if (v > 0 && Number.isFinite(v)) {
      hi = Math.max(hi, v);
      loPositive = Math.min(loPositive, v);
    }
  }
  if (!(hi > 0)) return new ColourScale(kind, 0, 0);
  if (kind === ScaleKind.Linear) return new ColourScale(kind, 0, hi);
  return new ColourScale(kind, Math.max(hi * pow10(-kLogScaleDecades), loPositive), hi);
}

// The colour at position t in [0, 1] as sRGB bytes: dark blue through blue, cyan, green and yellow
// to red.
const kRampStops = [[0, 0, 64], [0, 0, 255], [0, 255, 255], [0, 255, 0], [255, 255, 0], [255, 0, 0]];
export function falseColourRamp(t) {
  const s = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0)) * 5;
  const k = Math.min(4, Math.floor(s));
  const f = s - k;
  // C's lround: halves away from zero (the values are never negative).
  return [0, 1, 2].map((c) => Math.floor(kRampStops[k][c] + f * (kRampStops[k + 1][c] - kRampStops[k][c]) + 0.5));
}

// A bound taken as inside the scale up to rounding of the tick values themselves.
function inside(v, s) {
  const slack = 1e-9 * s.hi;
  return v >= s.lo - slack && v <= s.hi + slack;
}

function logTicks(s, maxTicks) {
  const first = Math.floor(Math.log10(s.lo));
  const last = Math.ceil(Math.log10(s.hi));
  for (const mantissas of [[1, 2, 5], [1]]) {
    for (let every = 1; every <= 8; every *= 2) {
      const ticks = [];
      for (let k = first; k <= last; ++k) {
        if (((k % every) + every) % every !== 0) continue;
        for (const m of mantissas) {
          const v = m * pow10(k);
          if (inside(v, s)) ticks.push({ value: v, label: tickLabel(v) });
        }
      }
      if (ticks.length <= maxTicks || (mantissas.length === 1 && every === 8)) return ticks;
      if (mantissas.length > 1) break; // thin the mantissas before the decades
    }
  }
  return [];
}

function linearTicks(s, maxTicks) {
  const raw = s.hi / Math.max(1, maxTicks - 1);
  const decade = pow10(Math.floor(Math.log10(raw)));
  let step = 10 * decade;
  for (const m of [1, 2, 2.5, 5]) {
    if (m * decade >= raw * (1 - 1e-12)) {
      step = m * decade;
      break;
    }
  }
  const ticks = [];
  for (let k = 0; k * step <= s.hi * (1 + 1e-9); ++k) ticks.push({ value: k * step, label: tickLabel(k * step) });
  return ticks;
}

// Ticks inside [lo, hi], at most about `maxTicks`: on a log scale 1, 2 and 5 × 10^k (or only the
// decades, or every other decade); on a linear scale multiples of the first of 1, 2, 2.5 or 5 × 10^k
// that keeps them within `maxTicks`. A scale with fewer than two such values gets its ends instead.
export function scaleTicks(s, maxTicks) {
  if (!(s.hi > 0)) return [{ value: 0, label: "0" }];
  let ticks = s.kind === ScaleKind.Log ? logTicks(s, maxTicks) : linearTicks(s, maxTicks);
  if (ticks.length < 2) ticks = [{ value: s.lo, label: tickLabel(s.lo) }, { value: s.hi, label: tickLabel(s.hi) }];
  return ticks;
}

function dropTrailingZeros(digits) {
  if (!digits.includes(".")) return digits;
  return digits.replace(/0+$/, "").replace(/\.$/, "");
}

// A value's label: at most three significant digits, plain decimals from 0.001 to 10^6 ("0.25",
// "20", "12000"), else "1.5e-4", "2e6"; 0 is "0". (A value exactly halfway between two labels in
// binary rounds up here and to even in C; the scale's ticks never are.)
export function tickLabel(value) {
  if (value === 0) return "0";
  const magnitude = Math.abs(value);
  if (magnitude >= 1e-3 && magnitude < 1e6) {
    const decimals = Math.max(0, 2 - Math.floor(Math.log10(magnitude)));
    return dropTrailingZeros(value.toFixed(decimals));
  }
  const [mantissa, exponent] = value.toExponential(2).split("e"); // "1.50e-4", "2.00e+6"
  return `${dropTrailingZeros(mantissa)}e${exponent.startsWith("-") ? "-" : ""}${exponent.replace(/^[+-]/, "")}`;
}
