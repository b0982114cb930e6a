#include "solver/thermal/radiant_temperature.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "solver/radiosity.h"

namespace lambert {

bool has_plane_radiant_temperature(const Probe& probe) {
  return probe.quantity == ProbeQuantity::Planar || probe.quantity == ProbeQuantity::Vertical;
}

std::vector<std::vector<RadiantPoint>> radiant_probes(const Scene& scene, const TransportOperator& op,
                                                      const SurfaceGroups& groups, const std::vector<double>& B,
                                                      const SolveControl& control) {
  std::vector<std::vector<RadiantPoint>> out(scene.probes.size());
  if (scene.probes.empty()) return out;
  const std::size_t N = op.size(), S = groups.size();
  // The vectors gathered: the radiosity, then each reported surface's indicator.
  const std::vector<int> group = patch_groups(op, groups);
  std::vector<std::vector<double>> indicator(S, std::vector<double>(N, 0.0));
  for (std::size_t i = 0; i < N; ++i)
    if (group[i] >= 0) indicator[group[i]][i] = 1;
  std::vector<const double*> vectors = {B.data()};
  for (const std::vector<double>& v : indicator) vectors.push_back(v.data());
  const std::unique_ptr<PointGather> gather = op.point_gather(vectors);
  auto temperature = [](double E) { return std::pow(std::max(0.0, E) / kStefanBoltzmann, 0.25); };
  for (std::size_t k = 0; k < scene.probes.size(); ++k) {
    const Probe& probe = scene.probes[k];
    out[k].resize(probe.points.size());
    const bool plane_too = has_plane_radiant_temperature(probe);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probe.points.size(), 1), [&](const auto& range) {
      std::vector<double> sphere(S + 1), plane(S + 1);
      for (std::size_t q = range.begin(); q != range.end(); ++q) {
        gather->gather_at_point({Receiver::Kind::Spherical, probe.points[q], probe.normal, {}}, sphere.data());
        if (plane_too) gather->gather_at_point({Receiver::Kind::Planar, probe.points[q], probe.normal, {}}, plane.data());
        RadiantPoint& point = out[k][q];
        point.mean_radiant_temperature_K = temperature(sphere[0]);
        if (plane_too) point.plane_radiant_temperature_K = temperature(plane[0]);
        point.view_factors.assign(sphere.begin() + 1, sphere.end());
      }
    });
    if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw SolveCancelled();
  }
  return out;
}

}  // namespace lambert
