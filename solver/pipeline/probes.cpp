#include "solver/pipeline/probes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "solver/pipeline/clear_panes.h"

namespace lambert {

Receiver probe_receiver(const Probe& probe, const Point3& point) {
  Receiver r{Receiver::Kind::Planar, point, probe.normal, probe.facing};
  switch (probe.quantity) {
    case ProbeQuantity::Planar:
    case ProbeQuantity::Vertical: break;
    case ProbeQuantity::Cylindrical: r.kind = Receiver::Kind::Cylindrical; break;
    case ProbeQuantity::Semicylindrical: r.kind = Receiver::Kind::Semicylindrical; break;
    case ProbeQuantity::Hemispherical: r.kind = Receiver::Kind::Hemispherical; break;
  }
  return r;
}

void solve_probes(Solution& sol, const Scene& scene, const DirectLight& light, const SpectralSystems& systems,
                  const SystemFields& fields, const TransportOperator* op, const Visibility& vis,
                  const SolveControl& control) {
  const std::size_t W = sol.wavelengths(), K = systems.size(), sets = systems.sets();
  sol.probes.resize(scene.probes.size());
  for (SourceContribution& c : sol.contributions) c.probes.resize(scene.probes.size());
  if (scene.probes.empty()) return;
  // Nothing radiates anywhere (no emitter, or nothing lit reflects): there is no indirect part.
  const bool radiates = std::any_of(fields.B.begin(), fields.B.end(), [](const std::vector<double>& b) {
    return std::any_of(b.begin(), b.end(), [](double v) { return v != 0; });
  });
  const std::unique_ptr<PointGather> gather = op && radiates ? op->point_gather(fields.radiosity()) : nullptr;
  // The irradiance of set s at probe k (the joint solution's, then each contribution's).
  auto irradiance = [&](std::size_t set, std::size_t k) -> std::vector<double>& {
    return set == 0 ? sol.probes[k].irradiance : sol.contributions[set - 1].probes[k].irradiance;
  };
  for (std::size_t k = 0; k < scene.probes.size(); ++k) {
    const Probe& probe = scene.probes[k];
    const std::size_t P = probe.points.size();
    for (std::size_t set = 0; set < sets; ++set) irradiance(set, k).assign(P * W, 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P, 1), [&](const auto& range) {
      std::vector<double> E(K, 0.0), through;
      for (std::size_t q = range.begin(); q != range.end(); ++q) {
        const Receiver receiver = probe_receiver(probe, probe.points[q]);
        if (gather) gather->gather_at_point(receiver, E.data());
        for (std::size_t set = 0; set < sets; ++set) {
          double* e = &irradiance(set, k)[q * W];
          for (std::size_t w = 0; w < W; ++w) e[w] = E[systems.system_of(set, w)];
        }
        for (std::size_t s = 0; s < light.sources.size(); ++s) {
          // Through clear panes (clear_panes.h), spectral: τ(λ) per pane's channel.
          auto factor = [&](const Visibility& v) { return light.sources[s]->receiver_factor(receiver, v); };
          if (light.clear && light.clear->through(*light.sources[s], factor, through)) {
            double* e = &sol.probes[k].irradiance[q * W];
            double* own = light.term_of_source[s] >= 0 ? &irradiance(light.term_of_source[s] + 1, k)[q * W] : nullptr;
            for (std::size_t w = 0; w < W; ++w) e[w] += through[w];
            if (own)
              for (std::size_t w = 0; w < W; ++w) own[w] += through[w];
          }
          const double g = light.sources[s]->receiver_factor(receiver, vis);
          if (g == 0) continue;
          const auto& S = light.sources[s]->spectrum();
          double* e = &sol.probes[k].irradiance[q * W];
          for (std::size_t w = 0; w < W; ++w) e[w] += g * S[w];
          if (light.term_of_source[s] >= 0) {
            double* own = &irradiance(light.term_of_source[s] + 1, k)[q * W];
            for (std::size_t w = 0; w < W; ++w) own[w] += g * S[w];
          }
        }
      }
    });
    if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw SolveCancelled();
  }
  if (gather) sol.stats.exact_visibility_evaluations = gather->exact_evaluations();
}

}  // namespace lambert
