// Scene decoder tests: valid scenes decode into SI units with photometric totals applied exactly
// (each expected value next to its closed form), and every kind of invalid input is rejected with
// the JSON pointer of the offending value.
#include "server/scene_codec.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace lambert {
namespace {

namespace fs = std::filesystem;

constexpr const char* kMaterials = R"("materials": {"white": {"reflectance": 0.5}})";
// A 1 × 1 floor facing +y (counter-clockwise seen from above).
constexpr const char* kFloor =
    R"({"name": "floor", "material": "white", "polygon": [[0,0,0], [0,0,1], [1,0,1], [1,0,0]]})";

// A scene with the given surfaces (JSON array body) and extra top-level members.
std::string scene_with_surfaces(const std::string& surfaces, const std::string& extra = "") {
  return std::string("{") + kMaterials + R"(, "surfaces": [)" + surfaces + "]" +
         (extra.empty() ? "" : ", " + extra) + "}";
}
// The minimal floor scene plus extra top-level members.
std::string scene_with(const std::string& extra) { return scene_with_surfaces(kFloor, extra); }

std::optional<Scene> decode_ok(const std::string& text, const FileAccess& files = {}) {
  DecodeResult r = decode_scene(text, files);
  if (!r.ok()) ADD_FAILURE() << "unexpected errors:\n" << format_errors(r.errors);
  EXPECT_EQ(r.scene.has_value(), r.ok());
  return std::move(r.scene);
}

// Succeeds iff decoding fails and some error sits exactly at `pointer` with `fragment` in its text.
::testing::AssertionResult HasError(const std::string& text, const std::string& pointer,
                                    const std::string& fragment, const FileAccess& files = {}) {
  const DecodeResult r = decode_scene(text, files);
  if (r.scene) return ::testing::AssertionFailure() << "decoded without errors";
  for (const DecodeError& e : r.errors)
    if (e.pointer == pointer && e.message.find(fragment) != std::string::npos)
      return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "no error at '" << pointer << "' containing '" << fragment
                                       << "'; got:\n" << format_errors(r.errors);
}

const PointLight& point_light(const Scene& s, std::size_t i) { return std::get<PointLight>(s.lights.at(i)); }

// A temporary directory removed at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "lambert_codec_XXXXXX").string();
    path = mkdtemp(tmpl.data());
  }
  ~TempDir() { std::error_code ec; fs::remove_all(path, ec); }
};

void write_triangle_obj(const fs::path& path) {
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
}

// ---- valid scenes ---------------------------------------------------------------------------

TEST(SceneCodec, MinimalSceneDecodesInMetres) {
  auto s = decode_ok(R"({
    "name": "room", "units": "cm",
    "materials": { "white": { "reflectance": 0.5 },
                   "red": { "reflectance": { "nm": [400, 700], "values": [0.1, 0.7] } } },
    "surfaces": [ { "name": "floor", "material": "white",
                    "polygon": [[0,0,0], [0,0,100], [100,0,100], [100,0,0]] } ] })");
  ASSERT_TRUE(s);
  EXPECT_EQ(s->name, "room");
  EXPECT_DOUBLE_EQ(s->unit_m, 0.01);
  // Default grid: 380..780 nm in 5 nm steps = (780 - 380)/5 + 1 = 81 samples.
  ASSERT_EQ(s->grid.size(), 81u);
  EXPECT_DOUBLE_EQ(s->grid.nm.front(), 380);
  EXPECT_DOUBLE_EQ(s->grid.nm.back(), 780);

  ASSERT_EQ(s->materials.size(), 2u);
  const Material* white = nullptr;
  const Material* red = nullptr;
  for (const Material& m : s->materials) (m.name == "white" ? white : red) = &m;
  ASSERT_TRUE(white && red && red->name == "red");
  ASSERT_EQ(white->reflectance.size(), 81u);
  for (double v : white->reflectance) EXPECT_DOUBLE_EQ(v, 0.5);
  // Table: held at its ends (reflectance), linear between: 550 nm is halfway, 0.4.
  EXPECT_NEAR(red->reflectance[0], 0.1, 1e-12);    // 380 nm
  EXPECT_NEAR(red->reflectance[34], 0.4, 1e-12);   // 550 nm
  EXPECT_NEAR(red->reflectance[80], 0.7, 1e-12);   // 780 nm

  ASSERT_EQ(s->surfaces.size(), 1u);
  const Surface& floor = s->surfaces[0];
  EXPECT_EQ(floor.name, "floor");
  EXPECT_EQ(floor.pointer, "/surfaces/0");
  EXPECT_EQ(s->materials[floor.material].name, "white");
  ASSERT_EQ(floor.mesh.triangles.size(), 2u);
  double area = 0;
  for (std::size_t t = 0; t < floor.mesh.triangles.size(); ++t) {
    area += floor.mesh.triangle(t).area();
    const Vector3 n = floor.mesh.triangle(t).normal();
    EXPECT_NEAR(n.y, 1.0, 1e-12) << "triangulation must keep the polygon's orientation";
  }
  EXPECT_NEAR(area, 1.0, 1e-12);  // 100 cm × 100 cm = 1 m²
  for (const Point3& v : floor.mesh.vertices) EXPECT_LE(std::max({v.x, v.y, v.z}), 1.0 + 1e-15);
  EXPECT_FALSE(floor.emission);
  EXPECT_TRUE(s->lights.empty());
  EXPECT_TRUE(s->warnings.empty());
}

TEST(SceneCodec, DefaultsAndOptions) {
  auto s = decode_ok(scene_with_surfaces(std::string(kFloor) + R"(, {"material": "white",
      "polygon": [[0,1,0], [1,1,0], [1,1,1]]})",
      R"("lambert": 1, "description": "test", "expected": {"anything": [1, 2]},
         "spectrum": {"mode": "spectral", "wavelengths_nm": [450, 550, 650]},
         "probes": [{"position": [0, 1, 0], "normal": [0, 5, 0]}],
         "meshing": {"max_patch_area": 0.25, "adaptive": true, "refine_direct": false},
         "solver": {"tolerance": 1e-3, "max_iterations": 1e3, "exact_visibility": true},
         "output": {"spectral": false})"));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->surfaces[1].name, "surface1");
  ASSERT_EQ(s->grid.size(), 3u);
  EXPECT_EQ(s->grid.nm[1], 550);
  ASSERT_EQ(s->probes.size(), 1u);
  EXPECT_EQ(s->probes[0].name, "probe0");
  EXPECT_FALSE(s->probes[0].is_grid);
  EXPECT_DOUBLE_EQ(s->probes[0].normal.y, 1.0);  // normalised
  EXPECT_DOUBLE_EQ(*s->meshing.max_patch_area_m2, 0.25);
  EXPECT_TRUE(s->meshing.adaptive);
  EXPECT_FALSE(s->meshing.refine_direct);
  EXPECT_DOUBLE_EQ(s->solver.tolerance, 1e-3);
  EXPECT_EQ(s->solver.max_iterations, 1000);  // 1e3 is a whole number
  EXPECT_TRUE(s->solver.exact_visibility);
  EXPECT_FALSE(s->output.spectral);
}

TEST(SceneCodec, ProbeGridPointsAreCellCentresInMetres) {
  auto s = decode_ok(scene_with(R"("units": "mm", "probes": [{"name": "desk", "normal": [0, 1, 0],
      "grid": {"origin": [0, 0, 0], "u": [2, 0, 0], "v": [0, 0, 4], "nu": 2, "nv": 2}}])"));
  ASSERT_TRUE(s);
  const Probe& p = s->probes.at(0);
  EXPECT_TRUE(p.is_grid);
  EXPECT_EQ(p.nu, 2);
  EXPECT_EQ(p.nv, 2);
  // origin + (a + 1/2)/nu u + (b + 1/2)/nv v, a fastest, in mm -> m.
  const std::vector<Point3> expected = {{0.5e-3, 0, 1e-3}, {1.5e-3, 0, 1e-3}, {0.5e-3, 0, 3e-3},
                                        {1.5e-3, 0, 3e-3}};
  ASSERT_EQ(p.points.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(p.points[k].x, expected[k].x, 1e-15);
    EXPECT_NEAR(p.points[k].z, expected[k].z, 1e-15);
  }
}

TEST(SceneCodec, MeshTransformMirrorsRotatesTranslatesAndKeepsFrontSide) {
  // One triangle facing +z. Mirror in x (keeps the front at +z once the winding is reversed),
  // rotate 90° about x (+z -> -y), translate by 5 along z; all in cm.
  auto s = decode_ok(scene_with_surfaces(R"({"material": "white",
      "mesh": {"vertices": [[0,0,0], [1,0,0], [0,1,0]], "triangles": [[0,1,2]]},
      "transform": {"scale": [-1, 1, 1], "rotate_deg": [90, 0, 0], "translate": [0, 0, 5]}})",
      R"("units": "cm")"));
  ASSERT_TRUE(s);
  const TriangleMesh& m = s->surfaces[0].mesh;
  ASSERT_EQ(m.vertices.size(), 3u);
  // p' = Rx(90°)(s ⊙ p) + t: (1,0,0) -> (-1,0,0) -> (-1,0,5); (0,1,0) -> (0,0,1) -> (0,0,6).
  const std::vector<Point3> expected = {{0, 0, 0.05}, {-0.01, 0, 0.05}, {0, 0, 0.06}};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(m.vertices[k].x, expected[k].x, 1e-15);
    EXPECT_NEAR(m.vertices[k].y, expected[k].y, 1e-15);
    EXPECT_NEAR(m.vertices[k].z, expected[k].z, 1e-15);
  }
  const Vector3 n = m.triangle(0).normal();
  EXPECT_NEAR(n.y, -1.0, 1e-12);
}

TEST(SceneCodec, InconsistentOrientationIsAWarning) {
  // Both triangles run along the shared edge 1 -> 2 in the same direction.
  auto s = decode_ok(scene_with_surfaces(R"({"material": "white",
      "mesh": {"vertices": [[0,0,0], [1,0,0], [0,1,0], [1,1,0]], "triangles": [[0,1,2], [1,2,3]]}})"));
  ASSERT_TRUE(s);
  ASSERT_EQ(s->warnings.size(), 1u);
  EXPECT_EQ(s->warnings[0].rfind("/surfaces/0/mesh: ", 0), 0u) << s->warnings[0];
  EXPECT_NE(s->warnings[0].find("oriented"), std::string::npos);
}

TEST(SceneCodec, NestingInsideStringsIsNotCounted) {
  const std::string name(100000, '[');
  EXPECT_TRUE(decode_ok(scene_with(R"("name": ")" + name + "\"")));
}

// ---- photometric scaling ------------------------------------------------------------------

TEST(SceneCodec, PointLightLuminousIntensity) {
  auto s = decode_ok(scene_with(R"("units": "cm", "lights": [{"type": "point", "position": [50, 200, 50],
      "intensity": {"cie": "E"}, "luminous_intensity_cd": 100}])"));
  ASSERT_TRUE(s);
  const PointLight& l = point_light(*s, 0);
  EXPECT_EQ(l.kind, PointLight::Kind::Point);
  EXPECT_TRUE(l.inverse_square);
  EXPECT_NEAR(l.position.y, 2.0, 1e-15);
  EXPECT_NEAR(luminous_integral(l.intensity_W_sr_nm, s->grid), 100.0, 1e-9);
  EXPECT_EQ(s->light_pointers.at(0), "/lights/0");
}

TEST(SceneCodec, IsotropicPointFlux) {
  auto s = decode_ok(scene_with(R"("lights": [{"type": "point", "position": [0, 2, 0],
      "intensity": {"blackbody_K": 2856}, "luminous_flux_lm": 1000}])"));
  ASSERT_TRUE(s);
  // Φ = 4π I.
  EXPECT_NEAR(luminous_integral(point_light(*s, 0).intensity_W_sr_nm, s->grid), 1000 / (4 * kPi), 1e-9);
}

TEST(SceneCodec, LobedPointLightFlux) {
  auto s = decode_ok(scene_with(R"("lights": [
      {"type": "spot", "position": [0,2,0], "axis": [0,-1,0], "intensity": 1, "exponent": 20,
       "cutoff_deg": 30, "luminous_flux_lm": 1000},
      {"type": "spot", "position": [0,2,0], "axis": [0,-1,0], "intensity": 1, "cutoff_deg": 120,
       "luminous_flux_lm": 1000},
      {"type": "spot", "position": [0,2,0], "axis": [0,-3,0], "intensity": 1, "exponent": 2,
       "cutoff_deg": 150, "radiant_flux_W": 10},
      {"type": "goniometric", "position": [0,2,0], "axis": [0,-1,0], "intensity": 1, "exponent": 4,
       "luminous_flux_lm": 1000},
      {"type": "warn", "position": [0,2,0], "axis": [0,-1,0], "intensity": {"cie": "D65"},
       "luminous_flux_lm": 1000, "attenuation": {"c1": 1, "c3": 0.5}}])"));
  ASSERT_TRUE(s);
  const double c30 = std::cos(30 * kPi / 180);
  // spot, m = 20: Ω = 2π (1 − cos^21 30°) / 21.
  EXPECT_NEAR(luminous_integral(point_light(*s, 0).intensity_W_sr_nm, s->grid),
              1000 / (2 * kPi * (1 - std::pow(c30, 21)) / 21), 1e-9);
  EXPECT_NEAR(point_light(*s, 0).cutoff_rad, kPi / 6, 1e-15);
  // spot, m = 0 (uniform cone): Ω = 2π (1 − cos 120°) = 3π.
  EXPECT_NEAR(luminous_integral(point_light(*s, 1).intensity_W_sr_nm, s->grid), 1000 / (3 * kPi), 1e-9);
  // spot, m = 2, cutoff beyond 90°: ψc = 90°, Ω = 2π/3; radiometric: Σ w I = Φ / Ω.
  EXPECT_NEAR(integrate(point_light(*s, 2).intensity_W_sr_nm, s->grid), 10 / (2 * kPi / 3), 1e-12);
  EXPECT_NEAR(point_light(*s, 2).axis.y, -1.0, 1e-15);
  // goniometric, m = 4: Ω = 2π/5.
  EXPECT_NEAR(luminous_integral(point_light(*s, 3).intensity_W_sr_nm, s->grid), 1000 / (2 * kPi / 5), 1e-9);
  EXPECT_DOUBLE_EQ(point_light(*s, 3).exponent, 4);
  // Warn (m = 1): Ω = π.
  const PointLight& warn = point_light(*s, 4);
  EXPECT_EQ(warn.kind, PointLight::Kind::Warn);
  EXPECT_DOUBLE_EQ(warn.exponent, 1);
  EXPECT_NEAR(luminous_integral(warn.intensity_W_sr_nm, s->grid), 1000 / kPi, 1e-9);
  EXPECT_FALSE(warn.inverse_square);
  EXPECT_DOUBLE_EQ(warn.attenuation.c1, 1);
  EXPECT_DOUBLE_EQ(warn.attenuation.c2, 0);
  EXPECT_DOUBLE_EQ(warn.attenuation.c3, 0.5);
}

TEST(SceneCodec, SurfaceLuminanceLambertAndPhong) {
  const std::string lamp = R"({"name": "L", "material": "white", "polygon": [[0,0,0], [0,0,1], [1,0,1], [1,0,0]],
      "emission": {"exitance": {"cie": "D65"}, "luminance_cd_m2": 50}})";
  const std::string phong = R"({"name": "P", "material": "white", "polygon": [[0,1,0], [0,1,1], [1,1,1], [1,1,0]],
      "emission": {"radiance": {"cie": "A"}, "luminance_cd_m2": 50, "lobe": {"phong": 8}}})";
  const std::string absolute = R"({"name": "R", "material": "white", "polygon": [[0,2,0], [0,2,1], [1,2,1], [1,2,0]],
      "emission": {"radiance": 2, "lobe": "lambert"}})";
  auto s = decode_ok(scene_with_surfaces(lamp + "," + phong + "," + absolute));
  ASSERT_TRUE(s);
  // Lambert: R = π L.
  const Emission& e0 = *s->surfaces[0].emission;
  EXPECT_DOUBLE_EQ(e0.lobe_exponent, 1);
  EXPECT_NEAR(luminous_integral(e0.exitance_W_m2_nm, s->grid), kPi * 50, 1e-9);
  // Phong n = 8: R = 2π L / (n + 1).
  const Emission& e1 = *s->surfaces[1].emission;
  EXPECT_DOUBLE_EQ(e1.lobe_exponent, 8);
  EXPECT_NEAR(luminous_integral(e1.exitance_W_m2_nm, s->grid), 2 * kPi / 9 * 50, 1e-9);
  // Absolute radiance 2 W m^-2 sr^-1 nm^-1, Lambert: R = 2π.
  for (double v : s->surfaces[2].emission->exitance_W_m2_nm) EXPECT_NEAR(v, 2 * kPi, 1e-12);
}

TEST(SceneCodec, SurfaceFluxAndIntensityOnTwoSquareMetres) {
  const std::string flux = R"({"name": "F", "material": "white", "polygon": [[0,0,0], [0,0,1], [2,0,1], [2,0,0]],
      "emission": {"exitance": {"cie": "E"}, "luminous_flux_lm": 1000}})";
  const std::string cd = R"({"name": "I", "material": "white", "polygon": [[0,1,0], [0,1,1], [2,1,1], [2,1,0]],
      "emission": {"exitance": 1, "luminous_intensity_cd": 100}})";
  const std::string w = R"({"name": "W", "material": "white", "polygon": [[0,2,0], [0,2,1], [2,2,1], [2,2,0]],
      "emission": {"exitance": 1, "radiant_exitance_W_m2": 40}})";
  auto s = decode_ok(scene_with_surfaces(flux + "," + cd + "," + w));
  ASSERT_TRUE(s);
  // Φ = R A: R = 1000 / 2.
  EXPECT_NEAR(luminous_integral(s->surfaces[0].emission->exitance_W_m2_nm, s->grid), 500, 1e-9);
  // I_0 = R A / π (Lambert): R = π 100 / 2.
  EXPECT_NEAR(luminous_integral(s->surfaces[1].emission->exitance_W_m2_nm, s->grid), kPi * 50, 1e-9);
  // Radiometric exitance: Σ w R = 40.
  EXPECT_NEAR(integrate(s->surfaces[2].emission->exitance_W_m2_nm, s->grid), 40, 1e-12);
}

TEST(SceneCodec, DirectionalAndAmbientIrradiance) {
  auto s = decode_ok(scene_with(R"("lights": [
      {"type": "directional", "direction": [0, -2, 0], "irradiance": {"cie": "D65"}, "illuminance_lx": 10000},
      {"type": "ambient", "irradiance": 0.5, "irradiance_W_m2": 3},
      {"type": "ambient", "irradiance": 0.01}])"));
  ASSERT_TRUE(s);
  const auto& d = std::get<DirectionalLight>(s->lights[0]);
  EXPECT_DOUBLE_EQ(d.direction.y, -1.0);
  EXPECT_NEAR(luminous_integral(d.irradiance_W_m2_nm, s->grid), 10000, 1e-8);
  EXPECT_NEAR(integrate(std::get<AmbientLight>(s->lights[1]).irradiance_W_m2_nm, s->grid), 3, 1e-12);
  for (double v : std::get<AmbientLight>(s->lights[2]).irradiance_W_m2_nm) EXPECT_DOUBLE_EQ(v, 0.01);
  EXPECT_EQ(s->light_pointers.size(), 3u);
}

// ---- one test per kind of error ---------------------------------------------------------

TEST(SceneCodecErrors, UnknownTopLevelKey) {
  EXPECT_TRUE(HasError(scene_with(R"("surface": [])"), "/surface",
                       "unknown key 'surface'; did you mean 'surfaces'?"));
}

TEST(SceneCodecErrors, UnknownNestedKey) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"materal": "white", "polygon": [[0,0,0], [0,0,1], [1,0,1]]})"),
                       "/surfaces/0/materal", "did you mean 'material'?"));
}

TEST(SceneCodecErrors, PointerEscapesTildeAndSlash) {
  EXPECT_TRUE(HasError(scene_with(R"("a/b~c": 1)"), "/a~1b~0c", "unknown key 'a/b~c'"));
}

TEST(SceneCodecErrors, DuplicateKey) {
  EXPECT_TRUE(HasError(R"({"materials": {"white": {"reflectance": 0.5, "reflectance": 0.6}},
                           "surfaces": [)" + std::string(kFloor) + "]}",
                       "/materials/white/reflectance", "duplicate key"));
}

TEST(SceneCodecErrors, WrongType) {
  EXPECT_TRUE(HasError(scene_with(R"("name": 5)"), "/name", "expected a string, got a number"));
  EXPECT_TRUE(HasError(scene_with(R"("meshing": {"adaptive": "yes"})"), "/meshing/adaptive",
                       "expected a boolean"));
  EXPECT_TRUE(HasError(scene_with(R"("meshing": {"refine_direct": 1})"), "/meshing/refine_direct",
                       "expected a boolean"));
  EXPECT_TRUE(HasError(scene_with(R"("solver": {"exact_visibility": "yes"})"), "/solver/exact_visibility",
                       "expected a boolean"));
}

TEST(SceneCodecErrors, NonWholeInteger) {
  EXPECT_TRUE(HasError(scene_with(R"("solver": {"max_iterations": 1.5})"), "/solver/max_iterations",
                       "expected a whole number, got 1.5"));
}

TEST(SceneCodecErrors, ReflectanceAboveOneInTable) {
  const auto r = decode_scene(R"({"materials": {"white": {"reflectance": 0.5},
      "red": {"reflectance": {"nm": [400, 500, 600, 700], "values": [0.05, 0.06, 0.55, 1.2]}}},
      "surfaces": [)" + std::string(kFloor) + "]}");
  ASSERT_EQ(r.errors.size(), 1u) << format_errors(r.errors);
  EXPECT_EQ(format_errors(r.errors), "/materials/red/reflectance/values/3: 1.2 is outside [0, 1]\n");
}

TEST(SceneCodecErrors, NegativeEmission) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "polygon": [[0,0,0], [0,0,1], [1,0,1]],
                                               "emission": {"exitance": -1}})"),
                       "/surfaces/0/emission/exitance", "-1 must be >= 0"));
  EXPECT_TRUE(HasError(scene_with(R"("lights": [{"type": "point", "position": [0,1,0],
                                     "intensity": {"nm": [400, 500], "values": [1, -0.5]}}])"),
                       "/lights/0/intensity/values/1", "must be >= 0"));
}

TEST(SceneCodecErrors, RgbSpectrumOnlyForReflectances) {
  EXPECT_TRUE(HasError(scene_with(R"("lights": [{"type": "ambient", "irradiance": {"rgb": [1, 1, 1]}}])"),
                       "/lights/0/irradiance/rgb", "only for reflectances"));
}

TEST(SceneCodecErrors, MissingMaterialReference) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "whte", "polygon": [[0,0,0], [0,0,1], [1,0,1]]})"),
                       "/surfaces/0/material", "unknown material 'whte'; did you mean 'white'?"));
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"polygon": [[0,0,0], [0,0,1], [1,0,1]]})"),
                       "/surfaces/0", "missing required key 'material'"));
}

TEST(SceneCodecErrors, DuplicateSurfaceName) {
  EXPECT_TRUE(HasError(scene_with_surfaces(std::string(kFloor) + "," + kFloor), "/surfaces/1/name",
                       "duplicate surface name 'floor'"));
}

TEST(SceneCodecErrors, BothPolygonAndMesh) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "polygon": [[0,0,0], [0,0,1], [1,0,1]],
      "mesh": {"vertices": [[0,0,0], [1,0,0], [0,1,0]], "triangles": [[0,1,2]]}})"),
                       "/surfaces/0", "has both polygon and mesh"));
}

TEST(SceneCodecErrors, NonPlanarPolygon) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white",
      "polygon": [[0,0,0], [0,0,1], [1,0.2,1], [1,0,0]]})"), "/surfaces/0/polygon", "non-planar"));
}

TEST(SceneCodecErrors, SelfIntersectingPolygon) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white",
      "polygon": [[0,0,0], [1,0,1], [1,0,0], [0,0,1]]})"), "/surfaces/0/polygon", "self-intersecting"));
}

TEST(SceneCodecErrors, MeshIndexOutOfRange) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white",
      "mesh": {"vertices": [[0,0,0], [1,0,0], [0,1,0]], "triangles": [[0,1,2], [0,2,3]]}})"),
                       "/surfaces/0/mesh/triangles/1/2", "out of range"));
}

TEST(SceneCodecErrors, DegenerateMeshTriangle) {
  // Triangle 1 is collinear: (0,0,0), (1,0,0), (2,0,0).
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white",
      "mesh": {"vertices": [[0,0,0], [1,0,0], [0,1,0], [2,0,0]], "triangles": [[0,1,2], [0,1,3]]}})"),
                       "/surfaces/0/mesh/triangles/1", "degenerate"));
}

TEST(SceneCodecErrors, TwoTotals) {
  EXPECT_TRUE(HasError(scene_with(R"("lights": [{"type": "point", "position": [0,1,0], "intensity": 1,
                                     "luminous_intensity_cd": 100, "luminous_flux_lm": 1000}])"),
                       "/lights/0", "two totals given (luminous_intensity_cd and luminous_flux_lm)"));
}

TEST(SceneCodecErrors, InapplicableTotal) {
  EXPECT_TRUE(HasError(scene_with(R"("lights": [{"type": "point", "position": [0,1,0], "intensity": 1,
                                     "luminance_cd_m2": 100}])"),
                       "/lights/0/luminance_cd_m2", "luminance_cd_m2 does not apply to a point light"));
}

TEST(SceneCodecErrors, SpectrumWithoutVisibleContent) {
  EXPECT_TRUE(HasError(scene_with(R"("lights": [{"type": "point", "position": [0,1,0],
      "intensity": {"nm": [900, 1000], "values": [1, 1]}, "luminous_intensity_cd": 100}])"),
                       "/lights/0/intensity", "no visible content"));
}

TEST(SceneCodecErrors, BadUnits) {
  EXPECT_TRUE(HasError(scene_with(R"("units": "km")"), "/units", "unknown unit 'km'"));
}

TEST(SceneCodecErrors, BadSpectrumGrid) {
  EXPECT_TRUE(HasError(scene_with(R"("spectrum": {"mode": "spectral", "from_nm": 780, "to_nm": 380, "step_nm": 5})"),
                       "/spectrum/to_nm", "must be greater than from_nm"));
  EXPECT_TRUE(HasError(scene_with(R"("spectrum": {"mode": "spectral", "from_nm": 380, "to_nm": 780, "step_nm": 0})"),
                       "/spectrum/step_nm", "0 must be > 0"));
  EXPECT_TRUE(HasError(scene_with(R"("spectrum": {"mode": "spectral", "from_nm": 1, "to_nm": 100000, "step_nm": 1})"),
                       "/spectrum/step_nm", "at most 10000"));
  EXPECT_TRUE(HasError(scene_with(R"("spectrum": {"mode": "spectral", "wavelengths_nm": [450, 550, 550]})"),
                       "/spectrum/wavelengths_nm/2", "strictly ascending"));
}

TEST(SceneCodecErrors, TooDeepNestingIsRejectedQuickly) {
  const auto start = std::chrono::steady_clock::now();
  const DecodeResult r = decode_scene(std::string(100000, '['));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].pointer, "");
  EXPECT_NE(r.errors[0].message.find("nesting deeper than 256"), std::string::npos);
  EXPECT_LT(seconds, 1.0);
}

TEST(SceneCodecErrors, InvalidUtf8) {
  EXPECT_TRUE(HasError("{\"name\": \"\xff\"}", "", "invalid UTF-8 at byte offset 10"));
  EXPECT_TRUE(HasError("{\"name\": \"\xed\xa0\x80\"}", "", "invalid UTF-8"));  // encoded surrogate
}

TEST(SceneCodecErrors, TruncatedJson) {
  EXPECT_TRUE(HasError("{\"materials\": {\n  \"white\": {\"reflectance\": 0.5", "", "line 2, column"));
}

TEST(SceneCodecErrors, TopLevelNotAnObject) {
  EXPECT_TRUE(HasError("[1, 2]", "", "a scene must be a JSON object, got an array"));
}

TEST(SceneCodecErrors, FileSurfaceDenied) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "file": "m.obj"})"), "/surfaces/0/file",
                       "file surfaces are not allowed here (start the server with --mesh-root)",
                       FileAccess{FileAccess::Policy::Deny, {}, {}}));
}

TEST(SceneCodecErrors, FileEscapingRootWithDotDot) {
  TempDir dir;
  fs::create_directory(dir.path / "root");
  write_triangle_obj(dir.path / "outside.obj");
  const FileAccess under{FileAccess::Policy::UnderRoot, {}, dir.path / "root"};
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "file": "../outside.obj"})"),
                       "/surfaces/0/file", "must not contain '..'", under));
}

TEST(SceneCodecErrors, AbsoluteFileUnderRoot) {
  TempDir dir;
  write_triangle_obj(dir.path / "m.obj");
  const FileAccess under{FileAccess::Policy::UnderRoot, {}, dir.path};
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "file": ")" +
                                           (dir.path / "m.obj").string() + "\"}"),
                       "/surfaces/0/file", "must be relative to the mesh root", under));
}

TEST(SceneCodecErrors, SymlinkEscapingRoot) {
  TempDir dir;
  fs::create_directory(dir.path / "root");
  write_triangle_obj(dir.path / "secret.obj");
  fs::create_symlink(dir.path / "secret.obj", dir.path / "root" / "link.obj");
  const FileAccess under{FileAccess::Policy::UnderRoot, {}, dir.path / "root"};
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "file": "link.obj"})"),
                       "/surfaces/0/file", "outside the mesh root", under));
}

TEST(SceneCodec, FileSurfacesUnderRootAndAnywhere) {
  TempDir dir;
  fs::create_directory(dir.path / "meshes");
  write_triangle_obj(dir.path / "meshes" / "tri.obj");
  const std::string text = scene_with_surfaces(
      R"({"material": "white", "file": "meshes/tri.obj", "transform": {"scale": 2}})", R"("units": "cm")");
  for (const FileAccess& files : {FileAccess{FileAccess::Policy::UnderRoot, {}, dir.path},
                                  FileAccess{FileAccess::Policy::Anywhere, dir.path, {}}}) {
    auto s = decode_ok(text, files);
    ASSERT_TRUE(s);
    const TriangleMesh& m = s->surfaces[0].mesh;
    ASSERT_EQ(m.triangles.size(), 1u);
    EXPECT_NEAR(m.triangle(0).area(), 0.5 * 0.02 * 0.02, 1e-18);  // scale 2 in cm
  }
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "file": "meshes/none.obj"})"),
                       "/surfaces/0/file", "not found", FileAccess{FileAccess::Policy::UnderRoot, {}, dir.path}));
  // A file the reader rejects: the message shows the scene's path, not the server's root.
  std::ofstream(dir.path / "meshes" / "bad.off") << "not an off file\n";
  const DecodeResult r = decode_scene(scene_with_surfaces(R"({"material": "white", "file": "meshes/bad.off"})"),
                                      FileAccess{FileAccess::Policy::UnderRoot, {}, dir.path});
  ASSERT_EQ(r.errors.size(), 1u) << format_errors(r.errors);
  EXPECT_EQ(r.errors[0].pointer, "/surfaces/0/file");
  EXPECT_EQ(r.errors[0].message.find(dir.path.string()), std::string::npos) << r.errors[0].message;
  EXPECT_EQ(r.errors[0].message.rfind("meshes/bad.off: ", 0), 0u) << r.errors[0].message;
}

TEST(SceneCodecErrors, UnsupportedVersion) {
  EXPECT_TRUE(HasError(scene_with(R"("lambert": 2)"), "/lambert", "unsupported format version 2"));
}

TEST(SceneCodecErrors, RgbModeTakesNoGrid) {  // the rgb model chooses its own internal grid
  EXPECT_TRUE(HasError(scene_with(R"("spectrum": {"mode": "rgb", "step_nm": 5})"), "/spectrum/step_nm",
                       "unknown key"));
}

TEST(SceneCodecErrors, ZeroLengthProbeNormal) {
  EXPECT_TRUE(HasError(scene_with(R"("probes": [{"position": [0, 1, 0], "normal": [0, 0, 0]}])"),
                       "/probes/0/normal", "zero vector"));
}

TEST(SceneCodec, ProbeQuantities) {
  auto s = decode_ok(scene_with(R"("probes": [
      {"position": [0, 1, 0], "normal": [0, 1, 0]},
      {"position": [0, 1, 0], "normal": [1, 0, 0], "quantity": "vertical"},
      {"position": [0, 1, 0], "normal": [0, 2, 0], "quantity": "cylindrical"},
      {"position": [0, 1, 0], "normal": [0, 1, 0], "quantity": "semicylindrical", "facing": [0, 0, -3]},
      {"grid": {"origin": [0, 1, 0], "u": [1, 0, 0], "v": [0, 0, 1], "nu": 2, "nv": 2}, "normal": [0, 1, 0],
       "quantity": "hemispherical"}])"));
  ASSERT_TRUE(s);
  ASSERT_EQ(s->probes.size(), 5u);
  EXPECT_EQ(s->probes[0].quantity, ProbeQuantity::Planar);  // the default
  EXPECT_EQ(s->probes[1].quantity, ProbeQuantity::Vertical);
  EXPECT_EQ(s->probes[2].quantity, ProbeQuantity::Cylindrical);
  EXPECT_DOUBLE_EQ(s->probes[2].normal.y, 1.0);  // the axis, normalised
  EXPECT_EQ(s->probes[3].quantity, ProbeQuantity::Semicylindrical);
  EXPECT_DOUBLE_EQ(s->probes[3].facing.z, -1.0);  // normalised
  EXPECT_EQ(s->probes[4].quantity, ProbeQuantity::Hemispherical);
  EXPECT_EQ(s->probes[4].points.size(), 4u);
}

TEST(SceneCodecErrors, ProbeQuantities) {
  EXPECT_TRUE(HasError(scene_with(R"("probes": [{"position": [0, 1, 0], "normal": [0, 1, 0], "quantity": "cylindric"}])"),
                       "/probes/0/quantity", "did you mean 'cylindrical'?"));
  EXPECT_TRUE(HasError(scene_with(R"("probes": [{"position": [0, 1, 0], "normal": [0, 1, 0], "quantity": 3}])"),
                       "/probes/0/quantity", "expected a string"));
  EXPECT_TRUE(HasError(scene_with(R"("probes": [{"position": [0, 1, 0], "normal": [0, 1, 0], "quantity": "semicylindrical"}])"),
                       "/probes/0", "needs facing"));
  EXPECT_TRUE(HasError(scene_with(R"("probes": [{"position": [0, 1, 0], "normal": [0, 1, 0], "quantity": "semicylindrical",
                                                 "facing": [1, 0.01, 0]}])"),
                       "/probes/0/facing", "must be perpendicular to normal"));
  EXPECT_TRUE(HasError(scene_with(R"("probes": [{"position": [0, 1, 0], "normal": [0, 1, 0], "facing": [1, 0, 0]}])"),
                       "/probes/0/facing", "semicylindrical probes only"));
}

TEST(SceneCodec, TaskSummaryAndGlare) {
  auto s = decode_ok(scene_with_surfaces(
      R"({"material": "white", "role": "wall", "polygon": [[0,0,0], [0,0,1], [1,0,1], [1,0,0]]})",
      R"("probes": [{"name": "desk", "grid": {"origin": [0, 1, 0], "u": [1, 0, 0], "v": [0, 0, 1], "nu": 2, "nv": 2},
                     "normal": [0, 1, 0]},
                    {"name": "point", "position": [0, 1, 0], "normal": [0, 1, 0]}],
         "task_summary": {"maintenance_factor": 0.8},
         "glare": [{"name": "desk", "position": [0, 1200, 0], "view": [1, 0, 0], "up": [1, 2, 0]}],
         "units": "mm")"));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->surfaces[0].role, SurfaceRole::Wall);
  ASSERT_TRUE(s->task_summary);
  EXPECT_EQ(s->task_summary->maintenance_factor, 0.8);
  ASSERT_EQ(s->task_summary->grids.size(), 1u);  // every grid probe by default, not the point
  EXPECT_EQ(s->task_summary->grids[0], 0);
  ASSERT_EQ(s->glare.size(), 1u);
  EXPECT_DOUBLE_EQ(s->glare[0].position.y, 1.2);  // metres
  EXPECT_DOUBLE_EQ(s->glare[0].up.y, 1.0);        // the part of up across the view
  EXPECT_DOUBLE_EQ(s->glare[0].up.x, 0.0);
}

TEST(SceneCodecErrors, TaskSummaryAndGlare) {
  const std::string probes = R"("probes": [{"name": "desk", "grid": {"origin": [0, 1, 0], "u": [1, 0, 0], "v": [0, 0, 1],
                                "nu": 2, "nv": 2}, "normal": [0, 1, 0]}, {"name": "dot", "position": [0, 1, 0], "normal": [0, 1, 0]}])";
  EXPECT_TRUE(HasError(scene_with(probes + R"(, "task_summary": {"grids": ["dsek"]})"), "/task_summary/grids/0",
                       "did you mean 'desk'?"));
  EXPECT_TRUE(HasError(scene_with(probes + R"(, "task_summary": {"grids": ["dot"], "up": [0, 1, 0]})"),
                       "/task_summary/grids/0", "is a point, not a grid"));
  EXPECT_TRUE(HasError(scene_with(probes + R"(, "task_summary": {})"), "/task_summary", "no surface has a role"));
  EXPECT_TRUE(HasError(scene_with(probes + R"(, "task_summary": {"up": [0, 1, 0], "maintenance_factor": 1.2})"),
                       "/task_summary/maintenance_factor", "outside"));
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "role": "wal", "polygon": [[0,0,0], [0,0,1], [1,0,1]]})"),
                       "/surfaces/0/role", "did you mean 'wall'?"));
  EXPECT_TRUE(HasError(scene_with(R"("glare": [{"position": [0, 1, 0], "view": [1, 0, 0], "up": [2, 0, 0]}])"),
                       "/glare/0/up", "parallel to view"));
  EXPECT_TRUE(HasError(scene_with(R"("glare": [{"position": [0, 1, 0], "up": [0, 1, 0]}])"), "/glare/0",
                       "view"));
}

TEST(SceneCodecErrors, HugeCoordinate) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "polygon": [[0,0,0], [1e300,0,1], [1,0,1]]})"),
                       "/surfaces/0/polygon/1/0", "beyond the coordinate limit"));
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "polygon": [[0,0,0], [1e400,0,1], [1,0,1]]})"),
                       "/surfaces/0/polygon/1/0", "number overflow parsing '1e400' (not a finite double)"));
}

TEST(SceneCodecErrors, TransformOnPolygon) {
  EXPECT_TRUE(HasError(scene_with_surfaces(R"({"material": "white", "polygon": [[0,0,0], [0,0,1], [1,0,1]],
                                               "transform": {"scale": 2}})"),
                       "/surfaces/0/transform", "only to mesh and file"));
}

TEST(SceneCodecErrors, AllErrorsAreCollected) {
  const DecodeResult r = decode_scene(R"({"units": "km", "materials": {"white": {"reflectance": 2}},
      "surfaces": [{"material": "white", "polygon": [[0,0,0], [0,0,1], [1,0,1]], "colour": 1}],
      "solver": {"tolerance": 0.5}})");
  ASSERT_FALSE(r.ok());
  const std::string all = format_errors(r.errors);
  EXPECT_EQ(r.errors.size(), 4u) << all;
  for (const char* p : {"/units: ", "/materials/white/reflectance: ", "/surfaces/0/colour: ",
                        "/solver/tolerance: 0.5 is outside (0, 0.1]"})
    EXPECT_NE(all.find(p), std::string::npos) << p << " missing in\n" << all;
}

TEST(SceneCodecErrors, FormatErrorsNamesTheDocument) {
  EXPECT_EQ(format_errors({{"", "invalid JSON"}, {"/units", "bad"}}), "(document): invalid JSON\n/units: bad\n");
}

}  // namespace
}  // namespace lambert

namespace lambert {
namespace {

// "thermal" on surfaces and output.view_factors (SPEC §5).
std::string thermal_floor(const std::string& name, const std::string& thermal) {
  return R"({"name": ")" + name + R"(", "material": "white", "polygon": [[0,0,0], [0,0,1], [1,0,1], [1,0,0]], "thermal": )" +
         thermal + "}";
}
std::string plain_floor(const std::string& name) {
  return R"({"name": ")" + name + R"(", "material": "white", "polygon": [[0,0,0], [0,0,1], [1,0,1], [1,0,0]]})";
}

TEST(SceneCodec, ThermalAndViewFactors) {
  const auto scene = decode_ok(scene_with_surfaces(
      thermal_floor("a", R"({"emissivity": 0.9, "temperature_K": 300})") + "," +
          thermal_floor("b", R"({"emissivity": 0.5, "net_flux_W_m2": -20})"),
      R"("output": {"view_factors": true})"));
  ASSERT_TRUE(scene);
  ASSERT_TRUE(scene->surfaces[0].thermal && scene->surfaces[1].thermal);
  EXPECT_EQ(scene->surfaces[0].thermal->emissivity, 0.9);
  EXPECT_EQ(*scene->surfaces[0].thermal->temperature_K, 300);
  EXPECT_FALSE(scene->surfaces[0].thermal->net_flux_W_m2);
  EXPECT_EQ(*scene->surfaces[1].thermal->net_flux_W_m2, -20);
  EXPECT_TRUE(scene->output.view_factors);
  EXPECT_FALSE(decode_ok(scene_with(R"("output": {"view_factors": false})"))->output.view_factors);
}

TEST(SceneCodecErrors, ThermalIsCheckedAndOnEverySurface) {
  const std::string t300 = R"({"emissivity": 0.9, "temperature_K": 300})";
  EXPECT_TRUE(HasError(scene_with_surfaces(thermal_floor("a", t300) + "," + plain_floor("b")), "/surfaces/1",
                       "\"thermal\" is needed on every surface once one has it"));
  EXPECT_TRUE(HasError(scene_with_surfaces(thermal_floor("a", R"({"emissivity": 0.9, "temperature_K": 300,
                                                                  "net_flux_W_m2": 0})")),
                       "/surfaces/0/thermal", "not both"));
  EXPECT_TRUE(HasError(scene_with_surfaces(thermal_floor("a", R"({"emissivity": 0.9})")), "/surfaces/0/thermal",
                       "\"temperature_K\" or its \"net_flux_W_m2\""));
  EXPECT_TRUE(HasError(scene_with_surfaces(thermal_floor("a", R"({"temperature_K": 300})")), "/surfaces/0/thermal",
                       "\"emissivity\" is required"));
  EXPECT_TRUE(HasError(scene_with_surfaces(thermal_floor("a", R"({"emissivity": 1.2, "temperature_K": 300})")),
                       "/surfaces/0/thermal/emissivity", "outside [0, 1]"));
  EXPECT_TRUE(HasError(scene_with_surfaces(thermal_floor("a", R"({"emissivity": 0.9, "temperature_K": -3})")),
                       "/surfaces/0/thermal/temperature_K", "-3 is outside (0, 1e+05]"));
  EXPECT_TRUE(HasError(scene_with_surfaces(thermal_floor("a", R"({"emissivity": 0, "net_flux_W_m2": 5})")),
                       "/surfaces/0/thermal/net_flux_W_m2", "neither emits nor absorbs"));
  EXPECT_TRUE(HasError(scene_with(R"("output": {"view_factors": "yes"})"), "/output/view_factors",
                       "expected a boolean"));
}

TEST(SceneCodec, OutputErrorEstimate) {
  EXPECT_FALSE(decode_ok(scene_with(""))->output.error_estimate);
  EXPECT_TRUE(decode_ok(scene_with(R"("output": {"error_estimate": true})"))->output.error_estimate);
  EXPECT_TRUE(HasError(scene_with(R"("output": {"error_estimate": 1})"), "/output/error_estimate",
                       "expected a boolean"));
}

}  // namespace
}  // namespace lambert
