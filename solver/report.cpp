// Photometry and colour of a solution (see report.h).
#include "solver/report.h"

#include <algorithm>
#include <limits>

#include "solver/rgb_model.h"

namespace lambert {
namespace {

// The photometric end of the pipeline, by spectrum mode: spectral integrals against the CIE tables,
// or, in rgb mode, the inverse EBU matrix applied to the three channel values.
struct Photometer {
  const WavelengthGrid& grid;
  bool rgb;
  std::array<double, 3> channels(const std::vector<double>& s) const { return {s[0], s[1], s[2]}; }
  Xyz xyz(const std::vector<double>& s) const {
    return rgb ? xyz_from_rgb_channels(channels(s)) : tristimulus(s, grid);
  }
  double luminous(const std::vector<double>& s) const {
    return rgb ? xyz_from_rgb_channels(channels(s)).Y : luminous_integral(s, grid);
  }
  std::optional<Melanopic> melanopic(const std::vector<double>& E) const {
    if (rgb) return std::nullopt;
    const double E_mel = melanopic_integral(E, grid);
    return Melanopic{E_mel, melanopic_edi_lx(E_mel)};
  }
};

}  // namespace

Report make_report(const Scene& scene, const Solution& sol) {
  Report report;
  const std::size_t N = sol.patches.size(), W = sol.wavelengths();
  const WavelengthGrid& grid = sol.grid;
  const Photometer photometer{grid, scene.mode == SpectrumMode::Rgb};
  report.patches.resize(N);
  double white_Y = 0;  // display white: the brightest patch that does not emit
  std::vector<double> B(W), H(W), L(W);
  for (std::size_t i = 0; i < N; ++i) {
    PatchPhotometry& p = report.patches[i];
    for (std::size_t w = 0; w < W; ++w) {
      H[w] = sol.irradiance[i * W + w];
      L[w] = sol.radiosity[i * W + w] / kPi;  // Lambertian: L = B / (π ω0)
    }
    p.illuminance_lx = photometer.luminous(H);
    p.melanopic = photometer.melanopic(H);
    p.xyz = photometer.xyz(L);
    p.luminance_cd_m2 = p.xyz.Y;
    p.xy = chromaticity_xy(p.xyz);
    p.rgb_ebu = xyz_to_linear_ebu_rgb(p.xyz);
    p.srgb = xyz_to_linear_srgb(p.xyz);
    if (!scene.surfaces[sol.patches[i].surface].emission) white_Y = std::max(white_Y, p.xyz.Y);
  }
  for (PatchPhotometry& p : report.patches) {
    const double scale = white_Y > 0 ? 1 / white_Y : 0;
    for (int c = 0; c < 3; ++c) p.srgb_encoded[c] = srgb_encode(p.srgb[c] * scale);
  }

  report.surfaces.resize(scene.surfaces.size());
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    SurfaceSummary& out = report.surfaces[s];
    out.name = scene.surfaces[s].name;
    out.radiosity_mean.assign(W, 0.0);
    out.irradiance_mean.assign(W, 0.0);
    out.illuminance_min_lx = std::numeric_limits<double>::infinity();
    out.illuminance_max_lx = -std::numeric_limits<double>::infinity();
  }
  for (std::size_t i = 0; i < N; ++i) {
    SurfaceSummary& out = report.surfaces[sol.patches[i].surface];
    const double A = sol.patches[i].area_m2;
    const PatchPhotometry& p = report.patches[i];
    out.area_m2 += A;
    out.illuminance_mean_lx += A * p.illuminance_lx;
    out.luminance_mean_cd_m2 += A * p.luminance_cd_m2;
    if (p.melanopic) {
      if (!out.melanopic_mean) out.melanopic_mean = Melanopic{};
      out.melanopic_mean->irradiance_W_m2 += A * p.melanopic->irradiance_W_m2;
      out.melanopic_mean->edi_lx += A * p.melanopic->edi_lx;
    }
    out.illuminance_min_lx = std::min(out.illuminance_min_lx, p.illuminance_lx);
    out.illuminance_max_lx = std::max(out.illuminance_max_lx, p.illuminance_lx);
    for (std::size_t w = 0; w < W; ++w) {
      out.radiosity_mean[w] += A * sol.radiosity[i * W + w];
      out.irradiance_mean[w] += A * sol.irradiance[i * W + w];
    }
  }
  for (SurfaceSummary& out : report.surfaces) {
    if (out.area_m2 <= 0) {
      out.illuminance_min_lx = out.illuminance_max_lx = 0;
      continue;
    }
    out.illuminance_mean_lx /= out.area_m2;
    out.luminance_mean_cd_m2 /= out.area_m2;
    if (out.melanopic_mean) {
      out.melanopic_mean->irradiance_W_m2 /= out.area_m2;
      out.melanopic_mean->edi_lx /= out.area_m2;
    }
    for (std::size_t w = 0; w < W; ++w) {
      out.radiosity_mean[w] /= out.area_m2;
      out.irradiance_mean[w] /= out.area_m2;
    }
  }

  report.probes.resize(sol.probes.size());
  for (std::size_t k = 0; k < sol.probes.size(); ++k) {
    ProbeSummary& out = report.probes[k];
    const auto& E = sol.probes[k].irradiance;
    const std::size_t points = W ? E.size() / W : 0;
    std::vector<double> e(W);
    for (std::size_t q = 0; q < points; ++q) {
      std::copy(E.begin() + q * W, E.begin() + (q + 1) * W, e.begin());
      out.illuminance_lx.push_back(photometer.luminous(e));
      if (const auto mel = photometer.melanopic(e)) out.melanopic.push_back(*mel);
    }
    if (points == 0) continue;
    const auto [lo, hi] = std::minmax_element(out.illuminance_lx.begin(), out.illuminance_lx.end());
    out.min_lx = *lo;
    out.max_lx = *hi;
    double sum = 0;
    for (double v : out.illuminance_lx) sum += v;
    out.mean_lx = sum / points;
    out.min_over_mean = out.mean_lx > 0 ? out.min_lx / out.mean_lx : 0;
    out.min_over_max = out.max_lx > 0 ? out.min_lx / out.max_lx : 0;
  }
  // Per-source photometry: the same conversions applied to each contribution (linear, so the
  // values add up to the joint ones in spectral mode as well as in rgb mode).
  std::vector<double> e(W);
  for (const SourceContribution& c : sol.contributions) {
    SourceReport& out = report.sources.emplace_back();
    for (std::size_t i = 0; i < N; ++i) {
      std::copy(c.irradiance.begin() + i * W, c.irradiance.begin() + (i + 1) * W, e.begin());
      out.patch_illuminance_lx.push_back(photometer.luminous(e));
      for (std::size_t w = 0; w < W; ++w) e[w] = c.radiosity[i * W + w] / kPi;
      out.patch_luminance_cd_m2.push_back(photometer.luminous(e));
    }
    for (const ProbeResult& probe : c.probes) {
      auto& lux = out.probe_illuminance_lx.emplace_back();
      for (std::size_t q = 0; W && q < probe.irradiance.size() / W; ++q) {
        std::copy(probe.irradiance.begin() + q * W, probe.irradiance.begin() + (q + 1) * W, e.begin());
        lux.push_back(photometer.luminous(e));
      }
    }
  }
  std::vector<std::vector<double>> probe_lux;
  for (const ProbeSummary& p : report.probes) probe_lux.push_back(p.illuminance_lx);
  report.daylight = make_daylight_report(scene, sol, probe_lux,
                                         [&](const std::vector<double>& s) { return photometer.luminous(s); });
  return report;
}

}  // namespace lambert
