// Spotlight (SPEC §1): I(ψ) = I_0 cos^m ψ inside the cutoff cone ψ ≤ ψ_c, zero beyond (and beyond 90°
// when m > 0; an m = 0 spot is a uniform cone, which may be wider than a hemisphere). Flux
// 2π I_0 (1 − cos^{m+1} ψ_c)/(m+1); for m = 0, 2π I_0 (1 − cos ψ_c) (REFERENCES P4). The cutoff edge
// across a patch is integrated exactly: the cone integral clamps each azimuth's band at ψ_c and
// breaks its outer integral where the patch's edges cross the cone.
#include <algorithm>

#include "solver/lights/point_like.h"

namespace lambert {
namespace {

class SpotLightModel final : public PointLikeLight {
 public:
  explicit SpotLightModel(const PointLight& light)
      : PointLikeLight(light, ConeLobe{light.axis, light.exponent,
                                       light.exponent > 0 ? std::min(light.cutoff_rad, kPi / 2)
                                                          : light.cutoff_rad}) {}
  double flux_factor() const override { return cone_lobe_flux(lobe()); }
};

}  // namespace

std::unique_ptr<LightModel> make_spot_light(const PointLight& light) {
  return std::make_unique<SpotLightModel>(light);
}

}  // namespace lambert
