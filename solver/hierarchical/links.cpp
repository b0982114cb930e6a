#include "solver/hierarchical/links.h"

#include <algorithm>
#include <cmath>

#include "solver/cubature.h"
#include "solver/form_factor.h"

namespace lambert::hierarchical {

void LinkSet::index_links(std::size_t elements, const std::vector<Cluster>& clusters) {
  auto offsets = [](const auto& list, std::size_t receivers, std::vector<std::size_t>& start) {
    start.assign(receivers + 1, 0);
    for (const auto& l : list) ++start[l.receiver + 1];
    for (std::size_t r = 0; r < receivers; ++r) start[r + 1] += start[r];
  };
  offsets(links, elements, link_start);
  offsets(hidden_links, elements, hidden_start);
  offsets(cluster_links, clusters.size(), cluster_link_start);
  offsets(hidden_cluster_links, clusters.size(), hidden_cluster_start);
  links_below.assign(clusters.size(), 0);
  for (std::size_t c = clusters.size(); c-- > 0;) {  // children come after their parent
    const Cluster& cl = clusters[c];
    links_below[c] = cluster_link_start[c + 1] > cluster_link_start[c] ||
                     (cl.root < 0 && (links_below[cl.child[0]] || links_below[cl.child[1]]));
  }
}

// A near link's point on its source S: the centroid of S weighted by the factor from its points to
// the receiver R (the degree-5 rule over S), so that the link reads S's radiosity where R sees it:
// next to an edge S shares with R, not at S's centroid. The transpose then hands S's leaves near
// the edge their share; spread evenly over S, it left their column sums short and the closure
// balance scaled them up for every receiver.
std::array<unsigned char, 3> source_point_of(const Element& S, const Element& R) {
  const TriangleRule rule = triangle_rule_degree5();
  std::array<Point3, kMaxRuleSize> nodes;
  std::array<double, kMaxRuleSize> factors;
  for (int q = 0; q < rule.size; ++q) {
    const auto& w = rule.nodes[q];
    nodes[q] = barycentric(S.tri.v[0], S.tri.v[1], S.tri.v[2], w[0], w[1], w[2]);
  }
  // One batch (point_triangle_factors' lanes give point_triangle_factor's values): 7 calls one by
  // one were 5 % of the cube room's solve with solver.exact_visibility.
  point_triangle_factors({nodes.data(), static_cast<std::size_t>(rule.size)}, S.normal, R.tri,
                         {factors.data(), static_cast<std::size_t>(rule.size)});
  double sum = 0, b1 = 0, b2 = 0;
  for (int q = 0; q < rule.size; ++q) {
    const auto& w = rule.nodes[q];
    const double f = rule.weights[q] * factors[q];
    sum += f;
    b1 += f * w[1];
    b2 += f * w[2];
  }
  if (!(sum > 0)) return {kCentroid, kCentroid, 0};
  // Rounded so that β1 + β2 stays within 1 (β0 ≥ 0).
  const double x1 = std::clamp(b1 / sum, 0.0, 1.0), x2 = std::clamp(b2 / sum, 0.0, 1.0 - x1);
  const auto q1 = static_cast<unsigned char>(std::lround(x1 * kPointScale));
  const auto q2 = static_cast<unsigned char>(std::min<long>(std::lround(x2 * kPointScale), 255 - q1));
  return {q1, q2, 0};
}

// Room left for the links that rays found hidden (Hierarchy::hidden_links), kept for
// solver.exact_visibility only; each one kept takes one, and at 0 no more are kept. Links between
// elements: when their room runs out the gather does not retrace at all (Hierarchy::hidden_complete).

}  // namespace lambert::hierarchical
