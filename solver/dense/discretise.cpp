#include "solver/dense/discretise.h"

#include "mesh/mesh_ops.h"
#include "solver/patch_refinement.h"
#include "solver/visibility.h"

namespace lambert {
namespace {

// The surfaces cut into patches of at most max_area (mesh_ops.h, subdivide_to_max_area_with_parents).
std::vector<Patch> mesh_patches(const Scene& scene, double max_area) {
  std::vector<Patch> out;
  int first_input = 0;  // index of the surface's first input triangle over all surfaces
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const SubdividedMesh patches = subdivide_to_max_area_with_parents(scene.surfaces[s].mesh, max_area);
    for (std::size_t t = 0; t < patches.mesh.triangles.size(); ++t) {
      Patch p;
      p.surface = static_cast<int>(s);
      p.input_triangle = first_input + patches.parent[t];
      p.triangle = patches.mesh.triangle(t);
      p.area_m2 = p.triangle.area();
      if (!(p.area_m2 > 0)) continue;  // degenerate input was rejected by the decoder; splits are not
      p.normal = p.triangle.normal();
      out.push_back(p);
    }
    first_input += static_cast<int>(scene.surfaces[s].mesh.triangles.size());
  }
  return out;
}

// Direct-light meshing (meshing.refine_direct): before the solve, split where the direct irradiance
// jumps between neighbours by more than kDirectRatio (where_varies), in up to two rounds, down to
// 1/16 of max_area. This puts small patches in penumbrae and along shadow edges before any factor is
// formed (meshing.adaptive solves the whole scene again for each round). The ratio is a jump, not a
// gradient: smooth fall-off (a wall below a ceiling light) stays coarse (patch_refinement.h).
// A round that would exceed `limit` patches is not taken.
std::vector<Patch> refine_where_direct_light_varies(const Scene& scene, std::vector<Patch> patches, double max_area,
                                                    std::size_t limit, const SolveControl& control) {
  if (!has_direct_light(scene)) return patches;
  const Visibility vis(input_triangles(scene));
  for (int round = 0; round < 2; ++round) {
    std::vector<char> marked = where_varies(patches, direct_irradiance_totals(scene, patches, vis, control), kDirectRatio);
    if (round == 0) mark_near_probes(patches, scene.probes, marked);
    std::vector<Patch> refined = split_marked(patches, marked, max_area / 16);
    if (refined.size() == patches.size() || refined.size() > limit) break;
    patches = std::move(refined);
  }
  return patches;
}

}  // namespace

std::vector<Patch> dense_patches(const Scene& scene, double max_area, const SolveControl& control, SolveStats& stats) {
  // Every patch has an area <= max_area, so total area / max_area bounds the patch count from below:
  // a limit that is sure to be exceeded is reported before meshing, which a tiny max_patch_area
  // would otherwise drive out of memory.
  check_patch_count(scene_area(scene) / max_area, true, kMaxDensePatches, control);
  std::vector<Patch> patches = mesh_patches(scene, max_area);
  const std::size_t base = patches.size();
  if (scene.meshing.refine_direct)
    patches = refine_where_direct_light_varies(scene, std::move(patches), max_area,
                                               patch_limit(kMaxDensePatches, control), control);
  stats.direct_refinement_patches = patches.size() - base;
  return patches;
}

std::vector<Patch> refine_where_irradiance_varies(const Solution& sol) {
  const std::size_t N = sol.patches.size(), W = sol.wavelengths();
  std::vector<double> q(N, 0.0);
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t w = 0; w < W; ++w) q[i] += sol.grid.weight_nm[w] * sol.irradiance[i * W + w];
  return split_marked(sol.patches, where_varies(sol.patches, q, 1.1 / 0.9), sol.stats.max_patch_area_m2 / 16);
}

}  // namespace lambert
