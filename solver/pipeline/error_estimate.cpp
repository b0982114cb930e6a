#include "solver/pipeline/error_estimate.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace lambert {
namespace {

// Σ_λ E(λ) Δλ: the radiometric total of one spectrum [W m^-2].
double total(const WavelengthGrid& grid, const double* E) {
  double sum = 0;
  for (std::size_t w = 0; w < grid.size(); ++w) sum += grid.weight_nm[w] * E[w];
  return sum;
}

// Each surface's area-weighted mean total irradiance; surfaces without patches (enclosed, or cut
// away as contact area) get −1, which no comparison reads.
std::vector<double> surface_means(const Solution& sol, std::size_t surfaces) {
  std::vector<double> flux(surfaces, 0.0), area(surfaces, 0.0);
  const std::size_t W = sol.grid.size();
  for (std::size_t i = 0; i < sol.patches.size(); ++i) {
    const Patch& p = sol.patches[i];
    flux[p.surface] += p.area_m2 * total(sol.grid, &sol.irradiance[i * W]);
    area[p.surface] += p.area_m2;
  }
  std::vector<double> mean(surfaces, -1.0);
  for (std::size_t s = 0; s < surfaces; ++s)
    if (area[s] > 0) mean[s] = flux[s] / area[s];
  return mean;
}

// A relative change; values below 1e-9 of the set's largest (a shadowed point, an unlit surface)
// are measured against that floor instead of themselves, so that a change of nothing into nearly
// nothing does not read as an error of order one. No change is 0, also in a set that is all dark.
double relative_change(double fine, double coarse, double floor) {
  const double change = std::abs(fine - coarse);
  const double scale = std::max(std::abs(fine), floor);
  return change == 0 || !(scale > 0) ? 0.0 : change / scale;
}

}  // namespace

Scene coarser_scene(const Scene& scene, const SolveStats& fine) {
  Scene coarse = scene;
  coarse.meshing.max_patch_area_m2 = 4 * fine.max_patch_area_m2;
  coarse.solver.method = fine.method;
  if (fine.method == SolverMethod::Hierarchical) coarse.solver.accuracy = std::min(0.1, 4 * scene.solver.accuracy);
  coarse.output.error_estimate = false;
  coarse.output.per_source = false;
  coarse.output.view_factors = false;
  return coarse;
}

void estimate_discretisation_error(const Scene& scene, Solution& fine,
                                   const std::function<Solution(const Scene&)>& solve_coarse) {
  const auto t0 = std::chrono::steady_clock::now();
  const Solution coarse = solve_coarse(coarser_scene(scene, fine.stats));
  SolveStats::ErrorEstimate e;
  e.coarse_patches = coarse.stats.patches;
  e.coarse_max_patch_area_m2 = coarse.stats.max_patch_area_m2;

  const std::vector<double> a = surface_means(fine, scene.surfaces.size());
  const std::vector<double> b = surface_means(coarse, scene.surfaces.size());
  const double surface_floor = 1e-9 * *std::max_element(a.begin(), a.end());
  for (std::size_t s = 0; s < a.size(); ++s)
    if (a[s] >= 0 && b[s] >= 0) e.surface_irradiance_max = std::max(e.surface_irradiance_max, relative_change(a[s], b[s], surface_floor));

  const std::size_t W = fine.grid.size();
  double sum2 = 0;
  std::size_t points = 0;
  for (std::size_t k = 0; k < fine.probes.size() && k < coarse.probes.size(); ++k) {
    const std::vector<double>& f = fine.probes[k].irradiance;
    const std::vector<double>& c = coarse.probes[k].irradiance;
    const std::size_t n = f.size() / std::max<std::size_t>(W, 1);
    double largest = 0;
    for (std::size_t q = 0; q < n; ++q) largest = std::max(largest, std::abs(total(fine.grid, &f[q * W])));
    for (std::size_t q = 0; q < n; ++q) {
      const double r = relative_change(total(fine.grid, &f[q * W]), total(coarse.grid, &c[q * W]), 1e-9 * largest);
      e.probe_irradiance_max = std::max(e.probe_irradiance_max, r);
      sum2 += r * r;
      ++points;
    }
  }
  if (points > 0) e.probe_irradiance_rms = std::sqrt(sum2 / points);
  e.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  fine.stats.error_estimate = e;
}

}  // namespace lambert
