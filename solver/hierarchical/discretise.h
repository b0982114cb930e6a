// The hierarchical method's discretisation: the element forest at the patch size, split once more
// where the direct light jumps between neighbouring leaves or a probe point stands near
// (meshing.refine_direct), and the operator over it.
#pragma once

#include <cstddef>
#include <memory>

#include "solver/hierarchical/hierarchical_operator.h"

namespace lambert::hierarchical {

// The method's own patch limit. Elements, links and spectra take 2.5–7 KB per patch at one
// wavelength (docs/BENCHMARKS.md: 4.9 GB at 1.9 M patches of the office furnace, 7.2 GB at 0.98 M
// patches of faceted spheres, one root each), so this is 5–14 GB.
inline constexpr std::size_t kMaxPatches = 2'000'000;

// Throws SolveError where the patch limit would be exceeded, before the forest is allocated where the
// areas already tell. Sets stats.max_patch_area_m2 and stats.direct_refinement_patches.
std::unique_ptr<HierarchicalOperator> discretise(const Scene& scene, const SolveControl& control, SolveStats& stats);

}  // namespace lambert::hierarchical
