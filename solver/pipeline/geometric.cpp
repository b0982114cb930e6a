#include "solver/pipeline/geometric.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "solver/dense/dense_operator.h"
#include "solver/dense/discretise.h"
#include "solver/hierarchical/discretise.h"
#include "solver/pipeline/pipeline.h"
#include "solver/stopwatch.h"

namespace lambert {
namespace {

using Clock = std::chrono::steady_clock;

// Auto takes the dense method wherever it can hold the patches (its factors are exact and stored:
// the patch matrix is read off them), the hierarchical one beyond.
SolverMethod geometric_method(const Scene& scene) {
  if (scene.solver.method != SolverMethod::Auto) return scene.solver.method;
  return estimated_patch_count(scene) <= static_cast<double>(kMaxDensePatches) ? SolverMethod::Dense
                                                                                : SolverMethod::Hierarchical;
}

std::unique_ptr<TransportOperator> discretise(const Scene& prepared, const SolveControl& control, SolveStats& stats) {
  if (geometric_method(prepared) == SolverMethod::Hierarchical) return hierarchical::discretise(prepared, control, stats);
  const double max_area = prepared.meshing.max_patch_area_m2.value_or(default_max_patch_area(prepared));
  stats.max_patch_area_m2 = max_area;
  std::vector<Patch> patches = dense_patches(prepared, max_area, control, stats);
  check_patch_count(static_cast<double>(patches.size()), false, kMaxDensePatches, control);
  control.check_cancel();
  enter_stage(control, SolveStage::Visibility);
  return std::make_unique<DenseOperator>(prepared, std::move(patches), stats);
}

}  // namespace

GeometricOperator build_geometric_operator(const Scene& scene, const SolveControl& control) {
  const auto t_start = Clock::now();
  GeometricOperator out;
  enter_stage(control, SolveStage::Meshing);
  out.prepared = std::make_unique<PreparedScene>(scene, control, false);
  std::unique_ptr<TransportOperator> op = discretise(out.prepared->scene(), control, out.stats);
  out.stats.patches = op->size();
  out.stats.time_meshing_s = seconds_since(t_start);
  const auto t_build = Clock::now();
  enter_stage(control, SolveStage::Links);
  op->build_geometric(control);
  out.stats.time_form_factors_s = seconds_since(t_build);
  op->report(out.stats);
  // The preparation's warnings and stats, and the patches where the given scene lies.
  Solution placed;
  placed.patches = op->patches();
  placed.warnings = scene.warnings;
  placed.stats = out.stats;
  out.prepared->finish(placed);
  out.patches = std::move(placed.patches);
  out.warnings = std::move(placed.warnings);
  out.stats = placed.stats;
  out.op = std::move(op);
  out.stats.time_total_s = seconds_since(t_start);
  return out;
}

}  // namespace lambert
