// The three-sample RGB model (SPEC §1 "spectrum": {"mode": "rgb"}), as the lecture derives it: every
// spectrum of the scene is reduced to three numbers by weighting it with the EBU spectral value
// curves, and the radiosity system is solved for three "wavelengths" R, G, B instead of a spectrum.
//
//   value curves   c̄(λ) = M · (x̄, ȳ, z̄)(λ),  c = R, G, B,  M = XYZ -> linear EBU RGB (EBU Tech 3213
//                  primaries, D65 white; the same matrix as xyz_to_linear_ebu_rgb). They have
//                  negative lobes (e.g. r̄ < 0 between about 440 and 545 nm).
//   sources        I_c = ∫ S(λ) c̄(λ) dλ           (the source's linear EBU RGB tristimulus values)
//   reflectances   O_c = ∫ β(λ) c̄(λ) S_D65(λ) dλ / ∫ c̄(λ) S_D65(λ) dλ
//
// Units: a channel value carries the unit of the spectrum times nm (exitance W m^-2 nm^-1 -> W m^-2),
// and is photometrically consistent with the spectrum it came from:
//   X, Y, Z = M^-1 (I_R, I_G, I_B), luminous value = 683 lm/W · Y = 683 (0.2220 R + 0.7067 G + 0.0713 B),
// the coefficients being the middle row of M^-1 (computed, not typed in).
//
// The decoder samples every spectrum of an rgb-mode scene on rgb_reduction_grid() (1 nm over the whole
// CIE 1931 table), applies the photometric totals there, and then calls reduce_scene_to_rgb().
#pragma once

#include <array>
#include <string>
#include <vector>

#include "solver/scene.h"
#include "solver/spectrum.h"

namespace lambert {

inline constexpr std::array<const char*, 3> kRgbChannelNames = {"R", "G", "B"};

// 360-830 nm in 1 nm steps: the fine grid on which rgb-mode spectra are decoded and scaled before
// the reduction (radiometric totals such as radiant_flux_W are therefore integrated over 360-830 nm).
WavelengthGrid rgb_reduction_grid();

// The Scene::grid of an rgb-mode scene: three channels in the order R, G, B. nm holds each EBU
// primary's dominant wavelength (relative to D65, from the CIE 1931 spectrum locus), for labelling
// only: nothing integrates against it, and it is descending, so it is not a WavelengthGrid that
// from_list would accept. weight_nm holds the luminance coefficients (Y of each primary, Y_white = 1),
// so that integrate(channels, grid) = Y = (luminous value) / 683 lm/W: the solver's energy balance
// ("emitted_W", "absorbed_W") is then in these photometric watts, one W being 683 lm.
WavelengthGrid rgb_channel_grid();

// r̄(λ), ḡ(λ), b̄(λ) at one wavelength (zero outside 360-830 nm, like the CMFs).
std::array<double, 3> ebu_value_curves(double nm);

// I_c of a source spectrum S sampled on `fine` (Σ w S c̄).
std::array<double, 3> rgb_source_values(const std::vector<double>& S, const WavelengthGrid& fine);

// O_c of a reflectance β sampled on `fine`. A constant β gives O_R = O_G = O_B = β (to rounding) and
// β = 1 gives exactly 1. O_c may leave [0, 1] for saturated β, because c̄ has negative lobes.
std::array<double, 3> rgb_object_reflectance(const std::vector<double>& beta,
                                             const WavelengthGrid& fine);

// Photometric XYZ (Y in lx for an irradiance, cd m^-2 for a radiance) of channel values:
// 683 lm/W · M^-1 c.
Xyz xyz_from_rgb_channels(const std::array<double, 3>& c);

// Reduces a scene decoded on rgb_reduction_grid() to the three-channel model: materials,
// emissions and lights; sets mode = Rgb and grid = rgb_channel_grid(). Adds a warning for every
// reflectance whose O_c leaves [0, 1] and every source with a negative channel (out of the EBU
// gamut), saying by how much; the values are kept as computed, never clamped.
// Throws std::invalid_argument when the scene's spectra are not on rgb_reduction_grid().
void reduce_scene_to_rgb(Scene& scene);

}  // namespace lambert
