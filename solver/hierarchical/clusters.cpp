#include "solver/hierarchical/clusters.h"

#include <algorithm>
#include <array>
#include <limits>

#include "solver/cubature.h"
#include "solver/visible_fraction.h"

namespace lambert::hierarchical {

ClusterTree::ClusterSample cluster_sample(const ClusterTree& h, const Cluster& C, int k) {
  if (C.samples >= 0 && k < kTabledClusterSamples) return h.cluster_samples[C.samples + k];
  const int pick = (37 * k + 11) % kMaxVisibilitySamples;
  const ClusterTree::RootSample& root =
      h.ordered_roots[C.first_root + static_cast<int>(static_cast<long long>(pick) * C.root_count / kMaxVisibilitySamples)];
  return {visibility_sample(root.tri, k), root.normal};
}

namespace {

// From this depth down every split is the median one, which bounds the tree's depth whatever the
// areas (an area split may peel off one root at a time).
constexpr int kAreaSplitDepth = 48;
constexpr int kSplitBins = 16;

// The area split of root_order[first, first + count): the centroids binned along each axis, and the
// cut between bins that minimises Σ (half the surface area of a child's box × its roots), the surface
// area heuristic of ray-tracing BVHs (MacDonald & Booth 1990; pbrt-v4's BVHAggregate). A pair of
// clusters links as a whole only where it is well separated (d ≥ 2.5 × the radii's sum), and the
// median of the centroids may put flat ground and the walls standing on it, or parts of two
// buildings, in one box. Partitions the roots and returns the left child's count, or 0 where no cut
// leaves both sides non-empty.
int area_split(ClusterTree& h, const ElementForest& f, int first, int count, const Bounds3& centroids) {
  struct Bin {
    Bounds3 box;
    int roots = 0;
  };
  auto half_area = [](const Bounds3& b) {
    const Vector3 d = b.diagonal();
    return d.x * d.y + d.y * d.z + d.z * d.x;
  };
  const Point3 lo = centroids.lo;
  const Vector3 extent = centroids.diagonal();
  auto bin_of = [&](int e, int axis) {
    const double t = (f.elements[e].centre[axis] - lo[axis]) / extent[axis];
    return std::clamp(static_cast<int>(kSplitBins * t), 0, kSplitBins - 1);
  };
  double best = std::numeric_limits<double>::infinity();
  int best_axis = -1, best_cut = 0;  // the left child takes bins [0, best_cut]
  for (int axis = 0; axis < 3; ++axis) {
    if (!(extent[axis] > 0)) continue;
    std::array<Bin, kSplitBins> bins;
    for (int k = first; k < first + count; ++k) {
      const int e = h.root_order[k];
      Bin& b = bins[bin_of(e, axis)];
      ++b.roots;
      b.box.add(bounds(f.elements[e].tri));
    }
    std::array<double, kSplitBins> right_cost{};  // of bins [b, end)
    Bounds3 box;
    int roots = 0;
    for (int b = kSplitBins - 1; b > 0; --b) {
      box.add(bins[b].box);
      roots += bins[b].roots;
      right_cost[b] = half_area(box) * roots;
    }
    box = Bounds3{};
    roots = 0;
    for (int b = 0; b + 1 < kSplitBins; ++b) {
      box.add(bins[b].box);
      roots += bins[b].roots;
      if (roots == 0 || roots == count) continue;
      const double cost = half_area(box) * roots + right_cost[b + 1];
      if (cost < best) best = cost, best_axis = axis, best_cut = b;
    }
  }
  if (best_axis < 0) return 0;
  const auto middle = std::partition(h.root_order.begin() + first, h.root_order.begin() + first + count,
                                     [&](int e) { return bin_of(e, best_axis) <= best_cut; });
  return static_cast<int>(middle - (h.root_order.begin() + first));
}

// Builds the BVH over root_order[first, first + count); returns the cluster's index. Children are
// appended after their parent. A cluster whose normals are all axis-aligned (buildings, rooms and
// their furniture) is split by area_split: its projected area is exact from its bins whatever its
// shape, and what its links need of it is a small box. Any other is split at the median of its
// centroids along their longest axis: area splits of faceted spheres gave their links into clusters
// larger errors (docs/BENCHMARKS.md, "The cluster tree's splits").
int build_clusters(ClusterTree& h, const ElementForest& f, int first, int count, int depth = 0) {
  const int index = static_cast<int>(h.clusters.size());
  h.clusters.emplace_back();
  FacetBounds facets;
  Bounds3 centroids;
  for (int k = first; k < first + count; ++k) {
    const Element& e = f.elements[h.root_order[k]];
    facets.add(e.tri, e.normal, e.area);
    centroids.add(e.centre);
  }
  facets.fit_cone([&](auto&& each) {
    for (int k = first; k < first + count; ++k) each(f.elements[h.root_order[k]].normal);
  });
  {
    Cluster& c = h.clusters[index];
    static_cast<FacetBounds&>(c) = facets;
    c.centre = facets.box.center();
    c.radius = 0.5 * length(facets.box.diagonal());
    c.first_root = first;
    c.root_count = count;
  }
  if (count == 1) {
    h.clusters[index].root = h.root_order[first];
    h.clusters[index].slot = f.root_slot(h.root_order[first]);
    return index;
  }
  int half = facets.axis_normals && depth < kAreaSplitDepth ? area_split(h, f, first, count, centroids) : 0;
  if (half == 0) {
    const Vector3 extent = centroids.diagonal();
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    auto key = [&](int e) { return f.elements[e].centre[axis]; };
    half = count / 2;
    std::nth_element(h.root_order.begin() + first, h.root_order.begin() + first + half,
                     h.root_order.begin() + first + count, [&](int a, int b) { return key(a) < key(b); });
  }
  const int left = build_clusters(h, f, first, half, depth + 1);
  const int right = build_clusters(h, f, first + half, count - half, depth + 1);
  h.clusters[index].child[0] = left;
  h.clusters[index].child[1] = right;
  return index;
}

// Bounds of Σ A (n·w)⁺ over the roots of cluster c, added to [lower, upper], and with `sent` of
// Σ B A (n·w)⁺, added to [sent_lower, sent_upper]. A subtree whose normal cone lies wholly in front of
// w's horizon adds its area vector · w, one wholly behind adds nothing, and one with axis-aligned
// normals adds its bins, all exactly; only clusters whose normals straddle the horizon are descended
// into, at most `budget` of them. Past the budget a cluster adds (area vector · w)⁺ below and its bins
// above.
struct ProjectedBounds {
  double lower = 0, upper = 0, sent_lower = 0, sent_upper = 0;
};
void bound_projected_area(const ClusterTree& h, int c, const Vector3& w, const std::vector<SentFacets>* sent, int& budget,
                          ProjectedBounds& out) {
  const Cluster& C = h.clusters[c];
  enum class Seen { Straddling, Bins, Facing, Behind } seen = Seen::Straddling;
  if (C.axis_normals) {
    seen = Seen::Bins;
  } else if (C.cone_sin <= 1 || C.root >= 0) {
    const double along = dot(C.cone_axis, w);
    if (along >= C.cone_sin || C.root >= 0) seen = Seen::Facing;
    else if (along <= -C.cone_sin) seen = Seen::Behind;
  }
  if (seen == Seen::Straddling && budget-- > 0) {
    bound_projected_area(h, C.child[0], w, sent, budget, out);
    bound_projected_area(h, C.child[1], w, sent, budget, out);
    return;
  }
  auto add = [&](const Bins& bins, const Vector3& area_vector, double& lower, double& upper) {
    const double in_bins = binned(bins, w), facing = std::max(0.0, dot(area_vector, w));
    switch (seen) {
      case Seen::Bins: lower += in_bins, upper += in_bins; break;
      case Seen::Facing: lower += facing, upper += facing; break;
      case Seen::Behind: break;
      case Seen::Straddling: lower += facing, upper += in_bins; break;  // past the budget
    }
  };
  add(C.projected, C.area_vector, out.lower, out.upper);
  if (sent) add((*sent)[c].projected, (*sent)[c].area_vector, out.sent_lower, out.sent_upper);
}
constexpr int kProjectionBudget = 256;  // clusters descended into per bound_projected_area

// Fills ClusterTree::cluster_samples (see there) once the clusters and ordered_roots are built.
void table_cluster_samples(ClusterTree& h) {
  for (Cluster& C : h.clusters) {
    if (C.root_count <= kTabledClusterSamples) continue;
    const int first = static_cast<int>(h.cluster_samples.size());
    for (int k = 0; k < kTabledClusterSamples; ++k) h.cluster_samples.push_back(cluster_sample(h, C, k));
    C.samples = first;
  }
}

}  // namespace

ClusterView cluster_view(const ClusterTree& h, int c, const Vector3& w, double sin_delta,
                         const std::vector<SentFacets>* sent) {
  ClusterView view;
  const double wa[3] = {w.x, w.y, w.z};
  for (int a = 0; a < 3; ++a) view.bin[a] = static_cast<unsigned char>(wa[a] > 0 ? 2 * a : 2 * a + 1);
  const Cluster& C = h.clusters[c];
  view.turning = turning_area(C, w, sin_delta);
  const double in_bins = binned_area(C, w);
  if (in_bins <= 0) return view;
  if (C.axis_normals) {  // the bins are exact (the common case in buildings)
    view.projected = in_bins;
    for (int a = 0; a < 3; ++a) view.weight[a] = std::abs(wa[a]);
    return view;
  }
  // Every normal within θ of the cone's axis faces w where the axis is within π/2 − θ of it.
  if (C.cone_sin < 1 && dot(C.cone_axis, w) > C.cone_sin) {
    view.projected = dot(C.area_vector, w);
    for (int a = 0; a < 3; ++a) {
      view.bin[a] = static_cast<unsigned char>(kAxisBin + a);
      view.weight[a] = wa[a];
    }
    return view;
  }
  ProjectedBounds bounds;
  int budget = kProjectionBudget;
  bound_projected_area(h, c, w, sent, budget, bounds);
  view.projected = 0.5 * (bounds.lower + bounds.upper);
  view.uncertainty = 0.5 * (bounds.upper - bounds.lower);
  // The bins' share that the cluster sends along w: of its area, or of its power under `sent`.
  double share = view.projected / in_bins;
  if (sent) {
    const double sent_binned = binned((*sent)[c].projected, w);
    if (sent_binned > 0) share = 0.5 * (bounds.sent_lower + bounds.sent_upper) / sent_binned;
  }
  for (int a = 0; a < 3; ++a) view.weight[a] = std::abs(wa[a]) * share;
  return view;
}

double weight_along(const ClusterView& view, int a, const Vector3& w, const Vector3& u) {
  if (view.bin[a] >= kAxisBin) return u[a];
  return (u[a] > 0) == (w[a] > 0) && w[a] != 0 ? view.weight[a] * u[a] / w[a] : 0.0;
}

std::array<double, 3> receiver_mean_factors(const ClusterView& view, const Vector3& w, const Point3& centre,
                                            const Triangle& R, const Vector3& n_R) {
  const TriangleRule rule = triangle_rule_degree5();
  std::array<double, 3> factor{};
  for (int q = 0; q < rule.size; ++q) {
    const auto& b = rule.nodes[q];
    const Vector3 to_node = barycentric(R.v[0], R.v[1], R.v[2], b[0], b[1], b[2]) - centre;
    const double d2 = dot(to_node, to_node);
    const double d = std::sqrt(d2);
    const double cos_r = -dot(n_R, to_node) / d;
    if (!(cos_r > 0)) continue;  // behind R's horizon: the kernel's (cos θ)⁺ is 0
    const double kernel = rule.weights[q] * cos_r / (kPi * d2);
    for (int a = 0; a < 3; ++a) factor[a] += kernel * weight_along(view, a, w, to_node / d);
  }
  return factor;
}

std::array<double, 3> receivers_factors(const ClusterView& view, const Vector3& w, const Point3& to, const Point3& from,
                                        Vector3& toward) {
  const Vector3 from_source = to - from;
  const double d2 = dot(from_source, from_source);
  toward = -from_source / std::sqrt(d2);
  std::array<double, 3> factor{};
  for (int a = 0; a < 3; ++a) factor[a] = weight_along(view, a, w, -toward) / (kPi * d2);
  return factor;
}

ClusterTree build_cluster_tree(const ElementForest& forest) {
  ClusterTree tree;
  for (int root : forest.roots)
    if (!forest.is_enclosed(root)) tree.root_order.push_back(root);
  if (!tree.root_order.empty()) build_clusters(tree, forest, 0, static_cast<int>(tree.root_order.size()));
  for (int root : tree.root_order) tree.ordered_roots.push_back({forest.elements[root].tri, forest.elements[root].normal});
  table_cluster_samples(tree);
  return tree;
}

double one_point_error(const ClusterView& view, double scale, double d, double d_min) {
  return (view.projected * scale / d + view.uncertainty + view.turning) / (kPi * d_min * d_min);
}

double vector_estimate_error(double source_area, double receivers_radius, double centre_to_source) {
  const double near = centre_to_source - receivers_radius;
  return source_area / kPi * (1 / (near * near) - 1 / (centre_to_source * centre_to_source));
}

double horizon_cut_error(double sin_excess, double shown, double d_min) {
  return sin_excess * shown / (kPi * d_min * d_min);
}

double unseen_transfer(const Cluster& C, const ClusterView& view, bool receiver_faces, double sin_delta, double d_min) {
  return max_projected(C) * (view.projected > 0 ? 1 : sin_delta) * (receiver_faces ? 1 : sin_delta) /
         (kPi * d_min * d_min);
}

bool box_in_front(const Bounds3& box, const Point3& o, const Vector3& n, double tol) {
  for (int c = 0; c < 8; ++c) {
    if (dot(box.corner(c) - o, n) > tol) return true;
  }
  return false;
}

}  // namespace lambert::hierarchical
