// Clear glass ("transmission": "specular"): the pane's angular factor g(θ) (solver/glazing.h)
// against the Fresnel equations in their other (Snell-angle) form and Duffie & Beckman's worked
// example; through the whole solve (scene JSON → solution), a point light's rays through a pane
// against τ(λ) g(θ) I cos α / d² (one crossing at a known angle), τ = 0 against the closed room, and
// the energy certificate (transmitted + reflected + absorbed = received) by both methods.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "server/scene_codec.h"
#include "solver/glazing.h"
#include "solver/radiosity.h"
#include "solver/scene.h"
#include "tests/daylight_scenes.h"

namespace lambert {
namespace {

using nlohmann::json;
using namespace test::daylight;

double deg(double d) { return d * kPi / 180; }

// Fresnel's reflectances by the angles (Hecht, Optics, eqs. 4.42–4.43):
//   r_s = sin²(θ_t − θ) / sin²(θ_t + θ),   r_p = tan²(θ_t − θ) / tan²(θ_t + θ),   sin θ_t = sin θ / n,
// and the non-absorbing slab's ½ Σ (1 − r)/(1 + r) (Duffie & Beckman eq. 5.1.8, N = 1).
double slab_by_angles(double theta, double n) {
  const double t = std::asin(std::sin(theta) / n);
  const double rs = std::pow(std::sin(t - theta) / std::sin(t + theta), 2);
  const double rp = std::pow(std::tan(t - theta) / std::tan(t + theta), 2);
  return 0.5 * ((1 - rs) / (1 + rs) + (1 - rp) / (1 + rp));
}

TEST(PaneAngularFactor, IsTheFresnelSlabNormalisedToOneAtNormalIncidence) {
  // g(0) = 1; at normal incidence the slab passes 2n/(n² + 1) (r = ((n − 1)/(n + 1))²).
  const double n = kPaneRefractiveIndex;
  EXPECT_DOUBLE_EQ(pane_angular_factor(1.0), 1.0);
  EXPECT_NEAR(slab_transmittance(1.0, n), 2 * n / (n * n + 1), 1e-15);
  EXPECT_EQ(pane_angular_factor(0.0), 0.0);              // grazing: r_s = r_p = 1
  EXPECT_LT(pane_angular_factor(std::cos(deg(89.99))), 1e-3);
  // Either side of the pane alike.
  EXPECT_EQ(pane_angular_factor(-0.5), pane_angular_factor(0.5));
  for (const double d : {10.0, 30.0, 45.0, 60.0, 70.0, 80.0, 85.0}) {
    const double g = slab_by_angles(deg(d), n) / (2 * n / (n * n + 1));
    EXPECT_NEAR(pane_angular_factor(std::cos(deg(d))), g, 1e-13) << d;
  }
  // g falls monotonically: the shape of a pane's transmittance.
  double last = 1.0;
  for (int d = 1; d < 90; ++d) {
    const double g = pane_angular_factor(std::cos(deg(d)));
    EXPECT_LE(g, last) << d;
    last = g;
  }
}

TEST(PaneAngularFactor, MatchesDuffieAndBeckmansExample) {
  // Duffie & Beckman, Solar Engineering of Thermal Processes (4th ed.), Example 5.1.1: one
  // non-absorbing cover of n = 1.526 at 60° passes τ_r = 0.842 (θ_t = 34.6°, r_s = 0.185,
  // r_p = 0.0014); at normal incidence 0.917. To the example's three digits.
  EXPECT_NEAR(slab_transmittance(std::cos(deg(60)), 1.526), 0.842, 5e-4);
  EXPECT_NEAR(slab_transmittance(1.0, 1.526), 0.917, 5e-4);
}

TEST(PaneAngularFactor, HemisphericalMeanByAnotherQuadrature) {
  // ḡ = ∫₀¹ g du with u = sin²θ (cos θ sin θ dθ = du/2): a midpoint sum in u of 2·10⁵ cells, whose
  // error (the integrand's √(1 − u) end) is below 1e-7.
  const int cells = 200000;
  double sum = 0;
  for (int k = 0; k < cells; ++k) sum += pane_angular_factor(std::sqrt(1 - (k + 0.5) / cells));
  EXPECT_NEAR(pane_hemispherical_factor(), sum / cells, 1e-6);
  EXPECT_NEAR(pane_hemispherical_factor(), 0.92171, 1e-5);  // docs/METHOD.md's value
}

// ---- through the solve ---------------------------------------------------------------------------

Solution solve_scene(const json& scene) {
  DecodeResult decoded = decode_scene(scene.dump());
  if (!decoded.ok()) throw std::runtime_error(format_errors(decoded.errors));
  return solve(*decoded.scene);
}

const std::vector<double> kNm = {450, 550, 650};

json clear_glass(double rho, const std::vector<double>& tau) {
  return {{"reflectance", rho}, {"transmittance", {{"nm", kNm}, {"values", tau}}}, {"transmission", "specular"}};
}

// The room [0,4]×[0,4]×[0,3] of `material` with its roof opening [1.5,2.5]² at z = 3 open, or glazed
// with `glass` (front face down into the room), three wavelengths, the given lights and floor probes.
json glazed_room(const std::string& material, const std::string& glass, json lights, const std::vector<Point3>& at,
                 const std::string& method) {
  json surfaces = room_with_roof_opening(material);
  if (!glass.empty()) surfaces.push_back(rectangle("pane", glass, {1.5, 1.5, 3}, {0, 1, 0}, {1, 0, 0}));
  json probes = json::array();
  for (std::size_t k = 0; k < at.size(); ++k) probes.push_back(probe(std::string("p").append(std::to_string(k)), at[k], {0, 0, 1}));
  json scene = scene_with(surfaces, std::move(lights), probes, method);
  scene["spectrum"] = {{"mode", "spectral"}, {"wavelengths_nm", kNm}};
  return scene;
}

TEST(ClearPane, PointLightThroughItIsTauGTimesTheOpenOpening) {
  // A point source of I = 40 W sr⁻¹ nm⁻¹ at (2, 2, 5), 2 m above the opening, lights the black room's
  // floor only through it. Open: E = I cos α / d² at a floor point (cos α = 5/d, the floor facing up).
  // Glazed (ρ = 0.08, τ = 0.3, 0.8, 0.6): the ray crosses the horizontal pane at the same α from its
  // normal, E = τ(λ) g(α) I cos α / d² exactly; the pane's faces re-emit nothing onto the floor (its
  // lit face looks out, the room is black). Points from straight below (α = 0, g = 1) to α = 24°.
  const double I = 40;
  const std::vector<double> tau = {0.3, 0.8, 0.6};
  const std::vector<Point3> at = {{2, 2, 0}, {1.7, 2.2, 0}, {2.3, 1.2, 0}, {0.3, 2.6, 0}, {3.1, 3.9, 0}};
  const json lamp = json::array({{{"type", "point"}, {"position", {2, 2, 5}}, {"intensity", I}}});
  for (const std::string method : {"dense", "hierarchical"}) {
    json scene = glazed_room("black", "glass", lamp, at, method);
    scene["materials"]["glass"] = clear_glass(0.08, tau);
    const Solution sol = solve_scene(scene);
    const Solution open = solve_scene(glazed_room("black", "", lamp, at, method));
    for (std::size_t k = 0; k < at.size(); ++k) {
      const Vector3 d = Point3{2, 2, 5} - at[k];
      const double r = length(d), cos_alpha = d.z / r, E_open = I * cos_alpha / (r * r);
      const bool lit = k < 3;  // the last two see the source past the opening's rim: dark either way
      for (std::size_t w = 0; w < kNm.size(); ++w) {
        EXPECT_NEAR(open.probes[k].irradiance[w], lit ? E_open : 0.0, 1e-12 * E_open) << method << " " << k;
        const double E = lit ? tau[w] * pane_angular_factor(cos_alpha) * E_open : 0.0;
        EXPECT_NEAR(sol.probes[k].irradiance[w], E, 1e-12 * E_open) << method << " " << k << " " << w;
      }
    }
    EXPECT_LT(std::abs(sol.stats.relative_imbalance), 1e-6) << method;
  }
}

TEST(ClearPane, TauZeroIsTheClosedRoom) {
  // τ = 0: the pane is an opaque panel of its reflectance. A lamp above the roof leaves the floor
  // dark; with a lamp inside the room reads as the room whose opening an opaque panel of the same
  // reflectance closes, to the solver's tolerance.
  const json outside = json::array({{{"type", "point"}, {"position", {2, 2, 5}}, {"intensity", 40}}});
  const json inside = json::array({{{"type", "point"}, {"position", {1, 3, 2}}, {"intensity", 50}}});
  const std::vector<Point3> at = {{2, 2, 0}, {1.7, 2.2, 0}, {0.3, 3.1, 0}};
  for (const std::string method : {"dense", "hierarchical"}) {
    json dark = glazed_room("grey", "glass", outside, at, method);
    dark["materials"]["glass"] = clear_glass(0.3, {0, 0, 0});
    const Solution d = solve_scene(dark);
    for (std::size_t k = 0; k < at.size(); ++k)
      for (std::size_t w = 0; w < kNm.size(); ++w) EXPECT_EQ(d.probes[k].irradiance[w], 0.0) << method << " " << k;
    json glazed = glazed_room("grey", "glass", inside, at, method);
    glazed["materials"]["glass"] = clear_glass(0.3, {0, 0, 0});
    json closed = glazed_room("grey", "panel", inside, at, method);
    closed["materials"]["panel"] = {{"reflectance", 0.3}};
    const Solution a = solve_scene(glazed), b = solve_scene(closed);
    for (std::size_t k = 0; k < at.size(); ++k)
      for (std::size_t w = 0; w < kNm.size(); ++w) {
        const double E = b.probes[k].irradiance[w];
        EXPECT_NEAR(a.probes[k].irradiance[w], E, 1e-4 * E) << method << " " << k;
      }
  }
}

TEST(ClearPane, EnergyBalancesWithReflectingAbsorbingAndTransmittingPanes) {
  // A grey room glazed with clear glass that reflects, absorbs and transmits (ρ = 0.1, τ = 0.7),
  // lit through it by a lamp and a low sun outside and by a lamp inside (light crosses the pane
  // both ways: rays in, interreflection out): emitted = absorbed + escaped. The light the pane
  // passes by rays is computed twice, independently: from the pane (what its face transmits) and at
  // the patches it lands on; the balance holds to their ray estimates (measured: 4e-9 dense, 4e-7
  // hierarchical). Counting the rays' light as absorbed in the pane, as an opaque pane would, is off
  // by 1.4 % here. Both methods, and the dense one with meshing.adaptive (the pane's faces split
  // where their irradiance jumps, each on its own).
  const json lights = json::array({{{"type", "point"}, {"position", {2.2, 1.8, 5}}, {"intensity", 40}},
                                   {{"type", "directional"}, {"direction", {0.3, 0.2, -1}}, {"irradiance", 2}},
                                   {{"type", "point"}, {"position", {1, 3, 2}}, {"intensity", 5}}});
  for (const std::string method : {"dense", "hierarchical", "adaptive"}) {
    const bool adaptive = method == "adaptive";
    json scene = glazed_room("grey", "glass", lights, {{2, 2, 0}}, adaptive ? "dense" : method);
    scene["materials"]["glass"] = clear_glass(0.1, {0.7, 0.7, 0.7});
    scene["meshing"] = {{"max_patch_area", 0.25}, {"refine_direct", false}, {"adaptive", adaptive}};
    const Solution sol = solve_scene(scene);
    EXPECT_GT(sol.stats.absorbed_W, 0) << method;
    if (adaptive) {
      EXPECT_GT(sol.stats.dense.adaptive_rounds, 0);
    }
    EXPECT_LT(std::abs(sol.stats.relative_imbalance), 1e-5) << method << ": " << sol.stats.emitted_W << " W emitted, "
                                                            << sol.stats.absorbed_W << " absorbed, "
                                                            << sol.stats.escaped_W << " escaped";
  }
}

// E = τ L_z ∫_{opening} (L/L_z)(ω) g(cos θ) cos θ dω at a floor point p under a roof opening at height
// h (θ from the vertical, the pane's normal and the floor's; dω = h dA / r³, cos θ = h / r), by the
// midpoint rule over a 400 × 400 grid of the opening: another method than the solver's (the visible
// part's fan cubature, sky_dome.h), its error about 2e-7 (Δ²/24 times the integrand's curvature).
double through_roof_opening(const Point3& p, double h, bool overcast) {
  const int cells = 400;
  const double lo = 1.5, side = 1.0, dA = side * side / (cells * cells);
  double sum = 0;
  for (int a = 0; a < cells; ++a)
    for (int b = 0; b < cells; ++b) {
      const double x = lo + (a + 0.5) * side / cells - p.x, y = lo + (b + 0.5) * side / cells - p.y;
      const double r2 = x * x + y * y + h * h, c = h / std::sqrt(r2);
      const double L = overcast ? (1 + 2 * c) / 3 : 1.0;  // CIE overcast: (1 + 2 sin γ)/3, sin γ = cos θ
      sum += L * pane_angular_factor(c) * h * h / (r2 * r2) * dA;  // L g cos θ · h dA / r³
    }
  return sum;
}

TEST(ClearPane, SkyThroughAGlazedRoofOpeningIsTheOpeningWeightedByTauG) {
  // The black room's roof opening glazed with clear glass (ρ = 0.1, τ = 0.7): the floor reads
  // τ L_z ∫ (L/L_z) g cos dω over the opening (through_roof_opening), under the uniform sky and the
  // CIE overcast sky, by both methods, to 1e-6 (measured: 2.5e-7, the midpoint rule's error); the
  // pane's faces re-emit nothing onto the floor (the room is black). The energy certificate balances.
  const double Lz = 2000;
  const std::vector<Point3> at = {{2, 2, 0}, {1.7, 2.2, 0}, {0.3, 3.1, 0}, {3.9, 0.2, 0}};
  for (const std::string method : {"dense", "hierarchical"})
    for (const bool overcast : {false, true}) {
      json scene = glazed_room("black", "glass",
                               json::array({sky(overcast ? json(16) : json("uniform"), "zenith_luminance_cd_m2", Lz)}),
                               at, method);
      scene.erase("spectrum");  // the default grid: lux are τ times the sky's
      scene["materials"]["glass"] = {{"reflectance", 0.1}, {"transmittance", 0.7}, {"transmission", "specular"}};
      const json result = solve_json(scene);
      for (std::size_t k = 0; k < at.size(); ++k) {
        const double E = 0.7 * Lz * through_roof_opening(at[k], 3, overcast);
        EXPECT_NEAR(result["probes"][k]["illuminance_lx"].get<double>(), E, 1e-6 * E)
            << method << " " << overcast << " " << k;
      }
      EXPECT_LT(std::abs(result["stats"]["energy"]["relative_imbalance"].get<double>()), 1e-6) << method;
    }
}

TEST(ClearPane, OvercastSkyThroughAGlazedFacadeWindow) {
  // A clear pane (τ = 0.7) in the west wall's window x = 0, y ∈ [1, 3], z ∈ [1, 2] of the black room;
  // a work-plane probe at p = (1.5, 2, 0.8) facing up sees the sky through it only (every direction
  // through the window rises). With ω = d/r, d = y − p over the window's points y:
  //   E = τ L_z ∫ (1 + 2 ω_z)/3 · g(|ω_x|) · ω_z · 1.5 dA / r³
  // (CIE overcast, sin γ = ω_z; g of the angle to the pane's normal x, not to the probe's), by the
  // midpoint rule over an 800 × 400 grid (measured: 7e-7 from the solver's, the rule's error).
  const double Lz = 3000, tau = 0.7;
  const Point3 p{1.5, 2, 0.8};
  json walls = json::array({rectangle("floor", "black", {0, 0, 0}, {4, 0, 0}, {0, 4, 0}),
                            rectangle("ceiling", "black", {0, 0, 3}, {0, 4, 0}, {4, 0, 0}),
                            rectangle("west below", "black", {0, 0, 0}, {0, 0, 1}, {0, 4, 0}),
                            rectangle("west above", "black", {0, 0, 2}, {0, 0, 1}, {0, 4, 0}),
                            rectangle("west south", "black", {0, 0, 1}, {0, 0, 1}, {0, 1, 0}),
                            rectangle("west north", "black", {0, 3, 1}, {0, 0, 1}, {0, 1, 0}),
                            rectangle("window", "glass", {0, 1, 1}, {0, 0, 1}, {0, 2, 0}),
                            rectangle("east", "black", {4, 0, 0}, {0, 4, 0}, {0, 0, 3}),
                            rectangle("south", "black", {0, 0, 0}, {4, 0, 0}, {0, 0, 3}),
                            rectangle("north", "black", {0, 4, 0}, {0, 0, 3}, {4, 0, 0})});
  json scene = scene_with(walls, json::array({sky(16, "zenith_luminance_cd_m2", Lz)}),
                          json::array({probe("desk", p, {0, 0, 1})}));
  scene["materials"]["glass"] = {{"reflectance", 0.08}, {"transmittance", tau}, {"transmission", "specular"}};
  const json result = solve_json(scene);
  const int nu = 800, nv = 400;
  double sum = 0;
  for (int a = 0; a < nu; ++a)
    for (int b = 0; b < nv; ++b) {
      const Vector3 d = Point3{0, 1 + 2.0 * (a + 0.5) / nu, 1 + (b + 0.5) / nv} - p;
      const double r = length(d);
      const Vector3 w = d / r;
      sum += (1 + 2 * w.z) / 3 * pane_angular_factor(std::abs(w.x)) * w.z * 1.5 / (r * r * r) * (2.0 / nu) * (1.0 / nv);
    }
  const double E = tau * Lz * sum;
  EXPECT_NEAR(result["probes"][0]["illuminance_lx"].get<double>(), E, 1e-5 * E);
}

TEST(Panes, InRgbModeFilterAsAReflectanceOfTheSameSpectrum) {
  // rgb mode reduces a pane's τ(λ) as it reduces a reflectance: a pane of τ(λ) (ρ = 0) and an opaque
  // tile of reflectance τ(λ) side by side under a vertical beam E give, per channel, B_back = τ_c E_c
  // (opal) and, at a probe below, τ_c g(0) E_c = τ_c E_c (clear), both equal to the tile's
  // B = O_c E_c. τ rises from 0.2 at 380 nm to 0.8 at 780 nm, so its three channels differ.
  const json tau = {{"nm", {380, 780}}, {"values", {0.2, 0.8}}};
  for (const std::string kind : {"diffuse", "specular"}) {
    json scene = {{"spectrum", {{"mode", "rgb"}}},
                  {"materials",
                   {{"pane", {{"reflectance", 0}, {"transmittance", tau}, {"transmission", kind}}},
                    {"tile", {{"reflectance", tau}}}}},
                  {"surfaces", json::array({rectangle("pane", "pane", {-1, -1, 0}, {2, 0, 0}, {0, 2, 0}),
                                            rectangle("tile", "tile", {5, -1, 0}, {2, 0, 0}, {0, 2, 0})})},
                  {"lights", json::array({{{"type", "directional"}, {"direction", {0, 0, -1}}, {"irradiance", 3}}})},
                  {"probes", json::array({probe("below", {0, 0, -1e-3}, {0, 0, 1})})},
                  {"meshing", {{"max_patch_area", 4}, {"refine_direct", false}}}};
    const Solution sol = solve_scene(scene);
    ASSERT_EQ(sol.wavelengths(), 3u);
    std::vector<double> tile(3, -1), back(3, -1);
    for (std::size_t i = 0; i < sol.patches.size(); ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        if (sol.patches[i].surface == 1) tile[c] = sol.radiosity[i * 3 + c];
        if (sol.patches[i].surface == 0 && sol.patches[i].normal.z < 0) back[c] = sol.radiosity[i * 3 + c];
      }
    EXPECT_GT(tile[0], 1.5 * tile[2]) << kind;  // red passes more than blue
    for (std::size_t c = 0; c < 3; ++c) {
      if (kind == "diffuse") {
        EXPECT_NEAR(back[c], tile[c], 1e-12) << c;
      }
      // Clear: the probe 1 mm below the pane's centre takes the beam through it, and nothing of the
      // pane's back face (which passes on only interreflected light: none here).
      if (kind == "specular") {
        EXPECT_NEAR(sol.probes[0].irradiance[c], tile[c], 1e-12) << c;
      }
    }
  }
}

TEST(ClearPane, PerSourceContributionsAddUpThroughIt) {
  // output.per_source: each source's light through the pane is its own, and the contributions add up
  // to the joint solution (the radiosity equation is linear in the sources), at the probes and the
  // patches, to the solver's tolerance (set to 1e-10: each system is solved on its own); the lamp
  // outside reaches the floor only through the pane.
  const json lights = json::array({{{"type", "point"}, {"position", {2.2, 1.8, 5}}, {"intensity", 40}},
                                   {{"type", "directional"}, {"direction", {0.3, 0.2, -1}}, {"irradiance", 2}}});
  const std::vector<Point3> at = {{2, 2, 0}, {1.7, 2.2, 0}};
  json scene = glazed_room("grey", "glass", lights, at, "dense");
  scene["materials"]["glass"] = clear_glass(0.1, {0.3, 0.8, 0.6});
  scene["output"] = {{"per_source", true}};
  scene["solver"]["tolerance"] = 1e-10;
  const Solution sol = solve_scene(scene);
  ASSERT_EQ(sol.contributions.size(), 2u);
  const std::size_t W = kNm.size();
  for (std::size_t k = 0; k < at.size(); ++k)
    for (std::size_t w = 0; w < W; ++w) {
      const double sum = sol.contributions[0].probes[k].irradiance[w] + sol.contributions[1].probes[k].irradiance[w];
      EXPECT_GT(sol.contributions[0].probes[k].irradiance[w], 0) << k << " " << w;
      EXPECT_NEAR(sum, sol.probes[k].irradiance[w], 1e-8 * sol.probes[k].irradiance[w]) << k << " " << w;
    }
  for (std::size_t i = 0; i < sol.patches.size() * W; ++i)
    EXPECT_NEAR(sol.contributions[0].radiosity[i] + sol.contributions[1].radiosity[i], sol.radiosity[i],
                1e-8 * sol.radiosity[i])
        << i;
}

TEST(ClearPane, LightThroughItDrivesTheDirectRefinement) {
  // meshing.refine_direct splits patches where the direct light jumps: the edge of the lamp's light
  // through the roof window on the floor of the black room. With τ = 0 the floor stays dark and only
  // the pane's lit face differs from its neighbours, so clear glass refines strictly more.
  const json lamp = json::array({{{"type", "point"}, {"position", {2, 2, 5}}, {"intensity", 40}}});
  std::size_t refined[2] = {0, 0};
  for (const int clear : {0, 1}) {
    json scene = glazed_room("black", "glass", lamp, {{2, 2, 0}}, "dense");
    scene["materials"]["glass"] = clear_glass(0.1, std::vector<double>(3, clear ? 0.8 : 0.0));
    scene["meshing"] = {{"max_patch_area", 0.25}, {"refine_direct", true}};
    refined[clear] = solve_scene(scene).stats.direct_refinement_patches;
  }
  EXPECT_GT(refined[1], refined[0]);
}

TEST(ClearPane, WhatItDoesNotTakeIsRefusedByName) {
  // A sky through clear panes of one material in two orientations (g is weighted by one normal per
  // material over the window): refused at the material, naming the surface.
  json scene = glazed_room("black", "glass", json::array({sky(16, "horizontal_illuminance_lx", 10000)}), {}, "dense");
  scene["materials"]["glass"] = clear_glass(0.1, {0.7, 0.7, 0.7});
  scene["surfaces"].push_back(rectangle("window", "glass", {4.5, 1, 1}, {0, 1, 0}, {0, 0, 1}));
  const DecodeResult decoded = decode_scene(scene.dump());
  ASSERT_FALSE(decoded.ok());
  const std::string errors = format_errors(decoded.errors);
  EXPECT_NE(errors.find("/materials/glass/transmission: "), std::string::npos) << errors;
  EXPECT_NE(errors.find("/surfaces/10"), std::string::npos) << errors;
  // A ray through two panes (a second sheet 0.5 m above the first): τ(λ)² is not one channel's τ.
  json twice = glazed_room("black", "glass", json::array({{{"type", "point"}, {"position", {2, 2, 5}}, {"intensity", 4}}}),
                           {{2, 2, 0}}, "dense");
  twice["materials"]["glass"] = clear_glass(0.1, {0.7, 0.7, 0.7});
  twice["surfaces"].push_back(rectangle("outer pane", "glass", {1.5, 1.5, 3.5}, {0, 1, 0}, {1, 0, 0}));
  try {
    solve_scene(twice);
    ADD_FAILURE() << "a ray through two panes was not refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("two specular panes, surfaces 'pane' and 'outer pane'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace lambert
