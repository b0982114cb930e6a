#include "server/export/corner_values.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <numbers>
#include <tuple>

namespace lambert {
namespace {

struct Corner {
  int surface;
  double x, y, z;
  std::size_t triangle;
  int k;
  auto key() const { return std::tie(surface, x, y, z); }
};

}  // namespace

std::vector<double> corner_values(const std::vector<Triangle>& triangles, const std::vector<int>& surface,
                                  const std::vector<double>& values, std::size_t stride, Shading shading) {
  const std::size_t N = triangles.size();
  if (values.size() != N * stride || (!surface.empty() && surface.size() != N))
    throw std::invalid_argument("corner_values: the values or surfaces do not match the triangles");
  std::vector<double> out(3 * N * stride);
  for (std::size_t i = 0; i < N; ++i)
    for (int k = 0; k < 3; ++k) std::copy_n(&values[i * stride], stride, &out[(3 * i + k) * stride]);
  if (shading == Shading::Flat) return out;

  std::vector<Vector3> normal(N);
  std::vector<double> area(N);
  std::vector<Corner> corners;
  corners.reserve(3 * N);
  for (std::size_t i = 0; i < N; ++i) {
    normal[i] = triangles[i].normal();
    area[i] = triangles[i].area();
    for (int k = 0; k < 3; ++k) {
      const Point3& p = triangles[i].v[k];
      corners.push_back({surface.empty() ? 0 : surface[i], p.x, p.y, p.z, i, k});
    }
  }
  std::sort(corners.begin(), corners.end(), [](const Corner& a, const Corner& b) { return a.key() < b.key(); });
  const double cos_crease = std::cos(kCreaseAngle_deg * std::numbers::pi / 180);
  std::vector<double> sum(stride);
  for (std::size_t first = 0; first < corners.size();) {
    std::size_t last = first + 1;
    while (last < corners.size() && corners[last].key() == corners[first].key()) ++last;
    for (std::size_t a = first; a < last; ++a) {
      const std::size_t i = corners[a].triangle;
      std::fill(sum.begin(), sum.end(), 0.0);
      double weight = 0;
      for (std::size_t b = first; b < last; ++b) {
        const std::size_t j = corners[b].triangle;
        if (dot(normal[i], normal[j]) < cos_crease) continue;
        for (std::size_t c = 0; c < stride; ++c) sum[c] += area[j] * values[j * stride + c];
        weight += area[j];
      }
      if (weight > 0)
        for (std::size_t c = 0; c < stride; ++c) out[(3 * i + corners[a].k) * stride + c] = sum[c] / weight;
    }
    first = last;
  }
  return out;
}

}  // namespace lambert
