// The rule each leaf of the final gather integrates its links with, and the row it gathers
// (LeafGather::gather_leaf): see final_gather.h.
#include <algorithm>
#include <cmath>

#include "solver/cubature.h"
#include "solver/hierarchical/final_gather.h"

namespace lambert::hierarchical {

void LeafGather::leaf_pieces(const Element& L, const std::vector<Entry>& entries, const std::vector<char>& cut,
                 std::vector<Triangle>& pieces) const {
  thread_local std::vector<Triangle> next;
  pieces.assign(1, L.tri);
  if (retrace_) {
    std::array<std::pair<Vector3, Point3>, kMaxCuttingPlanes> planes;  // unit normal, a point on it
    int count = 0;
    const double tolerance = 1e-6 * L.radius;  // planes closer than this at the leaf: one cut
    for (std::size_t k = 0; k < entries.size() && count < kMaxCuttingPlanes; ++k) {
      if (!cut[k]) continue;
      const Element& S = h_.elements[entries[k].source];
      const bool known = std::any_of(planes.begin(), planes.begin() + count, [&](const auto& plane) {
        return std::abs(dot(plane.first, S.normal)) > 1 - 1e-12 &&
               std::abs(dot(plane.first, S.tri.v[0] - plane.second)) <= tolerance;
      });
      if (!known) planes[count++] = {S.normal, S.tri.v[0]};
    }
    for (int k = 0; k < count; ++k) {
      const auto& [m, o] = planes[k];
      next.clear();
      for (const Triangle& t : pieces) {
        const FrontPart front = front_part(t, o, m), back = front_part(t, o, -m);
        if (!front.cut) {
          next.push_back(t);
          continue;
        }
        for (int i = 0; i < front.count; ++i) next.push_back(front.pieces[i]);
        for (int i = 0; i < back.count; ++i) next.push_back(back.pieces[i]);
      }
      pieces.swap(next);
    }
  }
}

bool LeafGather::within(const Point3& p, const Element& S, double reach) {
  const double bound = reach + S.radius;
  if (length_squared(p - S.centre) > bound * bound * (1 + 1e-9)) return false;
  return distance_to_triangle(p, S.tri) <= reach * kTie;
}

void LeafGather::leaf_rule(const Element& L, const std::vector<Triangle>& pieces, std::vector<Point3>& nodes,
                      std::vector<double>& weights) {
  const TriangleRule rule = triangle_rule_degree5();
  nodes.clear(), weights.clear();
  for (const Triangle& t : pieces) {
    const double share = pieces.size() == 1 ? 1.0 : t.area() / L.area;
    for (int q = 0; q < rule.size; ++q) {
      const auto& w = rule.nodes[q];
      nodes.push_back(barycentric(t.v[0], t.v[1], t.v[2], w[0], w[1], w[2]));
      weights.push_back(rule.weights[q] * share);
    }
  }
}

bool LeafGather::split_near(std::vector<Triangle>& pieces, std::span<const Triangle* const> near) {
  thread_local std::vector<Triangle> next;
  next.clear();
  for (const Triangle& t : pieces) {
    const Point3 c = t.centroid();
    double r = 0;
    for (const Point3& v : t.v) r = std::max(r, distance(c, v));
    const bool close = std::any_of(near.begin(), near.end(), [&](const Triangle* S) {
      return distance_to_triangle(c, *S) <= kRuleSplitDistance * r * kTie;
    });
    if (!close) {
      next.push_back(t);
      continue;
    }
    const auto mid = [](const Point3& a, const Point3& b) { return a + (b - a) * 0.5; };
    const Point3 m01 = mid(t.v[0], t.v[1]), m12 = mid(t.v[1], t.v[2]), m20 = mid(t.v[2], t.v[0]);
    next.push_back(Triangle{{t.v[0], m01, m20}});
    next.push_back(Triangle{{m01, t.v[1], m12}});
    next.push_back(Triangle{{m20, m12, t.v[2]}});
    next.push_back(Triangle{{m01, m12, m20}});
  }
  if (next.size() == pieces.size()) return false;
  pieces.swap(next);
  return true;
}

void LeafGather::gather_leaf(int e, const std::vector<Entry>& entries, std::vector<Link>& row, LeafGatherStats& stats) const {
  const Element& L = h_.elements[e];
  thread_local std::vector<char> usable, cut;
  usable.resize(entries.size()), cut.resize(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const Element& S = h_.elements[entries[k].source];
    usable[k] = entries[k].source != e && !h_.is_enclosed(entries[k].source) &&
                any_in_front(L.tri, L.normal, S.tri) && any_in_front(S.tri, S.normal, L.tri);
    cut[k] = usable[k] && plane_cuts(L.tri, S.tri.v[0], S.tri.area_vector());
  }
  // Where the leaf is small beside its distance to the source and wholly in front of the source's
  // plane, the kernel is smooth over it and the rule alone is exact to about 1e-6; nearer, the
  // link's factor is the exact mean.
  thread_local std::vector<double> near_F;  // per entry: the exact mean where near, else −1
  near_F.assign(entries.size(), -1.0);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    if (!usable[k]) continue;
    const Triangle& S = h_.elements[entries[k].source].tri;
    if (cut[k] || within(L.centre, h_.elements[entries[k].source], kLeafFarField * L.radius))
      near_F[k] = exchange_area(L.tri, S, near_field_) / L.area;
  }
  thread_local std::vector<Triangle> pieces;
  leaf_pieces(L, entries, cut, pieces);
  // The near sources, and the leaf's own near links that stay (wholly visible, exact means too).
  thread_local std::vector<const Triangle*> near;
  thread_local std::vector<double> kept_F;
  near.clear(), kept_F.clear();
  if (retrace_) {
    for (std::size_t l = h_.link_start[e]; l < h_.link_start[e + 1]; ++l) {
      const Link& link = h_.links[l];
      if (link.from_cluster || expanded(link, l, e)) continue;
      const Triangle& S = h_.elements[link.source].tri;
      if (!within(L.centre, h_.elements[link.source], kLeafFarField * L.radius)) continue;
      near.push_back(&S);
      kept_F.push_back(link.mean_factor());
    }
    for (std::size_t k = 0; k < entries.size(); ++k)
      if (near_F[k] >= 0) near.push_back(&h_.elements[entries[k].source].tri);
  }
  const std::size_t begin = row.size();
  thread_local std::vector<Point3> nodes;
  thread_local std::vector<double> weights, f;
  thread_local std::vector<int> row_entry;  // per link formed: its entry
  for (int level = 0;; ++level) {
    leaf_rule(L, pieces, nodes, weights);
    LeafGatherStats attempt;
    row_entry.clear();
    form_links(e, entries, usable, near_F, nodes, weights, row, row_entry, attempt);
    stats.rays += attempt.rays;  // traced in every attempt, the links counted in the last
    bool done = !retrace_ || near.empty() || level == kRuleLevels;
    if (!done) {
      double missed = 0;  // Σ v (F − F_rule) over the near sources
      f.resize(nodes.size());
      const auto rule_mean = [&](const Triangle& S) {
        point_triangle_factors(nodes, L.normal, S, f);
        double F = 0;
        for (std::size_t q = 0; q < nodes.size(); ++q) F += weights[q] * f[q];
        return F;
      };
      for (std::size_t i = 0; i < kept_F.size(); ++i) missed += kept_F[i] - rule_mean(*near[i]);
      for (std::size_t i = begin; i < row.size(); ++i) {
        const double F = near_F[row_entry[i - begin]];
        if (F < 0 || row[i].source == kReplaced) continue;
        missed += row[i].coeff[0] * (1 - rule_mean(h_.elements[row[i].source].tri) / F);
      }
      done = std::abs(missed) <= kRuleTolerance || !split_near(pieces, near);
    }
    if (done) {
      stats.traced += attempt.traced, stats.exact += attempt.exact;
      break;
    }
    row.resize(begin);
  }
  row.erase(std::remove_if(row.begin() + static_cast<std::ptrdiff_t>(begin), row.end(),
                           [](const Link& l) { return l.source == kReplaced; }),
            row.end());
  stats.leaf_links += row.size() - begin;
}

}  // namespace lambert::hierarchical
