// Shaft culling over the occluders of ExactVisibility (exact_visibility.h): which occluders lie
// between two patches, and whether one convex solid hides them from each other wholly.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "solver/exact_visibility_impl.h"

namespace lambert {
namespace {

// The convex hull of up to 16 points shrunk by 1e-9 of its size, as half-spaces (its faces: planes
// through three points with every point on one side, by brute force), relative to `shift`. Empty
// where the points span no volume (then nothing can be inside), or no extent at all.
void shaft_region(std::span<const Point3> points_world, const Vector3& shift, std::vector<HalfSpace>& region) {
  region.clear();
  std::array<Point3, 16> p;
  const int n = static_cast<int>(std::min<std::size_t>(points_world.size(), p.size()));
  Bounds3 box;
  for (int i = 0; i < n; ++i) box.add(p[i] = points_world[i] - shift);
  const double size = length(box.diagonal());
  if (!(size > 0)) return;
  const double margin = 1e-9 * size;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        Vector3 normal = cross(p[j] - p[i], p[k] - p[i]);
        const double len = length(normal);
        if (!(len > 1e-12 * size * size)) continue;
        normal = normal / len;
        int above = 0, below = 0;
        for (int m = 0; m < n; ++m) {
          const double d = dot(normal, p[m] - p[i]);
          above += d > margin;
          below += d < -margin;
        }
        if (above > 0 && below > 0) continue;
        if (above == 0 && below == 0) continue;  // every point in this plane
        const HalfSpace face{above > 0 ? normal : -normal, p[i], margin};
        const bool known = std::any_of(region.begin(), region.end(), [&](const HalfSpace& h) {
          return dot(h.normal, face.normal) > 1 - 1e-12 && std::abs(h.signed_distance(p[i]) + margin) <= margin;
        });
        if (!known) region.push_back(face);
      }
}

}  // namespace

bool ExactVisibility::shaft_is_clear(std::span<const Point3> points) const {
  thread_local std::vector<HalfSpace> region;
  shaft_region(points, to_vector(impl_->centre), region);
  if (region.empty()) return true;  // flat: nothing can be inside
  return !impl_->query(region, [&](int k) { return impl_->meets(k, region); });
}

void ExactVisibility::shaft_occluders(std::span<const Point3> points, std::vector<int>& out) const {
  out.clear();
  thread_local std::vector<HalfSpace> region;
  shaft_region(points, to_vector(impl_->centre), region);
  if (region.empty()) return;
  impl_->query(region, [&](int k) {
    if (impl_->meets(k, region)) out.push_back(k);
    return false;
  });
}

std::size_t ExactVisibility::occluders_near_box(const Bounds3& box) const {
  const Impl::Grid& g = impl_->grid;
  if (g.table.empty()) return 0;
  const Vector3 shift = to_vector(impl_->centre);
  std::array<int, 3> lo, hi;
  for (int a = 0; a < 3; ++a) {
    const double first = std::floor(((box.lo - shift)[a] - g.origin[a]) / g.cell[a]);
    const double last = std::floor(((box.hi - shift)[a] - g.origin[a]) / g.cell[a]);
    if (!(last >= 0 && first <= g.n[a] - 1)) return 0;  // beside the grid: no centroid is near
    // The cells the box meets, less one below (the table's prefix sums are 1-based).
    lo[a] = static_cast<int>(std::max(first, 0.0)) - 1;
    hi[a] = static_cast<int>(std::min(last, g.n[a] - 1.0));
  }
  const auto at = [&](int i, int j, int k) {
    return g.table[(static_cast<std::size_t>(k + 1) * (g.n[1] + 1) + (j + 1)) * (g.n[0] + 1) + (i + 1)];
  };
  return at(hi[0], hi[1], hi[2]) - at(lo[0], hi[1], hi[2]) - at(hi[0], lo[1], hi[2]) - at(hi[0], hi[1], lo[2]) +
         at(lo[0], lo[1], hi[2]) + at(lo[0], hi[1], lo[2]) + at(hi[0], lo[1], lo[2]) - at(lo[0], lo[1], lo[2]);
}

std::size_t ExactVisibility::occluders() const { return impl_->triangles.size(); }

}  // namespace lambert
