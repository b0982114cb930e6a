// The dense method's gather at a point (a probe): the visible factor from the point to every patch
// that radiates, times its radiosity. Rays from the point to each patch's corners (pulled 0.1 %
// towards the centroid: a straight shadow edge that crosses a triangle separates its corners, so it
// cannot slip between interior samples) and to 16 interior samples decide the common cases: all
// visible gives the unoccluded factor, none the value 0. The rays of all patches go to Embree as one
// stream; patches that no occluder plane separates from the point (occluder_planes.h) need none.
// Where they disagree, the visible part of the patch is computed exactly (solver/exact_visibility.h):
// the occluders in the cone from the point over the patch, projected onto its plane and subtracted
// (inclusion–exclusion over their convex intersections, or CGAL's exact Booleans beyond 8 of them).
// Per patch, not once per input triangle clipped to its patches: a patch's cone holds a few
// occluders, an input triangle's (a wall) often more than 8, which made the Boolean path the larger
// part of the Cornell box's probe time (docs/BENCHMARKS.md).
#pragma once

#include <memory>
#include <vector>

#include "solver/exact_visibility.h"
#include "solver/occluder_planes.h"
#include "solver/pipeline/transport_operator.h"

namespace lambert {

class DensePointGather final : public PointGather {
 public:
  // B: K radiosity vectors over the patches. Exact partial visibility works on the scene's input
  // triangles (fewer, larger occluders than the patches), with the solids they bound (a convex
  // solid's front faces hide the sum of their factors).
  DensePointGather(const Scene& scene, const std::vector<Patch>& patches, const Visibility& vis,
                   const OccluderPlanes& planes, const std::vector<OccluderPlanes::Sides>& sides,
                   std::vector<const double*> B);
  void gather_at_point(const Receiver& receiver, double* E) const override;
  std::uint64_t exact_evaluations() const override { return exact_->occluded_evaluations(); }

 private:
  const std::vector<Patch>& patches_;
  const Visibility& vis_;
  const OccluderPlanes& planes_;
  const std::vector<OccluderPlanes::Sides>& sides_;
  std::vector<const double*> B_;
  std::vector<char> radiates_;  // per patch: some B_k is not 0
  std::unique_ptr<ExactVisibility> exact_;
};

}  // namespace lambert
