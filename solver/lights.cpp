// Ambient, directional and point-like sources (isotropic point, goniometric cos^m, spot, Warn).
// The geometric factor g of each model is documented in lights.h; the closed forms are tested in
// tests/radiosity_test.cpp (point source E = I h/d³, patch flux I Ω).
#include "solver/lights.h"

#include <algorithm>
#include <cmath>

#include "solver/cubature.h"
#include "solver/form_factor.h"

namespace lambert {
namespace {

struct SpectrumOf {
  const std::vector<double>& operator()(const AmbientLight& l) const { return l.irradiance_W_m2_nm; }
  const std::vector<double>& operator()(const DirectionalLight& l) const { return l.irradiance_W_m2_nm; }
  const std::vector<double>& operator()(const PointLight& l) const { return l.intensity_W_sr_nm; }
};

// I(ψ)/I_0 for the point-like models; ψ is the angle between the axis and the direction to the
// receiver. cos^m ψ is evaluated as exp(m ln cos ψ), which underflows gracefully for m ≈ 10⁴.
double lobe(const PointLight& l, const Vector3& to_receiver_unit) {
  if (l.kind == PointLight::Kind::Point) return 1;
  const double cos_psi = dot(l.axis, to_receiver_unit);
  if (l.kind == PointLight::Kind::Spot && cos_psi < std::cos(l.cutoff_rad)) return 0;
  if (l.exponent == 0) return 1;
  if (cos_psi <= 0) return 0;
  return std::exp(l.exponent * std::log(cos_psi));
}

double attenuation(const PointLight& l, double r) {
  if (l.inverse_square) return r * r;
  return l.attenuation.c1 + l.attenuation.c2 * r + l.attenuation.c3 * r * r;
}

double point_unshadowed(const PointLight& l, const Point3& p, const Vector3& n) {
  const Vector3 d = p - l.position;
  const double r = length(d);
  if (r == 0) return 0;  // receiver at the source: no defined direction, measure zero
  const double cos_alpha = -dot(n, d) / r;
  if (cos_alpha <= 0) return 0;
  const double att = attenuation(l, r);
  if (!(att > 0)) return 0;
  return lobe(l, d / r) * cos_alpha / att;
}

bool isotropic_inverse_square(const PointLight& l) {
  return l.inverse_square && (l.kind == PointLight::Kind::Point ||
                              (l.exponent == 0 && l.kind != PointLight::Kind::Spot));
}

// Kernel-weighted visible fraction of a point (light position) seen from a triangle: rays from the
// stratified samples, weighted by the unshadowed factor at each sample (so that the estimate is of
// the shadowed flux, not of the shadowed area). Four rays first; twelve more if they disagree.
template <class Kernel>
double visible_fraction_to_point(const Triangle& t, const Point3& target, const Visibility& vis,
                                 Kernel&& kernel) {
  const auto& samples = triangle_visibility_samples();
  double seen = 0, total = 0;
  int visible_count = 0;
  for (int k = 0; k < 16; ++k) {
    if (k == 4 && (visible_count == 0 || visible_count == 4)) break;
    const auto& w = samples[k];
    const Point3 p = barycentric(t.v[0], t.v[1], t.v[2], w[0], w[1], w[2]);
    const double weight = kernel(p) + 1e-300;
    const bool v = vis.visible(p, target);
    visible_count += v;
    seen += v ? weight : 0;
    total += weight;
  }
  return seen / total;
}

}  // namespace

const std::vector<double>& light_spectrum(const Light& light) { return std::visit(SpectrumOf{}, light); }

double light_unshadowed_factor(const Light& light, const Point3& p, const Vector3& n) {
  if (std::holds_alternative<AmbientLight>(light)) return 1;
  if (const auto* d = std::get_if<DirectionalLight>(&light)) return std::max(0.0, -dot(n, d->direction));
  return point_unshadowed(std::get<PointLight>(light), p, n);
}

double light_point_factor(const Light& light, const Point3& p, const Vector3& n, const Visibility& vis) {
  const double g = light_unshadowed_factor(light, p, n);
  if (g == 0 || std::holds_alternative<AmbientLight>(light)) return g;
  if (const auto* d = std::get_if<DirectionalLight>(&light)) {
    // Shadow ray towards the light, long enough to leave the scene (Embree works re-centred).
    return vis.visible_towards(p, -d->direction) ? g : 0;
  }
  return vis.visible(p, std::get<PointLight>(light).position) ? g : 0;
}

double light_patch_factor(const Light& light, const Triangle& t, const Visibility& vis) {
  const Vector3 n = t.normal();
  if (std::holds_alternative<AmbientLight>(light)) return 1;
  if (const auto* d = std::get_if<DirectionalLight>(&light)) {
    const double g = std::max(0.0, -dot(n, d->direction));
    if (g == 0) return 0;
    const auto& samples = triangle_visibility_samples();
    int seen = 0, traced = 0;
    for (int k = 0; k < 16; ++k) {
      if (k == 4 && (seen == 0 || seen == 4)) break;
      const auto& w = samples[k];
      seen += vis.visible_towards(barycentric(t.v[0], t.v[1], t.v[2], w[0], w[1], w[2]), -d->direction);
      ++traced;
    }
    return g * seen / traced;
  }
  const PointLight& l = std::get<PointLight>(light);
  auto kernel = [&](const Point3& p) { return point_unshadowed(l, p, n); };
  double average;
  if (isotropic_inverse_square(l)) {
    // ∫_T I cos α / r² dA = I Ω(T): exact, whatever the distance (a light 1 µm above the patch).
    if (dot(l.position - t.v[0], n) <= 0) return 0;
    average = triangle_solid_angle(l.position, t) / t.area();
  } else {
    const double coarse = apply_rule(triangle_rule_degree5(), t, kernel);
    average = integrate_adaptive(t, kernel, coarse, 1e-7 * std::abs(coarse) + 1e-300, 8) / t.area();
  }
  if (average == 0) return 0;
  return average * visible_fraction_to_point(t, l.position, vis, kernel);
}

double light_flux_factor(const Light& light) {
  const auto* l = std::get_if<PointLight>(&light);
  if (!l) return 0;
  const double m = l->kind == PointLight::Kind::Point ? 0 : l->exponent;
  if (l->kind == PointLight::Kind::Point) return 4 * kPi;
  if (l->kind == PointLight::Kind::Spot) {
    const double psi_c = m > 0 ? std::min(l->cutoff_rad, kPi / 2) : l->cutoff_rad;
    return 2 * kPi * (1 - std::pow(std::cos(psi_c), m + 1)) / (m + 1);
  }
  return 2 * kPi / (m + 1);  // ∫ cos^m ψ dω over the front hemisphere
}

const std::array<std::array<double, 3>, 16>& triangle_visibility_samples() {
  static const std::array<std::array<double, 3>, 16> samples = [] {
    const Triangle unit{{Point3{1, 0, 0}, Point3{0, 1, 0}, Point3{0, 0, 1}}};
    std::array<std::array<double, 3>, 16> out{};
    const auto level1 = split4(unit);
    for (int c = 0; c < 4; ++c) {
      const auto level2 = split4(level1[c]);
      for (int g = 0; g < 4; ++g) {
        const Point3 centroid = level2[g].centroid();  // barycentric coordinates of the unit triangle
        out[g * 4 + c] = {centroid.x, centroid.y, centroid.z};
      }
    }
    return out;
  }();
  return samples;
}

}  // namespace lambert
