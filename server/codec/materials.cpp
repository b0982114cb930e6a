// "materials" (SPEC §1): name -> diffuse reflectance spectrum, an optional Phong lobe and, for glazing,
// a transmittance and how the pane transmits.
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <variant>

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

// "transmittance" with "transmission" (SPEC §5 "Glazing"): τ(λ) at normal incidence, and what is
// neither reflected nor transmitted is absorbed, so β + τ ≤ 1 at every wavelength.
void decode_transmission(Decoder& d, const json& m, const std::string& p, Material& material) {
  const json* t = d.member(m, "transmittance");
  const json* kind = d.member(m, "transmission");
  if (!t && !kind) return;
  if (!t) {
    d.error(p + "/transmission", "needs \"transmittance\" (the pane's normal-incidence spectrum)");
    return;
  }
  if (!kind) {
    d.error(p, "\"transmittance\" needs \"transmission\": \"specular\" (clear glass) or \"diffuse\" (opal glass)");
    return;
  }
  if (*kind == "diffuse") material.transmission = Transmission::kDiffuse;
  else if (*kind == "specular") material.transmission = Transmission::kSpecular;
  else {
    d.error(p + "/transmission", "expected \"specular\" or \"diffuse\", got " + kind->dump());
    return;
  }
  auto tau = spectrum(d, *t, p + "/transmittance", SpectrumRole::Reflectance);
  if (!tau) return;
  const WavelengthGrid* grid = d.grid();
  for (std::size_t k = 0; grid && k < tau->size() && k < material.reflectance.size(); ++k)
    if (material.reflectance[k] + (*tau)[k] > 1 + 1e-12) {
      d.error(p + "/transmittance", "reflectance + transmittance is " + num(material.reflectance[k] + (*tau)[k]) +
                                        " at " + num(grid->nm[k]) + " nm: a pane cannot give out more than it receives");
      return;
    }
  material.transmittance = std::move(*tau);
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
    if (!d.object(m, p, {"reflectance", "specular", "transmittance", "transmission"})) {
      scene.materials.push_back(std::move(material));
      continue;
    }
    if (const json* r = d.required(m, p, "reflectance"))
      if (auto s = spectrum(d, *r, p + "/reflectance", SpectrumRole::Reflectance))
        material.reflectance = std::move(*s);
    // The Phong lobe only affects rendered images (SPEC §1; `lambert render`).
    if (const json* sp = d.member(m, "specular"))
      material.specular = specular_lobe(d, *sp, p + "/specular");
    decode_transmission(d, m, p, material);
    scene.materials.push_back(std::move(material));
  }
}

void check_clear_glass(Decoder& d) {
  const Scene& scene = d.scene();
  if (std::none_of(scene.lights.begin(), scene.lights.end(),
                   [](const Light& l) { return std::holds_alternative<SkyLight>(l); }))
    return;
  // The sky through clear glass is weighted by g of the angle to the panes' normal over the window
  // (solver/lights/sky_dome.h): one normal per clear material.
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    if (scene.materials[m].transmission != Transmission::kSpecular) continue;
    std::optional<Vector3> normal;
    for (const Surface& s : scene.surfaces) {
      if (s.material != static_cast<int>(m)) continue;
      for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) {
        const Vector3 n = s.mesh.triangle(t).normal();
        if (!normal) normal = n;
        if (std::abs(dot(n, *normal)) < 1 - 1e-9) {
          d.error(key_ptr("/materials", scene.materials[m].name) + "/transmission",
                  "the sky through clear glass needs the panes of one material parallel; " + s.pointer +
                      " is not parallel to the others (give each orientation a material of its own)");
          return;
        }
      }
    }
  }
}

}  // namespace lambert::codec
