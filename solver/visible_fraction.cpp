#include "solver/visible_fraction.h"

#include "solver/cubature.h"

namespace lambert {

const std::array<std::array<double, 3>, kMaxVisibilitySamples>& triangle_visibility_samples() {
  static const auto samples = [] {
    const Triangle unit{{Point3{1, 0, 0}, Point3{0, 1, 0}, Point3{0, 0, 1}}};
    std::array<std::array<double, 3>, kMaxVisibilitySamples> out{};
    const auto level1 = split4(unit);
    for (int a = 0; a < 4; ++a) {
      const auto level2 = split4(level1[a]);
      for (int b = 0; b < 4; ++b) {
        const auto level3 = split4(level2[b]);
        for (int c = 0; c < 4; ++c) {
          const Point3 centroid = level3[c].centroid();  // barycentric coordinates of `unit`
          out[c * 16 + b * 4 + a] = {centroid.x, centroid.y, centroid.z};
        }
      }
    }
    return out;
  }();
  return samples;
}

}  // namespace lambert
