#include "solver/daylight_report.h"

#include <algorithm>
#include <cmath>

#include "solver/lights/sky.h"

namespace lambert {
namespace {

SkyReport sky_report(std::size_t index, const SkyLight& light,
                     const std::function<double(const std::vector<double>&)>& luminous) {
  const SkySummary summary = summarize_sky(light);
  SkyReport r;
  r.light = index;
  r.horizontal_factor_sr = summary.horizontal_factor_sr;
  r.zenith_luminance_cd_m2 = luminous(light.zenith_radiance_W_m2_sr_nm);
  r.sky_irradiance = summary.horizontal_irradiance_W_m2_nm;
  for (double E : r.sky_irradiance) r.ground_irradiance.push_back(light.ground_reflectance * E);
  r.sky_illuminance_lx = luminous(r.sky_irradiance);
  r.ground_illuminance_lx = luminous(r.ground_irradiance);
  return r;
}

// The daylight factor of every point, its statistics, the share at or above the target and, where
// asked, EN 17037's summary.
void daylight_factors(const DaylightRequest& request, const std::vector<double>& lux, double sky_lx,
                      ProbeDaylight& out) {
  for (double E : lux) out.daylight_factor_pct.push_back(sky_lx > 0 ? 100 * E / sky_lx : 0);
  const std::vector<double>& df = out.daylight_factor_pct;
  if (df.empty()) return;
  std::vector<double> sorted = df;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  out.min_pct = sorted.front();
  out.max_pct = sorted.back();
  double sum = 0;
  for (double v : sorted) sum += v;
  out.mean_pct = sum / n;
  out.median_pct = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  out.target_pct = request.target_pct;
  const auto at_or_above = std::count_if(df.begin(), df.end(), [&](double v) { return v >= request.target_pct; });
  out.share_at_or_above_target = static_cast<double>(at_or_above) / n;
  if (!request.en17037) return;
  En17037Summary s;
  s.request = *request.en17037;
  std::tie(s.target_illuminance_lx, s.minimum_target_illuminance_lx) = en17037_illuminances(s.request.level);
  const double E_med = s.request.median_external_diffuse_illuminance_lx;
  s.target_daylight_factor_pct = 100 * s.target_illuminance_lx / E_med;
  s.minimum_target_daylight_factor_pct = 100 * s.minimum_target_illuminance_lx / E_med;
  s.daylight_factor_over_50_pct = value_reached_over(df, 0.5);
  s.daylight_factor_over_95_pct = value_reached_over(df, 0.95);
  s.target_met = s.daylight_factor_over_50_pct >= s.target_daylight_factor_pct;
  s.minimum_met = s.daylight_factor_over_95_pct >= s.minimum_target_daylight_factor_pct;
  out.en17037 = s;
}

}  // namespace

double value_reached_over(std::vector<double> values, double share) {
  const std::size_t n = values.size();
  const auto k = static_cast<std::size_t>(std::ceil(share * static_cast<double>(n) - 1e-9));
  const std::size_t rank = std::clamp<std::size_t>(k, 1, n);  // the rank-th largest
  std::nth_element(values.begin(), values.begin() + (rank - 1), values.end(), std::greater<>());
  return values[rank - 1];
}

std::pair<double, double> en17037_illuminances(En17037Request::Level level) {
  switch (level) {
    case En17037Request::Level::kMinimum: return {300, 100};
    case En17037Request::Level::kMedium: return {500, 300};
    case En17037Request::Level::kHigh: return {750, 500};
  }
  return {300, 100};
}

std::optional<DaylightReport> make_daylight_report(const Scene& scene, const Solution& sol,
                                                   const std::vector<std::vector<double>>& probe_lux,
                                                   const std::function<double(const std::vector<double>&)>& luminous) {
  DaylightReport report;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    if (const auto* sky = std::get_if<SkyLight>(&scene.lights[l])) report.skies.push_back(sky_report(l, *sky, luminous));
    if (const auto* d = std::get_if<DirectionalLight>(&scene.lights[l]); d && d->sun)
      report.suns.push_back({l, *d->sun, -d->direction, luminous(d->irradiance_W_m2_nm)});
  }
  if (report.skies.empty() && report.suns.empty()) return std::nullopt;
  report.probes.resize(scene.probes.size());
  for (std::size_t k = 0; k < scene.probes.size(); ++k) {
    const DaylightRequest& request = scene.probes[k].daylight;
    if (!request.daylight_factor && !request.vertical_sky_component) continue;
    ProbeDaylight& out = report.probes[k].emplace();
    if (request.daylight_factor && !report.skies.empty() && k < probe_lux.size())
      daylight_factors(request, probe_lux[k], report.skies.front().sky_illuminance_lx, out);
    if (k < sol.probes.size())
      for (double f : sol.probes[k].sky_component) out.vertical_sky_component_pct.push_back(100 * f);
  }
  return report;
}

}  // namespace lambert
