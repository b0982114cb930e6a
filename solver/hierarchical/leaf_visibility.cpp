// The links of one leaf of the final gather, and the exact visible part of those whose visibility
// is not proven (LeafGather::form_links): see final_gather.h.
#include <algorithm>
#include <array>
#include <tuple>

#include "solver/hierarchical/final_gather.h"
#include "solver/visible_fraction.h"

namespace lambert::hierarchical {

void LeafGather::form_links(int e, const std::vector<Entry>& entries, const std::vector<char>& usable,
                            const std::vector<double>& near_F, std::span<const Point3> node_span,
                            std::span<const double> weights, std::vector<Link>& row, std::vector<int>& row_entry,
                            LeafGatherStats& stats) const {
  const Element& L = h_.elements[e];
  const std::size_t size = node_span.size();
  thread_local std::vector<double> f;
  // Evaluated exactly, and by the leaf's rays.
  thread_local Pending pending, traced;
  f.resize(size);
  for (Pending* p : {&pending, &traced}) {
    p->leaf = &L, p->nodes = node_span, p->weights = weights;
    p->links.clear(), p->f.clear();
  }
  for (std::size_t k = 0; k < entries.size(); ++k) {
    if (!usable[k]) continue;
    const Entry& entry = entries[k];
    const Element& S = h_.elements[entry.source];
    const bool proven = entry.verdict == LinkVisibility::ShaftClear || entry.verdict == LinkVisibility::SolidsClear ||
                        clear(e, entry.source);
    const bool near = near_F[k] >= 0;
    double F = 0;
    int f_row = -1;
    bool rule_factors = false;  // f holds the source's unoccluded factors at the nodes
    if (near) {
      F = near_F[k];
    } else if (!h_.has_children(entry.source)) {  // leaf pairs as the refiner's: A F the same both ways
      F = exchange_area(L.tri, S.tri, near_field_) / L.area;
    } else {
      point_triangle_factors(node_span, L.normal, S.tri, f);
      for (std::size_t q = 0; q < size; ++q) F += weights[q] * f[q];
      rule_factors = true;
    }
    if (!(F > 0)) continue;
    // Rays that all arrived are trusted, except for a bright link: its 16 clear rays leave room for an
    // occluder's edge that hides more than the budget (a floor leaf at a ball's penumbra, under a panel).
    const bool trusted = entry.verdict == LinkVisibility::RaysTrusted || (!retrace_ && rays_unanimous(entry.verdict));
    const bool is_bright = bright(e, entry.source, F);
    const bool visible = proven || (trusted && !is_bright);
    const bool exact = !visible && (entry.exact || is_bright);
    if (exact && rule_factors) {  // kept for the exact pass, which needs the same factors
      f_row = static_cast<int>(pending.f.size() / size);
      pending.f.insert(pending.f.end(), f.begin(), f.end());
    }
    Link link;
    link.receiver = e;
    link.source = entry.source;
    link.coeff.fill(static_cast<float>(F));
    // The link reads its source's radiosity where the leaf sees it (Link::bin), as the refiner's do.
    if (h_.has_children(entry.source)) link.bin = source_point_of(S, L);
    link.set_visibility(proven    ? LinkVisibility::ShaftClear
                        : visible ? LinkVisibility::RaysUnanimous
                                  : LinkVisibility::Unknown);
    if (!visible) {
      Pending& to = exact ? pending : traced;
      to.links.emplace_back(static_cast<int>(row.size()), f_row);
    }
    row.push_back(link);
    row_entry.push_back(static_cast<int>(k));
  }
  if (!pending.links.empty()) evaluate_pending(pending, row, stats);
  if (!traced.links.empty()) trace_pending(traced, row, stats);
}

// The leaf's own rays to each pending link's source, as the refiner's (Refiner::resolve_pending): the
// leaf's stratified samples paired with the source's, 16 before the first vote.
void LeafGather::trace_pending(Pending& pending, std::vector<Link>& row, LeafGatherStats& stats) const {
  thread_local std::vector<double> fraction;
  fraction.resize(pending.links.size());
  const Element& L = *pending.leaf;
  Vector3 source_normal;  // of the sample just drawn (the weight follows the endpoints for each ray)
  stats.rays += weighted_visible_fractions(
      vis_, pending.links.size(),
      [&](std::size_t l, int k) {
        const Element& S = h_.elements[row[pending.links[l].first].source];
        source_normal = S.normal;
        return element_pair_ray(vis_, L.tri, L.normal, S.tri, S.normal, k);
      },
      [&](std::size_t, const Point3& p, const Point3& q) { return link_weight(p, L.normal, q, source_normal); },
      fraction, 16);
  stats.traced += pending.links.size();
  for (std::size_t l = 0; l < pending.links.size(); ++l) set_visible_share(row[pending.links[l].first], fraction[l]);
}

// The visible part at the rule's nodes, exactly (no rays: rays that agree by chance kept the rows near
// an occluder from closing): F(x_q -> S) less the factor the occluders hide at each node, as a
// fraction of the link's unoccluded rule. The links are taken by the input triangle their source was
// cut from: the occluders in the shaft between the leaf and that triangle are the only ones any node
// can see in front of its sources (none: every one is wholly visible). Their shadows on its plane
// from each node (one convex polygon per group: a convex solid or a single triangle), united once as
// disjoint convex pieces, serve all its sources (ExactVisibility::Shadow).
void LeafGather::evaluate_pending(Pending& pending, std::vector<Link>& row, LeafGatherStats& stats) const {
  stats.traced += pending.links.size();
  // By input triangle, root and element: the carriers of the shadows, from the largest down.
  const auto key = [&](const std::pair<int, int>& entry) {
    const int source = row[entry.first].source;
    return std::tuple{h_.elements[source].input, h_.elements[source].root, source, entry.first};
  };
  std::sort(pending.links.begin(), pending.links.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
  const auto input_of = [&](std::size_t l) { return h_.elements[row[pending.links[l].first].source].input; };
  for (std::size_t g = 0, next; g < pending.links.size(); g = next) {
    for (next = g + 1; next < pending.links.size() && input_of(next) == input_of(g); ++next) {
    }
    evaluate_carrier(pending, row, inputs_[input_of(g)], 0, g, next, stats);
  }
}

// One shadow per node serves all the links of a carrier. Where the carrier's shaft holds more
// occluders than the links' own (a city block's ground, whose shaft from a facade takes in most
// buildings), they are taken root by root, then source by source: a source's shaft lies in its
// link's box, near which about kExactOccluders occluders lie at most.
void LeafGather::evaluate_carrier(Pending& pending, std::vector<Link>& row, const Triangle& carrier, int level,
                                  std::size_t first, std::size_t last, LeafGatherStats& stats) const {
  const Element& L = *pending.leaf;
  const std::size_t size = pending.nodes.size();
  thread_local std::vector<int> candidates;
  thread_local std::vector<ExactVisibility::Shadow> shadows;
  thread_local std::vector<double> f, hidden;
  const std::array<Point3, 6> hull{L.tri.v[0], L.tri.v[1], L.tri.v[2], carrier.v[0], carrier.v[1], carrier.v[2]};
  exact_.shaft_occluders(hull, candidates);
  if (candidates.empty()) {
    for (std::size_t l = first; l < last; ++l) row[pending.links[l].first].set_visibility(LinkVisibility::ShaftClear);
    return;
  }
  if (level < 2 && candidates.size() > kExactOccluders && last - first > 1) {
    const auto part = [&](std::size_t l) {
      const int source = row[pending.links[l].first].source;
      return level == 0 ? h_.elements[source].root : source;
    };
    for (std::size_t g = first, next; g < last; g = next) {
      for (next = g + 1; next < last && part(next) == part(g); ++next) {
      }
      evaluate_carrier(pending, row, h_.elements[part(g)].tri, level + 1, g, next, stats);
    }
    return;
  }
  if (shadows.size() < size) shadows.resize(size);
  f.resize(size), hidden.resize(size);
  for (std::size_t q = 0; q < size; ++q) exact_.shadow(pending.nodes[q], L.normal, carrier, candidates, shadows[q]);
  for (std::size_t l = first; l < last; ++l) {
    Link& link = row[pending.links[l].first];
    const Triangle& source = h_.elements[link.source].tri;
    bool any = false;
    for (std::size_t q = 0; q < size; ++q) {
      // +∞: wholly in the shadow, f[q] − hidden[q] is then 0 below
      hidden[q] = shadows[q].hidden_factor(source);
      any = any || hidden[q] > 0;
    }
    double v = 1;
    if (any) {
      const int f_row = pending.links[l].second;
      if (f_row < 0) point_triangle_factors(pending.nodes, L.normal, source, f);
      const double* fq = f_row < 0 ? f.data() : pending.f.data() + static_cast<std::size_t>(f_row) * size;
      double seen = 0, whole = 0;
      for (std::size_t q = 0; q < size; ++q) {
        seen += pending.weights[q] * std::max(0.0, fq[q] - hidden[q]);
        whole += pending.weights[q] * fq[q];
      }
      v = whole > 0 ? std::clamp(seen / whole, 0.0, 1.0) : 0.0;
      ++stats.exact;
    }
    set_visible_share(link, v);
  }
}

void LeafGather::set_visible_share(Link& link, double v) {
  if (v == 1) link.set_visibility(LinkVisibility::RaysUnanimous);
  for (float& c : link.coeff) c = static_cast<float>(c * v);
  if (!(v > 0)) link.source = kReplaced;  // hidden: dropped below
}

}  // namespace lambert::hierarchical
