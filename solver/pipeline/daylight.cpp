#include "solver/pipeline/daylight.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <memory>

#include "solver/light_model.h"
#include "solver/lights/sky.h"

namespace lambert {

void measure_sky_components(const Scene& scene, Solution& sol, const SolveControl& control) {
  const bool asked = std::any_of(scene.probes.begin(), scene.probes.end(),
                                 [](const Probe& p) { return p.daylight.vertical_sky_component; });
  if (!asked) return;
  const auto sky = std::find_if(scene.lights.begin(), scene.lights.end(),
                                [](const Light& l) { return std::holds_alternative<SkyLight>(l); });
  if (sky == scene.lights.end()) throw SolveError("vertical_sky_component needs a sky in the scene's lights");
  const SceneLightContext lights(scene);
  const std::unique_ptr<SkyDome> dome = make_sky_dome(std::get<SkyLight>(*sky), lights.context());
  const double K = dome->sky().horizontal_factor();
  sol.probes.resize(scene.probes.size());
  for (std::size_t k = 0; k < scene.probes.size(); ++k) {
    const Probe& probe = scene.probes[k];
    if (!probe.daylight.vertical_sky_component) continue;
    std::vector<double>& out = sol.probes[k].sky_component;
    out.assign(probe.points.size(), 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probe.points.size(), 1), [&](const auto& range) {
      for (std::size_t q = range.begin(); q != range.end(); ++q) out[q] = dome->at(probe.points[q], probe.normal).sky / K;
    });
    if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw SolveCancelled();
  }
}

}  // namespace lambert
