// Spectral core: wavelength grids and their trapezoidal weights, sampling of the spectrum forms of
// SPEC §1, the embedded CIE tables, photometric/colorimetric integrals and the RGB matrices.
#include "solver/spectrum.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace lambert {
namespace {

// Defines kCmf1nm[][4] = {nm, xbar, ybar, zbar}, kD65_1nm[][2] = {nm, S} and kMelanopic1nm[][2] =
// {nm, s_mel}, generated at build time from solver/data/*.csv by tools/embed_cie_tables.cmake
// (which also checks the 1 nm spacing).
#include "cie_tables.inc"

constexpr std::size_t kCmfRows = std::size(kCmf1nm);
constexpr std::size_t kD65Rows = std::size(kD65_1nm);
static_assert(kCmf1nm[0][0] == 360.0 && kCmf1nm[kCmfRows - 1][0] == 830.0,
              "the CIE 1931 table must span 360-830 nm");
static_assert(kD65_1nm[0][0] == 300.0 && kD65_1nm[kD65Rows - 1][0] == 830.0,
              "the D65 table must span 300-830 nm");
constexpr std::size_t kMelanopicRows = std::size(kMelanopic1nm);
static_assert(kMelanopic1nm[0][0] == 380.0 && kMelanopic1nm[kMelanopicRows - 1][0] == 780.0,
              "the CIE S 026 melanopic table must span 380-780 nm");

// CODATA 2018 exact SI defining constants.
constexpr double kPlanck_J_s = 6.62607015e-34;
constexpr double kSpeedOfLight_m_s = 299792458.0;
constexpr double kBoltzmann_J_K = 1.380649e-23;

// Second radiation constant as written in the CIE definition of illuminant A (CIE 15:2018 §3.1,
// ISO 11664-2): c2 = 1.435e7 nm K with T = 2848 K. The CIE keeps this historical value on purpose,
// so it is NOT derived from the CODATA constants above.
constexpr double kCieA_c2_nm_K = 1.435e7;
constexpr double kCieA_T_K = 2848.0;

// Above this exponent exp(x) overflows a double (ln(DBL_MAX) ≈ 709.8); Planck's law is then 0 to
// within any representable precision, since 2hc²/λ⁵ never exceeds ~1e30 at wavelengths > 1 pm.
constexpr double kMaxExponent = 700.0;

// Linear interpolation in a table whose rows are 1 nm apart starting at table[0][0]; column `col`.
// Outside the table the value is 0 (callers rely on it: the CMF and D65 are 0 outside their range).
template <std::size_t Rows, std::size_t Cols>
double interpolate_1nm(const double (&table)[Rows][Cols], std::size_t col, double nm) {
  const double first = table[0][0];
  const double last = table[Rows - 1][0];
  if (!(nm >= first && nm <= last)) return 0.0;
  const double offset = nm - first;
  const auto i = static_cast<std::size_t>(offset);
  if (i >= Rows - 1) return table[Rows - 1][col];
  const double t = offset - static_cast<double>(i);
  return table[i][col] + t * (table[i + 1][col] - table[i][col]);
}

// Planck's law per unit wavelength, converted from per metre to per nanometre:
//   B(λ, T) = 2 h c² / λ⁵ / (exp(h c / (λ k T)) − 1)   [W m^-2 sr^-1 m^-1] × 1e-9 m/nm.
// expm1 keeps the long-wavelength (Rayleigh-Jeans) end accurate where the exponent is tiny.
double planck_W_m2_sr_nm(double nm, double kelvin) {
  if (!(nm > 0.0) || !(kelvin > 0.0)) return 0.0;
  const double lambda_m = nm * 1e-9;
  const double x = kPlanck_J_s * kSpeedOfLight_m_s / (lambda_m * kBoltzmann_J_K * kelvin);
  if (x > kMaxExponent) return 0.0;
  const double lambda5 = std::pow(lambda_m, 5);
  const double per_m =
      2.0 * kPlanck_J_s * kSpeedOfLight_m_s * kSpeedOfLight_m_s / lambda5 / std::expm1(x);
  return per_m * 1e-9;
}

// CIE illuminant A (CIE 15:2018 eq. 3.1), relative, 100 at 560 nm:
//   S_A(λ) = 100 (560/λ)^5 [exp(c2/(2848·560)) − 1] / [exp(c2/(2848·λ)) − 1],  λ in nm.
double cie_a(double nm) {
  if (!(nm > 0.0)) return 0.0;
  const double x = kCieA_c2_nm_K / (kCieA_T_K * nm);
  if (x > kMaxExponent) return 0.0;
  const double x560 = kCieA_c2_nm_K / (kCieA_T_K * 560.0);
  return 100.0 * std::pow(560.0 / nm, 5) * std::expm1(x560) / std::expm1(x);
}

// Smooth RGB -> reflectance upsampling.
//
// Method: a partition of unity of three smooth basis curves over wavelength,
//   b_blue(λ)  = 1 − σ((λ − λ_bg) / w),      σ(t) = 1 / (1 + e^−t)  (the logistic function)
//   b_red(λ)   = σ((λ − λ_gr) / w),
//   b_green(λ) = 1 − b_blue − b_red = σ((λ − λ_bg)/w) − σ((λ − λ_gr)/w),
// and ρ(λ) = r b_red + g b_green + b b_blue. Each basis is C∞, in [0, 1] (b_green ≥ 0 because σ is
// increasing and λ_bg < λ_gr with a common width), and the three sum to 1, so ρ is a convex
// combination of r, g, b: ρ ∈ [0, 1] for rgb in [0, 1]³, rgb (1,1,1) gives exactly 1 and (0,0,0)
// gives 0.
//
// Parameters: λ_bg = 488.5 nm, λ_gr = 590.5 nm, w = 8 nm, found by a grid search (0.5 nm, 1 nm
// steps) minimising the largest entry of |M − I|, where M maps the input rgb to the linear sRGB of
// the reflected light under D65 (CIE 1931 2°, 1 nm, 360-830 nm, white normalised to Y = 1).
// Accuracy: the round trip is linear in rgb; for the pure primaries every channel is within 0.022
// of the input, and for any rgb in [0, 1]³ within 0.044 (the largest row sum of |M − I|). Colours
// near the sRGB gamut boundary are reproduced less saturated than a full spectral fit (e.g. Jakob &
// Hanika 2019) would give; this model favours smoothness, bounds and exact white over saturation.
constexpr double kRgbBlueGreenEdge_nm = 488.5;
constexpr double kRgbGreenRedEdge_nm = 590.5;
constexpr double kRgbEdgeWidth_nm = 8.0;

double logistic(double t) { return 1.0 / (1.0 + std::exp(-t)); }

double rgb_reflectance(const std::array<double, 3>& rgb, double nm) {
  const double red_basis = logistic((nm - kRgbGreenRedEdge_nm) / kRgbEdgeWidth_nm);
  const double blue_basis = 1.0 - logistic((nm - kRgbBlueGreenEdge_nm) / kRgbEdgeWidth_nm);
  // Written relative to g so that r = g = b gives exactly that value (no rounding from b_green).
  const double r = rgb[0], g = rgb[1], b = rgb[2];
  const double value = g + (r - g) * red_basis + (b - g) * blue_basis;
  // The clamp only removes rounding (a few ulp): the exact value lies between min and max of rgb.
  return std::clamp(value, 0.0, 1.0);
}

// Tabulated spectrum, linear between samples. Beyond the ends a reflectance holds its end value and
// an emission is zero (SPEC §1).
double tabulated_value(const TabulatedSpectrum& t, double nm, SpectrumRole role) {
  const std::size_t n = t.nm.size();
  if (n == 0 || t.values.size() != n) {
    throw std::invalid_argument("tabulated spectrum: " + std::to_string(n) + " wavelengths and " +
                                std::to_string(t.values.size()) + " values");
  }
  if (nm < t.nm.front() || nm > t.nm[n - 1]) {
    if (role == SpectrumRole::Emission) return 0.0;
    return nm < t.nm.front() ? t.values.front() : t.values[n - 1];
  }
  const auto end = t.nm.begin() + static_cast<std::ptrdiff_t>(n);
  const auto upper = std::upper_bound(t.nm.begin(), end, nm);  // first sample > nm
  if (upper == end) return t.values[n - 1];                    // nm is the last sample
  const std::size_t i = static_cast<std::size_t>(upper - t.nm.begin()) - 1;
  const double span = t.nm[i + 1] - t.nm[i];
  const double f = (nm - t.nm[i]) / span;
  return t.values[i] + f * (t.values[i + 1] - t.values[i]);
}

// ---- RGB matrices, derived from chromaticities (SMPTE RP 177-1993) ----
using Matrix3 = std::array<std::array<double, 3>, 3>;
struct Chromaticity {
  double x, y;
};

constexpr std::array<double, 3> xyz_from_xy(Chromaticity c) {  // (X, Y, Z) with Y = 1
  return {c.x / c.y, 1.0, (1.0 - c.x - c.y) / c.y};
}

constexpr Matrix3 inverse(const Matrix3& m) {
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  return {{{c00 / det, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det,
            (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det},
           {c01 / det, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det,
            (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det},
           {c02 / det, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det,
            (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det}}};
}

// XYZ -> linear RGB for primaries r, g, b and white w. The RGB -> XYZ matrix has the primaries' XYZ
// (Y = 1) as columns, each scaled by S_i so that RGB (1,1,1) lands on the white: S = P^-1 W. Its
// inverse is the wanted matrix, and maps the white with Y = 1 to (1,1,1).
constexpr Matrix3 xyz_to_rgb_matrix(Chromaticity r, Chromaticity g, Chromaticity b,
                                    Chromaticity w) {
  const std::array<double, 3> pr = xyz_from_xy(r), pg = xyz_from_xy(g), pb = xyz_from_xy(b);
  const Matrix3 p = {{{pr[0], pg[0], pb[0]}, {pr[1], pg[1], pb[1]}, {pr[2], pg[2], pb[2]}}};
  const Matrix3 p_inv = inverse(p);
  const std::array<double, 3> white = xyz_from_xy(w);
  std::array<double, 3> s{};
  for (int i = 0; i < 3; ++i) {
    s[i] = p_inv[i][0] * white[0] + p_inv[i][1] * white[1] + p_inv[i][2] * white[2];
  }
  Matrix3 rgb_to_xyz{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rgb_to_xyz[i][j] = p[i][j] * s[j];
  }
  return inverse(rgb_to_xyz);
}

// D65 white as the RGB standards state it (4 digits; CIE 15 gives 0.31272, 0.32903 for the table).
constexpr Chromaticity kWhiteD65{0.3127, 0.3290};
// EBU Tech 3213-E (1975): EBU standard for chromaticity tolerances for studio monitors.
constexpr Matrix3 kXyzToEbu =
    xyz_to_rgb_matrix({0.640, 0.330}, {0.290, 0.600}, {0.150, 0.060}, kWhiteD65);
// IEC 61966-2-1:1999 (sRGB) = ITU-R BT.709 primaries.
constexpr Matrix3 kXyzToSrgb =
    xyz_to_rgb_matrix({0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}, kWhiteD65);
constexpr Matrix3 kEbuToXyz = inverse(kXyzToEbu);

std::array<double, 3> apply(const Matrix3& m, const Xyz& c) {
  return {m[0][0] * c.X + m[0][1] * c.Y + m[0][2] * c.Z,
          m[1][0] * c.X + m[1][1] * c.Y + m[1][2] * c.Z,
          m[2][0] * c.X + m[2][1] * c.Y + m[2][2] * c.Z};
}

void require_same_size(const std::vector<double>& s, const WavelengthGrid& grid, const char* what) {
  if (s.size() != grid.size()) {
    throw std::invalid_argument(std::string(what) + ": spectrum has " + std::to_string(s.size()) +
                                " samples, grid has " + std::to_string(grid.size()));
  }
}

// Trapezoidal weights over sorted samples: each sample gets half of each neighbouring interval.
std::vector<double> trapezoid_weights(const std::vector<double>& nm) {
  const std::size_t n = nm.size();
  if (n == 1) return {1.0};  // a single wavelength stands for a 1 nm band (header contract)
  std::vector<double> w(n, 0.0);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double half = 0.5 * (nm[i + 1] - nm[i]);
    w[i] += half;
    w[i + 1] += half;
  }
  return w;
}

}  // namespace

// ---- WavelengthGrid ----

WavelengthGrid WavelengthGrid::uniform(double from_nm, double to_nm, double step_nm) {
  if (!std::isfinite(from_nm) || !std::isfinite(to_nm) || !std::isfinite(step_nm) ||
      !(from_nm > 0.0) || !(step_nm > 0.0) || to_nm < from_nm) {
    throw std::invalid_argument(
        "WavelengthGrid::uniform: need 0 < from <= to and step > 0, got from " +
        std::to_string(from_nm) + ", to " + std::to_string(to_nm) + ", step " +
        std::to_string(step_nm));
  }
  // `to` is included when it lies on the grid up to rounding: (780 − 380) / 5 may come out as
  // 79.999999999 in floating point, which must still give 81 samples.
  constexpr double kOnGridTolerance = 1e-9;  // in units of the step
  const double intervals = (to_nm - from_nm) / step_nm;
  const auto count = static_cast<std::size_t>(std::floor(intervals + kOnGridTolerance)) + 1;
  std::vector<double> nm(count);
  for (std::size_t i = 0; i < count; ++i) nm[i] = from_nm + static_cast<double>(i) * step_nm;
  if (std::abs(nm.back() - to_nm) <= kOnGridTolerance * step_nm) nm.back() = to_nm;
  return from_list(std::move(nm));
}

WavelengthGrid WavelengthGrid::from_list(std::vector<double> nm) {
  if (nm.empty()) throw std::invalid_argument("WavelengthGrid::from_list: no wavelengths");
  for (std::size_t i = 0; i < nm.size(); ++i) {
    if (!std::isfinite(nm[i]) || !(nm[i] > 0.0) || (i > 0 && !(nm[i] > nm[i - 1]))) {
      throw std::invalid_argument(
          "WavelengthGrid::from_list: wavelengths must be finite, > 0 and strictly ascending; "
          "entry " + std::to_string(i) + " is " + std::to_string(nm[i]));
    }
  }
  WavelengthGrid grid;
  grid.weight_nm = trapezoid_weights(nm);
  grid.nm = std::move(nm);
  return grid;
}

// ---- Sampling ----

double spectrum_value(const SpectrumSpec& spec, double nm, SpectrumRole role) {
  return std::visit(
      [&](const auto& s) -> double {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, ConstantSpectrum>) {
          return s.value;
        } else if constexpr (std::is_same_v<T, TabulatedSpectrum>) {
          return tabulated_value(s, nm, role);
        } else if constexpr (std::is_same_v<T, CieSpectrum>) {
          return cie_illuminant(s.illuminant, nm);
        } else if constexpr (std::is_same_v<T, BlackbodySpectrum>) {
          return planck_W_m2_sr_nm(nm, s.kelvin);
        } else {
          static_assert(std::is_same_v<T, RgbReflectanceSpectrum>);
          return rgb_reflectance(s.rgb, nm);
        }
      },
      spec);
}

std::vector<double> sample_spectrum(const SpectrumSpec& spec, const WavelengthGrid& grid,
                                    SpectrumRole role) {
  std::vector<double> out(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) out[i] = spectrum_value(spec, grid.nm[i], role);
  return out;
}

// ---- CIE data ----

Cmf cie1931_cmf(double nm) {
  return {interpolate_1nm(kCmf1nm, 1, nm), interpolate_1nm(kCmf1nm, 2, nm),
          interpolate_1nm(kCmf1nm, 3, nm)};
}

double cie_illuminant(CieIlluminant illuminant, double nm) {
  switch (illuminant) {
    case CieIlluminant::D65: return interpolate_1nm(kD65_1nm, 1, nm);
    case CieIlluminant::A: return cie_a(nm);
    case CieIlluminant::E: return 100.0;
  }
  throw std::logic_error("cie_illuminant: unknown illuminant " +
                         std::to_string(static_cast<int>(illuminant)));
}

// ---- Integrals ----

double integrate(const std::vector<double>& s, const WavelengthGrid& grid) {
  require_same_size(s, grid, "integrate");
  double sum = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) sum += grid.weight_nm[i] * s[i];
  return sum;
}

double luminous_integral(const std::vector<double>& s, const WavelengthGrid& grid) {
  require_same_size(s, grid, "luminous_integral");
  double sum = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    sum += grid.weight_nm[i] * cie1931_cmf(grid.nm[i]).y * s[i];
  }
  return kLuminousEfficacy_lm_W * sum;
}

Xyz tristimulus(const std::vector<double>& s, const WavelengthGrid& grid) {
  require_same_size(s, grid, "tristimulus");
  Xyz c{0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Cmf cmf = cie1931_cmf(grid.nm[i]);
    const double ws = grid.weight_nm[i] * s[i];
    c.X += cmf.x * ws;
    c.Y += cmf.y * ws;
    c.Z += cmf.z * ws;
  }
  return {kLuminousEfficacy_lm_W * c.X, kLuminousEfficacy_lm_W * c.Y, kLuminousEfficacy_lm_W * c.Z};
}

std::array<double, 2> chromaticity_xy(const Xyz& c) {
  const double sum = c.X + c.Y + c.Z;
  if (!(sum > 0.0)) return {0.0, 0.0};
  return {c.X / sum, c.Y / sum};
}

// ---- RGB ----

std::array<double, 3> xyz_to_linear_ebu_rgb(const Xyz& c) { return apply(kXyzToEbu, c); }

std::array<double, 3> xyz_to_linear_srgb(const Xyz& c) { return apply(kXyzToSrgb, c); }

Xyz linear_ebu_rgb_to_xyz(const std::array<double, 3>& rgb) {
  const std::array<double, 3> c = apply(kEbuToXyz, {rgb[0], rgb[1], rgb[2]});
  return {c[0], c[1], c[2]};
}

// IEC 61966-2-1:1999 §5.2 (the encoding half of the sRGB transfer function).
double srgb_encode(double linear) {
  if (!(linear > 0.0)) return 0.0;  // also maps NaN to 0
  if (linear >= 1.0) return 1.0;
  if (linear <= 0.0031308) return 12.92 * linear;
  return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

// IEC 61966-2-1:1999 §5.2, the decoding half.
double srgb_decode(double encoded) {
  if (!(encoded > 0.0)) return 0.0;
  if (encoded >= 1.0) return 1.0;
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

// ---- CIE S 026 melanopic ----

double cie_s026_melanopic(double nm) { return interpolate_1nm(kMelanopic1nm, 1, nm); }

double melanopic_integral(const std::vector<double>& s, const WavelengthGrid& grid) {
  require_same_size(s, grid, "melanopic_integral");
  double sum = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    sum += grid.weight_nm[i] * cie_s026_melanopic(grid.nm[i]) * s[i];
  }
  return sum;
}

double melanopic_edi_lx(double melanopic_irradiance_W_m2) {
  return melanopic_irradiance_W_m2 / kMelanopicEfficacyD65_W_lm;
}

}  // namespace lambert
