// The energy certificate stage: emitted = absorbed + escaped (solver/energy_balance.h). What escapes
// of patch j's power is A_j B_j (1 − Σ_i A_i F_ij / A_j): the share no patch gathers, from the
// transpose of the operator as solved, so the balance is exact for that operator whatever its
// factors' errors.
#pragma once

#include "solver/pipeline/direct_light.h"
#include "solver/pipeline/transport_operator.h"

namespace lambert {

// op: nullptr where nothing is transported (every patch's power escapes, or is absorbed).
void certify_energy(Solution& sol, const Scene& scene, const DirectLight& light, const TransportOperator* op);

}  // namespace lambert
