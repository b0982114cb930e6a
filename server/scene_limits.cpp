// The scene limits' checks and the patch budget they leave (server/scene_limits.h).
#include "server/scene_limits.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "server/result_codec.h"
#include "server/scene_codec.h"

namespace lambert {
namespace {

std::size_t probe_points(const Scene& scene) {
  std::size_t n = 0;
  for (const Probe& p : scene.probes) n += p.points.size();
  return n;
}

// "1.2e+10" for large counts, the digits for the rest.
std::string count_text(double n) {
  if (n < 1e15) return std::to_string(static_cast<unsigned long long>(n));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", n);
  return buf;
}

std::string spectral_values_rule(const SceneLimits& limits) {
  return "the limit is " + limit_text(kMaxSpectralValuesName, limits.max_spectral_values) +
         " (wavelengths × (patches + probe points))";
}

}  // namespace

std::string limit_text(const char* name, std::size_t value) {
  std::string option = name;
  for (char& c : option) c = c == '_' ? '-' : c;
  return std::string(name) + " = " + std::to_string(value) + ", --" + option;
}

std::vector<DecodeError> check_scene_limits(const Scene& scene, const SceneLimits& limits) {
  std::vector<DecodeError> errors;
  const double W = static_cast<double>(scene.grid.size());
  const double points = static_cast<double>(probe_points(scene));
  if (limits.max_spectral_values > 0 && W * points > static_cast<double>(limits.max_spectral_values))
    errors.push_back({"/probes", count_text(W) + " wavelengths × " + count_text(points) + " probe points = " +
                                     count_text(W * points) + " spectral values before any patch; " +
                                     spectral_values_rule(limits)});
  const ResultSizeBound bound = result_size_bound(scene);
  if (limits.max_result_bytes > 0 && bound.bytes(1) > static_cast<double>(limits.max_result_bytes))
    errors.push_back({scene.probes.empty() ? "" : "/probes",
                      "the result would take up to " + count_text(bound.bytes(1)) +
                          " bytes before its patches (probes, surfaces, spectra: 25 bytes a number); the limit is " +
                          limit_text(kMaxResultBytesName, limits.max_result_bytes) +
                          " (output.spectral false makes it smaller)"});
  return errors;
}

PatchBudget patch_budget(const Scene& scene, const SceneLimits& limits) {
  PatchBudget budget;
  const double W = static_cast<double>(scene.grid.size());
  if (limits.max_spectral_values > 0 && W > 0) {
    const double n = std::floor(static_cast<double>(limits.max_spectral_values) / W) -
                     static_cast<double>(probe_points(scene));
    const auto patches = static_cast<std::size_t>(std::clamp(n, 1.0, 1e18));
    budget = {patches, "the " + std::to_string(patches) + " patches that " +
                           limit_text(kMaxSpectralValuesName, limits.max_spectral_values) + " allows with " +
                           count_text(W) + " wavelengths (wavelengths × (patches + probe points))"};
  }
  if (limits.max_result_bytes > 0) {
    const ResultSizeBound bound = result_size_bound(scene);
    const double n = std::floor((static_cast<double>(limits.max_result_bytes) - bound.fixed_bytes) / bound.per_patch_bytes);
    const auto patches = static_cast<std::size_t>(std::clamp(n, 1.0, 1e18));
    if (budget.max_patches == 0 || patches < budget.max_patches)
      budget = {patches, "the " + std::to_string(patches) + " patches whose result " +
                             limit_text(kMaxResultBytesName, limits.max_result_bytes) + " allows (up to " +
                             count_text(std::ceil(bound.per_patch_bytes)) + " bytes a patch" +
                             (scene.output.spectral ? "; output.spectral false makes it smaller" : "") + ")"};
  }
  return budget;
}

PatchBudget tighter(PatchBudget budget, std::size_t max_patches, const std::string& name) {
  if (max_patches == 0 || (budget.max_patches > 0 && budget.max_patches <= max_patches)) return budget;
  return {max_patches, "this server's limit of " + std::to_string(max_patches) + " (" + name + ")"};
}

}  // namespace lambert
