#include "server/codec/thermal.h"

namespace lambert::codec {

std::optional<SurfaceThermal> decode_thermal(Decoder& d, const json& j, const std::string& p,
                                             std::optional<double> default_emissivity) {
  if (!d.object(j, p, {"emissivity", "temperature_K", "net_flux_W_m2"})) return std::nullopt;
  SurfaceThermal t;
  bool ok = true;
  if (const json* e = d.member(j, "emissivity")) {
    const auto v = d.number_in(*e, p + "/emissivity", 0, true, 1, true);
    ok = ok && v.has_value();
    if (v) t.emissivity = *v;
  } else if (default_emissivity) {
    t.emissivity = *default_emissivity;
  } else {
    d.error(p, "\"emissivity\" is required (the surface's total hemispherical emissivity, in [0, 1])");
    ok = false;
  }
  const json* temperature = d.member(j, "temperature_K");
  const json* flux = d.member(j, "net_flux_W_m2");
  if ((temperature != nullptr) == (flux != nullptr)) {
    d.error(p, temperature ? "give \"temperature_K\" or \"net_flux_W_m2\", not both"
                           : "give the surface's \"temperature_K\" or its \"net_flux_W_m2\" (0: reradiating)");
    return std::nullopt;
  }
  if (temperature) {
    const auto v = d.number_in(*temperature, p + "/temperature_K", 0, false, kMaxTemperatureK, true);
    if (!v) return std::nullopt;
    t.temperature_K = *v;
  } else {
    const auto v = d.number_in(*flux, p + "/net_flux_W_m2", -kMaxNetFluxWm2, true, kMaxNetFluxWm2, true);
    if (!v) return std::nullopt;
    if (ok && *v != 0 && t.emissivity == 0) {
      d.error(p + "/net_flux_W_m2", "a surface of emissivity 0 neither emits nor absorbs: its net flux is 0, not " +
                                        num(*v));
      return std::nullopt;
    }
    t.net_flux_W_m2 = *v;
  }
  return ok ? std::optional<SurfaceThermal>(t) : std::nullopt;
}

void check_thermal_everywhere(Decoder& d) {
  const std::vector<Surface>& surfaces = d.scene().surfaces;
  const Surface* with = nullptr;
  for (const Surface& s : surfaces)
    if (s.thermal && !with) with = &s;
  if (!with) return;
  for (const Surface& s : surfaces)
    if (!s.thermal)
      d.error(s.pointer, "\"thermal\" is needed on every surface once one has it (\"" + with->name + "\" at " +
                             with->pointer + " has): the radiant exchange needs every surface's emissivity and "
                             "temperature or net flux");
}

}  // namespace lambert::codec
