// Clear glass ("transmission": "specular"): the pane's angular factor g(θ) (solver/glazing.h)
// against the Fresnel equations in their other (Snell-angle) form and Duffie & Beckman's worked
// example.
#include <gtest/gtest.h>

#include <cmath>

#include "solver/glazing.h"
#include "solver/scene.h"

namespace lambert {
namespace {

double deg(double d) { return d * kPi / 180; }

// Fresnel's reflectances by the angles (Hecht, Optics, eqs. 4.42–4.43):
//   r_s = sin²(θ_t − θ) / sin²(θ_t + θ),   r_p = tan²(θ_t − θ) / tan²(θ_t + θ),   sin θ_t = sin θ / n,
// and the non-absorbing slab's ½ Σ (1 − r)/(1 + r) (Duffie & Beckman eq. 5.1.8, N = 1).
double slab_by_angles(double theta, double n) {
  const double t = std::asin(std::sin(theta) / n);
  const double rs = std::pow(std::sin(t - theta) / std::sin(t + theta), 2);
  const double rp = std::pow(std::tan(t - theta) / std::tan(t + theta), 2);
  return 0.5 * ((1 - rs) / (1 + rs) + (1 - rp) / (1 + rp));
}

TEST(PaneAngularFactor, IsTheFresnelSlabNormalisedToOneAtNormalIncidence) {
  // g(0) = 1; at normal incidence the slab passes 2n/(n² + 1) (r = ((n − 1)/(n + 1))²).
  const double n = kPaneRefractiveIndex;
  EXPECT_DOUBLE_EQ(pane_angular_factor(1.0), 1.0);
  EXPECT_NEAR(slab_transmittance(1.0, n), 2 * n / (n * n + 1), 1e-15);
  EXPECT_EQ(pane_angular_factor(0.0), 0.0);              // grazing: r_s = r_p = 1
  EXPECT_LT(pane_angular_factor(std::cos(deg(89.99))), 1e-3);
  // Either side of the pane alike.
  EXPECT_EQ(pane_angular_factor(-0.5), pane_angular_factor(0.5));
  for (const double d : {10.0, 30.0, 45.0, 60.0, 70.0, 80.0, 85.0}) {
    const double g = slab_by_angles(deg(d), n) / (2 * n / (n * n + 1));
    EXPECT_NEAR(pane_angular_factor(std::cos(deg(d))), g, 1e-13) << d;
  }
  // g falls monotonically: the shape of a pane's transmittance.
  double last = 1.0;
  for (int d = 1; d < 90; ++d) {
    const double g = pane_angular_factor(std::cos(deg(d)));
    EXPECT_LE(g, last) << d;
    last = g;
  }
}

TEST(PaneAngularFactor, MatchesDuffieAndBeckmansExample) {
  // Duffie & Beckman, Solar Engineering of Thermal Processes (4th ed.), Example 5.1.1: one
  // non-absorbing cover of n = 1.526 at 60° passes τ_r = 0.842 (θ_t = 34.6°, r_s = 0.185,
  // r_p = 0.0014); at normal incidence 0.917. To the example's three digits.
  EXPECT_NEAR(slab_transmittance(std::cos(deg(60)), 1.526), 0.842, 5e-4);
  EXPECT_NEAR(slab_transmittance(1.0, 1.526), 0.917, 5e-4);
}

TEST(PaneAngularFactor, HemisphericalMeanByAnotherQuadrature) {
  // ḡ = ∫₀¹ g du with u = sin²θ (cos θ sin θ dθ = du/2): a midpoint sum in u of 2·10⁵ cells, whose
  // error (the integrand's √(1 − u) end) is below 1e-7.
  const int cells = 200000;
  double sum = 0;
  for (int k = 0; k < cells; ++k) sum += pane_angular_factor(std::sqrt(1 - (k + 0.5) / cells));
  EXPECT_NEAR(pane_hemispherical_factor(), sum / cells, 1e-6);
  EXPECT_NEAR(pane_hemispherical_factor(), 0.92171, 1e-5);  // docs/METHOD.md's value
}

}  // namespace
}  // namespace lambert
