// "type": "ambient": the same irradiance on every surface, from every direction (SPEC §1).
#include <utility>

#include "server/codec/lights/light_types.h"
#include "server/codec/spectra.h"

namespace lambert::codec {

void decode_ambient_light(Decoder& d, const json& j, const std::string& p, std::string_view) {
  d.unknown_keys(j, p, with_totals({"type", "irradiance"}));
  auto E = uniform_irradiance(d, j, p, "an ambient light", true);
  if (!E) return;
  d.add_light(AmbientLight{std::move(*E)}, p);
}

}  // namespace lambert::codec
