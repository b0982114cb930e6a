// Exact point-to-polygon form factors and adaptive cubature of them over receiving triangles.
// See form_factor.h for the formulas and conventions.
#include "solver/form_factor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <type_traits>
#include <vector>

#include "solver/cubature.h"
#include "solver/spectrum.h"

namespace lambert {
namespace {

constexpr int kMaxClippedVertices = 20;

// atan(t)/t as a polynomial in z = t² (the Taylor series of atan to t²³), for 0 ≤ t ≤ 1/4: the
// truncation error is below t²⁴/25 ≤ 3·10⁻¹⁶ relative, as exact as std::atan2.
inline double atan_over_t(double z) {
  double p = -1.0 / 23;
  p = p * z + 1.0 / 21;
  p = p * z - 1.0 / 19;
  p = p * z + 1.0 / 17;
  p = p * z - 1.0 / 15;
  p = p * z + 1.0 / 13;
  p = p * z - 1.0 / 11;
  p = p * z + 1.0 / 9;
  p = p * z - 1.0 / 7;
  p = p * z + 1.0 / 5;
  p = p * z - 1.0 / 3;
  return 1 + z * p;
}

// The angle atan2(s, d) ∈ [0, π] between two vectors with |a × b| = s ≥ 0 and a · b = d, without
// atan2 and without branches (selects only, so that it vectorises in point_triangle_factors' lanes):
// folded onto t = min(s, |d|) / max(s, |d|) ∈ [0, 1] by symmetry, then reduced about the nearest of
// 0, tan(π/8), 1 to |u| ≤ tan(π/16) with atan(t) = atan(c) + atan(u), u = (t − c) / (1 + t c), where
// atan_over_t's series is exact to about 10⁻¹⁸ (tested against std::atan2 to 4 ulp).
inline double edge_angle(double s, double d) {
  constexpr double kTanPi8 = 0.41421356237309504880;             // tan(π/8) = √2 − 1
  constexpr double kLow = 0.19891236737965800691, kHigh = 0.66817863791929891999;  // tan(π/16), tan(3π/16)
  const double ad = std::abs(d);
  const bool swap = s > ad;
  const double num = swap ? ad : s, den = swap ? s : ad;
  const double t = den > 0 ? num / den : 0.0;
  const bool high = t > kHigh, mid = t > kLow;
  const double c = high ? 1.0 : (mid ? kTanPi8 : 0.0);
  const double base = high ? kPi / 4 : (mid ? kPi / 8 : 0.0);
  const double u = (t - c) / (1 + t * c);
  const double a = base + u * atan_over_t(u * u);  // atan(t), in [0, π/4]
  const double b = swap ? kPi / 2 - a : a;
  return d < 0 ? kPi - b : b;
}

// Lambert/Hottel contour sum for a polygon (given as vectors R_i from p) wholly in front of p's plane
// and counter-clockwise about its own front normal as seen from p. For that orientation each edge
// contributes γ_i n·c_i/|c_i| ≥ 0 to 2π F, with c_i = R_{i+1} × R_i and γ_i = atan2(|c_i|, R_i·R_{i+1})
// the angle the edge subtends. Edges seen under less than 14° (|c| ≤ R_i·R_{i+1}/4: all edges of all
// but nearby patches) use γ/|c| = atan_over_t(|c|²/(R_i·R_{i+1})²)/(R_i·R_{i+1}), which needs neither
// the square root nor the angle's reduction; wider ones edge_angle.
// An edge's term γ n·c/|c| for nc = n·c, c2 = |c|², d = R_i·R_{i+1}: the one expression of contour_sum
// and of point_triangle_factors' lanes, so both give the same value.
inline double series_edge_term(double nc, double c2, double d) {
  const double r = 1 / d;  // one division: two took 8 % more time in a batch of seven
  return nc * atan_over_t(c2 * r * r) * r;
}
inline double wide_edge_term(double nc, double c2, double d) {
  const double s = std::sqrt(c2);
  return s > 0 ? edge_angle(s, d) * nc / s : 0.0;  // s = 0: parallel (γ = 0), or p on the edge's line
}

// The sum over the closed boundary R(0), ..., R(count − 1), each vertex relative to the receiving point.
template <class At>
double contour_sum_of(const Vector3& n, int count, At&& R) {
  if (count <= 0) return 0;
  double sum = 0;
  const Vector3 first = R(0);
  Vector3 a = first;
  for (int i = 0; i < count; ++i) {
    const Vector3 b = i + 1 < count ? R(i + 1) : first;
    const Vector3 c = cross(b, a);
    const double c2 = length_squared(c), d = dot(a, b);
    if (d > 0 && 16 * c2 <= d * d) sum += series_edge_term(dot(n, c), c2, d);
    else sum += wide_edge_term(dot(n, c), c2, d);
    a = b;
  }
  return sum;
}

double contour_sum(const Vector3& n, const Vector3* R, int count) {
  return contour_sum_of(n, count, [R](int i) { return R[i]; });
}

}  // namespace

double point_polygon_factor(const Point3& p, const Vector3& n, std::span<const Point3> polygon) {
  const int count = static_cast<int>(polygon.size());
  if (count < 3 || count > kMaxClippedVertices - 4) return 0;

  // Only the front side emits: p must lie strictly in front of the polygon's plane.
  Vector3 newell;
  for (int i = 0; i < count; ++i) {
    const Point3& a = polygon[i];
    const Point3& b = polygon[(i + 1) % count];
    newell += Vector3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  if (dot(p - polygon[0], newell) <= 0) return 0;

  // Clip at p's horizon (Sutherland–Hodgman against the plane through p with normal n): the part of
  // the polygon below the horizon is invisible to a one-sided receiver.
  std::array<Vector3, kMaxClippedVertices> R;
  int clipped = 0;
  for (int i = 0; i < count; ++i) {
    const Vector3 a = polygon[i] - p;
    const Vector3 b = polygon[(i + 1) % count] - p;
    const double da = dot(a, n);
    const double db = dot(b, n);
    if (da >= 0) R[clipped++] = a;
    if ((da >= 0) != (db >= 0)) {
      const double t = da / (da - db);
      R[clipped++] = a + (b - a) * t;
    }
  }
  if (clipped < 3) return 0;
  return std::max(0.0, contour_sum(n, R.data(), clipped) / (2 * kPi));
}

double point_triangle_factor(const Point3& p, const Vector3& n, const Triangle& t) {
  // The common case without the general path's copies: a triangle wholly above p's horizon needs
  // no clipping (its Newell normal is twice its area vector).
  const Vector3 R[3] = {t.v[0] - p, t.v[1] - p, t.v[2] - p};
  if (dot(R[0], cross(t.v[1] - t.v[0], t.v[2] - t.v[0])) >= 0) return 0;  // p not in front
  if (dot(R[0], n) >= 0 && dot(R[1], n) >= 0 && dot(R[2], n) >= 0)
    return std::max(0.0, contour_sum(n, R, 3) / (2 * kPi));
  return point_polygon_factor(p, n, std::span<const Point3>(t.v.data(), 3));
}

Vector3 triangle_vector_factor(const Point3& p, const Triangle& t) {
  const Vector3 R[3] = {t.v[0] - p, t.v[1] - p, t.v[2] - p};
  if (dot(R[0], cross(t.v[1] - t.v[0], t.v[2] - t.v[0])) >= 0) return {};  // p not in front
  const double scale = 1 / (2 * kPi);
  return {contour_sum({1, 0, 0}, R, 3) * scale, contour_sum({0, 1, 0}, R, 3) * scale, contour_sum({0, 0, 1}, R, 3) * scale};
}

// Compiled twice, for AVX2 (4 lanes per instruction) and for the baseline x86-64 (2), and chosen at
// load time. Neither uses FMA ("avx2" does not enable it), so both round as point_triangle_factor does.
__attribute__((target_clones("avx2", "default"))) void point_triangle_factors(std::span<const Point3> points,
                                                                              const Vector3& n, const Triangle& t,
                                                                              std::span<double> out) {
  // Lanes of kLanes points in separate coordinate arrays, every branch of the common case written as
  // a select, so that the compiler vectorises the loops over lanes. The common case is
  // point_triangle_factor's: p in front of t and t wholly above p's horizon; the same arithmetic per
  // point (each edge's series or wide term, as contour_sum chooses), so the same value.
  constexpr int kLanes = 8;
  const Vector3 area = cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);
  for (std::size_t first = 0; first < points.size(); first += kLanes) {
    const int used = static_cast<int>(std::min<std::size_t>(kLanes, points.size() - first));
    double x[kLanes], y[kLanes], z[kLanes], sum[kLanes], above[kLanes];  // 1 or 0
    for (int l = 0; l < kLanes; ++l) {
      const Point3& p = points[first + std::min(l, used - 1)];  // unused lanes repeat the last point
      x[l] = p.x, y[l] = p.y, z[l] = p.z, above[l] = 1;
    }
    // Every edge's series term first, kept with what its wide term needs (nearly all lanes of far
    // points need nothing else); then, only for an edge that some lane sees under more than 14°,
    // that edge's wide term in every lane (a square root, two divisions and the angle's reduction),
    // selected where the series does not hold. The terms are summed in edge order, as contour_sum
    // does. (Computing both terms for every edge and lane made the batch slower than the calls one by
    // one; recomputing all three edges where one needed the wide term cost 44 % of the batches of
    // the cube room's final gather a second pass.)
    double term[3][kLanes], nc[3][kLanes], c2[3][kLanes], d[3][kLanes];
    double wide[3];  // per edge: 1 where some lane needs the wide term
    for (int k = 0; k < 3; ++k) {
      const Point3& A = t.v[k];
      const Point3& B = t.v[(k + 1) % 3];
      double any = 0;
      for (int l = 0; l < kLanes; ++l) {
        const double ax = A.x - x[l], ay = A.y - y[l], az = A.z - z[l];
        const double bx = B.x - x[l], by = B.y - y[l], bz = B.z - z[l];
        const double cx = by * az - bz * ay, cy = bz * ax - bx * az, cz = bx * ay - by * ax;  // c = b × a
        c2[k][l] = cx * cx + cy * cy + cz * cz, d[k][l] = ax * bx + ay * by + az * bz;
        nc[k][l] = n.x * cx + n.y * cy + n.z * cz;
        const bool good = (d[k][l] > 0) & (16 * c2[k][l] <= d[k][l] * d[k][l]);
        term[k][l] = series_edge_term(nc[k][l], c2[k][l], good ? d[k][l] : 1.0);
        any = good ? any : 1.0;
        above[l] = ax * n.x + ay * n.y + az * n.z >= 0 ? above[l] : 0.0;
      }
      wide[k] = any;
    }
    for (int k = 0; k < 3; ++k) {
      if (wide[k] == 0) continue;
      for (int l = 0; l < kLanes; ++l) {
        const bool good = (d[k][l] > 0) & (16 * c2[k][l] <= d[k][l] * d[k][l]);
        term[k][l] = good ? term[k][l] : wide_edge_term(nc[k][l], c2[k][l], d[k][l]);
      }
    }
    for (int l = 0; l < kLanes; ++l) sum[l] = ((0.0 + term[0][l]) + term[1][l]) + term[2][l];
    for (int l = 0; l < used; ++l) {
      const Point3& p = points[first + l];
      if (dot(t.v[0] - p, area) >= 0) out[first + l] = 0;  // p not in front
      else if (above[l] != 0) out[first + l] = std::max(0.0, sum[l] / (2 * kPi));
      else out[first + l] = point_triangle_factor(p, n, t);
    }
  }
}

// contour_sum_of's arithmetic edge by edge, in lanes over the edges: every edge's series term first
// (the compiler vectorises that loop), then the wide term for the edges that need it, and the terms
// summed in edge order, so the value is contour_sum_of's. The exact visible parts' loops (the final
// gather's shadows cut to a patch, five to eight edges) are its main use.
__attribute__((target_clones("avx2", "default"))) double point_boundary_factor(const Point3& p, const Vector3& n,
                                                                              std::span<const Point3> boundary) {
  constexpr int kMaxLanes = 32;
  const int count = static_cast<int>(boundary.size());
  if (count > kMaxLanes) return contour_sum_of(n, count, [&](int i) { return boundary[i] - p; }) / (2 * kPi);
  double x[kMaxLanes + 1], y[kMaxLanes + 1], z[kMaxLanes + 1];
  for (int i = 0; i < count; ++i) {
    const Vector3 R = boundary[i] - p;
    x[i] = R.x, y[i] = R.y, z[i] = R.z;
  }
  if (count > 0) x[count] = x[0], y[count] = y[0], z[count] = z[0];
  double term[kMaxLanes], nc[kMaxLanes], c2[kMaxLanes], d[kMaxLanes];
  double wide = 0;
  for (int i = 0; i < count; ++i) {
    const double ax = x[i], ay = y[i], az = z[i], bx = x[i + 1], by = y[i + 1], bz = z[i + 1];
    const double cx = by * az - bz * ay, cy = bz * ax - bx * az, cz = bx * ay - by * ax;  // c = b × a
    c2[i] = cx * cx + cy * cy + cz * cz, d[i] = ax * bx + ay * by + az * bz;
    nc[i] = n.x * cx + n.y * cy + n.z * cz;
    const bool good = (d[i] > 0) & (16 * c2[i] <= d[i] * d[i]);
    term[i] = series_edge_term(nc[i], c2[i], good ? d[i] : 1.0);
    wide = good ? wide : 1.0;
  }
  if (wide != 0)
    for (int i = 0; i < count; ++i)
      if (!(d[i] > 0 && 16 * c2[i] <= d[i] * d[i])) term[i] = wide_edge_term(nc[i], c2[i], d[i]);
  double sum = 0;
  for (int i = 0; i < count; ++i) sum += term[i];
  return sum / (2 * kPi);
}

double triangle_solid_angle(const Point3& p, const Triangle& t) {
  const Vector3 a = t.v[0] - p, b = t.v[1] - p, c = t.v[2] - p;
  const double la = length(a), lb = length(b), lc = length(c);
  const double numerator = std::abs(dot(a, cross(b, c)));
  const double denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
  return 2 * std::atan2(numerator, denominator);
}

namespace {

// Radon's 7-point rule, degree 5 (a = (6 - √15)/21, b = (6 + √15)/21).
constexpr double kSqrt15 = 3.872983346207417;
constexpr double kA = (6 - kSqrt15) / 21, kB = (6 + kSqrt15) / 21;
constexpr double kWa = (155 - kSqrt15) / 1200, kWb = (155 + kSqrt15) / 1200;
constexpr std::array<std::array<double, 3>, 7> kDeg5Points = {{{1.0 / 3, 1.0 / 3, 1.0 / 3},
                                                                {kA, kA, 1 - 2 * kA},
                                                                {kA, 1 - 2 * kA, kA},
                                                                {1 - 2 * kA, kA, kA},
                                                                {kB, kB, 1 - 2 * kB},
                                                                {kB, 1 - 2 * kB, kB},
                                                                {1 - 2 * kB, kB, kB}}};
constexpr std::array<double, 7> kDeg5Weights = {9.0 / 40, kWa, kWa, kWa, kWb, kWb, kWb};
static_assert(kDeg5Points.size() <= kMaxRuleSize);


}  // namespace

TriangleRule triangle_rule_degree5() { return {kDeg5Points.data(), kDeg5Weights.data(), 7}; }

namespace {

// area_form_factor for a receiver wholly in front of (or on) the source's plane.
double front_area_form_factor(const Triangle& receiver, const Triangle& source, const AreaFactorOptions& options) {
  const Vector3 n = receiver.normal();
  const Point3 cr = receiver.centroid(), cs = source.centroid();
  const double separation =
      distance(cr, cs) / (receiver.bounding_radius() + source.bounding_radius());
  // The batched kernel: its vectorised lanes serve every node but those whose horizon crosses the
  // source (which it hands to the point kernel).
  auto batch = [&](std::span<const Point3> points, std::span<double> values) {
    point_triangle_factors(points, n, source, values);
  };
  const double coarse = apply_rule(triangle_rule_degree5(), receiver, batch);
  // Well separated pairs: the integrand is smooth on the scale of the receiver and the degree-5 rule
  // is accurate far below the tolerance (measured in form_factor_test, "far field"). A pair wholly in
  // front of each other's planes has no horizon crossing the receiver, and its integrand is smooth
  // sooner: there the rule's error is below 2·10⁻⁶ from 3/4 of that separation on.
  if (separation > options.far_field_separation) return coarse;
  if (separation > 0.75 * options.far_field_separation) {
    const Vector3 ns = source.area_vector();
    bool clear = true;
    for (int k = 0; k < 3 && clear; ++k)
      clear = dot(source.v[k] - receiver.v[0], n) > 0 && dot(receiver.v[k] - source.v[0], ns) > 0;
    if (clear) return coarse;
  }
  const double tolerance = std::max(options.abs_tolerance * receiver.area(),
                                    options.rel_tolerance * std::abs(coarse));
  return integrate_adaptive(receiver, batch, coarse, tolerance, options.max_depth);
}

}  // namespace

double area_form_factor(const Triangle& receiver, const Triangle& source, const AreaFactorOptions& options) {
  // The kernel vanishes where the receiver lies behind the source's plane; where that plane cuts the
  // receiver, integrate over the part in front (the source's part behind the receiver's plane needs
  // nothing: every receiving point clips it at the same plane, its horizon).
  const FrontPart part = front_part(receiver, source.v[0], source.area_vector());
  if (!part.cut) return part.count > 0 ? front_area_form_factor(receiver, source, options) : 0.0;
  double sum = 0;
  for (int k = 0; k < part.count; ++k) sum += front_area_form_factor(part.pieces[k], source, options);
  return sum;
}

double exchange_area(const Triangle& a, const Triangle& b, const AreaFactorOptions& options) {
  auto radius2 = [](const Triangle& t) {  // the bounding radius, squared (the dense solver asks per pair)
    const Point3 c = t.centroid();
    return std::max({length_squared(t.v[0] - c), length_squared(t.v[1] - c), length_squared(t.v[2] - c)});
  };
  auto tie_key = [](const Triangle& t) {
    return std::tuple{t.area(), t.v[0].x, t.v[0].y, t.v[0].z, t.v[1].x, t.v[1].y, t.v[1].z, t.v[2].x, t.v[2].y, t.v[2].z};
  };
  const double ra = radius2(a), rb = radius2(b);
  const bool over_a = ra != rb ? ra < rb : tie_key(a) <= tie_key(b);
  return over_a ? area_form_factor(a, b, options) : area_form_factor(b, a, options);
}

}  // namespace lambert
