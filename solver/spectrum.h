// Spectral core: the wavelength grid, spectrum descriptions and their sampling, photometric and
// colorimetric integrals. Radiometric values are per nanometre; conversion to photometric or colour
// values happens only here, at the end (SPEC "Physical conventions").
#pragma once

#include <array>
#include <string>
#include <variant>
#include <vector>

namespace lambert {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kLuminousEfficacy_lm_W = 683.0;  // K_m, lm/W at 555 nm (SPEC)

// The wavelengths the solver samples, with the quadrature weight (nm) of each sample for integrals
// over wavelength. Weights are trapezoidal over the sorted samples; a single wavelength gets 1 nm.
// Every spectral integral in Lambert (photometric scaling of inputs, lux of outputs) uses these
// same weights, so that "100 cd in" gives exactly the lux the closed form predicts.
// Both factories throw std::invalid_argument on a violated precondition (the codec checks first).
struct WavelengthGrid {
  std::vector<double> nm;
  std::vector<double> weight_nm;
  std::size_t size() const { return nm.size(); }
  static WavelengthGrid uniform(double from_nm, double to_nm, double step_nm);
  static WavelengthGrid from_list(std::vector<double> nm);  // sorted ascending, distinct, > 0
};

enum class CieIlluminant { D65, A, E };

// What a spectrum in a scene says, before sampling.
struct ConstantSpectrum { double value; };
struct TabulatedSpectrum { std::vector<double> nm, values; };   // nm strictly ascending
struct CieSpectrum { CieIlluminant illuminant; };              // relative SPD (100 at 560 nm; E = 100)
struct BlackbodySpectrum { double kelvin; };                   // Planck, W m^-2 sr^-1 nm^-1 (absolute)
struct RgbReflectanceSpectrum { std::array<double, 3> rgb; };  // linear sRGB in [0,1], smooth upsampling
using SpectrumSpec = std::variant<ConstantSpectrum, TabulatedSpectrum, CieSpectrum, BlackbodySpectrum,
                                  RgbReflectanceSpectrum>;

// Beyond a table's ends a reflectance holds its end values; an emission is zero (SPEC §1).
enum class SpectrumRole { Reflectance, Emission };

// Samples a spectrum at the grid's wavelengths (linear interpolation of tables).
std::vector<double> sample_spectrum(const SpectrumSpec& spec, const WavelengthGrid& grid,
                                    SpectrumRole role);

// Value of one spectrum at one wavelength (same rules as sample_spectrum).
double spectrum_value(const SpectrumSpec& spec, double nm, SpectrumRole role);

// ---- CIE data (tables embedded from solver/data/*.csv; sources cited there) ----
struct Cmf { double x, y, z; };
Cmf cie1931_cmf(double nm);            // CIE 1931 2° observer, linear between 1 nm samples, 0 outside 360-830
double cie_illuminant(CieIlluminant illuminant, double nm);  // D65 (1 nm table), A (formula), E (= 100)

// ---- Integrals over the grid, all with grid.weight_nm ----
double integrate(const std::vector<double>& s, const WavelengthGrid& grid);          // Σ w s
double luminous_integral(const std::vector<double>& s, const WavelengthGrid& grid);  // 683 Σ w ȳ s

struct Xyz { double X, Y, Z; };   // Y in photometric units (683 Σ w ȳ s: lx for E, cd/m² for L)
Xyz tristimulus(const std::vector<double>& s, const WavelengthGrid& grid);
std::array<double, 2> chromaticity_xy(const Xyz& c);     // (x, y); (0,0) for black

// Linear RGB from XYZ for two primary sets, both with D65 white (X,Y,Z of D65 with Y = 1 -> (1,1,1)).
std::array<double, 3> xyz_to_linear_ebu_rgb(const Xyz& c);   // EBU Tech 3213 primaries
std::array<double, 3> xyz_to_linear_srgb(const Xyz& c);      // IEC 61966-2-1 primaries
Xyz linear_ebu_rgb_to_xyz(const std::array<double, 3>& rgb);  // the inverse of xyz_to_linear_ebu_rgb
double srgb_encode(double linear);                           // IEC 61966-2-1 transfer, clamped to [0,1]
double srgb_decode(double encoded);                          // its inverse on [0,1], clamped likewise

// ---- CIE S 026:2018 melanopic quantities (ipRGC-influenced responses to light) ----
// s_mel(λ): the melanopic action spectrum, 1 at its peak (490 nm), linear between the standard's
// 1 nm samples, 0 outside 380-780 nm (where the standard defines no value).
double cie_s026_melanopic(double nm);
// K_mel,v^D65: the melanopic efficacy of luminous radiation of CIE D65, 1.3262 mW/lm (CIE S 026:2018).
inline constexpr double kMelanopicEfficacyD65_W_lm = 1.3262e-3;
// Σ w s_mel s: the melanopic irradiance E_mel [W m^-2] of a spectral irradiance s [W m^-2 nm^-1]
// (or the melanopic radiance of a spectral radiance).
double melanopic_integral(const std::vector<double>& s, const WavelengthGrid& grid);
// Melanopic equivalent daylight (D65) illuminance [lx] = E_mel / K_mel,v^D65: the illuminance of D65
// light that has the same melanopic irradiance.
double melanopic_edi_lx(double melanopic_irradiance_W_m2);

}  // namespace lambert
