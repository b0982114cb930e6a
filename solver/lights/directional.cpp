// Directional (parallel) light (SPEC §1): E = E_q max(0, cos α), with E_q the irradiance on a plane
// perpendicular to the beam (a receiver: E_q w(−direction), receiver.h); shadowed by rays towards the light that leave the scene.
#include <algorithm>

#include "solver/light_model.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

class DirectionalLightModel final : public LightModel {
 public:
  explicit DirectionalLightModel(const DirectionalLight& light) : light_(light) {}
  const std::vector<double>& spectrum() const override { return light_.irradiance_W_m2_nm; }

  double unshadowed_factor(const Point3&, const Vector3& n) const override {
    return std::max(0.0, -dot(n, light_.direction));
  }

  double point_factor(const Point3& p, const Vector3& n, const Visibility& vis) const override {
    const double g = unshadowed_factor(p, n);
    return g != 0 ? g * vis.transmitted(p, p + reach(vis)) : 0;
  }

  double receiver_factor(const Receiver& r, const Visibility& vis) const override {
    const double g = receiver_weight(r, -light_.direction);
    return g != 0 ? g * vis.transmitted(r.point, r.point + reach(vis)) : 0;
  }

  // cos α is constant over a planar patch: the average is cos α times the visible fraction.
  double patch_factor(const Triangle& t, const Visibility& vis) const override {
    const double g = unshadowed_factor(t.v[0], t.normal());
    if (g == 0) return 0;
    const Vector3 r = reach(vis);
    return g * weighted_visible_fraction(
                   vis, [&](int k) { const Point3 p = visibility_sample(t, k); return std::pair{p, p + r}; },
                   [](const Point3&, const Point3&) { return 1.0; });
  }

  double flux_factor() const override { return 0; }
  std::string_view kind() const override { return "directional"; }

 private:
  // A segment towards the light long enough to leave the scene (Embree works re-centred).
  Vector3 reach(const Visibility& vis) const { return -light_.direction * vis.scene_extent(); }
  DirectionalLight light_;
};

}  // namespace

std::unique_ptr<LightModel> make_directional_light(const DirectionalLight& light) {
  return std::make_unique<DirectionalLightModel>(light);
}

}  // namespace lambert
