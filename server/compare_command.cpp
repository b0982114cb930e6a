// `lambert compare-rgb` (see compare_command.h). The comparison works on the photometric report of
// each solve (solver/report.h): spectral integrals on one side, the inverse EBU matrix on the other.
#include "server/compare_command.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "server/cli_common.h"
#include "server/cli_parser.h"
#include "server/cli_progress.h"
#include "solver/report.h"
#include "solver/rgb_model.h"
#include "solver/stopwatch.h"

namespace lambert {
namespace {

using nlohmann::json;

// The chromaticity of the CIELAB reference white: D65 as the RGB standards state it, the white of the
// EBU matrix both solves are displayed with.
constexpr double kWhite_x = 0.3127, kWhite_y = 0.3290;
// Illuminance below this fraction of the largest patch illuminance counts as unlit: no relative
// difference is defined there.
constexpr double kUnlitFraction = 1e-9;
constexpr std::size_t kWorstListed = 10;

Statistics statistics(std::vector<double> values) {
  Statistics s;
  s.count = values.size();
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  s.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(n);
  s.median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  const auto rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(n)));
  s.p95 = values[std::max<std::size_t>(rank, 1) - 1];
  s.max = values.back();
  return s;
}

bool same_triangle(const Triangle& a, const Triangle& b) {
  for (int k = 0; k < 3; ++k)
    if (a.v[k].x != b.v[k].x || a.v[k].y != b.v[k].y || a.v[k].z != b.v[k].z) return false;
  return true;
}

json lab_json(const Lab& c) { return json::array({c.L, c.a, c.b}); }

json statistics_json(const Statistics& s) {
  return {{"count", s.count}, {"mean", s.mean}, {"median", s.median}, {"p95", s.p95}, {"max", s.max}};
}

}  // namespace

DecodeResult decode_scene_as_rgb(const std::string& json_text, const FileAccess& files) {
  json doc = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  // Text that is not a JSON object: let the decoder report it, exactly as for the spectral scene.
  if (doc.is_discarded() || !doc.is_object()) return decode_scene(json_text, files);
  doc["spectrum"] = {{"mode", "rgb"}};
  return decode_scene(doc.dump(), files);
}

RgbComparison compare_rgb(const Scene& spectral, const Scene& rgb, const SolveControl& control) {
  if (spectral.mode != SpectrumMode::Spectral)
    throw std::invalid_argument("compare_rgb: the first scene must be in spectral mode");
  if (rgb.mode != SpectrumMode::Rgb)
    throw std::invalid_argument("compare_rgb: the second scene must be in rgb mode");

  RgbComparison out;
  out.name = spectral.name;
  auto t0 = std::chrono::steady_clock::now();
  const Solution sol_s = solve(spectral, control);
  out.time_spectral_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  const Solution sol_r = solve(rgb, control);
  out.time_rgb_s = seconds_since(t0);
  const Report rep_s = make_report(spectral, sol_s), rep_r = make_report(rgb, sol_r);
  out.wavelengths = sol_s.wavelengths();
  out.systems_spectral = static_cast<std::size_t>(sol_s.stats.spectral_systems_solved);
  out.systems_rgb = static_cast<std::size_t>(sol_r.stats.spectral_systems_solved);
  out.warnings_spectral = sol_s.warnings;
  out.warnings_rgb = sol_r.warnings;

  const std::size_t N = sol_s.patches.size();
  if (sol_r.patches.size() != N)
    throw std::invalid_argument("compare_rgb: the spectral solve has " + std::to_string(N) +
                                " patches, the rgb solve " + std::to_string(sol_r.patches.size()));
  for (std::size_t i = 0; i < N; ++i)
    if (sol_s.patches[i].surface != sol_r.patches[i].surface ||
        !same_triangle(sol_s.patches[i].triangle, sol_r.patches[i].triangle))
      throw std::invalid_argument("compare_rgb: patch " + std::to_string(i) + " differs between the solves");

  // The CIELAB white: the brightest reflecting (non-emitting) patch of the spectral solution, at its
  // luminance, with the D65 chromaticity. The same white for both solutions, so that a difference in
  // brightness shows as a difference in L*.
  auto is_emitter = [&](std::size_t i) { return spectral.surfaces[sol_s.patches[i].surface].emission.has_value(); };
  double white_Y = 0;
  for (std::size_t i = 0; i < N; ++i)
    if (!is_emitter(i) && rep_s.patches[i].xyz.Y > white_Y) {
      white_Y = rep_s.patches[i].xyz.Y;
      out.white_patch = i;
    }
  if (!(white_Y > 0)) throw SolveError("compare-rgb: no reflecting patch receives light; nothing to compare");
  out.white = white_from_chromaticity(white_Y, kWhite_x, kWhite_y);

  double max_E = 0;
  for (const PatchPhotometry& p : rep_s.patches) max_E = std::max(max_E, p.illuminance_lx);
  std::vector<double> delta_e, relative_abs;
  double relative_sum = 0;
  out.patches.resize(N);
  for (std::size_t i = 0; i < N; ++i) {
    PatchComparison& c = out.patches[i];
    c.id = i;
    c.surface = sol_s.patches[i].surface;
    c.emitter = is_emitter(i);
    c.area_m2 = sol_s.patches[i].area_m2;
    c.lab_spectral = cielab(rep_s.patches[i].xyz, out.white);
    c.lab_rgb = cielab(rep_r.patches[i].xyz, out.white);
    c.delta_e00 = ciede2000(c.lab_spectral, c.lab_rgb);
    c.illuminance_spectral_lx = rep_s.patches[i].illuminance_lx;
    c.illuminance_rgb_lx = rep_r.patches[i].illuminance_lx;
    if (c.illuminance_spectral_lx > kUnlitFraction * max_E)
      c.illuminance_relative_difference = (c.illuminance_rgb_lx - c.illuminance_spectral_lx) / c.illuminance_spectral_lx;
    if (c.emitter) continue;
    delta_e.push_back(c.delta_e00);
    if (c.illuminance_relative_difference) {
      relative_abs.push_back(std::abs(*c.illuminance_relative_difference));
      relative_sum += *c.illuminance_relative_difference;
    }
  }
  out.delta_e00 = statistics(delta_e);
  out.illuminance_relative = statistics(relative_abs);
  out.illuminance_relative_signed_mean = relative_abs.empty() ? 0 : relative_sum / static_cast<double>(relative_abs.size());

  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < N; ++i)
    if (!out.patches[i].emitter) order.push_back(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return out.patches[a].delta_e00 > out.patches[b].delta_e00; });
  order.resize(std::min(order.size(), kWorstListed));
  out.worst = order;

  // Per surface: area-weighted means, and the colour of the mean radiance.
  out.surfaces.resize(spectral.surfaces.size());
  std::vector<Xyz> sum_s(out.surfaces.size(), Xyz{0, 0, 0}), sum_r(out.surfaces.size(), Xyz{0, 0, 0});
  for (std::size_t s = 0; s < out.surfaces.size(); ++s) out.surfaces[s].name = spectral.surfaces[s].name;
  for (const PatchComparison& c : out.patches) {
    SurfaceComparison& s = out.surfaces[c.surface];
    const double A = c.area_m2;
    s.area_m2 += A;
    s.delta_e00_mean += A * c.delta_e00;
    s.delta_e00_max = std::max(s.delta_e00_max, c.delta_e00);
    s.illuminance_spectral_lx += A * c.illuminance_spectral_lx;
    s.illuminance_rgb_lx += A * c.illuminance_rgb_lx;
    const Xyz& xs = rep_s.patches[c.id].xyz;
    const Xyz& xr = rep_r.patches[c.id].xyz;
    sum_s[c.surface] = {sum_s[c.surface].X + A * xs.X, sum_s[c.surface].Y + A * xs.Y, sum_s[c.surface].Z + A * xs.Z};
    sum_r[c.surface] = {sum_r[c.surface].X + A * xr.X, sum_r[c.surface].Y + A * xr.Y, sum_r[c.surface].Z + A * xr.Z};
  }
  for (std::size_t k = 0; k < out.surfaces.size(); ++k) {
    SurfaceComparison& s = out.surfaces[k];
    if (!(s.area_m2 > 0)) continue;
    const double a = 1 / s.area_m2;
    s.delta_e00_mean *= a;
    s.illuminance_spectral_lx *= a;
    s.illuminance_rgb_lx *= a;
    s.lab_spectral = cielab({sum_s[k].X * a, sum_s[k].Y * a, sum_s[k].Z * a}, out.white);
    s.lab_rgb = cielab({sum_r[k].X * a, sum_r[k].Y * a, sum_r[k].Z * a}, out.white);
  }
  return out;
}

std::string encode_comparison(const Scene& spectral, const RgbComparison& c, int indent) {
  json out;
  out["lambert"] = 1;
  out["report"] = "compare-rgb";
  out["name"] = c.name;
  out["method"] = {
      {"colour_difference", "CIEDE2000 (kL = kC = kH = 1) of the patch radiance"},
      {"cielab_white", "the brightest non-emitting patch of the spectral solution, at its luminance, "
                       "with chromaticity x = 0.3127, y = 0.3290"},
      {"illuminance_difference", "(E_rgb - E_spectral) / E_spectral; statistics of its absolute value"},
      {"statistics_over", "non-emitting patches, unweighted; p95 by nearest rank"}};
  out["white"] = {{"patch", c.white_patch},
                  {"surface", spectral.surfaces[c.patches.at(c.white_patch).surface].name},
                  {"xyz", json::array({c.white.X, c.white.Y, c.white.Z})}};
  out["solves"] = {{"spectral", {{"wavelengths", c.wavelengths}, {"systems_solved", c.systems_spectral}}},
                   {"rgb", {{"channels", json::array({"R", "G", "B"})}, {"systems_solved", c.systems_rgb}}}};
  out["summary"] = {{"patches", c.patches.size()},
                    {"delta_e00", statistics_json(c.delta_e00)},
                    {"illuminance_relative_difference", statistics_json(c.illuminance_relative)},
                    {"illuminance_relative_difference_signed_mean", c.illuminance_relative_signed_mean}};
  auto patch_json = [&](const PatchComparison& p) {
    json j = {{"id", p.id},
              {"surface", spectral.surfaces[p.surface].name},
              {"emitter", p.emitter},
              {"area", p.area_m2},
              {"lab_spectral", lab_json(p.lab_spectral)},
              {"lab_rgb", lab_json(p.lab_rgb)},
              {"delta_e00", p.delta_e00},
              {"illuminance_spectral_lx", p.illuminance_spectral_lx},
              {"illuminance_rgb_lx", p.illuminance_rgb_lx}};
    j["illuminance_relative_difference"] =
        p.illuminance_relative_difference ? json(*p.illuminance_relative_difference) : json(nullptr);
    return j;
  };
  json worst = json::array();
  for (std::size_t id : c.worst) worst.push_back(patch_json(c.patches[id]));
  out["worst_patches"] = std::move(worst);
  json surfaces = json::array();
  for (const SurfaceComparison& s : c.surfaces) {
    surfaces.push_back({{"name", s.name},
                        {"area", s.area_m2},
                        {"delta_e00_mean", s.delta_e00_mean},
                        {"delta_e00_max", s.delta_e00_max},
                        {"illuminance_spectral_lx", s.illuminance_spectral_lx},
                        {"illuminance_rgb_lx", s.illuminance_rgb_lx},
                        {"lab_spectral", lab_json(s.lab_spectral)},
                        {"lab_rgb", lab_json(s.lab_rgb)}});
  }
  out["surfaces"] = std::move(surfaces);
  json patches = json::array();
  for (const PatchComparison& p : c.patches) patches.push_back(patch_json(p));
  out["patches"] = std::move(patches);
  out["warnings"] = {{"spectral", c.warnings_spectral}, {"rgb", c.warnings_rgb}};
  return out.dump(indent);
}

std::string summarize_comparison(const Scene& spectral, const RgbComparison& c) {
  std::string s;
  char line[512];
  std::size_t emitters = 0;
  for (const PatchComparison& p : c.patches) emitters += p.emitter;
  std::snprintf(line, sizeof line, "compare-rgb %s: %zu patches (%zu emitting, not in the statistics)\n",
                c.name.empty() ? "scene" : c.name.c_str(), c.patches.size(), emitters);
  s += line;
  std::snprintf(line, sizeof line,
                "spectral: %zu wavelengths, %zu systems solved; rgb: 3 channels, %zu systems solved\n",
                c.wavelengths, c.systems_spectral, c.systems_rgb);
  s += line;
  std::snprintf(line, sizeof line, "CIELAB white: Y = %.6g cd/m2 (patch %zu on %s), x = %.4f, y = %.4f\n\n",
                c.white.Y, c.white_patch, spectral.surfaces[c.patches.at(c.white_patch).surface].name.c_str(),
                kWhite_x, kWhite_y);
  s += line;
  s += "                                   mean    median       p95       max\n";
  std::snprintf(line, sizeof line, "  dE00                        %9.4f %9.4f %9.4f %9.4f\n", c.delta_e00.mean,
                c.delta_e00.median, c.delta_e00.p95, c.delta_e00.max);
  s += line;
  std::snprintf(line, sizeof line, "  |E_rgb - E_spec| / E_spec %%  %9.4f %9.4f %9.4f %9.4f   (signed mean %+.4f %%)\n",
                100 * c.illuminance_relative.mean, 100 * c.illuminance_relative.median,
                100 * c.illuminance_relative.p95, 100 * c.illuminance_relative.max,
                100 * c.illuminance_relative_signed_mean);
  s += line;
  s += "\nper surface (area-weighted means; L*a*b* of the mean radiance):\n";
  std::snprintf(line, sizeof line, "  %-20s %8s %8s %12s %12s %8s   %-24s %-24s\n", "surface", "dE00", "max",
                "E_spec lx", "E_rgb lx", "dE/E %", "L*a*b* spectral", "L*a*b* rgb");
  s += line;
  for (const SurfaceComparison& sc : c.surfaces) {
    const double rel = sc.illuminance_spectral_lx > 0
                           ? 100 * (sc.illuminance_rgb_lx - sc.illuminance_spectral_lx) / sc.illuminance_spectral_lx
                           : 0;
    char lab_s[64], lab_r[64];
    std::snprintf(lab_s, sizeof lab_s, "(%.2f, %.2f, %.2f)", sc.lab_spectral.L, sc.lab_spectral.a, sc.lab_spectral.b);
    std::snprintf(lab_r, sizeof lab_r, "(%.2f, %.2f, %.2f)", sc.lab_rgb.L, sc.lab_rgb.a, sc.lab_rgb.b);
    std::snprintf(line, sizeof line, "  %-20s %8.4f %8.4f %12.4f %12.4f %+8.3f   %-24s %-24s\n", sc.name.c_str(),
                  sc.delta_e00_mean, sc.delta_e00_max, sc.illuminance_spectral_lx, sc.illuminance_rgb_lx, rel,
                  lab_s, lab_r);
    s += line;
  }
  s += "\nworst patches:\n";
  for (std::size_t id : c.worst) {
    const PatchComparison& p = c.patches[id];
    char rel[32] = "-";
    if (p.illuminance_relative_difference)
      std::snprintf(rel, sizeof rel, "%+.3f %%", 100 * *p.illuminance_relative_difference);
    std::snprintf(line, sizeof line, "  patch %6zu  %-20s dE00 %8.4f  illuminance %s\n", p.id,
                  spectral.surfaces[p.surface].name.c_str(), p.delta_e00, rel);
    s += line;
  }
  for (const std::string& w : c.warnings_rgb) s += "warning (rgb): " + w + "\n";
  for (const std::string& w : c.warnings_spectral) s += "warning (spectral): " + w + "\n";
  return s;
}

namespace {

struct CompareArgs {
  std::string scene_path, output_path;
};

int run_compare(const CompareArgs& args) {
  const std::string& scene_path = args.scene_path;
  const std::string& output_path = args.output_path;
  std::string text;
  if (!read_text_file(scene_path, text)) {
    std::cerr << "lambert compare-rgb: cannot read " << scene_path << "\n";
    return 2;
  }
  const std::optional<Scene> spectral = decode_scene_file(scene_path, text);
  if (!spectral) return 2;
  if (spectral->mode != SpectrumMode::Spectral) {
    std::cerr << scene_path << ": /spectrum/mode: compare-rgb needs a spectral scene (it makes the rgb twin itself)\n";
    return 2;
  }
  DecodeResult rgb = decode_scene_as_rgb(text, command_line_file_access(scene_path));
  if (!rgb.ok()) {
    std::cerr << scene_path << ": invalid in rgb mode\n" << format_errors(rgb);
    return 2;
  }

  SolveControl control;
  show_progress_on_terminal(control);
  try {
    const RgbComparison comparison = compare_rgb(*spectral, *rgb.scene, control);
    std::cout << summarize_comparison(*spectral, comparison);
    std::printf("time: spectral solve %.3f s, rgb solve %.3f s (wall clock; varies between runs)\n",
                comparison.time_spectral_s, comparison.time_rgb_s);
    std::fflush(stdout);
    if (!output_path.empty()) {
      if (!write_text_file("compare-rgb", output_path, encode_comparison(*spectral, comparison) + "\n")) return 1;
      std::cout << "report written to " << output_path << "\n";
    }
  } catch (const SolveError& e) {
    std::cerr << "lambert compare-rgb: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "lambert compare-rgb: failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

cli::CommandSpec command_compare_rgb() {
  return {"compare-rgb", "the price of the three-sample RGB model: per-patch dE00 and lux against spectral",
          [](cli::Options& o) {
            auto args = std::make_shared<CompareArgs>();
            o.input("SCENE.json", args->scene_path, "a spectral scene; its rgb twin is made from it");
            o.output(args->output_path, "also write the comparison as JSON");
            o.footer("Solves the scene as given and again in rgb mode, and reports per patch the CIEDE2000\n"
                     "colour difference and the relative illuminance difference (summary on stdout).");
            return [args] { return run_compare(*args); };
          }};
}

int run_compare_rgb(const std::vector<std::string>& args) { return cli::run_one(command_compare_rgb(), args); }

}  // namespace lambert
