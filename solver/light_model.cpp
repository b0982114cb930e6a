// make_light_model: the scene's Light variant to its model (one per file in solver/lights/).
#include "solver/light_model.h"

#include <algorithm>
#include <stdexcept>

#include "solver/glazing.h"
#include "solver/receiver_kernel.h"

namespace lambert {

double LightModel::receiver_factor(const Receiver& receiver, const Visibility& vis) const {
  if (receiver.kind == Receiver::Kind::Planar) return point_factor(receiver.point, receiver.normal, vis);
  return receiver_by_planes(receiver, [&](const Vector3& n) { return point_factor(receiver.point, n, vis); });
}

std::unique_ptr<LightModel> make_light_model(const Light& light, const LightContext& context) {
  if (const auto* a = std::get_if<AmbientLight>(&light)) return make_ambient_light(*a);
  if (const auto* d = std::get_if<DirectionalLight>(&light)) return make_directional_light(*d);
  if (const auto* s = std::get_if<SkyLight>(&light)) return make_sky_light(*s, context);
  if (const auto* l = std::get_if<LuminaireLight>(&light)) return make_luminaire_light(*l);
  const PointLight& p = std::get<PointLight>(light);
  switch (p.kind) {
    case PointLight::Kind::Point: return make_point_light(p);
    case PointLight::Kind::Goniometric:
    case PointLight::Kind::Warn: return make_goniometric_light(p);
    case PointLight::Kind::Spot: return make_spot_light(p);
  }
  throw std::logic_error("make_light_model: unhandled PointLight::Kind");  // a bug, not bad input
}

SceneLightContext::SceneLightContext(const Scene& scene) {
  const bool needed = std::any_of(scene.lights.begin(), scene.lights.end(),
                                  [](const Light& l) { return std::holds_alternative<SkyLight>(l); });
  if (needed) {
    const std::vector<int> channel = clear_glass_channels(scene);
    const bool clear = std::any_of(channel.begin(), channel.end(), [](int c) { return c >= 0; });
    for (const Surface& s : scene.surfaces)
      for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) {
        triangles_.push_back(s.mesh.triangle(t));
        if (clear) pane_channel_.push_back(channel[s.material]);
      }
    solids_ = outward_solids(scene.surfaces);
    context_.solids = &solids_;
    context_.pane_channel = pane_channel_;
  }
  context_.occluders = triangles_;
  context_.has_scene = true;
}

std::vector<std::unique_ptr<LightModel>> make_scene_light_models(const Scene& scene) {
  const SceneLightContext lights(scene);
  std::vector<std::unique_ptr<LightModel>> out;
  for (const Light& light : scene.lights) out.push_back(make_light_model(light, lights.context()));
  return out;
}

}  // namespace lambert
