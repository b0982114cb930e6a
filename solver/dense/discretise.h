// The dense method's discretisation: the surfaces cut into patches of at most the patch size, split
// further where the direct light jumps (meshing.refine_direct) and, with meshing.adaptive, where the
// solved irradiance does.
#pragma once

#include <cstddef>
#include <vector>

#include "solver/radiosity.h"

namespace lambert {

// The dense solver keeps F in memory (8 N² bytes): it refuses what would not fit comfortably.
inline constexpr std::size_t kMaxDensePatches = 20000;

// The patches of `scene` at max_area, with meshing.refine_direct's splits (stats:
// direct_refinement_patches). Throws SolveError where the patch limit is exceeded, before meshing
// where the areas already tell.
std::vector<Patch> dense_patches(const Scene& scene, double max_area, const SolveControl& control, SolveStats& stats);

// Adaptive meshing (meshing.adaptive): the patches split where the solved irradiance differs from a
// neighbour's by more than 20 % of the pair's mean (a ratio of 1.1/0.9), down to 1/16 of
// meshing.max_patch_area.
std::vector<Patch> refine_where_irradiance_varies(const Solution& sol);

}  // namespace lambert
