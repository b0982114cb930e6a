// The patch-size defaults and limits shared by both methods (radiosity.h). The solve itself is
// solver/pipeline/solve.cpp.
#include "solver/radiosity.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace lambert {

const char* stage_name(SolveStage stage) {
  switch (stage) {
    case SolveStage::Meshing: return "meshing";
    case SolveStage::Visibility: return "visibility";
    case SolveStage::Links: return "links";
    case SolveStage::Solve: return "solve";
    case SolveStage::Probes: return "probes";
  }
  return "solve";
}

const char* method_name(SolverMethod method) {
  switch (method) {
    case SolverMethod::Auto: return "auto";
    case SolverMethod::Dense: return "dense";
    case SolverMethod::Hierarchical: return "hierarchical";
  }
  return "auto";
}

double scene_area(const Scene& scene) {
  double total = 0;
  for (const Surface& s : scene.surfaces)
    for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) total += s.mesh.triangle(t).area();
  return total;
}

double default_max_patch_area(const Scene& scene) { return scene_area(scene) / 1200; }

double estimated_patch_count(const Scene& scene) {
  const double max_area = scene.meshing.max_patch_area_m2.value_or(default_max_patch_area(scene));
  double patches = 0;
  for (const Surface& s : scene.surfaces)
    for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t)
      patches += std::max(1.0, std::ceil(s.mesh.triangle(t).area() / max_area));
  return patches;
}

std::vector<Triangle> input_triangles(const Scene& scene) {
  std::vector<Triangle> out;
  for (const Surface& s : scene.surfaces)
    for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) out.push_back(s.mesh.triangle(t));
  return out;
}

std::vector<char> input_two_sided(const Scene& scene) {
  std::vector<char> out;
  for (const Surface& s : scene.surfaces)
    for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) out.push_back(t < s.two_sided.size() ? s.two_sided[t] : 0);
  return out;
}

std::size_t patch_limit(std::size_t solver_limit, const SolveControl& control) {
  return control.max_patches > 0 ? std::min(control.max_patches, solver_limit) : solver_limit;
}

void check_patch_count(double patches, bool estimate, std::size_t solver_limit, const SolveControl& control) {
  const std::size_t limit = patch_limit(solver_limit, control);
  // An estimate (total area / max area) is a lower bound up to rounding of the areas.
  if (!((estimate ? patches * (1 - 1e-9) : patches) > static_cast<double>(limit))) return;
  const std::string count =
      (estimate ? "at least " : "") + std::to_string(static_cast<std::size_t>(std::min(patches, 1e18)));
  if (limit == control.max_patches)
    throw SolveError("meshing gives " + count + " patches, more than " +
                     (control.max_patches_reason.empty()
                          ? "this server's limit of " + std::to_string(limit) + " (max_patches)"
                          : control.max_patches_reason) +
                     "; increase meshing.max_patch_area");
  throw SolveError("meshing gives " + count + " patches, more than this solver's limit of " + std::to_string(limit) +
                   "; increase meshing.max_patch_area (it is in the scene's units squared)");
}

}  // namespace lambert
