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
          // Sample k = c'·16 + b'·4 + a with b = (b' + a) mod 4, c = (c' + b) mod 4: the first four
          // are the cells (a, a, a), i.e. the three corner cells and the centre cell, so a shadow
          // edge that crosses the triangle separates the first round's samples.
          const int b_rank = (b - a + 4) % 4, c_rank = (c - b + 4) % 4;
          out[c_rank * 16 + b_rank * 4 + a] = {centroid.x, centroid.y, centroid.z};
        }
      }
    }
    return out;
  }();
  return samples;
}

}  // namespace lambert
