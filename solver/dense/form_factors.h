// The dense method's factors: every pair of patches that can see each other, once per unordered pair,
//
//   G_ij = A_i F_ij = G_ji = exchange_area(i, j) × (kernel-weighted visible fraction)
//
// from the exact kernel integrated over the smaller patch of the pair (solver/form_factor.h) times
// the fraction of rays between the two patches' stratified samples that arrive, weighted by the
// differential kernel (solver/patch_refinement.h, patch_visible_fractions). Pairs that no occluder
// plane separates (solver/occluder_planes.h) are wholly visible and take no rays.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "solver/occluder_planes.h"
#include "solver/radiosity.h"
#include "solver/visibility.h"
#include "solver/visible_fraction.h"

namespace lambert {

struct DenseFactors {
  std::vector<double> F;  // row-major N×N, F_ij = G_ij / A_i
  // Per patch: whether a link of its row needed rays (its row sum is then an estimate).
  std::unique_ptr<std::atomic<char>[]> row_traced;
  std::size_t links = 0;        // pairs with a factor (each unordered pair once)
  std::size_t links_clear = 0;  // of which the occluder planes proved wholly visible
  std::uint64_t link_rays = 0;
  double link_ray_thread_s = 0;  // thread time spent on the rays, summed over threads
};

// Patches inside closed solids (hemisphere Enclosed) take no factor. `sides`: each patch's sides of
// the occluder planes (empty where the planes cannot serve). Progress in [0.1, 0.85] of the solve.
DenseFactors form_dense_factors(const std::vector<Patch>& patches, const Visibility& vis,
                                const OccluderPlanes& planes, const std::vector<OccluderPlanes::Sides>& sides,
                                const std::vector<Hemisphere>& hemisphere, const SolveControl& control);

}  // namespace lambert
