// What places a light in the world (lights/light_types.h): the scene's "up" and "north", and
// "sun": {"latitude_deg", "longitude_deg", "time"} read into the sun's direction by NOAA's algorithm
// (solver/lights/solar_position.h). Shared by the sky and the directional light.
#include <cmath>
#include <string>

#include "server/codec/lights/light_types.h"
#include "solver/lights/solar_position.h"

namespace lambert::codec {
namespace {

// Unit vectors closer to perpendicular than this are taken as perpendicular (1e-6 rad); anything
// else is an error, not silently made perpendicular.
constexpr double kPerpendicular = 1e-6;

}  // namespace

std::optional<Horizon> decode_horizon(Decoder& d, const json& j, const std::string& p, bool north_required) {
  std::optional<Vector3> up, north;
  if (const json* ju = d.required(j, p, "up")) up = d.direction(*ju, p + "/up");
  const json* jn = north_required ? d.required(j, p, "north") : d.member(j, "north");
  if (jn) north = d.direction(*jn, p + "/north");
  if (!up || (jn && !north) || (north_required && !jn)) return std::nullopt;
  if (north && !(std::abs(dot(*up, *north)) <= kPerpendicular)) {
    d.error(p + "/north", "must be perpendicular to up (north·up = " + num(dot(*up, *north)) + ")");
    return std::nullopt;
  }
  return Horizon{*up, north};
}

std::optional<SunAt> decode_sun(Decoder& d, const json& js, const std::string& ps, const Horizon* horizon) {
  if (!d.object(js, ps, {"latitude_deg", "longitude_deg", "time"})) return std::nullopt;
  const json* jlat = d.required(js, ps, "latitude_deg");
  const json* jlon = d.required(js, ps, "longitude_deg");
  const json* jtime = d.required(js, ps, "time");
  std::optional<double> latitude, longitude;
  std::optional<std::string> time;
  if (jlat) latitude = d.number_in(*jlat, ps + "/latitude_deg", -90, true, 90, true);
  if (jlon) longitude = d.number_in(*jlon, ps + "/longitude_deg", -180, true, 180, true);
  if (jtime) time = d.string(*jtime, ps + "/time");
  std::optional<Instant> instant;
  if (time) {
    std::string why;
    instant = parse_iso8601(*time, &why);
    if (!instant) d.error(ps + "/time", quote_text(*time) + " is not an ISO 8601 time with an offset: " + why);
  }
  if (!latitude || !longitude || !instant || !horizon || !horizon->north) return std::nullopt;
  const SolarPosition position = solar_position(instant->julian_day_ut, *latitude, *longitude);
  SunAt out;
  out.placement = {*latitude, *longitude, *time, position.elevation_deg, position.azimuth_deg, false};
  out.towards = direction_to_sun(position, horizon->up, *horizon->north);
  out.clear_sky_normal_illuminance_lx = clear_sky_normal_illuminance_lx(position, instant->day_of_year);
  return out;
}

}  // namespace lambert::codec
