// CIELAB and CIEDE2000 (see colour_difference.h). Angles in degrees, as in the formula's definition.
#include "solver/colour_difference.h"

#include <cmath>

namespace lambert {
namespace {

constexpr double kDegree = kPi / 180.0;

// CIE 15:2018 eq. 8.9: f(t) = t^(1/3) above (6/29)^3, and the linear segment t/(3 (6/29)^2) + 4/29
// below it, which joins it with equal value and slope.
double lab_f(double t) {
  constexpr double delta = 6.0 / 29.0;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3 * delta * delta) + 4.0 / 29.0;
}

// Hue angle in [0, 360) degrees; 0 for the achromatic point (Sharma eq. 4).
double hue_deg(double b, double a_prime) {
  if (b == 0 && a_prime == 0) return 0;
  const double h = std::atan2(b, a_prime) / kDegree;
  return h < 0 ? h + 360 : h;
}

double pow7(double x) {
  const double x2 = x * x;
  return x2 * x2 * x2 * x;
}

}  // namespace

Lab cielab(const Xyz& c, const Xyz& white) {
  const double fx = lab_f(c.X / white.X), fy = lab_f(c.Y / white.Y), fz = lab_f(c.Z / white.Z);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

Xyz white_from_chromaticity(double Y, double x, double y) {
  return {Y * x / y, Y, Y * (1 - x - y) / y};
}

double ciede2000(const Lab& first, const Lab& second) {
  constexpr double k25pow7 = 6103515625.0;  // 25^7
  // Sharma eqs. 2-5: a' stretched by G so that near-neutral colours get hue differences of the
  // right size; C' and h' from it.
  const double C1 = std::hypot(first.a, first.b), C2 = std::hypot(second.a, second.b);
  const double C_mean = 0.5 * (C1 + C2);
  const double G = 0.5 * (1 - std::sqrt(pow7(C_mean) / (pow7(C_mean) + k25pow7)));
  const double a1 = (1 + G) * first.a, a2 = (1 + G) * second.a;
  const double C1p = std::hypot(a1, first.b), C2p = std::hypot(a2, second.b);
  const double h1p = hue_deg(first.b, a1), h2p = hue_deg(second.b, a2);

  // Eqs. 8-11: differences; the hue difference takes the shorter way round the circle.
  const double dLp = second.L - first.L;
  const double dCp = C2p - C1p;
  double dhp = 0;
  if (C1p * C2p != 0) {
    dhp = h2p - h1p;
    if (dhp > 180) dhp -= 360;
    else if (dhp < -180) dhp += 360;
  }
  const double dHp = 2 * std::sqrt(C1p * C2p) * std::sin(0.5 * dhp * kDegree);

  // Eqs. 12-22: means (the mean hue again the shorter way round), weighting functions, rotation.
  const double Lp_mean = 0.5 * (first.L + second.L);
  const double Cp_mean = 0.5 * (C1p + C2p);
  double hp_mean = h1p + h2p;
  if (C1p * C2p != 0) {
    if (std::abs(h1p - h2p) <= 180) hp_mean *= 0.5;
    else if (h1p + h2p < 360) hp_mean = 0.5 * (h1p + h2p + 360);
    else hp_mean = 0.5 * (h1p + h2p - 360);
  }
  const double T = 1 - 0.17 * std::cos((hp_mean - 30) * kDegree) + 0.24 * std::cos(2 * hp_mean * kDegree) +
                   0.32 * std::cos((3 * hp_mean + 6) * kDegree) - 0.20 * std::cos((4 * hp_mean - 63) * kDegree);
  const double d_theta = 30 * std::exp(-std::pow((hp_mean - 275) / 25, 2));
  const double R_C = 2 * std::sqrt(pow7(Cp_mean) / (pow7(Cp_mean) + k25pow7));
  const double L50 = (Lp_mean - 50) * (Lp_mean - 50);
  const double S_L = 1 + 0.015 * L50 / std::sqrt(20 + L50);
  const double S_C = 1 + 0.045 * Cp_mean;
  const double S_H = 1 + 0.015 * Cp_mean * T;
  const double R_T = -std::sin(2 * d_theta * kDegree) * R_C;

  const double l = dLp / S_L, c = dCp / S_C, h = dHp / S_H;
  return std::sqrt(l * l + c * c + h * h + R_T * c * h);
}

}  // namespace lambert
