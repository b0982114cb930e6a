// `lambert bench`: built-in reference scenes with exact answers (REFERENCES.md), each solved at a
// ladder of patch sizes; one table row per (scene, setting) with time, patches, rays, ray throughput,
// peak memory and the error against the closed form. The scenes go through the same JSON decoder as
// users' scenes, so the whole pipeline is measured. --plot draws time against error, one series per scene.
#include "server/bench_command.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <iostream>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>

#include "server/bench_plot.h"
#include "server/cli_parser.h"
#include "server/scene_codec.h"
#include "solver/closed_forms.h"
#include "solver/radiosity.h"
#include "solver/report.h"
#include "solver/visibility.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

using nlohmann::json;

json rect(const std::array<double, 3>& o, const std::array<double, 3>& u, const std::array<double, 3>& v) {
  auto add = [](auto a, auto b) { return std::array<double, 3>{a[0] + b[0], a[1] + b[1], a[2] + b[2]}; };
  return json::array({o, add(o, u), add(add(o, u), v), add(o, v)});
}

// Axis-aligned box as an inline mesh (6 quads, 12 triangles), normals inward or outward.
json box(const std::array<double, 3>& lo, const std::array<double, 3>& hi, bool inward) {
  const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
  struct Face { std::array<double, 3> o, u, v; };
  const Face faces[] = {{lo, {dx, 0, 0}, {0, dy, 0}},           {{lo[0], lo[1], hi[2]}, {0, dy, 0}, {dx, 0, 0}},
                        {lo, {0, 0, dz}, {dx, 0, 0}},           {{lo[0], hi[1], lo[2]}, {dx, 0, 0}, {0, 0, dz}},
                        {lo, {0, dy, 0}, {0, 0, dz}},           {{hi[0], lo[1], lo[2]}, {0, 0, dz}, {0, dy, 0}}};
  json vertices = json::array(), triangles = json::array();
  for (const Face& f : faces) {
    const int b = static_cast<int>(vertices.size());
    for (const auto& p : inward ? rect(f.o, f.u, f.v) : rect(f.o, f.v, f.u)) vertices.push_back(p);
    triangles.push_back({b, b + 1, b + 2});
    triangles.push_back({b, b + 2, b + 3});
  }
  return {{"vertices", vertices}, {"triangles", triangles}};
}

using closed_form::howell_c11;
using closed_form::howell_c14;
using closed_form::point_under_rectangle;

struct Case {
  std::string name;
  std::string what;      // what the error measures
  json scene;            // without meshing
  double total_area;
  std::function<double(const Scene&, const Solution&, const Report&)> error;
  // The solve's own estimate of that error (stats.error_estimate) where it measures the same
  // quantity; null where the error is not the patches' (the sphere's tessellation) or not a
  // surface or probe value (a furnace's worst patch).
  std::function<double(const SolveStats::ErrorEstimate&)> estimate = nullptr;
  // Scenes whose tessellation is the ladder's subject build their own (with "meshing") per step.
  std::function<json(double divisions)> make_scene = nullptr;
  double max_divisions = 1e300;  // the ladder's rungs above this are skipped (a costly reference)
};

constexpr double kRoomLadderTop = 1200;  // room-interreflection's finest rung: its reference has 4x

// Whether the estimate bounds the error; "floor" where the error is below 1e-6, the quadrature and
// rounding floor of the exact references (black scenes: no discretisation error to estimate).
const char* bound_verdict(double error, const std::optional<double>& estimate) {
  if (!estimate) return "-";
  if (error < 1e-6) return "floor";
  return *estimate >= error ? "yes" : "NO";
}

double surface_estimate(const SolveStats::ErrorEstimate& e) { return e.surface_irradiance_max; }
double probe_rms_estimate(const SolveStats::ErrorEstimate& e) { return e.probe_irradiance_rms; }
double probe_max_estimate(const SolveStats::ErrorEstimate& e) { return e.probe_irradiance_max; }

// Geodesic sphere of radius 1 about the origin, facing inward: each face of an icosahedron split
// into n² triangles on a barycentric grid, the points pushed onto the sphere; 20 n² triangles.
// Shared points are welded by their coordinates rounded to 1e-12.
json inward_geodesic_sphere(int n) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  const std::array<std::array<double, 3>, 12> v = {{{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                                   {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                                   {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}}};
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                            {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                            {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  json vertices = json::array(), triangles = json::array();
  std::map<std::array<long long, 3>, int> index;
  auto point = [&](const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
                   int i, int j) {
    const double u = double(i) / n, w = double(j) / n, t = 1 - u - w;
    std::array<double, 3> p{};
    for (int k = 0; k < 3; ++k) p[k] = t * a[k] + u * b[k] + w * c[k];
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (double& x : p) x /= r;
    const std::array<long long, 3> key{std::llround(p[0] * 1e12), std::llround(p[1] * 1e12), std::llround(p[2] * 1e12)};
    const auto [it, added] = index.try_emplace(key, static_cast<int>(vertices.size()));
    if (added) vertices.push_back(p);
    return it->second;
  };
  for (const auto& f : faces) {
    const auto &a = v[f[0]], &b = v[f[1]], &c = v[f[2]];
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        // The icosahedron's faces are counter-clockwise seen from outside; listed reversed, inward.
        triangles.push_back({point(a, b, c, i, j), point(a, b, c, i, j + 1), point(a, b, c, i + 1, j)});
        if (i + j + 1 < n)
          triangles.push_back({point(a, b, c, i + 1, j), point(a, b, c, i, j + 1), point(a, b, c, i + 1, j + 1)});
      }
  }
  return {{"vertices", vertices}, {"triangles", triangles}};
}

double surface_mean_irradiance(const Report& r, const std::string& name) {
  for (const auto& s : r.surfaces)
    if (s.name == name) return s.irradiance_mean.at(0);
  throw std::runtime_error("no surface " + name);
}

double peak_rss_mb();

// The 6 x 4 x 3 m room of the CIE 171-style cases: every surface of reflectance rho, a 1 m² panel
// (L = 1 W m^-2 sr^-1 nm^-1) 1 mm below the ceiling facing down, and nu x nv sensors 1 cm above the
// floor facing up.
constexpr double kPanelRoomArea = 2 * (24 + 18 + 12) + 1;
json panel_room(const std::string& name, double rho, int nu, int nv) {
  json s = {{"name", name},
            {"spectrum", {{"mode", "spectral"}, {"wavelengths_nm", {555}}}},
            {"materials", {{"wall", {{"reflectance", rho}}}}}};
  s["surfaces"] = {{{"name", "room"}, {"material", "wall"}, {"mesh", box({0, 0, 0}, {6, 4, 3}, true)}},
                   {{"name", "panel"}, {"material", "wall"}, {"polygon", rect({2.5, 1.5, 2.999}, {0, 1, 0}, {1, 0, 0})},
                    {"emission", {{"radiance", 1.0}}}}};
  s["probes"] = {{{"name", "sensors"}, {"normal", {0, 0, 1}},
                  {"grid", {{"origin", {0, 0, 0.01}}, {"u", {6, 0, 0}}, {"v", {0, 4, 0}}, {"nu", nu}, {"nv", nv}}}}};
  return s;
}

std::vector<Case> cases() {
  std::vector<Case> out;
  const json one_wavelength = {{"mode", "spectral"}, {"wavelengths_nm", {555}}};
  {
    json s = {{"name", "opposed-plates"}, {"spectrum", one_wavelength}, {"materials", {{"black", {{"reflectance", 0}}}}}};
    s["surfaces"] = {{{"name", "emitter"}, {"material", "black"}, {"polygon", rect({0, 0, 1}, {0, 1, 0}, {1, 0, 0})},
                      {"emission", {{"exitance", 1.0}}}},
                     {{"name", "receiver"}, {"material", "black"}, {"polygon", rect({0, 0, 0}, {1, 0, 0}, {0, 1, 0})}}};
    out.push_back({"opposed-plates", "receiver mean E vs Howell C-11", s, 2.0, [](const Scene&, const Solution&, const Report& r) {
                     return std::abs(surface_mean_irradiance(r, "receiver") / howell_c11(1, 1) - 1);
                   }, surface_estimate});
  }
  {
    json s = {{"name", "perpendicular-plates"}, {"spectrum", one_wavelength}, {"materials", {{"black", {{"reflectance", 0}}}}}};
    s["surfaces"] = {{{"name", "floor"}, {"material", "black"}, {"polygon", rect({0, 0, 0}, {1, 0, 0}, {0, 1, 0})}},
                     {{"name", "wall"}, {"material", "black"}, {"polygon", rect({0, 0, 0}, {0, 0, 1}, {1, 0, 0})},
                      {"emission", {{"exitance", 1.0}}}}};
    out.push_back({"perpendicular-plates", "floor mean E vs Howell C-14", s, 2.0, [](const Scene&, const Solution&, const Report& r) {
                     return std::abs(surface_mean_irradiance(r, "floor") / howell_c14(1, 1) - 1);
                   }, surface_estimate});
  }
  for (double rho : {0.9, 0.999}) {
    json s = {{"name", "furnace"}, {"spectrum", one_wavelength}, {"materials", {{"grey", {{"reflectance", rho}}}}}};
    s["surfaces"] = {{{"name", "room"}, {"material", "grey"}, {"mesh", box({0, 0, 0}, {4, 3, 2.5}, true)}, {"emission", {{"exitance", 1.0}}}},
                     {{"name", "obstacle"}, {"material", "grey"}, {"mesh", box({1.5, 1, 0.8}, {2.5, 2, 1.6}, false)},
                      {"emission", {{"exitance", 1.0}}}}};
    char name[64];
    std::snprintf(name, sizeof name, "furnace-obstacle-rho%g", rho);
    out.push_back({name, "max patch |B (1-rho)/M - 1|", s, 2 * (12 + 10 + 7.5) + 2 * (1 + 0.8 + 0.8),
                   [rho](const Scene&, const Solution& sol, const Report&) {
                     double worst = 0;
                     for (double b : sol.radiosity) worst = std::max(worst, std::abs(b * (1 - rho) - 1));
                     return worst;
                   }});
  }
  {
    // CIE 171-style: a 6 x 4 x 3 m room with black surfaces, a 1 m² Lambertian ceiling panel (L = 1
    // W m^-2 sr^-1 nm^-1), 384 sensors 1 cm above the floor: E = π L F(point -> panel), exact (B-3).
    const json s = panel_room("cie-room-direct", 0, 24, 16);
    out.push_back({"cie-room-direct", "rms sensor E vs pi L F (B-3)", s, kPanelRoomArea,
                   [](const Scene& scene, const Solution& sol, const Report&) {
                     double sum = 0;
                     const auto& pts = scene.probes.at(0).points;
                     for (std::size_t q = 0; q < pts.size(); ++q) {
                       const double exact = kPi * point_under_rectangle(pts[q].x, pts[q].y, 2.999 - pts[q].z, 2.5, 3.5, 1.5, 2.5);
                       const double e = sol.probes[0].irradiance[q] / exact - 1;
                       sum += e * e;
                     }
                     return std::sqrt(sum / pts.size());
                   }, probe_rms_estimate});
  }
  {
    // REFERENCES V9 (point receiver, opaque polygon between it and a planar emitter): the visible
    // factor is F(emitter) − F(central projection of the obstruction onto the emitter's plane), both
    // by Howell B-3 corner decomposition; E = π L F_visible with L = 1. The obstruction is placed off
    // the mesh's symmetry lines, so its shadow cuts emitter patches and the error measures the
    // ray-estimated visible fractions.
    const double x0 = -0.2, x1 = 0.33, y0 = -0.17, y1 = 0.29;  // blocker at z = 1; shadow ×2 at z = 2
    json s = {{"name", "obstructed-emitter"}, {"spectrum", one_wavelength}, {"materials", {{"black", {{"reflectance", 0}}}}}};
    s["surfaces"] = {{{"name", "emitter"}, {"material", "black"}, {"polygon", rect({-1, -1, 2}, {0, 2, 0}, {2, 0, 0})},
                      {"emission", {{"radiance", 1.0}}}},
                     {{"name", "blocker"}, {"material", "black"}, {"polygon", rect({x0, y0, 1}, {0, y1 - y0, 0}, {x1 - x0, 0, 0})}}};
    s["probes"] = {{{"name", "p"}, {"position", {0, 0, 0}}, {"normal", {0, 0, 1}}}};
    const double visible = point_under_rectangle(0, 0, 2, -1, 1, -1, 1) -
                           point_under_rectangle(0, 0, 2, 2 * x0, 2 * x1, 2 * y0, 2 * y1);
    out.push_back({"obstructed-emitter", "probe E vs pi L F_visible (V9)", s, 4 + (x1 - x0) * (y1 - y0),
                   [visible](const Scene&, const Solution& sol, const Report&) {
                     return std::abs(sol.probes[0].irradiance[0] / (kPi * visible) - 1);
                   }, probe_max_estimate});
  }
  {
    // The issue-33 room with interreflection (every surface ρ = 0.5, a 1 m² panel with L = 1 in the
    // ceiling, 96 sensors 1 cm above the floor). No closed form: the reference is the dense method on
    // four times the finest rung's patches (edges half as long), so the error column is the rung's
    // error up to that reference's own, about a quarter to a half of it. Here the patches' error is
    // what is measured, and the estimate's bound is put to the test.
    const json s = panel_room("room-interreflection", 0.5, 12, 8);
    const double area = kPanelRoomArea;
    auto reference = std::make_shared<std::vector<double>>();
    out.push_back({"room-interreflection", "rms sensor E vs dense, 4x patches", s, area,
                   [s, area, reference](const Scene&, const Solution& sol, const Report&) {
                     if (reference->empty()) {
                       json fine = s;
                       fine["meshing"] = {{"max_patch_area", area / (4 * kRoomLadderTop)}};
                       fine["solver"] = {{"method", "dense"}};
                       const DecodeResult d = decode_scene(fine.dump(), FileAccess{FileAccess::Policy::Deny, {}, {}});
                       *reference = solve(*d.scene).probes.at(0).irradiance;
                     }
                     double sum = 0;
                     for (std::size_t q = 0; q < reference->size(); ++q) {
                       const double e = sol.probes[0].irradiance[q] / (*reference)[q] - 1;
                       sum += e * e;
                     }
                     return std::sqrt(sum / reference->size());
                   },
                   probe_rms_estimate, nullptr, kRoomLadderTop});
  }
  {
    // REFERENCES "the sphere interior": inside a sphere F_ij = A_j / A for any two patches, so with
    // ρ = 0.5 everywhere and a cap (z > 0.5) emitting M = 1, H = Φ / (A (1 − ρ)) on every patch, Φ
    // the cap's flux. The geodesic sphere's facets only approximate that, so the error measures
    // the tessellation: each ladder step tessellates the sphere more finely.
    auto make = [](double divisions) {
      const int n = std::max(2, static_cast<int>(std::lround(std::sqrt(divisions / 20))));
      const json mesh = inward_geodesic_sphere(n);
      json cap = {{"vertices", mesh["vertices"]}, {"triangles", json::array()}};
      json rest = cap;
      for (const auto& t : mesh["triangles"]) {
        double z = 0;
        for (int k = 0; k < 3; ++k) z += mesh["vertices"][t[k].get<int>()][2].get<double>() / 3;
        (z > 0.5 ? cap : rest)["triangles"].push_back(t);
      }
      json s = {{"name", "sphere-interior"},
                {"spectrum", {{"mode", "spectral"}, {"wavelengths_nm", {555}}}},
                {"materials", {{"grey", {{"reflectance", 0.5}}}}},
                {"meshing", {{"max_patch_area", 100.0}}}};  // the facets are the patches
      s["surfaces"] = {{{"name", "cap"}, {"material", "grey"}, {"mesh", cap}, {"emission", {{"exitance", 1.0}}}},
                       {{"name", "rest"}, {"material", "grey"}, {"mesh", rest}}};
      return s;
    };
    out.push_back({"sphere-interior", "max patch |H / H_sphere - 1|", json(), 0,
                   [](const Scene&, const Solution& sol, const Report&) {
                     double area = 0, flux = 0;
                     for (std::size_t i = 0; i < sol.patches.size(); ++i) {
                       area += sol.patches[i].area_m2;
                       flux += sol.patches[i].surface == 0 ? sol.patches[i].area_m2 : 0;
                     }
                     const double exact = flux / (area * (1 - 0.5));
                     double worst = 0;
                     for (double h : sol.irradiance) worst = std::max(worst, std::abs(h / exact - 1));
                     return worst;
                   },
                   nullptr, make});
  }
  return out;
}

// The scaling scene: a 20 × 10 × 3 m open-plan office (walls facing in) with a 10 × 5 grid of
// desk-sized closed boxes standing on the floor (their bottoms and the floor under them are contact
// area, removed before meshing), every surface ρ = 0.5 and M = 1, so that B = M/(1 − ρ) = 2 exactly
// on every patch (a furnace); solved by the hierarchical method at a ladder of patch counts.
struct ScalingScene {
  json scene;
  double total_area = 0;
};
ScalingScene office_furnace() {
  ScalingScene out;
  out.scene = {{"name", "office-furnace"},
               {"spectrum", {{"mode", "spectral"}, {"wavelengths_nm", {555}}}},
               {"materials", {{"grey", {{"reflectance", 0.5}}}}},
               {"solver", {{"method", "hierarchical"}}}};
  json surfaces = json::array();
  surfaces.push_back({{"name", "room"}, {"material", "grey"}, {"mesh", box({0, 0, 0}, {20, 10, 3}, true)},
                      {"emission", {{"exitance", 1.0}}}});
  out.total_area = 2 * (20 * 10 + 20 * 3 + 10 * 3);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 5; ++j) {
      const double x = 1 + 1.9 * i, y = 0.8 + 1.8 * j;
      surfaces.push_back({{"name", "desk-" + std::to_string(i) + "-" + std::to_string(j)},
                          {"material", "grey"},
                          {"mesh", box({x, y, 0}, {x + 1.6, y + 0.8, 0.75}, false)},
                          {"emission", {{"exitance", 1.0}}}});
      out.total_area += 2 * (1.6 * 0.75 + 0.8 * 0.75);  // sides; its top makes up for the floor it covers
    }
  out.scene["surfaces"] = surfaces;
  return out;
}

// `lambert bench --scaling MAX`: the office furnace at 10^3, 10^4, ... patches up to MAX.
int run_scaling(double max_patches, const std::string& json_path) {
  const ScalingScene office = office_furnace();
  std::printf("%-16s %9s %10s %11s %8s %8s %9s %12s %12s\n", "scene", "patches", "links", "rays", "time_s",
              "Mrays/s", "peak_MB", "closure_corr", "max|B/2-1|");
  json rows = json::array();
  for (double target = 1e3; target <= max_patches * (1 + 1e-9); target *= 10) {
    json scene = office.scene;
    scene["meshing"] = {{"max_patch_area", office.total_area / target}};
    const DecodeResult decoded = decode_scene(scene.dump(), FileAccess{FileAccess::Policy::Deny, {}, {}});
    if (!decoded.ok()) {
      std::cerr << "office-furnace: " << format_errors(decoded.errors);
      return 1;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const Solution sol = solve(*decoded.scene);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double worst = 0;
    for (double b : sol.radiosity) worst = std::max(worst, std::abs(b / 2 - 1));
    const double ray_seconds = sol.stats.time_form_factors_s + sol.stats.time_probes_s;
    const double mrays = ray_seconds > 0 ? sol.stats.rays / ray_seconds / 1e6 : 0;
    std::printf("%-16s %9zu %10zu %11llu %8.2f %8.1f %9.0f %12.2e %12.2e\n", "office-furnace", sol.stats.patches,
                sol.stats.links, static_cast<unsigned long long>(sol.stats.rays), seconds, mrays, peak_rss_mb(),
                sol.stats.max_closure_error, worst);
    std::fflush(stdout);
    rows.push_back({{"scene", "office-furnace"}, {"method", "hierarchical"}, {"patches", sol.stats.patches},
                    {"links", sol.stats.links}, {"rays", sol.stats.rays}, {"time_s", seconds},
                    {"form_factor_and_probe_Mrays_per_s", mrays}, {"peak_rss_mb", peak_rss_mb()},
                    {"closure_correction", sol.stats.max_closure_error}, {"max_error", worst}});
  }
  if (!json_path.empty()) std::ofstream(json_path) << json{{"lambert_bench_scaling", 1}, {"rows", rows}}.dump(1) << "\n";
  return 0;
}

// The cost of a visibility ray in the solver against Embree's raw stream throughput on the same
// occluders: the solver's link rays (sample points, kernel weights, rtcOccluded1M streams and the
// votes) per thread-second, and random segments between points of facing patches traced by
// Visibility::estimate_visible on a span (the fast BVH, rtcOccluded1M in streams of 256), one
// thread, median of 3: random pairs (incoherent) and rows (one patch to all others in order, as the
// solver traces: coherent), and the rows again in the watertight BVH (robust mode) that every other
// ray uses. The ratio is the solver's cost over the coherent raw cost.
json run_ray_cost() {
  struct RayCase { std::string name; json scene; };
  std::vector<RayCase> scenes;
  {
    json s = {{"name", "cube-room"}, {"spectrum", {{"mode", "spectral"}, {"wavelengths_nm", {555}}}},
              {"materials", {{"grey", {{"reflectance", 0.5}}}}}, {"solver", {{"method", "dense"}}},
              {"meshing", {{"max_patch_area", 2 * (24 + 18 + 12 + 6) / 3000.0}}}};
    s["surfaces"] = {{{"name", "room"}, {"material", "grey"}, {"mesh", box({0, 0, 0}, {6, 4, 3}, true)}},
                     {{"name", "cube"}, {"material", "grey"}, {"mesh", box({2.5, 1.5, 1}, {3.5, 2.5, 2}, false)}},
                     {{"name", "panel"}, {"material", "grey"}, {"polygon", rect({2.5, 1.5, 2.999}, {0, 1, 0}, {1, 0, 0})},
                      {"emission", {{"radiance", 1.0}}}}};
    scenes.push_back({"cube-room", s});
  }
  {
    const ScalingScene office = office_furnace();
    json s = office.scene;
    s["solver"] = {{"method", "dense"}};
    s["meshing"] = {{"max_patch_area", office.total_area / 3000}};
    scenes.push_back({"office-50-desks", s});
  }
  std::printf("\n%-18s %8s %11s %14s %14s %14s %15s %7s\n", "ray cost", "patches", "link_rays", "solver_ns/ray",
              "raw_random_ns", "raw_rows_ns", "watertight_ns", "ratio");
  json rows = json::array();
  for (const RayCase& c : scenes) {
    const DecodeResult decoded = decode_scene(c.scene.dump(), FileAccess{FileAccess::Policy::Deny, {}, {}});
    if (!decoded.ok()) throw std::runtime_error(c.name + ": " + format_errors(decoded.errors));
    const Solution sol = solve(*decoded.scene);
    const double solver_ns = sol.stats.link_rays > 0 ? 1e9 * sol.stats.dense.link_ray_thread_s / sol.stats.link_rays : 0;
    std::vector<Triangle> occluders;
    for (const Patch& p : sol.patches) occluders.push_back(p.triangle);
    const Visibility vis(occluders, Visibility::Estimates::fast);  // as the solver traces link rays
    std::mt19937 rng(1);
    std::uniform_int_distribution<std::size_t> pick(0, sol.patches.size() - 1);
    std::uniform_int_distribution<int> sample(0, kMaxVisibilitySamples - 1);
    std::vector<Segment> segments;
    while (segments.size() < 2'000'000) {
      const Patch& a = sol.patches[pick(rng)];
      const Patch& b = sol.patches[pick(rng)];
      const Point3 p = vis.lift(visibility_sample(a.triangle, sample(rng)), a.normal);
      const Point3 q = vis.lift(visibility_sample(b.triangle, sample(rng)), b.normal);
      if (dot(q - p, a.normal) > 0 && dot(p - q, b.normal) > 0) segments.push_back({p, q});
    }
    // Coherent: one shooter patch to every facing patch in mesh order (the solver's row pattern).
    std::vector<Segment> rows_of_rays;
    while (rows_of_rays.size() < 2'000'000) {
      const Patch& a = sol.patches[pick(rng)];
      for (const Patch& b : sol.patches) {
        const Point3 p = vis.lift(visibility_sample(a.triangle, sample(rng)), a.normal);
        const Point3 q = vis.lift(visibility_sample(b.triangle, sample(rng)), b.normal);
        if (dot(q - p, a.normal) > 0 && dot(p - q, b.normal) > 0) rows_of_rays.push_back({p, q});
      }
    }
    auto raw_ns = [&](const std::vector<Segment>& rays, bool watertight = false) {
      std::vector<std::uint8_t> visible(rays.size());
      std::vector<double> runs;
      for (int r = 0; r < 3; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        watertight ? vis.visible(rays, visible) : vis.estimate_visible(rays, visible);
        runs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(runs.begin(), runs.end());
      return 1e9 * runs[1] / rays.size();
    };
    const double random_ns = raw_ns(segments), coherent_ns = raw_ns(rows_of_rays);
    const double watertight_ns = raw_ns(rows_of_rays, true);
    const double ratio = coherent_ns > 0 ? solver_ns / coherent_ns : 0;
    std::printf("%-18s %8zu %11llu %14.1f %14.1f %14.1f %15.1f %7.2f\n", c.name.c_str(), sol.stats.patches,
                static_cast<unsigned long long>(sol.stats.link_rays), solver_ns, random_ns, coherent_ns,
                watertight_ns, ratio);
    std::fflush(stdout);
    rows.push_back({{"scene", c.name}, {"patches", sol.stats.patches}, {"link_rays", sol.stats.link_rays},
                    {"solver_ns_per_ray_per_thread", solver_ns}, {"embree_random_ns_per_ray_one_thread", random_ns},
                    {"embree_coherent_ns_per_ray_one_thread", coherent_ns},
                    {"embree_coherent_watertight_ns_per_ray_one_thread", watertight_ns}, {"ratio_to_coherent", ratio}});
  }
  return rows;
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux: kilobytes
}

struct BenchArgs {
  std::string json_path, plot_path;
  bool quick = false;
  std::optional<double> scaling_max;  // the largest patch count of a scaling run
};

int run_bench(const BenchArgs& args) {
  const std::string& json_path = args.json_path;
  const std::string& plot_path = args.plot_path;
  std::vector<double> ladder = {150, 300, 600, 1200, 2400};  // patches ≈ total area / max_patch_area
  if (args.quick) ladder = {150, 600};
  if (args.scaling_max) return run_scaling(*args.scaling_max, json_path);
  // estimate: stats.error_estimate for the same measure (error_estimate.h), its coarser solve not
  // counted in time_s; "bound" says whether it is at least the error (bound_verdict).
  std::printf("%-26s %-32s %9s %8s %10s %8s %9s %9s %10s %10s %6s\n", "scene", "error measure", "patches", "time_s",
              "rays", "Mrays/s", "peak_MB", "systems", "error", "estimate", "bound");
  json rows = json::array();
  std::vector<PlotSeries> series;
  for (const Case& c : cases()) {
    series.push_back({c.name, {}});
    for (double divisions : ladder) {
      if (divisions > c.max_divisions) continue;
      json scene = c.make_scene ? c.make_scene(divisions) : c.scene;
      if (!c.make_scene) scene["meshing"] = {{"max_patch_area", c.total_area / divisions}};
      if (c.estimate) scene["output"] = {{"error_estimate", true}};
      const DecodeResult decoded = decode_scene(scene.dump(), FileAccess{FileAccess::Policy::Deny, {}, {}});
      if (!decoded.ok()) {
        std::cerr << c.name << ": " << format_errors(decoded.errors);
        return 1;
      }
      const auto t0 = std::chrono::steady_clock::now();
      const Solution sol = solve(*decoded.scene);
      const double estimate_s = sol.stats.error_estimate ? sol.stats.error_estimate->time_s : 0.0;
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() - estimate_s;
      const Report report = make_report(*decoded.scene, sol);
      const double error = c.error(*decoded.scene, sol, report);
      const std::optional<double> estimate =
          c.estimate && sol.stats.error_estimate ? std::optional(c.estimate(*sol.stats.error_estimate)) : std::nullopt;
      const double ray_seconds = sol.stats.time_form_factors_s + sol.stats.time_probes_s;
      const double mrays = ray_seconds > 0 ? sol.stats.rays / ray_seconds / 1e6 : 0;
      json estimate_json = nullptr;  // built apart: GCC 12 misreads the optional in a conditional
      if (estimate) estimate_json = *estimate;
      char estimate_text[32] = "-";
      if (estimate) std::snprintf(estimate_text, sizeof estimate_text, "%.2e", *estimate);
      std::printf("%-26s %-32s %9zu %8.3f %10llu %8.1f %9.0f %9d %10.2e %10s %6s\n", c.name.c_str(), c.what.c_str(),
                  sol.stats.patches, seconds, static_cast<unsigned long long>(sol.stats.rays), mrays, peak_rss_mb(),
                  sol.stats.spectral_systems_solved, error, estimate_text, bound_verdict(error, estimate));
      std::fflush(stdout);
      rows.push_back({{"scene", c.name}, {"error_measure", c.what}, {"max_patch_area_m2", sol.stats.max_patch_area_m2},
                      {"patches", sol.stats.patches}, {"time_s", seconds}, {"rays", sol.stats.rays},
                      {"form_factor_and_probe_Mrays_per_s", mrays}, {"peak_rss_mb", peak_rss_mb()},
                      {"error", error}, {"error_estimate", estimate_json}});
      series.back().points.push_back({seconds, error});
    }
  }
  json ray_cost;
  try {
    ray_cost = run_ray_cost();
  } catch (const std::runtime_error& e) {
    std::cerr << "lambert bench: " << e.what() << "\n";
    return 1;
  }
  if (!json_path.empty()) {
    std::ofstream(json_path) << json{{"lambert_bench", 1}, {"rows", rows}, {"ray_cost", ray_cost}}.dump(1) << "\n";
  }
  if (!plot_path.empty()) {
    try {
      plot_speed_against_error(series, plot_path);
    } catch (const std::runtime_error& e) {
      std::cerr << "lambert bench: " << e.what() << "\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace

cli::CommandSpec command_bench() {
  return {"bench", "speed against error on built-in reference scenes with exact answers", [](cli::Options& o) {
            auto args = std::make_shared<BenchArgs>();
            o.output(args->json_path, "write the table (or the scaling run) as JSON");
            const cli::Option plot = o.text("--plot", args->plot_path, "draw time against error into this PNG", "FILE");
            const cli::Option quick = o.flag("--quick", args->quick, "two patch sizes per scene instead of five");
            o.number("--scaling", args->scaling_max, 1e3, 2e6,
                     "instead: time and memory from 10^3 patches up to this many")
                .excludes(plot)
                .excludes(quick);
            return [args] { return run_bench(*args); };
          }};
}

int run_bench(const std::vector<std::string>& args) { return cli::run_one(command_bench(), args); }

}  // namespace lambert
