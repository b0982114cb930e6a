// The irradiance spectrum shared by ambient and directional lights (lights/light_types.h).
#include "server/codec/lights/light_types.h"
#include "server/codec/spectra.h"

namespace lambert::codec {

std::optional<std::vector<double>> uniform_irradiance(Decoder& d, const json& j,
                                                      const std::string& p,
                                                      std::string_view source, bool parameters_ok,
                                                      const Total* fallback) {
  std::optional<std::vector<double>> E;
  if (const json* e = d.required(j, p, "irradiance"))
    E = spectrum(d, *e, p + "/irradiance", SpectrumRole::Emission);
  const auto t = total(d, j, p, {"illuminance_lx", "irradiance_W_m2"}, source);
  if (!E || !parameters_ok) return std::nullopt;
  // The total is the irradiance itself (geometric factor 1): on every plane for an ambient light,
  // on a plane perpendicular to the beam for a directional one.
  const Total* scale = t ? &*t : fallback;
  if (scale && !scale_to_total(d, *E, *scale, 1.0, p + "/irradiance")) return std::nullopt;
  return E;
}

}  // namespace lambert::codec
