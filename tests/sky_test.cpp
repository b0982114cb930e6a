// Sky luminance distributions (solver/lights/sky_luminance.h) and the exact sky integral over the
// visible part of the sky (solver/lights/sky_dome.h), against closed forms, published values and
// integrations done here by other methods.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "solver/exact_visibility.h"
#include "solver/form_factor.h"
#include "solver/light_model.h"
#include "solver/lights/sky.h"
#include "solver/lights/sky_dome.h"
#include "solver/lights/sky_luminance.h"
#include "solver/spectrum.h"
#include "solver/visibility.h"
#include "tests/sky_quadrature.h"
#include "tests/test_geometry.h"

namespace lambert {
namespace {

using test::composite;
using test::graded_about;
using test::hemisphere_integral;
using test::kDeg;
using test::kUp;
using test::lune_integral;
using test::sky_direction;

TEST(SkyLuminance, PublishedExamples) {
  // colour-science's documented examples of ISO 15469 (sky_luminance_distribution_CIE2003):
  // type 1 at Z = 45°, α = 180° with the sun at Z_s = 30°, α_s = 0: 0.8325846...; type 12: 0.4544524...
  const Vector3 sun = sky_direction(30 * kDeg, 0);
  const Vector3 w = sky_direction(45 * kDeg, 180 * kDeg);
  EXPECT_NEAR(SkyDistribution::general(1, kUp, sun).relative_luminance(w), 0.8325846, 1e-7);
  EXPECT_NEAR(SkyDistribution::general(12, kUp, sun).relative_luminance(w), 0.4544524, 1e-7);
  // Every sky is 1 at the zenith, by its normalisation.
  for (int type = 1; type <= kCieGeneralSkyTypes; ++type)
    EXPECT_NEAR(SkyDistribution::general(type, kUp, sun).relative_luminance(kUp), 1, 1e-14) << type;
  // The traditional overcast sky: (1 + 2 sin γ)/3, 1/3 at the horizon.
  const SkyDistribution overcast = SkyDistribution::cie_overcast(kUp);
  EXPECT_NEAR(overcast.relative_luminance(sky_direction(60 * kDeg, 1.0)), (1 + 2 * std::sin(30 * kDeg)) / 3, 1e-15);
  EXPECT_EQ(overcast.relative_luminance(sky_direction(91 * kDeg, 0)), 0);
  // Types 1, 3 and 5 do not depend on the sun (indicatrix group 1), the others do.
  for (int type = 1; type <= kCieGeneralSkyTypes; ++type)
    EXPECT_EQ(cie_sky_depends_on_sun(type), type != 1 && type != 3 && type != 5) << type;
  EXPECT_THROW(SkyDistribution::general(12, kUp, -sun), std::invalid_argument);  // the sun below the horizon
  EXPECT_THROW(cie_general_sky(16), std::out_of_range);
}

TEST(SkyLuminance, HorizontalFactorsOfTheClosedForms) {
  // K = ∫ (L/L_z) cos Z dω: π for the uniform sky and general type 5 (a = c = e = 0), 7π/9 for the CIE
  // overcast sky. The production quadrature (about the sun) applied to both.
  EXPECT_NEAR(sky_horizontal_integral(SkyDistribution::uniform(kUp)), kPi, 1e-13);
  EXPECT_NEAR(sky_horizontal_integral(SkyDistribution::cie_overcast(kUp)), 7 * kPi / 9, 1e-13);
  EXPECT_DOUBLE_EQ(SkyDistribution::general(5, kUp, kUp).horizontal_factor(), kPi);
  EXPECT_DOUBLE_EQ(SkyDistribution::cie_overcast(kUp).horizontal_factor(), 7 * kPi / 9);
}

TEST(SkyLuminance, EveryGeneralSkyAgainstAnotherQuadrature) {
  // Each of the 15 general skies, with the sun at three heights and an azimuth off the axes: K from
  // the quadrature about the sun against the composite Gauss rule in zenith and azimuth above.
  for (double sun_Z_deg : {15.0, 50.0, 80.0}) {
    const double sun_Z = sun_Z_deg * kDeg, sun_alpha = 200 * kDeg;
    const Vector3 sun = sky_direction(sun_Z, sun_alpha);
    for (int type = 1; type <= kCieGeneralSkyTypes; ++type) {
      const SkyDistribution sky = SkyDistribution::general(type, kUp, sun);
      const double reference = hemisphere_integral(sky, sun_Z, sun_alpha, kUp);
      EXPECT_NEAR(sky.horizontal_factor() / reference, 1, 1e-10) << "type " << type << ", Z_s " << sun_Z_deg;
    }
  }
}

TEST(SkyDome, UnobstructedHorizontalIlluminance) {
  // E = L_z K: the dome's integral over its ten sky triangles against 7π/9 (overcast: the fan
  // cubature, to its tolerance of 1e-9 K; 9e-10 measured) and π (uniform: the contour integral, exact
  // to round-off); a horizontal plane facing up sees no ground, facing down no sky and all the ground.
  const Point3 p{1.5, -2, 0.3};
  const SkyDome overcast({}, SkyDistribution::cie_overcast(kUp));
  EXPECT_NEAR(overcast.at(p, kUp).sky / (7 * kPi / 9), 1, 2e-9);
  EXPECT_EQ(overcast.at(p, kUp).ground, 0);
  const SkyDome uniform({}, SkyDistribution::uniform(kUp));
  EXPECT_NEAR(uniform.at(p, kUp).sky, kPi, 1e-12);
  EXPECT_NEAR(uniform.at(p, -kUp).ground, kPi, 1e-12);
  EXPECT_NEAR(uniform.at(p, -kUp).sky, 0, 1e-12);
}

TEST(SkyDome, VerticalFacadeUnderTheOvercastSky) {
  // A vertical plane facing a horizontal direction sees half the sky:
  //   E_v = (2 L_z/3) ∫_0^{π/2} (1 + 2 cos Z) sin² Z dZ = (2 L_z/3)(π/4 + 2/3),
  // so E_v/E_h = (π/6 + 4/9)/(7π/9) = (3π + 8)/(14π) = 0.39618 (the 0.396), and half the ground.
  const SkyDome dome({}, SkyDistribution::cie_overcast(kUp));
  for (const Vector3& n : {Vector3{1, 0, 0}, Vector3{0, -1, 0}, normalize(Vector3{1, 2, 0})}) {
    const SkyFactors f = dome.at({0, 0, 0}, n);
    const double ratio = f.sky / (7 * kPi / 9);
    EXPECT_NEAR(ratio, (3 * kPi + 8) / (14 * kPi), 1e-9);
    EXPECT_NEAR(ratio, 0.396, 5e-4);
    EXPECT_NEAR(f.ground, kPi / 2, 1e-12);
  }
}

TEST(SkyDome, EveryGeneralSkyUnobstructed) {
  // The dome's fan cubature (gnomonic, on the box faces) against the sky's horizontal factor (the
  // quadrature about the sun) for a horizontal plane, and against the Gauss rule in coordinates about
  // the line where the horizons meet for a tilted one (facing south-east, 50° from the vertical).
  const double sun_Z = 40 * kDeg, sun_alpha = 150 * kDeg;
  const Vector3 sun = sky_direction(sun_Z, sun_alpha);
  const Vector3 tilted = sky_direction(50 * kDeg, 135 * kDeg);
  for (int type = 1; type <= kCieGeneralSkyTypes; ++type) {
    const SkyDistribution sky = SkyDistribution::general(type, kUp, sun);
    const SkyDome dome({}, sky);
    EXPECT_NEAR(dome.at({0, 0, 0}, kUp).sky / sky.horizontal_factor(), 1, 2e-9) << type;
    EXPECT_NEAR(dome.at({0, 0, 0}, tilted).sky / lune_integral(sky, tilted), 1, 2e-9) << type;
  }
}

// ---- openings in a black room: the sky seen through them --------------------------------------

// A room [0,4]×[0,4]×[0,3] (black: only the occluders matter) with an unglazed roof opening
// [1.5,2.5]×[1.5,2.5] in the ceiling or an unglazed façade opening x ∈ [1,3], z ∈ [1,2] in the wall
// y = 0: the kind of case of CIE 171:2006 §5.9–5.10 (the geometry is ours).
struct Room {
  std::vector<Triangle> triangles;
  Bounds3 bounds;
  void add(const Point3& o, const Vector3& u, const Vector3& v) {
    for (const Triangle& t : test::rectangle(o, u, v)) {
      triangles.push_back(t);
      for (const Point3& q : t.v) bounds.add(q);
    }
  }
};
Room black_room(bool roof_opening, bool facade_opening) {
  Room r;
  r.add({0, 0, 0}, {4, 0, 0}, {0, 4, 0});  // floor
  if (roof_opening) {                      // the ceiling (z = 3, facing down) around [1.5,2.5]²
    r.add({0, 0, 3}, {0, 1.5, 0}, {4, 0, 0});
    r.add({0, 2.5, 3}, {0, 1.5, 0}, {4, 0, 0});
    r.add({0, 1.5, 3}, {0, 1, 0}, {1.5, 0, 0});
    r.add({2.5, 1.5, 3}, {0, 1, 0}, {1.5, 0, 0});
  } else {
    r.add({0, 0, 3}, {0, 4, 0}, {4, 0, 0});
  }
  if (facade_opening) {  // the wall y = 0 (facing +y) around x ∈ [1,3], z ∈ [1,2]
    r.add({0, 0, 0}, {0, 0, 1}, {4, 0, 0});
    r.add({0, 0, 2}, {0, 0, 1}, {4, 0, 0});
    r.add({0, 0, 1}, {0, 0, 1}, {1, 0, 0});
    r.add({3, 0, 1}, {0, 0, 1}, {1, 0, 0});
  } else {
    r.add({0, 0, 0}, {0, 0, 3}, {4, 0, 0});
  }
  r.add({0, 4, 0}, {4, 0, 0}, {0, 0, 3});  // y = 4
  r.add({0, 0, 0}, {0, 4, 0}, {0, 0, 3});  // x = 0
  r.add({4, 0, 0}, {0, 0, 3}, {0, 4, 0});  // x = 4
  return r;
}

TEST(SkyDome, UniformSkyThroughARoofOpening) {
  // Under the uniform sky the opening is a Lambertian emitter of luminance L: E = π L F(p → opening),
  // Howell B-3 by corner decomposition, for floor points under and beside the opening. To 1e-11:
  // the opening's shadow-free part of the box face, peeled into convex pieces, is exact but for
  // round-off in the pieces' corners (2e-12 measured).
  const Room room = black_room(true, false);
  const SkyDome dome(room.triangles, SkyDistribution::uniform(kUp));
  for (const Point3& p : {Point3{2, 2, 0}, Point3{1.7, 2.2, 0}, Point3{0.3, 3.1, 0}, Point3{3.9, 0.2, 0}}) {
    const SkyFactors f = dome.at(p, kUp);
    EXPECT_NEAR(f.sky, kPi * test::point_under_rectangle(p.x, p.y, 3, 1.5, 2.5, 1.5, 2.5), 1e-11) << p.x << " " << p.y;
    EXPECT_NEAR(f.ground, 0, 1e-15);
  }
}

TEST(SkyDome, UniformSkyThroughAFacadeOpening) {
  // Floor points (all directions through the window rise: sky only): E = π L F by V2 corners. A point
  // facing the window at sill height + 0.5 sees its upper part as sky and its lower part as ground:
  // both by B-3 corners in the window's plane (distance y). To 1e-11, as above.
  const Room room = black_room(false, true);
  const SkyDome dome(room.triangles, SkyDistribution::uniform(kUp));
  for (const Point3& p : {Point3{2, 1, 0}, Point3{0.5, 2.5, 0}, Point3{3.7, 0.4, 0}}) {
    const SkyFactors f = dome.at(p, kUp);
    EXPECT_NEAR(f.sky, kPi * test::perpendicular_rectangle(1 - p.x, 3 - p.x, 1, 2, p.y), 1e-11) << p.x << " " << p.y;
    EXPECT_NEAR(f.ground, 0, 1e-15);
  }
  const Point3 q{1.6, 1.3, 1.5};
  const Vector3 facing{0, -1, 0};
  const SkyFactors f = dome.at(q, facing);
  // In the window's plane, about the foot of the perpendicular: x' = x − q.x, z' = z − q.z.
  EXPECT_NEAR(f.sky, kPi * test::point_under_rectangle(0, 0, q.y, 1 - q.x, 3 - q.x, 0, 2 - q.z), 1e-11);
  EXPECT_NEAR(f.ground, kPi * test::point_under_rectangle(0, 0, q.y, 1 - q.x, 3 - q.x, 1 - q.z, 0), 1e-11);
}

// ∫ (L/L_z)(ω) (n·ω) dω over a rectangle o + s u + t v (s, t ∈ [0, 1]) seen wholly from p: in the
// rectangle's plane dω = h dA / r³, by the composite Gauss rule on 12 × 12 panels, graded towards the
// point where the sun's direction crosses it (the indicatrix's kink) if it does.
double through_rectangle(const SkyDistribution& sky, const Point3& p, const Vector3& n, const Point3& o,
                         const Vector3& u, const Vector3& v) {
  const Vector3 m = normalize(cross(u, v));
  const double h = std::abs(dot(m, p - o)), area = length(cross(u, v));
  std::vector<double> s_breaks, t_breaks;
  for (int k = 0; k <= 12; ++k) s_breaks.push_back(k / 12.0), t_breaks.push_back(k / 12.0);
  const double towards = dot(sky.sun(), m), height = dot(o - p, m);
  if (sky.has_sun_kink() && towards * height > 0) {
    const Vector3 y = (p + sky.sun() * (height / towards)) - o;
    const double s = dot(y, u) / dot(u, u), t = dot(y, v) / dot(v, v);
    if (s > 0 && s < 1 && t > 0 && t < 1) s_breaks = graded_about(s, 0, 1), t_breaks = graded_about(t, 0, 1);
  }
  return area * composite(
                    [&](double t) {
                      return composite(
                          [&](double s) {
                            const Vector3 d = (o + u * s + v * t) - p;
                            const double r = length(d);
                            return sky.relative_luminance(d / r) * std::max(0.0, dot(n, d / r)) * h / (r * r * r);
                          },
                          s_breaks, 1);
                    },
                    t_breaks, 1);
}

TEST(SkyDome, GradedSkiesThroughRoofAndFacadeOpenings) {
  // The CIE overcast sky and general types 7 and 12 (the sun at Z_s = 35°, α_s = 200°, seen through the
  // roof opening from the first point) through each opening: the dome (the box face's visible loops,
  // fan cubature) against the direct integral over the opening above.
  const Vector3 sun = sky_direction(35 * kDeg, 200 * kDeg);
  const Room roof = black_room(true, false), facade = black_room(false, true);
  const Point3 under_sun = Point3{2, 2, 3} - sun * (3 / sun.z);  // sees the sun through the opening's centre
  for (const SkyDistribution& sky : {SkyDistribution::cie_overcast(kUp), SkyDistribution::general(7, kUp, sun),
                                     SkyDistribution::general(12, kUp, sun)}) {
    const double tolerance = 3e-9 * sky.horizontal_factor();
    const SkyDome at_roof(roof.triangles, sky), at_facade(facade.triangles, sky);
    for (const Point3& p : {under_sun, Point3{0.6, 3.2, 0}}) {
      const double expected = through_rectangle(sky, p, kUp, {1.5, 1.5, 3}, {1, 0, 0}, {0, 1, 0});
      EXPECT_NEAR(at_roof.at(p, kUp).sky, expected, tolerance) << "type " << sky.type();
    }
    for (const Point3& p : {Point3{2, 1, 0}, Point3{3.5, 2.5, 0.4}}) {
      const double expected = through_rectangle(sky, p, kUp, {1, 0, 1}, {2, 0, 0}, {0, 0, 1});
      EXPECT_NEAR(at_facade.at(p, kUp).sky, expected, tolerance) << "type " << sky.type();
    }
    // A point facing the window at 1.5 m: the upper half of the window is sky.
    const Point3 q{1.6, 1.3, 1.5};
    EXPECT_NEAR(at_facade.at(q, {0, -1, 0}).sky, through_rectangle(sky, q, {0, -1, 0}, {1, 0, 1.5}, {2, 0, 0}, {0, 0, 0.5}),
                tolerance)
        << "type " << sky.type();
  }
}

TEST(SkyDome, CubatureOfAUniformSkyIsTheContourIntegral) {
  // The fan cubature run with L/L_z ≡ 1 over the visible loops of the box's sky triangles (several
  // shadows of the room and of a tilted plate inside it) against π × their contour integral: the
  // accuracy of the quadrature itself, on the regions the dome really integrates.
  Room room = black_room(true, true);
  for (const Triangle& t : test::rectangle({1.2, 1.4, 2.2}, {1.1, 0.3, 0.4}, {-0.2, 0.9, 0.1})) room.triangles.push_back(t);
  ExactVisibility exact(room.triangles);
  exact.set_inclusion_exclusion_limit(0);  // as the dome does: disjoint convex pieces
  const SkyDistribution uniform = SkyDistribution::uniform(kUp);
  const Point3 p{1.9, 1.8, 0.5};
  const Vector3 n = normalize(Vector3{0.2, -0.5, 1});
  const double R = 40;
  const Vector3 e1 = perpendicular(kUp), e2 = cross(kUp, e1);
  auto corner = [&](double i, double j, double k) { return p + (e1 * i + e2 * j + kUp * k) * R; };
  const std::vector<Triangle> top = test::rectangle(corner(-1, -1, 1), (corner(-1, 1, 1) - corner(-1, -1, 1)),
                                                    (corner(1, -1, 1) - corner(-1, -1, 1)));
  const std::vector<Triangle> side = test::rectangle(corner(1, -1, 0), corner(1, -1, 1) - corner(1, -1, 0),
                                                     corner(1, 1, 0) - corner(1, -1, 0));
  int regions = 0;
  for (const std::vector<Triangle>& face : {top, side})
    for (const Triangle& t : face) {
      ASSERT_GT(dot(t.area_vector(), p - t.v[0]), 0);  // faces p
      const ExactVisibility::VisibleRegion region = exact.visible_region(p, n, t);
      regions += region.loops().size() > 1;
      EXPECT_NEAR(sky_integral_over_region(region, p, n, uniform, 1e-13), kPi * region.factor_of(t), 1e-11);
    }
  EXPECT_GT(regions, 0);  // some of the regions are made of several loops (shadows subtracted)
}

// ---- the sky as a LightModel -----------------------------------------------------------------

TEST(SkyLight, NeedsTheScene) {
  SkyLight light;
  light.zenith_radiance_W_m2_sr_nm = {1.0};
  EXPECT_THROW(make_sky_light(light, LightContext{}), std::invalid_argument);
  light.model = SkyLight::Model::kGeneral, light.cie_type = 12;  // depends on the sun, none given
  const std::vector<Triangle> none;
  EXPECT_THROW(make_sky_light(light, LightContext{none, nullptr, true, {}}), std::invalid_argument);
}

TEST(SkyLight, SkyAndGroundThroughAFacadeOpening) {
  // g = sky + (ρ_g K/π) ground [sr per unit L_z]: under the uniform sky (K = π) a probe facing the
  // window sees its upper part as sky and its lower part as ground of luminance ρ_g L_z, so
  //   g = π F(upper) + ρ_g π F(lower),   B-3 corners in the window's plane;
  // unshadowed, the same probe sees half the sky and half the ground: π/2 + ρ_g π/2.
  const Room room = black_room(false, true);
  SkyLight light;
  light.model = SkyLight::Model::kUniform;
  light.ground_reflectance = 0.3;
  light.zenith_radiance_W_m2_sr_nm = {2.0, 3.0};
  const auto model = make_sky_light(light, LightContext{room.triangles, nullptr, true, {}});
  EXPECT_EQ(model->spectrum(), light.zenith_radiance_W_m2_sr_nm);
  EXPECT_EQ(model->flux_factor(), 0);
  const Point3 q{1.6, 1.3, 1.5};
  const Vector3 facing{0, -1, 0};
  const double upper = test::point_under_rectangle(0, 0, q.y, 1 - q.x, 3 - q.x, 0, 2 - q.z);
  const double lower = test::point_under_rectangle(0, 0, q.y, 1 - q.x, 3 - q.x, 1 - q.z, 0);
  const Visibility vis(room.triangles);  // the sky traces no ray
  EXPECT_NEAR(model->point_factor(q, facing, vis), kPi * upper + 0.3 * kPi * lower, 1e-11);
  EXPECT_EQ(vis.rays_traced(), 0u);
  EXPECT_NEAR(model->unshadowed_factor(q, facing), kPi / 2 + 0.3 * kPi / 2, 1e-12);
  const SkySummary summary = summarize_sky(light);
  EXPECT_DOUBLE_EQ(summary.horizontal_factor_sr, kPi);
  EXPECT_DOUBLE_EQ(summary.horizontal_irradiance_W_m2_nm[1], kPi * 3.0);
  EXPECT_DOUBLE_EQ(summary.ground_radiance_W_m2_sr_nm[1], 0.3 * 3.0);  // ρ_g E_h/π = ρ_g L_z here
}

// The mean of f over triangle t by the centroid rule on its n² similar sub-triangles (error O(1/n²)).
template <class F>
double centroid_rule_mean(const Triangle& t, int n, F&& f) {
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j)
      for (int flipped = 0; flipped < (i + j + 1 < n ? 2 : 1); ++flipped) {
        const double a = (i + (flipped ? 2.0 : 1.0) / 3) / n, b = (j + (flipped ? 2.0 : 1.0) / 3) / n;
        sum += f(barycentric(t.v[0], t.v[1], t.v[2], 1 - a - b, a, b));
      }
  return sum / (n * n);
}

TEST(SkyLight, PatchAverageUnderARoofOpening) {
  // A floor patch under the roof opening: the average of π F(p → opening) (B-3 corners) over the
  // triangle, by the centroid rule on 40² and 80² sub-triangles extrapolated (Richardson, O(1/n⁴)),
  // against the model's degree-5 rule of exact point values: within 1e-7 on a 0.5 m triangle (F is
  // smooth on the floor).
  const Room room = black_room(true, false);
  const Visibility vis(room.triangles);
  SkyLight light;
  light.model = SkyLight::Model::kUniform;
  light.zenith_radiance_W_m2_sr_nm = {1.0};
  const auto model = make_sky_light(light, LightContext{room.triangles, nullptr, true, {}});
  const Triangle t{{Point3{1.2, 1.1, 0}, Point3{1.7, 1.2, 0}, Point3{1.4, 1.6, 0}}};
  auto factor = [](const Point3& p) { return kPi * test::point_under_rectangle(p.x, p.y, 3, 1.5, 2.5, 1.5, 2.5); };
  const double coarse = centroid_rule_mean(t, 40, factor), fine = centroid_rule_mean(t, 80, factor);
  EXPECT_NEAR(model->patch_factor(t, vis) / ((4 * fine - coarse) / 3), 1, 1e-7);
}

}  // namespace
}  // namespace lambert
