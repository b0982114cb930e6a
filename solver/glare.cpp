// The UGR formula and the Guth position index (see glare.h for the sources).
#include "solver/glare.h"

#include <algorithm>
#include <cmath>

namespace lambert {

std::optional<double> guth_position_index(const Vector3& view, const Vector3& up, const Vector3& to_source) {
  constexpr double kDeg = 180 / 3.14159265358979323846;
  const double c = std::clamp(dot(to_source, view), -1.0, 1.0);
  if (c <= 0) return std::nullopt;
  const Vector3 across = to_source - view * c;  // the source's offset in the plane of the field
  const double s = length(across);
  if (s == 0) return 1.0;
  const double sigma = std::atan2(s, c) * kDeg;
  const double tau = std::acos(std::clamp(std::abs(dot(across, up)) / s, 0.0, 1.0)) * kDeg;
  const double linear = (35.2 - 0.31889 * tau - 1.22 * std::exp(-2 * tau / 9)) * 1e-3;
  const double quadratic = (21 + 0.26667 * tau - 0.002963 * tau * tau) * 1e-5;
  return std::exp(sigma * (linear + sigma * quadratic));
}

std::optional<double> unified_glare_rating(double background_luminance_cd_m2, const std::vector<GlareSource>& sources) {
  double sum = 0;
  for (const GlareSource& s : sources) sum += s.term;
  if (!(background_luminance_cd_m2 > 0) || !(sum > 0)) return std::nullopt;
  return 8 * std::log10(0.25 / background_luminance_cd_m2 * sum);
}

}  // namespace lambert
