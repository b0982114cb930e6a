// "type": "luminaire" (SPEC §1): a luminaire from an IES LM-63 or EULUMDAT file, read through the
// same sandbox as mesh files (codec/mesh_files.h) or given inline, placed by its photometric centre,
// the direction of γ = 0 (nadir) and of the C0 half-plane. Its spectrum is a shape; the file's
// candela set the scale, as a point light's luminous_intensity_cd does (codec/spectra.h).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <utility>

#include "mesh/mesh_file.h"
#include "server/codec/lights/light_types.h"
#include "server/codec/mesh_files.h"
#include "server/codec/spectra.h"
#include "solver/photometry/distribution.h"

namespace lambert::codec {
namespace {

constexpr double kMaxFlux_lm = 1e12;
constexpr double kPerpendicularTolerance = 1e-6;  // |cos| between nadir and c0

std::shared_ptr<const LuminairePhotometry> parsed(Decoder& d, const PhotometricParse& parse, const std::string& p) {
  if (!parse.ok()) {
    d.error(p, parse.error);
    return nullptr;
  }
  for (const std::string& w : parse.data->warnings) d.warn(p, w);
  return std::make_shared<const LuminairePhotometry>(*parse.data);
}

// "file": the sandbox's path, the format by its extension, each file read once per scene.
std::shared_ptr<const LuminairePhotometry> photometry_file(Decoder& d, const json& jf, const std::string& p,
                                                           std::string& source) {
  auto rel = d.string(jf, p);
  if (!rel) return nullptr;
  source = *rel;
  std::string extension = std::filesystem::path(*rel).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  if (extension != ".ies" && extension != ".ldt") {
    d.error(p, "photometric file " + quote_text(*rel) + " has the extension " + quote_text(extension) +
                   "; expected .ies (IES LM-63) or .ldt (EULUMDAT)");
    return nullptr;
  }
  auto path = resolve_scene_file(d, *rel, p, "photometric file", "photometric files");
  if (!path) return nullptr;
  const std::string key = path->string();
  if (auto it = d.photometry_files().find(key); it != d.photometry_files().end()) return it->second;
  const PhotometricLimits limits;
  std::string bytes;
  if (auto problem = read_regular_file(key, limits.max_bytes, bytes)) {
    d.error(p, *rel + ": " + *problem);
    return nullptr;
  }
  const PhotometricParse parse = extension == ".ies" ? parse_ies(bytes, *rel, limits) : parse_ldt(bytes, *rel, limits);
  auto photometry = parsed(d, parse, p);
  if (photometry) d.photometry_files().emplace(key, photometry);
  return photometry;
}

// "photometry": exactly one of {"file"}, {"ies"} and {"ldt"}.
std::shared_ptr<const LuminairePhotometry> read_photometry(Decoder& d, const json& j, const std::string& p,
                                                           std::string& source) {
  if (!d.object(j, p, {"file", "ies", "ldt"})) return nullptr;
  const int given = static_cast<int>(j.contains("file")) + static_cast<int>(j.contains("ies")) +
                    static_cast<int>(j.contains("ldt"));
  if (given != 1) {
    d.error(p, "give exactly one of \"file\", \"ies\" (LM-63 text) and \"ldt\" (EULUMDAT text)");
    return nullptr;
  }
  if (const json* jf = d.member(j, "file")) return photometry_file(d, *jf, p + "/file", source);
  const bool ies = j.contains("ies");
  const std::string pt = p + (ies ? "/ies" : "/ldt");
  auto text = d.string(j.at(ies ? "ies" : "ldt"), pt);
  if (!text) return nullptr;
  source = ies ? "inline IES text" : "inline EULUMDAT text";
  return parsed(d, ies ? parse_ies(*text, source) : parse_ldt(*text, source), pt);
}

// position, nadir and c0 (perpendicular to nadir, to within 1e-6).
bool read_frame(Decoder& d, const json& j, const std::string& p, LuminaireLight& light) {
  bool ok = true;
  const json* jp = d.required(j, p, "position");
  if (auto q = jp ? d.point(*jp, p + "/position") : std::nullopt) light.position = d.metres(*q);
  else ok = false;
  const json* jn = d.required(j, p, "nadir");
  const json* jc = d.required(j, p, "c0");
  auto nadir = jn ? d.direction(*jn, p + "/nadir") : std::nullopt;
  auto c0 = jc ? d.direction(*jc, p + "/c0") : std::nullopt;
  if (!nadir || !c0) return false;
  const double c = dot(*nadir, *c0);
  if (std::abs(c) > kPerpendicularTolerance) {
    d.error(p + "/c0", "must be perpendicular to nadir (they make " +
                           num(std::acos(std::clamp(c, -1.0, 1.0)) / kDegree) + "°)");
    return false;
  }
  light.nadir = *nadir;
  light.c0 = normalize(*c0 - *nadir * c);
  return ok;
}

// The file's tilt multiplier at tilt_deg (linear between its angles), 1 without tilt data.
bool read_tilt(Decoder& d, const json& j, const std::string& p, const PhotometricData& file, LuminaireLight& light) {
  if (const json* jt = d.member(j, "tilt_deg")) {
    auto t = d.number_in(*jt, p + "/tilt_deg", 0, true, 180, true);
    if (!t) return false;
    light.tilt_deg = *t;
  }
  if (!file.tilt) {
    if (light.tilt_deg != 0)
      d.warn(p + "/tilt_deg", "the file has no tilt data (TILT=NONE): its output does not depend on the tilt");
    return true;
  }
  const auto& a = file.tilt->angles_deg;
  const auto& f = file.tilt->factors;
  if (light.tilt_deg < a.front() || light.tilt_deg > a.back()) {
    d.error(p + "/tilt_deg", num(light.tilt_deg) + " is outside the file's tilt angles [" + num(a.front()) + ", " +
                                 num(a.back()) + "]");
    return false;
  }
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(a.begin(), a.end(), light.tilt_deg) - a.begin());
  if (k >= a.size()) light.tilt_factor = f.back();
  else if (k == 0) light.tilt_factor = f.front();
  else light.tilt_factor = f[k - 1] + (f[k] - f[k - 1]) * (light.tilt_deg - a[k - 1]) / (a[k] - a[k - 1]);
  return true;
}

// maintenance_factor and luminous_flux_lm give candela_scale (with the tilt factor).
bool read_scale(Decoder& d, const json& j, const std::string& p, double file_flux, LuminaireLight& light) {
  bool ok = true;
  if (const json* jm = d.member(j, "maintenance_factor")) {
    auto m = d.number_in(*jm, p + "/maintenance_factor", 0, false, 1, true);
    if (m) light.maintenance_factor = *m;
    else ok = false;
  }
  if (const json* jf = d.member(j, "luminous_flux_lm")) {
    auto f = d.number_in(*jf, p + "/luminous_flux_lm", 0, false, kMaxFlux_lm, true);
    if (f) light.luminous_flux_lm = *f;
    else ok = false;
  }
  if (!(file_flux > 0)) {
    d.error(p + "/photometry", "the file's intensities are all zero: the luminaire emits no light");
    return false;
  }
  const double rescale = light.luminous_flux_lm ? *light.luminous_flux_lm / file_flux : 1.0;
  light.candela_scale = rescale * light.tilt_factor * light.maintenance_factor;
  return ok;
}

}  // namespace

void decode_luminaire_light(Decoder& d, const json& j, const std::string& p, std::string_view) {
  d.unknown_keys(j, p, {"type", "name", "photometry", "position", "nadir", "c0", "luminous_flux_lm",
                        "maintenance_factor", "spectrum", "tilt_deg"});
  LuminaireLight light;
  light.name = d.unique_name(j, p, "luminaire" + std::to_string(d.scene().lights.size()), d.luminaire_names(),
                             "luminaire");
  bool ok = read_frame(d, j, p, light);
  if (const json* jp = d.required(j, p, "photometry")) light.photometry = read_photometry(d, *jp, p + "/photometry", light.source);
  std::optional<std::vector<double>> shape;
  if (const json* js = d.member(j, "spectrum")) shape = spectrum(d, *js, p + "/spectrum", SpectrumRole::Emission);
  else if (d.grid()) shape = std::vector<double>(d.grid()->size(), 1.0);  // equal energy (CIE E)
  if (!light.photometry || !ok) return;
  if (light.photometry->file.opening.shape == LuminousShape::kUnsupported)
    d.warn(p + "/photometry", "the luminous shape '" + light.photometry->file.opening.description +
                                  "' is not modelled as an area: the point form is used at every distance");
  if (!read_tilt(d, j, p, light.photometry->file, light) ||
      !read_scale(d, j, p, light.photometry->distribution.flux(), light) || !shape)
    return;
  // One candela of the file: 683 Σ w ȳ S = candela_scale (the same quadrature that converts results).
  const Total per_candela{"the file's candela", true, light.candela_scale};
  if (!scale_to_total(d, *shape, per_candela, 1.0, p + "/spectrum")) return;
  light.intensity_W_sr_nm = std::move(*shape);
  d.add_light(std::move(light), p);
}

}  // namespace lambert::codec
