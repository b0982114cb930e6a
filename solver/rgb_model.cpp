// The three-sample RGB model (see rgb_model.h).
#include "solver/rgb_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <variant>

namespace lambert {
namespace {

constexpr double kGridFrom_nm = 360.0, kGridTo_nm = 830.0, kGridStep_nm = 1.0;

// EBU Tech 3213 primaries and the D65 white, as spectrum.cpp's matrix uses them (for the dominant
// wavelengths only; the reduction itself goes through xyz_to_linear_ebu_rgb).
constexpr std::array<std::array<double, 2>, 3> kEbuPrimaries_xy = {{{0.640, 0.330}, {0.290, 0.600},
                                                                    {0.150, 0.060}}};
constexpr std::array<double, 2> kD65_xy = {0.3127, 0.3290};

// Dominant wavelength of chromaticity p relative to white w: where the ray from w through p meets
// the spectrum locus (CIE 1931, 1 nm chords). The nearest crossing in the direction of p.
double dominant_wavelength_nm(const std::array<double, 2>& p, const std::array<double, 2>& w) {
  const double dx = p[0] - w[0], dy = p[1] - w[1];
  double best_t = std::numeric_limits<double>::infinity(), best_nm = 0;
  std::array<double, 2> prev = chromaticity_xy(
      Xyz{cie1931_cmf(kGridFrom_nm).x, cie1931_cmf(kGridFrom_nm).y, cie1931_cmf(kGridFrom_nm).z});
  for (double nm = kGridFrom_nm + kGridStep_nm; nm <= kGridTo_nm; nm += kGridStep_nm) {
    const Cmf c = cie1931_cmf(nm);
    const std::array<double, 2> next = chromaticity_xy(Xyz{c.x, c.y, c.z});
    // Solve w + t d = prev + u (next − prev) for t and u (Cramer's rule).
    const double ex = next[0] - prev[0], ey = next[1] - prev[1];
    const double det = dx * (-ey) - dy * (-ex);
    if (det != 0) {
      const double rx = prev[0] - w[0], ry = prev[1] - w[1];
      const double t = (rx * (-ey) - ry * (-ex)) / det;
      const double u = (dx * ry - dy * rx) / det;
      if (t > 0 && u >= 0 && u <= 1 && t < best_t) {
        best_t = t;
        best_nm = nm - kGridStep_nm + u * kGridStep_nm;
      }
    }
    prev = next;
  }
  return best_nm;
}

std::string json_pointer_token(const std::string& s) {  // RFC 6901: '~' -> "~0", '/' -> "~1"
  std::string out;
  for (char ch : s) {
    if (ch == '~') out += "~0";
    else if (ch == '/') out += "~1";
    else out += ch;
  }
  return out;
}

std::string format_triple(const std::array<double, 3>& v) {
  char text[160];
  std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", v[0], v[1], v[2]);
  return text;
}

void require_fine_grid(const std::vector<double>& s, const WavelengthGrid& fine, const char* what) {
  if (s.size() != fine.size()) {
    throw std::invalid_argument(std::string(what) + ": spectrum has " + std::to_string(s.size()) +
                                " samples, grid has " + std::to_string(fine.size()));
  }
}

}  // namespace

WavelengthGrid rgb_reduction_grid() {
  return WavelengthGrid::uniform(kGridFrom_nm, kGridTo_nm, kGridStep_nm);
}

WavelengthGrid rgb_channel_grid() {
  WavelengthGrid grid;
  for (int c = 0; c < 3; ++c) {
    grid.nm.push_back(dominant_wavelength_nm(kEbuPrimaries_xy[c], kD65_xy));
    std::array<double, 3> unit{0, 0, 0};
    unit[c] = 1;
    grid.weight_nm.push_back(linear_ebu_rgb_to_xyz(unit).Y);
  }
  return grid;
}

std::array<double, 3> ebu_value_curves(double nm) {
  const Cmf cmf = cie1931_cmf(nm);
  return xyz_to_linear_ebu_rgb(Xyz{cmf.x, cmf.y, cmf.z});
}

std::array<double, 3> rgb_source_values(const std::vector<double>& S, const WavelengthGrid& fine) {
  require_fine_grid(S, fine, "rgb_source_values");
  std::array<double, 3> I{0, 0, 0};
  for (std::size_t i = 0; i < fine.size(); ++i) {
    const std::array<double, 3> cbar = ebu_value_curves(fine.nm[i]);
    for (int c = 0; c < 3; ++c) I[c] += fine.weight_nm[i] * S[i] * cbar[c];
  }
  return I;
}

// Why the reflectance is weighted under the white point: an O_c is meant to multiply an incident
// channel value, and the channel value of light reflected from β under a source S is ∫ β S c̄ dλ,
// which depends on S. The model has to pick one S for every material; the scene white (D65, the white
// of the EBU matrix) is the natural choice: under D65 light, the product O_c · I_c is then exactly the
// reflected channel value, a grey β keeps O_R = O_G = O_B = β, and β = 1 gives O_c = 1 exactly (the
// numerator and denominator are the same sum). The alternative, weighting by c̄ alone
// (O_c = ∫ β c̄ dλ / ∫ c̄ dλ, i.e. under the equal-energy illuminant E), is just as simple but makes the
// reflectances exact for illuminant E instead, whose EBU RGB is not (1, 1, 1). Under any other
// source, and after each further bounce, both choices err; compare-rgb measures by how much.
std::array<double, 3> rgb_object_reflectance(const std::vector<double>& beta,
                                             const WavelengthGrid& fine) {
  require_fine_grid(beta, fine, "rgb_object_reflectance");
  std::array<double, 3> numerator{0, 0, 0}, denominator{0, 0, 0};
  for (std::size_t i = 0; i < fine.size(); ++i) {
    const std::array<double, 3> cbar = ebu_value_curves(fine.nm[i]);
    const double white = fine.weight_nm[i] * cie_illuminant(CieIlluminant::D65, fine.nm[i]);
    for (int c = 0; c < 3; ++c) {
      const double weight = white * cbar[c];
      numerator[c] += weight * beta[i];
      denominator[c] += weight;
    }
  }
  std::array<double, 3> O{};
  for (int c = 0; c < 3; ++c) O[c] = numerator[c] / denominator[c];
  return O;
}

Xyz xyz_from_rgb_channels(const std::array<double, 3>& c) {
  const Xyz xyz = linear_ebu_rgb_to_xyz(c);
  return {kLuminousEfficacy_lm_W * xyz.X, kLuminousEfficacy_lm_W * xyz.Y,
          kLuminousEfficacy_lm_W * xyz.Z};
}

void reduce_scene_to_rgb(Scene& scene) {
  const WavelengthGrid fine = rgb_reduction_grid();
  if (scene.grid.size() != fine.size() || scene.grid.nm.front() != fine.nm.front() ||
      scene.grid.nm.back() != fine.nm.back()) {
    throw std::invalid_argument("reduce_scene_to_rgb: the scene is not sampled on the 360-830 nm, "
                                "1 nm reduction grid");
  }
  auto to_vector = [](const std::array<double, 3>& a) { return std::vector<double>(a.begin(), a.end()); };

  for (Material& m : scene.materials) {
    const std::array<double, 3> O = rgb_object_reflectance(m.reflectance, fine);
    std::string problems;
    for (int c = 0; c < 3; ++c) {
      char text[160];
      if (O[c] < 0) {
        std::snprintf(text, sizeof text, "%sO_%s = %.6g is below 0 by %.6g", problems.empty() ? "" : "; ",
                      kRgbChannelNames[c], O[c], -O[c]);
        problems += text;
      } else if (O[c] > 1) {
        std::snprintf(text, sizeof text, "%sO_%s = %.6g is above 1 by %.6g", problems.empty() ? "" : "; ",
                      kRgbChannelNames[c], O[c], O[c] - 1);
        problems += text;
      }
    }
    if (!problems.empty()) {
      scene.warnings.push_back(
          "/materials/" + json_pointer_token(m.name) + "/reflectance: in rgb mode this reflectance is " +
          "O = " + format_triple(O) + ": " + problems +
          " (the EBU value curves have negative lobes; the value is used as computed, not clamped)");
    }
    m.reflectance = to_vector(O);
    if (m.specular) m.specular->reflectance = to_vector(rgb_object_reflectance(m.specular->reflectance, fine));
    // A pane's τ(λ) filters the light it passes as a reflectance filters what it reflects.
    if (!m.transmittance.empty()) m.transmittance = to_vector(rgb_object_reflectance(m.transmittance, fine));
  }

  auto reduce_source = [&](std::vector<double>& S, const std::string& pointer) {
    const std::array<double, 3> I = rgb_source_values(S, fine);
    if (I[0] < 0 || I[1] < 0 || I[2] < 0) {
      const double Y = linear_ebu_rgb_to_xyz(I).Y;
      std::string negative;
      for (int c = 0; c < 3; ++c) {
        if (I[c] >= 0) continue;
        char text[120];
        std::snprintf(text, sizeof text, "%sI_%s = %.6g (%.3g of Y)", negative.empty() ? "" : ", ",
                      kRgbChannelNames[c], I[c], Y > 0 ? I[c] / Y : 0.0);
        negative += text;
      }
      scene.warnings.push_back(pointer + ": in rgb mode this source is I = " + format_triple(I) +
                               ", outside the EBU gamut: " + negative +
                               " (negative channel values are kept, not clamped)");
    }
    S = to_vector(I);
  };

  for (Surface& s : scene.surfaces) {
    if (s.emission) reduce_source(s.emission->exitance_W_m2_nm, s.pointer + "/emission");
  }
  for (std::size_t k = 0; k < scene.lights.size(); ++k) {
    const std::string pointer =
        k < scene.light_pointers.size() ? scene.light_pointers[k] : "/lights/" + std::to_string(k);
    std::visit(
        [&](auto& light) {
          using T = std::decay_t<decltype(light)>;
          if constexpr (std::is_same_v<T, AmbientLight>) {
            reduce_source(light.irradiance_W_m2_nm, pointer);
          } else if constexpr (std::is_same_v<T, DirectionalLight>) {
            reduce_source(light.irradiance_W_m2_nm, pointer);
          } else if constexpr (std::is_same_v<T, SkyLight>) {
            reduce_source(light.zenith_radiance_W_m2_sr_nm, pointer);
          } else if constexpr (std::is_same_v<T, LuminaireLight>) {
            reduce_source(light.intensity_W_sr_nm, pointer);
          } else {
            static_assert(std::is_same_v<T, PointLight>, "reduce_scene_to_rgb: a new light type");
            reduce_source(light.intensity_W_sr_nm, pointer);
          }
        },
        scene.lights[k]);
  }
  scene.mode = SpectrumMode::Rgb;
  scene.grid = rgb_channel_grid();
}

}  // namespace lambert
