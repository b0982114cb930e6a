// Integrals of a sky's luminance over the hemisphere by product Gauss rules in angles, independent of
// the solver's own quadratures (sky_luminance.h about the sun, sky_dome.h on the box faces): the
// tests' second method for every general sky.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "mesh/geometry.h"
#include "solver/lights/sky_luminance.h"

namespace lambert::test {

inline const Vector3 kUp{0, 0, 1}, kNorth{0, 1, 0};  // east = north × up = +x
inline constexpr double kDeg = kPi / 180;

// The direction of zenith angle Z and azimuth α (clockwise from north).
inline Vector3 sky_direction(double Z, double alpha) {
  return {std::sin(Z) * std::sin(alpha), std::sin(Z) * std::cos(alpha), std::cos(Z)};
}

// The 10-point Gauss–Legendre rule on [−1, 1] (Abramowitz & Stegun, table 25.4), symmetric pairs.
inline constexpr std::array<double, 5> kGL10x = {0.1488743389816312, 0.4333953941292472, 0.6794095682990244,
                                          0.8650633666889845, 0.9739065285171717};
inline constexpr std::array<double, 5> kGL10w = {0.2955242247147529, 0.2692667193099963, 0.2190863625159820,
                                          0.1494513491505806, 0.0666713443086881};
template <class F>
double gauss10(F&& f, double a, double b) {
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double s = 0;
  for (int i = 0; i < 5; ++i) s += kGL10w[i] * (f(mid - half * kGL10x[i]) + f(mid + half * kGL10x[i]));
  return s * half;
}
// ∫ f over [a, b] split at the given sorted breakpoints into `per` equal panels each.
template <class F>
double composite(F&& f, std::vector<double> breaks, int per) {
  double s = 0;
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k)
    for (int j = 0; j < per; ++j) {
      const double a = breaks[k] + (breaks[k + 1] - breaks[k]) * j / per;
      const double b = breaks[k] + (breaks[k + 1] - breaks[k]) * (j + 1) / per;
      s += gauss10(f, a, b);
    }
  return s;
}

// Breakpoints over [lo, hi] graded geometrically towards `at` from both sides (halving 12 times):
// the panels of a product rule about a point where the integrand has a kink.
inline std::vector<double> graded_about(double at, double lo, double hi) {
  std::vector<double> out = {lo};
  for (int k = 1; k <= 12; ++k) out.push_back(at - (at - lo) * std::ldexp(1.0, -k));
  out.push_back(at);
  for (int k = 12; k >= 1; --k) out.push_back(at + (hi - at) * std::ldexp(1.0, -k));
  out.push_back(hi);
  std::vector<double> kept;  // without the empty panels of a point at an end
  for (double b : out)
    if (kept.empty() || b > kept.back()) kept.push_back(b);
  return kept;
}

// ∫ (L/L_z) (ω·n) dω over the upper hemisphere (ω·n clipped at 0) in zenith and azimuth angles
// (dω = sin Z dZ dα), with panels graded towards the sun's zenith angle and azimuth (its kink on a
// panel corner) and towards the horizon: another method than sky_horizontal_integral's quadrature
// about the sun.
inline double hemisphere_integral(const SkyDistribution& sky, double sun_Z, double sun_alpha, const Vector3& n) {
  std::vector<double> Z_breaks = graded_about(sun_Z, 0, kPi / 2);
  for (int k = 2; k <= 9; ++k) Z_breaks.insert(Z_breaks.end() - 1, kPi / 2 - (kPi / 2 - sun_Z) * std::ldexp(1.0, -k));
  const std::vector<double> alpha_breaks = graded_about(sun_alpha, 0, 2 * kPi);
  return composite(
      [&](double alpha) {
        return composite(
            [&](double Z) {
              const Vector3 w = sky_direction(Z, alpha);
              return sky.relative_luminance(w) * std::max(0.0, dot(w, n)) * std::sin(Z);
            },
            Z_breaks, 2);
      },
      alpha_breaks, 2);
}

// ∫ (L/L_z)(ω) (ω·n) dω over the sky in front of a tilted plane (n not vertical), in coordinates
// about the line a = up × n where the sky's horizon and the plane meet: ω = cos θ a + sin θ (cos φ up +
// sin φ c), c = a × up, dω = sin θ dθ dφ. Both horizons are lines of constant φ (the sky: φ = ±π/2; the
// plane: φ = β ± π/2, n = cos β up + sin β c), so the region is a product of intervals; the panels are
// graded towards the sun in θ and φ and towards the sky's horizon in φ.
inline double lune_integral(const SkyDistribution& sky, const Vector3& n) {
  const Vector3 a = normalize(cross(kUp, n)), c = cross(a, kUp);
  const double beta = std::atan2(dot(n, c), dot(n, kUp));
  const double lo = std::max(-kPi / 2, beta - kPi / 2), hi = std::min(kPi / 2, beta + kPi / 2);
  const Vector3 s = sky.sun();
  const double sun_theta = std::acos(std::clamp(dot(s, a), -1.0, 1.0));
  const double sun_phi = std::atan2(dot(s, c), dot(s, kUp));
  std::vector<double> phi_breaks = graded_about(std::clamp(sun_phi, lo, hi), lo, hi);
  const double sky_horizon = hi == kPi / 2 ? hi : lo;  // the end of φ where the sky meets its horizon
  std::vector<double> extra;
  for (int k = 1; k <= 10; ++k) extra.push_back(sky_horizon - (sky_horizon - (lo + hi) / 2) * std::ldexp(1.0, -k));
  phi_breaks.insert(phi_breaks.end(), extra.begin(), extra.end());
  std::sort(phi_breaks.begin(), phi_breaks.end());
  phi_breaks.erase(std::unique(phi_breaks.begin(), phi_breaks.end()), phi_breaks.end());
  const std::vector<double> theta_breaks = graded_about(sun_theta, 0, kPi);
  return composite(
      [&](double phi) {
        const Vector3 across = kUp * std::cos(phi) + c * std::sin(phi);
        return composite(
            [&](double theta) {
              const Vector3 w = a * std::cos(theta) + across * std::sin(theta);
              return sky.relative_luminance(w) * std::max(0.0, dot(w, n)) * std::sin(theta);
            },
            theta_breaks, 2);
      },
      phi_breaks, 2);
}

}  // namespace lambert::test
