// Daylight through the whole solve (scene JSON → result JSON): the sky light, the daylight factor and
// the vertical sky component against closed forms (7π L_z/9, π L, (3π + 8)/(14π), Howell B-3 and its
// second moment through an opening) and against sky integrals done here by another method
// (tests/sky_quadrature.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "server/result_codec.h"
#include "server/scene_codec.h"
#include "solver/radiosity.h"
#include "solver/report.h"
#include "tests/daylight_scenes.h"
#include "tests/sky_quadrature.h"
#include "tests/test_geometry.h"

namespace lambert {
namespace {

using nlohmann::json;
using test::kDeg;
using namespace test::daylight;

// ---- the unobstructed sky ---------------------------------------------------------------------

TEST(SkyThroughTheSolve, OvercastAndUniformSkiesOnAnOpenPlate) {
  // A grey plate under the sky alone (it sees no other surface): every patch and a probe on it take
  // E = K L_z, K = 7π/9 under the CIE overcast sky (∫ (1 + 2 cos Z) cos Z dω / 3) and π under the
  // uniform sky, exactly but for the dome cubature's 1e-9 K (overcast); the result states E_h and
  // the ground's ρ_g E_h on a plane facing down. Both methods.
  const double L_z = 1000;  // cd/m²
  for (const char* method : {"dense", "hierarchical"})
    for (const auto& [type, K] : {std::pair<json, double>{16, 7 * kPi / 9}, {"uniform", kPi}}) {
      json light = sky(type, "zenith_luminance_cd_m2", L_z);
      light["ground_reflectance"] = 0.3;
      const json result = solve_json(scene_with(json::array({rectangle("plate", "grey", {0, 0, 0}, {2, 0, 0}, {0, 1, 0})}),
                                                json::array({light}),
                                                json::array({probe("on the plate", {0.7, 0.4, 0}, {0, 0, 1})}), method));
      const double E = K * L_z;
      EXPECT_NEAR(result["probes"][0]["illuminance_lx"].get<double>() / E, 1, 2e-9) << method << " " << type;
      for (const json& patch : result["patches"])
        EXPECT_NEAR(patch["illuminance_lx"].get<double>() / E, 1, 2e-9) << method << " " << type;
      const json& stated = result["daylight"]["skies"][0];
      EXPECT_EQ(stated["source"], "/lights/0");
      EXPECT_NEAR(stated["horizontal_factor_sr"].get<double>(), K, 1e-13);
      EXPECT_NEAR(stated["zenith_luminance_cd_m2"].get<double>(), L_z, 1e-9);
      EXPECT_NEAR(stated["unobstructed_illuminance_lx"]["sky"].get<double>(), E, 1e-9);
      EXPECT_NEAR(stated["unobstructed_illuminance_lx"]["ground"].get<double>(), 0.3 * E, 1e-9);
    }
}

TEST(SkyThroughTheSolve, EveryGeneralSkyAgainstAnotherQuadrature) {
  // Each of the 15 general skies scaled to 10 000 lx on the unobstructed horizontal plane, the sun
  // at Z_s = 40°, azimuth 150° (east of south, with north +y): a probe facing up reads 10 000 lx; a
  // tilted one (facing south-east, 50° from the vertical) reads 10 000 × I(n)/K with both the
  // integral over the sky in front of it, I(n), and K computed here by product Gauss rules in angles
  // (graded at the sun and the horizon), not by the solver's quadratures. The ground is black, the
  // plate far below the probes and black.
  const Vector3 sun = test::sky_direction(40 * kDeg, 150 * kDeg);
  const Vector3 tilted = test::sky_direction(50 * kDeg, 135 * kDeg);
  for (int type = 1; type <= kCieGeneralSkyTypes; ++type) {
    json light = sky(type, "horizontal_illuminance_lx", 10000);
    light["ground_reflectance"] = 0;
    light["sun_direction"] = triple(sun);
    const json result = solve_json(
        scene_with(json::array({rectangle("plate", "black", {-50, -50, -100}, {1, 0, 0}, {0, 1, 0})}), json::array({light}),
                   json::array({probe("up", {0, 0, 0}, {0, 0, 1}), probe("tilted", {0, 0, 0}, tilted)})));
    const SkyDistribution distribution = SkyDistribution::general(type, test::kUp, sun);
    const double K = test::hemisphere_integral(distribution, 40 * kDeg, 150 * kDeg, test::kUp);
    EXPECT_NEAR(result["probes"][0]["illuminance_lx"].get<double>(), 10000, 1e-5) << "type " << type;
    EXPECT_NEAR(result["probes"][1]["illuminance_lx"].get<double>() / (10000 * test::lune_integral(distribution, tilted) / K),
                1, 3e-9)
        << "type " << type;
  }
}

TEST(SkyThroughTheSolve, VerticalFacadeUnderTheOvercastSky) {
  // An unobstructed vertical plane sees half the sky: E_v/E_h = (π/6 + 4/9)/(7π/9) = (3π + 8)/(14π)
  // = 0.39618, the 0.396 to its three digits; with a black ground it is all sky, which is
  // also its vertical sky component.
  json light = sky(16, "horizontal_illuminance_lx", 10000);
  light["ground_reflectance"] = 0;
  json facade = probe("facade", {0, 0, 0}, {1, 0, 0});
  facade["vertical_sky_component"] = true;
  const json result = solve_json(scene_with(json::array({rectangle("plate", "black", {-50, -50, -100}, {1, 0, 0}, {0, 1, 0})}),
                                            json::array({light}), json::array({facade})));
  const double ratio = result["probes"][0]["illuminance_lx"].get<double>() / 10000;
  EXPECT_NEAR(ratio, (3 * kPi + 8) / (14 * kPi), 2e-9);
  EXPECT_NEAR(ratio, 0.396, 5e-4);
  EXPECT_NEAR(result["probes"][0]["vertical_sky_component_pct"].get<double>(), 100 * (3 * kPi + 8) / (14 * kPi), 2e-7);
}

// ---- the sun -----------------------------------------------------------------------------------

TEST(SunThroughTheSolve, PlacedByPlaceAndTime) {
  // A directional light placed by NOAA's algorithm at NOAA's spreadsheet inputs (40° N, 105° W),
  // 2010-06-21 12:00 UTC−7, where the spreadsheet gives the sun at 73.4384793° elevation (refracted),
  // azimuth 178.5332300° (solar_position_test). Scene up = z, north = y, east = x. Without a total its
  // normal illuminance is the clear-sky model's: E_n = 128 000 lx (1 + 0.033412 cos(2π (172 − 3)/365))
  // exp(−0.21 m), m Kasten & Young's air mass at that zenith angle; a plate facing up reads
  // E_n sin γ. With "illuminance_lx": 80 000 it reads 80 000 sin γ.
  const double elevation = 73.4384793439627, azimuth = 178.533230037881, Z = 90 - elevation;
  const double m = 1 / (std::cos(Z * kDeg) + 0.50572 * std::pow(96.07995 - Z, -1.6364));
  const double E_n = 128000 * (1 + 0.033412 * std::cos(2 * kPi * (172 - 3) / 365.0)) * std::exp(-0.21 * m);
  for (const bool given : {false, true}) {
    json sun = {{"type", "directional"},
                {"sun", {{"latitude_deg", 40}, {"longitude_deg", -105}, {"time", "2010-06-21T12:00:00-07:00"}}},
                {"up", {0, 0, 1}},
                {"north", {0, 1, 0}},
                {"irradiance", {{"cie", "D65"}}}};
    if (given) sun["illuminance_lx"] = 80000;
    const json result = solve_json(scene_with(json::array({rectangle("plate", "black", {0, 0, 0}, {1, 0, 0}, {0, 1, 0})}),
                                              json::array({sun}), json::array({probe("up", {0.5, 0.5, 0}, {0, 0, 1})})));
    const json& placed = result["daylight"]["suns"][0];
    EXPECT_NEAR(placed["elevation_deg"].get<double>(), elevation, 1e-6);
    EXPECT_NEAR(placed["azimuth_deg"].get<double>(), azimuth, 1e-6);
    const double expected_n = given ? 80000 : E_n;
    EXPECT_NEAR(placed["normal_illuminance_lx"].get<double>(), expected_n, 1e-8 * expected_n);
    EXPECT_EQ(placed["normal_illuminance_from"], given ? "scene" : "clear_sky_model");
    const double towards_x = std::cos(elevation * kDeg) * std::sin(azimuth * kDeg);  // east
    EXPECT_NEAR(placed["towards"][0].get<double>(), towards_x, 1e-8);
    EXPECT_NEAR(result["probes"][0]["illuminance_lx"].get<double>(), expected_n * std::sin(elevation * kDeg), 1e-6 * expected_n);
  }
}

// ---- openings ----------------------------------------------------------------------------------

TEST(SkyThroughTheSolve, UniformSkyThroughARoofOpeningIsALambertianEmitter) {
  // Under the uniform sky of luminance L the opening is a Lambertian emitter of luminance L: at floor
  // points of a black room E = π L F(p → opening), Howell B-3 by corner decomposition, and the same
  // scene with the opening closed by an emitting panel of luminance L facing down reads the same
  // (the area-emitter path of the solver, a second method).
  const double L = 2000;
  const std::vector<Point3> points = {{2, 2, 0}, {1.7, 2.2, 0}, {0.3, 3.1, 0}, {3.9, 0.2, 0}};
  json probes = json::array();
  for (std::size_t k = 0; k < points.size(); ++k) probes.push_back(probe(std::string("p").append(std::to_string(k)), points[k], {0, 0, 1}));
  const json open = solve_json(scene_with(room_with_roof_opening("black"),
                                          json::array({sky("uniform", "zenith_luminance_cd_m2", L)}), probes));
  json surfaces = room_with_roof_opening("black");
  json panel = rectangle("panel", "black", {1.5, 1.5, 3}, {0, 1, 0}, {1, 0, 0});
  panel["emission"] = {{"radiance", 1}, {"luminance_cd_m2", L}};
  surfaces.push_back(panel);
  json closed_scene = scene_with(surfaces, json::array(), probes);
  const json closed = solve_json(closed_scene);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Point3& p = points[k];
    const double E = kPi * L * test::point_under_rectangle(p.x, p.y, 3, 1.5, 2.5, 1.5, 2.5);
    EXPECT_NEAR(open["probes"][k]["illuminance_lx"].get<double>(), E, 1e-9 * E + 1e-9) << k;
    EXPECT_NEAR(closed["probes"][k]["illuminance_lx"].get<double>(), E, 1e-9 * E + 1e-9) << k;
  }
}

TEST(SkyThroughTheSolve, DaylightFactorUnderARoofOpening) {
  // A black room (no reflected light: DF is the sky component) with an unglazed roof opening, a grid
  // of 8 × 8 points on the floor. Under the uniform sky DF = F(p → opening) (B-3 corners); under the
  // CIE overcast sky, L = L_z (1 + 2 cos Z)/3 and E_h = 7π L_z/9, so
  //   DF = (3/(7π)) (π F + 2 M),   M = ∫ cos² Z dω over the opening (closed_forms.h, second_moment_b3).
  // To the dome cubature's tolerance, 1e-9 K per face of its box: at most 1e-6 % of DF. The
  // statistics against those of the closed-form values, sorted here.
  for (const json& type : {json("uniform"), json(16)}) {
    json grid = {{"name", "floor"},
                 {"grid", {{"origin", {0, 0, 0}}, {"u", {4, 0, 0}}, {"v", {0, 4, 0}}, {"nu", 8}, {"nv", 8}}},
                 {"normal", {0, 0, 1}},
                 {"daylight_factor", true},
                 {"daylight_factor_target_pct", 1.5},
                 {"en17037", {{"level", "minimum"}, {"median_external_diffuse_illuminance_lx", 20000}}}};
    const json result = solve_json(scene_with(room_with_roof_opening("black"),
                                              json::array({sky(type, "horizontal_illuminance_lx", 10000)}),
                                              json::array({grid})));
    const json& out = result["probes"][0];
    std::vector<double> expected;
    for (int b = 0; b < 8; ++b)
      for (int a = 0; a < 8; ++a) {
        const double x = 0.25 + 0.5 * a, y = 0.25 + 0.5 * b;
        const double F = test::point_under_rectangle(x, y, 3, 1.5, 2.5, 1.5, 2.5);
        const double M = test::under_rectangle(test::second_moment_b3, x, y, 3, 1.5, 2.5, 1.5, 2.5);
        expected.push_back(100 * (type == "uniform" ? F : 3 / (7 * kPi) * (kPi * F + 2 * M)));
      }
    for (std::size_t q = 0; q < expected.size(); ++q)
      EXPECT_NEAR(out["daylight_factor_pct"][q].get<double>(), expected[q], 1e-6) << type << " point " << q;
    std::vector<double> sorted = expected;
    std::sort(sorted.begin(), sorted.end());
    const json& df = out["daylight_factor"];
    EXPECT_NEAR(df["median_pct"].get<double>(), 0.5 * (sorted[31] + sorted[32]), 1e-6);
    EXPECT_NEAR(df["min_pct"].get<double>(), sorted.front(), 1e-6);
    EXPECT_NEAR(df["max_pct"].get<double>(), sorted.back(), 1e-6);
    const double above = static_cast<double>(std::count_if(expected.begin(), expected.end(), [](double v) { return v >= 1.5; }));
    EXPECT_DOUBLE_EQ(df["share_at_or_above_target"].get<double>(), above / 64);
    // EN 17037, minimum level, E_v,d,med = 20 000 lx: D_T = 300/20000 = 1.5 %, D_TM = 0.5 %; the DF
    // reached at 50 % of the 64 points is the 32nd largest, at 95 % the 61st (⌈60.8⌉).
    const json& en = out["en17037"];
    EXPECT_NEAR(en["target_daylight_factor_pct"].get<double>(), 1.5, 1e-12);
    EXPECT_NEAR(en["minimum_target_daylight_factor_pct"].get<double>(), 0.5, 1e-12);
    EXPECT_NEAR(en["daylight_factor_over_50_pct_of_points"].get<double>(), sorted[64 - 32], 1e-6);
    EXPECT_NEAR(en["daylight_factor_over_95_pct_of_points"].get<double>(), sorted[64 - 61], 1e-6);
    EXPECT_EQ(en["target_met"].get<bool>(), sorted[32] >= 1.5);
    EXPECT_EQ(en["minimum_target_met"].get<bool>(), sorted[3] >= 0.5);
  }
}

// ---- strict input ----------------------------------------------------------------------------------

// The errors of a scene that must not decode, as "pointer: message" lines.
std::string errors_of(const json& scene) {
  const DecodeResult decoded = decode_scene(scene.dump());
  EXPECT_FALSE(decoded.ok());
  return format_errors(decoded.errors);
}

TEST(DaylightInput, ErrorsNameTheField) {
  const json plate = json::array({rectangle("plate", "black", {0, 0, 0}, {1, 0, 0}, {0, 1, 0})});
  auto with_light = [&](json light, json probes = json::array()) { return scene_with(plate, json::array({light}), probes); };
  struct Case {
    json scene;
    std::string expected;  // a part of the message, with its pointer
  };
  json no_scale = sky(16, "zenith_luminance_cd_m2", 1);
  no_scale.erase("zenith_luminance_cd_m2");
  json two_scales = sky(16, "zenith_luminance_cd_m2", 1);
  two_scales["horizontal_illuminance_lx"] = 10000;
  json needs_sun = sky(12, "horizontal_illuminance_lx", 10000);
  json sun_below = sky(12, "horizontal_illuminance_lx", 10000);
  sun_below["sun_direction"] = {0, 1, -0.1};
  json both_suns = sky(12, "horizontal_illuminance_lx", 10000);
  both_suns["sun_direction"] = {0, 1, 1};
  both_suns["sun"] = {{"latitude_deg", 40}, {"longitude_deg", -105}, {"time", "2010-06-21T12:00-07:00"}};
  json sun_without_north = sky(12, "horizontal_illuminance_lx", 10000);
  sun_without_north["sun"] = both_suns["sun"];
  json tilted_north = sky(16, "horizontal_illuminance_lx", 10000);
  tilted_north["north"] = {0, 1, 0.1};
  json night = {{"type", "directional"}, {"sun", {{"latitude_deg", 40}, {"longitude_deg", -105}, {"time", "2010-06-21T23:00-07:00"}}},
                {"up", {0, 0, 1}}, {"north", {0, 1, 0}}, {"irradiance", 1}};
  json no_offset = night;
  no_offset["sun"]["time"] = "2010-06-21T12:00";
  json up_without_sun = {{"type", "directional"}, {"direction", {0, 0, -1}}, {"up", {0, 0, 1}}, {"irradiance", 1}};
  json df_grid = {{"name", "g"}, {"position", {0.5, 0.5, 0}}, {"normal", {0, 0, 1}}, {"daylight_factor", true}};
  json df_en = df_grid;
  df_en["en17037"] = {{"level", "minimum"}, {"median_external_diffuse_illuminance_lx", 14000}};
  json vsc_up = {{"name", "v"}, {"position", {0.5, 0.5, 1}}, {"normal", {0, 0, 1}}, {"vertical_sky_component", true}};
  json point_light = {{"type", "point"}, {"position", {0, 0, 5}}, {"intensity", 1}};
  const std::vector<Case> cases = {
      {with_light(sky(17, "zenith_luminance_cd_m2", 1)), "/lights/0/cie_type"},
      {with_light(sky("clear", "zenith_luminance_cd_m2", 1)), "/lights/0/cie_type: unknown sky"},
      {with_light(no_scale), "/lights/0: a sky needs its scale"},
      {with_light(two_scales), "/lights/0: two totals given"},
      {with_light(needs_sun), "/lights/0: CIE general sky type 12 depends on the sun"},
      {with_light(sun_below), "/lights/0/sun_direction: the sun must stand above the horizon"},
      {with_light(both_suns), "/lights/0: give sun_direction or sun, not both"},
      {with_light(sun_without_north), "/lights/0: missing required key 'north'"},
      {with_light(tilted_north), "/lights/0/north: must be perpendicular to up"},
      {with_light(night), "/lights/0/sun: the sun stands"},
      {with_light(no_offset), "/lights/0/sun/time"},
      {with_light(up_without_sun), "/lights/0/up: places the sun"},
      {with_light(point_light, json::array({df_grid})), "/probes/0/daylight_factor: needs the scene's one sky"},
      {scene_with(plate, json::array({sky(16, "zenith_luminance_cd_m2", 1), point_light}), json::array({df_grid})),
       "/probes/0/daylight_factor: the daylight factor is the sky's light alone"},
      {with_light(sky(16, "zenith_luminance_cd_m2", 1), json::array({df_en})), "/probes/0/en17037: EN 17037's summary is over a grid"},
      {with_light(sky(16, "zenith_luminance_cd_m2", 1), json::array({vsc_up})),
       "/probes/0/vertical_sky_component: is measured on a vertical plane"},
  };
  for (const Case& c : cases) {
    const std::string errors = errors_of(c.scene);
    EXPECT_NE(errors.find(c.expected), std::string::npos) << "expected " << c.expected << "\ngot: " << errors;
  }
}

}  // namespace
}  // namespace lambert
