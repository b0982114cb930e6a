#include "solver/hierarchical/point_gather.h"

#include <algorithm>
#include <cmath>

#include "solver/form_factor.h"
#include "solver/receiver_kernel.h"
#include "solver/visible_fraction.h"

namespace lambert::hierarchical {
namespace {

// The weight of a visibility ray from the receiver to q on a source of normal nq: w(ω) cos θ_q / r²
// (for a plane, the differential form-factor kernel link_weight).
double receiver_link_weight(const Receiver& r, const Point3& q, const Vector3& nq) {
  if (r.kind == Receiver::Kind::Planar) return link_weight(r.point, r.normal, q, nq);
  const Vector3 d = q - r.point;
  const double r2 = length_squared(d);
  if (!(r2 > 0)) return 0;
  const double dist = std::sqrt(r2);
  return receiver_weight(r, d / dist) * std::max(0.0, -dot(nq, d)) / (r2 * dist);
}

}  // namespace

HierarchicalPointGather::HierarchicalPointGather(const Hierarchy& h, const PlaneVerdicts& planes, const Visibility& vis,
                                                 const ExactVisibility& exact, const std::vector<const double*>& B,
                                                 double accuracy)
    : h_(h), planes_(planes), vis_(vis), exact_(exact) {
  const std::size_t K = B.size(), N = h.leaves.size();
  h.pull(B, values_);
  lo_.assign(h.elements.size(), 1e300), hi_.assign(h.elements.size(), -1e300);
  for (std::size_t e = h.elements.size(); e-- > 0;) {
    const Element& el = h.elements[e];
    if (el.leaf >= 0)
      for (std::size_t k = 0; k < K; ++k) lo_[e] = std::min(lo_[e], B[k][el.leaf]), hi_[e] = std::max(hi_[e], B[k][el.leaf]);
    if (el.parent >= 0) lo_[el.parent] = std::min(lo_[el.parent], lo_[e]), hi_[el.parent] = std::max(hi_[el.parent], hi_[e]);
  }
  std::vector<double> largest(N);  // per leaf, over the systems
  for (std::size_t i = 0; i < N; ++i) largest[i] = largest_B(h.leaves[i]);
  sending_ = cluster_sending(h, largest, cluster_B_);
  double power = 0, area = 0;
  for (std::size_t i = 0; i < N; ++i) {
    const int e = h.leaves[i];
    if (h.is_enclosed(e)) continue;  // enclosed: no part of what a probe can see
    power += h.elements[e].area * largest_B(e);
    area += h.elements[e].area;
  }
  mean_B_ = area > 0 ? power / area : 0;
  tolerance_ = 0.1 * accuracy * mean_B_;
}

// An element is taken whole where its radiosity varies little (f × spread within the tolerance) and
// it is wholly visible or hidden: the visible part of a partly hidden element need not have its mean
// radiosity (a probe under a floating cube read 3 % high where partly hidden elements were taken
// whole). Only the occluder planes prove it wholly visible: where rays decide, an element whose
// whole share exceeds the tolerance is opened, since 16 agreeing rays can miss a shadow edge across
// a small part of it (up to 2 % at floor sensors beside a table's shadow, docs/BENCHMARKS.md). A
// leaf's partly hidden share is the exact factor of its visible part.
void HierarchicalPointGather::visit_element(const Receiver& r, const OccluderPlanes::Sides& sides, int node,
                                            double tolerance, std::vector<int>& stack, std::vector<Pending>& pending,
                                            double* E) const {
  const Element& S = h_.elements[node];
  const double f = receiver_triangle_factor(r, S.tri);  // the kernel the dense gather uses
  if (f <= 0) return;
  const bool splittable = S.first_child >= 0;
  const bool proven_visible = planes_.point_sees(sides, node);
  // Opened before any ray is traced: where its radiosity varies too much, or where rays would have
  // to decide and its whole share exceeds the tolerance.
  if (splittable && (f * (hi_[node] - lo_[node]) > tolerance ||
                     (!proven_visible && f * largest_B(node) > tolerance))) {
    for (int c = 0; c < 4; ++c) stack.push_back(S.first_child + c);
    return;
  }
  if (proven_visible) add(node, f, E);
  else pending.push_back({node, f});
}

void HierarchicalPointGather::add(int node, double factor, double* E) const {
  const std::size_t K = values_.K;
  for (std::size_t k = 0; k < K; ++k) E[k] += factor * values_.B[node * K + k];
}

void HierarchicalPointGather::trace_pending(const Receiver& r, const Point3& from, std::span<const Pending> pending,
                                            double tolerance, double* E) const {
  thread_local std::vector<double> fraction;
  thread_local std::vector<char> early_hidden;
  fraction.resize(pending.size());
  early_hidden.resize(pending.size());
  // An element whose whole share is within the tolerance is closed as hidden by 4 blocked rays, as a
  // link within its budget is: a wrong verdict costs no more than the tolerance. (Unanimously visible
  // rays still go on to 16.)
  for (std::size_t l = 0; l < pending.size(); ++l) early_hidden[l] = pending[l].f * largest_B(pending[l].node) <= tolerance;
  weighted_visible_fractions(
      vis_, pending.size(),
      [&](std::size_t l, int k) {
        const Element& S = h_.elements[pending[l].node];
        return std::pair{from, vis_.lift(visibility_sample(S.tri, k), S.normal)};
      },
      [&](std::size_t l, const Point3&, const Point3& q) {
        return receiver_link_weight(r, q, h_.elements[pending[l].node].normal);
      },
      fraction, kFirstRound, early_hidden);
  for (std::size_t l = 0; l < pending.size(); ++l) {
    const auto [node, f] = pending[l];
    const Element& S = h_.elements[node];
    const double v = fraction[l];
    add(node, S.first_child < 0 && v > 0 && v < 1 ? exact_visible_factor(r, S.tri, exact_) : f * v, E);
  }
}

void HierarchicalPointGather::visit_cluster(const Receiver& r, const Point3& from, const OccluderPlanes::Sides& sides,
                                            int c, double tolerance, std::vector<int>& stack, double* E) const {
  const Cluster& C = h_.clusters[c];
  if (C.root >= 0) {
    stack.push_back(C.root);
    return;
  }
  const Point3& p = r.point;
  const Vector3& n = r.normal;
  const bool planar = r.kind == Receiver::Kind::Planar;  // the others see every direction
  if (planar && !box_in_front(C.box, p, n, 0)) return;
  const Vector3 d_vec = p - C.centre;
  const double d = length(d_vec), d_min = d - C.radius;
  if (d >= 2 * C.radius * kTie && d_min > 0) {
    // The oracle's bounds (clusters.h), as for a link from the cluster to a receiver of no extent;
    // they take the receiver's weight w(ω) at most 1, as (n·ω)⁺ is for a plane.
    const Vector3 w = d_vec / d;
    const double sin_delta = C.radius / d;
    if (planar && -dot(n, w) <= -sin_delta) return;  // behind the plane from every point of the cluster
    if (!may_face(C, w, sin_delta, Bounds3{p, p})) return;
    const ClusterView view = cluster_view(h_, c, w, sin_delta, &sending_.sent);
    const double weight = receiver_weight(r, -w);  // (n·ω)⁺ for a plane
    if (view.projected <= 0 || weight <= 0) {
      // The line between the centres misses; the other directions may not. A receiver other than
      // a plane may see them at full weight.
      const bool faces = weight > 0 || !planar;
      if (cluster_B_[c] * unseen_transfer(C, view, faces, sin_delta, d_min) <= tolerance) return;
    } else if (cluster_B_[c] * one_point_error(view, C.radius, d, d_min) <= tolerance) {
      Vector3 source_normal;
      const double v = planes_.point_sees_cluster(sides, c) ? 1.0 : weighted_visible_fraction(
          vis_,
          [&](int j) {
            const ClusterTree::ClusterSample S = cluster_sample(h_, C, j);
            source_normal = S.normal;
            return std::pair{from, vis_.lift(S.point, S.normal)};
          },
          [&](const Point3&, const Point3& q) { return receiver_link_weight(r, q, source_normal); });
      const std::size_t K = values_.K;
      Vector3 toward;  // from the probe to where the cluster's power comes from
      const std::array<double, 3> factor = receivers_factors(view, w, p, sending_.source[c], toward);
      const double seen = receiver_weight(r, toward);
      for (int a = 0; a < 3; ++a) {
        const double coeff = factor[a] * seen * v;
        for (std::size_t k = 0; k < K; ++k) E[k] += coeff * bin_value(&values_.Phi[c * 6 * K], view.bin[a], K, k);
      }
      return;
    }
  }
  stack.push_back(-1 - C.child[0]);
  stack.push_back(-1 - C.child[1]);
}

void HierarchicalPointGather::gather_at_point(const Receiver& receiver, double* E) const {
  gather(receiver, tolerance_, E);
  // The tolerance is absolute, a share of the scene's mean radiosity: a point that gathers much less
  // (a room beside a brighter one, a shaded corner) would err by more of its own value. Such a point
  // is gathered again with the tolerance scaled by what it gathered, down to kDimScale of the mean
  // (docs/BENCHMARKS.md, "A dim room beside a bright one").
  double gathered = 0;
  for (std::size_t k = 0; k < values_.K; ++k) gathered = std::max(gathered, std::abs(E[k]));
  const double scale = mean_B_ > 0 ? gathered / mean_B_ : 1;
  if (scale < 1) gather(receiver, tolerance_ * std::max(scale, kDimScale), E);
}

void HierarchicalPointGather::gather(const Receiver& receiver, double tolerance, double* E) const {
  std::fill(E, E + values_.K, 0.0);
  // A plane on a surface is lifted off it; the other receivers stand in free space.
  const Point3 from = receiver.kind == Receiver::Kind::Planar ? vis_.lift(receiver.point, receiver.normal) : receiver.point;
  const OccluderPlanes::Sides sides = planes_.sides(receiver.point);
  thread_local std::vector<int> stack;  // −1 − c: cluster c; ≥ 0: element
  thread_local std::vector<Pending> pending;
  stack.assign(h_.clusters.empty() ? 0 : 1, -1);
  pending.clear();
  while (!stack.empty()) {
    const int node = stack.back();
    stack.pop_back();
    if (node >= 0) visit_element(receiver, sides, node, tolerance, stack, pending, E);
    else visit_cluster(receiver, from, sides, -1 - node, tolerance, stack, E);
  }
  trace_pending(receiver, from, pending, tolerance, E);
}

}  // namespace lambert::hierarchical
