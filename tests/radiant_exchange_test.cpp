// Radiant exchange between grey surfaces (solver/thermal/grey_exchange.h), against closed forms and
// hand-solved systems (Siegel & Howell's net-radiation method), and against conservation: an
// isothermal enclosure exchanges nothing, and the net fluxes of a closed enclosure sum to zero.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "solver/pipeline/geometric.h"
#include "solver/thermal/radiant.h"
#include "tests/net_radiation.h"
#include "tests/scene_builder.h"

namespace lambert {
namespace {

using test::SceneBuilder;

double sigma_T4(double T) { return kStefanBoltzmann * T * T * T * T; }

SurfaceThermal at(double emissivity, double T) { return {emissivity, T, std::nullopt}; }
SurfaceThermal flux(double emissivity, double q) { return {emissivity, std::nullopt, q}; }

RadiantExchange exchange_of(const Scene& scene) {
  RadiantOptions options;
  options.thermal = true;
  return radiant_exchange(scene, SurfaceGroups::each_surface(scene), options, {});
}

// The box [0, d] seen from inside, one surface per face in test_geometry.h's order (z = 0, z = d.z,
// y = 0, y = d.y, x = 0, x = d.x), each with its thermal boundary.
Scene box_room(const Vector3& d, const std::array<SurfaceThermal, 6>& thermal, double max_patch_area) {
  SceneBuilder b;
  const int black = b.material("black", 0);
  const char* names[] = {"floor", "ceiling", "south", "north", "west", "east"};
  int k = 0;
  test::for_each_box_face(Point3{0, 0, 0}, to_point(d), [&](const Point3& o, const Vector3& u, const Vector3& v) {
    b.surface(names[k], black, test::rectangle(o, u, v)).thermal = thermal[k];
    ++k;
  });
  b.max_patch_area(max_patch_area);
  return b.scene();
}

TEST(RadiantExchange, IsothermalEnclosureExchangesNothing) {
  // A room with a floating box, emissivities from 0.05 to 1 and one reradiating wall: at one
  // temperature everywhere every patch emits what it absorbs, q = 0, and the reradiating wall takes
  // that temperature.
  const double T = 293.15;
  SceneBuilder b;
  const int black = b.material("black", 0);
  const double eps[] = {0.05, 0.3, 0.9, 1.0, 0.6};
  int k = 0;
  test::for_each_box_face(Point3{0, 0, 0}, Point3{4, 3, 2.5}, [&](const Point3& o, const Vector3& u, const Vector3& v) {
    Surface& s = b.surface("wall" + std::to_string(k), black, test::rectangle(o, u, v));
    s.thermal = k == 5 ? flux(0.7, 0.0) : at(eps[k], T);
    ++k;
  });
  b.surface("box", black, test::box({1, 1, 0.5}, {2, 1.8, 1.2}, false)).thermal = at(0.8, T);
  b.max_patch_area(0.1);
  const RadiantExchange r = exchange_of(b.scene());
  ASSERT_TRUE(r.thermal);
  const GreyExchange& g = *r.thermal;
  for (std::size_t i = 0; i < g.patches.size(); ++i) {
    EXPECT_NEAR(g.patches[i].net_flux_W_m2, 0.0, 1e-9 * sigma_T4(T)) << "patch " << i;
    EXPECT_NEAR(g.patches[i].radiosity_W_m2, sigma_T4(T), 1e-9 * sigma_T4(T));
  }
  ASSERT_TRUE(g.surfaces[5].temperature_K);
  EXPECT_NEAR(*g.surfaces[5].temperature_K, T, 1e-6);
  EXPECT_NEAR(g.net_sum_W, 0.0, 1e-9 * sigma_T4(T));
}

// Two concentric faceted spheres: the inner (1, convex, facing out) sees only the outer (2, facing in),
// so F12 = 1, F21 = A1/A2 by reciprocity and F22 = 1 − A1/A2 by closure, and the net-radiation method
// gives q1 = σ (T1⁴ − T2⁴) / (1/ε1 + (A1/A2)(1/ε2 − 1)) (Siegel & Howell; A1, A2 the polyhedra's areas).
TEST(RadiantExchange, ConcentricSpheresAgainstTheClosedForm) {
  const double e1 = 0.8, T1 = 500, e2 = 0.6, T2 = 300;
  SceneBuilder b;
  const int black = b.material("black", 0);
  b.surface("inner", black, test::icosphere({0, 0, 0}, 0.5, 2)).thermal = at(e1, T1);
  std::vector<Triangle> outer = test::icosphere({0, 0, 0}, 1, 2);
  for (Triangle& t : outer) std::swap(t.v[1], t.v[2]);  // facing in
  b.surface("outer", black, outer).thermal = at(e2, T2);
  b.max_patch_area(0.02);
  const RadiantExchange r = exchange_of(b.scene());
  const ViewFactorMatrix& m = r.factors;
  const double ratio = m.area_m2[0] / m.area_m2[1];
  EXPECT_NEAR(m.at(0, 1), 1.0, 1e-12);
  EXPECT_NEAR(m.at(1, 0), ratio, 1e-12);
  EXPECT_NEAR(m.at(1, 1), 1 - ratio, 1e-12);
  const double q1 = (sigma_T4(T1) - sigma_T4(T2)) / (1 / e1 + ratio * (1 / e2 - 1));
  // The surface level (each sphere's radiosity uniform): the closed form to the solver's tolerance.
  const GreyExchange s = grey_exchange(m, {at(e1, T1), at(e2, T2)}, {});
  EXPECT_NEAR(s.surfaces[0].net_flux_W_m2, q1, 1e-6 * q1);
  EXPECT_NEAR(s.surfaces[1].net_W, -q1 * m.area_m2[0], 1e-6 * q1 * m.area_m2[0]);
  // The patch level: each outer facet sees the inner polyhedron a little differently from the sphere.
  const GreyExchange& g = *r.thermal;
  EXPECT_NEAR(g.surfaces[0].net_flux_W_m2, q1, 1e-5 * q1);
  EXPECT_NEAR(g.net_sum_W, 0.0, 1e-9 * q1 * m.area_m2[0]);
}

// F_IJ of the box [0, d] from Howell's catalogue: opposite faces C-11, adjacent faces C-14 (their
// common edge along the third axis). Faces in test_geometry.h's order: normal axes z, z, y, y, x, x.
double box_factor(const Vector3& d, int I, int J) {
  const int axis[] = {2, 2, 1, 1, 0, 0};
  const double dim[] = {d.x, d.y, d.z};
  const int n1 = axis[I], n2 = axis[J];
  if (I == J) return 0;
  if (n1 == n2) {
    const int u = (n1 + 1) % 3, v = (n1 + 2) % 3;
    return test::howell_c11(dim[u] / dim[n1], dim[v] / dim[n1]);
  }
  const int e = 3 - n1 - n2;
  return test::howell_c14(dim[n2] / dim[e], dim[n1] / dim[e]);
}

// J_I − ρ_I Σ_J F_IJ J_J = ε_I σ T_I⁴ over the box's faces (tests/net_radiation.h).
std::vector<double> hand_solved_radiosity(const Vector3& d, const std::array<SurfaceThermal, 6>& t) {
  std::vector<double> eps, T;
  for (const SurfaceThermal& s : t) eps.push_back(s.emissivity), T.push_back(*s.temperature_K);
  return test::net_radiation_radiosity([&](int I, int J) { return box_factor(d, I, J); }, eps, T);
}

// Long coaxial cylinders (regular 12-gon prisms, radii 0.5 and 1, 16 long, ends open to black space
// at 0 K): over the 2 m about the middle the inner one gives off the infinite cylinders' q = σ (T1⁴ −
// T2⁴) / (1/ε1 + (A1/A2)(1/ε2 − 1)), A1/A2 = r1/r2 for similar prisms. The open ends take about 1e-3
// of the view there and make it 6e-4 higher (2e-3 at length 10): the tolerance is 2e-3.
TEST(RadiantExchange, LongCoaxialCylindersAgainstTheClosedForm) {
  const double e1 = 0.8, T1 = 500, e2 = 0.6, T2 = 300, r1 = 0.5, r2 = 1, L = 16;
  const int n = 12, m = 32;  // 12 sides, 32 rings of 0.5 (one patch pair per face of a ring)
  SceneBuilder b;
  const int black = b.material("black", 0);
  std::vector<Triangle> inner, outer;
  for (int k = 0; k < n; ++k) {
    const double a0 = 2 * kPi * k / n, a1 = 2 * kPi * (k + 1) / n;
    const Vector3 c0{std::cos(a0), std::sin(a0), 0}, c1{std::cos(a1), std::sin(a1), 0}, up{0, 0, L / m};
    for (int j = 0; j < m; ++j) {
      for (const Triangle& t : test::rectangle(to_point(c0 * r1 + up * j), (c1 - c0) * r1, up)) inner.push_back(t);  // out
      for (const Triangle& t : test::rectangle(to_point(c0 * r2 + up * j), up, (c1 - c0) * r2)) outer.push_back(t);  // in
    }
  }
  b.surface("inner", black, inner).thermal = at(e1, T1);
  b.surface("outer", black, outer).thermal = at(e2, T2);
  b.max_patch_area(1);
  const RadiantExchange r = exchange_of(b.scene());
  const double q1 = (sigma_T4(T1) - sigma_T4(T2)) / (1 / e1 + (r1 / r2) * (1 / e2 - 1));
  double net_W = 0, area = 0;
  for (std::size_t i = 0; i < r.patches.size(); ++i) {
    const Patch& p = r.patches[i];
    const double z = (p.triangle.v[0].z + p.triangle.v[1].z + p.triangle.v[2].z) / 3;
    if (p.surface != 0 || std::abs(z - L / 2) > 1) continue;
    net_W += r.thermal->patches[i].net_W;
    area += p.area_m2;
  }
  ASSERT_GT(area, 0);
  EXPECT_NEAR(net_W / area, q1, 2e-3 * q1);
}

TEST(RadiantExchange, BoxWithTwoHotFacesAgainstTheHandSolvedSystem) {
  const Vector3 d{2, 1.5, 1};
  const std::array<SurfaceThermal, 6> t = {at(0.9, 400), at(0.8, 300), at(0.6, 300),
                                           at(0.5, 300), at(0.85, 300), at(0.7, 350)};
  const RadiantExchange r = exchange_of(box_room(d, t, 0.01));
  const std::vector<double> J = hand_solved_radiosity(d, t);
  const std::vector<SurfaceThermal> boundary(t.begin(), t.end());
  const GreyExchange s = grey_exchange(r.factors, boundary, {});
  const double scale = sigma_T4(400) - sigma_T4(300);
  for (int I = 0; I < 6; ++I) {
    double H = 0;
    for (int K = 0; K < 6; ++K) H += box_factor(d, I, K) * J[K];
    const double q = J[I] - H;  // the hand-solved net flux of face I
    EXPECT_NEAR(r.factors.at(I, (I + 2) % 6), box_factor(d, I, (I + 2) % 6), 1e-6);
    EXPECT_NEAR(s.surfaces[I].radiosity_W_m2, J[I], 1e-6 * scale) << r.factors.names[I];
    EXPECT_NEAR(s.surfaces[I].net_flux_W_m2, q, 1e-5 * scale) << r.factors.names[I];
    // Patch by patch the radiosity varies over each face (brighter near the hot ones): the surface
    // means of the patch solution differ from the uniform-radiosity method's by that much.
    EXPECT_NEAR(r.thermal->surfaces[I].net_flux_W_m2, q, 1e-2 * scale) << r.factors.names[I];
  }
  EXPECT_NEAR(s.net_sum_W, 0, 1e-9 * scale);
  EXPECT_NEAR(r.thermal->net_sum_W, 0, 1e-9 * scale);
}

// A heated floor (q = 100 W/m²) under a ceiling at 300 K, walls reradiating (q = 0): the walls pass on
// what they receive, the ceiling takes all the floor gives off, and the floor's temperature follows
// from σ T⁴ = H + q/ε.
TEST(RadiantExchange, PrescribedFluxesAreKeptAndBalanced) {
  const std::array<SurfaceThermal, 6> t = {flux(0.9, 100), at(0.8, 300), flux(0.5, 0),
                                           flux(0.5, 0),   flux(0.5, 0), flux(0.5, 0)};
  const RadiantExchange r = exchange_of(box_room({3, 2, 2.5}, t, 0.05));
  const GreyExchange& g = *r.thermal;
  for (std::size_t i = 0; i < g.patches.size(); ++i) {
    const Patch& p = r.patches[i];
    const double q = p.surface == 0 ? 100 : p.surface == 1 ? g.patches[i].net_flux_W_m2 : 0;
    EXPECT_NEAR(g.patches[i].net_flux_W_m2, q, 1e-6 * 100) << "patch " << i << " of surface " << p.surface;
    if (p.surface == 1) continue;
    ASSERT_TRUE(g.patches[i].temperature_K);
    const double eps = t[p.surface].emissivity;
    EXPECT_NEAR(sigma_T4(*g.patches[i].temperature_K), g.patches[i].irradiance_W_m2 + q / eps, 1e-9 * sigma_T4(300));
  }
  EXPECT_NEAR(g.surfaces[0].net_W, 100 * 6, 1e-6 * 600);
  EXPECT_NEAR(g.surfaces[1].net_W, -100 * 6, 1e-6 * 600);
  EXPECT_GT(*g.surfaces[0].temperature_K, 300);
}

TEST(RadiantExchange, FluxesAloneInAClosedEnclosureAreRefused) {
  std::array<SurfaceThermal, 6> t;
  t.fill(flux(0.5, 0));
  t[0] = flux(0.9, 10);
  t[1] = flux(0.9, -10);
  EXPECT_THROW(exchange_of(box_room({1, 1, 1}, t, 0.05)), SolveError);
}

// At the centre of a cube of black faces at different temperatures the sphere sees each face under a
// sixth of all directions: T_mr⁴ = Σ T_I⁴ / 6 (ISO 7726 with angle factors 1/6). A plane facing +z sees
// the ceiling under 4 B-3(1, 1) = 0.5541264 (V1c, s/h = 2) and each wall under a quarter of the rest.
TEST(RadiantExchange, MeanAndPlaneRadiantTemperatureAtTheCentreOfACube) {
  const std::array<double, 6> T = {290, 330, 300, 310, 285, 320};
  std::array<SurfaceThermal, 6> t;
  for (int I = 0; I < 6; ++I) t[I] = at(1.0, T[I]);
  Scene scene = box_room({1, 1, 1}, t, 0.02);
  Probe centre;
  centre.name = "centre";
  centre.points = {{0.5, 0.5, 0.5}};
  centre.normal = {0, 0, 1};
  scene.probes.push_back(centre);
  const RadiantExchange r = exchange_of(scene);
  ASSERT_EQ(r.thermal->probes.size(), 1u);
  const RadiantPoint& p = r.thermal->probes[0][0];
  double mean_T4 = 0, plane_T4 = 0;
  const double ceiling = 4 * test::howell_b3(1, 1);
  EXPECT_NEAR(ceiling, 0.554126424, 1e-9);
  for (int I = 0; I < 6; ++I) {
    mean_T4 += std::pow(T[I], 4) / 6;
    plane_T4 += std::pow(T[I], 4) * (I == 1 ? ceiling : I == 0 ? 0.0 : (1 - ceiling) / 4);
    EXPECT_NEAR(p.view_factors[I], 1.0 / 6, 1e-12);
  }
  EXPECT_NEAR(p.mean_radiant_temperature_K, std::pow(mean_T4, 0.25), 1e-9);
  EXPECT_NEAR(p.plane_radiant_temperature_K, std::pow(plane_T4, 0.25), 1e-9);
}

// Hottel's total exchange factors: with black surfaces they are the view factors; otherwise each
// closed row sums to the surface's emissivity and A_I ℱ_IJ = A_J ℱ_JI.
TEST(RadiantExchange, TotalExchangeFactors) {
  std::array<SurfaceThermal, 6> t;
  t.fill(at(1, 300));
  const Scene scene = box_room({2, 1.5, 1}, t, 0.02);
  RadiantOptions options;
  options.total_exchange_emissivity.assign(6, 1.0);
  const RadiantExchange black = radiant_exchange(scene, SurfaceGroups::each_surface(scene), options, {});
  for (std::size_t k = 0; k < 36; ++k) EXPECT_NEAR(black.total_exchange[k], black.factors.F[k], 1e-12);
  options.total_exchange_emissivity = {0.9, 0.2, 0.5, 0.7, 0.35, 1.0};
  const RadiantExchange grey = radiant_exchange(scene, SurfaceGroups::each_surface(scene), options, {});
  const ViewFactorMatrix& m = grey.factors;
  for (int I = 0; I < 6; ++I) {
    double row = 0;
    for (int J = 0; J < 6; ++J) {
      row += grey.total_exchange[I * 6 + J];
      const double a = m.area_m2[I] * grey.total_exchange[I * 6 + J], b = m.area_m2[J] * grey.total_exchange[J * 6 + I];
      EXPECT_NEAR(a, b, 1e-6 * std::max(a, b));
    }
    EXPECT_NEAR(row, options.total_exchange_emissivity[I], 1e-6);
  }
}

}  // namespace
}  // namespace lambert
