// The wavelength grid, spectrum specs and photometric totals (server/codec/spectra.h).
#include "server/codec/spectra.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "solver/rgb_model.h"

namespace lambert::codec {
namespace {

constexpr std::size_t kMaxSpectrumSamples = 10000;

struct TotalKind {
  std::string_view key;
  bool luminous;  // luminous_integral (683 Σ w ȳ s) rather than integrate (Σ w s)
};
constexpr std::array<TotalKind, 12> kTotalKinds = {{
    {"luminous_intensity_cd", true},   {"radiant_intensity_W_sr", false},
    {"luminous_flux_lm", true},        {"radiant_flux_W", false},
    {"illuminance_lx", true},          {"irradiance_W_m2", false},
    {"luminous_exitance_lm_m2", true}, {"radiant_exitance_W_m2", false},
    {"luminance_cd_m2", true},         {"radiance_W_m2_sr", false},
    {"horizontal_illuminance_lx", true}, {"zenith_luminance_cd_m2", true},  // a sky
}};

// ---- the grid ---------------------------------------------------------------------------------

// "wavelengths_nm": [..]: an explicit list, strictly ascending.
std::optional<WavelengthGrid> wavelength_list(Decoder& d, const json& spec, const json& list,
                                              const std::string& p) {
  d.unknown_keys(spec, p, {"mode", "wavelengths_nm"});
  const std::string pl = p + "/wavelengths_nm";
  if (!d.array(list, pl, 1)) return std::nullopt;
  if (list.size() > kMaxSpectrumSamples) {
    d.error(pl, "has " + std::to_string(list.size()) + " wavelengths; at most " +
                    std::to_string(kMaxSpectrumSamples) + " are allowed");
    return std::nullopt;
  }
  std::vector<double> nm;
  bool ok = true;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string pk = index_ptr(pl, k);
    auto v = d.number(list[k], pk);
    if (!v) { ok = false; continue; }
    if (*v <= 0 || *v > 100000) {
      d.error(pk, num(*v) + " is outside (0, 100000] nm");
      ok = false;
    } else if (!nm.empty() && ok && *v <= nm.back()) {
      d.error(pk, "wavelengths must be strictly ascending: " + num(*v) + " follows " +
                      num(nm.back()));
      ok = false;
    }
    nm.push_back(*v);
  }
  if (!ok) return std::nullopt;
  return WavelengthGrid::from_list(std::move(nm));
}

// from_nm, to_nm, step_nm: a uniform grid.
std::optional<WavelengthGrid> wavelength_range(Decoder& d, const json& spec, const std::string& p) {
  d.unknown_keys(spec, p, {"mode", "from_nm", "to_nm", "step_nm", "wavelengths_nm"});
  const json* jf = d.required(spec, p, "from_nm");
  const json* jt = d.required(spec, p, "to_nm");
  const json* js = d.required(spec, p, "step_nm");
  std::optional<double> from, to, step;
  if (jf) from = d.number_in(*jf, p + "/from_nm", 0, false, 100000, true);
  if (jt) to = d.number_in(*jt, p + "/to_nm", 0, false, 100000, true);
  if (js) step = d.number_in(*js, p + "/step_nm", 0, false, INFINITY, false);
  if (!from || !to || !step) return std::nullopt;
  if (!(*to > *from)) {
    d.error(p + "/to_nm",
            "to_nm (" + num(*to) + ") must be greater than from_nm (" + num(*from) + ")");
    return std::nullopt;
  }
  const double intervals = (*to - *from) / *step;
  if (!(intervals + 1 <= static_cast<double>(kMaxSpectrumSamples))) {
    d.error(p + "/step_nm", "gives about " + num(std::floor(intervals) + 1) + " samples; at most " +
                                std::to_string(kMaxSpectrumSamples) + " are allowed");
    return std::nullopt;
  }
  return WavelengthGrid::uniform(*from, *to, *step);
}

// The three-sample RGB model (SPEC §1 "mode": "rgb", solver/rgb_model.h): every spectrum is first
// sampled and photometrically scaled on the fine reduction grid, exactly as in spectral mode;
// Decoder::finish then reduces the finished scene to the three EBU channels.
WavelengthGrid rgb_mode(Decoder& d, const json& spec) {
  d.unknown_keys(spec, "/spectrum", {"mode"});
  d.scene().mode = SpectrumMode::Rgb;
  return rgb_reduction_grid();
}

std::optional<WavelengthGrid> grid_of(Decoder& d, const json* spec) {
  const std::string p = "/spectrum";
  if (!spec) return WavelengthGrid::uniform(380, 780, 5);
  if (!spec->is_object()) {
    d.error(p, "expected an object, got " + a_type(*spec));
    return std::nullopt;
  }
  const json* mode = d.required(*spec, p, "mode");
  if (!mode) {
    d.unknown_keys(*spec, p, {"mode", "from_nm", "to_nm", "step_nm", "wavelengths_nm"});
    return std::nullopt;
  }
  auto m = d.string(*mode, p + "/mode");
  if (!m) return std::nullopt;
  if (*m == "rgb") return rgb_mode(d, *spec);
  if (*m != "spectral") {
    d.error(p + "/mode", "unknown mode " + quote_text(*m) + "; expected \"spectral\" or \"rgb\"");
    return std::nullopt;
  }
  if (const json* list = d.member(*spec, "wavelengths_nm"))
    return wavelength_list(d, *spec, *list, p);
  return wavelength_range(d, *spec, p);
}

// ---- spectrum specs ---------------------------------------------------------------------------

std::optional<SpectrumSpec> tabulated(Decoder& d, const json& j, const std::string& p, double hi) {
  d.unknown_keys(j, p, {"nm", "values"});
  const json* jn = d.required(j, p, "nm");
  const json* jv = d.required(j, p, "values");
  if (!jn || !jv) return std::nullopt;
  const bool arrays_ok = d.array(*jn, p + "/nm", 1) != nullptr;
  if (!d.array(*jv, p + "/values", 1) || !arrays_ok) return std::nullopt;
  if (jn->size() != jv->size()) {
    d.error(p + "/values", "has " + std::to_string(jv->size()) + " entries but nm has " +
                               std::to_string(jn->size()));
    return std::nullopt;
  }
  TabulatedSpectrum t;
  bool ok = true;
  for (std::size_t k = 0; k < jn->size(); ++k) {
    const std::string pk = index_ptr(p + "/nm", k);
    auto v = d.number((*jn)[k], pk);
    if (!v) { ok = false; continue; }
    if (*v <= 0) { d.error(pk, num(*v) + " must be > 0 nm"); ok = false; }
    else if (!t.nm.empty() && *v <= t.nm.back()) {
      d.error(pk, "nm must be strictly ascending: " + num(*v) + " follows " + num(t.nm.back()));
      ok = false;
    }
    t.nm.push_back(*v);
  }
  for (std::size_t k = 0; k < jv->size(); ++k) {
    auto v = d.number_in((*jv)[k], index_ptr(p + "/values", k), 0, true, hi, true);
    if (!v) { ok = false; continue; }
    t.values.push_back(*v);
  }
  return ok ? std::optional<SpectrumSpec>(std::move(t)) : std::nullopt;
}

std::optional<SpectrumSpec> cie(Decoder& d, const json& j, const std::string& p) {
  d.unknown_keys(j, p, {"cie"});
  auto name = d.string(j.at("cie"), p + "/cie");
  if (!name) return std::nullopt;
  if (*name == "D65") return CieSpectrum{CieIlluminant::D65};
  if (*name == "A") return CieSpectrum{CieIlluminant::A};
  if (*name == "E") return CieSpectrum{CieIlluminant::E};
  d.error(p + "/cie",
          "unknown CIE illuminant " + quote_text(*name) + "; expected \"D65\", \"A\" or \"E\"");
  return std::nullopt;
}

std::optional<SpectrumSpec> blackbody(Decoder& d, const json& j, const std::string& p) {
  d.unknown_keys(j, p, {"blackbody_K"});
  auto t = d.number_in(j.at("blackbody_K"), p + "/blackbody_K", 0, false, INFINITY, false);
  return t ? std::optional<SpectrumSpec>(BlackbodySpectrum{*t}) : std::nullopt;
}

std::optional<SpectrumSpec> rgb(Decoder& d, const json& j, const std::string& p, SpectrumRole role) {
  d.unknown_keys(j, p, {"rgb"});
  if (role != SpectrumRole::Reflectance) {
    d.error(p + "/rgb", "rgb spectra are only for reflectances; give an emission as a number, "
                        "nm/values, cie or blackbody_K");
    return std::nullopt;
  }
  const json& jr = j.at("rgb");
  if (!jr.is_array() || jr.size() != 3) {
    d.error(p + "/rgb", "expected 3 numbers [r, g, b] in [0, 1], got " +
                            (jr.is_array() ? std::to_string(jr.size()) + " entries" : a_type(jr)));
    return std::nullopt;
  }
  RgbReflectanceSpectrum spec{};
  bool ok = true;
  for (std::size_t k = 0; k < 3; ++k) {
    auto v = d.number_in(jr[k], index_ptr(p + "/rgb", k), 0, true, 1, true);
    if (v) spec.rgb[k] = *v;
    else ok = false;
  }
  return ok ? std::optional<SpectrumSpec>(spec) : std::nullopt;
}

std::optional<SpectrumSpec> spectrum_spec(Decoder& d, const json& j, const std::string& p,
                                          SpectrumRole role) {
  const double hi = role == SpectrumRole::Reflectance ? 1.0 : INFINITY;
  if (j.is_number()) {
    auto v = d.number_in(j, p, 0, true, hi, true);
    return v ? std::optional<SpectrumSpec>(ConstantSpectrum{*v}) : std::nullopt;
  }
  if (!j.is_object()) {
    d.error(p, std::string("expected a spectrum (a number or an object), got ") + a_type(j));
    return std::nullopt;
  }
  std::vector<std::string_view> forms;
  if (j.contains("nm") || j.contains("values")) forms.push_back("nm/values");
  if (j.contains("cie")) forms.push_back("cie");
  if (j.contains("blackbody_K")) forms.push_back("blackbody_K");
  if (j.contains("rgb")) forms.push_back("rgb");
  if (forms.size() != 1) {
    d.unknown_keys(j, p, {"nm", "values", "cie", "blackbody_K", "rgb"});
    d.error(p, forms.empty() ? "expected a spectrum: a number or an object with nm/values, cie, "
                               "blackbody_K or rgb"
                             : "give exactly one spectrum form, not " + join(forms, " and "));
    return std::nullopt;
  }
  const std::string_view form = forms.front();
  if (form == "nm/values") return tabulated(d, j, p, hi);
  if (form == "cie") return cie(d, j, p);
  if (form == "blackbody_K") return blackbody(d, j, p);
  return rgb(d, j, p, role);
}

}  // namespace

void decode_spectrum_section(Decoder& d, const json* spectrum) {
  if (auto grid = grid_of(d, spectrum)) d.set_grid(std::move(*grid));
}

// The sampled values are checked again, since smooth RGB upsampling or interpolation must not leave
// [0, 1] for a reflectance either.
std::optional<std::vector<double>> spectrum(Decoder& d, const json& j, const std::string& p,
                                            SpectrumRole role) {
  auto spec = spectrum_spec(d, j, p, role);
  const WavelengthGrid* grid = d.grid();
  if (!spec || !grid) return std::nullopt;
  std::vector<double> s = sample_spectrum(*spec, *grid, role);
  for (std::size_t k = 0; k < s.size(); ++k) {
    const bool bad = role == SpectrumRole::Reflectance ? !(s[k] >= 0 && s[k] <= 1)
                                                       : !(s[k] >= 0 && std::isfinite(s[k]));
    if (bad) {
      d.error(p, "sampled value " + num(s[k]) + " at " + num(grid->nm[k]) + " nm is outside " +
                     (role == SpectrumRole::Reflectance ? "[0, 1]" : "[0, inf)"));
      return std::nullopt;
    }
  }
  return s;
}

Keys with_totals(Keys keys) {
  for (const auto& t : kTotalKinds) keys.push_back(t.key);
  return keys;
}

// At most one total (SPEC §1), and only one that applies to this kind of source.
std::optional<Total> total(Decoder& d, const json& obj, const std::string& p,
                           const Keys& applicable, std::string_view source) {
  std::vector<Total> found;
  for (const TotalKind& kind : kTotalKinds) {
    const json* v = d.member(obj, kind.key);
    if (!v) continue;
    const std::string pk = key_ptr(p, kind.key);
    auto value = d.number_in(*v, pk, 0, true, INFINITY, false);
    if (std::find(applicable.begin(), applicable.end(), kind.key) == applicable.end()) {
      d.error(pk, std::string(kind.key) + " does not apply to " + std::string(source) +
                      "; use one of " + join(applicable, " or "));
      continue;
    }
    if (value) found.push_back({kind.key, kind.luminous, *value});
  }
  if (found.size() > 1) {
    d.error(p, "two totals given (" + std::string(found[0].key) + " and " +
                   std::string(found[1].key) + "); a spectrum is scaled by at most one");
    return std::nullopt;
  }
  if (found.empty()) return std::nullopt;
  return found.front();
}

bool scale_to_total(Decoder& d, std::vector<double>& s, const Total& t, double geometric_factor,
                    const std::string& spectrum_pointer) {
  const WavelengthGrid& grid = *d.grid();  // s was sampled on it
  const double integral = t.luminous ? luminous_integral(s, grid) : integrate(s, grid);
  const double denominator = geometric_factor * integral;
  if (!(denominator > 0) || !std::isfinite(denominator)) {
    d.error(spectrum_pointer,
            t.luminous ? "spectrum has no visible content, cannot scale to lumens (" +
                             std::string(t.key) + ")"
                       : "spectrum integrates to zero over the wavelength grid, cannot scale it "
                         "to " + std::string(t.key));
    return false;
  }
  const double factor = t.value / denominator;
  for (double& v : s) v *= factor;
  if (!std::all_of(s.begin(), s.end(), [](double v) { return std::isfinite(v); })) {
    d.error(spectrum_pointer, "scaling to " + std::string(t.key) + " overflows");
    return false;
  }
  return true;
}

}  // namespace lambert::codec
