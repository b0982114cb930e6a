// The calculation objects (solver/receiver.h): the receivers' weights, the lights' direct factors
// against the point-source closed forms, the shared kernel over a Lambertian triangle against the
// planar decomposition of the contour integral and against the cubature, and probes of every kind
// in solved rooms (the furnace: E = B for every receiver; the planar decomposition of the gather).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "solver/form_factor.h"
#include "solver/light_model.h"
#include "solver/pipeline/probes.h"
#include "solver/radiosity.h"
#include "solver/receiver.h"
#include "solver/receiver_kernel.h"
#include "solver/visibility.h"
#include "tests/scene_builder.h"

namespace lambert {
namespace {

using test::box;
using test::rectangle;
using test::SceneBuilder;

const Vector3 kUp{0, 0, 1};

Receiver make(Receiver::Kind kind, const Point3& p, const Vector3& n, const Vector3& facing = {}) {
  return Receiver{kind, p, normalize(n), facing};
}

// ∫ w dω over the sphere by the midpoint rule in (θ, φ), dω = sin θ dθ dφ, 2000 × 2000 cells: its
// error on these weights, smooth but for a kink along a great circle, is about 1e-6.
double sphere_integral(const Receiver& r) {
  const int n = 2000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double theta = (i + 0.5) * kPi / n, z = std::cos(theta), s = std::sin(theta);
    for (int j = 0; j < n; ++j) {
      const double phi = (j + 0.5) * 2 * kPi / n;
      sum += receiver_weight(r, {s * std::cos(phi), s * std::sin(phi), z}) * s;
    }
  }
  return sum * (kPi / n) * (2 * kPi / n);
}

TEST(Receiver, EveryWeightIntegratesToPiOverTheSphere) {
  // A uniform radiance L gives every receiver E = π L (a diffuse field lights every surface alike):
  // ∫ (n·ω)⁺ dω = π, ∫ sin θ/π dω = π, ∫ (sin θ + f·ω)/π dω = π, ∫ (1 + n·ω)/4 dω = π, ∫ 1/4 dω = π.
  const Point3 o{0, 0, 0};
  for (const Receiver& r : {make(Receiver::Kind::Planar, o, {1, 2, 3}), make(Receiver::Kind::Cylindrical, o, kUp),
                            make(Receiver::Kind::Semicylindrical, o, kUp, {1, 0, 0}),
                            make(Receiver::Kind::Hemispherical, o, {0, 1, 1}), make(Receiver::Kind::Spherical, o, kUp)})
    EXPECT_NEAR(sphere_integral(r), kPi, 1e-5) << static_cast<int>(r.kind);
}

// An isotropic point source of I = 1 W/sr at the origin, no occluder.
struct PointSource {
  PointLight light;
  std::unique_ptr<LightModel> model;
  Visibility vis{std::vector<Triangle>{}};
  PointSource() {
    light.intensity_W_sr_nm = {1.0};
    model = make_light_model(light);
  }
};

TEST(Receiver, PointSourceClosedForms) {
  // A receiver at p, the source at the origin: d = |p|, the light travels along u = p/d, and ε is
  // the angle between u and the axis (sin ε = |a × u|).
  //   cylindrical      E_z  = I sin ε / (π d²)
  //   semicylindrical  E_sz = I sin ε (1 + cos φ) / (π d²),  φ: azimuth of the source from f
  //   hemispherical    E_hs = I (1 + cos ε') / (4 d²),       ε': angle between −u and the pole
  //   vertical         E_v  = I cos α / d²                   (planar, facing a horizontal normal)
  PointSource s;
  const Point3 p{1.2, -0.7, -2.1};
  const double d = length(to_vector(p));
  const Vector3 to_light = -to_vector(p) / d;
  const double sin_eps = length(cross(kUp, to_light));
  const double I = 1.0;
  {
    const Receiver r = make(Receiver::Kind::Cylindrical, p, kUp);
    EXPECT_NEAR(s.model->receiver_factor(r, s.vis), I * sin_eps / (kPi * d * d), 1e-15);
  }
  for (const Vector3 f : {Vector3{1, 0, 0}, Vector3{0, 1, 0}, Vector3{-1, 0, 0}, normalize(Vector3{1, 1, 0})}) {
    const Receiver r = make(Receiver::Kind::Semicylindrical, p, kUp, f);
    const Vector3 horizontal = normalize(Vector3{to_light.x, to_light.y, 0});
    const double cos_phi = dot(horizontal, f);
    EXPECT_NEAR(s.model->receiver_factor(r, s.vis), I * sin_eps * (1 + cos_phi) / (kPi * d * d), 1e-15);
  }
  for (const Vector3 pole : {kUp, Vector3{0, 0, -1}, normalize(Vector3{1, 0, 1})}) {
    const Receiver r = make(Receiver::Kind::Hemispherical, p, pole);
    EXPECT_NEAR(s.model->receiver_factor(r, s.vis), I * (1 + dot(pole, to_light)) / (4 * d * d), 1e-15);
  }
  const Vector3 n = normalize(Vector3{-1, 0.5, 0});
  EXPECT_NEAR(s.model->receiver_factor(make(Receiver::Kind::Planar, p, n), s.vis),
              I * std::max(0.0, dot(n, to_light)) / (d * d), 1e-15);
}

TEST(Receiver, PlanarDecompositionReproducesThePointSourceClosedForms) {
  // The lights' default receiver_factor (the mean of the planar illuminance over the receiver's
  // normals, by adaptive quadrature) against the closed forms of the test above.
  PointSource s;
  const Point3 p{0.4, 0.9, -1.5};
  const double d = length(to_vector(p));
  const Vector3 u = -to_vector(p) / d;
  const double sin_eps = length(cross(kUp, u));
  auto planar = [&](const Vector3& n) { return s.model->point_factor(p, n, s.vis); };
  EXPECT_NEAR(receiver_by_planes(make(Receiver::Kind::Cylindrical, p, kUp), planar), sin_eps / (kPi * d * d),
              1e-7 * sin_eps / (kPi * d * d));
  const Vector3 f{0, 1, 0};
  const double semi = sin_eps * (1 + dot(normalize(Vector3{u.x, u.y, 0}), f)) / (kPi * d * d);
  EXPECT_NEAR(receiver_by_planes(make(Receiver::Kind::Semicylindrical, p, kUp, f), planar), semi, 1e-7 * semi);
  const double hemi = (1 + dot(kUp, u)) / (4 * d * d);
  EXPECT_NEAR(receiver_by_planes(make(Receiver::Kind::Hemispherical, p, kUp), planar), hemi, 1e-6 * hemi);
}

TEST(Receiver, DirectionalAndAmbientLight) {
  // Directional light of E_q = 1 travelling along t: E = w(−t). Ambient: 1 for every receiver.
  const Visibility vis{std::vector<Triangle>{}};
  DirectionalLight sun;
  sun.direction = normalize(Vector3{1, 0, -1});
  sun.irradiance_W_m2_nm = {1.0};
  const auto model = make_light_model(sun);
  const Receiver cyl = make(Receiver::Kind::Cylindrical, {0, 0, 0}, kUp);
  EXPECT_NEAR(model->receiver_factor(cyl, vis), std::sin(kPi / 4) / kPi, 1e-15);  // ε = 45°
  const Receiver hemi = make(Receiver::Kind::Hemispherical, {0, 0, 0}, kUp);
  EXPECT_NEAR(model->receiver_factor(hemi, vis), (1 + std::cos(kPi / 4)) / 4, 1e-15);
  const auto ambient = make_light_model(AmbientLight{{1.0}});
  for (const Receiver& r : {cyl, hemi}) EXPECT_EQ(ambient->receiver_factor(r, vis), 1.0);
}

TEST(Receiver, PhongEmitterAgainstTheKernelAndThePlanarDecomposition) {
  // A Phong-lobed emitter above the point: its own receiver_factor (the cone integral with the
  // receiver's weight). At n = 1 it is a Lambertian emitter, whose factor is the shared kernel
  // (receiver_triangle_factor: closed forms and the graded area cubature, another integrand); at
  // n = 5 it is checked against the decomposition of its planar factor over the cylinder's normals.
  const Visibility vis{std::vector<Triangle>{}};
  const Triangle emitter{{Point3{-0.5, -0.5, 1}, Point3{0.5, 0.5, 1}, Point3{0.5, -0.5, 1}}};  // faces down
  const Point3 p{0.3, 0.2, 0.1};
  const std::vector<Receiver> receivers = {make(Receiver::Kind::Cylindrical, p, kUp),
                                           make(Receiver::Kind::Semicylindrical, p, kUp, {1, 0, 0}),
                                           make(Receiver::Kind::Hemispherical, p, {1, 0, 0})};
  const auto lambertian = make_phong_emitter(emitter, 1, {1.0});
  for (const Receiver& r : receivers) {
    const double kernel = receiver_triangle_factor(r, emitter);
    EXPECT_NEAR(lambertian->receiver_factor(r, vis), kernel, 1e-7 * kernel) << static_cast<int>(r.kind);
  }
  const auto lobed = make_phong_emitter(emitter, 5, {1.0});
  for (const Receiver& r : {receivers[0], receivers[1]}) {
    const double expected = receiver_by_planes(r, [&](const Vector3& n) { return lobed->point_factor(p, n, vis); }, 1e-7);
    EXPECT_NEAR(lobed->receiver_factor(r, vis), expected, 2e-6 * expected) << static_cast<int>(r.kind);
  }
}

// Triangles about the point in several positions: far, near (1e-3 of their size above), crossing the
// axis, beside it, and edge-on.
std::vector<Triangle> kernel_cases() {
  return {Triangle{{Point3{-1, -1, 2}, Point3{1, 2, 3}, Point3{2, -1, 2.5}}},           // above, tilted
          Triangle{{Point3{-0.3, -0.3, -0.001}, Point3{0, 0.4, -0.001}, Point3{0.3, -0.3, -0.001}}},  // just below
          Triangle{{Point3{1, -2, -1}, Point3{1, 2, -1}, Point3{1, 0, 3}}},               // a wall at x = 1 facing −x
          Triangle{{Point3{0.02, -0.5, -0.5}, Point3{0.02, 0.5, -0.5}, Point3{0.02, 0, 0.5}}},  // a wall 2 cm away
          Triangle{{Point3{5, 5, -3}, Point3{6, 5, -3}, Point3{5, 6, -2}}}};              // far, below the horizon
}

TEST(ReceiverKernel, AgainstThePlanarDecompositionOfTheContourIntegral) {
  // The cylindrical part (area cubature), the semicylindrical, hemispherical and spherical closed forms, each
  // against the mean of Lambert's contour integral over the receiver's normals (receiver_by_planes
  // of point_triangle_factor): a second method sharing no code with the kernel but the contour sum.
  const Point3 p{0, 0, 0};
  for (const Triangle& t0 : kernel_cases()) {
    Triangle t = t0;
    if (dot(p - t.v[0], t.area_vector()) < 0) std::swap(t.v[1], t.v[2]);  // face the point
    for (const Receiver& r : {make(Receiver::Kind::Cylindrical, p, kUp), make(Receiver::Kind::Cylindrical, p, {1, 1, 0}),
                              make(Receiver::Kind::Semicylindrical, p, kUp, {0, -1, 0}),
                              make(Receiver::Kind::Semicylindrical, p, kUp, {-1, 0, 0}),
                              make(Receiver::Kind::Hemispherical, p, kUp), make(Receiver::Kind::Hemispherical, p, {-1, 0, 0}),
                              make(Receiver::Kind::Spherical, p, kUp)}) {
      const double kernel = receiver_triangle_factor(r, t);
      const double planes = receiver_by_planes(r, [&](const Vector3& n) { return point_triangle_factor(p, n, t); }, 1e-10);
      EXPECT_NEAR(kernel, planes, 1e-7 * std::max(planes, 1e-3)) << static_cast<int>(r.kind) << " " << t.v[0].x;
    }
  }
}

TEST(ReceiverKernel, CubatureReducesToTheContourIntegralAndTheHemisphericalClosedForm) {
  // The graded cubature with the planar weight (n·ω)⁺ against Lambert's contour integral (a triangle
  // wholly above the horizon, and one the horizon cuts, where the weight has a kink the rule does not
  // follow: looser), and with the hemispherical weight against its closed form.
  const Point3 p{0, 0, 0};
  const Triangle above{{Point3{-0.2, -0.3, 0.05}, Point3{0.4, 0.1, 0.3}, Point3{-0.1, 0.5, 0.2}}};
  Triangle t = above;
  if (dot(p - t.v[0], t.area_vector()) < 0) std::swap(t.v[1], t.v[2]);
  const Receiver planar = make(Receiver::Kind::Planar, p, kUp);
  EXPECT_NEAR(receiver_triangle_cubature(planar, t), point_triangle_factor(p, kUp, t), 1e-9);
  for (const Triangle& t0 : kernel_cases()) {
    Triangle c = t0;
    if (dot(p - c.v[0], c.area_vector()) < 0) std::swap(c.v[1], c.v[2]);
    const Receiver hemi = make(Receiver::Kind::Hemispherical, p, {0, 1, 1});
    const double closed = receiver_triangle_factor(hemi, c);
    EXPECT_NEAR(receiver_triangle_cubature(hemi, c), closed, 1e-8 * std::max(closed, 1e-3));
  }
  const Triangle cut{{Point3{-1, -1, -0.5}, Point3{1, -1, 0.5}, Point3{0, 1, 0.3}}};
  Triangle c = cut;
  if (dot(p - c.v[0], c.area_vector()) < 0) std::swap(c.v[1], c.v[2]);
  const double contour = point_triangle_factor(p, kUp, c);
  EXPECT_NEAR(receiver_triangle_cubature(planar, c), contour, 1e-5 * contour);
}

TEST(ReceiverKernel, NothingFromBehind) {
  const Triangle t{{Point3{-1, -1, 1}, Point3{1, -1, 1}, Point3{0, 1, 1}}};  // faces +z: the point below sees its back
  for (const Receiver& r : {make(Receiver::Kind::Cylindrical, {0, 0, 0}, kUp), make(Receiver::Kind::Hemispherical, {0, 0, 0}, kUp),
                            make(Receiver::Kind::Semicylindrical, {0, 0, 0}, kUp, {1, 0, 0}),
                            make(Receiver::Kind::Spherical, {0, 0, 0}, kUp)})
    EXPECT_EQ(receiver_triangle_factor(r, t), 0.0);
}

// ---- probes of every kind in solved rooms ---------------------------------------------------------

void add_probe(SceneBuilder& b, const std::string& name, const Point3& p, ProbeQuantity q, const Vector3& n,
               const Vector3& facing = {}) {
  b.probe(name, p, n);
  b.scene().probes.back().quantity = q;
  b.scene().probes.back().facing = facing;
}

class CalculationObjectsByMethod : public ::testing::TestWithParam<SolverMethod> {};

TEST_P(CalculationObjectsByMethod, FurnaceGivesEveryReceiverTheRadiosity) {
  // Every surface of a closed room and of a box floating in it emits M = 1 and is black: the
  // radiance is 1/π everywhere, so every receiver anywhere reads E = 1 (R1 for a point receiver),
  // also where the box hides part of a patch (dense: the visible part's loops, exact; hierarchical:
  // the visible share of its rays, and its elements and clusters taken whole within its accuracy).
  const bool dense = GetParam() == SolverMethod::Dense;
  SceneBuilder b;
  b.scene().solver.method = GetParam();
  const int black = b.material("black", 0.0);
  b.surface("room", black, box({0, 0, 0}, {4, 3, 2.5}, true), 1.0);
  b.surface("box", black, box({1.5, 1, 0.8}, {2.5, 2, 1.6}, false), 1.0);
  const std::vector<Point3> points = {{1, 1, 1.2}, {2, 0.5, 1.0}, {3.9, 2.9, 0.1}, {2.0, 2.05, 1.2}};
  for (const Point3& p : points) {
    add_probe(b, "cyl", p, ProbeQuantity::Cylindrical, kUp);
    add_probe(b, "semi", p, ProbeQuantity::Semicylindrical, kUp, {0, -1, 0});
    add_probe(b, "hemi", p, ProbeQuantity::Hemispherical, {1, 0, 0});
    add_probe(b, "vert", p, ProbeQuantity::Vertical, {0, 1, 0});
  }
  const Solution sol = solve(b.scene());
  for (std::size_t k = 0; k < sol.probes.size(); ++k)
    EXPECT_NEAR(sol.probes[k].irradiance[0], 1.0, dense ? 2e-6 : 2e-3) << b.scene().probes[k].name << " at " << k / 4;
  if (dense) {
    EXPECT_GT(sol.stats.exact_visibility_evaluations, 0u);  // the box hid part of some patch
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, CalculationObjectsByMethod,
                         ::testing::Values(SolverMethod::Dense, SolverMethod::Hierarchical),
                         [](const auto& info) { return info.param == SolverMethod::Dense ? "Dense" : "Hierarchical"; });

TEST(CalculationObjects, InterreflectedPartAgainstThePlanarDecomposition) {
  // A grey room lit by a point source under a floating box: the cylindrical, semicylindrical and
  // hemispherical probes' values (direct + gathered) against the mean of planar probes at the same
  // point over the receiver's normals (the trapezoid rule over 96 azimuths, 48 × 96 directions for
  // the hemisphere, whose error on these smooth-but-kinked integrands is below 2e-4).
  SceneBuilder b;
  const int grey = b.material("grey", 0.6);
  b.surface("room", grey, box({0, 0, 0}, {5, 4, 3}, true));
  b.surface("box", grey, box({2, 1.5, 1.9}, {3, 2.5, 2.2}, false));
  b.point_light({2.5, 2, 2.8}, 100);
  const Point3 p{1.7, 1.4, 1.2};
  add_probe(b, "cyl", p, ProbeQuantity::Cylindrical, kUp);
  add_probe(b, "semi", p, ProbeQuantity::Semicylindrical, kUp, {1, 0, 0});
  add_probe(b, "hemi", p, ProbeQuantity::Hemispherical, kUp);
  const int azimuths = 96, rings = 48;
  for (int j = 0; j < azimuths; ++j) {
    const double phi = 2 * kPi * j / azimuths;
    b.probe("plane", p, {std::cos(phi), std::sin(phi), 0});
  }
  for (int i = 0; i < rings; ++i) {
    const double beta = (i + 0.5) * (kPi / 2) / rings;  // midpoint rule in the polar angle
    for (int j = 0; j < azimuths; ++j) {
      const double phi = 2 * kPi * j / azimuths;
      b.probe("ring", p, {std::sin(beta) * std::cos(phi), std::sin(beta) * std::sin(phi), std::cos(beta)});
    }
  }
  const Solution sol = solve(b.scene());
  auto E = [&](std::size_t k) { return sol.probes[k].irradiance[0]; };
  double cyl = 0, semi = 0, hemi = 0;
  for (int j = 0; j < azimuths; ++j) {
    const double phi = 2 * kPi * j / azimuths;
    cyl += E(3 + j) / azimuths;                                              // (1/2π) ∫ E dφ
    if (std::cos(phi) > 1e-12) semi += E(3 + j) * (2 * kPi / azimuths) / kPi;  // (1/π) ∫_{−π/2}^{π/2} E dφ
    else if (std::abs(std::cos(phi)) <= 1e-12) semi += 0.5 * E(3 + j) * (2 * kPi / azimuths) / kPi;
  }
  for (int i = 0; i < rings; ++i) {
    const double beta = (i + 0.5) * (kPi / 2) / rings;
    for (int j = 0; j < azimuths; ++j)
      hemi += E(3 + azimuths + i * azimuths + j) * std::sin(beta) * (kPi / 2 / rings) * (2 * kPi / azimuths) / (2 * kPi);
  }
  EXPECT_NEAR(E(0), cyl, 2e-4 * cyl);
  EXPECT_NEAR(E(1), semi, 2e-4 * semi);
  EXPECT_NEAR(E(2), hemi, 2e-4 * hemi);
}

}  // namespace
}  // namespace lambert
