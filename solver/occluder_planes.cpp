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

OccluderPlanes::OccluderPlanes(std::span<const Triangle> triangles, std::span<const Point3> receivers) {
  Bounds3 box;
  for (const Triangle& t : triangles)
    for (const Point3& p : t.v) box.add(p);
  for (const Point3& p : receivers) box.add(p);
  if (box.empty()) {
    usable_ = true;
    return;
  }
  const double size = std::max(length(box.diagonal()), 1e-300);
  eps_ = 1e-9 * size;
  centre_ = box.center();  // planes and points relative to it: no cancellation at x ≈ 5e5

  // Distinct planes (the triangles of one flat face share theirs), with the vertices of their
  // triangles, and distinct vertices of the scene.
  struct Candidate {
    Plane plane;
    std::vector<Vector3> vertices;
  };
  std::map<PlaneKey, Candidate> distinct_planes;
  std::map<std::tuple<long long, long long, long long>, Vector3> distinct_points;
  auto q = [](double x, double unit) { return static_cast<long long>(std::llround(x / unit)); };
  for (const Triangle& t : triangles) {
    const Vector3 area = t.area_vector();
    if (!(length(area) > 0)) continue;
    const Vector3 n = normalize(area);
    const double d = dot(n, t.v[0] - centre_);
    Candidate& c = distinct_planes.try_emplace(plane_key(n, d, eps_), Candidate{Plane{n, d}, {}}).first->second;
    for (const Point3& p : t.v) {
      const Vector3 r = p - centre_;
      c.vertices.push_back(r);
      distinct_points.try_emplace({q(r.x, eps_), q(r.y, eps_), q(r.z, eps_)}, r);
    }
  }
  for (const Point3& p : receivers) {
    const Vector3 r = p - centre_;
    distinct_points.try_emplace({q(r.x, eps_), q(r.y, eps_), q(r.z, eps_)}, r);
  }
  if (static_cast<double>(distinct_planes.size()) * static_cast<double>(distinct_points.size()) > kMaxClassificationWork)
    return;  // not usable
  for (const auto& [key, c] : distinct_planes) {
    const Plane& plane = c.plane;
    const bool occludes = std::any_of(distinct_points.begin(), distinct_points.end(), [&](const auto& entry) {
      return dot(plane.n, entry.second) - plane.d < -eps_;  // some of the scene behind the plane
    });
    if (!occludes) continue;
    if (groups_.size() == static_cast<std::size_t>(kMaxGroups)) {
      groups_.clear();
      return;  // not usable
    }
    // The bounding rectangle of the plane's triangles in an orthonormal frame (u, v) of the plane.
    const Vector3 u = perpendicular(plane.n);
    const Vector3 v = cross(plane.n, u);
    double lo_u = 1e300, hi_u = -1e300, lo_v = 1e300, hi_v = -1e300;
    for (const Vector3& r : c.vertices) {
      lo_u = std::min(lo_u, dot(u, r)), hi_u = std::max(hi_u, dot(u, r));
      lo_v = std::min(lo_v, dot(v, r)), hi_v = std::max(hi_v, dot(v, r));
    }
    groups_.push_back({plane, {Plane{u, hi_u}, Plane{-u, -lo_u}, Plane{v, hi_v}, Plane{-v, -lo_v}}});
  }
  for (std::size_t g = 0; g < groups_.size(); ++g) low_bits_[g / 8] |= std::uint64_t{1} << (8 * (g % 8));
  words_ = static_cast<int>((groups_.size() + 7) / 8);
  usable_ = true;
}

OccluderPlanes::Sides OccluderPlanes::sides(std::span<const Point3> points) const {
  Sides s;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const Group& group = groups_[g];
    const int word = static_cast<int>(g / 8), shift = static_cast<int>(8 * (g % 8));
    bool front = true, behind = true;
    std::array<bool, 4> outside = {true, true, true, true};
    for (const Point3& p : points) {
      const Vector3 r = p - centre_;
      const double d = dot(group.plane.n, r) - group.plane.d;
      front &= d >= -eps_;
      behind &= d <= eps_;
      for (int k = 0; k < 4; ++k) outside[k] = outside[k] && dot(group.sides[k].n, r) - group.sides[k].d >= -eps_;
    }
    std::uint64_t byte = front ? 1 : 0;
    for (int k = 0; k < 4; ++k) byte |= outside[k] ? std::uint64_t{2} << k : 0;
    s.front[word] |= byte << shift;
    if (behind) s.behind[word] |= std::uint64_t{1} << shift;
  }
  return s;
}

}  // namespace lambert
