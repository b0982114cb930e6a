// View factors and radiant exchange of a scene, in one call: the geometric operator
// (solver/pipeline/geometric.h), the surface matrix (view_factors.h), optionally the sparse patch
// matrix, Hottel's total exchange factors and the grey-body exchange with its radiant temperatures
// at the probes (grey_exchange.h). What `lambert viewfactors` and a solve with output.view_factors or
// "thermal" surfaces return.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "solver/thermal/grey_exchange.h"
#include "solver/thermal/view_factors.h"

namespace lambert {

// The patch-to-patch factors F_ij ≠ 0 as triplets (row i, column j; patches as in
// RadiantExchange::patches).
struct PatchFactors {
  std::vector<std::uint32_t> i, j;
  std::vector<double> F;
};
// The patch matrix is refused beyond this many non-zero factors (16 bytes each in memory, about 40
// in a file).
inline constexpr std::size_t kMaxPatchFactors = 20'000'000;

struct RadiantOptions {
  bool patch_factors = false;  // also the sparse patch matrix
  bool thermal = false;        // the grey exchange (every surface of the scene has "thermal")
  // Not empty: also Hottel's total exchange factors with these emissivities (per scene surface).
  std::vector<double> total_exchange_emissivity;
};

struct RadiantExchange {
  SurfaceGroups groups;
  ViewFactorMatrix factors;
  std::string geometry_hash;
  std::vector<Patch> patches;    // the operator's patches where the scene lies
  std::vector<int> patch_group;  // per patch: its reported surface, or −1
  std::optional<PatchFactors> patch_factors;
  std::vector<double> total_exchange;  // ℱ, S × S row-major, when asked
  std::optional<GreyExchange> thermal;
  SolveStats stats;  // the operator's (meshing, visibility, factors, closure), time_solve_s the exchange's
  std::vector<std::string> warnings;
};

// Throws SolveError (solver/radiosity.h) where the scene cannot be served (see build_geometric_operator,
// grey_exchange) or the patch matrix exceeds kMaxPatchFactors.
RadiantExchange radiant_exchange(const Scene& scene, const SurfaceGroups& groups, const RadiantOptions& options,
                                 const SolveControl& control);

// Whether a scene asks for it: output.view_factors, or "thermal" on its surfaces.
bool wants_radiant_exchange(const Scene& scene);

}  // namespace lambert
