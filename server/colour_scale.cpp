#include "server/colour_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace lambert {
namespace {

// A bound taken as inside the scale up to rounding of the tick values themselves.
bool inside(double v, const ColourScale& s) {
  const double slack = 1e-9 * s.hi;
  return v >= s.lo - slack && v <= s.hi + slack;
}

std::vector<Tick> log_ticks(const ColourScale& s, int max_ticks) {
  const int first = static_cast<int>(std::floor(std::log10(s.lo))), last = static_cast<int>(std::ceil(std::log10(s.hi)));
  for (const std::vector<double>& mantissas : {std::vector<double>{1, 2, 5}, std::vector<double>{1}}) {
    for (int every = 1; every <= 8; every *= 2) {
      std::vector<Tick> ticks;
      for (int k = first; k <= last; ++k) {
        if (((k % every) + every) % every != 0) continue;
        for (double m : mantissas) {
          const double v = m * std::pow(10.0, k);
          if (inside(v, s)) ticks.push_back({v, tick_label(v)});
        }
      }
      if (static_cast<int>(ticks.size()) <= max_ticks || (mantissas.size() == 1 && every == 8)) return ticks;
      if (mantissas.size() > 1) break;  // thin the mantissas before the decades
    }
  }
  return {};
}

std::vector<Tick> linear_ticks(const ColourScale& s, int max_ticks) {
  const double raw = s.hi / std::max(1, max_ticks - 1);
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * decade;
  for (double m : {1.0, 2.0, 2.5, 5.0})
    if (m * decade >= raw * (1 - 1e-12)) {
      step = m * decade;
      break;
    }
  std::vector<Tick> ticks;
  for (int k = 0; k * step <= s.hi * (1 + 1e-9); ++k) ticks.push_back({k * step, tick_label(k * step)});
  return ticks;
}

}  // namespace

double ColourScale::position(double v) const {
  if (!(hi > 0) || !std::isfinite(v)) return 0;
  if (kind == ScaleKind::Linear) return std::clamp(v / hi, 0.0, 1.0);
  if (!(v > 0)) return 0;
  return hi > lo ? std::clamp(std::log(v / lo) / std::log(hi / lo), 0.0, 1.0) : 1.0;
}

ColourScale colour_scale(const std::vector<double>& values, ScaleKind kind) {
  double hi = 0, lo_positive = std::numeric_limits<double>::infinity();
  for (double v : values)
    if (v > 0 && std::isfinite(v)) hi = std::max(hi, v), lo_positive = std::min(lo_positive, v);
  if (!(hi > 0)) return {kind, 0, 0};
  if (kind == ScaleKind::Linear) return {kind, 0, hi};
  return {kind, std::max(hi * std::pow(10.0, -kLogScaleDecades), lo_positive), hi};
}

Rgb false_colour_ramp(double t) {
  static constexpr double stops[6][3] = {{0, 0, 64}, {0, 0, 255}, {0, 255, 255}, {0, 255, 0}, {255, 255, 0}, {255, 0, 0}};
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 5;
  const int k = std::min(4, static_cast<int>(t));
  const double f = t - k;
  auto mix = [&](int c) { return static_cast<std::uint8_t>(std::lround(stops[k][c] + f * (stops[k + 1][c] - stops[k][c]))); };
  return {mix(0), mix(1), mix(2)};
}

std::vector<Tick> scale_ticks(const ColourScale& s, int max_ticks) {
  if (!(s.hi > 0)) return {{0, "0"}};
  std::vector<Tick> ticks = s.kind == ScaleKind::Log ? log_ticks(s, max_ticks) : linear_ticks(s, max_ticks);
  if (ticks.size() < 2) ticks = {{s.lo, tick_label(s.lo)}, {s.hi, tick_label(s.hi)}};
  return ticks;
}

std::string tick_label(double value) {
  if (value == 0) return "0";
  char text[32];
  const double magnitude = std::abs(value);
  if (magnitude >= 1e-3 && magnitude < 1e6) {
    // Three significant digits as plain decimals, trailing zeros after the point dropped.
    const int decimals = std::max(0, 2 - static_cast<int>(std::floor(std::log10(magnitude))));
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    std::string s = text;
    if (s.find('.') != std::string::npos) {
      s.erase(s.find_last_not_of('0') + 1);
      if (s.back() == '.') s.pop_back();
    }
    return s;
  }
  std::snprintf(text, sizeof text, "%.2e", value);  // "1.50e-04", "2.00e+06"
  std::string s = text;
  const auto e = s.find('e');
  std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
  mantissa.erase(mantissa.find_last_not_of('0') + 1);
  if (mantissa.back() == '.') mantissa.pop_back();
  const bool negative = exponent[0] == '-';
  exponent.erase(0, 1);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return mantissa + "e" + (negative ? "-" : "") + exponent;
}

}  // namespace lambert
