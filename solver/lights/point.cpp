// Ideal isotropic point source (SPEC §1): I(ψ) = I_0 in every direction, E = I cos α / r² or, with an
// attenuation polynomial, E = I cos α / (c1 + c2 r + c3 r²). Flux 4π I_0 (REFERENCES P1, P6).
#include "solver/form_factor.h"
#include "solver/lights/point_like.h"

namespace lambert {
namespace {

class PointLightModel final : public PointLikeLight {
 public:
  explicit PointLightModel(const PointLight& light) : PointLikeLight(light, ConeLobe{{0, 0, -1}, 0, kPi}) {}
  double flux_factor() const override { return 4 * kPi; }

 protected:
  // 1/r²: ∫_T I cos α / r² dA = I Ω(T), exact whatever the distance (a light 1 µm above the patch).
  // Attenuated: the lobe is uniform, so the polar axis is free; about the patch's inward normal the
  // distance r = h / cos ψ depends on ψ alone, and the foot of the perpendicular is the pole.
  double patch_integral(const Triangle& t) const override {
    if (light().inverse_square) return triangle_solid_angle(light().position, t);
    return attenuated_cone_integral(t, ConeLobe{-t.normal(), 0, kPi});
  }
};

}  // namespace

std::unique_ptr<LightModel> make_point_light(const PointLight& light) {
  return std::make_unique<PointLightModel>(light);
}

}  // namespace lambert
