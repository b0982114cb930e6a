// Exchange formats of a result (server/export/): a solved scene written as a result, read back
// (result_model.h) and exported as glTF binary, PLY and CSV, each file read back by an independent
// reader (the GLB container and its accessors parsed here from the specification; the PLY by the
// strict mesh reader that takes files from the field, mesh/mesh_ops.h, and its header by hand; the
// CSV by strtod) and compared with the
// result's own numbers. The Khronos validator checks the same files in tests/export_validate_test.sh.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <numbers>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mesh/mesh_ops.h"
#include "server/export/corner_values.h"
#include "server/export/export_formats.h"
#include "server/export/export_mesh.h"
#include "server/export/result_model.h"
#include "server/result_codec.h"
#include "server/scene_codec.h"
#include "solver/radiosity.h"
#include "solver/report.h"
#include "solver/spectrum.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// A floor (grey, facing +y) and a wall (red, facing +x) in millimetres under a 1 cd point source,
// with a 4 × 3 probe grid whose name needs quoting in CSV, and a single probe point that measures
// cylindrical illuminance (a vertical cylinder, axis +y).
constexpr const char* kScene = R"({"lambert": 1, "name": "export-test", "units": "mm",
  "spectrum": {"mode": "spectral", "wavelengths_nm": [450, 550, 650]},
  "materials": {"grey": {"reflectance": 0.5},
                "red": {"reflectance": {"nm": [450, 550, 650], "values": [0.1, 0.1, 0.7]}}},
  "surfaces": [{"name": "floor", "material": "grey", "polygon": [[0,0,0], [0,0,1000], [1000,0,1000], [1000,0,0]]},
               {"name": "wall", "material": "red", "polygon": [[0,0,0], [0,1000,0], [0,1000,1000], [0,0,1000]]}],
  "lights": [{"type": "point", "position": [500, 800, 500], "intensity": 1.0}],
  "probes": [{"name": "work, \"plane\"", "grid": {"origin": [100, 1, 100], "u": [800, 0, 0], "v": [0, 0, 800],
                                                "nu": 4, "nv": 3}, "normal": [0, 1, 0]},
             {"name": "desk", "position": [500, 500, 500], "normal": [0, 1, 0], "quantity": "cylindrical"}],
  "meshing": {"max_patch_area": 20000}})";

struct Solved {
  Scene scene;
  Solution solution;
  Report report;
  std::string result_json;
};

Solved solve_text(const std::string& scene_json) {
  DecodeResult decoded = decode_scene(scene_json);
  EXPECT_TRUE(decoded.ok()) << format_errors(decoded.errors);
  Solved s{*decoded.scene, {}, {}, {}};
  s.solution = solve(s.scene);
  s.report = make_report(s.scene, s.solution);
  s.result_json = encode_result(s.scene, s.solution, s.report);
  return s;
}

const Solved& lit_corner() {
  static const Solved solved = solve_text(kScene);
  return solved;
}

double brightest_luminance(const Report& r) {
  double white = 0;
  for (const PatchPhotometry& p : r.patches) white = std::max(white, p.luminance_cd_m2);
  return white;
}

TEST(ResultModel, ReadsBackWhatSolveWrote) {
  const Solved& s = lit_corner();
  const ResultModel model = read_result(s.result_json);
  EXPECT_EQ(model.name, "export-test");
  EXPECT_EQ(model.unit_m, 0.001);  // "units": "mm"
  ASSERT_EQ(model.patches.size(), s.solution.patches.size());
  ASSERT_EQ(model.surfaces, (std::vector<std::string>{"floor", "wall"}));
  for (std::size_t i = 0; i < model.patches.size(); ++i) {
    const ResultPatch& p = model.patches[i];
    EXPECT_EQ(p.illuminance_lx, s.report.patches[i].illuminance_lx);
    EXPECT_EQ(p.luminance_cd_m2, s.report.patches[i].luminance_cd_m2);
    EXPECT_EQ(model.surfaces[p.surface], s.scene.surfaces[s.solution.patches[i].surface].name);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.triangle.v[k].x * model.unit_m, s.solution.patches[i].triangle.v[k].x, 1e-12);
  }
  // No patch emits: the white is the brightest patch (solver/report.cpp), recovered from srgb_encoded.
  ASSERT_TRUE(model.white_cd_m2);
  EXPECT_NEAR(*model.white_cd_m2, brightest_luminance(s.report), 1e-9 * brightest_luminance(s.report));
  ASSERT_EQ(model.probes.size(), 2u);
  EXPECT_TRUE(model.probes[0].is_grid);
  EXPECT_EQ(model.probes[0].nu, 4);
  EXPECT_EQ(model.probes[0].illuminance_lx, s.report.probes[0].illuminance_lx);
  EXPECT_FALSE(model.probes[1].is_grid);

  EXPECT_THROW(read_result("[1, 2]"), std::invalid_argument);
  try {
    read_result(R"({"patches": [{"vertices": [[0,0,0], [1,0,0]]}]})");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "/patches/0/vertices: expected three points");
  }
}

// A fan of three coplanar triangles around the origin with areas 1, 2, 3 (z = 0), and a fourth
// triangle on the fan's edge folded out of the plane by `fold_deg`.
std::vector<Triangle> fan(double fold_deg) {
  const double f = fold_deg * std::numbers::pi / 180;
  return {Triangle{{Point3{0, 0, 0}, Point3{2, 0, 0}, Point3{0, 1, 0}}},          // area 1
          Triangle{{Point3{0, 0, 0}, Point3{0, 1, 0}, Point3{-4, 0, 0}}},         // area 2
          Triangle{{Point3{0, 0, 0}, Point3{-4, 0, 0}, Point3{0, -1.5, 0}}},      // area 3
          Triangle{{Point3{0, 0, 0}, Point3{0, -1.5, 0}, Point3{std::cos(f), 0, std::sin(f)}}}};
}

TEST(CornerValues, FlatCopiesSmoothIsTheAreaWeightedMeanAndCreasesStaySharp) {
  const std::vector<double> values = {10, 20, 30, 40};
  const std::vector<double> flat = corner_values(fan(0), {}, values, 1, Shading::Flat);
  for (std::size_t c = 0; c < 12; ++c) EXPECT_EQ(flat[c], values[c / 3]);

  // Folded by 20° (< kCreaseAngle_deg): the fourth joins. Its area is ½ · 1.5 · 1 = 0.75, and the
  // origin is a corner of all four: (1·10 + 2·20 + 3·30 + 0.75·40) / 6.75.
  const std::vector<double> smooth = corner_values(fan(20), {}, values, 1, Shading::Smooth);
  EXPECT_NEAR(smooth[0], (10 + 40 + 90 + 30) / 6.75, 1e-12);
  EXPECT_NEAR(smooth[1], 10, 1e-12);                         // (2,0,0): only the first triangle
  EXPECT_NEAR(smooth[2], (1 * 10 + 2 * 20) / 3.0, 1e-12);    // (0,1,0): the first two
  EXPECT_NEAR(smooth[7], (2 * 20 + 3 * 30) / 5.0, 1e-12);    // (−4,0,0): the second and third
  EXPECT_NEAR(smooth[10], (3 * 30 + 0.75 * 40) / 3.75, 1e-12);  // (0,−1.5,0)
  // Folded by 90°, the fourth is across a crease: it keeps its own value, the others leave it out.
  const std::vector<double> creased = corner_values(fan(90), {}, values, 1, Shading::Smooth);
  EXPECT_NEAR(creased[0], (10 + 40 + 90) / 6.0, 1e-12);
  EXPECT_NEAR(creased[9], 40, 1e-12);
  // Another surface never blends, however flat the fold.
  const std::vector<double> apart = corner_values(fan(0), {0, 0, 0, 1}, values, 1, Shading::Smooth);
  EXPECT_NEAR(apart[9], 40, 1e-12);
  EXPECT_NEAR(apart[0], (10 + 40 + 90) / 6.0, 1e-12);
}

TEST(ExportMesh, FlatVerticesCarryTheirPatchValuesAndTheResultsDisplayColour) {
  const Solved& s = lit_corner();
  const ResultModel model = read_result(s.result_json);
  const ExportMesh mesh = export_mesh(model, {Shading::Flat, std::nullopt});
  ASSERT_EQ(mesh.surfaces.size(), 2u);
  const double white = brightest_luminance(s.report);
  EXPECT_NEAR(mesh.white_cd_m2, white, 1e-9 * white);
  std::vector<std::size_t> next(2, 0);  // each surface's triangles in the result's patch order
  for (std::size_t i = 0; i < model.patches.size(); ++i) {
    const ResultPatch& p = model.patches[i];
    const ExportSurface& out = mesh.surfaces[p.surface];
    const std::size_t t = next[p.surface]++;
    ASSERT_LT(3 * t + 2, out.indices.size());
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = out.indices[3 * t + k];
      EXPECT_EQ(out.illuminance_lx[v], float(p.illuminance_lx));
      EXPECT_EQ(out.luminance_cd_m2[v], float(p.luminance_cd_m2));
      EXPECT_EQ(out.position_m[v][0], float(s.solution.patches[i].triangle.v[k].x));
      EXPECT_EQ(out.position_m[v][2], float(s.solution.patches[i].triangle.v[k].z));
      for (int c = 0; c < 3; ++c) {
        // The colour is the result's own display value before its transfer curve (report.cpp).
        EXPECT_NEAR(out.colour[v][c], std::min(1.0, s.report.patches[i].srgb[c] / white), 1e-6);
        EXPECT_NEAR(srgb_encode(out.colour[v][c]), s.report.patches[i].srgb_encoded[c], 1e-6);
      }
    }
  }
  for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(next[k] * 3, mesh.surfaces[k].indices.size());
}

TEST(ExportMesh, SmoothSharesVerticesAndKeepsAUniformFieldExact) {
  // A black floor under a directional light: E = 1000 lx cos 0 on every patch, so smoothing
  // (a mean of equal values) must give 1000 everywhere.
  const Solved s = solve_text(R"({"lambert": 1, "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
    "materials": {"black": {"reflectance": 0}},
    "surfaces": [{"name": "floor", "material": "black", "polygon": [[0,0,0], [2,0,0], [2,1,0], [0,1,0]]}],
    "lights": [{"type": "directional", "direction": [0, 0, -1], "irradiance": 1.0, "illuminance_lx": 1000}],
    "meshing": {"max_patch_area": 0.01}})");
  const ResultModel model = read_result(s.result_json);
  const ExportMesh smooth = export_mesh(model, {Shading::Smooth, std::nullopt});
  const ExportMesh flat = export_mesh(model, {Shading::Flat, std::nullopt});
  ASSERT_EQ(smooth.surfaces.size(), 1u);
  for (float E : smooth.surfaces[0].illuminance_lx) EXPECT_NEAR(E, 1000, 1000 * 1e-6);
  EXPECT_EQ(smooth.surfaces[0].indices.size(), 3 * model.patches.size());
  // Interior vertices are shared by several patches: far fewer vertices than corners.
  EXPECT_LT(smooth.surfaces[0].position_m.size(), model.patches.size());
  EXPECT_LE(flat.surfaces[0].position_m.size(), 3 * model.patches.size());
}

// ---- the GLB container, read as glTF 2.0 §4.4 describes it ---------------------------------------

std::uint32_t u32(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int b = 3; b >= 0; --b) v = (v << 8) | static_cast<unsigned char>(bytes[at + b]);
  return v;
}

struct Glb {
  json doc;
  std::string bin;
};

Glb parse_glb(const std::string& bytes) {
  Glb g;
  EXPECT_GE(bytes.size(), 28u);
  EXPECT_EQ(u32(bytes, 0), 0x46546C67u);  // "glTF"
  EXPECT_EQ(u32(bytes, 4), 2u);
  EXPECT_EQ(u32(bytes, 8), bytes.size());
  const std::uint32_t json_length = u32(bytes, 12);
  EXPECT_EQ(u32(bytes, 16), 0x4E4F534Au);  // "JSON"
  EXPECT_EQ(json_length % 4, 0u);
  g.doc = json::parse(bytes.substr(20, json_length));
  const std::size_t bin_at = 20 + json_length;
  const std::uint32_t bin_length = u32(bytes, bin_at);
  EXPECT_EQ(u32(bytes, bin_at + 4), 0x004E4942u);  // "BIN\0"
  EXPECT_EQ(bin_length % 4, 0u);
  EXPECT_EQ(bin_at + 8 + bin_length, bytes.size());
  g.bin = bytes.substr(bin_at + 8, bin_length);
  return g;
}

// Accessor `index` as floats (FLOAT, tightly packed).
std::vector<float> floats(const Glb& g, int index) {
  const json& a = g.doc["accessors"][index];
  EXPECT_EQ(a["componentType"], 5126);
  const json& view = g.doc["bufferViews"][a["bufferView"].get<int>()];
  const int components = a["type"] == "SCALAR" ? 1 : a["type"] == "VEC3" ? 3 : 0;
  const std::size_t n = a["count"].get<std::size_t>() * components;
  EXPECT_EQ(view["byteLength"].get<std::size_t>(), 4 * n);
  std::vector<float> out(n);
  std::memcpy(out.data(), g.bin.data() + view["byteOffset"].get<std::size_t>(), 4 * n);
  return out;
}

TEST(Glb, ParsesBackToTheExportedVertices) {
  const Solved& s = lit_corner();
  const ExportMesh mesh = export_mesh(read_result(s.result_json), {Shading::Smooth, std::nullopt});
  const Glb g = parse_glb(export_result(s.result_json, ExportFormat::Glb, {Shading::Smooth, std::nullopt}));
  EXPECT_EQ(g.doc["asset"]["version"], "2.0");
  EXPECT_EQ(g.doc["extensionsUsed"], json::array({"KHR_materials_unlit"}));
  EXPECT_TRUE(g.doc["materials"][0]["extensions"].contains("KHR_materials_unlit"));
  ASSERT_EQ(g.doc["meshes"].size(), 4u);  // the two surfaces, then the two probes
  EXPECT_NEAR(g.doc["scenes"][0]["extras"]["white_cd_m2"].get<double>(), mesh.white_cd_m2, 1e-9 * mesh.white_cd_m2);
  for (std::size_t k = 0; k < 2; ++k) {
    SCOPED_TRACE(k);
    const ExportSurface& surface = mesh.surfaces[k];
    EXPECT_EQ(g.doc["nodes"][k]["name"], surface.name);
    const json& primitive = g.doc["meshes"][k]["primitives"][0];
    const json& attributes = primitive["attributes"];
    const std::vector<float> E = floats(g, attributes["_ILLUMINANCE_LX"]);
    const std::vector<float> L = floats(g, attributes["_LUMINANCE_CD_M2"]);
    const std::vector<float> P = floats(g, attributes["POSITION"]);
    const std::vector<float> C = floats(g, attributes["COLOR_0"]);
    ASSERT_EQ(E.size(), surface.position_m.size());
    for (std::size_t v = 0; v < E.size(); ++v) {
      EXPECT_EQ(E[v], surface.illuminance_lx[v]);
      EXPECT_EQ(L[v], surface.luminance_cd_m2[v]);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(P[3 * v + c], surface.position_m[v][c]);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(C[3 * v + c], surface.colour[v][c]);
    }
    // POSITION's bounds are required and must be the data's (glTF 2.0 §5.1.1).
    const json& position = g.doc["accessors"][attributes["POSITION"].get<int>()];
    for (int c = 0; c < 3; ++c) {
      float lo = INFINITY, hi = -INFINITY;
      for (std::size_t v = 0; v < E.size(); ++v) lo = std::min(lo, P[3 * v + c]), hi = std::max(hi, P[3 * v + c]);
      EXPECT_EQ(position["min"][c].get<double>(), lo);
      EXPECT_EQ(position["max"][c].get<double>(), hi);
    }
    const json& indices = g.doc["accessors"][primitive["indices"].get<int>()];
    EXPECT_EQ(indices["componentType"], 5125);
    EXPECT_EQ(indices["count"].get<std::size_t>(), surface.indices.size());
  }
}

// The probes follow the surfaces as point clouds, in metres, with their illuminance and (in the
// node's extras) the grid's shape; the positions against the scene's own grid formula (SPEC §5).
TEST(Glb, ProbesArePointCloudsInMetresWithTheirIlluminance) {
  const Solved& s = lit_corner();
  const Glb g = parse_glb(export_result(s.result_json, ExportFormat::Glb, {Shading::Flat, std::nullopt}));
  ASSERT_EQ(g.doc["nodes"].size(), 4u);
  EXPECT_EQ(g.doc["scenes"][0]["nodes"], json::array({0, 1, 2, 3}));
  const json& grid = g.doc["nodes"][2];
  EXPECT_EQ(grid["name"], "work, \"plane\"");
  EXPECT_EQ(grid["extras"], json({{"probe", "grid"}, {"nu", 4}, {"nv", 3}}));
  EXPECT_EQ(g.doc["nodes"][3]["extras"], json({{"probe", "point"}, {"nu", 1}, {"nv", 1}}));
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k);
    const json& primitive = g.doc["meshes"][g.doc["nodes"][2 + k]["mesh"].get<int>()]["primitives"][0];
    EXPECT_EQ(primitive["mode"], 0);  // POINTS
    EXPECT_FALSE(primitive.contains("indices"));
    const std::vector<float> P = floats(g, primitive["attributes"]["POSITION"]);
    const std::vector<float> E = floats(g, primitive["attributes"]["_ILLUMINANCE_LX"]);
    const std::vector<double>& expected = s.report.probes[k].illuminance_lx;
    ASSERT_EQ(E.size(), expected.size());
    for (std::size_t q = 0; q < E.size(); ++q) EXPECT_EQ(E[q], float(expected[q]));
    if (k == 1) {
      EXPECT_EQ(P, (std::vector<float>{0.5f, 0.5f, 0.5f}));  // the desk probe at (500, 500, 500) mm
      continue;
    }
    for (std::size_t q = 0; q < E.size(); ++q) {
      // origin + (u + ½)/nu · u⃗ + (v + ½)/nv · v⃗, millimetres to metres.
      const double u = q % 4, v = q / 4;
      EXPECT_FLOAT_EQ(P[3 * q + 0], float((100 + (u + 0.5) / 4 * 800) / 1000));
      EXPECT_FLOAT_EQ(P[3 * q + 1], float(1.0 / 1000));
      EXPECT_FLOAT_EQ(P[3 * q + 2], float((100 + (v + 0.5) / 3 * 800) / 1000));
    }
  }
}

TEST(Ply, TheMeshReaderReadsTheSameTrianglesAndTheHeaderListsTheValues) {
  const Solved& s = lit_corner();
  const ExportOptions options{Shading::Flat, std::nullopt};
  const ExportMesh mesh = export_mesh(read_result(s.result_json), options);
  const std::string bytes = export_result(s.result_json, ExportFormat::Ply, options);
  const fs::path path = fs::temp_directory_path() / ("lambert_export_test_" + std::to_string(::getpid()) + ".ply");
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  const MeshFileResult read = read_mesh_file(path.string());
  fs::remove(path);
  ASSERT_TRUE(read.ok()) << read.error;
  std::size_t vertices = 0, faces = 0;
  for (const ExportSurface& surface : mesh.surfaces) vertices += surface.position_m.size(), faces += surface.indices.size() / 3;
  EXPECT_EQ(read.mesh.vertices.size(), vertices);
  EXPECT_EQ(read.mesh.triangles.size(), faces);
  EXPECT_EQ(read.mesh.triangles.size(), s.solution.patches.size());
  // The first surface's first triangle is the first patch, in metres.
  for (int k = 0; k < 3; ++k) {
    const Point3& p = read.mesh.vertices[read.mesh.triangles[0][k]];
    EXPECT_NEAR(p.x, s.solution.patches[0].triangle.v[k].x, 1e-6);
    EXPECT_NEAR(p.y, s.solution.patches[0].triangle.v[k].y, 1e-6);
  }
  // Header, and then exactly V vertices of 6 + 2 floats and 3 bytes, F faces of 1 + 4·3 + 4 bytes.
  const std::size_t end = bytes.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = bytes.substr(0, end);
  for (const char* line : {"format binary_little_endian 1.0", "property uchar red", "property float illuminance_lx",
                           "property float luminance_cd_m2", "property list uchar uint vertex_indices",
                           "comment surface 1 wall"})
    EXPECT_NE(header.find(line), std::string::npos) << line;
  const std::size_t body = end + std::strlen("end_header\n");
  EXPECT_EQ(bytes.size() - body, vertices * 35 + faces * 17);
  // The first vertex's colour bytes: the display colour through the sRGB curve.
  for (int c = 0; c < 3; ++c)
    EXPECT_EQ(static_cast<unsigned char>(bytes[body + 24 + c]), std::lround(255 * srgb_encode(mesh.surfaces[0].colour[0][c])));
  float E = 0;
  std::memcpy(&E, bytes.data() + body + 27, 4);
  EXPECT_EQ(E, mesh.surfaces[0].illuminance_lx[0]);
}

// RFC 4180 fields of one line.
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (quoted && c == '"' && k + 1 < line.size() && line[k + 1] == '"') out.back() += '"', ++k;
    else if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) out.emplace_back();
    else out.back() += c;
  }
  return out;
}

TEST(ProbeCsv, EveryPointWithItsCellAndExactIlluminance) {
  const Solved& s = lit_corner();
  std::istringstream lines(export_result(s.result_json, ExportFormat::Csv, {}));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "probe,u,v,x,y,z,illuminance_lx,quantity\r");
  std::vector<std::vector<std::string>> rows;
  while (std::getline(lines, line)) {
    ASSERT_FALSE(line.empty());
    ASSERT_EQ(line.back(), '\r');
    rows.push_back(csv_fields(line.substr(0, line.size() - 1)));
  }
  ASSERT_EQ(rows.size(), 12u + 1u);
  for (std::size_t q = 0; q < 12; ++q) {
    ASSERT_EQ(rows[q].size(), 8u);
    EXPECT_EQ(rows[q][0], "work, \"plane\"");
    EXPECT_EQ(std::stoi(rows[q][1]), int(q % 4));
    EXPECT_EQ(std::stoi(rows[q][2]), int(q / 4));
    // Grid probes sample cell centres (SPEC §5): x = 100 + (u + ½) · 800 / 4 mm.
    EXPECT_NEAR(std::strtod(rows[q][3].c_str(), nullptr), 100 + (q % 4 + 0.5) * 200, 1e-9);
    EXPECT_EQ(std::strtod(rows[q][6].c_str(), nullptr), s.report.probes[0].illuminance_lx[q]);
    EXPECT_EQ(rows[q][7], "planar");  // the default
  }
  EXPECT_EQ(rows[12][0], "desk");
  EXPECT_EQ(std::strtod(rows[12][6].c_str(), nullptr), s.report.probes[1].illuminance_lx[0]);
  EXPECT_EQ(rows[12][7], "cylindrical");
  // A result written without quantities (before they existed) reads as planar.
  json old = json::parse(s.result_json);
  for (json& p : old["probes"]) p.erase("quantity");
  EXPECT_NE(export_result(old.dump(), ExportFormat::Csv, {}).find(",planar\r\n"), std::string::npos);
}

TEST(ExportFormats, NamesAndExtensions) {
  EXPECT_EQ(export_format_of_path("a/b/OUT.GLB"), ExportFormat::Glb);
  EXPECT_EQ(export_format_of_path("x.ply"), ExportFormat::Ply);
  EXPECT_EQ(export_format_of_path("x.csv"), ExportFormat::Csv);
  EXPECT_FALSE(export_format_of_path("x.gltf"));
  EXPECT_FALSE(export_format_of_path("x"));
  EXPECT_STREQ(export_media_type(ExportFormat::Glb), "model/gltf-binary");
}

}  // namespace
}  // namespace lambert
