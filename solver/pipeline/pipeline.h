// The one loop of the solve (pbrt-v4's ImageTileIntegrator::Render, Mitsuba 3's
// SamplingIntegrator::render): every stage is written once and run in order; the method enters only
// through the transport operator it hands over (solver/pipeline/transport_operator.h).
//
//   discretise (the method: its operator's patches and visibility scene)
//   → sources and direct light (direct_light.h)
//   → hemispheres (hemisphere.h; the operator classifies, before any factor)
//   → spectral systems (spectral_systems.h: the joint set, then each source's)
//   → rounds: the operator builds (refines) F, closes its rows, and the systems are solved
//     (lockstep GMRES, solver/linear_solve.h), until the operator wants no further round
//   → outputs (H = F B + E, outputs.h) → probes (probes.h) → energy certificate (certificate.h)
//   → stats
#pragma once

#include <chrono>

#include "solver/pipeline/transport_operator.h"
#include "solver/radiosity.h"

namespace lambert {

// Tells control.stage that `stage` begins.
inline void enter_stage(const SolveControl& control, SolveStage stage) {
  if (control.stage) control.stage(stage);
}

// Solves `scene` (prepared: solver/pipeline/prepare.h) with the operator its method's discretise step
// made. `stats` holds what the discretisation measured (patches, meshing time, ...).
Solution run_pipeline(const Scene& scene, TransportOperator& op, SolveStats stats, const SolveControl& control,
                      std::chrono::steady_clock::time_point t_start);

}  // namespace lambert
