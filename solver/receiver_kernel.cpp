// The receivers' kernel over a Lambertian triangle and the planar decomposition (receiver_kernel.h).
#include "solver/receiver_kernel.h"

#include <array>
#include <cmath>

#include "solver/cubature.h"
#include "solver/form_factor.h"
#include "solver/quadrature_1d.h"
#include "solver/spectrum.h"

namespace lambert {
namespace {

constexpr double kInvPi = 1 / kPi;
// The cylindrical cubature stops where the children agree with their parent within this share of
// the triangle's solid angle over π² (an upper bound of the kernel: sin θ ≤ 1).
constexpr double kRelTolerance = 1e-9;
constexpr int kMaxAdaptiveDepth = 6;
// Grading: a piece nearer to the point than kNearRatio times its longest edge is split, down to
// kMaxNearLevels levels (a point 1e-7 of the triangle's size above it).
constexpr double kNearRatio = 2;
constexpr int kMaxNearLevels = 24;

bool in_front(const Point3& p, const Triangle& t) { return dot(p - t.v[0], t.area_vector()) > 0; }

template <class F>
double graded(const Point3& p, const Triangle& t, F& f, double abs_tolerance, int level) {
  if (level < kMaxNearLevels && distance_to_triangle(p, t) < kNearRatio * t.max_edge_length()) {
    double sum = 0;
    if (is_elongated(t)) {
      for (const Triangle& c : split2(t)) sum += graded(p, c, f, abs_tolerance, level + 1);
    } else {
      for (const Triangle& c : split4(t)) sum += graded(p, c, f, abs_tolerance, level + 1);
    }
    return sum;
  }
  const double coarse = apply_rule(triangle_rule_degree5(), t, f);
  return integrate_adaptive(t, f, coarse, abs_tolerance, kMaxAdaptiveDepth);
}

// ∫ f over [a, b] by adaptive Gauss–Kronrod, starting from its four quarters.
template <class F>
double integrate(F&& f, double a, double b, double rel_tolerance) {
  const std::array<quadrature::Interval, 4> quarters = {quadrature::Interval{a, a + 0.25 * (b - a)},
                                                        {a + 0.25 * (b - a), a + 0.5 * (b - a)},
                                                        {a + 0.5 * (b - a), a + 0.75 * (b - a)},
                                                        {a + 0.75 * (b - a), b}};
  return quadrature::integrate_1d(f, quarters, rel_tolerance, 400);
}

// (1/π) ∫_T w(ω) (n_T·(p − y)) / r³ dA_y, with w(ω) ≤ w_max, by the graded cubature.
template <class W>
double kernel_cubature(const Point3& p, const Triangle& t, W&& w, double w_max) {
  if (!in_front(p, t)) return 0;
  const Vector3 n = t.normal();
  auto f = [&](const Point3& y) {
    const Vector3 d = y - p;
    const double r2 = length_squared(d);
    if (!(r2 > 0)) return 0.0;
    const double r = std::sqrt(r2);
    return w(d / r) * std::max(0.0, -dot(n, d)) / (r2 * r);
  };
  const double bound = triangle_solid_angle(p, t) * w_max;
  return graded(p, t, f, kRelTolerance * bound, 0) * kInvPi;
}

}  // namespace

double cylinder_triangle_factor(const Point3& p, const Vector3& axis, const Triangle& t) {
  return kernel_cubature(p, t, [&](const Vector3& w) { return length(cross(axis, w)) * kInvPi; }, kInvPi);
}

double receiver_triangle_cubature(const Receiver& r, const Triangle& t) {
  return kernel_cubature(r.point, t, [&](const Vector3& w) { return receiver_weight(r, w); }, 2 * kInvPi);
}

double receiver_triangle_factor(const Receiver& r, const Triangle& t) {
  if (r.kind == Receiver::Kind::Planar) return point_triangle_factor(r.point, r.normal, t);
  if (!in_front(r.point, t)) return 0;
  switch (r.kind) {
    case Receiver::Kind::Hemispherical:
      return std::max(0.0, 0.25 * (triangle_solid_angle(r.point, t) * kInvPi + point_boundary_factor(r.point, r.normal, t.v)));
    case Receiver::Kind::Spherical: return 0.25 * triangle_solid_angle(r.point, t) * kInvPi;
    case Receiver::Kind::Cylindrical: return cylinder_triangle_factor(r.point, r.normal, t);
    case Receiver::Kind::Semicylindrical:
      return std::max(0.0, cylinder_triangle_factor(r.point, r.normal, t) + kInvPi * point_boundary_factor(r.point, r.facing, t.v));
    case Receiver::Kind::Planar: break;
  }
  return 0;
}

Vector3 region_normal(const Receiver& r, const Vector3& source_normal) {
  return r.kind == Receiver::Kind::Planar ? r.normal : -source_normal;
}

double exact_visible_factor(const Receiver& r, const Triangle& source, const ExactVisibility& exact) {
  if (r.kind == Receiver::Kind::Planar) return exact.visible_factor(r.point, r.normal, source);
  const Vector3 n = source.normal();
  return receiver_region_factor(r, exact.visible_region(r.point, region_normal(r, n), source), n);
}

double receiver_region_factor(const Receiver& r, const ExactVisibility::VisibleRegion& region,
                              const Vector3& source_normal) {
  double sum = 0;
  auto at = [&](const Point2d& q) { return region.origin() + region.e1() * q[0] + region.e2() * q[1]; };
  for (const Loop2d& loop : region.loops()) {
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
      Triangle fan{{at(loop[0]), at(loop[k]), at(loop[k + 1])}};
      const double orientation = dot(fan.area_vector(), source_normal);
      if (orientation == 0) continue;
      if (orientation < 0) std::swap(fan.v[1], fan.v[2]);
      const double K = receiver_triangle_factor(r, fan);
      sum += orientation > 0 ? K : -K;
    }
  }
  return std::max(0.0, sum);
}

double receiver_by_planes(const Receiver& r, const std::function<double(const Vector3&)>& planar,
                          double rel_tolerance) {
  if (r.kind == Receiver::Kind::Planar) return planar(r.normal);
  const Vector3 a = r.normal;
  switch (r.kind) {
    case Receiver::Kind::Cylindrical: {
      const Vector3 u = perpendicular(a), v = cross(a, u);
      auto E = [&](double phi) { return planar(u * std::cos(phi) + v * std::sin(phi)); };
      return integrate(E, 0, 2 * kPi, rel_tolerance) / (2 * kPi);
    }
    case Receiver::Kind::Semicylindrical: {
      const Vector3 f = r.facing, v = cross(a, f);
      auto E = [&](double phi) { return planar(f * std::cos(phi) + v * std::sin(phi)); };
      return integrate(E, -kPi / 2, kPi / 2, rel_tolerance) / kPi;
    }
    case Receiver::Kind::Hemispherical: {
      const Vector3 u = perpendicular(a), v = cross(a, u);
      auto ring = [&](double beta) {  // ∫ E dφ over the normals at polar angle β from the pole
        const double s = std::sin(beta), c = std::cos(beta);
        auto E = [&](double phi) { return planar(a * c + (u * std::cos(phi) + v * std::sin(phi)) * s); };
        return integrate(E, 0, 2 * kPi, rel_tolerance) * s;
      };
      return integrate(ring, 0, kPi / 2, rel_tolerance) / (2 * kPi);
    }
    case Receiver::Kind::Spherical: {  // (1/4π) ∫ E(m) dΩ_m over every normal m
      const Vector3 a{0, 0, 1}, u{1, 0, 0}, v{0, 1, 0};
      auto ring = [&](double beta) {
        const double s = std::sin(beta), c = std::cos(beta);
        auto E = [&](double phi) { return planar(a * c + (u * std::cos(phi) + v * std::sin(phi)) * s); };
        return integrate(E, 0, 2 * kPi, rel_tolerance) * s;
      };
      return integrate(ring, 0, kPi, rel_tolerance) / (4 * kPi);
    }
    case Receiver::Kind::Planar: break;
  }
  return 0;
}

}  // namespace lambert
