// Spectra in a scene (SPEC §1): the wavelength grid of the "spectrum" section, spectrum specs
// sampled on that grid, and the photometric or radiometric totals that scale an emission's shape.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/codec/decoder.h"

namespace lambert::codec {

// The "spectrum" section (absent: 380-780 nm in 5 nm steps). Sets the decoder's grid, or leaves it
// empty after reporting why.
void decode_spectrum_section(Decoder& d, const json* spectrum);

// A spectrum validated and sampled on the scene grid; nullopt after an error, or when the grid is
// invalid (the spec is still checked).
std::optional<std::vector<double>> spectrum(Decoder& d, const json& j, const std::string& p,
                                            SpectrumRole role);

// One total beside a spectrum: "luminous_flux_lm": 800 and the like.
struct Total {
  std::string_view key;
  bool luminous = false;  // luminous_integral (683 Σ w ȳ s) rather than integrate (Σ w s)
  double value = 0;
};

// keys plus every total key, for the unknown-key check of an object that may carry a total (the
// totals that do not apply to it are reported by total(), with a better message).
Keys with_totals(Keys keys);

// The one total of obj that applies to this kind of source (source: "a spot light" and the like,
// for messages). nullopt when there is none (an absolute spectrum) or an error was reported.
std::optional<Total> total(Decoder& d, const json& obj, const std::string& p,
                           const Keys& applicable, std::string_view source);

// Scales s so that t.value = geometric_factor × integral(s) (luminous or radiometric, on the grid);
// false after reporting at spectrum_pointer.
bool scale_to_total(Decoder& d, std::vector<double>& s, const Total& t, double geometric_factor,
                    const std::string& spectrum_pointer);

}  // namespace lambert::codec
