#include "solver/hierarchical/reciprocity.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

namespace lambert::hierarchical {

Reciprocity reciprocity_error(const Hierarchy& h) {
  // A_r F_rs of element r's link from element s, in either store; −1 where r has none from s.
  auto exchange_from = [&](int r, int s) {
    const auto first = h.links.begin() + h.link_start[r];
    const auto last = h.links.begin() + h.link_start[r + 1];
    auto it = std::lower_bound(first, last, s, [](const Link& a, int x) { return a.source < x; });
    while (it != last && it->source == s && it->from_cluster) ++it;
    if (it != last && it->source == s)
      return h.elements[r].area * it->mean_factor();
    const std::span<const LeafLink> leaf = h.leaf_links_of(r);
    const auto at = std::lower_bound(leaf.begin(), leaf.end(), s, [](const LeafLink& a, int x) { return a.source < x; });
    if (at != leaf.end() && at->source == s) return h.elements[r].area * double(at->F);
    return -1.0;
  };
  auto add = [](Reciprocity& r, double g, double g_back) {
    const double big = std::max(g, g_back);
    if (!(g_back >= 0) || !(big > 0)) return;
    r.worst = std::max(r.worst, std::abs(g - g_back) / big);
    r.differ += std::abs(g - g_back);
    r.exchanged += big;
  };
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, h.elements.size(), 256), Reciprocity{},
      [&](const auto& range, Reciprocity r) {
        for (std::size_t e = range.begin(); e != range.end(); ++e) {
          const int receiver = static_cast<int>(e);
          const double area = h.elements[e].area;
          for (std::size_t i = h.link_start[e]; i < h.link_start[e + 1]; ++i) {
            const Link& l = h.links[i];
            if (l.from_cluster) continue;
            add(r, area * l.mean_factor(), exchange_from(l.source, receiver));
          }
          for (const LeafLink& l : h.leaf_links_of(receiver)) add(r, area * double(l.F), exchange_from(l.source, receiver));
        }
        return r;
      },
      [](Reciprocity a, const Reciprocity& b) {
        a.worst = std::max(a.worst, b.worst);
        a.differ += b.differ;
        a.exchanged += b.exchanged;
        return a;
      });
}

}  // namespace lambert::hierarchical
