// The refinement of the hierarchical method: the BF oracle (Hanrahan, Salzman & Aupperle 1991) decides,
// for each pair of a receiving element or cluster and a source, whether one link carries their
// exchange within the budget ε, or whether the larger side is split and its children linked.
//
// A link is kept when B_source × (its irradiance error bound per unit radiosity) × max(1,
// A_receiver / (4 patch areas)) ≤ ε = solver.accuracy × (mean radiosity); otherwise the larger side
// is split. An element link carries the exact point-to-polygon kernel fitted by a linear function over
// the receiver (10 points; its residual is the link's error) times a kernel-weighted ray-traced visible
// fraction (16 rays, 64 where they disagree; none where the pair's shaft is clear), whose error is
// F / 2 before the rays and F max(v, 1 − v) once they find a visible fraction v below 1, F where they
// find the pair hidden (every leaf below takes v, and a leaf may see all of the source or none:
// docs/BENCHMARKS.md, "Where a faceted room's patch errors come from"); a link from a cluster
// carries a one-point estimate of the cluster's intensity (clusters.h), erring by about the pair's
// relative size, and only from a cluster whose bins read any radiosity (reads_any_radiosity); a link
// into a cluster needs the pair well separated (2.5 × the radii's sum).
#pragma once

#include <tbb/concurrent_unordered_map.h>

#include <atomic>
#include <cstdint>
#include <utility>
#include <vector>

#include "solver/exact_visibility.h"
#include "solver/form_factor.h"
#include "solver/hierarchical/hierarchy.h"
#include "solver/hierarchical/oracle.h"
#include "solver/hierarchical/plane_verdicts.h"
#include "solver/hierarchical/solid_shafts.h"
#include "solver/visibility.h"

namespace lambert::hierarchical {

// The oracle's area weight starts above this many patches (Refiner::area_weight).
inline constexpr double kUnitPatches = 4;

// A_r F_rs = A_s F_sr of near pairs of leaves (exchange_area), keyed by the pair (the lower element
// index in the high 32 bits): see Refiner::leaf_exchange.
using ExchangeCache = tbb::concurrent_unordered_map<std::uint64_t, double>;

// Room left for the links that rays found hidden (LinkSet::hidden_links), kept for
// solver.exact_visibility only; each one kept takes one, and at 0 no more are kept. Links between
// elements: when their room runs out the gather does not retrace at all (LinkSet::hidden_complete).
// Links from or into clusters have a room of their own, past which they are dropped (the city
// block's overran kMaxLeafLinks with one room for both, and its gather then did not retrace).
struct HiddenRoom {
  std::atomic<std::int64_t> elements{0}, clustered{0};
  // By default: bright pairs of leaves found hidden (Refiner::keeps_bright_hidden), whose visible
  // part the final gather evaluates exactly (LeafGather::own_hidden).
  std::atomic<std::int64_t> bright_leaves{0};
};

// The refinement of one (receiver, source) pair into links, with the BF oracle; `oracle`: its
// radiosity per element and cluster (oracle.h).
class Refiner {
 public:
  Refiner(const Hierarchy& h, const Visibility& vis, const ExactVisibility& shafts, const PlaneVerdicts& planes,
          const SolidShafts& solids, const OracleValues& oracle, double epsilon, double unit_area, double accuracy,
          ExchangeCache& exchange, HiddenRoom& hidden_room);

  // The oracle bounds irradiance errors at the patch scale and power errors above it: an error of
  // δE over a receiver of area A counts δE × max(1, A / unit_area). Coarse receivers (many patches)
  // may err more per unit area, since their links are pushed down to children that also gather
  // their own finer links; this keeps the link count near-linear.
  double area_weight(double receiver_area) const { return std::max(1.0, receiver_area / unit_area_); }


  void refine_to_element(int r, int s, LinkBatch& out) const;

  void refine_to_cluster(int r, int c, LinkBatch& out) const;

  // The refinement of the pair (receivers in cluster rc, source s: a cluster, or an element where
  // !from_cluster). A well separated pair links as a whole where the receivers' normals all face the
  // source (their cone lies in front of the direction between the centres, so (n · u)⁺ = n · u is
  // linear and V = Σ Ψ u serves them all) and the oracle allows the estimate, with what a receiver's
  // horizon may cut off the source (the cone widened by the pair's angle δ) as part of its error;
  // otherwise the larger side is split, the receivers where their normals are the obstacle. An element
  // source facing every receiver is read by its vector factor (link_vector_estimate), any other by its
  // one-point estimate. A receiver that is one root goes on as refine_to_cluster or refine_to_element.
  void refine_pair(int rc, int s, bool from_cluster, LinkBatch& out) const;
  // A link into cluster rc from element s where the source faces every receiver and every receiver's
  // normal faces the source's centre: it carries the source's vector factor at the cluster's centre
  // (triangle_vector_factor), exact there for every normal whose horizon leaves the whole source in
  // front, whatever the source's extent; refine_pair bounds the rest (vector_estimate_error, and the
  // part a horizon may cut).
  void link_vector_estimate(int rc, int s, double error_per_B, LinkBatch& out) const;

  // Traces the rays of the pending links, all at once as streams (16 per link before the first vote:
  // four unanimous rays between large elements miss small occluders; but four blocked rays may drop
  // a link whose whole transfer is within the oracle's ε), and keeps the visible ones with
  // their coefficients times the visible fraction. Element links pair the two elements' stratified
  // samples; cluster links go to points of the cluster's roots spread over its BVH range, each
  // weighted by the differential kernel with the sampled element's own normal (elements of the
  // cluster that face away, often hidden by the cluster itself, weigh nothing).
  void resolve(LinkBatch& out) const;
  // One pass of resolve over the pending element links; the pairs found partly visible beyond the
  // budget go to `resplit` instead of `out`.
  void resolve_pending(LinkBatch& out, std::vector<std::pair<int, int>>& resplit) const;

  // The rays of links into clusters: between samples of the receiving cluster's roots and of the
  // source's, each weighted by the kernel with both samples' own normals; 16 before the first vote.
  void resolve_cluster_links(LinkBatch& out) const;

  // Whether a link that rays found hidden is kept for the final gather (LinkSet::hidden_links):
  // while there is room, if the gather can expand its source (an element, or a cluster of at most
  // kExpandedClusterRoots roots). `clustered`: from a cluster or into one.
  bool keeps_hidden(bool clustered, bool from_cluster, int source) const;

  // Whether a pair of leaves that rays found hidden is kept for the final gather while there is room
  // (HiddenRoom::bright_leaves): where its unoccluded transfer exceeds the budget ε (`bright`), the
  // refiner cannot split it, and its 16 blocked rays leave room for a visible part that errs by more
  // than ε (a wall patch that sees an emitter over a beam's top through a strip of a few degrees).
  bool keeps_bright_hidden(bool bright) const;
  // Whether two leaves' transfer exceeds ε by twice the point factor at the receiver's centroid (the
  // estimate resolve_pending's early vote takes for pairs well apart).
  bool bright_leaves(const Link& link) const;

  // Re-examines a kept link into a cluster: keeps it (false) or refines the pair again (true).
  bool recheck(const ClusterLink& link, LinkBatch& out) const;

  // Re-examines a link with the current radiosity: keeps it (false) or refines it into `out` (true).
  bool recheck(const Link& link, LinkBatch& out) const;

 private:
  // Two leaves: nothing can be split, so the link needs neither the linear fit (a leaf takes the mean
  // of what it gathers) nor an error bound (recheck keeps leaf-to-leaf links), nor a shaft test (it
  // would only spare the rays of a clear link, and in cluttered scenes most links are not clear: a city
  // block cleared 6 % of its shafts at 3.8 µs each, the price of 40 rays).
  // Its factor waits for the rays (resolve()): most leaf pairs in a cluttered scene turn out wholly
  // hidden, and the factor of a near pair (adaptive cubature) cost more than their rays.
  // A pair that the occluder planes or the solids' shafts clear needs no rays: its factor now, and
  // wholly visible.
  void link_leaves(int r, int s, LinkBatch& out) const;

  // A_r F_rs = A_s F_sr of two leaves (exchange_area: the same whichever asks). Near pairs (adaptive
  // cubature, tens of µs at contact) are cached and computed once for both directions of their links:
  // in the city block of the benchmarks, pairs closer than 1.5 times their radii took 85 % of the
  // cubature.
  double leaf_exchange(int r, int s) const;

  // Splits the larger element of the pair (or the one that can be split) and links the children.
  void split(int r, int s, LinkBatch& out) const;

  // Traces the pending links once they fill a batch (kResolveBatch). Asked after each child of a
  // split, not only once per pair of the cluster tree: a pair of one large root (a room's floor, its
  // element tree of 10⁵ leaves) and a large source cluster yields millions of pending links, and the
  // rays of a batch are held together (weighted_visible_fractions: 64 bytes a ray, 16 rays a link).
  // Where the links are traced does not change what they are: each link's rays are its own.
  void resolve_if_full(LinkBatch& out) const;

  const Hierarchy& h_;
  const Visibility& vis_;
  const ExactVisibility& shafts_;
  const PlaneVerdicts& planes_;
  const SolidShafts& solids_;
  const std::vector<double>& element_B_;
  const std::vector<double>& cluster_B_;
  const ClusterSending& sending_;          // OracleValues::sending
  const std::vector<double>& departure_;  // OracleValues::element_departure
  double epsilon_;
  double unit_area_;
  AreaFactorOptions near_field_;
  ExchangeCache& exchange_;
  HiddenRoom& hidden_room_;
};

}  // namespace lambert::hierarchical
