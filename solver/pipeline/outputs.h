// The outputs stage: every system's radiosity over all patches, H = F B per system, and the
// solution's per-patch spectra (the joint set, then each source's contribution),
//   B_i(λ) = B_{k(set, λ)}[i],   H_i(λ) = (F B_k)_i + E_i^direct(λ).
#pragma once

#include <vector>

#include "solver/pipeline/direct_light.h"
#include "solver/pipeline/spectral_systems.h"
#include "solver/pipeline/transport_operator.h"

namespace lambert {

struct SystemFields {
  std::vector<std::vector<double>> B;   // per system: radiosity over all patches
  std::vector<std::vector<double>> FB;  // per system: F B (empty where nothing is transported)
  std::vector<const double*> radiosity() const;
};

// op: nullptr where nothing is transported (H = E).
SystemFields system_fields(const SpectralSystems& systems, const TransportOperator* op, bool keep_sign);

void write_outputs(Solution& sol, const SpectralSystems& systems, const SystemFields& fields, const DirectLight& light);

}  // namespace lambert
