#include "solver/hierarchical/discretise.h"

#include <chrono>

#include "solver/patch_refinement.h"
#include "solver/pipeline/pipeline.h"
#include "solver/visibility.h"

namespace lambert::hierarchical {

std::unique_ptr<HierarchicalOperator> discretise(const Scene& scene, const SolveControl& control, SolveStats& stats) {
  const auto t_start = std::chrono::steady_clock::now();
  const double max_area = scene.meshing.max_patch_area_m2.value_or(default_max_patch_area(scene));
  stats.max_patch_area_m2 = max_area;
  check_patch_count(scene_area(scene) / max_area, true, kMaxPatches, control);
  std::set<TriangleKey> split_further;
  ElementForest forest = build_forest(scene, max_area, split_further);
  // meshing.refine_direct, as in the dense method (patch_refinement.h): leaves where the direct light
  // jumps between neighbours, or next to a probe point, are split, in up to two rounds; a round that
  // would pass the patch limit is not taken.
  if (scene.meshing.refine_direct && has_direct_light(scene)) {
    const std::size_t base = forest.leaves.size();
    const Visibility roots_vis(forest.root_triangles());
    for (int round = 0; round < 2; ++round) {
      const std::vector<Patch> patches = forest.leaf_patches();
      std::vector<char> marked =
          where_varies(patches, direct_irradiance_totals(scene, patches, roots_vis, control), kDirectRatio);
      if (round == 0) mark_near_probes(patches, scene.probes, marked);
      std::size_t added = 0;
      for (std::size_t i = 0; i < patches.size(); ++i) added += marked[i] && patches[i].area_m2 / 4 >= max_area / 16 ? 3 : 0;
      if (added == 0 || patches.size() + added > patch_limit(kMaxPatches, control)) break;
      for (std::size_t i = 0; i < patches.size(); ++i)
        if (marked[i]) split_further.insert(triangle_key(patches[i].triangle));
      forest = build_forest(scene, max_area, split_further);
    }
    stats.direct_refinement_patches = forest.leaves.size() - base;
  }
  check_patch_count(static_cast<double>(forest.leaves.size()), false, kMaxPatches, control);
  stats.time_meshing_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  control.check_cancel();
  enter_stage(control, SolveStage::Visibility);
  return std::make_unique<HierarchicalOperator>(scene, std::move(forest), stats);
}

}  // namespace lambert::hierarchical
