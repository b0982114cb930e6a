// The IES LM-63 and EULUMDAT readers and the distribution they make: files written here from known
// tables are read back value for value; every kind of broken file is refused with the file, the line
// and the field; no input makes a reader crash; the interpolant returns the file's values at its
// nodes, unfolds each symmetry into the same web a full file gives, and integrates exactly (closed
// forms for distributions the interpolant reproduces exactly, linear in its angles).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "solver/photometry/distribution.h"
#include "solver/photometry/photometric_data.h"
#include "tests/photometric_writer.h"

namespace lambert {
namespace {

using test::IesSpec;
using test::LdtSpec;
using test::steps;

constexpr double kPiD = 3.14159265358979323846;

PhotometricData read_ies(const std::string& text) {
  PhotometricParse r = parse_ies(text, "t.ies");
  if (!r.ok()) throw std::runtime_error(r.error);
  return std::move(*r.data);
}
PhotometricData read_ldt(const std::string& text) {
  PhotometricParse r = parse_ldt(text, "t.ldt");
  if (!r.ok()) throw std::runtime_error(r.error);
  return std::move(*r.data);
}

// A small type C file: vertical 0, 45, 90; horizontal 0, 90 (quadrant symmetry).
const char* kBaseIes =
    "IESNA:LM-63-2002\n"   // 1
    "[TEST] t\n"           // 2
    "[MANUFAC] m\n"        // 3
    "TILT=NONE\n"          // 4
    "1 1000 1 3 2 1 2 0 0 0\n"  // 5
    "1 1 10\n"             // 6
    "0 45 90\n"            // 7
    "0 90\n"               // 8
    "100 80 10\n"          // 9
    "100 70 5\n";          // 10

std::string with_line(std::string text, int line, const std::string& replacement) {
  std::vector<std::string> lines;
  std::string current;
  for (char c : text) {
    if (c == '\n') lines.push_back(current), current.clear();
    else current += c;
  }
  if (!current.empty()) lines.push_back(current);
  if (line == 0) lines.push_back(replacement);  // 0: append
  else lines.at(static_cast<std::size_t>(line - 1)) = replacement;
  std::string out;
  for (const std::string& l : lines)
    if (l != "\x01") out += l + "\n";  // "\x01": drop the line
  return out;
}

void expect_refused(const PhotometricParse& r, const std::string& expected, const std::string& what) {
  ASSERT_FALSE(r.ok()) << what;
  EXPECT_NE(r.error.find(expected), std::string::npos) << what << "\n  got: " << r.error << "\n  expected: " << expected;
}

// ---- IES ----------------------------------------------------------------------------------------

TEST(IesReader, ReadsTheTableWithItsMultipliers) {
  IesSpec s;
  s.vertical = steps(0, 90, 15);
  s.horizontal = steps(0, 360, 30);
  s.candela = [](double h, double v) { return 100 + h + v / 10; };
  s.lamps = 2, s.lumens_per_lamp = 1500, s.multiplier = 2, s.ballast = 0.9, s.watts = 35;
  const PhotometricData d = read_ies(test::ies_text(s));
  EXPECT_EQ(d.version, "LM-63-2002");
  EXPECT_EQ(d.type, PhotometryType::kC);
  ASSERT_EQ(d.candela.size(), 7u * 13u);
  for (std::size_t i = 0; i < 13; ++i)
    for (std::size_t j = 0; j < 7; ++j)
      EXPECT_DOUBLE_EQ(d.candela[i * 7 + j], 1.8 * (100 + 30.0 * i + 1.5 * j));  // × multiplier × ballast
  EXPECT_EQ(d.declared_lamp_flux_lm, 3000);
  EXPECT_FALSE(d.absolute_photometry);
  EXPECT_EQ(d.input_watts, 35);
}

TEST(IesReader, EveryVersion) {
  struct Case { std::string line; std::vector<std::string> keywords; std::string version; double scale; };
  // 1986 has no version line and free labels; 1986 and 1991 multiply by the ballast-lamp factor.
  const std::vector<Case> cases = {
      {"", {"Any label text", "more label"}, "LM-63-1986", 0.5},
      {"IESNA91", {"[TEST] t", "[MANUFAC] m"}, "LM-63-1991", 0.5},
      {"IESNA:LM-63-1995", {"[TEST] t", "[MANUFAC] m", "[MORE] more"}, "LM-63-1995", 1},
      {"IESNA:LM-63-2002", {"[TEST] t", "[MANUFAC] m"}, "LM-63-2002", 1},
      {"IES:LM-63-2019", {"[TEST] t", "[TESTLAB] l", "[ISSUEDATE] 2024-01-01", "[MANUFAC] m", "[_USER_KEY] x"}, "LM-63-2019", 1},
  };
  for (const Case& c : cases) {
    IesSpec s;
    s.version_line = c.line;
    s.keywords = c.keywords;
    s.vertical = {0, 90};
    s.horizontal = {0};
    s.second = 0.5;  // the ballast-lamp photometric factor (1986/1991), "future use" or file type after
    s.candela = [](double, double v) { return 200 - v; };
    const PhotometricData d = read_ies(test::ies_text(s));
    EXPECT_EQ(d.version, c.version);
    EXPECT_DOUBLE_EQ(d.candela[0], 200 * c.scale) << c.version;
    EXPECT_TRUE(d.warnings.empty()) << c.version;
  }
}

TEST(IesReader, MissingRequiredKeywordsAreWarnings) {
  IesSpec s;
  s.version_line = "IES:LM-63-2019";
  s.keywords = {"[TEST] t"};
  s.vertical = {0, 90};
  s.horizontal = {0};
  s.candela = [](double, double) { return 1.0; };
  const PhotometricData d = read_ies(test::ies_text(s));
  ASSERT_EQ(d.warnings.size(), 3u);
  EXPECT_NE(d.warnings[0].find("[TESTLAB]"), std::string::npos) << d.warnings[0];
}

TEST(IesReader, AbsolutePhotometryTiltAndCommas) {
  IesSpec s;
  s.tilt = "TILT=INCLUDE\n1\n3\n0 45 90\n1.0, 0.9, 0.7";
  s.vertical = {0, 90};
  s.horizontal = {0};
  s.candela = [](double, double) { return 5.0; };
  std::string text = test::ies_text(s);
  const PhotometricData d = read_ies(text);
  EXPECT_TRUE(d.absolute_photometry);
  EXPECT_FALSE(d.declared_lamp_flux_lm);
  ASSERT_TRUE(d.tilt);
  EXPECT_EQ(d.tilt->lamp_to_luminaire_geometry, 1);
  EXPECT_EQ(d.tilt->factors, (std::vector<double>{1.0, 0.9, 0.7}));
  EXPECT_EQ(d.candela, (std::vector<double>{5, 5}));
}

TEST(IesReader, LuminousShapesBySign) {
  struct Case { std::string version; double w, l, h; LuminousShape shape; double length, width, height; };
  const double ft = 0.3048;
  const std::vector<Case> cases = {
      {"IESNA:LM-63-2002", 0, 0, 0, LuminousShape::kPoint, 0, 0, 0},
      {"IESNA:LM-63-2002", 0.3, 0.6, 0, LuminousShape::kRectangle, 0.6, 0.3, 0},
      {"IESNA:LM-63-2002", 0.3, 0.6, 0.1, LuminousShape::kBox, 0.6, 0.3, 0.1},
      {"IESNA:LM-63-2002", -0.2, -0.2, 0, LuminousShape::kDisk, 0.2, 0.2, 0},
      {"IESNA:LM-63-2002", -0.2, -0.4, 0, LuminousShape::kEllipse, 0.4, 0.2, 0},
      {"IESNA:LM-63-2002", -0.2, -0.2, 0.3, LuminousShape::kVerticalCylinder, 0.2, 0.2, 0.3},
      {"IESNA:LM-63-2002", -0.2, -0.2, -0.2, LuminousShape::kSphere, 0.2, 0.2, 0.2},
      {"IESNA:LM-63-2002", -0.1, 1.2, -0.1, LuminousShape::kHorizontalCylinderAlongC0, 1.2, 0.1, 0.1},
      {"IESNA:LM-63-2002", -0.2, -0.4, -0.3, LuminousShape::kUnsupported, 0.4, 0.2, 0.3},
      {"IES:LM-63-2019", 0.3, -0.1, -0.1, LuminousShape::kHorizontalCylinderAlongC90, 0.1, 0.3, 0.1},
      {"IESNA:LM-63-1995", -0.2, 0, 0, LuminousShape::kDisk, 0.2, 0.2, 0},
      {"IESNA:LM-63-1995", -0.2, 0, 0.3, LuminousShape::kVerticalCylinder, 0.2, 0.2, 0.3},
  };
  for (const Case& c : cases) {
    IesSpec s;
    s.version_line = c.version;
    s.keywords = {"[TEST] t", "[TESTLAB] l", "[ISSUEDATE] d", "[MANUFAC] m"};
    s.vertical = {0, 90};
    s.horizontal = {0};
    s.candela = [](double, double) { return 1.0; };
    s.width = c.w, s.length = c.l, s.height = c.h;
    const PhotometricData d = read_ies(test::ies_text(s));
    EXPECT_EQ(d.opening.shape, c.shape) << c.version << " " << c.w << " " << c.l << " " << c.h;
    EXPECT_NEAR(d.opening.length_m, c.length, 1e-12) << luminous_shape_name(c.shape);
    EXPECT_NEAR(d.opening.width_m, c.width, 1e-12) << luminous_shape_name(c.shape);
    EXPECT_NEAR(d.opening.height_m, c.height, 1e-12) << luminous_shape_name(c.shape);
  }
  IesSpec feet;
  feet.units = 1, feet.width = 2, feet.length = 4;
  feet.vertical = {0, 90};
  feet.horizontal = {0};
  feet.candela = [](double, double) { return 1.0; };
  const PhotometricData d = read_ies(test::ies_text(feet));
  EXPECT_DOUBLE_EQ(d.opening.width_m, 2 * ft);
  EXPECT_DOUBLE_EQ(d.opening.length_m, 4 * ft);
}

TEST(IesReader, BrokenFilesNameTheLineAndTheField) {
  struct Case { int line; std::string replacement; std::string expected; };
  const std::vector<Case> cases = {
      {10, "\x01", "t.ies: line 10: the file ends before candela value 1 of horizontal angle 90"},
      {0, "5", "line 11: '5' follows the last of the 6 candela values the header declares"},
      {5, "1 1000 1 4 2 1 2 0 0 0", "line 8: vertical angle 4: 0 does not follow 90 in ascending order"},
      {9, "100 nan 10", "line 9: candela value 2 of horizontal angle 0: 'nan' is not a finite number"},
      {9, "100 -80 10", "line 9: candela value 2 of horizontal angle 0: -80 is negative"},
      {9, "-100 80 10", "line 9: candela value 1 of horizontal angle 0: -100 is negative"},
      {9, "100 1e999 10", "line 9: candela value 2 of horizontal angle 0: '1e999' is out of the range of a double"},
      {7, "0 90 45", "line 7: vertical angle 3: 45 does not follow 90 in ascending order"},
      {7, "0 45 100", "line 7: vertical angles: 0 to 100; type C takes 0 or 90 to 90 or 180"},
      {8, "0 45", "line 8: horizontal angles: 0 to 45; type C takes"},
      {2, "[TE ST] t", "line 2: bad keyword '[TE ST]'"},
      {2, "TEST t", "line 2: expected a keyword line '[KEYWORD] text' or the TILT= line"},
      {2, "[MORE] t", "line 2: [MORE] continues no keyword"},
      {1, "IESNA:LM-63-2099", "line 1: unknown version line 'IESNA:LM-63-2099'"},
      {4, "[KEYWORD] no tilt", "line 5: expected a keyword line"},
      {4, "TILT=lamp.tlt", "line 4: TILT=lamp.tlt: tilt data in a separate file is not read"},
      {5, "1 1000 1 3 2 4 2 0 0 0", "line 5: photometric type: 4 is outside [1, 3]"},
      {5, "1 0 1 3 2 1 2 0 0 0", "line 5: lumens per lamp: 0 is neither positive nor -1 (absolute photometry)"},
      {5, "1 1000 0 3 2 1 2 0 0 0", "line 5: candela multiplier: 0 is not positive"},
      {5, "1 1000 x 3 2 1 2 0 0 0", "line 5: candela multiplier: expected a number, got 'x'"},
      {5, "1.5 1000 1 3 2 1 2 0 0 0", "line 5: number of lamps: expected an integer, got '1.5'"},
      {5, "1 1000 1 2000000000 2 1 2 0 0 0", "line 5: declares 2000000000 vertical angles; the limit is 3601"},
      {5, "1 1000 1 3 2 1 2 0.5 -0.5 0", "line 5: luminous dimensions: width 0.5, length -0.5, height 0 (m) match no luminous shape"},
      {6, "0 1 10", "line 6: ballast factor: 0 is not positive"},
      {6, "1 1 -10", "line 6: input watts: -10 is negative"},
  };
  for (const Case& c : cases) expect_refused(parse_ies(with_line(kBaseIes, c.line, c.replacement), "t.ies"), c.expected, c.expected);
  expect_refused(parse_ies("", "t.ies"), "t.ies: the file is empty", "empty");
  expect_refused(parse_ies(std::string("IESNA:LM-63-2002\n\0", 18), "t.ies"), "holds NUL bytes", "NUL");
  PhotometricLimits small;
  small.max_bytes = 10;
  expect_refused(parse_ies(kBaseIes, "t.ies", small), "bytes; the limit is 10", "size");
  // TILT=INCLUDE with a negative factor.
  std::string tilted = with_line(kBaseIes, 4, "TILT=INCLUDE\n1\n2\n0 90\n1 -0.5");
  expect_refused(parse_ies(tilted, "t.ies"), "line 8: tilt multiplying factor 2: -0.5 is negative", "tilt factor");
  // Type B: horizontal angles must be mirrored (0 to at most 90) or symmetric.
  std::string b = with_line(with_line(kBaseIes, 5, "1 1000 1 3 2 2 2 0 0 0"), 8, "10 90");
  expect_refused(parse_ies(b, "t.ies"), "line 8: horizontal angles: 10 to 90; type B takes", "type B range");
}

// ---- EULUMDAT -----------------------------------------------------------------------------------

TEST(LdtReader, ReadsEverySymmetry) {
  for (int isym = 0; isym <= 4; ++isym) {
    LdtSpec s;
    s.isym = isym;
    s.mc = 24;
    s.lamp_flux = 2500, s.conversion = 1.2, s.lorl = 80;
    s.cd_per_klm = [](double c, double g) { return 300 + c + g / 100; };
    const PhotometricData d = read_ldt(test::ldt_text(s));
    const std::vector<double> planes = test::ldt_stored_planes(s);
    EXPECT_EQ(d.horizontal_deg, planes) << isym;
    ASSERT_EQ(d.candela.size(), planes.size() * s.gamma.size()) << isym;
    for (std::size_t k = 0; k < planes.size(); ++k)
      for (std::size_t j = 0; j < s.gamma.size(); ++j)
        EXPECT_NEAR(d.candela[k * s.gamma.size() + j], (300 + planes[k] + s.gamma[j] / 100) * 1.2 * 2.5, 1e-9);
    EXPECT_EQ(d.declared_lamp_flux_lm, 2500);
    EXPECT_NEAR(*d.declared_output_lm, 2000, 1e-9);  // LORL × lamp flux
  }
}

// LORL a little above 100 %, as real files state it (100.1 %): read as stated, declared flux
// LORL × lamp flux = 1.001 × 2 500 lm, with a warning that names the value.
TEST(LdtReader, LorlRoundedAboveAHundredIsTakenAsStatedWithAWarning) {
  LdtSpec s;
  s.isym = 1, s.mc = 1, s.lamp_flux = 2500, s.lorl = 100.1;
  s.cd_per_klm = [](double, double g) { return 300 + g / 100; };
  const PhotometricData d = read_ldt(test::ldt_text(s));
  ASSERT_TRUE(d.declared_output_lm);
  EXPECT_NEAR(*d.declared_output_lm, 1.001 * 2500, 1e-9);
  ASSERT_EQ(d.warnings.size(), 1u);
  EXPECT_NE(d.warnings[0].find("LORL 100.1 % is above 100 %"), std::string::npos) << d.warnings[0];
}

TEST(LdtReader, AbsolutePhotometryDecimalCommaAndOpening) {
  LdtSpec s;
  s.isym = 1, s.mc = 1, s.lamps = -1, s.lamp_flux = 1800;
  s.gamma = {0, 90, 180};
  s.area_length_mm = 600, s.area_width_mm = 0;  // a disk of diameter 0.6 m
  s.cd_per_klm = [](double, double g) { return g <= 90 ? 500 - g : 0.0; };
  std::string text = test::ldt_text(s);
  text = with_line(text, 47, "500,0");  // the intensity at γ = 0 with a decimal comma
  const PhotometricData d = read_ldt(text);
  EXPECT_TRUE(d.absolute_photometry);
  EXPECT_FALSE(d.declared_lamp_flux_lm);
  EXPECT_EQ(d.declared_output_lm, 1800);
  EXPECT_DOUBLE_EQ(d.candela[0], 500 * 1.8);
  EXPECT_EQ(d.opening.shape, LuminousShape::kDisk);
  EXPECT_DOUBLE_EQ(d.opening.length_m, 0.6);
}

TEST(LdtReader, BrokenFilesNameTheLineAndTheField) {
  LdtSpec s;
  s.isym = 1, s.mc = 1;
  s.gamma = {0, 90, 180};
  s.cd_per_klm = [](double, double) { return 100.0; };
  const std::string base = test::ldt_text(s);  // C angle on line 43, γ on 44–46, intensities on 47–49
  ASSERT_NO_THROW(read_ldt(base));
  struct Case { int line; std::string replacement; std::string expected; };
  const std::vector<Case> cases = {
      {3, "5", "t.ldt: line 3: Isym: 5 is outside [0, 4]"},
      {49, "\x01", "line 49: the file ends before intensity at C0, gamma 180"},
      {49, "-1", "line 49: intensity at C0, gamma 180: -1 is negative"},
      {48, "nan", "line 48: intensity at C0, gamma 90: 'nan' is not a finite number"},
      {45, "200", "line 45: gamma angle 2: 200 is outside [0, 180]"},
      {46, "80", "line 46: gamma angle 3: 80 does not follow 90 in ascending order"},
      {0, "7", "line 50: more lines follow the 3 intensities that Isym 1, Mc and Ng declare"},
      {23, "150", "line 23: LORL: 150 is outside [0, 101]"},
      {24, "1 2", "line 24: conversion factor: expected one number on the line, got '1 2'"},
      {27, "0", "line 27: lamp set 1: number of lamps: 0 lamps"},
      {29, "-5", "line 29: lamp set 1: total luminous flux: -5 is not positive"},
      {6, "99999", "line 6: declares 99999 intensities per C-plane; the limit is 3601"},
  };
  for (const Case& c : cases) expect_refused(parse_ldt(with_line(base, c.line, c.replacement), "t.ldt"), c.expected, c.expected);
  // Isym 2 keeps C0 to C180, which a file of three planes (0, 120, 240) does not list.
  LdtSpec three = s;
  three.isym = 2, three.mc = 3;
  std::string text = test::ldt_text(three);
  expect_refused(parse_ldt(text, "t.ldt"), "C angles: Isym 2 keeps the planes C0 to C180", "isym 2");
}

// ---- no input crashes ---------------------------------------------------------------------------

TEST(PhotometricReaders, NoInputCrashes) {
  LdtSpec s;
  s.isym = 4, s.mc = 8;
  s.cd_per_klm = [](double c, double g) { return 100 + c - g / 2; };
  const std::string ldt = test::ldt_text(s);
  std::mt19937 rng(7);
  const std::string chars = "0123456789-+.,eE nan[]TILT=\n\r\t\x01";
  for (const std::string& base : {std::string(kBaseIes), ldt}) {
    for (std::size_t cut = 0; cut < base.size(); ++cut) {
      const std::string prefix = base.substr(0, cut);
      const PhotometricParse a = parse_ies(prefix, "f"), b = parse_ldt(prefix, "f");
      EXPECT_TRUE(a.ok() || a.error.rfind("f: ", 0) == 0);
      EXPECT_TRUE(b.ok() || b.error.rfind("f: ", 0) == 0);
    }
    for (int trial = 0; trial < 3000; ++trial) {
      std::string m = base;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits; ++e) m[rng() % m.size()] = chars[rng() % chars.size()];
      const PhotometricParse a = parse_ies(m, "f"), b = parse_ldt(m, "f");
      EXPECT_TRUE(a.ok() || a.error.rfind("f: ", 0) == 0) << a.error;
      EXPECT_TRUE(b.ok() || b.error.rfind("f: ", 0) == 0) << b.error;
      if (a.ok()) PhotometricDistribution check(*a.data);  // an accepted file always unfolds
      if (b.ok()) PhotometricDistribution check(*b.data);
    }
  }
}

// ---- the distribution ---------------------------------------------------------------------------

PhotometricDistribution distribution_of(const IesSpec& s) { return PhotometricDistribution(read_ies(test::ies_text(s))); }

TEST(PhotometricDistribution, ReturnsTheFileAtItsNodesForEveryType) {
  // An asymmetric table (no two nodes alike) over the full range of each type; at every node's
  // direction (the SPEC's formulas, written in the test) the interpolant returns the table.
  auto value = [](double h, double v) { return 1000 + 3 * h + 0.7 * v + 0.01 * h * v; };
  struct Case { int type; std::vector<double> vertical, horizontal; Vector3 (*direction)(double, double); };
  const std::vector<Case> cases = {
      {1, steps(0, 180, 15), steps(0, 360, 20), [](double h, double v) { return test::type_c_direction(h, v); }},
      {2, steps(-180, 180, 20), steps(-90, 90, 15), [](double h, double v) { return test::type_b_direction(h, v); }},
      {3, steps(-90, 90, 15), steps(-180, 180, 20), [](double h, double v) { return test::type_a_direction(h, v); }},
  };
  for (const Case& c : cases) {
    IesSpec s;
    s.type = c.type, s.vertical = c.vertical, s.horizontal = c.horizontal, s.candela = value;
    const PhotometricDistribution d = distribution_of(s);
    for (double h : c.horizontal)
      for (double v : c.vertical) {
        const Vector3 w = c.direction(h, v);
        // Poles and the seam (±180°) are one direction for several nodes; the table holds
        // different values there, so only nodes off them are compared.
        const bool pole = c.type == 1 ? (v == 0 || v == 180) : c.type == 2 ? std::abs(h) == 90 : std::abs(v) == 90;
        const bool seam = (c.type == 1 && h == 360) || (c.type != 1 && std::abs(c.type == 2 ? v : h) == 180);
        if (pole || seam) continue;
        EXPECT_NEAR(d.intensity(w), value(h, v), 1e-9 * value(h, v)) << c.type << " " << h << " " << v;
      }
  }
}

TEST(PhotometricDistribution, SymmetriesUnfoldToTheFullWeb) {
  // A distribution with every symmetry (I depends on |sin C|, |cos C| and the polar angle) written
  // as each symmetric file and as the full file: the two interpolants agree everywhere.
  auto sym = [](double c, double g) { return 100 + 40 * std::pow(std::cos(c * test::kDeg), 2) + g / 3; };
  IesSpec full;
  full.vertical = steps(0, 180, 10);
  full.horizontal = steps(0, 360, 15);
  full.candela = sym;
  const PhotometricDistribution reference = distribution_of(full);
  std::vector<std::pair<double, double>> ranges = {{0, 90}, {0, 180}, {90, 270}, {0, 345}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const auto& [first, last] : ranges) {
    IesSpec s = full;
    s.horizontal = steps(first, last, 15);
    const PhotometricDistribution d = distribution_of(s);
    for (int k = 0; k < 500; ++k) {
      const Vector3 w = normalize(Vector3{u(rng), u(rng), u(rng)});
      EXPECT_NEAR(d.intensity(w), reference.intensity(w), 1e-9 * reference.intensity(w)) << first << "-" << last;
    }
    EXPECT_NEAR(d.flux(), reference.flux(), 1e-12 * reference.flux()) << first << "-" << last;
  }
  // Types A and B mirrored about their horizontal and vertical zero planes.
  for (int type : {2, 3}) {
    IesSpec whole;
    whole.type = type;
    whole.vertical = type == 2 ? steps(-180, 180, 15) : steps(-90, 90, 10);
    whole.horizontal = type == 2 ? steps(-90, 90, 10) : steps(-180, 180, 15);
    whole.candela = [](double h, double v) { return 50 + std::abs(h) / 2 + std::abs(v) / 3; };
    IesSpec half = whole;
    half.vertical = type == 2 ? steps(0, 180, 15) : steps(0, 90, 10);
    half.horizontal = type == 2 ? steps(0, 90, 10) : steps(0, 180, 15);
    const PhotometricDistribution a = distribution_of(whole), b = distribution_of(half);
    for (int k = 0; k < 500; ++k) {
      const Vector3 w = normalize(Vector3{u(rng), u(rng), u(rng)});
      EXPECT_NEAR(a.intensity(w), b.intensity(w), 1e-9 * a.intensity(w)) << type;
    }
    EXPECT_NEAR(a.flux(), b.flux(), 1e-12 * a.flux()) << type;
  }
}

TEST(PhotometricDistribution, FluxIsExactForTheInterpolant) {
  // I = a + b γ is its own interpolant: Φ = 2π ∫_0^π (a + b γ) sin γ dγ = 2π (2a + π b).
  const double a = 300, b = -50;
  IesSpec c;
  c.vertical = {0, 7, 30, 45, 90, 100, 180};  // uneven steps
  c.horizontal = {0};
  c.candela = [&](double, double v) { return a + b * v * test::kDeg; };
  EXPECT_NEAR(distribution_of(c).flux(), 2 * kPiD * (2 * a + kPiD * b), 1e-12 * 2 * kPiD * 2 * a);
  // Type B, bilinear in (V, H): I = (p + q V)(a + b θ), θ = H + 90°, V in [−60°, 60°] (no light
  // beyond): Φ = ∫(p + qV) dV · ∫_0^π (a + bθ) sin θ dθ = 2p·(π/3) · (2a + πb).
  const double p = 2, q = 0.5;
  IesSpec fb;
  fb.type = 2;
  fb.vertical = steps(-60, 60, 20);
  fb.horizontal = steps(-90, 90, 30);
  fb.candela = [&](double h, double v) { return (p + q * v * test::kDeg) * (a + b * (h + 90) * test::kDeg); };
  EXPECT_NEAR(distribution_of(fb).flux(), 2 * p * (kPiD / 3) * (2 * a + kPiD * b), 1e-12 * 1e4);
  // cos^m lobes converge to 2π I0/(m+1) (the interpolant's error, O(Δγ²)).
  for (int m : {0, 1, 5}) {
    IesSpec lobe;
    lobe.vertical = steps(0, 90, 0.5);
    lobe.horizontal = {0};
    lobe.candela = [&](double, double v) { return 1000 * std::pow(std::cos(v * test::kDeg), m); };
    EXPECT_NEAR(distribution_of(lobe).flux(), 2 * kPiD * 1000 / (m + 1), 2e-4 * 2 * kPiD * 1000 / (m + 1)) << m;
  }
}

TEST(PhotometricDistribution, BandIsTheIntegralAlongAPlane) {
  // band(φ, θ1, θ2) against a fine Simpson rule of I(φ, θ) sin θ along the same half-plane.
  IesSpec s;
  s.vertical = steps(0, 180, 10);
  s.horizontal = steps(0, 360, 30);
  s.candela = [](double h, double v) { return 200 + 50 * std::sin(h * test::kDeg) + v; };
  const PhotometricDistribution d = distribution_of(s);
  for (double phi : {0.1, 1.0, 2.5, 4.0, 6.0})
    for (auto [t1, t2] : std::vector<std::pair<double, double>>{{0, kPiD}, {0.2, 1.3}, {2.0, 2.9}}) {
      const int n = 20000;
      double sum = 0;
      for (int k = 0; k <= n; ++k) {
        const double t = t1 + (t2 - t1) * k / n;
        sum += (k == 0 || k == n ? 1 : k % 2 ? 4 : 2) * d.intensity_at(phi, t) * std::sin(t);
      }
      sum *= (t2 - t1) / n / 3;
      EXPECT_NEAR(d.band(phi, t1, t2), sum, 1e-7 * sum) << phi << " " << t1 << " " << t2;
    }
}

}  // namespace
}  // namespace lambert
