#include "solver/thermal/radiant.h"

#include <algorithm>
#include <chrono>

#include "solver/pipeline/geometric.h"
#include "solver/pipeline/pipeline.h"
#include "solver/radiosity.h"

namespace lambert {
namespace {

PatchFactors collect_patch_factors(const TransportOperator& op) {
  std::size_t count = 0;
  op.visit_factors([&](std::size_t, std::size_t, double) { ++count; });
  if (count > kMaxPatchFactors)
    throw SolveError("the patch-to-patch matrix has " + std::to_string(count) + " non-zero factors over " +
                     std::to_string(op.size()) + " patches, more than the limit of " +
                     std::to_string(kMaxPatchFactors) + "; ask for the surface matrix only, or set a larger "
                     "meshing.max_patch_area");
  PatchFactors out;
  out.i.reserve(count), out.j.reserve(count), out.F.reserve(count);
  op.visit_factors([&](std::size_t i, std::size_t j, double F) {
    out.i.push_back(static_cast<std::uint32_t>(i));
    out.j.push_back(static_cast<std::uint32_t>(j));
    out.F.push_back(F);
  });
  return out;
}

}  // namespace

bool wants_radiant_exchange(const Scene& scene) {
  return scene.output.view_factors ||
         std::any_of(scene.surfaces.begin(), scene.surfaces.end(), [](const Surface& s) { return s.thermal.has_value(); });
}

RadiantExchange radiant_exchange(const Scene& scene, const SurfaceGroups& groups, const RadiantOptions& options,
                                 const SolveControl& control) {
  GeometricOperator geometric = build_geometric_operator(scene, control);
  const TransportOperator& op = *geometric.op;
  RadiantExchange out;
  out.groups = groups;
  out.factors = surface_view_factors(op, groups);
  out.geometry_hash = geometry_hash(scene, groups);
  out.patch_group = patch_groups(op, groups);
  if (options.patch_factors) out.patch_factors = collect_patch_factors(op);
  const auto t0 = std::chrono::steady_clock::now();
  enter_stage(control, SolveStage::Solve);
  if (!options.total_exchange_emissivity.empty())
    out.total_exchange = total_exchange_factors(op, groups, out.factors, options.total_exchange_emissivity, control);
  if (options.thermal) {
    enter_stage(control, SolveStage::Probes);
    out.thermal = grey_exchange(geometric.scene(), op, groups, control);
  }
  out.stats = geometric.stats;
  out.stats.time_solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.stats.time_total_s += out.stats.time_solve_s;
  if (out.thermal) {
    out.stats.iterations = out.thermal->iterations;
    out.stats.residual = out.thermal->residual;
  }
  out.patches = std::move(geometric.patches);
  out.warnings = std::move(geometric.warnings);
  out.warnings.insert(out.warnings.end(), out.factors.warnings.begin(), out.factors.warnings.end());
  return out;
}

}  // namespace lambert
