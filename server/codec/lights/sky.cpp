// "type": "sky" (SPEC §1): a CIE sky (solver/lights/sky_luminance.h) over a uniform Lambertian
// ground, given by its type, its scale (the unobstructed horizontal illuminance or the zenith
// luminance), the scene's up (and north, to place a sun given by place and time), the sun for the
// skies that depend on it, the ground's reflectance and the spectrum's shape (default D65).
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "server/codec/lights/light_types.h"
#include "server/codec/spectra.h"
#include "solver/lights/sky.h"

namespace lambert::codec {
namespace {

constexpr double kDefaultGroundReflectance = 0.2;

// "cie_type": 1–15 (ISO 15469 general skies), 16 (the traditional CIE overcast sky) or "uniform".
bool read_cie_type(Decoder& d, const json& jt, const std::string& pt, SkyLight& light) {
  if (jt.is_string()) {
    if (jt.get<std::string>() == "uniform") {
      light.model = SkyLight::Model::kUniform;
      light.cie_type = 0;
      return true;
    }
    d.error(pt, "unknown sky " + quote_text(jt.get<std::string>()) + "; expected 1 to 16 or \"uniform\"");
    return false;
  }
  const auto type = d.whole(jt, pt, 1, kCieOvercastSkyType);
  if (!type) return false;
  light.cie_type = static_cast<int>(*type);
  light.model = *type == kCieOvercastSkyType ? SkyLight::Model::kCieOvercast : SkyLight::Model::kGeneral;
  return true;
}

std::string sky_name(const SkyLight& light) {
  switch (light.model) {
    case SkyLight::Model::kUniform: return "the uniform sky";
    case SkyLight::Model::kCieOvercast: return "the CIE overcast sky (16)";
    case SkyLight::Model::kGeneral: break;
  }
  return "CIE general sky type " + std::to_string(light.cie_type);
}

// "sun_direction" or "sun", where the sky depends on the sun (needs_sun); checked, and a warning
// where it does not (the sky ignores it). False after an error.
bool read_sun(Decoder& d, const json& j, const std::string& p, const std::optional<Horizon>& horizon,
              bool needs_sun, SkyLight& light) {
  const json* jd = d.member(j, "sun_direction");
  const json* js = d.member(j, "sun");
  if (jd && js) {
    d.error(p, "give sun_direction or sun, not both");
    return false;
  }
  if (!jd && !js) {
    if (needs_sun) d.error(p, sky_name(light) + " depends on the sun: give sun_direction or sun");
    return !needs_sun;
  }
  const std::string ps = p + (jd ? "/sun_direction" : "/sun");
  std::optional<Vector3> towards;
  if (jd) {
    towards = d.direction(*jd, ps);
  } else if (auto sun = decode_sun(d, *js, ps, horizon ? &*horizon : nullptr)) {
    towards = sun->towards;
    light.sun_placement = sun->placement;
  }
  if (!towards || !horizon) return false;
  if (!needs_sun) {
    d.warn(ps, "not used: " + sky_name(light) + " does not depend on the sun");
    light.sun_placement.reset();
    return true;
  }
  const double elevation_deg = std::asin(std::clamp(dot(*towards, horizon->up), -1.0, 1.0)) * 180 / kPi;
  if (!(elevation_deg > 0)) {
    d.error(ps, "the sun must stand above the horizon for " + sky_name(light) + "; it stands at " +
                    num(elevation_deg) + "° elevation");
    return false;
  }
  light.sun = towards;
  return true;
}

}  // namespace

void decode_sky_light(Decoder& d, const json& j, const std::string& p, std::string_view) {
  d.unknown_keys(j, p, with_totals({"type", "cie_type", "up", "north", "sun_direction", "sun",
                                    "ground_reflectance", "spectrum"}));
  SkyLight light;
  bool ok = true;
  if (const json* jt = d.required(j, p, "cie_type")) ok = read_cie_type(d, *jt, p + "/cie_type", light);
  else ok = false;
  const std::optional<Horizon> horizon = decode_horizon(d, j, p, d.member(j, "sun") != nullptr);
  if (horizon) light.up = horizon->up;
  const bool needs_sun = ok && light.model == SkyLight::Model::kGeneral && cie_sky_depends_on_sun(light.cie_type);
  if (ok) ok = read_sun(d, j, p, horizon, needs_sun, light) && horizon;
  if (const json* jg = d.member(j, "ground_reflectance")) {
    if (auto rho = d.number_in(*jg, p + "/ground_reflectance", 0, true, 1, true)) light.ground_reflectance = *rho;
    else ok = false;
  } else {
    light.ground_reflectance = kDefaultGroundReflectance;
  }
  std::optional<std::vector<double>> L;
  if (const json* js = d.member(j, "spectrum")) L = spectrum(d, *js, p + "/spectrum", SpectrumRole::Emission);
  else if (d.grid()) L = sample_spectrum(CieSpectrum{CieIlluminant::D65}, *d.grid(), SpectrumRole::Emission);
  const auto t = total(d, j, p, {"horizontal_illuminance_lx", "zenith_luminance_cd_m2"}, "a sky");
  if (!t && !d.member(j, "horizontal_illuminance_lx") && !d.member(j, "zenith_luminance_cd_m2")) {
    d.error(p, "a sky needs its scale: horizontal_illuminance_lx (unobstructed, from the sky alone) or "
               "zenith_luminance_cd_m2");
    ok = false;
  }
  if (!ok || !L || !t) return;
  // E_h = K L_z (sky_luminance.h): the horizontal illuminance is K times the zenith luminance.
  const double K = t->key == "horizontal_illuminance_lx" ? sky_distribution(light).horizontal_factor() : 1.0;
  if (!scale_to_total(d, *L, *t, K, p + "/spectrum")) return;
  light.zenith_radiance_W_m2_sr_nm = std::move(*L);
  d.add_light(std::move(light), p);
}

}  // namespace lambert::codec
