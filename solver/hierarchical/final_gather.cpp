#include "solver/hierarchical/final_gather.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <numeric>

namespace lambert::hierarchical {

LeafGather::LeafGather(Hierarchy& h, const ExactVisibility& exact, const PlaneVerdicts& planes, const Visibility& vis,
                       std::span<const Triangle> inputs, std::span<const Hemisphere> hemispheres, bool retrace,
                       const AreaFactorOptions& near_field, OracleBudget oracle)
    : h_(h), exact_(exact), planes_(planes), vis_(vis), inputs_(inputs), retrace_(retrace), near_field_(near_field),
      oracle_(oracle) {
  const std::size_t E = h.elements.size();
  leaves_below_.assign(E, 0);
  leaks_below_.assign(E, 0);
  for (std::size_t e = E; e-- > 0;) {  // children come after their parent
    const Element& el = h.elements[e];
    if (el.leaf >= 0) {
      leaves_below_[e] = 1;
      const Hemisphere hemisphere = hemispheres[static_cast<std::size_t>(el.leaf)];
      leaks_below_[e] = hemisphere == Hemisphere::Leaking || hemisphere == Hemisphere::Enclosed;
    }
    if (el.parent >= 0) {
      leaves_below_[el.parent] += leaves_below_[e];
      leaks_below_[el.parent] = leaks_below_[el.parent] || leaks_below_[e];
    }
  }
  cluster_parent_.assign(h.clusters.size(), -1);
  cluster_of_root_.assign(E, -1);
  for (std::size_t c = 0; c < h.clusters.size(); ++c) {
    const Cluster& C = h.clusters[c];
    if (C.root >= 0) cluster_of_root_[C.root] = static_cast<int>(c);
    else
      for (int ch : C.child) cluster_parent_[ch] = static_cast<int>(c);
  }
  cluster_leaves_.assign(h.clusters.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h.clusters.size(), 64), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      const Cluster& C = h.clusters[c];
      for (int k = C.first_root; k < C.first_root + C.root_count; ++k) cluster_leaves_[c] += leaves_below_[h.root_order[k]];
    }
  });
}

void LeafGather::mark_cluster_links(bool proven) {
  cluster_link_expands_.assign(h_.cluster_links.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h_.cluster_links.size(), 16), [&](const auto& range) {
    for (std::size_t l = range.begin(); l != range.end(); ++l) cluster_link_expands_[l] = expands(l, proven);
  });
}

bool LeafGather::fits(std::size_t budget) {
  if (retrace_) mark_crowded_links();
  mark_cluster_links(true);
  std::size_t n = count();
  if (n <= budget) return n > 0;
  if (cap_certain(budget)) return true;
  if (partly_hidden_) {  // the links found partly hidden (and, by default, into clusters) stay
    partly_hidden_ = false;
    mark_cluster_links(true);
    n = count();
  }
  if (n > budget && !retrace_) {  // (with retrace every link into a cluster expands, proven or not)
    mark_cluster_links(false);
    n = count();
  }
  if (n > budget && clustered_hidden_) {  // without the hidden links from and into clusters
    clustered_hidden_ = false;
    n = count();
  }
  if (n > budget) n = cap_receivers(budget);
  return n > 0 && n <= budget;
}

bool LeafGather::cap_certain(std::size_t budget) {
  max_certain_leaves_ = 0;
  if (count() > budget / kUncertainShare) {
    max_certain_leaves_ = SIZE_MAX;
    return false;
  }
  if (largest_cap(max_certain_leaves_, budget, false) > 0) return true;
  max_certain_leaves_ = SIZE_MAX;
  return false;
}

std::size_t LeafGather::cap_receivers(std::size_t budget) {
  // Every kind of link expands again, but only into the receivers ranked first: the leaves' own
  // bright links, evaluated exactly, are most of what the gather corrects where a shadow falls (the
  // ball under a panel in tests/leaf_gather_test.cpp: 0.125 % rms of the floor's E with a 17th of
  // the leaf links, 0.09 % with all, 0.31 % with none, and 0.31 % at half the budget with only the
  // links fits() keeps to the last).
  partly_hidden_ = clustered_hidden_ = true;
  rank_receivers();
  return largest_cap(max_rank_, budget, true);
}

void LeafGather::rank_receivers() {
  const std::size_t E = h_.elements.size(), C = h_.clusters.size();
  // Per receiver (elements, then clusters): the error bound b_r of the links that would expand there
  // (as count() finds them, every receiver admitted) and the leaf links m_r they form per leaf.
  max_rank_ = SIZE_MAX;
  mark_cluster_links(true);
  std::vector<double> bound(E + C, 0.0), sources(E + C, 0.0);
  const auto add = [&](std::size_t r, const auto& link, std::size_t m, double uncertain_F) {
    const std::span<const double> B = link.from_cluster ? oracle_.cluster_B : oracle_.element_B;
    bound[r] += B[static_cast<std::size_t>(link.source)] * (link.error_per_B + uncertain_F);
    sources[r] += static_cast<double>(m);
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, E, 1024), [&](const auto& range) {
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      const int receiver = static_cast<int>(e);
      for (std::size_t l = h_.link_start[e]; l < h_.link_start[e + 1]; ++l)
        if (expanded(h_.links[l], l, receiver)) {
          const Link& link = h_.links[l];
          add(e, link, sources_of(link, l, receiver), certain(link, l, receiver) ? 0.0 : link.mean_factor());
        }
      for (std::size_t l = hidden_first(e); l < hidden_first(e + 1); ++l) {
        const std::size_t m = (retrace_ ? sources_of_hidden(l).size() : 0) + own_hidden(receiver, l);
        if (m > 0) add(e, h_.hidden_links[l], m, 0.0);
      }
    }
  });
  for (std::size_t l = 0; l < h_.cluster_links.size(); ++l)
    if (cluster_link_expands_[l]) {
      const ClusterLink& link = h_.cluster_links[l];
      add(E + link.receiver, link, roots_of(link), link.proven_visible || link.from_cluster ? 0.0 : link.coeff[0]);
    }
  if (retrace_ && clustered_hidden_)
    for (std::size_t l = 0; l < h_.hidden_cluster_links.size(); ++l)
      if (hidden_cluster_expands(l)) {
        const ClusterLink& link = h_.hidden_cluster_links[l];
        add(E + link.receiver, link, roots_of(link), 0.0);
      }
  // Each leaf's bound: the sum over the elements above it (parents come before their children),
  // then each receiver's sum of its leaves' bounds. The clusters above a root are left out of the
  // leaf's bound: theirs take the largest radiosity below a source cluster and a one-point estimate's
  // bound, looser than an element link's, and added to every leaf below they rank receivers by
  // where the clusters are rather than where the leaves err (the 107 000-patch room of final_gather.h:
  // its floor 0.27 % rms off the gather of every link with them, 0.16 % without).
  std::vector<double> above(E, 0.0), leaf_sum(E + C, 0.0);
  for (std::size_t e = 0; e < E; ++e) {
    const int parent = h_.elements[e].parent;
    above[e] = bound[e] + (parent >= 0 ? above[parent] : 0.0);
  }
  for (std::size_t e = E; e-- > 0;) {
    if (h_.elements[e].leaf >= 0) leaf_sum[e] += above[e];
    if (h_.elements[e].parent >= 0) leaf_sum[h_.elements[e].parent] += leaf_sum[e];
  }
  for (std::size_t c = 0; c < C; ++c) {
    const Cluster& cl = h_.clusters[c];
    for (int k = cl.first_root; k < cl.first_root + cl.root_count; ++k) leaf_sum[E + c] += leaf_sum[h_.root_order[k]];
  }
  std::vector<double> gain(E + C, 0.0);
  for (std::size_t r = 0; r < E + C; ++r) {
    const std::size_t leaves = r < E ? leaves_below_[r] : cluster_leaves_[r - E];
    if (leaves > 0 && sources[r] > 0) gain[r] = bound[r] * leaf_sum[r] / (static_cast<double>(leaves) * sources[r]);
  }
  std::vector<std::size_t> order(E + C);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return gain[a] > gain[b]; });
  rank_.assign(E, 0);
  cluster_rank_.assign(C, 0);
  for (std::size_t k = 0; k < order.size(); ++k) (order[k] < E ? rank_[order[k]] : cluster_rank_[order[k] - E]) = k + 1;
}

std::size_t LeafGather::largest_cap(std::size_t& cap, std::size_t budget, bool cluster_links) {
  const auto counted = [&] {
    if (cluster_links) mark_cluster_links(true);
    return count();
  };
  std::size_t fits = 0, over = h_.elements.size() + h_.clusters.size() + 1;
  while (over - fits > 1) {
    cap = fits + (over - fits) / 2;
    if (counted() <= budget) fits = cap;
    else over = cap;
  }
  cap = fits;
  return counted();
}

LeafGatherStats LeafGather::run(const SolveControl& control) {
  const std::size_t blocks = h_.root_block.size();
  std::vector<std::vector<Link>> out(blocks);
  tbb::combinable<LeafGatherStats> stats;
  std::atomic<bool> stop{false};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const auto& range) {
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      if (stop.load(std::memory_order_relaxed)) return;
      if (control.cancelled()) {
        stop = true;
        return;
      }
      gather_block(r, out[r], stats.local());
    }
  });
  control.check_cancel();
  // Each block read only its own elements' links, so the expanded ones are marked once all are done.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h_.elements.size(), 1024), [&](const auto& range) {
    for (std::size_t e = range.begin(); e != range.end(); ++e)
      for (std::size_t l = h_.link_start[e]; l < h_.link_start[e + 1]; ++l)
        if (expanded(h_.links[l], l, static_cast<int>(e))) h_.links[l].source = kReplaced;
  });
  merge_rechecked(h_.links, {});  // drops the expanded ones
  // The leaf links, compact (LeafLink): blocks in element order, each receiver's links by source.
  std::size_t total = 0;
  for (const auto& block : out) total += block.size();
  h_.leaf_links.clear();
  h_.leaf_links.reserve(total);
  h_.leaf_link_start.assign(h_.elements.size() + 1, 0);
  for (auto& block : out) {
    for (const Link& l : block) {
      ++h_.leaf_link_start[l.receiver + 1];
      h_.leaf_links.push_back({l.source, l.coeff[0], l.read_point()});
    }
    release(block);
  }
  for (std::size_t e = 0; e < h_.elements.size(); ++e) h_.leaf_link_start[e + 1] += h_.leaf_link_start[e];
  release(h_.hidden_links);
  release(h_.hidden_cluster_links);
  std::size_t kept = 0;
  for (std::size_t l = 0; l < h_.cluster_links.size(); ++l)
    if (!cluster_link_expands_[l]) h_.cluster_links[kept++] = h_.cluster_links[l];
  h_.cluster_links.resize(kept);
  return stats.combine([](LeafGatherStats a, const LeafGatherStats& b) {
    a.leaf_links += b.leaf_links, a.traced += b.traced, a.exact += b.exact, a.rays += b.rays;
    return a;
  });
}

std::size_t LeafGather::count() const {
  std::size_t n = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, h_.elements.size(), 1024), std::size_t{0},
      [&](const auto& range, std::size_t sum) {
        for (std::size_t e = range.begin(); e != range.end(); ++e) {
          for (std::size_t l = h_.link_start[e]; l < h_.link_start[e + 1]; ++l)
            if (expanded(h_.links[l], l, static_cast<int>(e)))
              sum += leaves_below_[e] * sources_of(h_.links[l], l, static_cast<int>(e));
          for (std::size_t l = hidden_first(e); l < hidden_first(e + 1); ++l) {
            if (retrace_ && ranked(static_cast<int>(e))) sum += leaves_below_[e] * sources_of_hidden(l).size();
            sum += own_hidden(static_cast<int>(e), l);
          }
        }
        return sum;
      },
      std::plus<>());
  for (std::size_t l = 0; l < h_.cluster_links.size(); ++l)
    if (cluster_link_expands_[l])
      n += cluster_leaves_[h_.cluster_links[l].receiver] * roots_of(h_.cluster_links[l]);
  if (retrace_ && clustered_hidden_)
    for (std::size_t l = 0; l < h_.hidden_cluster_links.size(); ++l)
      if (hidden_cluster_expands(l))
        n += cluster_leaves_[h_.hidden_cluster_links[l].receiver] * roots_of(h_.hidden_cluster_links[l]);
  return n;
}

std::span<const int> LeafGather::small_cluster(int c) const {
  const Cluster& C = h_.clusters[c];
  if (C.root_count > kExpandedClusterRoots) return {};
  return {h_.root_order.data() + C.first_root, static_cast<std::size_t>(C.root_count)};
}

std::size_t LeafGather::sources_of(const Link& l, std::size_t index, int receiver) const {
  const bool exact = retrace_ && !keeps_rays(index);
  if (!l.from_cluster)
    return exact || l.visibility() == LinkVisibility::ShaftClear || rays_unanimous(l.visibility()) ||
                   (partly_hidden_ && l.visibility() == LinkVisibility::Unknown && !leaks_below_[receiver]) ||
                   clear(receiver, l.source)
               ? 1
               : 0;
  const auto roots = small_cluster(l.source);
  if (roots.empty()) return 0;
  if (!exact)
    for (int r : roots)
      if (!clear(receiver, r)) return 0;
  return roots.size();
}

std::span<const int> LeafGather::sources_of_hidden(std::size_t index) const {
  const Link& l = h_.hidden_links[index];
  if (crowded_.hidden[index]) return {};
  if (!l.from_cluster) return {&l.source, 1};
  return clustered_hidden_ ? small_cluster(l.source) : std::span<const int>{};
}

LinkVisibility LeafGather::verdict_of(const Link& l, std::size_t index) const {
  return retrace_ && crowded_.link[index] && rays_unanimous(l.visibility()) ? LinkVisibility::RaysTrusted
                                                                                               : l.visibility();
}

bool LeafGather::crowded(const Bounds3& receiver, const Bounds3& source) const {
  Bounds3 box = receiver;
  box.add(source);
  return exact_.occluders_near_box(box) > kExactOccluders;
}

bool LeafGather::crowded(const Link& l) const {
  return crowded(box_of(l.receiver), l.from_cluster ? h_.clusters[l.source].box : box_of(l.source));
}

bool LeafGather::crowded(const ClusterLink& l) const {
  return crowded(h_.clusters[l.receiver].box, l.from_cluster ? h_.clusters[l.source].box : box_of(l.source));
}

std::size_t LeafGather::crowded_links() const {
  const auto ones = [](const std::vector<char>& v) { return static_cast<std::size_t>(std::count(v.begin(), v.end(), 1)); };
  return ones(crowded_.link) + ones(crowded_.hidden) + ones(crowded_.hidden_cluster) + ones(crowded_.cluster);
}

void LeafGather::mark_crowded_links() {
  crowded_.link.assign(h_.links.size(), 0);
  crowded_.hidden.assign(h_.hidden_links.size(), 0);
  crowded_.hidden_cluster.assign(h_.hidden_cluster_links.size(), 0);
  crowded_.cluster.assign(h_.cluster_links.size(), 0);
  if (exact_.occluders() <= kSmallScene) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h_.elements.size(), 256), [&](const auto& range) {
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      for (std::size_t l = h_.link_start[e]; l < h_.link_start[e + 1]; ++l) {
        const Link& link = h_.links[l];
        if (!link.from_cluster && (link.visibility() == LinkVisibility::ShaftClear || clear(static_cast<int>(e), link.source))) continue;
        crowded_.link[l] = crowded(link);
      }
      for (std::size_t l = h_.hidden_start[e]; l < h_.hidden_start[e + 1]; ++l) crowded_.hidden[l] = crowded(h_.hidden_links[l]);
    }
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h_.cluster_links.size(), 16), [&](const auto& range) {
    for (std::size_t l = range.begin(); l != range.end(); ++l) {
      const ClusterLink& link = h_.cluster_links[l];
      crowded_.cluster[l] = (!link.from_cluster || !small_cluster(link.source).empty()) && crowded(link);
    }
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h_.hidden_cluster_links.size(), 16), [&](const auto& range) {
    for (std::size_t l = range.begin(); l != range.end(); ++l) crowded_.hidden_cluster[l] = crowded(h_.hidden_cluster_links[l]);
  });
}

bool LeafGather::expands(std::size_t index, bool proven) const {
  const ClusterLink& l = h_.cluster_links[index];
  std::array<int, 1> element{l.source};
  const std::span<const int> sources = l.from_cluster ? small_cluster(l.source) : std::span<const int>(element);
  if (sources.empty() || !cluster_ranked(l.receiver)) return false;
  if (retrace_) return !crowded_.cluster[index] || partly_hidden_;
  if (partly_hidden_ || (proven && l.proven_visible)) return true;
  const Cluster& R = h_.clusters[l.receiver];
  if (static_cast<std::size_t>(R.root_count) * sources.size() > kMaxCheckedPairs) return false;
  for (int k = R.first_root; k < R.first_root + R.root_count; ++k)
    for (int s : sources)
      if (!clear(h_.root_order[k], s)) return false;
  return true;
}

bool LeafGather::expanded(const Link& l, std::size_t index, int receiver) const {
  if (!ranked(receiver) || sources_of(l, index, receiver) == 0) return false;
  if (h_.elements[receiver].leaf < 0 || l.from_cluster)
    return leaves_below_[receiver] <= max_certain_leaves_ || !certain(l, index, receiver);
  if (!retrace_ || keeps_rays(index)) return own_exact(l, index, receiver);
  return l.visibility() != LinkVisibility::ShaftClear && !clear(receiver, l.source);
}

bool LeafGather::certain(const Link& l, std::size_t index, int receiver) const {
  if (retrace_ && !keeps_rays(index)) return false;  // evaluated exactly at each leaf
  if (l.from_cluster) return true;  // (by default expanded only where every root is clear: sources_of)
  const LinkVisibility v = l.visibility();
  return v == LinkVisibility::ShaftClear || rays_unanimous(v) || clear(receiver, l.source);
}

bool LeafGather::own_hidden(int e, std::size_t index) const {
  if (!partly_hidden_ || h_.elements[e].leaf < 0 || leaks_below_[e]) return false;
  if (!retrace_) return true;  // the refiner kept only the bright pairs (Refiner::keeps_bright_hidden)
  const Link& l = h_.hidden_links[index];
  return crowded_.hidden[index] && !l.from_cluster &&
         bright_leaf_pair(h_.elements[e], h_.elements[l.source], oracle_.element_B[static_cast<std::size_t>(l.source)],
                          oracle_.epsilon);
}

bool LeafGather::own_exact(const Link& l, std::size_t index, int receiver) const {
  const LinkVisibility v = l.visibility();
  return (!retrace_ || keeps_rays(index)) && !l.from_cluster &&
         (v == LinkVisibility::Unknown || v == LinkVisibility::RaysUnanimous) && h_.elements[receiver].leaf >= 0 &&
         bright(receiver, l.source, l.mean_factor()) && !clear(receiver, l.source);
}

void LeafGather::gather_block(std::size_t r, std::vector<Link>& out, LeafGatherStats& stats) const {
  const auto [first, end] = h_.root_block[r];
  // Expanded links into the clusters above this root: the same sources for all its leaves.
  std::vector<Entry> from_cluster_links;
  // (exact: with retrace, unless the link is crowded; its leaves then take their own rays as by default)
  auto add_sources = [&](const ClusterLink& link, bool exact) {
    const LinkVisibility verdict = link.proven_visible ? LinkVisibility::ShaftClear : LinkVisibility::Unknown;
    if (!link.from_cluster) from_cluster_links.push_back({link.source, verdict, exact});
    for (int s : link.from_cluster ? small_cluster(link.source) : std::span<const int>{})
      from_cluster_links.push_back({s, verdict, exact});
  };
  for (int c = cluster_of_root_[first]; c >= 0; c = cluster_parent_[c]) {
    for (std::size_t l = h_.cluster_link_start[c]; l < h_.cluster_link_start[c + 1]; ++l)
      if (cluster_link_expands_[l]) add_sources(h_.cluster_links[l], retrace_ && !crowded_.cluster[l]);
    if (retrace_ && clustered_hidden_)
      for (std::size_t l = h_.hidden_cluster_start[c]; l < h_.hidden_cluster_start[c + 1]; ++l)
        if (hidden_cluster_expands(l)) add_sources(h_.hidden_cluster_links[l], true);
  }
  std::vector<Entry> entries;
  std::vector<Link> row;
  for (int e = first; e < end; ++e) {
    if (h_.elements[e].leaf < 0 || h_.is_enclosed(e)) continue;
    entries = from_cluster_links;
    for (int p = e; p >= 0; p = h_.elements[p].parent) {
      for (std::size_t l = h_.link_start[p]; l < h_.link_start[p + 1]; ++l) {
        const Link& link = h_.links[l];
        if (!expanded(link, l, p)) continue;
        if (!link.from_cluster)
          entries.push_back({link.source, verdict_of(link, l), (retrace_ && !keeps_rays(l)) || own_exact(link, l, p)});
        for (int s : link.from_cluster ? small_cluster(link.source) : std::span<const int>{})
          entries.push_back({s, LinkVisibility::Unknown, retrace_});
      }
      for (std::size_t l = hidden_first(p); l < hidden_first(p + 1); ++l) {
        if (retrace_ && ranked(p))
          for (int s : sources_of_hidden(l)) entries.push_back({s, LinkVisibility::Unknown, true});
        if (p == e && own_hidden(e, l)) entries.push_back({h_.hidden_links[l].source, LinkVisibility::Unknown, true});
      }
    }
    row.clear();
    gather_leaf(e, entries, row, stats);
    std::sort(row.begin(), row.end(), link_order<Link>);
    out.insert(out.end(), row.begin(), row.end());
  }
}

}  // namespace lambert::hierarchical
