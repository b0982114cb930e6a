// Photometric and colour values derived from a spectral Solution, computed once at the end
// (SPEC: compute radiometrically, convert at the end). Shared by the JSON codec and the CLI summary.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "solver/daylight_report.h"
#include "solver/radiosity.h"

namespace lambert {

// CIE S 026 melanopic irradiance and melanopic equivalent daylight (D65) illuminance.
struct Melanopic {
  double irradiance_W_m2 = 0;      // E_mel = ∫ H s_mel dλ
  double edi_lx = 0;               // E_mel / K_mel,v^D65
};

// In rgb mode (Scene::mode == Rgb) the photometric and colour values come from the three channels
// through the inverse EBU matrix (solver/rgb_model.h), and the melanopic values are absent: a
// three-sample solution does not determine them.
struct PatchPhotometry {
  double illuminance_lx = 0;       // 683 ∫ H ȳ dλ
  double luminance_cd_m2 = 0;      // 683 ∫ (B/π) ȳ dλ
  Xyz xyz{};                       // of the radiance B/π (Y = luminance)
  std::array<double, 2> xy{};      // chromaticity
  std::array<double, 3> rgb_ebu{}; // linear, same absolute scale as XYZ
  std::array<double, 3> srgb{};    // linear, same absolute scale as XYZ
  std::array<double, 3> srgb_encoded{};  // display values in [0,1], white = brightest reflector
  std::optional<Melanopic> melanopic;    // of the irradiance H; absent in rgb mode
};

struct SurfaceSummary {
  std::string name;
  double area_m2 = 0;
  double illuminance_mean_lx = 0, illuminance_min_lx = 0, illuminance_max_lx = 0;  // area-weighted mean
  double luminance_mean_cd_m2 = 0;
  std::optional<Melanopic> melanopic_mean;  // area-weighted; absent in rgb mode
  std::vector<double> radiosity_mean;   // area-weighted, W m^-2 nm^-1
  std::vector<double> irradiance_mean;  // area-weighted, W m^-2 nm^-1
};

struct ProbeSummary {
  std::vector<double> illuminance_lx;   // per point
  std::vector<Melanopic> melanopic;     // per point; empty in rgb mode
  double min_lx = 0, mean_lx = 0, max_lx = 0;
  double min_over_mean = 0, min_over_max = 0;  // uniformities (0 when the mean or max is 0)
};

// Photometry of one source's contribution (Solution::contributions), parallel to it.
struct SourceReport {
  std::vector<double> patch_illuminance_lx, patch_luminance_cd_m2;  // per patch
  std::vector<std::vector<double>> probe_illuminance_lx;             // per probe, per point
};

struct Report {
  std::vector<PatchPhotometry> patches;
  std::vector<SurfaceSummary> surfaces;
  std::vector<ProbeSummary> probes;
  std::vector<SourceReport> sources;
  std::optional<DaylightReport> daylight;  // skies, suns and the probes' daylight metrics, if any
};

Report make_report(const Scene& scene, const Solution& solution);

}  // namespace lambert
