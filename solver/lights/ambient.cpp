// Ambient light (SPEC §1): E = E_a on every surface, whatever its orientation or position, and never
// shadowed. g = 1, for every receiver too: an irradiance E_a on every plane whatever its normal is a
// uniform radiance E_a/π, and each receiver's weight integrates to π over the sphere (receiver.h:
// ∫ sin θ dω = π², ∫ (1 + n·ω)/4 dω = π). The flux it brings depends on the scene it falls on (flux_factor 0).
#include "solver/light_model.h"

namespace lambert {
namespace {

class AmbientLightModel final : public LightModel {
 public:
  explicit AmbientLightModel(const AmbientLight& light) : light_(light) {}
  const std::vector<double>& spectrum() const override { return light_.irradiance_W_m2_nm; }
  double unshadowed_factor(const Point3&, const Vector3&) const override { return 1; }
  double point_factor(const Point3&, const Vector3&, const Visibility&) const override { return 1; }
  double receiver_factor(const Receiver&, const Visibility&) const override { return 1; }
  double patch_factor(const Triangle&, const Visibility&) const override { return 1; }
  double flux_factor() const override { return 0; }
  std::string_view kind() const override { return "ambient"; }
  bool directionless() const override { return true; }

 private:
  AmbientLight light_;
};

}  // namespace

std::unique_ptr<LightModel> make_ambient_light(const AmbientLight& light) {
  return std::make_unique<AmbientLightModel>(light);
}

}  // namespace lambert
