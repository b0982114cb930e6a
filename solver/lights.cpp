// Ambient, directional and point-like sources (isotropic point, goniometric cos^m, spot, Warn).
// The geometric factor g of each model is documented in lights.h; the closed forms are tested in
// tests/radiosity_test.cpp (point source E = I h/d³, patch flux I Ω).
#include "solver/lights.h"

#include <algorithm>
#include <cmath>

#include "solver/cubature.h"
#include "solver/form_factor.h"
#include "solver/visible_fraction.h"

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
    return vis.visible(p, p - d->direction * vis.scene_extent()) ? g : 0;
  }
  return vis.visible(p, std::get<PointLight>(light).position) ? g : 0;
}

double light_patch_factor(const Light& light, const Triangle& t, const Visibility& vis) {
  const Vector3 n = t.normal();
  if (std::holds_alternative<AmbientLight>(light)) return 1;
  if (const auto* d = std::get_if<DirectionalLight>(&light)) {
    const double g = std::max(0.0, -dot(n, d->direction));
    if (g == 0) return 0;
    // A segment towards the light that surely leaves the scene (the direction is constant).
    const Vector3 reach = -d->direction * vis.scene_extent();
    return g * weighted_visible_fraction(
                   vis, [&](int k) { const Point3 p = visibility_sample(t, k); return std::pair{p, p + reach}; },
                   [](const Point3&, const Point3&) { return 1.0; });
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
  return average * weighted_visible_fraction(
                       vis, [&](int k) { return std::pair{visibility_sample(t, k), l.position}; },
                       [&](const Point3& p, const Point3&) { return kernel(p); });
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

}  // namespace lambert
