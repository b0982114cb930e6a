// Goniometric source (SPEC §1): I(ψ) = I_0 cos^m ψ about its axis, zero for ψ > 90°; Warn's source
// is m = 1. Flux ∫ I dω = 2π I_0 / (m+1) (REFERENCES P2, P3, P7). Exponents 0 to 10⁶.
#include "solver/lights/point_like.h"

namespace lambert {
namespace {

class GoniometricLightModel final : public PointLikeLight {
 public:
  explicit GoniometricLightModel(const PointLight& light)
      : PointLikeLight(light, ConeLobe{light.axis, light.exponent, kPi / 2}) {}
  double flux_factor() const override { return 2 * kPi / (lobe().exponent + 1); }
};

}  // namespace

std::unique_ptr<LightModel> make_goniometric_light(const PointLight& light) {
  return std::make_unique<GoniometricLightModel>(light);
}

}  // namespace lambert
