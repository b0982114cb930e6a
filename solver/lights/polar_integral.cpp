// The polar integral over a polygon's directions (polar_integral.h).
#include "solver/lights/polar_integral.h"

#include <vector>

namespace lambert {
namespace {

constexpr int kMaxPolygon = 8;

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
  bool section(const PolarFrame& f, double phi, double& psi1, double& psi2) const {
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
    // Every point kept has x_e ≥ 0; a point on the axis line may carry x_e = −0.0 (or a rounding
    // residue below 0), whose atan2 behind the origin would be −π instead of π (std::max keeps −0.0).
    auto on_side = [](double e) { return e > 0 ? e : 0.0; };
    const double a0 = std::atan2(on_side(e0), c0), a1 = std::atan2(on_side(e1), c1);
    psi1 = std::min(a0, a1);
    psi2 = std::max(a0, a1);
    return true;
  }

  // Azimuths where the section's end points move non-smoothly or sit closest to a lobe feature.
  std::vector<double> breakpoints(const PolarFrame& f, double max_angle) const {
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

double polar_integral(const Point3& origin, const PolarFrame& frame, std::span<const Point3> polygon,
                      const BandIntegral& band, double psi_max, std::span<const double> azimuth_breaks,
                      double rel_tolerance) {
  const SphericalPolygon poly(origin, polygon);
  if (!poly.has_extent()) return 0;
  auto section_band = [&](double phi) {
    double psi1, psi2;
    if (!poly.section(frame, phi, psi1, psi2)) return 0.0;
    return band(phi, psi1, psi2);
  };
  std::vector<double> breaks = poly.breakpoints(frame, psi_max);
  for (double phi : azimuth_breaks) {
    const double wrapped = phi - 2 * kPi * std::floor(phi / (2 * kPi));
    if (wrapped >= 0 && wrapped < 2 * kPi) breaks.push_back(wrapped);
  }
  std::sort(breaks.begin(), breaks.end());
  if (breaks.empty()) breaks.push_back(0);
  breaks.push_back(breaks.front() + 2 * kPi);
  // A full turn starting at the first breakpoint. Between consecutive breakpoints the section is
  // either empty throughout (the half-plane's hits change only at vertex azimuths, unless the axis
  // pierces the polygon, when they never do) or given by the same two edges: empty pieces are
  // dropped after one probe, and pieces longer than 1 rad start halved.
  std::vector<quadrature::Interval> pieces;
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
  return quadrature::integrate_1d(section_band, pieces, rel_tolerance, 2000);
}

}  // namespace lambert
