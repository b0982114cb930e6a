// "lights" (SPEC §1): an array of light objects, each decoded by the decoder of its "type".
#include <array>

#include "server/codec/lights/light_types.h"
#include "server/codec/sections.h"

namespace lambert::codec {
namespace {

struct LightType {
  std::string_view name;  // the "type" of the scene format
  LightDecoder decode;
};

// One row per light type; the order is the order of the "expected ..." list in messages.
constexpr std::array kLightTypes = {
    LightType{"ambient", decode_ambient_light},
    LightType{"directional", decode_directional_light},
    LightType{"point", decode_point_like_light},
    LightType{"goniometric", decode_point_like_light},
    LightType{"spot", decode_point_like_light},
    LightType{"warn", decode_point_like_light},
    LightType{"sky", decode_sky_light},
    LightType{"luminaire", decode_luminaire_light},
};

void decode_light(Decoder& d, const json& j, std::size_t i) {
  const std::string p = index_ptr("/lights", i);
  if (!j.is_object()) {
    d.error(p, "expected an object, got " + a_type(j));
    return;
  }
  const json* jtype = d.required(j, p, "type");
  if (!jtype) return;
  auto type = d.string(*jtype, p + "/type");
  if (!type) return;
  for (const LightType& t : kLightTypes)
    if (t.name == *type) return t.decode(d, j, p, t.name);
  std::vector<std::string_view> names;
  for (const LightType& t : kLightTypes) names.push_back(t.name);
  d.error(p + "/type", "unknown light type " + quote_text(*type) + "; expected " +
                           join(names, " or ") + suggestion(*type, names));
}

}  // namespace

void decode_lights(Decoder& d, const json& doc) {
  const json* lights = d.member(doc, "lights");
  if (!lights || !d.array(*lights, "/lights")) return;
  for (std::size_t i = 0; i < lights->size(); ++i) decode_light(d, (*lights)[i], i);
}

}  // namespace lambert::codec
