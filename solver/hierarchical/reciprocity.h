// How far the hierarchical operator's links are from reciprocity, A_r F_rs = A_s F_sr
// (stats.max_reciprocity_error, stats.mean_reciprocity_error).
#pragma once

#include "solver/hierarchical/hierarchy.h"

namespace lambert::hierarchical {

struct Reciprocity {
  double worst = 0, differ = 0, exchanged = 0;
  double mean() const { return exchanged > 0 ? differ / exchanged : 0; }
};

// Over the element links whose reverse link exists at the same pair of elements: the largest
// |A_r F_rs − A_s F_sr| / max(A_r F_rs, A_s F_sr), and the sum of the differences over the sum of the
// larger exchanges (each pair counted from both ends). The two directions' visible fractions come
// from different rays, so a small link partly hidden can differ by most of its value (0.94 in the lit
// sphere rooms of docs/BENCHMARKS.md, on factors of 1e-5 to 1e-3) while the sums differ by 0.9 % (the
// six-sphere room, 7 636 patches). The reverse link is looked up in the receiver-sorted CSRs of both
// stores, the refinement's links and the leaf links (each sorted by source within a receiver), so
// the check needs no memory of its own and runs on every core.
Reciprocity reciprocity_error(const Hierarchy& h);

}  // namespace lambert::hierarchical
