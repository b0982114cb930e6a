// The hierarchical method's gather at a point (a probe): a traversal of the hierarchy from the top
// cluster, taking a cluster or element whole where the error of doing so is within a tolerance, and
// descending into it otherwise. A leaf that rays find partly hidden takes the exact factor of its
// visible part, as the dense gather's patches do, so that the rays' noise does not reach the probe.
//
// A cluster is taken whole where the oracle's bound on its one-point estimate (clusters.h) is within
// the tolerance (read from where its power comes, its bins weighted by what it sends: ClusterSending),
// or left out where all it could send is; an element where its radiosity varies little
// over it and it is wholly visible or wholly hidden; a leaf always. The tolerance is a tenth of
// solver.accuracy times the scene's mean radiosity per unit of projected solid angle, and times what
// the point gathered relative to that mean where it gathered less (gather_at_point).
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "solver/exact_visibility.h"
#include "solver/hierarchical/hierarchy.h"
#include "solver/hierarchical/oracle.h"
#include "solver/hierarchical/plane_verdicts.h"
#include "solver/pipeline/transport_operator.h"

namespace lambert::hierarchical {

class HierarchicalPointGather final : public PointGather {
 public:
  // B: K radiosity vectors over the leaves.
  // exact: the input triangles as occluders, for the leaves that rays find partly hidden.
  HierarchicalPointGather(const Hierarchy& h, const PlaneVerdicts& planes, const Visibility& vis,
                          const ExactVisibility& exact, const std::vector<const double*>& B, double accuracy);
  void gather_at_point(const Receiver& receiver, double* E) const override;

  // The least share of the scene's mean radiosity that a dim point's tolerance is scaled to: a point
  // that gathers nothing (inside a box) would otherwise open every leaf it sees.
  static constexpr double kDimScale = 1.0 / 64;

 private:
  // The traversal with a given tolerance (per unit of projected solid angle, × B).
  void gather(const Receiver& receiver, double tolerance, double* E) const;
  // An element whose visibility rays decide, and its unoccluded factor f.
  struct Pending {
    int node;
    double f;
  };
  // Rays to an element's samples, 16 before the first vote (as for links: four unanimous rays to a
  // coarse element miss small occluders), but for an element within the tolerance found hidden by
  // its first 4.
  static constexpr int kFirstRound = 16;
  // Adds element `node`'s share to E where the occluder planes prove it wholly visible, queues it for
  // rays where they do not, or pushes its children where it must be opened.
  void visit_element(const Receiver& r, const OccluderPlanes::Sides& sides, int node, double tolerance,
                     std::vector<int>& stack, std::vector<Pending>& pending, double* E) const;
  // The queued elements' rays, traced together as streams (weighted_visible_fractions), and their
  // shares added to E: f times the visible fraction, or a partly hidden leaf's exact visible factor.
  void trace_pending(const Receiver& r, const Point3& from, std::span<const Pending> pending, double tolerance,
                     double* E) const;
  void add(int node, double factor, double* E) const;  // factor × the element's radiosity
  // The largest |B| of element e's subtree over the systems: what its whole share is weighed by.
  double largest_B(int e) const { return std::max(std::abs(lo_[e]), std::abs(hi_[e])); }
  // The same for cluster c.
  void visit_cluster(const Receiver& r, const Point3& from, const OccluderPlanes::Sides& sides, int c,
                     double tolerance, std::vector<int>& stack, double* E) const;

  const Hierarchy& h_;
  const PlaneVerdicts& planes_;
  const Visibility& vis_;
  const ExactVisibility& exact_;
  Hierarchy::Values values_;  // per element and cluster, every system
  // Per element: the subtree's least and largest radiosity over the systems, which decide how deep a
  // point must look into it; per cluster: its largest |B|.
  std::vector<double> lo_, hi_, cluster_B_;
  // How each cluster sends under the largest |B| over the systems: a cluster taken whole is read as
  // the refiner's links read it (Refiner::refine_to_cluster), from its power's centroid with its bins
  // weighted by what it sends, here by the solved radiosity itself.
  ClusterSending sending_;
  double mean_B_ = 0;     // the scene's mean radiosity (the largest over the systems), enclosed leaves left out
  double tolerance_ = 0;  // what a taken node may err by, per unit of projected solid angle (× B)
};

}  // namespace lambert::hierarchical
