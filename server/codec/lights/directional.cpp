// "type": "directional": a parallel beam (the sun as seen from the scene), given by the direction
// it travels and its irradiance on a plane perpendicular to it (SPEC §1).
#include <utility>

#include "server/codec/lights/light_types.h"
#include "server/codec/spectra.h"

namespace lambert::codec {

void decode_directional_light(Decoder& d, const json& j, const std::string& p, std::string_view) {
  d.unknown_keys(j, p, with_totals({"type", "direction", "irradiance"}));
  std::optional<Vector3> dir;
  if (const json* jd = d.required(j, p, "direction")) dir = d.direction(*jd, p + "/direction");
  auto E = uniform_irradiance(d, j, p, "a directional light", dir.has_value());
  if (!E) return;
  d.add_light(DirectionalLight{*dir, std::move(*E)}, p);
}

}  // namespace lambert::codec
