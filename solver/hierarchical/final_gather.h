// The final gather at the leaves of the hierarchical method.
//
// The refinement's links are estimates that the oracle lets err by its budget each: an element link
// carries the kernel as a linear fit over its receiver, a cluster link a one-point estimate. In a row
// those errors add up: the raw row sums of a closed convex 6 × 4 × 3 m room (17 408 patches, no ray
// traced) missed 1 by 1.3 %, and with a floating cube by 2.1 %. Once the links are final, LeafGather
// computes each leaf's share of the links above it exactly — the point-to-polygon kernel of the
// source integrated over the leaf (the degree-5 rule where the source is more than kLeafFarField
// leaf radii away, adaptive cubature nearer) — and replaces those links by the leaf links. Links from
// clusters of at most kExpandedClusterRoots roots, and links into clusters from such sources, are
// expanded the same way, to the clusters' roots. The refinement still decides which sources a leaf
// gathers from, and those partition the scene: in a closed convex room the row sums become 1 to the
// cubature's tolerance (1.3 % → 2e-6 in the room above).
//
// Visibility. By default only links whose visibility holds for every leaf below are expanded: the
// refinement proved their shaft clear, or their rays were all unobstructed (the verdict the
// refinement itself trusts), or the occluder planes separate nothing between the pair
// (occluder_planes.h); links into clusters also where the refiner proved them wholly visible as it
// formed them (ClusterLink::proven_visible). Those carry a one-point or vector estimate whose
// errors, each within the oracle's budget, add up with one sign over many sources: a square
// emitter's elements lighting a faceted sphere through clusters erred by up to 9.8 % on facets the
// whole emitter lights, 5e-9 expanded (tests/faceted_spheres_test.cpp; docs/BENCHMARKS.md for the
// lit sphere room). Where their leaf links would pass the budget, they keep their estimates.
//
// Links found partly hidden, and the other links into clusters from elements or small clusters (whose
// rays were cast to the cluster as a whole), expand too, and each leaf link traces its own rays (16,
// then 64 where they disagree): their rays gave every leaf below one visible fraction, where a leaf
// in the corner of a wall sees past a sphere what the far half of its element does not. Each link's
// error is within the budget, but the links of one row share the shadow and err alike: in the lit
// sphere room, a corner leaf gathered 0.961 of its view, its 30 links from the far wall reading 47 %
// visible where the leaf sees 100 % (tests/leaf_gather_test.cpp; docs/BENCHMARKS.md). A leaf link
// whose transfer B_s F exceeds the oracle's budget ε is evaluated exactly instead, as below, where
// its rays disagreed or all arrived (bright, own_exact): 16 clear rays may pass beside an occluder's
// edge, and a leaf's links from one emitter share its shadow and err alike (the direct light of the
// lit sphere room: 0.142 % rms off an exact integration by rays, 0.096 % evaluated so). Where their
// leaf links would pass the budget, those links stay as they are, before the proven ones do; so do
// the element links whose receiver holds a leaking or enclosed leaf (leaks_below_). With `retrace`
// (the scene's solver.exact_visibility), every link is expanded, those found hidden too
// (LinkSet::hidden_links), and each leaf link whose visibility is not proven is evaluated exactly,
// with no ray: the occluders in the shaft between the leaf and the input triangle its source was
// cut from (ExactVisibility::shaft_occluders; none: wholly visible), and at each node of the leaf's
// rule the factor they hide (their shadow on that triangle's plane, ExactVisibility::Shadow). Links
// whose pair's box holds too many occluders are crowded (mark_crowded_links): they are treated as
// by default (the partly hidden take the leaves' own rays, the hidden stay hidden, the unanimous are
// trusted, the bright ones are evaluated exactly all the same), which bounds the work where many
// occluders stand between many patches (a city block:
// 185 s, where evaluating every link exactly takes more than 15 minutes). The raw closure error of
// the room with a floating cube (18 176 patches): 2.1 % before the gather, 1.6 % after it when the
// partly hidden links stayed, 2e-6 with retrace, as in the room without the cube; the leaf's own 16
// rays in place of the exact evaluation leave 7e-4 (rays that agree by chance), and the leaf-wide
// rule in place of leaf_rule's pieces 1.7e-4. Retrace costs about 1.6 × the time there.
//
// Memory and time grow with the leaf links, about 10 per expanded link in the rooms of
// docs/BENCHMARKS.md; a scene whose leaf links would exceed the budget keeps more of its links, down
// to expanding only into the receivers where that gains most per leaf link (fits()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "solver/exact_visibility.h"
#include "solver/form_factor.h"
#include "solver/hierarchical/hierarchy.h"
#include "solver/hierarchical/plane_verdicts.h"
#include "solver/visibility.h"
#include "solver/visible_fraction.h"

namespace lambert::hierarchical {

inline constexpr double kLeafFarField = 4;        // the rule alone beyond this many leaf radii
inline constexpr int kMaxCuttingPlanes = 3;       // planes that divide a leaf's rule (LeafGather::leaf_pieces)
inline constexpr double kRuleTolerance = 1e-5;    // of a row, from its near sources (LeafGather::gather_leaf)
inline constexpr int kRuleLevels = 3;             // times gather_leaf may split the pieces near them
// With exact visibility, links near whose boxes lie more than kExactOccluders occluders, in a scene of
// more than kSmallScene, keep their rays' estimate, as every link does by default
// (LeafGather::mark_crowded_links): the exact gather projects each occluder at every node of every
// leaf below, and across a city block (22 082 occluders), where such shafts hold hundreds, that was
// more than 15 minutes of work for far links whose rays are accurate enough (133 s in all with
// these limits, 31 s by default; 54 s with 32 occluders, whose results differ from these by 0.18 %
// rms, 46 s with 24). A room with up to a few dozen floating boxes is gathered exactly everywhere.
inline constexpr std::size_t kExactOccluders = 48;
inline constexpr std::size_t kSmallScene = 256;
inline constexpr double kRuleSplitDistance = kLeafFarField;  // pieces this near a near source are split (radii)
// The budget of leaf links: at most this many per link of the refinement or per patch, whichever is
// more, and kMaxLeafLinks in all (28 bytes each as the threads form them, copied block by block
// into the 12-byte LeafLinks: 1.3 GB at most while they are copied, 0.4 GB after, beside the
// refinement's links, which the 10⁶-patch scenes of docs/BENCHMARKS.md leave room for within 8 GiB).
inline constexpr std::size_t kLeafLinksPerLink = 24;
inline constexpr std::size_t kLeafLinksPerPatch = 1000;
inline constexpr std::size_t kMaxLeafLinks = 32'000'000;
inline constexpr std::size_t kMaxCheckedPairs = 1 << 16;     // root pairs a link into a cluster may check
// The links whose visibility is uncertain are the gather's costly ones (their leaves' own rays and
// exact evaluations): where they alone would take more than 1/kUncertainShare of the budget, the
// certain links do not make room for them (LeafGather::fits). The medium lit room of
// docs/BENCHMARKS.md (248 000 patches, 537 M leaf links with every kind, nearly all uncertain) took
// more than 17 minutes with 32 M of them, capped, instead of 175 s; the furnished room of 34 000
// patches, 6 M of 34 M, took 25 s instead of 20 s.
inline constexpr std::size_t kUncertainShare = 2;

struct LeafGatherStats {
  std::size_t leaf_links = 0;  // links formed at the leaves
  std::size_t traced = 0;      // of which the leaf evaluated the visibility of: by its own rays, or exactly (retrace)
  std::size_t exact = 0;       // of which were partly visible, with the exact visible part (retrace)
  std::uint64_t rays = 0;      // the leaves' own rays
};


// What the refinement's oracle weighed links with (refiner.h): the radiosity per element and per
// cluster (its largest leaf's), and the budget ε per link.
struct OracleBudget {
  std::span<const double> element_B;
  std::span<const double> cluster_B;
  double epsilon = 0;
};

class LeafGather {
 public:
  // inputs: the input triangles (Element::input), which ExactVisibility holds as its occluders.
  // vis: the visibility scene of the refinement's rays, which the leaves' own rays take.
  // hemispheres: each leaf's (the operator's, per patch). oracle: which links are bright (own_exact).
  LeafGather(Hierarchy& h, const ExactVisibility& exact, const PlaneVerdicts& planes, const Visibility& vis,
             std::span<const Triangle> inputs, std::span<const Hemisphere> hemispheres, bool retrace,
             const AreaFactorOptions& near_field, OracleBudget oracle);

  // Whether there are leaf links to form, at most `budget` of them. Where there would be more, the
  // element links whose visibility is certain expand only into receivers with at most a number of
  // leaves below (cap_certain), if the uncertain ones are few enough (kUncertainShare): those
  // correct shadows, the certain ones only an estimate's shape within ε (a furnished room of
  // 34 000 patches, 34 M leaf links, 6 M of them uncertain: without these, floor patches beside a
  // stool read 10 % high on the mean, 60 % at worst; docs/BENCHMARKS.md). Otherwise the links found
  // partly hidden and the unproven links into clusters stay as they are, then the links into
  // clusters proven visible only as a whole keep their estimates, and then the hidden links from and
  // into clusters are left out. Where even those would pass the budget (a furnished room of
  // 107 000 patches needs 183 M against 32 M), every kind expands again, but only into the receivers
  // that gain most per leaf link (cap_receivers). Prepares run().
  bool fits(std::size_t budget);

  // Replaces the links that expand by leaf links (see above); the others stay. The links that expand
  // are marked in place and dropped; the leaf links go to their own compact store
  // (LinkSet::leaf_links), each block's as it is copied, so that they are held twice only a block
  // at a time.
  LeafGatherStats run(const SolveControl& control);

 private:
  // A source to expand for a leaf: an element, and what is known of its visibility from there.
  struct Entry {
    int source;
    LinkVisibility verdict;
    // Where its visibility is not proven: evaluated exactly (evaluate_pending), or by the leaf's own
    // rays (trace_pending). Exactly with retrace unless the link is crowded; by default, the leaf's
    // bright own links found partly hidden or unanimous (own_exact), and the bright pairs of leaves
    // that the refiner's rays found hidden (own_hidden). form_links adds every bright leaf link
    // (bright).
    bool exact;
  };

  // The number of leaf links the gather would form (an upper bound: some turn out 0).
  std::size_t count() const;

  bool clear(int a, int b) const { return planes_.clear(a, b); }
  // The roots of a cluster of at most kExpandedClusterRoots roots (none for a larger one).
  std::span<const int> small_cluster(int c) const;
  // How many element sources link l at `receiver` expands to (0: it stays as it is). Element links:
  // 1; links from small clusters: their roots. With retrace, all of those; by default only where the
  // visibility is certain for every leaf below (element links: its verdict, or the occluder planes;
  // links from clusters, whose rays are cast to the cluster as a whole: the planes, root by root),
  // and element links found partly hidden (partly_hidden_). Link l, h_.links[index] at `receiver`;
  // with retrace, links whose shaft is crowded (keeps_rays) are treated as by default.
  std::size_t sources_of(const Link& l, std::size_t index, int receiver) const;
  // The element sources of h_.hidden_links[index], which the refinement's rays found hidden: its
  // source, or the roots of a small cluster (links from larger ones are not kept:
  // Refiner::keeps_hidden); none where its shaft is crowded (it stays hidden, as by default).
  std::span<const int> sources_of_hidden(std::size_t index) const;
  // The verdict a leaf takes from element link h_.links[index]: with retrace, rays found unanimous
  // are trusted only where the shaft is crowded.
  LinkVisibility verdict_of(const Link& l, std::size_t index) const;
  bool keeps_rays(std::size_t index) const { return crowded_.link[index]; }

  // With retrace, whether many occluders may stand between a link's two ends: more than
  // kExactOccluders near the box of its receiver and source, which holds its shaft
  // (ExactVisibility::occluders_near_box, constant time: a city block has 31 M links and hidden
  // links, which took 20–60 µs each to count by their shafts). A link's box holds more than its shaft
  // does (the box of a link along a street takes in the buildings beside it).
  Bounds3 box_of(int element) const { return bounds(h_.elements[element].tri); }
  bool crowded(const Bounds3& receiver, const Bounds3& source) const;
  bool crowded(const Link& l) const;
  bool crowded(const ClusterLink& l) const;

 public:
  // How many links (refinement links and links into clusters, and those found hidden) keep their
  // rays' estimate or stay hidden, their shafts crowded (with retrace; 0 otherwise).
  std::size_t crowded_links() const;

 private:
  // With retrace: which links are crowded, among those that the gather would evaluate exactly (the
  // others' visibility is proven). In a scene of at most kSmallScene occluders, none.
  void mark_crowded_links();
  std::size_t roots_of(const ClusterLink& l) const { return l.from_cluster ? small_cluster(l.source).size() : 1; }
  // Whether link h_.cluster_links[index] into a cluster expands to the cluster's roots: with retrace
  // or partly_hidden_, any from an element or a small cluster (with retrace, a crowded one only with
  // partly_hidden_); otherwise where the visibility of every root pair is certain, by the occluder
  // planes root by root or, where `proven` is allowed, by the link's own proof (proven_visible).
  bool expands(std::size_t index, bool proven) const;
  // Marks the links into clusters that expand (cluster_link_expands_; see expands).
  void mark_cluster_links(bool proven);
  // With retrace, whether hidden link h_.hidden_cluster_links[index] into a cluster expands.
  bool hidden_cluster_expands(std::size_t index) const {
    return !crowded_.hidden_cluster[index] && cluster_ranked(h_.hidden_cluster_links[index].receiver);
  }
  // Where even the links fits() keeps to the last would pass the budget: ranks the receivers
  // (rank_receivers) and sets the largest max_rank_ at which the leaf links of every kind fit;
  // returns their count (0 where not even the first receiver's fit).
  std::size_t cap_receivers(std::size_t budget);
  // Ranks the receivers, elements and clusters together, by what expanding a receiver's links gains
  // per leaf link. A link's error bound over its receiver is B_s × error_per_B (the oracle's), plus
  // its transfer B_s F where only rays estimated its visibility (not certain()): its shadow may be
  // off by that much, which the oracle's bound of a link between two leaves leaves out (the ball
  // under a panel read 0.32 % rms without it, as with no gather; tests/leaf_gather_test.cpp). A
  // leaf's bound is the sum of those of the links into it and every element above it: where many links
  // within ε each share a sign (a floor beside a box, under the box's near field), that sum is what
  // the leaf errs by. Expanding receiver r's links takes their bound b_r off each of its n_r leaves,
  // and the leaves' summed squared bounds fall by about 2 b_r Σ_leaves (bound), for n_r × m_r leaf
  // links (m_r: the element sources its links expand to). So r ranks by b_r × Σ_leaves (bound) /
  // (n_r m_r). In a furnished room of 107 000 patches this spends the 32 M leaf links where the
  // stool stands on the floor: floor patches beside it 6.4 % rms (78 % worst) off the gather of all
  // 222 M with the smallest receivers first, 0.15 % (1.9 %) so (docs/BENCHMARKS.md).
  void rank_receivers();
  bool ranked(int e) const { return max_rank_ == SIZE_MAX || rank_[e] <= max_rank_; }
  bool cluster_ranked(int c) const { return max_rank_ == SIZE_MAX || cluster_rank_[c] <= max_rank_; }
  // Where the links whose visibility is uncertain (certain()) would take at most 1/kUncertainShare
  // of the budget by themselves: the largest cap on the leaves of the receivers of the others
  // (max_certain_leaves_) at which all fit. Returns whether it set one.
  bool cap_certain(std::size_t budget);
  // Sets `cap` (max_rank_ or max_certain_leaves_) to the largest value in [0, receivers] at which
  // the leaf links fit the budget, by bisection (their count falls with the cap), and returns their
  // count there; `cluster_links`: the cap bounds the links into clusters, marked again at each.
  std::size_t largest_cap(std::size_t& cap, std::size_t budget, bool cluster_links);
  // Whether link l at `receiver`, which expands, is one whose visibility holds for every leaf below
  // (its shaft proven clear, its rays unanimous, or the occluder planes clear the pair), so that its
  // leaf links correct only the estimate's shape over the receiver, within the oracle's budget ε.
  // The others' leaves trace their own rays or are evaluated exactly, and correct shadows.
  bool certain(const Link& l, std::size_t index, int receiver) const;

  // Whether link l at `receiver` is replaced by leaf links: it expands, unless it is a leaf's own
  // element link, which is a leaf link already (the refiner gave it the exact mean over the leaf) —
  // with retrace, one whose visibility is not proven is formed again, its visibility evaluated; by
  // default (and for a crowded link with retrace), a bright one (own_exact).
  bool expanded(const Link& l, std::size_t index, int receiver) const;
  // By default, whether leaf `receiver`'s own element link l, which rays found partly hidden or
  // wholly visible, is formed again with its visible part evaluated exactly. The refiner keeps a link
  // between two leaves whatever its error, since neither can be split. Where its transfer B_s F
  // exceeds the oracle's budget ε, the rays' error may too: 16 to 64 rays per link read a floor
  // leaf's links to a panel in a sphere's penumbra 3–11 % off each, all alike, since they share one
  // shadow, and 16 rays that all arrive may pass beside the sphere's edge (docs/BENCHMARKS.md). Not
  // where a leaf below leaks (leaks_below_). With retrace, the same for a crowded link (keeps_rays),
  // which is otherwise treated as by default: its rays read a floor leaf in a ball's umbra under a
  // panel 4 times short, where the ball's 1 280 faces crowd the pair's box.
  bool own_exact(const Link& l, std::size_t index, int receiver) const;
  // Whether leaf e gathers h_.hidden_links[index], a bright pair that the refiner's 16 rays found
  // hidden, by its exact visible part: by default, every one the refiner kept
  // (Refiner::keeps_bright_hidden); with retrace, the crowded bright ones, which the exact pass
  // leaves out (sources_of_hidden). Such a pair may see its source past an occluder's edge where all
  // 64 of its samples are blocked: a floor leaf under a panel sees three of the panel's leaves in
  // part so, and dropping such pairs errs one way (the lit sphere room's direct light: 0.096 % rms
  // off an exact integration where the pair's 48 further rays decided, 0.060 % evaluated exactly;
  // docs/BENCHMARKS.md).
  bool own_hidden(int e, std::size_t index) const;
  // By default (and for a crowded link with retrace), whether leaf e's link from `source`, of factor
  // F, whose rays disagreed or all arrived, is evaluated exactly rather than by the leaf's own rays
  // or trusted: where its transfer B_s F exceeds the budget ε, as own_exact does for the leaf's own
  // links. A floor leaf in a ball's penumbra gathers the panel through links formed above it too.
  bool bright(int e, int source, double F) const {
    return partly_hidden_ && !leaks_below_[e] && oracle_.element_B[static_cast<std::size_t>(source)] * F > oracle_.epsilon;
  }
  // The first hidden link of element e (hidden_start, which may be empty: none).
  std::size_t hidden_first(int e) const { return h_.hidden_start.empty() ? 0 : h_.hidden_start[e]; }

  // The leaf links of root block r, in element order, each leaf's sorted by source.
  void gather_block(std::size_t r, std::vector<Link>& out, LeafGatherStats& stats) const;

  // The rule a leaf's links are integrated with (weights summing to 1): the degree-5 rule on the
  // leaf; with retrace, on the pieces into which the planes of the sources that cut the leaf divide
  // it. The exact visible factors at the nodes of one rule sum to 1 over a closed scene, so a row
  // closes as well as its links' exact means (exchange_area: near and cut sources) agree with the
  // rule; across a cutting plane the kernel has a kink that a leaf-wide rule misses (1.7e-4 of the
  // row at the cube room's leaves cut by the cube's faces' planes), and on the pieces there is none.
  // cut[k]: whether the plane of entries[k]'s source cuts the leaf (front_part), computed once by the caller.
  void leaf_pieces(const Element& L, const std::vector<Entry>& entries, const std::vector<char>& cut,
                   std::vector<Triangle>& pieces) const;
  // Whether p lies within `reach` of element S (distance_to_triangle), the sphere about S first: most
  // sources of a row are far beyond it. (A margin of 1e-9 keeps the verdict the distance's own.)
  static bool within(const Point3& p, const Element& S, double reach);
  // The degree-5 rule on each piece, weighted by its share of the leaf.
  static void leaf_rule(const Element& L, const std::vector<Triangle>& pieces, std::vector<Point3>& nodes,
                        std::vector<double>& weights);

  // Splits 1:4 the pieces nearer one of the `near` sources than kRuleSplitDistance of their radius.
  // Returns whether any was split.
  static bool split_near(std::vector<Triangle>& pieces, std::span<const Triangle* const> near);

  // The leaf links of leaf element e from `entries`, appended to `row`.
  //
  // A near source's link takes its exact mean (exchange_area) times the visible fraction that the rule
  // finds; every other link, the rule's mean. The visible factors at a node sum to 1 over a closed
  // scene, so the row misses 1 by Σ v (F − F_rule) over the near sources, F_rule being the rule's mean
  // of their unoccluded factors and v their visible fractions. With retrace, the rule is refined
  // where that sum exceeds kRuleTolerance (the pieces near a near source split 1:4, at most
  // kRuleLevels times) and the links formed again: a floor leaf whose corner touches a crate's corner
  // missed 1.8e-3 of its row with the leaf-wide rule, 2.4e-5 after two splits. Over an adjacent wall
  // the near sources' errors cancel (their union's factor is smooth over the leaf), so few leaves
  // are refined: 36 of 3 204 in the L-shaped room of tools/l_room_furnace.py.
  void gather_leaf(int e, const std::vector<Entry>& entries, std::vector<Link>& row, LeafGatherStats& stats) const;

  // The links of leaf e for the rule (nodes, weights), appended to `row` (those found hidden with
  // source kReplaced), and each one's entry to `row_entry`.
  void form_links(int e, const std::vector<Entry>& entries, const std::vector<char>& usable,
                  const std::vector<double>& near_F, std::span<const Point3> node_span, std::span<const double> weights,
                  std::vector<Link>& row, std::vector<int>& row_entry, LeafGatherStats& stats) const;

  // The links of a leaf whose visibility it evaluates itself, and what form_links computed for them.
  struct Pending {
    const Element* leaf = nullptr;
    std::span<const Point3> nodes;
    std::span<const double> weights;
    std::vector<std::pair<int, int>> links;  // each one's index into the row, and its row of f (or −1)
    std::vector<double> f;                   // unoccluded factors at the nodes, [row of f][node]
  };
  // The visible part of every pending link of a leaf, exactly (leaf_visibility.cpp).
  void evaluate_pending(Pending& pending, std::vector<Link>& row, LeafGatherStats& stats) const;
  // The same by the leaf's own rays to each source: without retrace, the links found partly hidden
  // above the leaf and the unproven links into its clusters; with it, those of crowded links.
  void trace_pending(Pending& pending, std::vector<Link>& row, LeafGatherStats& stats) const;
  // The pending links [first, last) (sorted by input triangle, root, source), whose sources lie in
  // `carrier`, past the occluders in the shaft between the leaf and the carrier.
  void evaluate_carrier(Pending& pending, std::vector<Link>& row, const Triangle& carrier, int level,
                        std::size_t first, std::size_t last, LeafGatherStats& stats) const;
  // Scales a link to the visible share v of its factor (dropped where 0; wholly visible where 1).
  static void set_visible_share(Link& link, double v);

  Hierarchy& h_;
  const ExactVisibility& exact_;
  const PlaneVerdicts& planes_;
  const Visibility& vis_;
  std::span<const Triangle> inputs_;
  bool retrace_;
  // The links found partly hidden expand, and by default the unproven links into clusters, the leaves
  // tracing their own rays (with retrace, only the crowded ones' leaves: the others are exact). See
  // fits().
  bool partly_hidden_ = true;
  bool clustered_hidden_ = true;  // the hidden links from and into clusters are expanded (fits())
  // Links expand only into receivers (elements and clusters) ranked at most this (cap_receivers): a
  // scene too large to expand every link keeps its estimates where they err least.
  std::size_t max_rank_ = SIZE_MAX;
  std::vector<std::size_t> rank_;          // per element, from 1 (rank_receivers)
  std::vector<std::size_t> cluster_rank_;  // per cluster
  // The same for the element links whose visibility is certain (cap_certain), the first to stay.
  std::size_t max_certain_leaves_ = SIZE_MAX;
  AreaFactorOptions near_field_;
  OracleBudget oracle_;
  std::vector<std::size_t> leaves_below_;     // per element
  std::vector<std::size_t> cluster_leaves_;   // per cluster: the leaves below its roots
  // Per element: some leaf below is Leaking or Enclosed. Its links found partly hidden stay as they
  // are: its gathered flux is spread over its open part (ElementForest::open_spread), and a leaking
  // leaf's row is held at 1 only while its links gather a whole hemisphere (closure.h), conventions
  // that its leaves' own rays would break (a panel 1 mm under a ceiling: 9.4e-5 of the power created
  // in the gap, tests/hard_cases_test.cpp).
  std::vector<char> leaks_below_;
  std::vector<int> cluster_parent_;           // per cluster, −1 for the top
  std::vector<int> cluster_of_root_;          // per element: the BVH leaf of a root, else −1
  std::vector<char> cluster_link_expands_;    // per cluster link
  // With retrace, per link of h_.links, h_.hidden_links, h_.hidden_cluster_links and
  // h_.cluster_links: 1 where it is crowded (mark_crowded_links), so that it keeps its rays'
  // estimate (or stays hidden).
  struct Crowded {
    std::vector<char> link, hidden, hidden_cluster, cluster;
  } crowded_;
};

}  // namespace lambert::hierarchical
