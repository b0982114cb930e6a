// The light types of "lights" (SPEC §1 "Light models"). Each type has its own decoder that reads
// and checks its own parameters and adds the light to the scene; lights/dispatch.cpp picks the
// decoder by "type". A new type is a new file here, its declaration below and one row in
// kLightTypes (dispatch.cpp).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/codec/decoder.h"
#include "server/codec/spectra.h"

namespace lambert::codec {

// j: the light's object (its "type" already read: type), p: its pointer. Reports every problem at
// its pointer; adds the light (Decoder::add_light) only when there was none. A family of types may
// share one decoder and tell its members apart by type.
using LightDecoder = void (*)(Decoder& d, const json& j, const std::string& p,
                              std::string_view type);

void decode_ambient_light(Decoder& d, const json& j, const std::string& p, std::string_view type);
void decode_directional_light(Decoder& d, const json& j, const std::string& p,
                              std::string_view type);
// point, goniometric, spot and warn: I(ψ) = I_0 cos^m ψ about an axis (point_like.cpp).
void decode_point_like_light(Decoder& d, const json& j, const std::string& p,
                             std::string_view type);
// sky: a CIE sky over a uniform ground (sky.cpp).
void decode_sky_light(Decoder& d, const json& j, const std::string& p, std::string_view type);

// The scene's "up" and "north" (unit, perpendicular; sun.cpp): where a light needs the horizon and
// the compass. "up" is required; "north" where north_required (else read and checked if given).
struct Horizon {
  Vector3 up;
  std::optional<Vector3> north;
};
std::optional<Horizon> decode_horizon(Decoder& d, const json& j, const std::string& p, bool north_required);

// "sun": {"latitude_deg", "longitude_deg", "time"} (js at pointer ps; sun.cpp): the sun's position at
// that place and instant (NOAA), the unit direction towards it in the scene (horizon: its up and
// north; nullptr or no north: the position is checked but not placed), and the clear-sky normal
// illuminance there (solar_position.h). nullopt after an error.
struct SunAt {
  SunPlacement placement;
  Vector3 towards;
  double clear_sky_normal_illuminance_lx = 0;
};
std::optional<SunAt> decode_sun(Decoder& d, const json& js, const std::string& ps, const Horizon* horizon);

// A luminaire from an IES LM-63 or EULUMDAT file (luminaire.cpp).
void decode_luminaire_light(Decoder& d, const json& j, const std::string& p, std::string_view type);

// The "irradiance" spectrum of a light that delivers the same irradiance everywhere, scaled by its
// illuminance_lx or irradiance_W_m2 if given, else by `fallback` if given (source names the light
// for messages). nullopt after an error, or when the caller's own parameters failed
// (parameters_ok): then nothing is scaled.
std::optional<std::vector<double>> uniform_irradiance(Decoder& d, const json& j,
                                                      const std::string& p,
                                                      std::string_view source, bool parameters_ok,
                                                      const Total* fallback = nullptr);

}  // namespace lambert::codec
