#include "solver/pipeline/hemisphere.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>

namespace lambert {

HemisphereProbe::HemisphereProbe(const Visibility& vis, std::vector<Vector3> normals, std::vector<char> two_sided)
    : vis_(vis), normals_(std::move(normals)), two_sided_(std::move(two_sided)) {}

Hemisphere HemisphereProbe::classify(const Triangle& t, const Vector3& n, std::size_t seed, int rays) const {
  return probe_hemisphere(t, n, seed, rays, vis_, [&](int hit, const Vector3& d) {
    return !two_sided_[hit] && dot(normals_[hit], d) >= 0;
  });
}

Hemisphere hemisphere_from_coverage(double covered) {
  return std::abs(1 - covered) <= 1e-3 ? Hemisphere::Closed : Hemisphere::Open;
}

void report_hemisphere_findings(Solution& sol, const Scene& scene, const std::vector<Hemisphere>& hemisphere) {
  auto tally = [&](Hemisphere kind, double& area) {
    std::set<std::string> names;
    std::size_t count = 0;
    for (std::size_t i = 0; i < sol.patches.size() && i < hemisphere.size(); ++i)
      if (hemisphere[i] == kind) {
        ++count;
        area += sol.patches[i].area_m2;
        names.insert(scene.surfaces[sol.patches[i].surface].name);
      }
    std::string list;
    for (const auto& name : names) list += (list.empty() ? "" : ", ") + name;
    return std::pair{count, list};
  };
  double leak_area = 0, enclosed_area = 0;
  const auto [leaking, leak_surfaces] = tally(Hemisphere::Leaking, leak_area);
  if (leaking > 0)
    sol.warnings.push_back(std::to_string(leaking) + " patches (of " + leak_surfaces +
                           ") see the back of a surface: an enclosure is open underneath or a "
                           "surface faces the wrong way; light reaching a back side is lost");
  const auto [enclosed, enclosed_surfaces] = tally(Hemisphere::Enclosed, enclosed_area);
  if (enclosed > 0) {
    char text[64];
    std::snprintf(text, sizeof text, "%.6g", enclosed_area);
    sol.warnings.push_back(std::to_string(enclosed) + " patches (" + text + " m² of " + enclosed_surfaces +
                           ") lie inside closed solids (e.g. under a box standing on a floor): they see only "
                           "back faces, exchange no light with the scene and are left out of the result");
  }
}

void leave_out_enclosed(Solution& sol, const std::vector<Hemisphere>& hemisphere) {
  const std::size_t W = sol.wavelengths(), N = sol.patches.size();
  std::vector<char> gone(N, 0);
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < N && i < hemisphere.size(); ++i) {
    gone[i] = hemisphere[i] == Hemisphere::Enclosed;
    dropped += gone[i];
  }
  sol.stats.enclosed_patches = dropped;
  if (dropped == 0) return;
  auto compact = [&](std::vector<double>& per_patch) {
    if (per_patch.size() != N * W) return;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < N; ++i)
      if (!gone[i]) std::copy_n(&per_patch[i * W], W, &per_patch[kept++ * W]);
    per_patch.resize(kept * W);
  };
  compact(sol.radiosity);
  compact(sol.irradiance);
  for (SourceContribution& c : sol.contributions) {
    compact(c.radiosity);
    compact(c.irradiance);
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < N; ++i)
    if (!gone[i]) sol.patches[kept++] = sol.patches[i];
  sol.patches.resize(kept);
  sol.stats.patches = kept;
}

}  // namespace lambert
