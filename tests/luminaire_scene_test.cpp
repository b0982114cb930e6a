// Luminaires in scene JSON (SPEC §1 "luminaire"), through the decoder, the solve and the result: a
// luminaire given by a file, by inline IES or EULUMDAT text; the probe's lux under it against
// E = MF · I(γ) cos α / d² at the file's own nodes, whatever the spectrum; the result's "luminaires"
// reporting the file's declared lumens beside the exact integral of its interpolant; glare seeing
// the opening's luminance and solid angle; and every broken luminaire refused at its JSON pointer,
// with the file and line where the file is at fault.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "server/result_codec.h"
#include "server/scene_codec.h"
#include "solver/photometry/distribution.h"
#include "solver/radiosity.h"
#include "solver/report.h"
#include "solver/ugr_table.h"
#include "tests/photometric_writer.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::IesSpec;
using test::LdtSpec;
using test::steps;

struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "lambert_luminaire_XXXXXX").string();
    path = mkdtemp(tmpl.data());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// A rotationally symmetric downlight: I(γ) = 1000 cos γ (1 + γ/π) at 5° nodes, nothing above 90°.
double downlight(double gamma_deg) {
  const double g = gamma_deg * test::kDeg;
  return 1000 * std::cos(g) * (1 + g / kPi);
}
std::string downlight_ies() {
  IesSpec s;
  s.vertical = steps(0, 90, 5);
  s.horizontal = {0};
  s.candela = [](double, double v) { return downlight(v); };
  return test::ies_text(s);
}

// A 4 × 4 m floor at z = 0 facing up, the given lights and probes.
std::string scene(const json& lights, const json& probes = json::array(), const std::string& units = "m") {
  const double k = units == "cm" ? 100 : 1;
  json doc = {{"units", units},
              {"materials", {{"grey", {{"reflectance", 0}}}}},
              {"surfaces", json::array({{{"name", "floor"},
                                         {"material", "grey"},
                                         {"polygon", {{-2 * k, -2 * k, 0}, {2 * k, -2 * k, 0}, {2 * k, 2 * k, 0}, {-2 * k, 2 * k, 0}}}}})},
              {"lights", lights},
              {"probes", probes}};
  return doc.dump();
}

json luminaire_with(json photometry) {
  return {{"type", "luminaire"}, {"name", "D1"}, {"photometry", std::move(photometry)}, {"position", {0, 0, 2}},
          {"nadir", {0, 0, -1}}, {"c0", {1, 0, 0}}};
}

Scene decode_ok(const std::string& text, const FileAccess& files = {}) {
  DecodeResult r = decode_scene(text, files);
  if (!r.ok()) throw std::runtime_error(format_errors(r.errors));
  return std::move(*r.scene);
}

::testing::AssertionResult HasError(const std::string& text, const std::string& pointer, const std::string& fragment,
                                    const FileAccess& files = {}) {
  const DecodeResult r = decode_scene(text, files);
  if (r.scene) return ::testing::AssertionFailure() << "decoded without errors";
  for (const DecodeError& e : r.errors)
    if (e.pointer == pointer && e.message.find(fragment) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "no error at '" << pointer << "' containing '" << fragment << "'; got:\n"
                                       << format_errors(r.errors);
}

TEST(LuminaireScene, FileInlineIesAndInlineLdtDecodeAlike) {
  TempDir dir;
  std::ofstream(dir.path / "down.ies") << downlight_ies();
  LdtSpec l;
  l.isym = 1, l.mc = 1, l.gamma = steps(0, 90, 5), l.lamp_flux = 1000;
  l.cd_per_klm = [](double, double g) { return downlight(g); };
  FileAccess files;
  files.base_dir = dir.path;
  json lights = json::array({luminaire_with({{"file", "down.ies"}}), luminaire_with({{"ies", downlight_ies()}}),
                             luminaire_with({{"ldt", test::ldt_text(l)}})});
  for (std::size_t k = 0; k < 3; ++k) lights[k]["name"] = "D" + std::to_string(k);
  lights[1]["maintenance_factor"] = 0.8;
  lights[2]["luminous_flux_lm"] = 500;
  const Scene s = decode_ok(scene(lights, json::array(), "cm"), files);
  ASSERT_EQ(s.lights.size(), 3u);
  const auto& a = std::get<LuminaireLight>(s.lights[0]);
  const auto& b = std::get<LuminaireLight>(s.lights[1]);
  const auto& c = std::get<LuminaireLight>(s.lights[2]);
  EXPECT_EQ(a.source, "down.ies");
  EXPECT_EQ(b.source, "inline IES text");
  EXPECT_EQ(c.source, "inline EULUMDAT text");
  EXPECT_NEAR(a.position.z, 0.02, 1e-15);  // cm -> m
  // One candela of the file: 683 Σ w ȳ S = candela_scale (MF, or Φ_asked / Φ_file).
  EXPECT_NEAR(luminous_integral(a.intensity_W_sr_nm, s.grid), 1.0, 1e-12);
  EXPECT_NEAR(luminous_integral(b.intensity_W_sr_nm, s.grid), 0.8, 1e-12);
  const double flux = a.photometry->distribution.flux();
  EXPECT_NEAR(c.photometry->distribution.flux(), flux, 1e-9 * flux);  // the same table in both formats
  EXPECT_NEAR(luminous_integral(c.intensity_W_sr_nm, s.grid), 500 / flux, 1e-12);
}

TEST(LuminaireScene, ProbeLuxThroughTheSolveIsTheClosedForm) {
  // Probes at the file's nodes: straight under (γ = 0) and at γ = 30° (d = 2 / cos 30°), facing up:
  // E = MF · I(γ) cos γ / d², whatever the spectral shape (photometry sets the scale).
  const double t30 = std::tan(30 * test::kDeg);
  json light = luminaire_with({{"ies", downlight_ies()}});
  light["maintenance_factor"] = 0.8;
  light["spectrum"] = {{"blackbody_K", 3000}};
  const json probes = json::array({{{"name", "under"}, {"position", {0, 0, 0}}, {"normal", {0, 0, 1}}},
                                   {{"name", "at30"}, {"position", {2 * t30, 0, 0}}, {"normal", {0, 0, 1}}}});
  const Scene s = decode_ok(scene(json::array({light}), probes));
  const Solution sol = solve(s);
  const Report report = make_report(s, sol);
  const double d30 = 2 / std::cos(30 * test::kDeg);
  EXPECT_NEAR(report.probes[0].illuminance_lx[0], 0.8 * downlight(0) / 4, 1e-9 * downlight(0));
  EXPECT_NEAR(report.probes[1].illuminance_lx[0], 0.8 * downlight(30) * std::cos(30 * test::kDeg) / (d30 * d30),
              1e-9 * downlight(0));
  // The result: declared lumens (absolute photometry: none), the interpolant's exact integral, the
  // emitted flux after the maintenance factor.
  const json result = json::parse(encode_result(s, sol, report));
  ASSERT_TRUE(result.contains("luminaires"));
  const json& l = result["luminaires"][0];
  const double integral = std::get<LuminaireLight>(s.lights[0]).photometry->distribution.flux();
  EXPECT_EQ(l["light"], "/lights/0");
  EXPECT_EQ(l["name"], "D1");
  EXPECT_TRUE(l["declared_lamp_flux_lm"].is_null());
  EXPECT_NEAR(l["integral_lm"].get<double>(), integral, 1e-9 * integral);
  EXPECT_NEAR(l["emitted_lm"].get<double>(), 0.8 * integral, 1e-9 * integral);
  EXPECT_EQ(l["photometry_type"], "C");
}

// A Lambertian 0.6 × 0.3 m opening, I = 2000 cos γ cd (LM-63 length 0.6 along C0, width 0.3),
// tabulated every `step_deg` degrees of γ.
std::string lambertian_opening_ies(double step_deg) {
  IesSpec spec;
  spec.vertical = steps(0, 90, step_deg);
  spec.horizontal = {0};
  spec.candela = [](double, double v) { return 2000 * std::cos(v * test::kDeg); };
  spec.width = 0.3, spec.length = 0.6;
  return test::ies_text(spec);
}

TEST(LuminaireScene, GlareSeesTheOpeningThroughTheSolve) {
  // A Lambertian 0.6 × 0.3 m opening (I = 2000 cos γ, LM-63 length 0.6 along C0, width 0.3) at
  // z = 2 seen by an observer at (−2, 0, 1.2) looking along +x: UGR's source is the opening with
  // L = I0 / A = 2000 / 0.18 cd/m² and the solid angle of the rectangle 1.7 ≤ x ≤ 2.3, |y| ≤ 0.15 in
  // the plane h = 0.8 above the eye (the corner formula atan(x y / (h √(x² + y² + h²))) by
  // superposition).
  json doc = json::parse(scene(json::array({luminaire_with({{"ies", lambertian_opening_ies(0.25)}})})));
  doc["glare"] = json::array({{{"name", "desk"}, {"position", {-2, 0, 1.2}}, {"view", {1, 0, 0}}, {"up", {0, 0, 1}}}});
  const Scene s = decode_ok(doc.dump());
  const Solution sol = solve(s);
  const json result = json::parse(encode_result(s, sol, make_report(s, sol)));
  ASSERT_EQ(result["glare"].size(), 1u);
  const json& sources = result["glare"][0]["sources"];
  ASSERT_EQ(sources.size(), 1u);
  EXPECT_EQ(sources[0]["source"], "/lights/0");
  EXPECT_NEAR(sources[0]["luminance_cd_m2"].get<double>(), 2000 / 0.18, 1e-4 * 2000 / 0.18);
  auto corner = [](double x, double y) { return std::atan(x * y / (0.8 * std::sqrt(x * x + y * y + 0.64))); };
  const double omega = corner(2.3, 0.15) - corner(1.7, 0.15) - corner(2.3, -0.15) + corner(1.7, -0.15);
  EXPECT_NEAR(sources[0]["solid_angle_sr"].get<double>(), omega, 1e-9 * omega);
}

TEST(LuminaireScene, UgrTablesInTheResult) {
  // output.ugr_tables: each luminaire's CIE 190 table for its rescaled flux, without the maintenance
  // factor. Scaling the flux by k scales Σ L² ω by k² and L_b by k, so every cell moves by
  // 8 log10 k from the file's own table (k = 4 π 2000 lm over the file's integral, about 4); a point
  // luminaire has none (null).
  const std::string text = lambertian_opening_ies(2.5);
  json a = luminaire_with({{"ies", text}});
  a["luminous_flux_lm"] = 4 * kPi * 2000;  // the file integrates to π · 2000 lm
  a["maintenance_factor"] = 0.8;
  json b = luminaire_with({{"ies", downlight_ies()}});
  b["name"] = "P";
  json doc = json::parse(scene(json::array({a, b})));
  doc["output"] = {{"ugr_tables", true}};
  const Scene s = decode_ok(doc.dump());
  const Solution sol = solve(s);
  const json result = json::parse(encode_result(s, sol, make_report(s, sol)));
  const json& table = result["luminaires"][0]["ugr_table"];
  const auto& photometry = *std::get<LuminaireLight>(s.lights[0]).photometry;
  const auto own = standard_ugr_table(photometry.file, photometry.distribution, 1);
  ASSERT_TRUE(own);
  const double shift = 8 * std::log10(4 * kPi * 2000 / photometry.distribution.flux());
  EXPECT_EQ(table["method"], "CIE 190:2010");
  ASSERT_EQ(table["crosswise"].size(), kUgrRooms);
  EXPECT_NEAR(table["luminous_flux_lm"].get<double>(), 4 * kPi * 2000, 1e-3);
  for (std::size_t room = 0; room < kUgrRooms; ++room)
    for (std::size_t k = 0; k < kUgrReflectances; ++k) {
      EXPECT_NEAR(table["crosswise"][room][k].get<double>(), *own->crosswise[room][k] + shift, 1e-9);
      EXPECT_NEAR(table["endwise"][room][k].get<double>(), *own->endwise[room][k] + shift, 1e-9);
    }
  EXPECT_EQ(table["rooms"][5], json::array({2, 12}));
  EXPECT_TRUE(result["luminaires"][1]["ugr_table"].is_null());
  doc["output"] = json::object();
  const Scene plain = decode_ok(doc.dump());
  const Solution plain_sol = solve(plain);
  EXPECT_FALSE(json::parse(encode_result(plain, plain_sol, make_report(plain, plain_sol)))["luminaires"][0].contains("ugr_table"));
}

TEST(LuminaireScene, TheBundledFilesReportTheirDeclaredLumens) {
  // The EULUMDAT file of scenes/luminaires/ declares 321 lm (absolute photometry); its interpolated
  // table integrates to 321.25 lm (README there). The Cooper file declares 3500 lm of lamps.
  FileAccess files;
  files.base_dir = fs::path(LAMBERT_SOURCE_DIR) / "scenes";
  json a = luminaire_with({{"file", "luminaires/bega-50975-downlight.ldt"}});
  json b = luminaire_with({{"file", "luminaires/cooper-shaper-210d.ies"}});
  b["name"] = "S1";
  const Scene s = decode_ok(scene(json::array({a, b})), files);
  const auto& ldt = std::get<LuminaireLight>(s.lights[0]).photometry;
  EXPECT_EQ(ldt->file.declared_output_lm, 321);
  EXPECT_NEAR(ldt->distribution.flux(), 321.25, 0.01);
  const auto& cooper = std::get<LuminaireLight>(s.lights[1]).photometry;
  EXPECT_EQ(cooper->file.declared_lamp_flux_lm, 3500);
  EXPECT_EQ(cooper->file.opening.shape, LuminousShape::kVerticalCylinder);
}

TEST(LuminaireScene, BrokenLuminairesAreRefusedWhereTheyAre) {
  std::string broken = downlight_ies();
  broken.replace(broken.find("TILT=NONE"), 9, "TILT=lamp.tlt");
  EXPECT_TRUE(HasError(scene(json::array({luminaire_with({{"ies", broken}})})), "/lights/0/photometry/ies",
                       "inline IES text: line 4: TILT=lamp.tlt: tilt data in a separate file is not read"));
  EXPECT_TRUE(HasError(scene(json::array({luminaire_with({{"ldt", "nonsense"}})})), "/lights/0/photometry/ldt",
                       "inline EULUMDAT text: line 2: the file ends before Ityp"));
  EXPECT_TRUE(HasError(scene(json::array({luminaire_with({{"file", "a.txt"}})})), "/lights/0/photometry/file",
                       "expected .ies (IES LM-63) or .ldt (EULUMDAT)"));
  EXPECT_TRUE(HasError(scene(json::array({luminaire_with({{"ies", "x"}, {"ldt", "y"}})})), "/lights/0/photometry",
                       "give exactly one of"));
  json tilted = luminaire_with({{"ies", downlight_ies()}});
  tilted["c0"] = {1, 0, 0.1};
  EXPECT_TRUE(HasError(scene(json::array({tilted})), "/lights/0/c0", "must be perpendicular to nadir"));
  for (double mf : {0.0, 1.5}) {
    json l = luminaire_with({{"ies", downlight_ies()}});
    l["maintenance_factor"] = mf;
    EXPECT_TRUE(HasError(scene(json::array({l})), "/lights/0/maintenance_factor", "outside")) << mf;
  }
  json negative = luminaire_with({{"ies", downlight_ies()}});
  negative["luminous_flux_lm"] = -5;
  EXPECT_TRUE(HasError(scene(json::array({negative})), "/lights/0/luminous_flux_lm", "outside"));
  json twice = json::array({luminaire_with({{"ies", downlight_ies()}}), luminaire_with({{"ies", downlight_ies()}})});
  EXPECT_TRUE(HasError(scene(twice), "/lights/1/name", "duplicate luminaire name 'D1'"));
  json extra = luminaire_with({{"ies", downlight_ies()}});
  extra["axis"] = {0, 0, -1};
  EXPECT_TRUE(HasError(scene(json::array({extra})), "/lights/0/axis", "unknown"));
  // TILT=INCLUDE: the factor at tilt_deg, which must lie within the file's tilt angles.
  std::string with_tilt = downlight_ies();
  with_tilt.replace(with_tilt.find("TILT=NONE"), 9, "TILT=INCLUDE\r\n1\r\n2\r\n0 30\r\n1 0.5");
  json t = luminaire_with({{"ies", with_tilt}});
  t["tilt_deg"] = 45;
  EXPECT_TRUE(HasError(scene(json::array({t})), "/lights/0/tilt_deg", "45 is outside the file's tilt angles [0, 30]"));
  t["tilt_deg"] = 15;
  EXPECT_NEAR(std::get<LuminaireLight>(decode_ok(scene(json::array({t}))).lights[0]).tilt_factor, 0.75, 1e-15);
}

TEST(LuminaireScene, FilesGoThroughTheSandbox) {
  TempDir dir;
  fs::create_directories(dir.path / "root");
  std::ofstream(dir.path / "outside.ies") << downlight_ies();
  std::ofstream(dir.path / "root" / "in.ies") << downlight_ies();
  fs::create_symlink(dir.path / "outside.ies", dir.path / "root" / "link.ies");
  FileAccess deny{FileAccess::Policy::Deny, {}, {}};
  FileAccess root{FileAccess::Policy::UnderRoot, {}, dir.path / "root"};
  auto with_file = [](const std::string& f) { return scene(json::array({luminaire_with({{"file", f}})})); };
  EXPECT_TRUE(HasError(with_file("in.ies"), "/lights/0/photometry/file",
                       "photometric files are not allowed here (start the server with --mesh-root)", deny));
  EXPECT_NO_THROW(decode_ok(with_file("in.ies"), root));
  EXPECT_TRUE(HasError(with_file("../outside.ies"), "/lights/0/photometry/file", "must not contain '..'", root));
  EXPECT_TRUE(HasError(with_file((dir.path / "outside.ies").string()), "/lights/0/photometry/file",
                       "must be relative to the mesh root", root));
  EXPECT_TRUE(HasError(with_file("link.ies"), "/lights/0/photometry/file", "outside the mesh root", root));
  EXPECT_TRUE(HasError(with_file("missing.ies"), "/lights/0/photometry/file", "not found under the mesh root", root));
  // A broken file names itself as the scene does, never the server's path.
  std::ofstream(dir.path / "root" / "bad.ies") << "IESNA:LM-63-2002\n[TEST] t\nTILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 10\n0 90\n0\n100 -1\n";
  EXPECT_TRUE(HasError(with_file("bad.ies"), "/lights/0/photometry/file",
                       "bad.ies: line 8: candela value 2 of horizontal angle 0: -1 is negative", root));
}

}  // namespace
}  // namespace lambert
