// Solution -> result JSON (SPEC §2), and the short human summary printed by `lambert solve`.
#pragma once

#include <ostream>
#include <string>

#include "solver/radiosity.h"
#include "solver/report.h"

namespace lambert {

// Positions are written in the scene's units; every per-area value is per square metre and every
// area is in m² (SPEC "Lengths").
// The result JSON (SPEC §2), compact. write_result streams it: the patches, most of a large result,
// are never held as a document.
void write_result(std::ostream& os, const Scene& scene, const Solution& solution, const Report& report);
std::string encode_result(const Scene& scene, const Solution& solution, const Report& report);

std::string summarize(const Scene& scene, const Solution& solution, const Report& report);

// An upper bound on the size of the result document of `scene`, linear in its patch count:
// fixed_bytes + per_patch_bytes × patches. Every number is counted at 25 bytes (the longest double,
// "-2.2250738585072014e-308", and a separator), every name at its length, and each element's keys
// and brackets at a fixed allowance; the solver's warnings get 256 kB. Known before the solve, so
// that a result too large for a limit is refused before anything is computed.
struct ResultSizeBound {
  double fixed_bytes = 0;      // wavelengths, surfaces, probes, stats, warnings
  double per_patch_bytes = 0;  // a patch and, with output.per_source, its share of every source
  double bytes(std::size_t patches) const { return fixed_bytes + per_patch_bytes * static_cast<double>(patches); }
};
ResultSizeBound result_size_bound(const Scene& scene);

}  // namespace lambert
