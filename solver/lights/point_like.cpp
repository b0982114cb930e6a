// The cone integral and the point-like source base (see point_like.h for the derivation).
#include "solver/lights/point_like.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "solver/lights/polar_integral.h"
#include "solver/quadrature_1d.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

// ln cos ψ, accurate near ψ = 0 (where cos ψ rounds to 1) and near π/2.
double log_cos(double psi) {
  const double s = std::sin(0.5 * psi);
  return psi < kPi / 4 ? std::log1p(-2 * s * s) : std::log(std::cos(psi));
}

}  // namespace

double cone_lobe_value(const ConeLobe& lobe, double cos_psi) {
  if (lobe.max_angle_rad < kPi && cos_psi < std::cos(lobe.max_angle_rad)) return 0;
  if (lobe.exponent == 0) return 1;
  if (cos_psi <= 0) return 0;
  return std::exp(lobe.exponent * std::log(cos_psi));
}

double cone_band(double m, double psi1, double psi2) {
  if (!(psi2 > psi1)) return 0;
  // cos ψ1 − cos ψ2 = 2 sin((ψ1+ψ2)/2) sin((ψ2−ψ1)/2), exact for nearby angles.
  const double chord = 2 * std::sin(0.5 * (psi1 + psi2)) * std::sin(0.5 * (psi2 - psi1));
  if (m == 0) return chord;
  const double cos1 = std::cos(psi1);
  if (cos1 <= 0) return 0;
  const double k = m + 1;
  const double head = std::exp(k * log_cos(psi1)) / k;  // cos^{m+1} ψ1 / (m+1), underflows to 0
  if (head == 0 || psi2 >= kPi / 2) return head;
  // cos^k ψ1 − cos^k ψ2 = cos^k ψ1 (1 − (cos ψ2/cos ψ1)^k), cos ψ2/cos ψ1 = 1 − chord/cos ψ1.
  const double ratio = std::min(1.0, chord / cos1);
  return head * -std::expm1(k * std::log1p(-ratio));
}

double cone_lobe_flux(const ConeLobe& lobe) {
  return 2 * kPi * cone_band(lobe.exponent, 0, lobe.max_angle_rad);
}

double cone_integral(const Point3& origin, const ConeLobe& lobe, std::span<const Point3> polygon,
                     const DirectionWeight& weight, double rel_tolerance) {
  const PolarFrame frame(lobe.axis);
  const double m = lobe.exponent;
  const double psi_max = m > 0 ? std::min(lobe.max_angle_rad, kPi / 2) : lobe.max_angle_rad;

  // The band's integral along the half-plane of azimuth φ.
  auto band = [&](double phi, double psi1, double psi2) {
    psi2 = std::min(psi2, psi_max);
    const double exact = cone_band(m, psi1, psi2);
    if (!weight || exact == 0) return exact;
    // ∫ cos^m ψ sin ψ w dψ = (exact) × mean of w in the variable v = cos^{m+1} ψ (v = cos ψ when
    // m = 0), in which the lobe is uniform. v runs from v(ψ2) to v(ψ1) = v(ψ2) + (m+1) exact.
    const double cp = std::cos(phi), sp = std::sin(phi);
    const Vector3 e = frame.a * cp + frame.b * sp;
    const double k = m + 1;
    const double v2 = m == 0 ? std::cos(psi2) : (psi2 >= kPi / 2 ? 0.0 : std::exp(k * log_cos(psi2)));
    const double dv = k * exact;
    auto w_of_t = [&](double t) {
      const double v = v2 + t * dv;
      double cos_psi, sin_psi;
      if (m == 0) {
        cos_psi = std::clamp(v, -1.0, 1.0);
        sin_psi = std::sqrt((1 - cos_psi) * (1 + cos_psi));
      } else {
        const double L = std::log(v) / k;  // ln cos ψ
        cos_psi = std::exp(L);
        sin_psi = std::sqrt(std::max(0.0, -std::expm1(2 * L)));
      }
      return weight(e * sin_psi + frame.c * cos_psi);
    };
    const std::array<quadrature::Interval, 1> unit{quadrature::Interval{0, 1}};
    return exact * quadrature::integrate_1d(w_of_t, unit, 0.1 * rel_tolerance, 400);
  };
  return polar_integral(origin, frame, polygon, band, psi_max, {}, rel_tolerance);
}

// ---- PointLikeLight ------------------------------------------------------------------------------

double PointLikeLight::unshadowed_factor(const Point3& p, const Vector3& n) const {
  const Vector3 d = p - light_.position;
  const double r = length(d);
  if (r == 0) return 0;  // receiver at the source: no defined direction, measure zero
  const double cos_alpha = -dot(n, d) / r;
  if (cos_alpha <= 0) return 0;
  const Attenuation& c = light_.attenuation;
  const double att = light_.inverse_square ? r * r : c.c1 + c.c2 * r + c.c3 * r * r;
  if (!(att > 0)) return 0;
  return cone_lobe_value(lobe_, dot(lobe_.axis, d) / r) * cos_alpha / att;
}

double PointLikeLight::point_factor(const Point3& p, const Vector3& n, const Visibility& vis) const {
  const double g = unshadowed_factor(p, n);
  return g != 0 ? g * vis.transmitted(p, light_.position) : 0;
}

double PointLikeLight::receiver_factor(const Receiver& r, const Visibility& vis) const {
  if (r.kind == Receiver::Kind::Planar) return point_factor(r.point, r.normal, vis);
  const Vector3 d = r.point - light_.position;
  const double dist = length(d);
  if (dist == 0) return 0;  // receiver at the source: no defined direction, measure zero
  const Attenuation& c = light_.attenuation;
  const double att = light_.inverse_square ? dist * dist : c.c1 + c.c2 * dist + c.c3 * dist * dist;
  if (!(att > 0)) return 0;
  const double g = cone_lobe_value(lobe_, dot(lobe_.axis, d) / dist) * receiver_weight(r, -d / dist) / att;
  return g != 0 ? g * vis.transmitted(r.point, light_.position) : 0;
}

GlareView PointLikeLight::glare_view(const Point3& eye, const Visibility& vis) const {
  const Vector3 d = light_.position - eye;
  const double r = length(d);
  if (r == 0) return {};
  const double I = cone_lobe_value(lobe_, -dot(lobe_.axis, d) / r);
  if (I == 0 || !vis.visible(eye, light_.position)) return {};
  GlareView g;
  g.kind = GlareView::Kind::Point;
  g.direction = d / r;
  g.distance_m = r;
  g.intensity = I;
  return g;
}

double PointLikeLight::patch_factor(const Triangle& t, const Visibility& vis) const {
  const Vector3 n = t.normal();
  if (dot(light_.position - t.v[0], n) <= 0) return 0;  // the source is behind the patch
  const double average = patch_integral(t) / t.area();
  if (!(average > 0)) return 0;
  return average * weighted_visible_fraction(
                       vis, [&](int k) { return std::pair{visibility_sample(t, k), light_.position}; },
                       [&](const Point3& p, const Point3&) { return unshadowed_factor(p, n); });
}

double PointLikeLight::attenuated_cone_integral(const Triangle& t, const ConeLobe& lobe) const {
  if (light_.inverse_square) return cone_integral(light_.position, lobe, t.v);
  // A ray from the source in direction ω meets the patch's plane at r = h / (−n·ω); with x = 1/r,
  // r²/att(r) = 1/(c1 x² + c2 x + c3), finite up to grazing directions.
  const Vector3 n = t.normal();
  const double h = dot(light_.position - t.v[0], n);
  const Attenuation c = light_.attenuation;
  return cone_integral(light_.position, lobe, t.v, [&](const Vector3& w) {
    const double x = std::max(0.0, -dot(n, w)) / h;
    return 1 / (c.c1 * x * x + c.c2 * x + c.c3);
  });
}

}  // namespace lambert
