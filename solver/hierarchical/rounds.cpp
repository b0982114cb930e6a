// The refine–solve rounds of the hierarchical operator (HierarchicalOperator::next_round and
// close_rows; the pipeline solves between them).
//
// Round 0 refines every receiver against the top cluster with the oracle's first estimate of the
// radiosity (the first bounce and an ambient term, oracle.h); later rounds recheck every link with the
// solved radiosity and refine those over the budget. The final gather at the leaves (final_gather.h)
// comes once the links are final: in the last round, or after the round that changed nothing. Each
// round's operator is balanced (closure.h): toward the oracle's target in the rounds whose solutions
// only guide the refinement, toward the final target last.
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "solver/hierarchical/final_gather.h"
#include "solver/hierarchical/hierarchical_operator.h"
#include "solver/hierarchical/oracle.h"
#include "solver/hierarchical/reciprocity.h"

namespace lambert::hierarchical {
namespace {

// ε = accuracy × (mean radiosity) / kPowerShare: the irradiance error a link may carry at the patch
// scale (see Refiner::area_weight above it).
constexpr double kPowerShare = 1;

// Receivers against the top cluster, as pairs of clusters: a receiving cluster cannot link with the
// top cluster, which holds it, so the receivers are split breadth-first first, until there are
// enough pairs to share among the threads.
std::vector<std::pair<int, int>> first_pairs(const Hierarchy& h) {
  std::vector<std::pair<int, int>> pairs = {{0, 0}}, next;
  while (pairs.size() < 256) {
    next.clear();
    for (const auto& [rc, sc] : pairs) {
      const Cluster& R = h.clusters[rc];
      if (R.root >= 0) {
        next.emplace_back(rc, sc);
      } else {
        next.emplace_back(R.child[0], sc);
        next.emplace_back(R.child[1], sc);
      }
    }
    if (next.size() == pairs.size()) break;
    pairs.swap(next);
  }
  return pairs;
}

}  // namespace

// What the rounds need of the systems, once: which leaves emit or send anything, the area that
// takes part, and the balance targets for the largest reflectance.
void HierarchicalOperator::prepare_rounds(const SpectralSystems& systems) {
  const std::size_t N = patches_.size(), K = systems.size();
  Rounds& r = rounds_;
  r.started = true;
  r.emits.assign(N, 0), r.shoots.assign(N, 0);
  double rho_max = 0;  // of the leaves that are not enclosed, over the systems
  for (std::size_t i = 0; i < N; ++i) {
    for (std::size_t k = 0; k < K; ++k) {
      r.emits[i] = r.emits[i] || systems.emission(k, i) > 0;
      r.shoots[i] = r.shoots[i] || r.emits[i] || systems.reflectance(k, i) != 0;
      if (hemisphere_[i] != Hemisphere::Enclosed) rho_max = std::max(rho_max, std::abs(systems.reflectance(k, i)));
    }
    if (hemisphere_[i] != Hemisphere::Enclosed) r.total_area += patches_[i].area_m2;
  }
  r.final_target = balance_target(kFinalBalance, rho_max);
  r.oracle_target = balance_target(kOracleBalance, rho_max);
  // Hidden links are kept for the final gather's retrace (solver.exact_visibility); by default, only
  // bright pairs of leaves (Refiner::keeps_bright_hidden).
  if (scene_.solver.exact_visibility) {
    r.hidden_room.elements = static_cast<std::int64_t>(kMaxLeafLinks);
    r.hidden_room.clustered = static_cast<std::int64_t>(kMaxLeafLinks / 4);
  } else {
    r.hidden_room.bright_leaves = static_cast<std::int64_t>(kMaxLeafLinks / 16);  // 2 M: 56 MB of links
  }
}

bool HierarchicalOperator::next_round(const SpectralSystems& systems, const SolveControl& control) {
  Rounds& r = rounds_;
  if (r.done || patches_.empty()) return false;
  if (!r.started) prepare_rounds(systems);
  OracleRadiosity oracle;
  if (r.round < kRefineRounds) {
    const bool first = r.round == 0;
    if (refine(systems, first, oracle, control)) {
      ++own_.refine_rounds;
      r.final_balance = r.round == kRefineRounds - 1;
      if (r.final_balance) gather_at_leaves(oracle, control);
      // What each leaf sends: the radiosity of the last solve; before the first, the oracle's
      // estimate (M + ρ E_direct, and ρ times the mean interreflected irradiance), since a room lit
      // by an emitting panel has M + ρ E_direct = 0 on every reflector, whose columns would then be
      // left free in the first round, and the later rounds' balances would start without them.
      r.sends = first ? std::move(oracle.leaf_B) : largest_radiosity(systems);
      r.done = r.final_balance;
      ++r.round;
      return true;
    }
  }
  // The rounds ended on one that changed no link: the gather comes after that round's balance and
  // solve, which are taken again, toward the final target.
  r.done = true;
  if (!r.gathered) {
    if (oracle.leaf_B.empty()) oracle = oracle_radiosity(h_, systems, hemisphere_, r.shoots, false);
    gather_at_leaves(oracle, control);
  }
  r.sends = largest_radiosity(systems);
  r.final_balance = true;
  return true;
}

// One round of the refinement: all links (first) or the rechecks of the last round's. Returns whether
// the links changed; `oracle` is the radiosity it refined with.
bool HierarchicalOperator::refine(const SpectralSystems& systems, bool first, OracleRadiosity& oracle,
                                  const SolveControl& control) {
  oracle = oracle_radiosity(h_, systems, hemisphere_, rounds_.shoots, first);
  return refine_for(oracle, first, control);
}

double HierarchicalOperator::oracle_epsilon(const OracleRadiosity& oracle) const {
  return scene_.solver.accuracy * oracle.power / rounds_.total_area / kPowerShare;
}

bool HierarchicalOperator::refine_for(const OracleRadiosity& oracle, bool first, const SolveControl& control) {
  Rounds& r = rounds_;
  const OracleValues values = oracle_values(h_, oracle.leaf_B);
  const double accuracy = scene_.solver.accuracy;
  const double max_area = scene_.meshing.max_patch_area_m2.value_or(default_max_patch_area(scene_));
  const Refiner refiner(h_, *vis_, *shafts_, *planes_, *solid_shafts_, values, oracle_epsilon(oracle),
                        kUnitPatches * max_area, accuracy, r.exchange, r.hidden_room);
  found_.clear();
  bool changed = true;
  if (first) refine_first(refiner, control);
  else changed = recheck(refiner);
  control.check_cancel();
  for (const LinkBatch& batch : found_) own_link_rays_ += batch.rays;
  if (changed) store_links(first);
  return changed;
}

// For the geometry alone (view factors, radiant exchange): every leaf that takes part sends unit
// radiosity, so one round refines every link to the same share of the scene's mean exitance; then
// the final gather, and the final balance with every such leaf's root held to what it sends (the
// columns of an emitter: energy is conserved, so a closed enclosure's net fluxes sum to zero). The
// balance aims as for ρ = 0.9, where thermal exchange has its low emissivities.
void HierarchicalOperator::build_geometric(const SolveControl& control) {
  classify_hemispheres(control);
  const std::size_t N = patches_.size();
  Rounds& r = rounds_;
  r.started = r.done = true;
  OracleRadiosity oracle;
  oracle.leaf_B.assign(N, 0.0);
  r.emits.assign(N, 0), r.shoots.assign(N, 0);
  for (std::size_t i = 0; i < N; ++i) {
    if (hemisphere_[i] == Hemisphere::Enclosed) continue;
    oracle.leaf_B[i] = 1, r.emits[i] = r.shoots[i] = 1;
    r.total_area += patches_[i].area_m2;
  }
  oracle.power = r.total_area;
  if (N == 0 || !(r.total_area > 0)) return;
  r.final_target = r.oracle_target = balance_target(kFinalBalance, 0.9);
  refine_for(oracle, true, control);
  ++own_.refine_rounds;
  gather_at_leaves(oracle, control);
  r.sends = oracle.leaf_B;
  r.final_balance = true;
  close(control);
}

void HierarchicalOperator::refine_first(const Refiner& refiner, const SolveControl& control) {
  const std::vector<std::pair<int, int>> pairs = first_pairs(h_);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs.size(), 1), [&](const auto& range) {
    auto& out = found_.local();
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      if (control.cancelled()) return;
      refiner.refine_pair(pairs[p].first, pairs[p].second, true, out);
      refiner.resolve(out);
    }
  });
}

// Every link re-examined with the solved radiosity: those over the budget are marked replaced and
// refined into found_.
bool HierarchicalOperator::recheck(const Refiner& refiner) {
  tbb::combinable<bool> any_change([] { return false; });
  auto recheck_all = [&](auto& links, std::size_t grain) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, links.size(), grain), [&](const auto& range) {
      auto& out = found_.local();
      bool& c = any_change.local();
      for (std::size_t l = range.begin(); l != range.end(); ++l)
        if (refiner.recheck(links[l], out)) {
          links[l].source = kReplaced;
          c = true;
        }
      refiner.resolve(out);
    });
  };
  recheck_all(h_.links, 64);
  recheck_all(h_.cluster_links, 16);
  return any_change.combine([](bool a, bool b) { return a || b; });
}

// Round 0 found every link; later rounds only the replacements of those their rechecks refined.
void HierarchicalOperator::store_links(bool first) {
  constexpr double kHeadroom = 0.5;
  if (first) {
    h_.links = take_sorted(found_, &LinkBatch::links, kHeadroom);
    h_.cluster_links = take_sorted(found_, &LinkBatch::cluster_links, kHeadroom);
  } else {
    merge_rechecked(h_.links, take_sorted(found_, &LinkBatch::links));
    merge_rechecked(h_.cluster_links, take_sorted(found_, &LinkBatch::cluster_links));
  }
  const bool retrace = scene_.solver.exact_visibility;
  if (retrace ? rounds_.hidden_room.elements.load() <= 0 : rounds_.hidden_room.bright_leaves.load() <= 0) {
    // None kept, or past the room: the gather will not retrace (nor, by default, look at hidden leaves)
    h_.hidden_complete = false;
    release(h_.hidden_links);
    release(h_.hidden_cluster_links);
    for (LinkBatch& batch : found_) batch.hidden = {}, batch.hidden_cluster = {};
  } else {
    merge_rechecked(h_.hidden_links, take_sorted(found_, &LinkBatch::hidden));
    merge_rechecked(h_.hidden_cluster_links, take_sorted(found_, &LinkBatch::hidden_cluster));
  }
  h_.index_links(h_.elements.size(), h_.clusters);
}

// The final gather at the leaves (final_gather.h), once the links are final.
void HierarchicalOperator::gather_at_leaves(const OracleRadiosity& oracle, const SolveControl& control) {
  Rounds& r = rounds_;
  r.gathered = true;
  // The refinement's final element links that the occluder planes or the solids' shafts cleared (no
  // rays).
  own_links_clear_ = static_cast<std::uint64_t>(std::count_if(h_.links.begin(), h_.links.end(), [&](const Link& l) {
    return !l.from_cluster && l.source >= 0 &&
           (l.visibility() == LinkVisibility::SolidsClear || planes_->clear(l.receiver, l.source));
  }));
  const double accuracy = scene_.solver.accuracy;
  const bool retrace = scene_.solver.exact_visibility;
  AreaFactorOptions near_field;  // as the refiner's
  near_field.rel_tolerance = std::max(near_field.rel_tolerance, 0.1 * accuracy);
  near_field.abs_tolerance = std::max(near_field.abs_tolerance, 1e-3 * accuracy);
  const OracleValues values = oracle_values(h_, oracle.leaf_B);
  LeafGather gather(h_, *shafts_, *planes_, *vis_, inputs_, hemisphere_, retrace, near_field,
                    {values.element_B, values.cluster_B, oracle_epsilon(oracle)});
  const std::size_t N = patches_.size();
  const std::size_t budget =
      scene_.solver.leaf_link_budget > 0
          ? scene_.solver.leaf_link_budget
          : std::min(std::max(kLeafLinksPerLink * h_.links.size(), kLeafLinksPerPatch * N), kMaxLeafLinks);
  if (!scene_.solver.leaf_gather || (retrace && !h_.hidden_complete) || !gather.fits(budget)) {
    release(h_.hidden_links);  // kept for the gather only (LeafGather::run frees them too)
    release(h_.hidden_cluster_links);
    return;
  }
  const std::size_t refined_links = h_.links.size();
  const LeafGatherStats g = gather.run(control);
  own_.leaf_links = g.leaf_links;
  own_.leaf_links_traced = g.traced;
  own_.leaf_links_exact = g.exact;
  own_link_rays_ += g.rays;
  own_.crowded_links = gather.crowded_links();
  h_.index_links(h_.elements.size(), h_.clusters);
  // Where the leaf links are a small share of the links, the last balance's scales and its stop are
  // the start, as between refinement rounds; where the gather changed most rows (a room whose rows
  // closed to 2 % before and to 2e-6 after) they would be a worse start than 1.
  if (g.leaf_links > refined_links / 10) {
    h_.leaf_scale.assign(N, 1.0);
    h_.source_scale.assign(N, 1.0);
    h_.row_shift.clear();
    r.balance = BalanceState{};
  }
}

void HierarchicalOperator::close_rows(const SpectralSystems&, const SolveControl& control) { close(control); }

void HierarchicalOperator::close(const SolveControl& control) {
  Rounds& r = rounds_;
  const Balanced balanced = balance(h_, r.balance, hemisphere_, r.sends, r.emits, patches_,
                                    r.final_balance ? r.final_target : r.oracle_target, r.final_balance, control);
  max_closure_error_ = balanced.raw_error;
  closure_residual_ = balanced.residual;
  if (r.final_balance) {
    const Reciprocity reciprocity = reciprocity_error(h_);
    max_reciprocity_error_ = reciprocity.worst;
    mean_reciprocity_error_ = reciprocity.mean();
  }
}

std::vector<double> HierarchicalOperator::largest_radiosity(const SpectralSystems& systems) const {
  std::vector<double> B(patches_.size(), 0.0);
  for (std::size_t k = 0; k < systems.size(); ++k)
    for (std::size_t i = 0; i < B.size(); ++i) B[i] = std::max(B[i], std::abs(systems.radiosity(k, i)));
  return B;
}

}  // namespace lambert::hierarchical
