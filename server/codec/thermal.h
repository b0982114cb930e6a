// "thermal" (SPEC §5): a surface's grey, total thermal radiation for the radiant exchange
// (solver/thermal/grey_exchange.h): its emissivity and exactly one of a temperature or a net flux.
// Read in scenes (on each surface) and in the thermal files of `lambert viewfactors --thermal`.
#pragma once

#include <optional>

#include "server/codec/decoder.h"

namespace lambert::codec {

// The temperature limit: far above any surface a view-factor user models, far below where σ T⁴
// overflows.
constexpr double kMaxTemperatureK = 1e5;
constexpr double kMaxNetFluxWm2 = 1e12;

// `emissivity` may be absent where `default_emissivity` gives it (a View3D file's surface has its
// own); otherwise it is required.
std::optional<SurfaceThermal> decode_thermal(Decoder& d, const json& j, const std::string& p,
                                             std::optional<double> default_emissivity = std::nullopt);

// Every surface has "thermal" once one has: reports each that has none.
void check_thermal_everywhere(Decoder& d);

}  // namespace lambert::codec
