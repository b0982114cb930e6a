// The probes stage: irradiance at every probe point (on the probe's receiver: planar, cylindrical,
// semicylindrical or hemispherical, solver/receiver.h), for the joint solution and every source's
// contribution. The indirect part is the operator's gather at the point (TransportOperator::
// point_gather) over every system's radiosity, computed once per point and shared by every set and
// wavelength that system serves; the direct part is each LightModel's receiver factor (shadowed by
// its rays), added after it.
#pragma once

#include "solver/pipeline/direct_light.h"
#include "solver/pipeline/outputs.h"

namespace lambert {

// The receiver a probe measures with at one of its points.
Receiver probe_receiver(const Probe& probe, const Point3& point);

// op: nullptr where nothing is transported (no indirect part). `vis` shadows the direct part.
void solve_probes(Solution& sol, const Scene& scene, const DirectLight& light, const SpectralSystems& systems,
                  const SystemFields& fields, const TransportOperator* op, const Visibility& vis,
                  const SolveControl& control);

}  // namespace lambert
