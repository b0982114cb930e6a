// Glare (solver/glare.h): the Guth position index from CIE 117's table at hand-computed angles and
// against Levin's independent fit of the same data at every tabulated node, UGR
// of one-luminaire configurations computed by hand from the CIE 117 formula (and CIE 147's small-
// source form), and the background luminance from the solved indirect illuminance at the eye.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "solver/form_factor.h"
#include "solver/glare.h"
#include "solver/radiosity.h"
#include "solver/spectrum.h"
#include "tests/scene_builder.h"

namespace lambert {
namespace {

using test::box;
using test::rectangle;
using test::SceneBuilder;

constexpr double kDeg = kPi / 180;
const Vector3 kView{1, 0, 0}, kUp{0, 0, 1};

// Levin's equation, written out: ln p = σ[(35.2 − 0.31889 τ − 1.22 e^{−2τ/9})e-3 + σ(21 + 0.26667 τ
// − 0.002963 τ²)e-5], σ and τ in degrees.
double levin(double sigma, double tau) {
  return std::exp(sigma * ((35.2 - 0.31889 * tau - 1.22 * std::exp(-2 * tau / 9)) * 1e-3 +
                           sigma * (21 + 0.26667 * tau - 0.002963 * tau * tau) * 1e-5));
}

// The direction at R along the line of sight (+x), H above it (+z) and T beside it (+y), unit.
Vector3 direction(double R, double H, double T) { return normalize(Vector3{R, T, H}); }

// The index CIE 117 tabulates, from the source's direction by hand: H/R and T/R.
double table_index(const Vector3& d) { return *guth_position_index_table(std::abs(d.z) / d.x, std::abs(d.y) / d.x); }

TEST(Guth, PositionIndexFromTheTableAtHandComputedAngles) {
  EXPECT_EQ(*guth_position_index(kView, kUp, kView), 1.0);  // on the line of sight: Table 4.1's first entry
  // Nodes of CIE 117 Table 4.1: straight above at 45° (H/R = 1, T/R = 0) 7.00; beside at 45° (T/R = 1)
  // 2.11; H/R = 0.5, T/R = 1.0: 3.91.
  EXPECT_NEAR(*guth_position_index(kView, kUp, direction(1, 1, 0)), 7.00, 1e-12);
  EXPECT_NEAR(*guth_position_index(kView, kUp, direction(1, 0, 1)), 2.11, 1e-12);
  EXPECT_NEAR(*guth_position_index(kView, kUp, direction(2, 1, 2)), 3.91, 1e-12);
  // Bilinear between T/R 0.1–0.2 and H/R 0.4–0.5 (2.20, 2.75; 2.20, 2.66) at their centre: 2.4525.
  EXPECT_NEAR(*guth_position_index(kView, kUp, direction(1, 0.45, 0.15)), 2.4525, 1e-12);
  // Left and right, above and below alike; any frame (the view along y, up along −x).
  for (const double t : {1.0, -1.0})
    for (const double h : {1.0, -1.0}) {
      EXPECT_NEAR(*guth_position_index(kView, kUp, direction(2, h * 0.9, t * 1.3)), table_index(direction(2, 0.9, 1.3)), 1e-12);
      const Vector3 d = direction(2, h * 0.9, t * 1.3);
      EXPECT_NEAR(*guth_position_index({0, 1, 0}, {-1, 0, 0}, {-d.z, d.x, d.y}), table_index(d), 1e-12);
    }
  // Outside the table: behind the eye, beyond T/R = 3, above H/R = 1.9, and the blank cells above the
  // field of view near the line of sight (H/R 1.8 at T/R 0.2); inside at H/R 1.8, T/R 1.0: 15.00.
  EXPECT_FALSE(guth_position_index(kView, kUp, direction(-1, 0.2, 0.1)));
  EXPECT_FALSE(guth_position_index(kView, kUp, direction(1, 0.5, 3.2)));
  EXPECT_FALSE(guth_position_index(kView, kUp, direction(1, 1.95, 1.0)));
  EXPECT_FALSE(guth_position_index(kView, kUp, direction(1, 1.8, 0.2)));
  EXPECT_NEAR(*guth_position_index(kView, kUp, direction(1, 1.8, 1.0)), 15.00, 1e-12);
}

TEST(Guth, TheTableFollowsLevinsFitOfTheSameData) {
  // Levin fitted Guth's data analytically (J. IES 4 (1975) 99–105) and states his equation follows it
  // to 12 %: every tabulated value lies within that of his equation at the node's σ and τ (the
  // largest gap, 10.6 %, is at T/R = 3.0 on the line of sight's level); a mistyped value would not.
  int nodes = 0;
  for (int i = 0; i <= 30; ++i)
    for (int j = 0; j <= 19; ++j) {
      const double t = i / 10.0, h = j / 10.0;
      const auto p = guth_position_index_table(h, t);
      const bool blank = (j >= 18 && i <= 3) || (j == 19 && i <= 8);
      ASSERT_EQ(p.has_value(), !blank) << "T/R " << t << " H/R " << h;
      if (!p) continue;
      const double sigma = std::atan(std::hypot(t, h)) / kDeg, tau = std::atan2(t, h) / kDeg;
      EXPECT_NEAR(*p / levin(sigma, tau), 1, 0.12) << "T/R " << t << " H/R " << h;
      ++nodes;
    }
  EXPECT_EQ(nodes, 620 - 13);
}

// The scene's luminous efficacy at its single wavelength: lx per W m^-2.
double efficacy(const Scene& s) { return luminous_integral({1.0}, s.grid); }

TEST(UnifiedGlareRating, OneAreaLuminaireByHand) {
  // A black 6 × 4 × 3 m room (no interreflection); ambient light E_a gives the background; one
  // Lambertian 0.6 × 0.6 m panel of exitance M facing down at 2.8 m. The observer sits at 1.2 m
  // looking along +x towards it.
  //   L = K M / π,  L_b = K E_a / π,  UGR = 8 log10(0.25 / L_b Σ_t L² ω_t / p_t²)
  // over the panel's two triangles, ω_t their solid angles, p_t the tabulated index at their centroids.
  SceneBuilder b;
  const int black = b.material("black", 0.0);
  b.surface("room", black, box({0, 0, 0}, {6, 4, 3}, true));
  const double M = 20.0, Ea = 0.05;
  const std::vector<Triangle> panel = rectangle({3.7, 1.7, 2.8}, {0, 0.6, 0}, {0.6, 0, 0});  // faces −z
  b.surface("panel", black, panel, M);
  b.scene().lights.push_back(AmbientLight{{Ea}});
  b.scene().light_pointers.push_back("/lights/0");
  const Point3 eye{1, 2, 1.2};
  b.scene().glare.push_back(GlareObserver{"desk", eye, kView, kUp});
  const Solution sol = solve(b.scene());
  const double K = efficacy(b.scene());
  const double L = K * M / kPi, Lb = K * Ea / kPi;
  double sum = 0;
  for (const Triangle& t : panel) {
    const double p = table_index(t.centroid() - eye);
    sum += L * L * triangle_solid_angle(eye, t) / (p * p);
  }
  const double expected = 8 * std::log10(0.25 / Lb * sum);
  ASSERT_EQ(sol.glare.size(), 1u);
  const GlareResult& g = sol.glare[0];
  EXPECT_NEAR(g.background_luminance_cd_m2, Lb, 1e-12 * Lb);
  ASSERT_EQ(g.sources.size(), 1u);
  EXPECT_EQ(g.sources[0].source, "/surfaces/1");
  EXPECT_FALSE(g.sources[0].small);
  EXPECT_NEAR(g.sources[0].luminance_cd_m2, L, 1e-12 * L);
  ASSERT_TRUE(g.ugr);
  EXPECT_NEAR(*g.ugr, expected, 1e-9);
  EXPECT_GT(*g.ugr, 10);  // a bright panel against a dim room: a rating in the formula's range
}

TEST(UnifiedGlareRating, OnePointSourceByHandWithCie147) {
  // A point source of I = 3 W/sr (K I cd) at r from the eye, at R = 2, H = 1.2, T = 0.5: CIE 147's
  // small-source term 200 I² / (r² p²).
  SceneBuilder b;
  const int black = b.material("black", 0.0);
  b.surface("room", black, box({-5, -5, -5}, {10, 5, 5}, true));
  const double I = 3, Ea = 0.2, r = 2.5;
  const Point3 eye{0, 0, 0};
  const Vector3 d = direction(2, 1.2, 0.5);
  b.point_light(eye + d * r, I);
  b.scene().lights.push_back(AmbientLight{{Ea}});
  b.scene().light_pointers.push_back("/lights/1");
  b.scene().glare.push_back(GlareObserver{"o", eye, kView, kUp});
  const Solution sol = solve(b.scene());
  const double K = efficacy(b.scene());
  const double Iv = K * I, Lb = K * Ea / kPi, p = table_index(d);
  const double expected = 8 * std::log10(0.25 / Lb * 200 * Iv * Iv / (r * r * p * p));
  ASSERT_EQ(sol.glare.size(), 1u);
  const GlareResult& g = sol.glare[0];
  ASSERT_EQ(g.sources.size(), 1u);
  EXPECT_TRUE(g.sources[0].small);
  EXPECT_NEAR(g.sources[0].intensity_cd, Iv, 1e-12 * Iv);
  EXPECT_NEAR(g.sources[0].position_index, p, 1e-9 * p);
  ASSERT_TRUE(g.ugr);
  EXPECT_NEAR(*g.ugr, expected, 1e-9);
}

TEST(UnifiedGlareRating, BackgroundFromTheSolvedIndirectIlluminance) {
  // A grey room lit by a point source: E_ind at the eye on the plane facing the view is what a planar
  // probe there reads less the source's direct I cos α / d² (closed form), and L_b = E_ind / π.
  SceneBuilder b;
  const int grey = b.material("grey", 0.5);
  b.surface("room", grey, box({0, 0, 0}, {6, 4, 3}, true));
  const Point3 light{3, 2, 2.9}, eye{1, 1.5, 1.2};
  const double I = 10;
  b.point_light(light, I);
  b.probe("eye", eye, kView);
  b.scene().glare.push_back(GlareObserver{"o", eye, kView, kUp});
  const Solution sol = solve(b.scene());
  const double K = efficacy(b.scene());
  const Vector3 d = light - eye;
  const double direct = I * dot(kView, d) / std::pow(length(d), 3);
  const double E_ind = K * (sol.probes[0].irradiance[0] - direct);
  ASSERT_EQ(sol.glare.size(), 1u);
  EXPECT_GT(E_ind, 0);
  EXPECT_NEAR(sol.glare[0].indirect_illuminance_lx, E_ind, 1e-9 * E_ind);
  EXPECT_NEAR(sol.glare[0].background_luminance_cd_m2, E_ind / kPi, 1e-9 * E_ind);
}

TEST(UnifiedGlareRating, UndefinedWithoutBackgroundOrSources) {
  EXPECT_FALSE(unified_glare_rating(0, {GlareSource{"/lights/0", true, 0, 0, 1, 1, 1, 1}}));
  EXPECT_FALSE(unified_glare_rating(10, {}));
}

}  // namespace
}  // namespace lambert
