// The false-colour scale of Lambert's pictures: which values map to which colour, on a linear or a
// logarithmic scale, and the scale's tick values with their labels. Pure arithmetic; the legend is
// drawn by server/legend.h.
#pragma once

#include <string>
#include <vector>

#include "server/image.h"

namespace lambert {

enum class ScaleKind { Linear, Log };

struct ColourScale {
  ScaleKind kind = ScaleKind::Log;
  double lo = 0, hi = 1;  // log: 0 < lo ≤ hi; linear: lo = 0 ≤ hi
  // Where v sits on the scale, in [0, 1] (clamped): log(v/lo)/log(hi/lo), or v/hi. Values ≤ 0 on
  // a log scale sit at 0.
  double position(double v) const;
};

// The log scale spans three decades at most: from the largest value down to the smallest positive
// one or to a thousandth of the largest, whichever is higher. The linear scale runs from 0 to the
// largest value. {kind, 0, 0} when no value is positive: everything sits at 0.
inline constexpr double kLogScaleDecades = 3;
ColourScale colour_scale(const std::vector<double>& values, ScaleKind kind);

// The colour at position t in [0, 1]: dark blue through blue, cyan, green and yellow to red.
Rgb false_colour_ramp(double t);

struct Tick {
  double value = 0;
  std::string label;
};

// Ticks inside [lo, hi], at most about `max_ticks`: on a log scale 1, 2 and 5 × 10^k (or only the
// decades, or every other decade, when there would be too many); on a linear scale multiples of the
// first of 1, 2, 2.5 or 5 × 10^k that keeps them within `max_ticks`. A scale with fewer than two
// such values gets its ends instead.
std::vector<Tick> scale_ticks(const ColourScale& scale, int max_ticks);

// A tick's label: at most three significant digits, plain decimals from 0.001 to 10^6 ("0.25", "20",
// "12000"), else "1.5e-4", "2e6"; 0 is "0".
std::string tick_label(double value);

}  // namespace lambert
