// Sky luminance distributions (see sky_luminance.h).
#include "solver/lights/sky_luminance.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/spectrum.h"

namespace lambert {
namespace {

// ISO 15469:2004 (CIE S 011/E:2003), Table 1: the six gradation groups (a, b) ...
struct Gradation {
  double a, b;
};
constexpr std::array<Gradation, 6> kGradation = {{{4.0, -0.70},    // I: overcast, steep gradation to the zenith
                                                  {1.1, -0.80},    // II: overcast, moderate gradation
                                                  {0.0, -1.00},    // III: uniform gradation
                                                  {-1.0, -0.55},   // IV: partly cloudy
                                                  {-1.0, -0.32},   // V: clear
                                                  {-1.0, -0.15}}};  // VI: cloudless, turbid
// ... the six indicatrix groups (c, d, e) ...
struct Indicatrix {
  double c, d, e;
};
constexpr std::array<Indicatrix, 6> kIndicatrix = {{{0, -1.0, 0.00},    // 1: no sun dependence
                                                    {2, -1.5, 0.15},    // 2: slight brightening towards the sun
                                                    {5, -2.5, 0.30},    // 3: brighter circumsolar region
                                                    {10, -3.0, 0.45},   // 4: distinct solar corona
                                                    {16, -3.0, 0.30},   // 5
                                                    {24, -2.8, 0.15}}};  // 6: turbid
// ... and the fifteen standard skies as (gradation group, indicatrix group).
constexpr std::array<std::array<int, 2>, kCieGeneralSkyTypes> kTypeGroups = {{{1, 1}, {1, 2}, {2, 1}, {2, 2}, {3, 1},
                                                                             {3, 2}, {3, 3}, {3, 4}, {4, 2}, {4, 3},
                                                                             {4, 4}, {5, 4}, {5, 5}, {6, 5}, {6, 6}}};

const std::array<CieSkyParameters, kCieGeneralSkyTypes>& general_sky_table() {
  static const auto table = [] {
    std::array<CieSkyParameters, kCieGeneralSkyTypes> t{};
    for (int k = 0; k < kCieGeneralSkyTypes; ++k) {
      const auto [g, i] = kTypeGroups[k];
      t[k] = {g, i, kGradation[g - 1].a, kGradation[g - 1].b, kIndicatrix[i - 1].c, kIndicatrix[i - 1].d,
              kIndicatrix[i - 1].e};
    }
    return t;
  }();
  return table;
}

// The angle between two unit vectors, accurate near 0 and π (atan2 of the sine and cosine).
double angle_between(const Vector3& a, const Vector3& b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

// Gauss–Legendre nodes and weights on [−1, 1] (Newton's iteration on P_n from Chebyshev guesses).
struct GaussLegendre {
  std::vector<double> x, w;
};
GaussLegendre gauss_legendre(int n) {
  GaussLegendre g;
  g.x.resize(n), g.w.resize(n);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      const double step = p1 / dp;
      z -= step;
      if (std::abs(step) < 1e-16) break;
    }
    g.x[i] = z;
    g.w[i] = 2 / ((1 - z * z) * dp * dp);
  }
  return g;
}

}  // namespace

const CieSkyParameters& cie_general_sky(int type) {
  if (type < 1 || type > kCieGeneralSkyTypes) throw std::out_of_range("CIE general sky type " + std::to_string(type));
  return general_sky_table()[type - 1];
}

bool cie_sky_depends_on_sun(int type) { return cie_general_sky(type).indicatrix_group > 1; }

SkyDistribution::SkyDistribution(SkyKind kind, int type, const Vector3& up, const Vector3& sun)
    : kind_(kind), type_(type), up_(up), sun_(sun) {}

SkyDistribution SkyDistribution::general(int type, const Vector3& up, const Vector3& sun) {
  const CieSkyParameters& p = cie_general_sky(type);
  const bool needs_sun = p.indicatrix_group > 1;
  if (needs_sun && !(dot(sun, up) > 0)) throw std::invalid_argument("the sun must stand above the horizon");
  // Without a sun dependence the pole of the quadrature is put at the zenith.
  SkyDistribution sky(SkyKind::kGeneral, type, up, needs_sun ? sun : up);
  sky.params_ = p;
  sky.uniform_ = p.a == 0 && p.c == 0 && p.e == 0;
  sky.normalisation_ = 1 / (sky.gradation(1.0) * sky.indicatrix(angle_between(sky.sun_, up)));
  sky.horizontal_factor_ = sky.uniform_ ? kPi : sky_horizontal_integral(sky);
  return sky;
}

SkyDistribution SkyDistribution::cie_overcast(const Vector3& up) {
  SkyDistribution sky(SkyKind::kCieOvercast, kCieOvercastSkyType, up, up);
  sky.horizontal_factor_ = 7 * kPi / 9;
  return sky;
}

SkyDistribution SkyDistribution::uniform(const Vector3& up) {
  SkyDistribution sky(SkyKind::kUniform, 0, up, up);
  sky.uniform_ = true;
  sky.horizontal_factor_ = kPi;
  return sky;
}

double SkyDistribution::gradation(double cos_Z) const {
  return cos_Z > 0 ? 1 + params_.a * std::exp(params_.b / cos_Z) : 1.0;
}

double SkyDistribution::indicatrix(double chi) const {
  const double cos_chi = std::cos(chi);
  return 1 + params_.c * (std::exp(params_.d * chi) - std::exp(params_.d * kPi / 2)) + params_.e * cos_chi * cos_chi;
}

double SkyDistribution::relative_luminance(const Vector3& omega) const {
  const double cos_Z = dot(omega, up_);
  if (!(cos_Z > 0)) return 0;
  switch (kind_) {
    case SkyKind::kUniform: return 1;
    case SkyKind::kCieOvercast: return (1 + 2 * cos_Z) / 3;
    case SkyKind::kGeneral: break;
  }
  const double f = params_.c == 0 && params_.e == 0 ? 1.0 : indicatrix(angle_between(omega, sun_));
  return normalisation_ * gradation(cos_Z) * f;
}

double sky_horizontal_integral(const SkyDistribution& sky) {
  // Frame about the sun s: u towards the zenith in the vertical plane through the sun, v = s × u.
  const Vector3 s = sky.sun(), up = sky.up();
  const double s_z = dot(s, up);
  const Vector3 towards_zenith = up - s * s_z;
  const Vector3 u = length(towards_zenith) > 1e-12 ? normalize(towards_zenith) : perpendicular(s);
  const Vector3 v = cross(s, u);
  const double u_z = dot(u, up);
  // χ panels [t_k, t_{k+1}] χ_h with t_k = 1 − 2^−k (k < kPanels), the last ending at 1: halved towards
  // the horizon, where exp(b / cos Z) varies on the scale |b| of cos Z.
  constexpr int kPanels = 14, kNodes = 16, kAzimuths = 384;
  static const GaussLegendre gl = gauss_legendre(kNodes);
  double total = 0;
  for (int j = 0; j < kAzimuths; ++j) {
    const double psi = 2 * kPi * j / kAzimuths;
    const Vector3 across = u * std::cos(psi) + v * std::sin(psi);
    const double chi_h = std::atan2(s_z, -u_z * std::cos(psi));
    double inner = 0;
    for (int k = 0; k < kPanels; ++k) {
      const double t0 = 1 - std::ldexp(1.0, -k), t1 = k + 1 < kPanels ? 1 - std::ldexp(1.0, -(k + 1)) : 1.0;
      const double a = t0 * chi_h, b = t1 * chi_h, half = 0.5 * (b - a), mid = 0.5 * (a + b);
      for (int q = 0; q < kNodes; ++q) {
        const double chi = mid + half * gl.x[q];
        const Vector3 omega = s * std::cos(chi) + across * std::sin(chi);
        inner += half * gl.w[q] * sky.relative_luminance(omega) * std::max(0.0, dot(omega, up)) * std::sin(chi);
      }
    }
    total += inner;
  }
  return total * 2 * kPi / kAzimuths;
}

}  // namespace lambert
