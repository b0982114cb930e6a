// solve(): the scene prepared, the method chosen, and the pipeline run with the method's operator.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "solver/dense/dense_operator.h"
#include "solver/dense/discretise.h"
#include "solver/hierarchical/discretise.h"
#include "solver/pipeline/daylight.h"
#include "solver/pipeline/error_estimate.h"
#include "solver/pipeline/pipeline.h"
#include "solver/pipeline/prepare.h"
#include "solver/radiosity.h"
#include "solver/stopwatch.h"
#include "solver/thermal/radiant.h"

namespace lambert {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kAdaptiveRounds = 2;

// The dense method on `premeshed` patches, or on the scene's own meshing.
Solution solve_dense(const Scene& scene, const SolveControl& control, const std::vector<Patch>* premeshed) {
  const auto t_start = Clock::now();
  SolveStats stats;
  const double max_area = scene.meshing.max_patch_area_m2.value_or(default_max_patch_area(scene));
  stats.max_patch_area_m2 = max_area;
  std::vector<Patch> patches = premeshed ? *premeshed : dense_patches(scene, max_area, control, stats);
  check_patch_count(static_cast<double>(patches.size()), false, kMaxDensePatches, control);
  stats.time_meshing_s = seconds_since(t_start);
  control.check_cancel();
  enter_stage(control, SolveStage::Visibility);
  DenseOperator op(scene, std::move(patches), stats);
  return run_pipeline(scene, op, stats, control, t_start);
}

// The hierarchical method: its element forest and operator, and the pipeline.
Solution solve_hierarchical(const Scene& scene, const SolveControl& control) {
  const auto t_start = Clock::now();
  SolveStats stats;
  auto op = hierarchical::discretise(scene, control, stats);
  control.check_cancel();
  return run_pipeline(scene, *op, stats, control, t_start);
}

// Adaptive meshing (meshing.adaptive): solve, split the patches where the irradiance jumps between
// neighbours, solve again (at most kAdaptiveRounds times). Each pass reports progress in its share.
Solution solve_dense_adaptive(const Scene& scene, const SolveControl& control) {
  const auto t_start = Clock::now();
  auto pass_control = [&](int pass) {
    SolveControl c = control;
    if (control.progress)
      c.progress = [&control, pass](double f) { control.progress((pass + f) / (kAdaptiveRounds + 1)); };
    return c;
  };
  Solution sol = solve_dense(scene, pass_control(0), nullptr);
  for (int round = 1; round <= kAdaptiveRounds; ++round) {
    std::vector<Patch> refined = refine_where_irradiance_varies(sol);
    if (refined.size() == sol.patches.size()) break;
    const std::size_t direct_refinement = sol.stats.direct_refinement_patches;  // of the first pass
    sol = solve_dense(scene, pass_control(round), &refined);
    sol.stats.dense.adaptive_rounds = round;
    sol.stats.direct_refinement_patches = direct_refinement;
  }
  sol.stats.time_total_s = seconds_since(t_start);
  if (control.progress) control.progress(1.0);
  return sol;
}

Solution solve_method(const Scene& scene, const SolveControl& control) {
  // Method selection (scene.h SolverMethod): Auto by the estimated patch count.
  SolverMethod method = scene.solver.method;
  if (method == SolverMethod::Auto)
    method = estimated_patch_count(scene) <= kDenseAutoPatches ? SolverMethod::Dense : SolverMethod::Hierarchical;
  if (method == SolverMethod::Hierarchical) {
    Solution sol = solve_hierarchical(scene, control);
    if (scene.meshing.adaptive)
      sol.warnings.push_back("meshing.adaptive applies to the dense solver only; the hierarchical method "
                             "refines its own links");
    return sol;
  }
  return scene.meshing.adaptive ? solve_dense_adaptive(scene, control) : solve_dense(scene, control, nullptr);
}

}  // namespace

// The view factors and radiant exchange (output.view_factors, "thermal" surfaces; first, so that a
// scene they cannot serve fails at once), then the light, each reporting its progress in its half.
Solution solve(const Scene& scene, const SolveControl& control) {
  const bool radiant = wants_radiant_exchange(scene);
  auto half = [&](double from) {
    SolveControl c = control;
    if (radiant && control.progress) c.progress = [&control, from](double f) { control.progress(from + f / 2); };
    return c;
  };
  std::shared_ptr<RadiantExchange> exchange;
  if (radiant) {
    RadiantOptions options;
    options.thermal = std::any_of(scene.surfaces.begin(), scene.surfaces.end(),
                                  [](const Surface& s) { return s.thermal.has_value(); });
    exchange = std::make_shared<RadiantExchange>(
        radiant_exchange(scene, SurfaceGroups::each_surface(scene), options, half(0)));
  }
  const SolveControl light_control = half(0.5);
  enter_stage(control, SolveStage::Meshing);
  const PreparedScene prepared(scene, light_control);
  Solution sol = solve_method(prepared.scene(), light_control);
  if (scene.output.error_estimate) {
    SolveControl coarse_control = light_control;
    coarse_control.progress = nullptr;
    estimate_discretisation_error(prepared.scene(), sol,
                                  [&](const Scene& coarse) { return solve_method(coarse, coarse_control); });
  }
  measure_sky_components(prepared.scene(), sol, control);
  prepared.finish(sol);
  if (exchange) {
    sol.warnings.insert(sol.warnings.end(), exchange->factors.warnings.begin(), exchange->factors.warnings.end());
    sol.radiant = std::move(exchange);
  }
  return sol;
}

}  // namespace lambert
