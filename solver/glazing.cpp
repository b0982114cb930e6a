#include "solver/glazing.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "solver/quadrature_1d.h"
#include "solver/scene.h"

namespace lambert {

double slab_transmittance(double cos_theta, double n) {
  const double c = std::min(1.0, std::abs(cos_theta));
  const double sin2_t = (1 - c * c) / (n * n);  // Snell: sin θ_t = sin θ / n
  const double ct = std::sqrt(1 - sin2_t);
  const double as = (c - n * ct) / (c + n * ct), ap = (n * c - ct) / (n * c + ct);  // Fresnel amplitudes
  const double rs = as * as, rp = ap * ap;
  return 0.5 * ((1 - rs) / (1 + rs) + (1 - rp) / (1 + rp));
}

double pane_angular_factor(double cos_theta) {
  const double c = std::min(1.0, std::abs(cos_theta));
  if (!(c > 0)) return 0;  // grazing: r_s = r_p = 1
  static const double normal = slab_transmittance(1.0, kPaneRefractiveIndex);
  return slab_transmittance(c, kPaneRefractiveIndex) / normal;
}

std::vector<int> clear_glass_channels(const Scene& scene) {
  std::vector<int> out(scene.materials.size(), -1);
  int count = 0;
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    if (scene.materials[m].transmission == Transmission::kSpecular) out[m] = count++;
  return out;
}

double pane_hemispherical_factor() {
  // In c = cos θ the integrand 2 c g(c) is smooth on [0, 1] (cos θ_t is analytic there).
  static const double mean = [] {
    const std::array<quadrature::Interval, 1> unit{quadrature::Interval{0, 1}};
    return quadrature::integrate_1d([](double c) { return 2 * c * pane_angular_factor(c); }, unit, 1e-13, 200);
  }();
  return mean;
}

}  // namespace lambert
