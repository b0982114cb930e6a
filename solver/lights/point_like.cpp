// The cone integral and the point-like source base (see point_like.h for the derivation).
#include "solver/lights/point_like.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <queue>

#include "solver/quadrature_1d.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

using quadrature::integrate_1d;
using quadrature::Interval;

constexpr int kMaxPolygon = 8;

// ln cos ψ, accurate near ψ = 0 (where cos ψ rounds to 1) and near π/2.
double log_cos(double psi) {
  const double s = std::sin(0.5 * psi);
  return psi < kPi / 4 ? std::log1p(-2 * s * s) : std::log(std::cos(psi));
}

// An orthonormal right-handed frame (a, b, c) about the axis c; azimuth φ is measured from a to b.
struct Frame {
  Vector3 a, b, c;
  explicit Frame(const Vector3& axis) : c(axis) {
    a = perpendicular(c);
    b = cross(c, a);
  }
  double azimuth(const Vector3& v) const {
    const double phi = std::atan2(dot(b, v), dot(a, v));
    return phi < 0 ? phi + 2 * kPi : phi;
  }
};

// The polygon as seen from the origin (vertices relative to it), with the per-azimuth section.
class SphericalPolygon {
 public:
  SphericalPolygon(const Point3& origin, std::span<const Point3> polygon) {
    count_ = static_cast<int>(std::min<std::size_t>(polygon.size(), kMaxPolygon));
    for (int k = 0; k < count_; ++k) v_[k] = polygon[k] - origin;
  }
  int size() const { return count_; }
  const Vector3& vertex(int k) const { return v_[k]; }

  // Whether the origin is off the polygon's plane (relative to the polygon's size).
  bool has_extent() const {
    if (count_ < 3) return false;
    Vector3 newell;
    double scale = 0;
    for (int k = 0; k < count_; ++k) {
      newell += cross(v_[k], v_[(k + 1) % count_]);
      scale = std::max(scale, length(v_[k]));
    }
    const double area2 = length(newell);  // twice the area, when the polygon is planar
    return area2 > 0 && std::abs(dot(newell, v_[0])) > 1e-14 * area2 * scale;
  }

  // The interval [ψ1, ψ2] of polar angles (about f.c) of the polygon's points in the half-plane of
  // azimuth φ; false if the half-plane misses the polygon.
  bool section(const Frame& f, double phi, double& psi1, double& psi2) const {
    const double cp = std::cos(phi), sp = std::sin(phi);
    const Vector3 e = f.a * cp + f.b * sp;   // in-plane direction of the half-plane
    const Vector3 nu = f.b * cp - f.a * sp;  // c × e: normal of the plane through the axis
    std::array<double, kMaxPolygon + 1> s;
    for (int k = 0; k < count_; ++k) s[k] = dot(nu, v_[k]);
    // Points of the polygon on the plane ν·X = 0, in coordinates (x_c, x_e).
    std::array<double, 2 * kMaxPolygon> xc, xe;
    int points = 0;
    for (int k = 0; k < count_; ++k) {
      const int l = (k + 1) % count_;
      if (s[k] == 0) {
        xc[points] = dot(f.c, v_[k]);
        xe[points++] = dot(e, v_[k]);
      } else if (s[l] != 0 && (s[k] < 0) != (s[l] < 0)) {
        const Vector3 x = v_[k] + (v_[l] - v_[k]) * (s[k] / (s[k] - s[l]));
        xc[points] = dot(f.c, x);
        xe[points++] = dot(e, x);
      }
    }
    if (points < 2) return false;
    // The section is the segment between the two points farthest apart.
    int i0 = 0, i1 = 1;
    double best = -1;
    for (int i = 0; i < points; ++i)
      for (int j = i + 1; j < points; ++j) {
        const double d = (xc[i] - xc[j]) * (xc[i] - xc[j]) + (xe[i] - xe[j]) * (xe[i] - xe[j]);
        if (d > best) best = d, i0 = i, i1 = j;
      }
    double c0 = xc[i0], e0 = xe[i0], c1 = xc[i1], e1 = xe[i1];
    if (e0 < 0 && e1 < 0) return false;
    if ((e0 < 0) != (e1 < 0)) {  // the axis line pierces the polygon: clip at x_e = 0
      const double t = e0 / (e0 - e1);
      const double c_cross = c0 + t * (c1 - c0);
      if (e0 < 0) c0 = c_cross, e0 = 0;
      else c1 = c_cross, e1 = 0;
    }
    const double a0 = std::atan2(e0, c0), a1 = std::atan2(e1, c1);
    psi1 = std::min(a0, a1);
    psi2 = std::max(a0, a1);
    return true;
  }

  // Azimuths where the section's end points move non-smoothly or sit closest to a lobe feature.
  std::vector<double> breakpoints(const Frame& f, double max_angle) const {
    std::vector<double> out;
    auto add = [&](const Vector3& x) {
      if (dot(f.a, x) != 0 || dot(f.b, x) != 0) out.push_back(f.azimuth(x));
    };
    const double cos_max = std::cos(max_angle);
    for (int k = 0; k < count_; ++k) {
      const Vector3& A = v_[k];
      const Vector3& B = v_[(k + 1) % count_];
      add(A);
      // Points of the edge's great circle nearest to the axis and to its opposite (ψ extremal).
      const Vector3 g = cross(A, B);
      const double g2 = length_squared(g);
      if (g2 > 0) {
        const Vector3 x = f.c - g * (dot(f.c, g) / g2);
        for (const Vector3& y : {x, -x})
          if (dot(cross(A, y), g) > 0 && dot(cross(y, B), g) > 0) add(y);
      }
      // Crossings of the edge X(t) = A + t D with the cone ψ = ψ_max:
      // (c·X)² = cos²ψ_max |X|², with c·X of the sign of cos ψ_max.
      if (max_angle < kPi) {
        const Vector3 D = B - A;
        const double p = dot(f.c, A), q = dot(f.c, D);
        const double kappa = cos_max * cos_max;
        const double qa = q * q - kappa * length_squared(D), qb = 2 * (p * q - kappa * dot(A, D)),
                     qc = p * p - kappa * length_squared(A);
        std::array<double, 2> roots{-1, -1};
        if (std::abs(qa) > 1e-300) {
          const double disc = qb * qb - 4 * qa * qc;
          if (disc >= 0) {
            const double r = std::sqrt(disc);
            roots = {(-qb - r) / (2 * qa), (-qb + r) / (2 * qa)};
          }
        } else if (qb != 0) {
          roots[0] = -qc / qb;
        }
        for (double t : roots)
          if (t > 0 && t < 1) add(A + D * t);
      }
    }
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  std::array<Vector3, kMaxPolygon> v_;
  int count_ = 0;
};

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
  const SphericalPolygon poly(origin, polygon);
  if (!poly.has_extent()) return 0;
  const Frame frame(lobe.axis);
  const double m = lobe.exponent;
  const double psi_max = m > 0 ? std::min(lobe.max_angle_rad, kPi / 2) : lobe.max_angle_rad;

  // The band's integral along the half-plane of azimuth φ.
  auto band = [&](double phi) {
    double psi1, psi2;
    if (!poly.section(frame, phi, psi1, psi2)) return 0.0;
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
    const std::array<Interval, 1> unit{Interval{0, 1}};
    return exact * integrate_1d(w_of_t, unit, 0.1 * rel_tolerance, 400);
  };

  std::vector<double> breaks = poly.breakpoints(frame, psi_max);
  if (breaks.empty()) breaks.push_back(0);
  breaks.push_back(breaks.front() + 2 * kPi);
  // A full turn starting at the first breakpoint. Between consecutive breakpoints the section is
  // either empty throughout (the half-plane's hits change only at vertex azimuths, unless the axis
  // pierces the polygon, when they never do) or given by the same two edges: empty pieces are
  // dropped after one probe, and pieces longer than 1 rad start halved.
  std::vector<Interval> pieces;
  double psi1, psi2;
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
    const double a = breaks[k], b = breaks[k + 1], mid = 0.5 * (a + b);
    if (!(b > a) || !poly.section(frame, mid, psi1, psi2)) continue;
    if (b - a > 1) {
      pieces.emplace_back(a, mid);
      pieces.emplace_back(mid, b);
    } else {
      pieces.emplace_back(a, b);
    }
  }
  return integrate_1d(band, pieces, rel_tolerance, 2000);
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
  return g != 0 && vis.visible(p, light_.position) ? g : 0;
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
  return g != 0 && vis.visible(r.point, light_.position) ? g : 0;
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
