#include "solver/dense/point_gather.h"

#include <algorithm>
#include <utility>

#include "solver/form_factor.h"
#include "solver/receiver_kernel.h"
#include "solver/solids.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

constexpr int kProbeRays = 3 + 16;  // the corners and the interior samples

// The candidates' unoccluded factors (patch, factor > 0) replaced by the visible ones. A planar
// receiver on a surface is lifted off it along its normal; the others stand in free space.
void visible_point_triangle_factors(const Receiver& receiver, const std::vector<Patch>& patches,
                                    std::vector<std::pair<std::size_t, double>>& candidates, const Visibility& vis,
                                    const OccluderPlanes& planes, const std::vector<OccluderPlanes::Sides>& sides,
                                    const ExactVisibility& exact) {
  thread_local std::vector<Segment> rays;
  thread_local std::vector<std::uint8_t> visible;
  thread_local std::vector<std::size_t> traced;  // candidates whose rays are in the stream
  const Point3& p = receiver.point;
  const Point3 from = receiver.kind == Receiver::Kind::Planar ? vis.lift(p, receiver.normal) : p;
  const Point3 point[1] = {p};
  const OccluderPlanes::Sides point_sides = planes.sides(point);
  rays.clear(), traced.clear();
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const std::size_t j = candidates[c].first;
    if (!sides.empty() && planes.clear(point_sides, sides[j])) continue;  // wholly visible
    traced.push_back(c);
    const Patch& patch = patches[j];
    const Triangle& t = patch.triangle;
    for (int v = 0; v < 3; ++v) {
      const Point3 corner = barycentric(t.v[v], t.v[(v + 1) % 3], t.v[(v + 2) % 3], 0.998, 0.001, 0.001);
      rays.push_back({from, vis.lift(corner, patch.normal)});
    }
    for (int k = 0; k < 16; ++k) rays.push_back({from, vis.lift(visibility_sample(t, k), patch.normal)});
  }
  visible.resize(rays.size());
  vis.visible(rays, visible);
  for (std::size_t r = 0; r < traced.size(); ++r) {
    const std::size_t c = traced[r];
    const Patch& patch = patches[candidates[c].first];
    const int seen =
        static_cast<int>(std::count(visible.begin() + r * kProbeRays, visible.begin() + (r + 1) * kProbeRays, 1));
    double& factor = candidates[c].second;
    if (seen == kProbeRays) continue;
    factor = seen == 0 ? 0.0 : exact_visible_factor(receiver, patch.triangle, exact);
  }
}


}  // namespace

DensePointGather::DensePointGather(const Scene& scene, const std::vector<Patch>& patches, const Visibility& vis,
                                   const OccluderPlanes& planes, const std::vector<OccluderPlanes::Sides>& sides,
                                   std::vector<const double*> B)
    : patches_(patches), vis_(vis), planes_(planes), sides_(sides), B_(std::move(B)) {
  exact_ = scene_exact_visibility(scene);
  radiates_.assign(patches.size(), 0);
  for (std::size_t j = 0; j < patches.size(); ++j)
    for (const double* b : B_) radiates_[j] = radiates_[j] || b[j] != 0;
}

void DensePointGather::gather_at_point(const Receiver& receiver, double* E) const {
  thread_local std::vector<std::pair<std::size_t, double>> seen;  // (patch, visible point-to-patch factor)
  seen.clear();
  for (std::size_t j = 0; j < patches_.size(); ++j) {
    if (!radiates_[j]) continue;
    const double f = receiver_triangle_factor(receiver, patches_[j].triangle);
    if (f > 0) seen.emplace_back(j, f);
  }
  visible_point_triangle_factors(receiver, patches_, seen, vis_, planes_, sides_, *exact_);
  const std::size_t K = B_.size();
  for (std::size_t k = 0; k < K; ++k) E[k] = 0;
  for (const auto& [j, fv] : seen)
    for (std::size_t k = 0; k < K; ++k) E[k] += fv * B_[k][j];
}

}  // namespace lambert
