// Glazing through the whole solve (scene JSON → solution): panes of zero thickness with a
// transmittance (solver/pipeline/panes.h) against closed forms (a pane lit on one side passes
// B = τ E out of its other face; the uniform sky through a roof opening, Howell B-3), against the
// same room without the pane or with an opaque panel in its place (τ = 1 is the open opening, τ = 0
// the closed room), and against the energy certificate (transmitted + reflected + absorbed =
// received), by both methods.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "server/scene_codec.h"
#include "solver/pipeline/geometric.h"
#include "solver/radiosity.h"
#include "solver/thermal/view_factors.h"
#include "tests/daylight_scenes.h"
#include "tests/test_geometry.h"

namespace lambert {
namespace {

using nlohmann::json;
using namespace test::daylight;

Solution solve_scene(const json& scene) {
  DecodeResult decoded = decode_scene(scene.dump());
  if (!decoded.ok()) throw std::runtime_error(format_errors(decoded.errors));
  return solve(*decoded.scene);
}

// A room [0,4]×[0,4]×[0,3] of `material` whose roof opening [1.5,2.5]² at z = 3 is open, or closed by
// a panel of `panel_material` facing down into the room.
json roof_room(const std::string& material, const std::string& panel_material = "") {
  json s = room_with_roof_opening(material);
  if (!panel_material.empty()) s.push_back(rectangle("pane", panel_material, {1.5, 1.5, 3}, {0, 1, 0}, {1, 0, 0}));
  return s;
}

json pane_material(double rho, json tau, const std::string& kind = "diffuse") {
  return {{"reflectance", rho}, {"transmittance", std::move(tau)}, {"transmission", kind}};
}

json floor_probes(const std::vector<Point3>& points) {
  json probes = json::array();
  for (std::size_t k = 0; k < points.size(); ++k) probes.push_back(probe(std::string("p").append(std::to_string(k)), points[k], {0, 0, 1}));
  return probes;
}

const std::vector<Point3> kFloorPoints = {{2, 2, 0}, {1.7, 2.2, 0}, {0.3, 3.1, 0}, {3.9, 0.2, 0}};

// ---- diffuse panes ------------------------------------------------------------------------------

TEST(DiffusePane, LitOnOneSidePassesTauEOutOfTheOther) {
  // A lone horizontal pane (front up) under a vertical beam of irradiance E: the front receives E and
  // nothing else, the back nothing, so B_front = ρ E and B_back = τ E exactly at every wavelength
  // (no other surface: H_back = 0). A probe 1 m below its centre, facing up, reads
  // E_p = τ E F(p → pane) (Howell B-3 by corner decomposition), by both methods.
  const double E = 3.0, rho = 0.08;
  const std::vector<double> nm = {450, 550, 650}, tau = {0.3, 0.8, 0.6};
  for (const std::string method : {"dense", "hierarchical"}) {
    json scene = {{"spectrum", {{"mode", "spectral"}, {"wavelengths_nm", nm}}},
                  {"materials", {{"opal", pane_material(rho, {{"nm", nm}, {"values", tau}})}}},
                  {"surfaces", json::array({rectangle("pane", "opal", {-1, -1, 0}, {2, 0, 0}, {0, 2, 0})})},
                  {"lights", json::array({{{"type", "directional"}, {"direction", {0, 0, -1}}, {"irradiance", E}}})},
                  {"probes", json::array({probe("below", {0.3, 0.2, -1}, {0, 0, 1})})},
                  {"meshing", {{"max_patch_area", 0.3}}},
                  {"solver", {{"method", method}}}};
    const Solution sol = solve_scene(scene);
    const std::size_t W = sol.wavelengths();
    ASSERT_EQ(W, 3u);
    int fronts = 0, backs = 0;
    for (std::size_t i = 0; i < sol.patches.size(); ++i) {
      const bool front = sol.patches[i].normal.z > 0;
      (front ? fronts : backs)++;
      for (std::size_t w = 0; w < W; ++w)
        EXPECT_NEAR(sol.radiosity[i * W + w], front ? rho * E : tau[w] * E, 1e-12) << method << " " << i << " " << w;
    }
    EXPECT_GT(fronts, 0) << method;
    EXPECT_GT(backs, 0) << method;
    // The point 1 m below (0.3, 0.2): the pane [-1,1]² seen from it, Howell B-3.
    const double F = test::point_under_rectangle(0.3, 0.2, 1, -1, 1, -1, 1);
    for (std::size_t w = 0; w < W; ++w)
      EXPECT_NEAR(sol.probes[0].irradiance[w], tau[w] * E * F, 1e-9) << method << " " << w;
    // Received E·A on the front = reflected ρ E A + transmitted τ E A + absorbed (1 − ρ − τ) E A.
    EXPECT_LT(std::abs(sol.stats.relative_imbalance), 1e-9) << method;
  }
}

TEST(DiffusePane, TauOneUnderTheUniformSkyIsTheOpenRoofOpening) {
  // Under the uniform sky of luminance L the back face of a horizontal pane receives π L, and a pane
  // with τ = 1, ρ = 0 sends it on as a Lambertian emitter of luminance L: exactly the open opening
  // seen from below, E = π L F(p → opening) (Howell B-3) at the floor of a black room. With τ(λ) the
  // floor reads τ times that. By both methods.
  const double L = 2000;
  for (const std::string method : {"dense", "hierarchical"}) {
    for (const double tau : {1.0, 0.55}) {
      json scene = scene_with(roof_room("black", "glass"), json::array({sky("uniform", "zenith_luminance_cd_m2", L)}),
                              floor_probes(kFloorPoints), method);
      scene["materials"]["glass"] = pane_material(0, tau);
      const json result = solve_json(scene);
      for (std::size_t k = 0; k < kFloorPoints.size(); ++k) {
        const Point3& p = kFloorPoints[k];
        const double E = tau * kPi * L * test::point_under_rectangle(p.x, p.y, 3, 1.5, 2.5, 1.5, 2.5);
        EXPECT_NEAR(result["probes"][k]["illuminance_lx"].get<double>(), E, 1e-9 * E) << method << " " << tau << " " << k;
      }
    }
  }
}

TEST(DiffusePane, TauOneInAGreyRoomIsTheOpenOpeningWithItsInterreflections) {
  // A grey room (ρ = 0.5): light inside that reaches a τ = 1, ρ = 0 pane leaves through its back face
  // to the empty sky as it would through the opening, so the two rooms are the same to the
  // discretisation (the open room's patches take the sky exactly, the glazed room's through the
  // pane's patches' factors): the floor probes agree to 0.5 %.
  const double L = 2000;
  const json open = solve_json(scene_with(roof_room("grey"), json::array({sky("uniform", "zenith_luminance_cd_m2", L)}),
                                          floor_probes(kFloorPoints)));
  json glazed_scene = scene_with(roof_room("grey", "glass"), json::array({sky("uniform", "zenith_luminance_cd_m2", L)}),
                                 floor_probes(kFloorPoints));
  glazed_scene["materials"]["glass"] = pane_material(0, 1.0);
  const json glazed = solve_json(glazed_scene);
  for (std::size_t k = 0; k < kFloorPoints.size(); ++k) {
    const double E = open["probes"][k]["illuminance_lx"].get<double>();
    EXPECT_NEAR(glazed["probes"][k]["illuminance_lx"].get<double>(), E, 5e-3 * E) << k;
  }
}

TEST(DiffusePane, TauZeroIsTheClosedRoom) {
  // τ = 0: the pane is an opaque panel of its reflectance. Under the sky alone the room stays dark
  // (to round-off: 1e-11 of the 10 000 lx outside; the hierarchical method's cluster sums leave
  // about 5e-9 lx); with a lamp inside it reads as the room whose opening an opaque panel of the same
  // reflectance closes, to the solver's tolerance.
  const json lamp = {{"type", "point"}, {"position", {1, 3, 2}}, {"intensity", 50}};
  for (const std::string method : {"dense", "hierarchical"}) {
    json dark = scene_with(roof_room("grey", "glass"), json::array({sky(16, "horizontal_illuminance_lx", 10000)}),
                           floor_probes(kFloorPoints), method);
    dark["materials"]["glass"] = pane_material(0.3, 0.0);
    const json dark_result = solve_json(dark);
    for (std::size_t k = 0; k < kFloorPoints.size(); ++k)
      EXPECT_LT(std::abs(dark_result["probes"][k]["illuminance_lx"].get<double>()), 1e-11 * 10000) << method << " " << k;

    json glazed = scene_with(roof_room("grey", "glass"), json::array({lamp}), floor_probes(kFloorPoints), method);
    glazed["materials"]["glass"] = pane_material(0.3, 0.0);
    json closed = scene_with(roof_room("grey", "panel"), json::array({lamp}), floor_probes(kFloorPoints), method);
    closed["materials"]["panel"] = {{"reflectance", 0.3}};
    const json a = solve_json(glazed), b = solve_json(closed);
    for (std::size_t k = 0; k < kFloorPoints.size(); ++k) {
      const double E = b["probes"][k]["illuminance_lx"].get<double>();
      EXPECT_NEAR(a["probes"][k]["illuminance_lx"].get<double>(), E, 1e-4 * E) << method << " " << k;
    }
  }
}

TEST(DiffusePane, EnergyBalancesWithReflectingAbsorbingAndTransmittingPanes) {
  // A grey room glazed with a pane that reflects, absorbs and transmits (ρ = 0.1, τ = 0.7), lit by the
  // overcast sky outside and a lamp inside (light crosses the pane both ways): emitted = absorbed +
  // escaped, with each face absorbing (1 − ρ − τ) of what it receives. Counting transmitted light as
  // absorbed (1 − ρ) would be off by the transmitted share, several % of the total. Both methods;
  // meshing refines along the direct light, so the pane's faces are meshed differently.
  for (const std::string method : {"dense", "hierarchical"}) {
    json scene = scene_with(roof_room("grey", "glass"),
                            json::array({sky(16, "horizontal_illuminance_lx", 10000),
                                         {{"type", "point"}, {"position", {1, 3, 2}}, {"intensity", 500}}}),
                            floor_probes(kFloorPoints), method);
    scene["materials"]["glass"] = pane_material(0.1, 0.7);
    scene["meshing"] = {{"max_patch_area", 0.25}, {"refine_direct", true}};
    const Solution sol = solve_scene(scene);
    EXPECT_GT(sol.stats.absorbed_W, 0) << method;
    EXPECT_LT(std::abs(sol.stats.relative_imbalance), 2e-3) << method << ": " << sol.stats.emitted_W << " W emitted, "
                                                            << sol.stats.absorbed_W << " absorbed, "
                                                            << sol.stats.escaped_W << " escaped";
  }
}

TEST(DiffusePane, ViewFactorsTakeThePaneAsGiven) {
  // View factors and radiant exchange are opaque and grey: a pane is the face it was given, not two.
  // A unit cube room glazed at its ceiling: the ceiling's area is 1 m² and its factor to the floor
  // is Howell C-11's 0.1998248957 (X = Y = 1), as in the opaque room.
  json surfaces = json::array({rectangle("floor", "black", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}),
                               rectangle("ceiling", "glass", {0, 0, 1}, {0, 1, 0}, {1, 0, 0}),
                               rectangle("south", "black", {0, 0, 0}, {0, 0, 1}, {1, 0, 0}),
                               rectangle("north", "black", {0, 1, 0}, {1, 0, 0}, {0, 0, 1}),
                               rectangle("west", "black", {0, 0, 0}, {0, 1, 0}, {0, 0, 1}),
                               rectangle("east", "black", {1, 0, 0}, {0, 0, 1}, {0, 1, 0})});
  json scene = scene_with(surfaces, json::array(), json::array());
  scene["materials"]["glass"] = pane_material(0.1, 0.6);
  scene["meshing"] = {{"max_patch_area", 0.01}, {"refine_direct", false}};
  DecodeResult decoded = decode_scene(scene.dump());
  ASSERT_TRUE(decoded.ok()) << format_errors(decoded.errors);
  const GeometricOperator g = build_geometric_operator(*decoded.scene, {});
  const ViewFactorMatrix m = surface_view_factors(*g.op, SurfaceGroups::each_surface(*decoded.scene));
  ASSERT_EQ(m.size(), 6u);
  EXPECT_NEAR(m.area_m2[1], 1.0, 1e-12);
  EXPECT_NEAR(m.at(1, 0), test::howell_c11(1, 1), 1e-7);
}

TEST(GlazingInput, ErrorsNameTheField) {
  auto errors = [](json material) {
    json scene = scene_with(json::array({rectangle("pane", "glass", {0, 0, 0}, {1, 0, 0}, {0, 1, 0})}), json::array(),
                            json::array());
    scene["materials"]["glass"] = std::move(material);
    const DecodeResult decoded = decode_scene(scene.dump());
    return decoded.ok() ? std::string() : format_errors(decoded.errors);
  };
  EXPECT_NE(errors({{"reflectance", 0.5}, {"transmittance", 0.6}, {"transmission", "diffuse"}})
                .find("/materials/glass/transmittance"),
            std::string::npos);
  EXPECT_NE(errors({{"reflectance", 0.1}, {"transmittance", 0.6}}).find("/materials/glass"), std::string::npos);
  EXPECT_NE(errors({{"reflectance", 0.1}, {"transmittance", 0.6}, {"transmission", "frosted"}})
                .find("/materials/glass/transmission"),
            std::string::npos);
  EXPECT_NE(errors({{"reflectance", 0.1}, {"transmission", "diffuse"}}).find("/materials/glass/transmission"),
            std::string::npos);
  EXPECT_EQ(errors({{"reflectance", 0.1}, {"transmittance", 0.6}, {"transmission", "specular"}}), "");
  EXPECT_EQ(errors({{"reflectance", 0.1}, {"transmittance", 0.6}, {"transmission", "diffuse"}}), "");
}

}  // namespace
}  // namespace lambert
