// Occluder planes (see occluder_planes.h).
#include "solver/occluder_planes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace lambert {
namespace {

// Classifying costs (distinct planes) × (distinct vertices) dot products; above this, rays are cheaper
// than finding out.
constexpr double kMaxClassificationWork = 3e7;

}  // namespace

OccluderPlanes::OccluderPlanes(std::span<const Triangle> triangles) {
  Bounds3 box;
  for (const Triangle& t : triangles)
    for (const Point3& p : t.v) box.add(p);
  if (box.empty()) {
    usable_ = true;
    return;
  }
  const double size = std::max(length(box.diagonal()), 1e-300);
  eps_ = 1e-9 * size;
  centre_ = box.center();  // planes and points relative to it: no cancellation at x ≈ 5e5
  const Point3& centre = centre_;

  // Distinct planes (the triangles of one flat face share theirs) and distinct vertices.
  std::map<std::tuple<long long, long long, long long, long long>, Plane> distinct_planes;
  std::map<std::tuple<long long, long long, long long>, Vector3> distinct_points;
  for (const Triangle& t : triangles) {
    const Vector3 area = t.area_vector();
    if (!(length(area) > 0)) continue;
    const Vector3 n = normalize(area);
    const double d = dot(n, t.v[0] - centre);
    auto q = [](double x, double unit) { return static_cast<long long>(std::llround(x / unit)); };
    distinct_planes.try_emplace({q(n.x, 1e-9), q(n.y, 1e-9), q(n.z, 1e-9), q(d, eps_)}, Plane{n, d});
    for (const Point3& p : t.v) {
      const Vector3 r = p - centre;
      distinct_points.try_emplace({q(r.x, eps_), q(r.y, eps_), q(r.z, eps_)}, r);
    }
  }
  if (static_cast<double>(distinct_planes.size()) * static_cast<double>(distinct_points.size()) > kMaxClassificationWork)
    return;  // not usable
  for (const auto& [key, plane] : distinct_planes) {
    const bool occludes = std::any_of(distinct_points.begin(), distinct_points.end(), [&](const auto& entry) {
      return dot(plane.n, entry.second) - plane.d < -eps_;  // some of the scene behind the plane
    });
    if (!occludes) continue;
    if (planes_.size() == static_cast<std::size_t>(kMaxPlanes)) {
      planes_.clear();
      return;  // not usable
    }
    planes_.push_back(plane);
  }
  for (std::size_t k = 0; k < planes_.size(); ++k) all_[k / 64] |= std::uint64_t{1} << (k % 64);
  usable_ = true;
}

OccluderPlanes::Sides OccluderPlanes::sides(std::span<const Point3> points) const {
  Sides s;
  for (std::size_t k = 0; k < planes_.size(); ++k) {
    bool front = true, behind = true;
    for (const Point3& p : points) {
      const double d = dot(planes_[k].n, p - centre_) - planes_[k].d;
      front &= d >= -eps_;
      behind &= d <= eps_;
    }
    if (front) s.front[k / 64] |= std::uint64_t{1} << (k % 64);
    if (behind) s.behind[k / 64] |= std::uint64_t{1} << (k % 64);
  }
  return s;
}

}  // namespace lambert
