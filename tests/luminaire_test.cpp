// The luminaire light against independent answers (issue 34): files written here from cos^m lobes and
// from an isotropic source reproduce E = I(ψ) cos α / d² at points for every photometry type and
// symmetry; an asymmetric file returns its table at the nodes' directions and turns with the
// luminaire; a closed black room receives the file's flux times the maintenance factor (the energy
// certificate); a Lambertian opening's near field equals the exact contour integral
// (solver/form_factor.h) and Howell's disk factor (B-13), at points and over patches; and at the
// near-field distance d* the point form agrees with the exact field to 10⁻³ of the normal
// illuminance, as luminaire.h derives.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "solver/form_factor.h"
#include "solver/light_model.h"
#include "solver/lights/luminaire.h"
#include "solver/radiosity.h"
#include "tests/photometric_writer.h"
#include "tests/scene_builder.h"

namespace lambert {
namespace {

using test::IesSpec;
using test::LdtSpec;
using test::steps;

LuminaireLight luminaire(const PhotometricParse& parse, const Point3& position, const Vector3& nadir, const Vector3& c0,
                         double scale = 1) {
  if (!parse.ok()) throw std::runtime_error(parse.error);
  LuminaireLight l;
  l.name = "L";
  l.photometry = std::make_shared<const LuminairePhotometry>(*parse.data);
  l.position = position;
  l.nadir = normalize(nadir);
  l.c0 = normalize(c0 - l.nadir * dot(c0, l.nadir));
  l.candela_scale = scale;
  l.intensity_W_sr_nm = {scale};  // one wavelength: g × S is the file's candela × scale
  return l;
}

// A frame turned away from the axes: nadir down and tilted, c0 perpendicular to it.
const Vector3 kNadir = normalize(Vector3{0.3, -0.2, -1});
const Vector3 kC0 = normalize(cross(kNadir, Vector3{0, 1, 0}));

struct Sample { Point3 p; Vector3 n; };
// Receiving points 1–5 m from `centre` in directions within `max_psi` of `axis`, normals facing the
// centre within 75°.
std::vector<Sample> samples(const Point3& centre, const Vector3& axis, double max_psi, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), r(1, 5);
  std::vector<Sample> out;
  while (static_cast<int>(out.size()) < count) {
    const Vector3 w = normalize(Vector3{u(rng), u(rng), u(rng)});
    if (std::acos(std::clamp(dot(w, axis), -1.0, 1.0)) > max_psi) continue;
    const Vector3 n = normalize(-w + Vector3{u(rng), u(rng), u(rng)} * 0.8);
    if (dot(n, -w) < std::cos(75 * test::kDeg)) continue;
    out.push_back({centre + w * r(rng), n});
  }
  return out;
}

// ---- at points: every type and symmetry ---------------------------------------------------------

struct LobeCase {
  std::string name;
  PhotometricParse parse;
};

// Files of I = 1000 cos^m ψ (ψ from nadir; zero above the horizon when m > 0), or 1000 cd everywhere.
std::vector<LobeCase> lobe_files(int m) {
  const double I0 = 1000;
  auto lobe = [=](const Vector3& w) { return m == 0 ? I0 : I0 * std::pow(std::max(0.0, -w.z), m); };
  std::vector<LobeCase> out;
  const std::vector<double> gamma = m == 0 ? steps(0, 180, 0.5) : steps(0, 90, 0.5);
  for (auto [first, last, step] : std::vector<std::tuple<double, double, double>>{
           {0, 0, 1}, {0, 90, 15}, {0, 180, 15}, {0, 360, 15}, {90, 270, 15}, {0, 345, 15}}) {
    IesSpec s;
    s.vertical = gamma;
    s.horizontal = first == last ? std::vector<double>{0} : steps(first, last, step);
    s.candela = [&](double h, double v) { return lobe(test::type_c_direction(h, v)); };
    out.push_back({"IES C " + std::to_string(int(first)) + "-" + std::to_string(int(last)), parse_ies(test::ies_text(s), "c.ies")});
  }
  for (bool mirrored : {true, false}) {
    IesSpec b;  // type B: planes of V about the C90 axis, H across them
    b.type = 2;
    b.vertical = mirrored ? steps(0, 180, 0.5) : steps(-180, 180, 0.5);
    b.horizontal = mirrored ? steps(0, 90, 0.5) : steps(-90, 90, 0.5);
    b.candela = [&](double h, double v) { return lobe(test::type_b_direction(h, v)); };
    out.push_back({mirrored ? "IES B mirrored" : "IES B full", parse_ies(test::ies_text(b), "b.ies")});
    IesSpec a;  // type A: planes of H about the vertical axis, V the elevation; a mirrored V would
    a.type = 3;  // make the light symmetric about the horizontal plane, which a downward lobe is not
    a.vertical = steps(-90, 90, 0.5);
    a.horizontal = mirrored ? steps(0, 180, 0.5) : steps(-180, 180, 0.5);
    a.candela = [&](double h, double v) { return lobe(test::type_a_direction(h, v)); };
    out.push_back({mirrored ? "IES A mirrored" : "IES A full", parse_ies(test::ies_text(a), "a.ies")});
  }
  for (int isym = 0; isym <= 4; ++isym) {
    LdtSpec l;
    l.isym = isym;
    l.mc = 72;
    l.gamma = gamma;
    l.lamp_flux = 1000;  // cd/klm × 1 klm = cd
    l.cd_per_klm = [&](double c, double g) { return lobe(test::type_c_direction(c, g)); };
    out.push_back({"LDT Isym " + std::to_string(isym), parse_ldt(test::ldt_text(l), "l.ldt")});
  }
  return out;
}

TEST(Luminaire, GoniometricClosedFormsForEveryTypeAndSymmetry) {
  const Point3 P{1, 2, 3};
  for (int m : {0, 2}) {
    for (const LobeCase& c : lobe_files(m)) {
      const auto model = make_light_model(luminaire(c.parse, P, kNadir, kC0));
      // The lobe to 75° from its axis: the interpolant's absolute error, ~Δ²I0/4 near a zero of the
      // lobe, is no relative error there (the lobe's edge is covered by the flux below).
      for (const Sample& s : samples(P, kNadir, m == 0 ? test::kDeg * 180 : 75 * test::kDeg, 300, 11)) {
        const Vector3 d = s.p - P;
        const double r = length(d), cos_psi = dot(d, kNadir) / r, cos_alpha = -dot(s.n, d) / r;
        const double I = m == 0 ? 1000 : 1000 * std::pow(std::max(0.0, cos_psi), m);
        const double expected = I * cos_alpha / (r * r);  // E = I(ψ) cos α / d²
        // 10⁻³ of the normal illuminance I/d² of that direction (the acceptance bound); the bilinear
        // web of 0.5° steps errs by ~Δ²m²/8 relative, 1e-4.
        EXPECT_NEAR(model->unshadowed_factor(s.p, s.n), expected, 1e-3 * I / (r * r)) << c.name << " m=" << m;
        if (m == 0) {
          EXPECT_NEAR(model->unshadowed_factor(s.p, s.n), expected, 1e-12 * 1000 / (r * r)) << c.name;
        }
      }
      EXPECT_NEAR(model->flux_factor(), 2 * kPi * 1000 / (m + 1) * (m == 0 ? 2 : 1), 2e-4 * 4 * kPi * 1000) << c.name;
    }
  }
}

// ---- an asymmetric file: its nodes, and the field turning with the luminaire -----------------------

// Periodic in C (the 360° plane repeats the 0° one), no two nodes alike.
double table(double c, double g) {
  const double r = c * test::kDeg;
  return 500 + 150 * std::cos(r) + 80 * std::sin(2 * r + 0.3) + 2.5 * g + 0.4 * g * std::sin(r);
}

TEST(Luminaire, AsymmetricFileReturnsItsTableAtTheNodesInTheSceneFrame) {
  IesSpec s;
  s.vertical = steps(0, 180, 10);
  s.horizontal = steps(0, 360, 10);
  s.candela = table;
  const Point3 P{-1, 0.5, 2};
  const auto model = make_light_model(luminaire(parse_ies(test::ies_text(s), "a.ies"), P, kNadir, kC0));
  // The scene direction of (C, γ): C0 = c0, C90 = up × c0 (counter-clockwise seen from above), γ from nadir.
  const Vector3 up = -kNadir, c90 = cross(up, kC0);
  for (double c = 0; c < 360; c += 10)
    for (double g = 10; g < 180; g += 10) {
      const Vector3 w = kC0 * (std::sin(g * test::kDeg) * std::cos(c * test::kDeg)) +
                        c90 * (std::sin(g * test::kDeg) * std::sin(c * test::kDeg)) - up * std::cos(g * test::kDeg);
      const double d = 2.5;
      // A receiver facing the luminaire at distance d: E d² = I.
      EXPECT_NEAR(model->unshadowed_factor(P + w * d, -w) * d * d, table(c, g), 1e-9 * table(c, g)) << c << " " << g;
    }
}

TEST(Luminaire, TurningTheLuminaireTurnsItsField) {
  IesSpec s;
  s.vertical = steps(0, 180, 5);
  s.horizontal = steps(0, 360, 15);
  s.candela = table;
  const PhotometricParse parse = parse_ies(test::ies_text(s), "a.ies");
  // R: a rotation by 50° about (1, 2, 2)/3 (Rodrigues).
  const Vector3 k = normalize(Vector3{1, 2, 2});
  const double t = 50 * test::kDeg;
  auto R = [&](const Vector3& v) { return v * std::cos(t) + cross(k, v) * std::sin(t) + k * (dot(k, v) * (1 - std::cos(t))); };
  auto Rp = [&](const Point3& p) { return Point3{0, 0, 0} + R(p - Point3{0, 0, 0}); };
  const Point3 P{0.4, -0.3, 2.5};
  const auto a = make_light_model(luminaire(parse, P, kNadir, kC0));
  const auto b = make_light_model(luminaire(parse, Rp(P), R(kNadir), R(kC0)));
  for (const Sample& q : samples(P, kNadir, kPi, 200, 5))
    EXPECT_NEAR(b->unshadowed_factor(Rp(q.p), R(q.n)), a->unshadowed_factor(q.p, q.n),
                1e-10 * std::abs(a->unshadowed_factor(q.p, q.n)) + 1e-14);
  const Triangle floor{{Point3{-2, -2, 0}, Point3{2, -2, 0}, Point3{0, 2, 0}}};
  const Triangle turned{{Rp(floor.v[0]), Rp(floor.v[1]), Rp(floor.v[2])}};
  const Visibility none_a(std::vector<Triangle>{floor}), none_b(std::vector<Triangle>{turned});
  EXPECT_NEAR(b->patch_factor(turned, none_b), a->patch_factor(floor, none_a), 1e-7 * a->patch_factor(floor, none_a));
}

// ---- the flux into a closed black room ------------------------------------------------------------

double received_flux(const Solution& sol) {
  double sum = 0;
  for (std::size_t i = 0; i < sol.patches.size(); ++i) sum += sol.patches[i].area_m2 * sol.irradiance[i * sol.wavelengths()];
  return sum;
}

TEST(Luminaire, ClosedBlackRoomReceivesTheFileFluxTimesTheMaintenanceFactor) {
  // A point luminaire (asymmetric type C), one with a 0.6 × 0.6 m opening 5 cm under the ceiling
  // (its patches near the ceiling take the area form) and a luminous cylinder: Σ A E = Φ_file × MF, Φ_file the interpolant's
  // exact integral (REFERENCES R5 with ρ = 0).
  IesSpec point;
  point.vertical = steps(0, 180, 5);
  point.horizontal = steps(0, 360, 15);
  point.candela = table;
  LdtSpec panel;
  panel.isym = 4, panel.mc = 24, panel.lamp_flux = 4000, panel.lorl = 80;
  panel.area_length_mm = 600, panel.area_width_mm = 600;
  panel.cd_per_klm = [](double c, double g) { return g <= 90 ? 250 * std::cos(g * test::kDeg) * (1 + 0.2 * std::cos(2 * c * test::kDeg)) : 0.0; };
  LdtSpec point_panel = panel;
  point_panel.area_length_mm = point_panel.area_width_mm = 0;
  // A luminous vertical cylinder 0.3 m across and 0.4 m high (LM-63-2002: width = length < 0,
  // height > 0), up and down light: its patch averages are the degree-5 rule of point values.
  IesSpec cylinder;
  cylinder.vertical = steps(0, 180, 5);
  cylinder.horizontal = {0};
  cylinder.candela = [](double, double g) { return 300 * (1 + 0.5 * std::cos(g * test::kDeg)); };
  cylinder.width = cylinder.length = -0.3, cylinder.height = 0.4;
  struct Case { std::string name; LuminaireLight light; };
  const std::vector<Case> cases = {
      {"point", luminaire(parse_ies(test::ies_text(point), "p.ies"), {2, 1.5, 1.8}, kNadir, kC0, 0.8)},
      {"panel", luminaire(parse_ldt(test::ldt_text(panel), "p.ldt"), {2.2, 2.1, 2.95}, {0, 0, -1}, {1, 0, 0}, 0.7)},
      {"panel as a point", luminaire(parse_ldt(test::ldt_text(point_panel), "q.ldt"), {2.2, 2.1, 2.95}, {0, 0, -1}, {1, 0, 0}, 0.7)},
      {"cylinder", luminaire(parse_ies(test::ies_text(cylinder), "c.ies"), {1.9, 2.2, 2.5}, {0, 0, -1}, {1, 0, 0}, 0.9)},
  };
  for (const Case& c : cases) {
    test::SceneBuilder b;
    b.surface("room", b.material("black", 0), test::box({0, 0, 0}, {4, 4, 3}, true));
    b.max_patch_area(0.6);  // 134 patches: the near field's sum is as exact on few as on many
    b.scene().lights.push_back(c.light);
    b.scene().light_pointers.push_back("/lights/0");
    const Solution sol = solve(b.scene());
    const double flux = c.light.photometry->distribution.flux() * c.light.candela_scale;
    EXPECT_NEAR(sol.stats.emitted_W, flux, 1e-9 * flux) << c.name;  // one wavelength of weight 1 nm
    EXPECT_NEAR(received_flux(sol), flux, 1e-3 * flux) << c.name;   // the acceptance bound
    // What it achieves: 2e-5 where patch averages are exact in angle (point, flat panel); a solid
    // opening's degree-5 rule of point values over each patch reaches 4.8e-4 here.
    EXPECT_NEAR(received_flux(sol), flux, (c.name == "cylinder" ? 6e-4 : 2e-5) * flux) << c.name;
    EXPECT_LT(std::abs(sol.stats.relative_imbalance), 2e-5) << c.name;
  }
}

// ---- the near field of a Lambertian opening -------------------------------------------------------

// I = I0 cos γ below, nothing above: a Lambertian flat opening of radiance L = I0 / A.
PhotometricParse lambertian(double width, double length) {
  IesSpec s;
  s.vertical = steps(0, 90, 0.25);
  s.horizontal = {0};
  s.candela = [](double, double v) { return 2000 * std::cos(v * test::kDeg); };
  s.width = width, s.length = length;
  return parse_ies(test::ies_text(s), "lambertian.ies");
}

TEST(Luminaire, NearFieldOfALambertianRectangleIsTheContourIntegral) {
  // A 0.6 × 0.3 m opening at z = 3 facing down, C0 along x: E = π L F(p → rectangle) exactly.
  const Point3 P{0, 0, 3};
  const LuminaireLight light = luminaire(lambertian(0.3, 0.6), P, {0, 0, -1}, {1, 0, 0});
  const auto model = make_light_model(light);
  const double L = 2000 / (0.6 * 0.3);
  const std::vector<Point3> rectangle = {{-0.3, -0.15, 3}, {-0.3, 0.15, 3}, {0.3, 0.15, 3}, {0.3, -0.15, 3}};  // CCW from below
  const std::vector<Sample> cases = {
      {{0, 0, 2.95}, {0, 0, 1}},   {{0, 0, 2.8}, {0, 0, 1}},          {{0.1, 0.05, 2.99}, {0, 0, 1}},
      {{0, 0, 2}, {0, 0, 1}},      {{1, 0.5, 2.5}, normalize(Vector3{-1, 0, 1})}, {{0.5, 0, 2.9}, {-1, 0, 0}},
      {{0, 0.4, 2.99}, {0, -1, 0}}, {{2, -1, 0}, normalize(Vector3{-0.2, 0.1, 1})}, {{0.2, 0.1, 2.7}, normalize(Vector3{1, 1, 1})},
      // beyond d*/√10 = 3.9 m, where the 4-point rule takes over
      {{3, 2, -2}, normalize(Vector3{-1, 0, 1})}, {{6, 0, -3}, normalize(Vector3{-1, 0, 2})}, {{0.5, 0.5, -8}, {0, 0, 1}}};
  for (const Sample& s : cases) {
    const double exact = kPi * L * point_polygon_factor(s.p, s.n, rectangle);
    ASSERT_LT(distance(s.p, P), PlacedLuminaire(light).near_field_distance_m());
    EXPECT_NEAR(model->unshadowed_factor(s.p, s.n), exact, 1e-4 * exact + 1e-9) << s.p.x << " " << s.p.y << " " << s.p.z;
  }
  // Patch averages: π L A_p F(p → opening) / A_p, the exact kernel integrated over the patch.
  const std::vector<Triangle> opening = {Triangle{{rectangle[0], rectangle[1], rectangle[2]}},
                                         Triangle{{rectangle[0], rectangle[2], rectangle[3]}}};
  for (const Triangle& patch : {Triangle{{Point3{-0.5, -0.5, 2.5}, Point3{0.5, -0.5, 2.5}, Point3{0, 0.5, 2.5}}},
                                Triangle{{Point3{0.4, 0.3, 2.7}, Point3{0.4, -0.3, 2.7}, Point3{0.4, 0.0, 3.0}}},
                                Triangle{{Point3{-3, -3, 0}, Point3{3, -3, 0}, Point3{0, 3, 0}}}}) {
    double exact = 0;
    for (const Triangle& o : opening) exact += kPi * L * area_form_factor(patch, o) / patch.area();
    const Visibility nothing(std::vector<Triangle>{patch});
    EXPECT_NEAR(model->patch_factor(patch, nothing), exact, 1e-4 * exact) << patch.v[0].x;
  }
}

TEST(Luminaire, NearFieldOfALambertianDiskIsHowellsFactor) {
  // Howell B-13: a receiver parallel to a disk of radius r at height h, offset a (H = h/a, R = r/a):
  // F = ½ (1 − (1 + H² − R²) / √((1 + H² + R²)² − 4R²)); on the axis, F = r² / (r² + h²).
  const double r = 0.2, I0 = 2000, L = I0 / (kPi * r * r);
  const Point3 P{0, 0, 3};
  IesSpec s;
  s.vertical = steps(0, 90, 0.25);
  s.horizontal = {0};
  s.candela = [&](double, double v) { return I0 * std::cos(v * test::kDeg); };
  s.width = -2 * r, s.length = -2 * r;  // LM-63-2002: negative equal width and length, a circle
  const auto model = make_light_model(luminaire(parse_ies(test::ies_text(s), "disk.ies"), P, {0, 0, -1}, {1, 0, 0}));
  // d* = 44.7 r = 8.9 m: the last two are in the 4-point rule's range (beyond d*/√10 = 2.8 m).
  for (const auto& [a, h] : std::vector<std::pair<double, double>>{
           {0, 0.05}, {0, 0.5}, {0.1, 0.1}, {0.3, 0.2}, {1.5, 1}, {0.05, 2.5}, {3, 2}, {0.5, 6}}) {
    double F;
    if (a == 0) {
      F = r * r / (r * r + h * h);
    } else {
      const double H = h / a, R = r / a;
      F = 0.5 * (1 - (1 + H * H - R * R) / std::sqrt(std::pow(1 + H * H + R * R, 2) - 4 * R * R));
    }
    EXPECT_NEAR(model->unshadowed_factor({a, 0, 3 - h}, {0, 0, 1}), kPi * L * F, 1e-4 * kPi * L * F) << a << " " << h;
  }
}

TEST(Luminaire, AtTheNearFieldDistanceThePointFormAgreesToOnePerMille) {
  // The rule of luminaire.h: at d*, |E_point − E_exact| ≤ 10⁻³ I_max/d² for every direction below
  // the opening and receiver facing within 80°, E_exact the contour integral.
  const LuminaireLight light = luminaire(lambertian(0.3, 0.6), {0, 0, 3}, {0, 0, -1}, {1, 0, 0});
  const PlacedLuminaire placed(light);
  const double d = placed.near_field_distance_m();
  // <ρ²> = (0.6² + 0.3²)/12 and κ₁ = κ₂ = 1 for I0 cos γ: d* = √(8 <ρ²> / 2e-3) = √150.
  EXPECT_NEAR(d, std::sqrt(150.0), 1e-3 * d);
  const std::vector<Point3> rectangle = {{-0.3, -0.15, 3}, {-0.3, 0.15, 3}, {0.3, 0.15, 3}, {0.3, -0.15, 3}};
  const double L = 2000 / 0.18;
  double worst = 0;
  for (double g = 0; g <= 89; g += 4)
    for (double c = 0; c < 360; c += 30)
      for (double tilt = 0; tilt <= 80; tilt += 20)
        for (double turn = 0; turn < 360; turn += 90) {
          const Vector3 w = test::type_c_direction(c, g);
          const Point3 p = Point3{0, 0, 3} + w * d;
          const Vector3 side = normalize(cross(w, std::abs(w.z) < 0.9 ? Vector3{0, 0, 1} : Vector3{1, 0, 0}));
          const Vector3 other = cross(w, side);
          const Vector3 n = -w * std::cos(tilt * test::kDeg) +
                            (side * std::cos(turn * test::kDeg) + other * std::sin(turn * test::kDeg)) * std::sin(tilt * test::kDeg);
          const double I = 2000 * std::cos(g * test::kDeg);
          const double point = I * std::max(0.0, -dot(n, w)) / (d * d);
          const double exact = kPi * L * point_polygon_factor(p, n, rectangle);
          worst = std::max(worst, std::abs(point - exact) / (2000 / (d * d)));
        }
  EXPECT_LE(worst, 1e-3);
  EXPECT_GE(worst, 0.3e-3);  // and the rule is not needlessly far: the worst error is of its order
}

TEST(Luminaire, OpeningShadowsComeFromItsArea) {
  // A plate under half of the opening: the point beneath sees part of it. The rays' estimate is
  // checked against the exact visible part (ExactVisibility would give it; here the plate covers
  // x < 0 of the opening seen from directly below, so the visible part is the x > 0 half).
  const LuminaireLight light = luminaire(lambertian(0.3, 0.6), {0, 0, 3}, {0, 0, -1}, {1, 0, 0});
  const auto model = make_light_model(light);
  const std::vector<Triangle> plate = {Triangle{{Point3{-1, -1, 2.9}, Point3{0, -1, 2.9}, Point3{0, 1, 2.9}}},
                                       Triangle{{Point3{-1, -1, 2.9}, Point3{0, 1, 2.9}, Point3{-1, 1, 2.9}}}};
  const Visibility vis(plate);
  const Point3 p{0, 0, 2.0};
  const std::vector<Point3> right_half = {{0, -0.15, 3}, {0, 0.15, 3}, {0.3, 0.15, 3}, {0.3, -0.15, 3}};
  // From p the plate's edge x = 0 at z = 2.9 projects to x = 0 at the opening: the x > 0 half shows.
  const double visible = kPi * 2000 / 0.18 * point_polygon_factor(p, {0, 0, 1}, right_half);
  const double unshadowed = model->unshadowed_factor(p, {0, 0, 1});
  EXPECT_NEAR(model->point_factor(p, {0, 0, 1}, vis), visible, 0.05 * unshadowed);
  EXPECT_NEAR(model->point_factor({3, 0, 2.0}, {0, 0, 1}, vis), model->unshadowed_factor({3, 0, 2.0}, {0, 0, 1}), 1e-12);
  // From (−4, 0, 2) every ray to the opening crosses z = 2.9 at x in [−0.67, −0.13]: on the plate.
  EXPECT_GT(model->unshadowed_factor({-4, 0, 2.0}, {0, 0, 1}), 0.0);
  EXPECT_EQ(model->point_factor({-4, 0, 2.0}, {0, 0, 1}, vis), 0.0);
}

// ---- what calculation objects and glare see --------------------------------------------------------

// An isotropic point luminaire of I = 1000 cd.
LuminaireLight isotropic_at(const Point3& P) {
  IesSpec s;
  s.vertical = steps(0, 180, 5);
  s.horizontal = {0};
  s.candela = [](double, double) { return 1000.0; };
  return luminaire(parse_ies(test::ies_text(s), "iso.ies"), P, {0, 0, -1}, {1, 0, 0});
}

TEST(Luminaire, CurvedReceiversSeeThePointFormAsTheirClosedForms) {
  // Cylindrical illuminance from a point source: E_z = I sin ε / (π d²), ε between the light's
  // direction and the axis (issue 34); the semicylinder and hemisphere against the planar
  // decomposition (solver/receiver_kernel.h), a second method, to its quadrature's 1e-6.
  const auto model = make_light_model(isotropic_at({0, 0, 3}));
  const Visibility vis(std::vector<Triangle>{});
  for (const Point3& p : {Point3{2, 1, 1.2}, Point3{-0.5, 3, 0}, Point3{0.1, 0, 2.5}}) {
    const Vector3 d = Point3{0, 0, 3} - p;
    const double dist = length(d), sin_eps = length(cross(Vector3{0, 0, 1}, d)) / dist;
    const Receiver cyl{Receiver::Kind::Cylindrical, p, {0, 0, 1}, {}};
    EXPECT_NEAR(model->receiver_factor(cyl, vis), 1000 * sin_eps / (kPi * dist * dist), 1e-12);
    for (const Receiver& r : {Receiver{Receiver::Kind::Semicylindrical, p, {0, 0, 1}, {1, 0, 0}},
                              Receiver{Receiver::Kind::Hemispherical, p, normalize(Vector3{0.3, 0, 1}), {}}}) {
      const double exact = model->receiver_factor(r, vis), planes = model->LightModel::receiver_factor(r, vis);
      EXPECT_NEAR(exact, planes, 1e-6 * exact);
    }
  }
}

// Ω of the rectangle [x1, x2] × [y1, y2] in a plane at height h above the eye, coordinates from the
// eye's foot: the corner formula Ω(x, y) = atan(x y / (h √(x² + y² + h²))) by superposition.
double rectangle_solid_angle(double x1, double x2, double y1, double y2, double h) {
  auto corner = [h](double x, double y) { return std::atan(x * y / (h * std::sqrt(x * x + y * y + h * h))); };
  return corner(x2, y2) - corner(x1, y2) - corner(x2, y1) + corner(x1, y1);
}

TEST(Luminaire, GlareSeesTheOpeningsLuminanceAndSolidAngle) {
  // The Lambertian 0.6 × 0.3 m opening at z = 3 (I = 2000 cos γ): L = I0 / A toward every direction
  // below, A_proj = A cos γ, and the solid angle the rectangle's corner formula gives.
  const LuminaireLight light = luminaire(lambertian(0.3, 0.6), {0, 0, 3}, {0, 0, -1}, {1, 0, 0});
  const auto model = make_light_model(light);
  const Visibility open(std::vector<Triangle>{});
  for (const Point3& eye : {Point3{0, 0, 1.2}, Point3{1.0, 0.4, 1.0}, Point3{-2.5, 1.5, 1.2}}) {
    const GlareView g = model->glare_view(eye, open);
    ASSERT_EQ(g.kind, GlareView::Kind::Area);
    const double h = 3 - eye.z, dist = distance(eye, Point3{0, 0, 3});
    EXPECT_NEAR(g.luminance, 2000 / 0.18, 1e-4 * 2000 / 0.18);
    EXPECT_NEAR(g.projected_area_m2, 0.18 * h / dist, 1e-12);
    const double omega = rectangle_solid_angle(-0.3 - eye.x, 0.3 - eye.x, -0.15 - eye.y, 0.15 - eye.y, h);
    EXPECT_NEAR(g.solid_angle_sr, omega, 1e-9 * omega);
    EXPECT_NEAR(g.distance_m, dist, 1e-12);
  }
  // Half hidden by the plate under x < 0 (seen from below the centre), and wholly hidden from x = −4.
  const std::vector<Triangle> plate = {Triangle{{Point3{-1, -1, 2.9}, Point3{0, -1, 2.9}, Point3{0, 1, 2.9}}},
                                       Triangle{{Point3{-1, -1, 2.9}, Point3{0, 1, 2.9}, Point3{-1, 1, 2.9}}}};
  const Visibility vis(plate);
  const GlareView half = model->glare_view({0, 0, 2}, vis);
  EXPECT_NEAR(half.projected_area_m2 / 0.18, 0.5, 0.1);
  EXPECT_EQ(model->glare_view({-4, 0, 2}, vis).kind, GlareView::Kind::None);
  // Above the opening's plane (γ > 90°) the file has no light.
  EXPECT_EQ(model->glare_view({1, 0, 3.5}, open).kind, GlareView::Kind::None);
  // A point luminaire is its intensity toward the eye.
  const GlareView point = make_light_model(isotropic_at({0, 0, 3}))->glare_view({2, 1, 1.2}, open);
  ASSERT_EQ(point.kind, GlareView::Kind::Point);
  EXPECT_NEAR(point.intensity, 1000, 1e-9);
}

}  // namespace
}  // namespace lambert
