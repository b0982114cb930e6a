// A probe's daylight metrics (SPEC §5 "Daylight"): "daylight_factor": true (with
// "daylight_factor_target_pct" and "en17037": {"level", "median_external_diffuse_illuminance_lx"})
// and "vertical_sky_component": true. Each needs the scene's one sky; the daylight factor, the
// sky's light alone (CIE ILV 17-279 excludes direct sunlight), a scene that nothing else lights.
#include <cmath>
#include <string>

#include "server/codec/sections.h"

namespace lambert::codec {
namespace {

constexpr double kVertical = 1e-6;  // |normal·up| of a vertical plane's normal

const SkyLight* the_sky(Decoder& d, const std::string& pk) {
  const SkyLight* sky = nullptr;
  int skies = 0;
  for (const Light& light : d.scene().lights)
    if (const auto* s = std::get_if<SkyLight>(&light)) sky = s, ++skies;
  if (skies == 1) return sky;
  d.error(pk, "needs the scene's one sky among its lights; it has " + std::to_string(skies));
  return nullptr;
}

// The daylight factor is the sky's light alone: no other light, no emitting surface.
bool lit_by_the_sky_alone(Decoder& d, const std::string& pk) {
  const Scene& scene = d.scene();
  for (std::size_t l = 0; l < scene.lights.size(); ++l)
    if (!std::holds_alternative<SkyLight>(scene.lights[l])) {
      d.error(pk, "the daylight factor is the sky's light alone (CIE ILV 17-279: direct sunlight excluded), but " +
                      scene.light_pointers[l] + " lights this scene too; solve the sky alone for it");
      return false;
    }
  for (const Surface& s : scene.surfaces)
    if (s.emission) {
      d.error(pk, "the daylight factor is the sky's light alone, but " + s.pointer + " emits; solve the sky alone for it");
      return false;
    }
  return true;
}

std::optional<En17037Request> read_en17037(Decoder& d, const json& je, const std::string& pe) {
  if (!d.object(je, pe, {"level", "median_external_diffuse_illuminance_lx"})) return std::nullopt;
  En17037Request r;
  bool ok = true;
  if (const json* jl = d.required(je, pe, "level")) {
    const auto level = d.string(*jl, pe + "/level");
    if (level == "minimum") r.level = En17037Request::Level::kMinimum;
    else if (level == "medium") r.level = En17037Request::Level::kMedium;
    else if (level == "high") r.level = En17037Request::Level::kHigh;
    else {
      if (level) d.error(pe + "/level", "unknown level " + quote_text(*level) + "; expected \"minimum\", \"medium\" or \"high\"");
      ok = false;
    }
  } else {
    ok = false;
  }
  if (const json* jm = d.required(je, pe, "median_external_diffuse_illuminance_lx")) {
    const auto E = d.number_in(*jm, pe + "/median_external_diffuse_illuminance_lx", 0, false, INFINITY, false);
    if (E) r.median_external_diffuse_illuminance_lx = *E;
    else ok = false;
  } else {
    ok = false;
  }
  return ok ? std::optional<En17037Request>(r) : std::nullopt;
}

std::optional<bool> flag(Decoder& d, const json& j, const std::string& p, std::string_view key) {
  const json* v = d.member(j, key);
  return v ? d.boolean(*v, key_ptr(p, key)) : std::optional<bool>(false);
}

}  // namespace

bool decode_probe_daylight(Decoder& d, const json& j, const std::string& p, Probe& probe) {
  const auto df = flag(d, j, p, "daylight_factor");
  const auto vsc = flag(d, j, p, "vertical_sky_component");
  if (!df || !vsc) return false;
  DaylightRequest& r = probe.daylight;
  r.daylight_factor = *df;
  r.vertical_sky_component = *vsc;
  bool ok = true;
  for (const char* key : {"daylight_factor_target_pct", "en17037"})
    if (d.member(j, key) && !r.daylight_factor) {
      d.error(key_ptr(p, key), "applies to a probe with \"daylight_factor\": true");
      ok = false;
    }
  if (const json* jt = d.member(j, "daylight_factor_target_pct")) {
    if (auto t = d.number_in(*jt, p + "/daylight_factor_target_pct", 0, false, 100, true)) r.target_pct = *t;
    else ok = false;
  }
  if (const json* je = d.member(j, "en17037")) {
    if (!probe.is_grid) {
      d.error(p + "/en17037", "EN 17037's summary is over a grid's points; this probe is a single point");
      ok = false;
    } else if (!(r.en17037 = read_en17037(d, *je, p + "/en17037"))) {
      ok = false;
    }
  }
  if (r.daylight_factor) {
    const std::string pk = p + "/daylight_factor";
    ok = the_sky(d, pk) && lit_by_the_sky_alone(d, pk) && ok;
  }
  if (r.vertical_sky_component) {
    const std::string pk = p + "/vertical_sky_component";
    const SkyLight* sky = the_sky(d, pk);
    if (sky && !(std::abs(dot(probe.normal, sky->up)) <= kVertical)) {
      d.error(pk, "is measured on a vertical plane: the probe's normal must be horizontal (normal·up = " +
                      num(dot(probe.normal, sky->up)) + ")");
      ok = false;
    }
    ok = sky && ok;
  }
  return ok;
}

}  // namespace lambert::codec
