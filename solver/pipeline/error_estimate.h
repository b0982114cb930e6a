// The discretisation error a result states (output.error_estimate, SPEC §5 "stats"): the scene is
// solved a second time on patches four times larger (edges twice as long), by the same method, and
// the change between the two levels is reported for what a user reads: each surface's mean
// irradiance and each probe point's irradiance.
//
// Why the change bounds the error: with e(h) = C h^p + o(h^p) for patch size h and order p ≥ 1, the
// change between the levels is e(2h) − e(h) = (2^p − 1) e(h): the fine level's own error for p = 1
// and three times it for p = 2 (Richardson). Piecewise-constant radiosity converges with p = 1 at
// points and about p = 2 in averages. What it cannot see: errors that do not shrink with the patches
// (the curved surface a tessellation stands for; the rays' noise in visibility estimates, which does
// not scale with h, and errors below the quadrature tolerances, 1e-5 relative). `lambert bench` shows
// the estimate beside the exact error on its reference scenes (docs/BENCHMARKS.md).
#pragma once

#include <functional>

#include "solver/radiosity.h"

namespace lambert {

// The coarser level's scene: patches four times larger, the same method as `fine` ran, and the
// solve's outputs that the estimate does not read turned off. A hierarchical solve's link accuracy is
// loosened by the same factor of four (its link error falls with the element area as its oracle's
// bound does).
Scene coarser_scene(const Scene& scene, const SolveStats& fine);

// Fills fine.stats.error_estimate from a solve of coarser_scene(scene, fine.stats) by `solve_coarse`.
void estimate_discretisation_error(const Scene& scene, Solution& fine,
                                   const std::function<Solution(const Scene&)>& solve_coarse);

}  // namespace lambert
