// Every light model against its closed form (../shared/REFERENCES.md §4, P1–P9): irradiance at points,
// the flux a closed black room receives (= the source's flux), patch averages for narrow lobes
// (cos^10⁴, cos^10⁶), for sources 1 µm above a surface and for spot cutoffs across a patch, and the
// Phong-lobed area emitter (power R·A; n = 1 equals the Lambertian form-factor path). Where no closed
// form exists the reference is a second, independent estimator (the Lambert contour formula, adaptive
// area cubature, a tensor Gauss–Legendre rule), computed at 30 digits with mpmath where noted.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numeric>
#include <random>

#include "solver/cubature.h"
#include "solver/form_factor.h"
#include "solver/light_model.h"
#include "solver/lights/axial_moments.h"
#include "solver/lights/point_like.h"
#include "solver/radiosity.h"
#include "tests/scene_builder.h"

namespace lambert {
namespace {

using test::box;
using test::rectangle;
using test::SceneBuilder;

constexpr Vector3 kDown{0, 0, -1};
constexpr Vector3 kUp{0, 0, 1};

PointLight point_source(PointLight::Kind kind, const Point3& position, double I0, double m = 0,
                        const Vector3& axis = kDown, double cutoff_rad = kPi) {
  PointLight l;
  l.kind = kind;
  l.position = position;
  l.axis = axis;
  l.exponent = kind == PointLight::Kind::Warn ? 1 : m;
  l.cutoff_rad = cutoff_rad;
  l.intensity_W_sr_nm = {I0};
  return l;
}

// E at a floor point (x, 0, 0) facing up, unshadowed.
double floor_E(const Light& light, double x) {
  const auto model = make_light_model(light);
  return model->unshadowed_factor({x, 0, 0}, kUp) * model->spectrum()[0];
}

void add_light(SceneBuilder& b, const Light& light) {
  b.scene().lights.push_back(light);
  b.scene().light_pointers.push_back("/lights/" + std::to_string(b.scene().lights.size() - 1));
}

// Σ A_i g_i over one surface's patches (the flux it receives, per unit of the spectrum at w = 0).
double surface_flux(const Solution& sol, int surface, const std::vector<double>& values) {
  double sum = 0;
  for (std::size_t i = 0; i < sol.patches.size(); ++i)
    if (sol.patches[i].surface == surface) sum += sol.patches[i].area_m2 * values[i * sol.wavelengths()];
  return sum;
}
double total_flux(const Solution& sol, const std::vector<double>& values) {
  double sum = 0;
  for (std::size_t i = 0; i < sol.patches.size(); ++i) sum += sol.patches[i].area_m2 * values[i * sol.wavelengths()];
  return sum;
}

// The 1 x 1 floor [-0.5, 0.5]² at z = 0, facing up.
std::vector<Triangle> unit_floor() { return rectangle({-0.5, -0.5, 0}, {1, 0, 0}, {0, 1, 0}); }

// Flux onto each triangle from a model (patch average × area), with the triangles as occluders.
std::vector<double> triangle_fluxes(const LightModel& model, const std::vector<Triangle>& triangles) {
  const Visibility vis(triangles);
  std::vector<double> out;
  for (const Triangle& t : triangles) out.push_back(model.patch_factor(t, vis) * t.area());
  return out;
}
double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

// ---- at points ----------------------------------------------------------------------------------

TEST(Lights, P1IsotropicPointAtPoints) {
  // E = I h / d³, I = 100 cd, h = 2.
  const Light l = point_source(PointLight::Kind::Point, {0, 0, 2}, 100);
  for (const auto& [x, E] : {std::pair{0.0, 25.0}, {1.0, 17.88854382}, {2.0, 8.838834765}, {3.0, 4.266924586},
                             {5.0, 1.280657505}})
    EXPECT_NEAR(floor_E(l, x), E, 1e-9 * E) << "x=" << x;
  EXPECT_DOUBLE_EQ(make_light_model(l)->flux_factor(), 4 * kPi);
}

TEST(Lights, P2CosineLobeTableAndFlux) {
  // E = I0 (h/d)^m h/d³ with I0 = 100, h = 2, aimed straight down; Φ = 2π I0/(m+1).
  struct Row { double m, flux, e0, e05, e1, e2; };
  for (const Row& r : {Row{1, 314.1592654, 25.0, 22.14532872, 16.0, 6.25},
                       Row{2, 209.4395102, 25.0, 21.48412457, 14.31083506, 4.419417382},
                       Row{5, 104.7197551, 25.0, 19.61662336, 10.24, 1.5625},
                       Row{10, 57.11986643, 25.0, 16.8578392, 5.861718039, 0.2762135864},
                       Row{50, 12.31997119, 25.0, 5.014448006, 0.06758100781, 2.634178032e-7}}) {
    const Light l = point_source(PointLight::Kind::Goniometric, {0, 0, 2}, 100, r.m);
    EXPECT_NEAR(floor_E(l, 0), r.e0, 1e-9 * r.e0) << "m=" << r.m;
    EXPECT_NEAR(floor_E(l, 0.5), r.e05, 1e-9 * r.e05) << "m=" << r.m;
    EXPECT_NEAR(floor_E(l, 1), r.e1, 1e-9 * r.e1) << "m=" << r.m;
    EXPECT_NEAR(floor_E(l, 2), r.e2, 1e-9 * r.e2) << "m=" << r.m;
    EXPECT_NEAR(100 * make_light_model(l)->flux_factor(), r.flux, 1e-9 * r.flux) << "m=" << r.m;
  }
  // m = 0 is a uniform hemisphere (Φ = 2π I0), not the isotropic point: zero behind the source.
  const Light flat = point_source(PointLight::Kind::Goniometric, {0, 0, 2}, 100, 0);
  EXPECT_NEAR(floor_E(flat, 1), 17.88854382, 1e-8);
  EXPECT_EQ(make_light_model(flat)->unshadowed_factor({1, 0, 3}, kDown), 0.0);
  EXPECT_DOUBLE_EQ(make_light_model(flat)->flux_factor(), 2 * kPi);
  // Warn's source is the m = 1 row; the lobe is zero behind the source (ψ > 90°).
  const Light warn = point_source(PointLight::Kind::Warn, {0, 0, 2}, 100);
  EXPECT_NEAR(floor_E(warn, 0.5), 22.14532872, 1e-8);
  EXPECT_EQ(make_light_model(warn)->unshadowed_factor({0, 0, 3}, kDown), 0.0);
}

TEST(Lights, P3TiltedCos4) {
  // Source at (0,0,2), axis (1,0,-1)/√2, I0 = 100: the source's axis and the receiver's normal differ.
  const Light l = point_source(PointLight::Kind::Goniometric, {0, 0, 2}, 100, 4,
                               normalize(Vector3{1, 0, -1}));
  for (const auto& [x, E] : {std::pair{0.0, 6.25}, {1.0, 14.48972049}, {2.0, 8.838834765}, {3.0, 3.945011637}})
    EXPECT_NEAR(floor_E(l, x), E, 1e-9 * E) << "x=" << x;
}

TEST(Lights, P4SpotAtPointsAndFlux) {
  // Flat spot (m = 0), I0 = 100, cutoff 30°, h = 2: E = I0 h/d³ inside the cone, 0 beyond;
  // Φ = 2π I0 (1 − cos 30°) = 84.17872145 lm.
  const Light l = point_source(PointLight::Kind::Spot, {0, 0, 2}, 100, 0, kDown, 30 * kPi / 180);
  EXPECT_NEAR(floor_E(l, 1), 17.88854382, 1e-8);   // ψ = 26.57°
  EXPECT_NEAR(floor_E(l, 1.15), 16.28757732, 1e-8);  // ψ = 29.90°
  EXPECT_EQ(floor_E(l, 1.2), 0.0);                   // ψ = 30.96°
  EXPECT_NEAR(100 * make_light_model(l)->flux_factor(), 84.17872145, 1e-8);
  // cos^m inside the cone: Φ = 2π I0 (1 − cos^{m+1} ψc)/(m+1); m = 20, ψc = 30°: 28.46076693 lm.
  const Light lobed = point_source(PointLight::Kind::Spot, {0, 0, 2}, 100, 20, kDown, 30 * kPi / 180);
  EXPECT_NEAR(100 * make_light_model(lobed)->flux_factor(), 28.46076693, 1e-8);
  EXPECT_NEAR(floor_E(lobed, 1), 100 * std::pow(2 / std::sqrt(5.0), 20) * 2 / std::pow(5.0, 1.5), 1e-9);
}

TEST(Lights, P5Directional) {
  // E = E_perp max(0, cos α), E_perp = 1000; the beam travels straight down.
  const Light l = DirectionalLight{kDown, {1000}, std::nullopt};
  const auto model = make_light_model(l);
  for (const auto& [deg, E] : {std::pair{0.0, 1000.0}, {30.0, 866.0254038}, {60.0, 500.0}, {89.0, 17.45240644},
                               {90.0, 0.0}, {120.0, 0.0}}) {
    const double a = deg * kPi / 180;
    EXPECT_NEAR(1000 * model->unshadowed_factor({0, 0, 0}, {std::sin(a), 0, std::cos(a)}), E, 1e-7) << deg;
  }
  EXPECT_EQ(model->flux_factor(), 0.0);
}

TEST(Lights, AmbientIsConstant) {
  const auto model = make_light_model(AmbientLight{{0.5}});
  EXPECT_EQ(model->unshadowed_factor({1, 2, 3}, kUp), 1.0);
  EXPECT_EQ(model->unshadowed_factor({1, 2, 3}, kDown), 1.0);
  EXPECT_EQ(model->flux_factor(), 0.0);
}

TEST(Lights, AttenuationPolynomialAtAPoint) {
  // E = I cos α / (c1 + c2 r + c3 r²): I = 100 at (0,0,2), floor point (1.5, 0, 0): r = 2.5,
  // cos α = 0.8, c = (1, 0.5, 0.25): 80 / (1 + 1.25 + 1.5625) = 20.98360656.
  PointLight l = point_source(PointLight::Kind::Point, {0, 0, 2}, 100);
  l.inverse_square = false;
  l.attenuation = {1, 0.5, 0.25};
  EXPECT_NEAR(floor_E(l, 1.5), 20.98360656, 1e-8);
}

// ---- flux into a closed black room (the source's flux) --------------------------------------------

TEST(Lights, ClosedBlackRoomReceivesTheSourceFlux) {
  // A 4 x 4 x 3 m black room around a 10 000 lm source receives 10 000 lm (REFERENCES R5 with ρ = 0),
  // for every model: I0 = Φ / flux_factor with flux_factor 4π, 2π/(m+1), 2π(1 − cos^{m+1} ψc)/(m+1).
  const Point3 centre{2, 2, 1.5};
  const double c30 = std::cos(kPi / 6), c40 = std::cos(40 * kPi / 180);
  struct Case { const char* name; PointLight light; };
  const std::vector<Case> cases = {
      {"isotropic", point_source(PointLight::Kind::Point, centre, 10000 / (4 * kPi))},
      {"cos^5 tilted", point_source(PointLight::Kind::Goniometric, centre, 10000 * 6 / (2 * kPi), 5,
                                    normalize(Vector3{1, 0.5, -1}))},
      {"warn", point_source(PointLight::Kind::Warn, centre, 10000 * 2 / (2 * kPi))},
      {"cos^0 hemisphere", point_source(PointLight::Kind::Goniometric, centre, 10000 / (2 * kPi), 0, kUp)},
      {"cos^10000", point_source(PointLight::Kind::Goniometric, centre, 10000 * 10001 / (2 * kPi), 10000)},
      {"flat spot 30°", point_source(PointLight::Kind::Spot, centre, 10000 / (2 * kPi * (1 - c30)), 0, kDown,
                                     kPi / 6)},
      {"cos^20 spot 40°", point_source(PointLight::Kind::Spot, centre,
                                       10000 * 21 / (2 * kPi * (1 - std::pow(c40, 21))), 20,
                                       normalize(Vector3{0.3, -0.2, -1}), 40 * kPi / 180)},
      {"flat spot 120°", point_source(PointLight::Kind::Spot, centre, 10000 / (2 * kPi * (1 + 0.5)), 0, kDown,
                                      120 * kPi / 180)},
  };
  for (const Case& c : cases) {
    SceneBuilder b;
    b.surface("room", b.material("black", 0), box({0, 0, 0}, {4, 4, 3}, true));
    add_light(b, c.light);
    const Solution sol = solve(b.scene());
    EXPECT_NEAR(sol.stats.emitted_W, 10000, 1e-9 * 10000) << c.name;
    EXPECT_NEAR(total_flux(sol, sol.irradiance), 10000, 1e-3 * 10000) << c.name;  // the acceptance bound
    EXPECT_NEAR(total_flux(sol, sol.irradiance), 10000, 1e-7 * 10000) << c.name;  // what it achieves
    EXPECT_LT(std::abs(sol.stats.relative_imbalance), 1e-7) << c.name;
  }
}

// ---- patch averages: P6, P7 and the near field ----------------------------------------------------

TEST(Lights, P6IsotropicPatchFluxIsIntensityTimesSolidAngle) {
  // Flux onto a square of side a centred under the source at height h = I Ω (exact), with
  // Ω = 4 asin((a/2)² / ((a/2)² + h²)): a = 2, h = 1: 2π/3 = 2.094395102; a = 10, h = 1: 5.170198016;
  // a = 1, h = 2: 0.2354300238. The same with the attenuation written out as c3 r² (c3 = 1) takes the
  // cone-integral path instead of the closed form.
  for (const auto& [a, h, omega] : {std::tuple{2.0, 1.0, 2.094395102}, {10.0, 1.0, 5.170198016}, {1.0, 2.0, 0.2354300238}}) {
    const auto square = rectangle({-a / 2, -a / 2, 0}, {a, 0, 0}, {0, a, 0});
    PointLight l = point_source(PointLight::Kind::Point, {0, 0, h}, 1);
    EXPECT_NEAR(sum(triangle_fluxes(*make_light_model(l), square)), omega, 1e-9) << a << " " << h;
    l.inverse_square = false;
    l.attenuation = {0, 0, 1};
    EXPECT_NEAR(sum(triangle_fluxes(*make_light_model(l), square)), omega, 1e-9) << a << " " << h;
  }
}

TEST(Lights, P7WarnSourceOntoACentredSquare) {
  // Flux from a cosine source onto a rectangle = π I0 F(dA -> rect); 1 x 1 square centred at h = 1,
  // I0 = 1: π · 4 · B-3(0.5, 0.5) = 0.7522746885 lm.
  const auto model = make_light_model(point_source(PointLight::Kind::Warn, {0, 0, 1}, 1));
  EXPECT_NEAR(sum(triangle_fluxes(*model, unit_floor())), 0.7522746885, 1e-9);
  SceneBuilder b;
  b.surface("floor", b.material("black", 0), unit_floor());
  add_light(b, point_source(PointLight::Kind::Warn, {0, 0, 1}, 1));
  const Solution sol = solve(b.scene());
  EXPECT_NEAR(surface_flux(sol, 0, sol.irradiance), 0.7522746885, 1e-9);
}

TEST(Lights, WarnPatchFluxEqualsTheContourFormulaOnEveryPatch) {
  // ∫_T cos ψ cos α / r² dA = π F(dA_source with normal = axis -> T) for ANY geometry: an independent
  // exact reference (Lambert's contour formula) for every patch, here for a tilted axis and for a
  // source 1 µm above the floor.
  for (const auto& [h, axis] : {std::pair{0.7, normalize(Vector3{0.4, -0.3, -1})}, {1e-6, kDown},
                                {1e-6, normalize(Vector3{1, 0, -1})}}) {
    const Point3 source{0.12, -0.07, h};
    SceneBuilder b;
    b.surface("floor", b.material("black", 0), unit_floor());
    b.max_patch_area(0.01);
    add_light(b, point_source(PointLight::Kind::Warn, source, 1, 1, axis));
    const Solution sol = solve(b.scene());
    double worst = 0;
    for (std::size_t i = 0; i < sol.patches.size(); ++i) {
      const double exact = kPi * point_triangle_factor(source, axis, sol.patches[i].triangle);
      const double got = sol.irradiance[i] * sol.patches[i].area_m2;
      ASSERT_TRUE(std::isfinite(got));
      worst = std::max(worst, std::abs(got - exact));
    }
    EXPECT_LT(worst, 1e-10) << "h=" << h;
  }
}

TEST(Lights, AxisLineThroughAnEdgeBehindTheSource) {
  // A source whose axis line, continued backwards, crosses the edge two ceiling triangles share: the
  // section there lies behind the source (ψ near π) and must not wrap to −π. The box's faces, cut
  // into 4 × 4 cells each, receive the whole 4π I (and 2π I/(m+1) for a cos lobe).
  std::vector<Triangle> cells;
  test::for_each_box_face({0, 0, 0}, {4, 4, 3}, [&](const Point3& o, const Vector3& u, const Vector3& v) {
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        for (const Triangle& t : rectangle(o + u * (i / 4.0) + v * (j / 4.0), u * 0.25, v * 0.25)) cells.push_back(t);
  });
  for (const Point3& at : {Point3{2.01, 2.0, 2.5}, Point3{2.0, 2.0, 1.0}}) {
    const auto iso = make_light_model(point_source(PointLight::Kind::Point, at, 1));
    const auto lobe = make_light_model(point_source(PointLight::Kind::Goniometric, at, 1, 2));
    EXPECT_NEAR(sum(triangle_fluxes(*iso, cells)), 4 * kPi, 1e-9) << at.x << " " << at.y;
    EXPECT_NEAR(sum(triangle_fluxes(*lobe, cells)), 2 * kPi / 3, 1e-9) << at.x << " " << at.y;
  }
}

TEST(Lights, IsotropicPointOneMicrometreAboveTheFloor) {
  // P6 at h = 1 µm: patch-mean = I Ω / A with Ω = 4 asin((a/2)² / ((a/2)² + h²)) = 6.283173993471088 sr
  // for the centred unit square (→ 2π as h → 0).
  SceneBuilder b;
  b.surface("floor", b.material("black", 0), unit_floor());
  add_light(b, point_source(PointLight::Kind::Point, {0, 0, 1e-6}, 1));
  const Solution sol = solve(b.scene());
  for (double E : sol.irradiance) ASSERT_TRUE(std::isfinite(E));
  EXPECT_NEAR(surface_flux(sol, 0, sol.irradiance), 6.283173993471088, 1e-9);
}

TEST(Lights, LobedAndAttenuatedSourcesOneMicrometreAboveTheFloor) {
  // Centred unit square, source at height h, straight down. References (mpmath, 30 digits, polar
  // about the foot with the radial integral ∫_h^R h^k r^{1-k} dr / att(r), R = R(φ) to the square's edge):
  //  - cos^4, 1/r², h = 1 µm: 2π/5 (1 − O((2h)^5)) = 1.256637061435917;
  //  - isotropic, att = 0.01 + r², h = 1 µm: 8.75048840662189e-5;
  //  - isotropic, att = r (1/r law), h = 1 µm: 8.31415505722870e-5;
  //  - isotropic, att = 0.01 + 0.1 r + r², h = 0.01: 0.5970704983595822;
  //  - Warn, att = r, h = 1 µm: 6.28317399347109e-6.
  struct Case { const char* name; PointLight light; bool inverse_square; Attenuation c; double flux; };
  const double um = 1e-6;
  const std::vector<Case> cases = {
      {"cos^4", point_source(PointLight::Kind::Goniometric, {0, 0, um}, 1, 4), true, {}, 1.256637061435917},
      {"att 0.01+r²", point_source(PointLight::Kind::Point, {0, 0, um}, 1), false, {0.01, 0, 1}, 8.75048840662189e-5},
      {"att r", point_source(PointLight::Kind::Point, {0, 0, um}, 1), false, {0, 1, 0}, 8.31415505722870e-5},
      {"att 0.01+0.1r+r² at 1 cm", point_source(PointLight::Kind::Point, {0, 0, 0.01}, 1), false, {0.01, 0.1, 1},
       0.5970704983595822},
      {"warn att r", point_source(PointLight::Kind::Warn, {0, 0, um}, 1), false, {0, 1, 0}, 6.28317399347109e-6},
  };
  for (Case c : cases) {
    c.light.inverse_square = c.inverse_square;
    c.light.attenuation = c.c;
    SceneBuilder b;
    b.surface("floor", b.material("black", 0), unit_floor());
    b.max_patch_area(0.02);
    add_light(b, c.light);
    const Solution sol = solve(b.scene());
    for (double E : sol.irradiance) ASSERT_TRUE(std::isfinite(E)) << c.name;
    EXPECT_NEAR(surface_flux(sol, 0, sol.irradiance), c.flux, 1e-7 * c.flux) << c.name;
  }
}

TEST(Lights, SpotCutoffAcrossAPatch) {
  // Spot at h = 1 over the centred unit square, cutoff 30°: the cutoff circle (radius tan 30° = 0.577)
  // crosses all four edges of the square, and the square's diagonal splits it into two triangles
  // that receive half each (180° symmetry).
  //  m = 0: Ω(square ∩ cone) = 2π(1 − cos ψc) − 4 [2 asin(h sin φ0 / sqrt(a² + h²)) − 2 φ0 cos ψc],
  //         a = 0.5, φ0 = acos(a / (h tan ψc)) = π/6: 0.7602050709389197 sr;
  //  m = 20: the same region weighted by cos^20 ψ (mpmath, Cartesian quadrature of the four circular
  //         segments): 0.2785423029572075.
  for (const auto& [m, flux] : {std::pair{0.0, 0.7602050709389197}, {20.0, 0.2785423029572075}}) {
    const PointLight spot = point_source(PointLight::Kind::Spot, {0, 0, 1}, 1, m, kDown, kPi / 6);
    const auto halves = triangle_fluxes(*make_light_model(spot), unit_floor());
    EXPECT_NEAR(halves[0], flux / 2, 1e-9 * flux) << "m=" << m;
    EXPECT_NEAR(halves[1], flux / 2, 1e-9 * flux) << "m=" << m;
    SceneBuilder b;
    b.surface("floor", b.material("black", 0), unit_floor());
    b.max_patch_area(0.005);
    add_light(b, spot);
    const Solution sol = solve(b.scene());
    EXPECT_NEAR(surface_flux(sol, 0, sol.irradiance), flux, 1e-9 * flux) << "m=" << m;
  }
}

// ---- narrow lobes -----------------------------------------------------------------------------------

TEST(Lights, Cos10000OverTheFloor) {
  // cos^m source at h = 2 over a 1 x 1 m floor; the lobe (width ~ h/sqrt(m) = 2 cm) falls wholly on the
  // floor: the area-weighted patch mean is 2π I0/(m+1) / 1 m². m = 10⁴: 6.282557051474439e-4;
  // m = 10⁶: 6.283179024000562e-6.
  for (const auto& [m, mean] : {std::pair{1e4, 6.282557051474439e-4}, {1e6, 6.283179024000562e-6}}) {
    SceneBuilder b;
    b.surface("floor", b.material("black", 0), unit_floor());
    add_light(b, point_source(PointLight::Kind::Goniometric, {0.1, -0.05, 2}, 1, m));
    const Solution sol = solve(b.scene());
    for (double E : sol.irradiance) ASSERT_TRUE(std::isfinite(E) && E >= 0);
    EXPECT_NEAR(surface_flux(sol, 0, sol.irradiance), mean, 1e-3 * mean) << "m=" << m;  // acceptance
    EXPECT_NEAR(surface_flux(sol, 0, sol.irradiance), mean, 1e-8 * mean) << "m=" << m;
  }
}

TEST(Lights, NarrowLobeFootprintFarSmallerThanThePatch) {
  // The floor as its two triangles. Peak on the diagonal: by the mirror symmetry about it each
  // triangle receives π/(m+1). Peak 0.28 m from the diagonal: one triangle receives 2π/(m+1), the
  // other exp(-m·0.02/2)-small.
  for (double m : {1e4, 1e6}) {
    const auto on_diagonal = triangle_fluxes(
        *make_light_model(point_source(PointLight::Kind::Goniometric, {0.1, 0.1, 2}, 1, m)), unit_floor());
    EXPECT_NEAR(on_diagonal[0], kPi / (m + 1), 1e-9 * kPi / (m + 1)) << m;
    EXPECT_NEAR(on_diagonal[1], kPi / (m + 1), 1e-9 * kPi / (m + 1)) << m;
    const auto off = triangle_fluxes(
        *make_light_model(point_source(PointLight::Kind::Goniometric, {0.13, -0.27, 2}, 1, m)), unit_floor());
    EXPECT_NEAR(off[0], 2 * kPi / (m + 1), 1e-9 * 2 * kPi / (m + 1)) << m;
    EXPECT_LT(off[1], 1e-30 * 2 * kPi / (m + 1)) << m;
  }
}

TEST(Lights, LobedPatchIntegralMatchesAdaptiveAreaCubature) {
  // cos^200 with a tilted axis whose peak lies inside one triangle: the cone integral against the
  // independent adaptive area cubature of E = cos^m ψ cos α / r² (cubature.h, refined 4^10-deep).
  const Point3 s{0.05, 0.02, 0.8};
  const Vector3 axis = normalize(Vector3{0.2, -0.1, -1});
  const PointLight l = point_source(PointLight::Kind::Goniometric, s, 1, 200, axis);
  const auto model = make_light_model(l);
  for (const Triangle& t : unit_floor()) {
    auto E = [&](const Point3& p) { return model->unshadowed_factor(p, kUp); };
    const double coarse = apply_rule(triangle_rule_degree5(), t, E);
    const double reference = integrate_adaptive(t, E, coarse, 1e-13, 10);
    const Visibility vis(unit_floor());
    EXPECT_NEAR(model->patch_factor(t, vis) * t.area(), reference, 1e-8 * 0.0314);
  }
}

// ---- Phong-lobed area emitters ---------------------------------------------------------------------

// Box [0,2]² x [0,1.5] with its ceiling made of a 1 x 1 emitter in the middle and a ring around it.
int phong_box(SceneBuilder& b, double n, double rho) {
  const int m = b.material("wall", rho);
  const double H = 1.5;
  std::vector<Triangle> walls;
  const auto all = box({0, 0, 0}, {2, 2, H}, true);
  for (std::size_t k = 0; k < all.size(); ++k)
    if (k != 2 && k != 3) walls.push_back(all[k]);  // drop the ceiling (faces 2 and 3 of box())
  b.surface("walls", m, walls);
  std::vector<Triangle> ring;
  for (const auto& r : {rectangle({0, 0, H}, {0, 0.5, 0}, {2, 0, 0}), rectangle({0, 1.5, H}, {0, 0.5, 0}, {2, 0, 0}),
                        rectangle({0, 0.5, H}, {0, 1, 0}, {0.5, 0, 0}), rectangle({1.5, 0.5, H}, {0, 1, 0}, {0.5, 0, 0})})
    ring.insert(ring.end(), r.begin(), r.end());
  b.surface("ceiling", m, ring);
  Surface& e = b.surface("emitter", m, rectangle({0.5, 0.5, H}, {0, 1, 0}, {1, 0, 0}), 1.0);
  e.emission->lobe_exponent = n;
  return 2;  // the emitter's surface index
}

TEST(Lights, PhongEmitterPowerInAClosedBlackBox) {
  // A Phong-lobed (n = 8) 1 m² emitter, R = 1, in a closed black box: the box receives R·A = 1 W.
  SceneBuilder b;
  const int emitter = phong_box(b, 8, 0.0);
  b.max_patch_area(0.05);
  const Solution sol = solve(b.scene());
  double received = 0;
  for (std::size_t i = 0; i < sol.patches.size(); ++i)
    if (sol.patches[i].surface != emitter) received += sol.patches[i].area_m2 * sol.irradiance[i];
  EXPECT_NEAR(received, 1.0, 1e-3);  // acceptance
  EXPECT_NEAR(received, 1.0, 1e-5);
  EXPECT_NEAR(sol.stats.emitted_W, 1.0, 1e-12);
  EXPECT_LT(std::abs(sol.stats.relative_imbalance), 1e-5);
  // The black emitter's radiosity is its reflected part only (0): its emission is not in B.
  for (std::size_t i = 0; i < sol.patches.size(); ++i)
    if (sol.patches[i].surface == emitter) {
      EXPECT_EQ(sol.radiosity[i], 0.0);
    }
}

TEST(Lights, PhongEmitterAtPoints) {
  // 0.1 x 0.1 m square emitter at z = 0 facing up, n = 8, R = 1.
  //  - on the axis at d = 2 (far field): E ≈ R A (n+1)/(2π) / d² = 0.003580986220 (0.23 % high), exact
  //    (mpmath, 2-D quadrature of (n+1)/(2π) (d/r)^{n+1}/r²) 0.003572795324;
  //  - near and off axis at (0.03, 0.01, 0.05): 0.8510027101682 (same quadrature).
  const auto model = make_phong_emitter(Triangle{{Point3{-0.05, -0.05, 0}, Point3{0.05, -0.05, 0}, Point3{0.05, 0.05, 0}}},
                                        8, {1.0});
  const auto model2 = make_phong_emitter(Triangle{{Point3{-0.05, -0.05, 0}, Point3{0.05, 0.05, 0}, Point3{-0.05, 0.05, 0}}},
                                         8, {1.0});
  auto E = [&](const Point3& p) { return model->unshadowed_factor(p, kDown) + model2->unshadowed_factor(p, kDown); };
  const double far = E({0, 0, 2});
  EXPECT_NEAR(far, 0.003580986220, 3e-3 * 0.003580986220);  // the far-field approximation
  EXPECT_NEAR(far, 0.003572795324, 1e-9 * 0.003572795324);
  EXPECT_NEAR(E({0.03, 0.01, 0.05}), 0.8510027101682, 1e-9);
  EXPECT_EQ(E({0, 0, -1}), 0.0);  // behind the emitter
  EXPECT_DOUBLE_EQ(model->flux_factor(), 0.005);

  // The same through a solve's probe (with its shadow rays).
  SceneBuilder b;
  Surface& s = b.surface("emitter", b.material("black", 0), rectangle({-0.05, -0.05, 0}, {0.1, 0, 0}, {0, 0.1, 0}), 1.0);
  s.emission->lobe_exponent = 8;
  b.probe("near", {0.03, 0.01, 0.05}, kDown);
  b.max_patch_area(1);
  const Solution sol = solve(b.scene());
  EXPECT_NEAR(sol.probes[0].irradiance[0], 0.8510027101682, 1e-9);
}

TEST(Lights, PhongWithExponentOneEqualsTheFormFactorPath) {
  // n = 1 through the Phong path equals A_i F_ij / A_i from the Lambertian form factors.
  const auto emitter = rectangle({0, 0, 1}, {0, 1, 0}, {1, 0, 0});  // faces -z
  const std::vector<Triangle> receivers = {
      Triangle{{Point3{0, 0, 0}, Point3{1, 0, 0}, Point3{1, 1, 0}}},              // opposed, 1 below
      Triangle{{Point3{0, 0, 0}, Point3{0, 1, 0}, Point3{0, 0, 1}}},              // perpendicular, touching
      Triangle{{Point3{3, 0, 0}, Point3{3.1, 0.1, 0.4}, Point3{3, 0.2, 0}}},    // far, tilted
      Triangle{{Point3{0.2, 0.1, 0.99}, Point3{0.4, 0.2, 0.99}, Point3{0.3, 0.4, 0.99}}}};  // 1 cm gap
  std::vector<Triangle> occluders = receivers;
  occluders.insert(occluders.end(), emitter.begin(), emitter.end());
  const Visibility vis(occluders);
  for (const Triangle& e : emitter) {
    const auto phong = make_phong_emitter(e, 1, {1.0});
    for (std::size_t r = 0; r < receivers.size(); ++r) {
      const Triangle& t = receivers[r];
      const double lambert = area_form_factor(t, e) / t.area();  // E_avg per unit M = F(t -> e)
      const double got = phong->patch_factor(t, vis);
      ASSERT_GT(lambert, 0) << "receiver " << r;
      EXPECT_NEAR(got, lambert, 1e-4 * lambert) << "receiver " << r;  // the bound asked for
      EXPECT_NEAR(got, lambert, 1e-6 * lambert) << "receiver " << r;  // what it achieves
    }
  }
}

TEST(Lights, AxialMomentsAgreeWithThePolarIntegral) {
  // Arvo's double-axis moment τ^{n,1}(A; a, b) = ∫_A (a·u)^n (b·u) dσ against the polar integral about
  // a (cone_integral: adaptive quadrature in polar coordinates about a), on random triangles and quadrilaterals
  // within 35° of +z seen from the origin, a and b within 40° of +z (so a·u, b·u > 0 over A).
  std::mt19937 rng(20261205);
  std::uniform_real_distribution<double> U(-1, 1), Z(0.5, 2);
  auto near_z = [&](double max_tan) { return normalize(Vector3{max_tan * U(rng), max_tan * U(rng), 1}); };
  for (int trial = 0; trial < 24; ++trial) {
    const int vertices = trial % 2 ? 4 : 3;
    std::vector<Point3> polygon;
    if (vertices == 3) {
      for (int k = 0; k < 3; ++k) {
        const double z = Z(rng);
        polygon.push_back({0.35 * z * U(rng), 0.35 * z * U(rng), z});
      }
    } else {  // a planar quadrilateral: a square tilted about x, around a point on +z
      const double z = Z(rng), h = 0.2 * z, tilt = 0.6 * U(rng);
      const Vector3 e1{h, 0, 0}, e2{0, h * std::cos(tilt), h * std::sin(tilt)};
      const Point3 c{0.1 * z * U(rng), 0.1 * z * U(rng), z};
      polygon = {c - e1 - e2, c + e1 - e2, c + e1 + e2, c - e1 + e2};
    }
    const Vector3 a = near_z(0.8), b = near_z(0.8);
    double omega = 0;  // the solid angle Ω, the scale of the recurrence's rounding
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
      omega += triangle_solid_angle(Point3{0, 0, 0}, Triangle{{polygon[0], polygon[k], polygon[k + 1]}});
    for (const int n : {0, 1, 2, 3, 8, 19, 20, 100}) {
      const double polar = cone_integral(Point3{0, 0, 0}, ConeLobe{a, static_cast<double>(n), kPi / 2}, polygon,
                                         [&](const Vector3& u) { return dot(b, u); }, 1e-12);
      const double moment = double_axis_moment(Point3{0, 0, 0}, polygon, a, b, n);
      EXPECT_NEAR(moment, polar, 1e-9 * polar + 1e-14 * omega) << "trial " << trial << " n " << n;
    }
    // n = 0 is Lambert's contour integral: τ^{0,1}(A; ·, b) = π F(dA_b → polygon), F taken for the
    // orientation that faces the origin (the other gives 0).
    std::vector<Point3> reversed(polygon.rbegin(), polygon.rend());
    const double lambert = kPi * (point_polygon_factor(Point3{0, 0, 0}, b, polygon) +
                                  point_polygon_factor(Point3{0, 0, 0}, b, reversed));
    EXPECT_NEAR(double_axis_moment(Point3{0, 0, 0}, polygon, a, b, 0), lambert, 1e-12 * lambert) << "trial " << trial;
  }
  // Far off the axis the moments fall as (a·u)^n while the recurrence's rounding stays that of the
  // solid angle Ω: at 60° from a, n = 1000, τ ≈ 0.5^1000 Ω ≈ 1e-301 Ω, and the result is within 1e-14 Ω of it.
  const std::vector<Point3> off_axis = {{0.84, 0, 0.5}, {0.9, 0.05, 0.5}, {0.84, 0.1, 0.5}};
  const Vector3 axis{0, 0, 1};
  const double omega = triangle_solid_angle(Point3{0, 0, 0}, Triangle{{off_axis[0], off_axis[1], off_axis[2]}});
  for (const int n : {200, 1000, 5000})
    EXPECT_LE(std::abs(double_axis_moment(Point3{0, 0, 0}, off_axis, axis, axis, n)), 1e-14 * omega) << n;
}

TEST(Lights, PhongPatchFactorByMomentsEqualsTheEmitterSideIntegral) {
  // n = 20 by the moments (exact at receiver points, cubature over the receiver) against
  // n = 20 + 1e-12 by the polar integral (exact over the receiver, cubature over the emitter): two
  // routes that share no kernel. Opposed, perpendicular and touching, far and tilted, and 1 cm apart.
  const auto emitter = rectangle({0, 0, 1}, {0, 1, 0}, {1, 0, 0});  // faces -z
  const std::vector<Triangle> receivers = {
      Triangle{{Point3{0, 0, 0}, Point3{1, 0, 0}, Point3{1, 1, 0}}},
      Triangle{{Point3{0, 0, 0}, Point3{0, 1, 0}, Point3{0, 0, 1}}},
      Triangle{{Point3{1.5, 0, 0}, Point3{1.6, 0.1, 0.4}, Point3{1.5, 0.2, 0}}},
      Triangle{{Point3{0.2, 0.1, 0.99}, Point3{0.4, 0.2, 0.99}, Point3{0.3, 0.4, 0.99}}},
      Triangle{{Point3{0.45, 0.45, 0.2}, Point3{0.55, 0.45, 0.2}, Point3{0.5, 0.55, 0.2}}}};
  std::vector<Triangle> occluders = receivers;
  occluders.insert(occluders.end(), emitter.begin(), emitter.end());
  const Visibility vis(occluders);
  for (const Triangle& e : emitter) {
    const auto by_moments = make_phong_emitter(e, 20, {1.0});
    const auto by_polar = make_phong_emitter(e, 20 + 1e-12, {1.0});
    for (std::size_t r = 0; r < receivers.size(); ++r) {
      const double polar = by_polar->patch_factor(receivers[r], vis);
      ASSERT_GT(polar, 0) << "receiver " << r;
      EXPECT_NEAR(by_moments->patch_factor(receivers[r], vis), polar, 2e-5 * polar) << "receiver " << r;
    }
  }
}

TEST(Lights, PhongEmitterCutByTheReceiversPlane) {
  // n = 1 emitters (a floor x ∈ [0, 1], y ∈ [−w, w], as two triangles) cut by the plane y = 0 of the
  // receiving wall (facing +y, x ∈ [0, 1], z ∈ [8, 9]): only the half y > 0 shines on it, so by Howell
  // C-14 and additivity Σ A_t E_t = w (F14(w, 9) − F14(w, 8)) per unit exitance. Far enough for the
  // fixed rule, which must integrate the emitter's part in front of the wall only (3 % off otherwise).
  const double w = 0.5;
  const std::vector<Triangle> floor = {Triangle{{Point3{0, -w, 0}, Point3{1, -w, 0}, Point3{1, w, 0}}},
                                       Triangle{{Point3{0, -w, 0}, Point3{1, w, 0}, Point3{0, w, 0}}}};
  const std::vector<Triangle> wall = rectangle({0, 0, 8}, {0, 0, 1}, {1, 0, 0});
  std::vector<Triangle> occluders = floor;
  occluders.insert(occluders.end(), wall.begin(), wall.end());
  const Visibility vis(occluders);
  double power = 0;
  for (const Triangle& e : floor) {
    const auto phong = make_phong_emitter(e, 1, {1.0});
    for (const Triangle& t : wall) power += t.area() * phong->patch_factor(t, vis);
  }
  const double expected = w * (closed_form::howell_c14(w, 9) - closed_form::howell_c14(w, 8));
  EXPECT_NEAR(power, expected, 1e-5 * expected);
}

TEST(Lights, PhongSolveWithExponentNearOneMatchesLambertian) {
  // A reflecting room (ρ = 0.5) lit by a ceiling emitter: n = 1 (form factors, emission in B) against
  // n = 1 + 1e-12 (the direct path, emission outside B). H must agree on every patch, and B on every
  // patch but the emitter's, where the Lambertian B holds M = 1 besides ρH.
  auto run = [](double n) {
    SceneBuilder b;
    phong_box(b, n, 0.5);
    b.max_patch_area(0.06);
    b.scene().solver.tolerance = 1e-9;  // compare the two paths, not two linear-solve residuals
    return solve(b.scene());
  };
  const Solution lambert = run(1.0), phong = run(1.0 + 1e-12);
  ASSERT_EQ(lambert.patches.size(), phong.patches.size());
  double worst_H = 0, worst_B = 0;
  for (std::size_t i = 0; i < lambert.patches.size(); ++i) {
    worst_H = std::max(worst_H, std::abs(phong.irradiance[i] - lambert.irradiance[i]) / lambert.irradiance[i]);
    const double M = lambert.patches[i].surface == 2 ? 1.0 : 0.0;
    worst_B = std::max(worst_B, std::abs(phong.radiosity[i] + M - lambert.radiosity[i]) / lambert.radiosity[i]);
  }
  EXPECT_LT(worst_H, 1e-4);
  EXPECT_LT(worst_B, 1e-4);
  EXPECT_LT(std::abs(phong.stats.relative_imbalance), 1e-4);
  EXPECT_NEAR(phong.stats.emitted_W, 1.0, 1e-12);
}

}  // namespace
}  // namespace lambert
