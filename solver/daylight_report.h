// The daylight part of a result (SPEC §5 "Daylight"), derived at the end with the rest of the report
// (report.h):
//  - per sky: its horizontal factor K, its zenith luminance, and what it gives an unobstructed
//    horizontal plane: E_h = K L_z from the sky above (the plane facing up) and ρ_g E_h from the
//    ground below (the plane facing down), spectral and in lux;
//  - per sun placed by place and time: where it stands and its normal illuminance;
//  - per probe that asks: the daylight factor DF = E / E_h at each point (CIE ILV 17-279: the sky's
//    light received directly and after reflections, over the unobstructed horizontal illuminance of
//    the same sky, direct sunlight excluded; the decoder admits it only in scenes that the sky alone
//    lights, so E is all the sky's), its statistics and EN 17037's summary, and the vertical sky
//    component (solver/pipeline/daylight.h).
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "solver/radiosity.h"

namespace lambert {

struct SkyReport {
  std::size_t light = 0;                   // index into Scene::lights
  double horizontal_factor_sr = 0;         // K
  double zenith_luminance_cd_m2 = 0;       // L_z
  double sky_illuminance_lx = 0;           // E_h: an unobstructed horizontal plane facing up
  double ground_illuminance_lx = 0;        // ρ_g E_h: a horizontal plane facing down, from the ground
  std::vector<double> sky_irradiance;      // E_h(λ), W m^-2 nm^-1
  std::vector<double> ground_irradiance;   // ρ_g E_h(λ)
};

struct SunReport {
  std::size_t light = 0;                   // index into Scene::lights (a directional light)
  SunPlacement placement;
  Vector3 towards;                         // unit, towards the sun in the scene
  double normal_illuminance_lx = 0;        // on a plane facing the sun
};

// EN 17037:2018+A1:2021, Annex A (the daylight-factor method): the target illuminance E_T is to be
// reached over 50 % of the reference plane and the minimum target E_TM over 95 %, for half the
// daylight hours; for a site whose median external diffuse illuminance is E_v,d,med these are the
// daylight factors D_T = E_T / E_v,d,med and D_TM = E_TM / E_v,d,med. Levels (E_T, E_TM):
// minimum (300, 100) lx, medium (500, 300) lx, high (750, 500) lx.
struct En17037Summary {
  En17037Request request;
  double target_illuminance_lx = 0, minimum_target_illuminance_lx = 0;            // E_T, E_TM
  double target_daylight_factor_pct = 0, minimum_target_daylight_factor_pct = 0;  // D_T, D_TM
  // The daylight factor reached or exceeded at 50 % and at 95 % of the grid's points (its cells are
  // equal, so points count as area): value_reached_over(DF, 0.5) and (DF, 0.95).
  double daylight_factor_over_50_pct = 0, daylight_factor_over_95_pct = 0;
  bool target_met = false, minimum_met = false;  // over_50 ≥ D_T, over_95 ≥ D_TM
};

struct ProbeDaylight {
  std::vector<double> daylight_factor_pct;  // per point, 100 E / E_h (empty unless asked)
  double min_pct = 0, mean_pct = 0, median_pct = 0, max_pct = 0;
  double target_pct = 0;
  double share_at_or_above_target = 0;      // of the points, in [0, 1]
  std::optional<En17037Summary> en17037;
  std::vector<double> vertical_sky_component_pct;  // per point (empty unless asked)
};

struct DaylightReport {
  std::vector<SkyReport> skies;
  std::vector<SunReport> suns;
  std::vector<std::optional<ProbeDaylight>> probes;  // parallel to Scene::probes
};

// `probe_lux`: each probe's illuminance per point (report.h's ProbeSummary); `luminous`: the
// photometric value of a spectrum on the solution's grid (report.cpp's photometer, rgb mode
// included). nullopt when the scene has neither a sky nor a sun placed by place and time.
std::optional<DaylightReport> make_daylight_report(const Scene& scene, const Solution& sol,
                                                   const std::vector<std::vector<double>>& probe_lux,
                                                   const std::function<double(const std::vector<double>&)>& luminous);

// The value reached or exceeded at a share (0, 1] of `values` (not empty): the ⌈share·n⌉-th largest.
double value_reached_over(std::vector<double> values, double share);

// E_T and E_TM of an EN 17037 level [lx].
std::pair<double, double> en17037_illuminances(En17037Request::Level level);

}  // namespace lambert
