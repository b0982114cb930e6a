// Helpers of the hierarchical method's tests (hierarchical_test.cpp, faceted_spheres_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "solver/cubature.h"
#include "solver/radiosity.h"

namespace lambert::test {

inline Solution solve_with(Scene scene, SolverMethod method) {
  scene.solver.method = method;
  return solve(scene);
}

// The mean of f over a patch by the degree-5 rule on 64 similar parts (kernels that are
// log-singular at an edge, or kinked at a shadow's edge, need the parts).
template <class F>
double patch_mean_by_parts(const Patch& P, F f) {
  std::vector<Triangle> parts = {P.triangle};
  for (int level = 0; level < 3; ++level) {
    std::vector<Triangle> finer;
    for (const Triangle& t : parts)
      for (const Triangle& c : split4(t)) finer.push_back(c);
    parts.swap(finer);
  }
  const TriangleRule rule = triangle_rule_degree5();
  double sum = 0;
  for (const Triangle& t : parts) sum += apply_rule(rule, t, f);
  return sum / P.area_m2;
}

// R1: every surface emits M = 1 with the same ρ in a closed enclosure, so B = M/(1 − ρ) on every
// patch (to 0.1 %), and the energy certificate balances (to 1e-3).
inline void expect_furnace(const Solution& sol, double rho) {
  const double expected = 1 / (1 - rho);
  double worst = 0;
  for (double B : sol.radiosity) worst = std::max(worst, std::abs(B - expected) / expected);
  EXPECT_LT(worst, 1e-3) << "rho=" << rho;
  EXPECT_LT(std::abs(sol.stats.relative_imbalance), 1e-3) << "rho=" << rho;
}

}  // namespace lambert::test
