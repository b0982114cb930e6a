#include "solver/hierarchical/plane_verdicts.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>

namespace lambert::hierarchical {

PlaneVerdicts::PlaneVerdicts(const ElementForest& forest, const ClusterTree& tree, const OccluderPlanes& planes)
    : planes_(planes) {
  all_clear_ = planes_.usable() && planes_.planes() == 0;
  if (!planes_.usable() || planes_.planes() == 0 || forest.elements.size() + tree.clusters.size() > kMaxSidedElements)
    return;
  sides_.resize(forest.elements.size());
  cluster_sides_.resize(tree.clusters.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sides_.size(), 256), [&](const auto& range) {
    for (std::size_t e = range.begin(); e != range.end(); ++e) sides_[e] = planes_.sides(forest.elements[e].tri.v);
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cluster_sides_.size(), 256), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      const Bounds3& b = tree.clusters[c].box;
      std::array<Point3, 8> corners;
      for (int k = 0; k < 8; ++k) corners[k] = b.corner(k);
      cluster_sides_[c] = planes_.sides(corners);
    }
  });
}

}  // namespace lambert::hierarchical
