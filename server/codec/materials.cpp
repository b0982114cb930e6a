// "materials" (SPEC §1): name -> diffuse reflectance spectrum and an optional Phong lobe.
#include <utility>

#include "server/codec/sections.h"
#include "server/codec/spectra.h"

namespace lambert::codec {
namespace {

std::optional<SpecularLobe> specular_lobe(Decoder& d, const json& j, const std::string& p) {
  if (!d.object(j, p, {"coefficient", "exponent", "reflectance"})) return std::nullopt;
  SpecularLobe lobe;
  if (const json* c = d.required(j, p, "coefficient"))
    if (auto v = d.number_in(*c, p + "/coefficient", 0, true, 1, true)) lobe.coefficient = *v;
  if (const json* e = d.required(j, p, "exponent"))
    if (auto v = d.number_in(*e, p + "/exponent", 0, true, INFINITY, false)) lobe.exponent = *v;
  lobe.reflectance.assign(d.scene().grid.size(), 1.0);
  if (const json* r = d.member(j, "reflectance"))
    if (auto v = spectrum(d, *r, p + "/reflectance", SpectrumRole::Reflectance))
      lobe.reflectance = std::move(*v);
  return lobe;
}

}  // namespace

void decode_materials(Decoder& d, const json& doc) {
  const json* mats = d.required(doc, "", "materials");
  if (!mats) return;
  if (!mats->is_object()) {
    d.error("/materials", "expected an object (material name -> material), got " + a_type(*mats));
    return;
  }
  if (mats->empty()) {
    d.error("/materials", "must define at least one material");
    return;
  }
  Scene& scene = d.scene();
  for (const auto& [name, m] : mats->items()) {
    const std::string p = key_ptr("/materials", name);
    d.material_index()[name] = static_cast<int>(scene.materials.size());
    Material material;
    material.name = name;
    if (name.empty()) d.error(p, "a material name must not be empty");
    if (!d.object(m, p, {"reflectance", "specular"})) {
      scene.materials.push_back(std::move(material));
      continue;
    }
    if (const json* r = d.required(m, p, "reflectance"))
      if (auto s = spectrum(d, *r, p + "/reflectance", SpectrumRole::Reflectance))
        material.reflectance = std::move(*s);
    // The Phong lobe only affects rendered images (SPEC §1; `lambert render`).
    if (const json* sp = d.member(m, "specular"))
      material.specular = specular_lobe(d, *sp, p + "/specular");
    scene.materials.push_back(std::move(material));
  }
}

}  // namespace lambert::codec
