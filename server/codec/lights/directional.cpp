// "type": "directional": a parallel beam (the sun as seen from the scene), given by the direction
// it travels and its irradiance on a plane perpendicular to it (SPEC §1). In place of "direction",
// "sun": {"latitude_deg", "longitude_deg", "time"} with the scene's "up" and "north" places it by
// NOAA's algorithm; without a total, its normal illuminance is then the clear-sky model's
// (solver/lights/solar_position.h).
#include <utility>

#include "server/codec/lights/light_types.h"
#include "server/codec/spectra.h"

namespace lambert::codec {
namespace {

// The sun by place and time: its direction of travel and placement; nullopt after an error (a sun
// at or below the horizon is one: it lights nothing).
std::optional<SunAt> sun_of(Decoder& d, const json& j, const json& js, const std::string& p) {
  const std::optional<Horizon> horizon = decode_horizon(d, j, p, true);
  auto sun = decode_sun(d, js, p + "/sun", horizon ? &*horizon : nullptr);
  if (!sun) return std::nullopt;
  if (!(sun->placement.elevation_deg > 0)) {
    d.error(p + "/sun", "the sun stands " + num(-sun->placement.elevation_deg) +
                            "° below the horizon at this place and time: a directional light needs it above");
    return std::nullopt;
  }
  return sun;
}

}  // namespace

void decode_directional_light(Decoder& d, const json& j, const std::string& p, std::string_view) {
  d.unknown_keys(j, p, with_totals({"type", "direction", "irradiance", "sun", "up", "north"}));
  const json* jd = d.member(j, "direction");
  const json* js = d.member(j, "sun");
  std::optional<Vector3> dir;
  std::optional<SunAt> sun;
  if (jd && js) {
    d.error(p, "give direction or sun, not both");
  } else if (jd) {
    dir = d.direction(*jd, p + "/direction");
    for (const char* key : {"up", "north"})
      if (d.member(j, key)) d.error(key_ptr(p, key), "places the sun: used only with sun, not with direction");
  } else if (js) {
    sun = sun_of(d, j, *js, p);
    if (sun) dir = -sun->towards;
  } else {
    d.error(p, "a directional light needs direction, or sun with up and north");
  }
  const bool clear_sky = sun && !d.member(j, "illuminance_lx") && !d.member(j, "irradiance_W_m2");
  const Total clear_sky_total{"illuminance_lx", true, sun ? sun->clear_sky_normal_illuminance_lx : 0};
  auto E = uniform_irradiance(d, j, p, "a directional light", dir.has_value(), clear_sky ? &clear_sky_total : nullptr);
  if (!E) return;
  DirectionalLight light{*dir, std::move(*E), std::nullopt};
  if (sun) {
    light.sun = sun->placement;
    light.sun->clear_sky_illuminance = clear_sky;
  }
  d.add_light(std::move(light), p);
}

}  // namespace lambert::codec
