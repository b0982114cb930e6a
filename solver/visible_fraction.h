// Visible fraction of a link (patch-patch, point-patch, patch-light) from ray samples. Each ray is
// weighted by the link's differential kernel at its ends, so the estimate is of the visible share of
// the flux, not of the area. Progressive: 4 rays; if they disagree 16; if those disagree 64. Fully
// visible and fully hidden links (the vast majority) cost 4 rays.
#pragma once

#include <array>
#include <utility>

#include "mesh/geometry.h"
#include "solver/visibility.h"

namespace lambert {

inline constexpr int kMaxVisibilitySamples = 64;

// Stratified points on a triangle: centroids of the 64 cells of a three-level 1:4 split, ordered so
// that the first 4 lie one per level-1 cell (the three corner cells and the centre cell) and the
// first 16 one per level-2 cell.
const std::array<std::array<double, 3>, kMaxVisibilitySamples>& triangle_visibility_samples();
inline Point3 visibility_sample(const Triangle& t, int k) {
  const auto& w = triangle_visibility_samples()[k];
  return barycentric(t.v[0], t.v[1], t.v[2], w[0], w[1], w[2]);
}

// The sample of the far end paired with sample k of the near end: the first round pairs corner
// cells with corner cells (so that a patch partly covered by a nearby object, whose corners differ,
// is caught by the first four rays), the rest follow a fixed odd-multiplier permutation that pairs
// cells that do not correspond.
constexpr int paired_sample(int k) { return k < 4 ? (k + 1) % 4 : 4 + (37 * k + 11) % 60; }

// endpoints(k) -> {from, to} for ray k (k < 64); weight(from, to) >= 0. `first_round` rays (4 or 16)
// are traced before the first vote. Samples of zero weight
// (behind either end's horizon: the kernel has already excluded them) are not traced and do not vote:
// a link whose first samples all lie behind a horizon is not declared hidden by them. Returns 1 when
// no sample has weight (the rays cannot tell; the unoccluded factor stands).
template <class Endpoints, class Weight>
double weighted_visible_fraction(const Visibility& vis, Endpoints&& endpoints, Weight&& weight, int first_round = 4) {
  double seen = 0, total = 0;
  int visible = 0, traced = 0, k = 0;
  for (int round_end : {first_round, 16, kMaxVisibilitySamples}) {
    for (; k < round_end; ++k) {
      const auto [from, to] = endpoints(k);
      const double w = weight(from, to);
      if (!(w > 0)) continue;
      const bool v = vis.visible(from, to);
      ++traced;
      visible += v;
      seen += v ? w : 0;
      total += w;
    }
    if (traced > 0 && (visible == 0 || visible == traced)) break;  // unanimous: no need to refine
  }
  return total > 0 ? seen / total : 1.0;
}

}  // namespace lambert
