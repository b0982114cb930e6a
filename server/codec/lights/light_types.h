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

// The "irradiance" spectrum of a light that delivers the same irradiance everywhere, scaled by its
// illuminance_lx or irradiance_W_m2 if given (source names the light for messages). nullopt after
// an error, or when the caller's own parameters failed (parameters_ok): then nothing is scaled.
std::optional<std::vector<double>> uniform_irradiance(Decoder& d, const json& j,
                                                      const std::string& p,
                                                      std::string_view source, bool parameters_ok);

}  // namespace lambert::codec
