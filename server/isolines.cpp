#include "server/isolines.h"

#include <cmath>
#include <stdexcept>

namespace lambert {

std::vector<Segment2> isolines(const std::vector<double>& values, int nu, int nv, double level) {
  if (nu < 1 || nv < 1 || values.size() != static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv))
    throw std::invalid_argument("isolines: expected nu × nv values");
  std::vector<Segment2> out;
  auto at = [&](int i, int j) { return values[static_cast<std::size_t>(j) * nu + i]; };
  for (int j = 0; j + 1 < nv; ++j)
    for (int i = 0; i + 1 < nu; ++i) {
      // Corners counter-clockwise from (i, j); edge k runs from corner k to corner k + 1.
      const Point2 p[4] = {{double(i), double(j)}, {i + 1.0, double(j)}, {i + 1.0, j + 1.0}, {double(i), j + 1.0}};
      const double v[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !std::isfinite(v[3])) continue;
      bool above[4];
      for (int k = 0; k < 4; ++k) above[k] = v[k] >= level;
      Point2 crossing[4];
      bool crosses[4];
      int count = 0;
      for (int k = 0; k < 4; ++k) {
        const int n = (k + 1) % 4;
        crosses[k] = above[k] != above[n];
        if (!crosses[k]) continue;
        const double t = (level - v[k]) / (v[n] - v[k]);
        crossing[k] = {p[k].x + t * (p[n].x - p[k].x), p[k].y + t * (p[n].y - p[k].y)};
        ++count;
      }
      if (count == 2) {
        int first = -1, second = -1;
        for (int k = 0; k < 4; ++k)
          if (crosses[k]) (first < 0 ? first : second) = k;
        out.push_back({crossing[first], crossing[second]});
      } else if (count == 4) {
        // Cut off the two corners on the other side from the centre: corner k lies between edges
        // k − 1 and k.
        const bool centre_above = (v[0] + v[1] + v[2] + v[3]) / 4 >= level;
        for (int k = 0; k < 4; ++k)
          if (above[k] != centre_above) out.push_back({crossing[(k + 3) % 4], crossing[k]});
      }
    }
  return out;
}

}  // namespace lambert
