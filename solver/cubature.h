// Adaptive cubature over a triangle for bounded integrands that are smooth except near a few
// points or edges (touching patches, the foot of a nearby point light). Measure: area (m²).
#pragma once

#include <array>
#include <cmath>

#include "mesh/geometry.h"

namespace lambert {

// Fixed rule: barycentric nodes and weights summing to 1 (fraction of the triangle's area).
struct TriangleRule {
  const std::array<double, 3>* nodes;
  const double* weights;
  int size;
};
TriangleRule triangle_rule_degree5();  // 7 points (Radon), exact for quintics

template <class F>
double apply_rule(const TriangleRule& rule, const Triangle& t, F&& f) {
  double sum = 0;
  for (int q = 0; q < rule.size; ++q) {
    const auto& w = rule.nodes[q];
    sum += rule.weights[q] * f(barycentric(t.v[0], t.v[1], t.v[2], w[0], w[1], w[2]));
  }
  return sum * t.area();
}

// Midpoint split into four similar triangles (orientation preserved).
inline std::array<Triangle, 4> split4(const Triangle& t) {
  const Point3 m01 = barycentric(t.v[0], t.v[1], t.v[2], 0.5, 0.5, 0);
  const Point3 m12 = barycentric(t.v[0], t.v[1], t.v[2], 0, 0.5, 0.5);
  const Point3 m20 = barycentric(t.v[0], t.v[1], t.v[2], 0.5, 0, 0.5);
  return {Triangle{{t.v[0], m01, m20}}, Triangle{{m01, t.v[1], m12}}, Triangle{{m20, m12, t.v[2]}},
          Triangle{{m01, m12, m20}}};
}

// ∫_t f dA by the degree-5 rule, refined 1:4 where the children's sum differs from the parent's
// estimate by more than the tolerance (halved at each level). `coarse` is the parent's estimate.
template <class F>
double integrate_adaptive(const Triangle& t, F&& f, double coarse, double abs_tolerance, int max_depth) {
  const TriangleRule rule = triangle_rule_degree5();
  const auto children = split4(t);
  std::array<double, 4> fine;
  double fine_sum = 0;
  for (int c = 0; c < 4; ++c) fine_sum += fine[c] = apply_rule(rule, children[c], f);
  if (max_depth <= 0 || std::abs(fine_sum - coarse) <= abs_tolerance) return fine_sum;
  double sum = 0;
  for (int c = 0; c < 4; ++c)
    sum += integrate_adaptive(children[c], f, fine[c], abs_tolerance / 2, max_depth - 1);
  return sum;
}

}  // namespace lambert
