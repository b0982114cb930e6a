// ISO 7726's radiant temperatures at the scene's probe points, from the radiosity of a radiant
// exchange (grey_exchange.h, RadiantPoint): the operator's gather at a point (transport_operator.h,
// PointGather) of the radiosity and of every reported surface's indicator, on a small sphere (the
// mean radiant temperature and the point's view factors) and on the plane facing the probe's normal
// (the plane radiant temperature).
#pragma once

#include <vector>

#include "solver/thermal/grey_exchange.h"

namespace lambert {

// Whether a probe measures on a plane (quantity planar or vertical): the plane radiant temperature is
// that plane's; other receivers (cylindrical, ...) have none.
bool has_plane_radiant_temperature(const Probe& probe);

// Per scene probe, per point. `B`: the radiosity of every patch of `op`.
std::vector<std::vector<RadiantPoint>> radiant_probes(const Scene& scene, const TransportOperator& op,
                                                      const SurfaceGroups& groups, const std::vector<double>& B,
                                                      const SolveControl& control);

}  // namespace lambert
