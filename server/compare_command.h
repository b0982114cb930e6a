// `lambert compare-rgb SCENE.json [-o REPORT.json]`: the price of the three-sample RGB model. Solves a
// spectral scene as given and the same scene in rgb mode (solver/rgb_model.h), and compares them patch
// by patch: the CIEDE2000 colour difference of the patches' radiance and the relative difference of
// their illuminance, with summary statistics. Deterministic: no clock readings in the report.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "server/scene_codec.h"
#include "solver/colour_difference.h"
#include "solver/radiosity.h"

namespace lambert {

struct PatchComparison {
  std::size_t id = 0;                 // patch index (the same mesh in both solves)
  int surface = 0;                    // index into Scene::surfaces
  bool emitter = false;               // on an emitting surface: listed, but not in the statistics
  double area_m2 = 0;
  Lab lab_spectral{}, lab_rgb{};      // of the patch radiance, relative to RgbComparison::white
  double delta_e00 = 0;
  double illuminance_spectral_lx = 0, illuminance_rgb_lx = 0;
  // (E_rgb − E_spectral) / E_spectral; absent where E_spectral is 0 (below 1e-9 of the largest).
  std::optional<double> illuminance_relative_difference;
};

struct Statistics {
  std::size_t count = 0;
  double mean = 0, median = 0, p95 = 0, max = 0;  // p95: nearest rank, the ⌈0.95 n⌉-th smallest
};

struct SurfaceComparison {
  std::string name;
  double area_m2 = 0;
  double delta_e00_mean = 0, delta_e00_max = 0;     // area-weighted mean over the surface's patches
  double illuminance_spectral_lx = 0, illuminance_rgb_lx = 0;  // area-weighted means
  Lab lab_spectral{}, lab_rgb{};    // of the area-weighted mean radiance
};

struct RgbComparison {
  std::string name;
  std::size_t white_patch = 0;      // the brightest non-emitting patch of the spectral solution
  Xyz white{};                      // its luminance, with the D65 chromaticity (0.3127, 0.3290)
  std::vector<PatchComparison> patches;
  std::vector<SurfaceComparison> surfaces;
  Statistics delta_e00;             // over the non-emitting patches
  Statistics illuminance_relative;  // of |E_rgb − E_spectral| / E_spectral, same patches where defined
  double illuminance_relative_signed_mean = 0;
  std::vector<std::size_t> worst;   // up to 10 patch ids, largest ΔE00 first (ties: smaller id first)
  std::size_t wavelengths = 0, systems_spectral = 0, systems_rgb = 0;
  double time_spectral_s = 0, time_rgb_s = 0;  // wall clock; reported in the text only
  std::vector<std::string> warnings_spectral, warnings_rgb;
};

// The same scene document decoded in rgb mode: its "spectrum" section replaced by {"mode": "rgb"}.
DecodeResult decode_scene_as_rgb(const std::string& json_text, const FileAccess& files = {});

// Solves both scenes (the spectral one and its rgb twin) and compares them. Throws SolveError when a
// solve fails or the solution has no lit reflecting patch to take as the white, std::invalid_argument
// when the scenes do not mesh alike or `spectral` is not in spectral mode.
RgbComparison compare_rgb(const Scene& spectral, const Scene& rgb, const SolveControl& control = {});

std::string encode_comparison(const Scene& spectral, const RgbComparison& comparison, int indent = 2);
std::string summarize_comparison(const Scene& spectral, const RgbComparison& comparison);

// The command: args after "compare-rgb". Exit status as in SPEC §3.
int run_compare_rgb(const std::vector<std::string>& args);

}  // namespace lambert
