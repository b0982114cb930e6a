// make_light_model: the scene's Light variant to its model (one per file in solver/lights/).
#include "solver/light_model.h"

#include <stdexcept>

#include "solver/receiver_kernel.h"

namespace lambert {

double LightModel::receiver_factor(const Receiver& receiver, const Visibility& vis) const {
  if (receiver.kind == Receiver::Kind::Planar) return point_factor(receiver.point, receiver.normal, vis);
  return receiver_by_planes(receiver, [&](const Vector3& n) { return point_factor(receiver.point, n, vis); });
}

std::unique_ptr<LightModel> make_light_model(const Light& light, const LightContext&) {
  if (const auto* a = std::get_if<AmbientLight>(&light)) return make_ambient_light(*a);
  if (const auto* d = std::get_if<DirectionalLight>(&light)) return make_directional_light(*d);
  const PointLight& p = std::get<PointLight>(light);
  switch (p.kind) {
    case PointLight::Kind::Point: return make_point_light(p);
    case PointLight::Kind::Goniometric:
    case PointLight::Kind::Warn: return make_goniometric_light(p);
    case PointLight::Kind::Spot: return make_spot_light(p);
  }
  throw std::logic_error("make_light_model: unhandled PointLight::Kind");  // a bug, not bad input
}

}  // namespace lambert
