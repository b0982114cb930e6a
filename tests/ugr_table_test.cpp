// CIE 190's standard UGR table (solver/ugr_table.h): its background luminance against the closed-form
// zonal fluxes of a Lambertian luminaire, one cell against the room's luminaires summed one by one
// with the CIE 117 formula from placed luminaires (scene-frame rotation, the opening's exact solid
// angle, the 3D position index), and the symmetries of crosswise and endwise viewing.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "solver/glare.h"
#include "solver/lights/luminaire.h"
#include "solver/ugr_table.h"
#include "tests/photometric_writer.h"

namespace lambert {
namespace {

using test::kDeg;
using test::steps;

// A type C file with quadrant symmetry (planes 0–90°), I = 1000 cos γ f(C) below the horizon, and a
// rectangular opening of `length` along C0 and `width` along C90.
PhotometricParse quadrant_file(double (*f)(double c_deg), double length, double width) {
  test::IesSpec s;
  s.vertical = steps(0, 90, 2.5);
  s.horizontal = steps(0, 90, 5);
  s.candela = [f](double c, double g) { return 1000 * std::cos(g * kDeg) * f(c); };
  s.length = length, s.width = width;
  return parse_ies(test::ies_text(s), "q.ies");
}
double strong_c0(double c) { return 0.4 + 0.6 * std::pow(std::cos(c * kDeg), 2); }
double strong_c90(double c) { return 0.4 + 0.6 * std::pow(std::sin(c * kDeg), 2); }

struct Luminaire {
  explicit Luminaire(const PhotometricParse& p) : photometry(std::make_shared<const LuminairePhotometry>(*p.data)) {}
  std::shared_ptr<const LuminairePhotometry> photometry;
  UgrTable table() const {
    auto t = standard_ugr_table(photometry->file, photometry->distribution, 1);
    EXPECT_TRUE(t);
    return t ? *t : UgrTable{};
  }
};

TEST(UgrTable, ZonalFluxesAndBackgroundOfALambertianLuminaire) {
  // I = I0 cos γ below the horizon: the cone γ ≤ γn holds π I0 sin² γn = π I0 (1 − un²), un = 0.75,
  // 0.5, 0.25, 0, and nothing goes up. Room 4H × 8H (k = 2.67: F_GL = 0.280, 0.165, 0.499, 0.006;
  // 70/50/20: F_T = 0.115, 0.211, 0.307), N = 16 × 32 = 512 luminaires, A_w = 2 H (X + Y) = 96 m²:
  //   Φ_DF = Σ F_GLn Φ_zLn,  Φ_DW = π I0 − Φ_DF,  L_b = (N / A_w)(0.115 Φ_DF + 0.211 Φ_DW) / π.
  ASSERT_TRUE(quadrant_file([](double) { return 1.0; }, 0.6, 0.6).ok());
  const Luminaire lum(quadrant_file([](double) { return 1.0; }, 0.6, 0.6));
  const UgrZonalFlux f = ugr_zonal_flux(lum.photometry->distribution, 1);
  const double I0 = 1000, u[4] = {0.75, 0.5, 0.25, 0}, fgl[4] = {0.280, 0.165, 0.499, 0.006};
  double direct_plane = 0;
  for (int n = 0; n < 4; ++n) {
    const double cone = kPi * I0 * (1 - u[n] * u[n]);
    // The file's cos γ, interpolated linearly between 2.5° nodes (h = 0.0436 rad), integrates h²/12 =
    // 1.6e-4 low.
    EXPECT_NEAR(f.cumulative[n], cone, 2.5e-4 * cone) << n;
    direct_plane += fgl[n] * cone;
  }
  EXPECT_NEAR(f.upward, 0, 1e-9);
  const double walls = kPi * I0 - direct_plane;
  const double Lb = 512.0 / 96 * (0.115 * direct_plane + 0.211 * walls) / kPi;
  ASSERT_EQ(ugr_rooms()[10].x_h, 4);
  ASSERT_EQ(ugr_rooms()[10].y_h, 8);
  EXPECT_NEAR(ugr_background_luminance(f, 10, 0), Lb, 2.5e-4 * Lb);
}

// One cell by brute force: the room's luminaires placed in the scene one by one (eye at the origin
// looking along +x, up +z; a luminaire at R along the view, T across, H = 2 m above), each adding
// L² ω / p² with L from the placed luminaire towards the eye, ω the opening's exact solid angle and p
// the position index of the direction in 3D; those seen beyond the index table or at γ > 85° do not
// count. Crosswise the C0 half-plane faces the eye (c0 = −view), endwise the C90 half-plane does
// (c0 = +y, so that C90 = up × c0 = −view).
double brute_force_ugr(const Luminaire& lum, std::size_t room, std::size_t reflectance, UgrViewing viewing) {
  const Vector3 view{1, 0, 0}, up{0, 0, 1};
  LuminaireLight light;
  light.photometry = lum.photometry;
  light.nadir = {0, 0, -1};
  light.c0 = viewing == UgrViewing::kCrosswise ? Vector3{-1, 0, 0} : Vector3{0, 1, 0};
  const double H = 2, S = 0.25 * H, X = ugr_rooms()[room].x_h * H, Y = ugr_rooms()[room].y_h * H;
  double sum = 0;
  for (double R = S / 2; R < Y; R += S)
    for (double T = -X / 2 + S / 2; T < X / 2; T += S) {
      light.position = {R, T, H};
      const PlacedLuminaire placed(light);
      const Vector3 d = light.position - Point3{0, 0, 0};
      const double r = length(d);
      const auto p = guth_position_index(view, up, d / r);
      if (!p || H / r < std::cos(85 * kDeg)) continue;
      const double L = placed.luminance_cd_m2(-d / r);
      sum += L * L * placed.opening().solid_angle_sr({0, 0, 0}) / (*p * *p);
    }
  const double Lb = ugr_background_luminance(ugr_zonal_flux(lum.photometry->distribution, 1), room, reflectance);
  return 8 * std::log10(0.25 / Lb * sum);
}

TEST(UgrTable, OneCellAgainstTheRoomSummedLuminaireByLuminaire) {
  // A 0.6 × 0.3 m opening whose intensity is strongest in the C0 plane: crosswise and endwise differ.
  // The table takes ω = A_p / r²; the brute force the rectangle's exact solid angle, which differs by
  // up to 0.7 % for the luminaires in the field (r > 2.2 m; e.g. +0.68 % at R = 2.25, T = 0.75 m,
  // by midpoint quadrature): 8 log10(1.007) = 0.025 UGR.
  const Luminaire lum(quadrant_file(strong_c0, 0.6, 0.3));
  const UgrTable t = lum.table();
  const std::size_t room = 2;  // 2H × 4H: 8 × 16 luminaires
  for (const std::size_t refl : {std::size_t{0}, std::size_t{4}}) {
    ASSERT_TRUE(t.crosswise[room][refl] && t.endwise[room][refl]);
    EXPECT_NEAR(*t.crosswise[room][refl], brute_force_ugr(lum, room, refl, UgrViewing::kCrosswise), 0.03);
    EXPECT_NEAR(*t.endwise[room][refl], brute_force_ugr(lum, room, refl, UgrViewing::kEndwise), 0.03);
  }
  // Seen across its strong C0 plane, the luminaire glares more crosswise.
  EXPECT_GT(*t.crosswise[room][0], *t.endwise[room][0] + 0.5);
}

TEST(UgrTable, CrosswiseAndEndwiseSwapWhenTheLuminaireTurnsAQuarter) {
  // File B is file A turned by 90° about nadir (I_B(C) = I_A(C − 90°), length and width swapped):
  // B seen crosswise is A seen endwise, cell by cell.
  const UgrTable a = Luminaire(quadrant_file(strong_c0, 0.6, 0.3)).table();
  const UgrTable b = Luminaire(quadrant_file(strong_c90, 0.3, 0.6)).table();
  for (std::size_t room = 0; room < kUgrRooms; ++room)
    for (std::size_t k = 0; k < kUgrReflectances; ++k) {
      ASSERT_TRUE(a.crosswise[room][k] && b.endwise[room][k]);
      EXPECT_NEAR(*b.crosswise[room][k], *a.endwise[room][k], 1e-9) << room << " " << k;
      EXPECT_NEAR(*b.endwise[room][k], *a.crosswise[room][k], 1e-9) << room << " " << k;
    }
}

TEST(UgrTable, ARotationallySymmetricLuminaireLooksTheSameBothWays) {
  // One C-plane and a disk of 0.4 m: crosswise = endwise in every cell. UGR rises with the room
  // (more luminaires in the field) and falls with brighter walls (a higher background).
  test::IesSpec s;
  s.vertical = steps(0, 90, 2.5);
  s.horizontal = {0};
  s.candela = [](double, double g) { return 1500 * std::pow(std::cos(g * kDeg), 1.5); };
  s.width = s.length = -0.4;
  const UgrTable t = Luminaire(parse_ies(test::ies_text(s), "disk.ies")).table();
  for (std::size_t room = 0; room < kUgrRooms; ++room)
    for (std::size_t k = 0; k < kUgrReflectances; ++k) {
      ASSERT_TRUE(t.crosswise[room][k] && t.endwise[room][k]);
      EXPECT_NEAR(*t.crosswise[room][k], *t.endwise[room][k], 1e-9) << room << " " << k;
    }
  EXPECT_GT(*t.crosswise[5][0], *t.crosswise[0][0]);  // 2H × 12H over 2H × 2H
  EXPECT_LT(*t.crosswise[8][0], *t.crosswise[8][4]);  // 70/50/20 under 30/30/20
}

TEST(UgrTable, NoTableWithoutALuminousArea) {
  test::IesSpec s;
  s.vertical = steps(0, 90, 5);
  s.horizontal = {0};
  s.candela = [](double, double g) { return 1000 * std::cos(g * kDeg); };
  const Luminaire point(parse_ies(test::ies_text(s), "point.ies"));
  EXPECT_FALSE(standard_ugr_table(point.photometry->file, point.photometry->distribution, 1));
}

}  // namespace
}  // namespace lambert
