// Adaptive cubature over a triangle for bounded integrands that are smooth except near a few
// points or edges (touching patches, the foot of a nearby point light). Measure: area (m²).
#pragma once

#include <array>
#include <cmath>
#include <span>
#include <type_traits>

#include "mesh/geometry.h"

namespace lambert {

// Fixed rule: barycentric nodes and weights summing to 1 (fraction of the triangle's area).
struct TriangleRule {
  const std::array<double, 3>* nodes;
  const double* weights;
  int size;
};
TriangleRule triangle_rule_degree5();  // 7 points (Radon), exact for quintics

inline constexpr int kMaxRuleSize = 7;

// ∫_t f dA by the rule. f is either a point function, double(const Point3&), or a batch function,
// void(std::span<const Point3> nodes, std::span<double> values), which evaluates every node in one
// call (point_triangle_factors: several times faster than one call per node).
template <class F>
double apply_rule(const TriangleRule& rule, const Triangle& t, F&& f) {
  double sum = 0;
  if constexpr (std::is_invocable_v<F&, std::span<const Point3>, std::span<double>>) {
    std::array<Point3, kMaxRuleSize> nodes;
    std::array<double, kMaxRuleSize> values;
    for (int q = 0; q < rule.size; ++q) {
      const auto& w = rule.nodes[q];
      nodes[q] = barycentric(t.v[0], t.v[1], t.v[2], w[0], w[1], w[2]);
    }
    f(std::span<const Point3>(nodes.data(), rule.size), std::span<double>(values.data(), rule.size));
    for (int q = 0; q < rule.size; ++q) sum += rule.weights[q] * values[q];
  } else {
    for (int q = 0; q < rule.size; ++q) {
      const auto& w = rule.nodes[q];
      sum += rule.weights[q] * f(barycentric(t.v[0], t.v[1], t.v[2], w[0], w[1], w[2]));
    }
  }
  return sum * t.area();
}

// Midpoint split into four similar triangles (orientation preserved).
inline std::array<Triangle, 4> split4(const Triangle& t) {
  const Point3 m01 = midpoint(t.v[0], t.v[1]), m12 = midpoint(t.v[1], t.v[2]), m20 = midpoint(t.v[2], t.v[0]);
  return {Triangle{{t.v[0], m01, m20}}, Triangle{{m01, t.v[1], m12}}, Triangle{{m20, m12, t.v[2]}},
          Triangle{{m01, m12, m20}}};
}

// Bisection at the midpoint of the longest edge (orientation preserved): the split for elongated
// triangles, whose 1:4 children would be as elongated as they are.
inline std::array<Triangle, 2> split2(const Triangle& t) {
  int e = 0;  // the longest edge runs from v[e] to v[e+1]
  double longest = -1;
  for (int k = 0; k < 3; ++k) {
    const double len = length_squared(t.v[(k + 1) % 3] - t.v[k]);
    if (len > longest) longest = len, e = k;
  }
  const Point3 &a = t.v[e], &b = t.v[(e + 1) % 3], &c = t.v[(e + 2) % 3];
  const Point3 m = midpoint(a, b);
  return {Triangle{{a, m, c}}, Triangle{{m, b, c}}};
}

// The part of triangle t strictly in front of the plane through o with normal m (dot(x − o, m) > 0),
// as 0, 1 or 2 triangles (a triangle, or a quadrilateral split along a diagonal), orientation
// preserved. `cut` tells whether the plane crosses t's interior; vertices within 1e-12 of t's size
// of the plane count as lying on it (t then is not cut). Used where an integrand over t vanishes
// behind the plane: the kink along the crossing is one that a fixed cubature rule does not resolve at
// any distance (form_factor_test, "PairsWhosePlanesCutEachOther"), so the front part is integrated.
struct FrontPart {
  std::array<Triangle, 2> pieces{};
  int count = 0;
  bool cut = false;
};
inline FrontPart front_part(const Triangle& t, const Point3& o, const Vector3& m) {
  FrontPart out;
  double h[3];
  const double tolerance = 1e-12 * length(m) * t.max_edge_length();
  int front = 0, behind = 0;
  for (int k = 0; k < 3; ++k) {
    h[k] = dot(t.v[k] - o, m);
    if (std::abs(h[k]) <= tolerance) h[k] = 0;
    front += h[k] > 0;
    behind += h[k] < 0;
  }
  if (front == 0) return out;
  if (behind == 0) {
    out.pieces[0] = t;
    out.count = 1;
    return out;
  }
  std::array<Point3, 4> poly;  // Sutherland–Hodgman against one plane: at most 4 vertices
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3;
    if (h[k] >= 0) poly[n++] = t.v[k];
    if ((h[k] > 0 && h[j] < 0) || (h[k] < 0 && h[j] > 0)) poly[n++] = t.v[k] + (t.v[j] - t.v[k]) * (h[k] / (h[k] - h[j]));
  }
  out.cut = true;
  for (int k = 1; k + 1 < n; ++k) out.pieces[out.count++] = Triangle{{poly[0], poly[k], poly[k + 1]}};
  return out;
}

// front_part(t, o, m).cut without the pieces: whether vertices lie on both sides, beyond the same
// tolerance (only evaluated where the signs differ). For the pair tests of every link and leaf link.
inline bool plane_cuts(const Triangle& t, const Point3& o, const Vector3& m) {
  const double h[3] = {dot(t.v[0] - o, m), dot(t.v[1] - o, m), dot(t.v[2] - o, m)};
  const double highest = std::max({h[0], h[1], h[2]}), lowest = std::min({h[0], h[1], h[2]});
  if (!(highest > 0 && lowest < 0)) return false;
  const double tolerance = 1e-12 * length(m) * t.max_edge_length();
  return highest > tolerance && lowest < -tolerance;
}

// Whether a triangle is elongated enough (longest edge over height above 4) that bisection serves
// it better than the 1:4 split.
inline bool is_elongated(const Triangle& t) {
  const double longest = t.max_edge_length();
  return longest * longest > 8 * t.area();  // height = 2·area/longest < longest/4
}

namespace detail {
// `budget` counts half levels: a bisection spends one, a 1:4 split two (it halves the size in both
// directions where bisection halves it in one).
template <class F>
double integrate_adaptive(const Triangle& t, F& f, double coarse, double abs_tolerance, int budget) {
  const TriangleRule rule = triangle_rule_degree5();
  if (is_elongated(t)) {
    const auto children = split2(t);
    const double fine[2] = {apply_rule(rule, children[0], f), apply_rule(rule, children[1], f)};
    const double fine_sum = fine[0] + fine[1];
    if (budget <= 0 || std::abs(fine_sum - coarse) <= abs_tolerance) return fine_sum;
    return integrate_adaptive(children[0], f, fine[0], abs_tolerance / 2, budget - 1) +
           integrate_adaptive(children[1], f, fine[1], abs_tolerance / 2, budget - 1);
  }
  const auto children = split4(t);
  std::array<double, 4> fine;
  double fine_sum = 0;
  for (int c = 0; c < 4; ++c) fine_sum += fine[c] = apply_rule(rule, children[c], f);
  if (budget <= 1 || std::abs(fine_sum - coarse) <= abs_tolerance) return fine_sum;
  double sum = 0;
  for (int c = 0; c < 4; ++c) sum += integrate_adaptive(children[c], f, fine[c], abs_tolerance / 2, budget - 2);
  return sum;
}
}  // namespace detail

// ∫_t f dA by the degree-5 rule, refined where the children's sum differs from the parent's estimate
// by more than the tolerance (halved at each level): 1:4 for well-shaped triangles, bisection of the
// longest edge for elongated ones (a sliver's error comes from its length, and its 1:4 children
// would be slivers too). `coarse` is the parent's estimate; at most max_depth levels of 1:4 splits
// (or twice as many bisections).
template <class F>
double integrate_adaptive(const Triangle& t, F&& f, double coarse, double abs_tolerance, int max_depth) {
  return detail::integrate_adaptive(t, f, coarse, abs_tolerance, 2 * max_depth);
}

}  // namespace lambert
