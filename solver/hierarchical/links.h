// The links of the hierarchical method: what an element or a cluster gathers of another's radiosity,
// and the containers the refinement fills.
//
// Three kinds: element links (Link: into an element, from an element or a cluster), leaf links
// (LeafLink: the final gather's exact share of a link at one leaf, final_gather.h) and links into
// clusters (ClusterLink). Each store is sorted by receiver, then source, and indexed as CSR.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_sort.h>

#include "solver/form_factor.h"
#include "solver/hierarchical/clusters.h"

namespace lambert::hierarchical {

// A link's point on its element source (Link::bin): barycentric coordinates in 255ths.
inline constexpr double kPointScale = 255;
inline constexpr unsigned char kCentroid = 85;  // 1/3

// What is known of an element link's visibility: the final gather at the leaves (final_gather.h)
// takes the link's verdict for every leaf below its receiver where it is certain, and evaluates the
// leaves' own visibility where it is not.
enum class LinkVisibility : unsigned char {
  Unknown,        // partly hidden by its rays (or not yet traced)
  ShaftClear,     // no occluder in the pair's hull: wholly visible
  RaysUnanimous,  // every ray of it was unobstructed
  // What a leaf of the final gather takes from a link whose rays were unanimous and whose shaft holds
  // too many occluders for exact visibility (LeafGather::mark_crowded_links): wholly visible, as by
  // default.
  RaysTrusted,
  // Wholly visible: the solids' shafts (solid_shafts.h) proved it before any ray was traced. The
  // final gather's leaves take it as proven, as ShaftClear (with solver.exact_visibility, 95 072 such
  // leaf links of the exact-visibility tests evaluated exactly were all wholly visible); elsewhere
  // the gather takes it as RaysUnanimous. Kept apart for stats.links_clear.
  SolidsClear,
};

// Every ray of the link was unobstructed, or would have been: the verdicts the gather takes alike.
inline bool rays_unanimous(LinkVisibility v) {
  return v == LinkVisibility::RaysUnanimous || v == LinkVisibility::SolidsClear;
}

struct Link {
  int receiver = 0;          // element
  int source = 0;            // element or cluster
  bool from_cluster = false;
  // Cluster source: the bins of Φ that the three weights apply to (bin_value, clusters.h). Element
  // source: bin[0], bin[1] are β1, β2 of the point y* where the link reads the source's radiosity
  // (corner_weights), y* = ∫ f(y) y dA / ∫ f(y) dA with f(y) the factor from y to the receiver: exact for a radiosity linear
  // over the source, and in the transpose the link's share of each of the source's leaves then has
  // the kernel's first moment. Every element link reads its source there: a read at the centroid
  // misses a far source's radiosity gradient times the kernel's shift, which biases whole rows (by
  // −0.1 % in the issue-4 room, docs/BENCHMARKS.md). bin[2] holds an element
  // link's LinkVisibility. (One field for both keeps a link at 28 bytes: the 10⁶-triangle room has
  // 182 M of them.)
  std::array<unsigned char, 3> bin{kCentroid, kCentroid, 0};
  std::array<float, 3> coeff{};  // element source: F at the receiver's vertices (linear); cluster: weights of Φ_bin
  float error_per_B = 0;     // error bound of the factor: irradiance error per unit source radiosity

  std::array<unsigned char, 2> read_point() const { return {bin[0], bin[1]}; }
  LinkVisibility visibility() const { return static_cast<LinkVisibility>(bin[2]); }
  void set_visibility(LinkVisibility v) { bin[2] = static_cast<unsigned char>(v); }
  // The factor's mean over the receiver (an element link's linear field).
  double mean_factor() const { return (double{coeff[0]} + coeff[1] + coeff[2]) / 3; }
};
static_assert(sizeof(Link) == 28);

// Whether the unoccluded transfer from leaf S (radiosity B) to leaf R exceeds the budget ε, by twice
// the point factor at R's centroid: the estimate the refiner's early vote takes for pairs well apart.
// Neither leaf can be split, so such a pair's visibility must be known better than rays know it
// (Refiner::keeps_bright_hidden, LeafGather::own_exact).
inline bool bright_leaf_pair(const Element& R, const Element& S, double B, double epsilon) {
  return 2 * B * point_triangle_factor(R.centre, R.normal, S.tri) > epsilon;
}

// The weights w_v = 2 (β_v − 1/3) of an element link's point on its source, by which it reads the
// source's corner children: the linear field fitted to their means m_v is B + Σ_v D_v β_v with
// D_v = 2 (m_v − Σ m / 3), so the field at β is B + Σ_v w_v m_v. All 0 at the centroid (or no point).
inline std::array<double, 3> corner_weights(unsigned char q1, unsigned char q2) {
  const double b1 = q1 / kPointScale, b2 = q2 / kPointScale;
  return {2 * (1 - b1 - b2 - 1.0 / 3), 2 * (b1 - 1.0 / 3), 2 * (b2 - 1.0 / 3)};
}

// A link that the final gather formed at a leaf (LeafGather), from an element: its factor is one
// value over the leaf, so it keeps neither its receiver (LinkSet::leaf_link_start gives it) nor
// three coefficients. 12 bytes against a Link's 28: the passes of the closure balance and the solve
// go over these links, which are most of a gathered scene's (8.9 M of 9.1 M in the cube room of
// docs/BENCHMARKS.md), at the speed of memory.
struct LeafLink {
  int source = 0;                                       // element
  float F = 0;                                          // the factor, the same at the three vertices
  std::array<unsigned char, 2> point{kCentroid, kCentroid};  // Link::read_point(): where it reads its source
};
static_assert(sizeof(LeafLink) == 12);

// A link into a cluster of roots whose normals all face the source (Refiner::refine_pair): it adds
// Ψ × `toward` to the cluster's vector irradiance V, Ψ being the irradiance on a surface facing the
// source, and every root below the cluster receives n · V. Exact for (n · u)⁺ since n · u ≥ 0 there.
struct ClusterLink {
  int receiver = 0;          // cluster
  int source = 0;            // cluster, or element when !from_cluster
  bool from_cluster : 1 = false;
  // Proven wholly visible as it was formed (by the occluder planes or the solids' shafts, no rays).
  // So is every pair of a root below the receiver and one of the source, whose segments lie in the
  // pair's shaft: the final gather may expand the link root by root (LeafGather::expands).
  bool proven_visible : 1 = false;
  std::array<unsigned char, 3> bin{};
  std::array<float, 3> coeff{};   // cluster source: weights of Φ_bin; element source: Ψ = coeff[0] × B
  std::array<float, 3> toward{};  // unit direction from the receiver to the source
  float error_per_B = 0;
};
static_assert(sizeof(ClusterLink) == 40);

// The coefficients of a pending leaf-to-leaf link whose factor is computed once its rays find it
// visible (a NaN: no fit or factor is one).
inline constexpr float kFactorPending = std::numeric_limits<float>::quiet_NaN();
inline bool factor_pending(const Link& link) { return std::isnan(link.coeff[0]); }

// A link that a recheck replaced by finer ones (or the final gather expanded) is marked by its
// source (see merge_rechecked).
inline constexpr int kReplaced = -1;

// Clusters of at most this many roots are expanded to their roots by the final gather
// (final_gather.h); a link from a larger one keeps its one-point estimate.
inline constexpr int kExpandedClusterRoots = 16;

// Every link of the hierarchy, each store CSR over its receivers.
struct LinkSet {
  std::vector<Link> links;
  std::vector<std::size_t> link_start;  // links of element e in [start[e], start[e+1])
  // The final gather's links (LeafGather::run), CSR over receiving elements (leaves), each receiver's
  // sorted by source; empty until then.
  std::vector<LeafLink> leaf_links;
  std::vector<std::size_t> leaf_link_start;
  std::vector<ClusterLink> cluster_links;
  std::vector<std::size_t> cluster_link_start;  // CSR over receiving clusters
  std::vector<char> links_below;  // cluster c or one below it receives cluster links
  // Links whose rays were all blocked (factor 0, sorted by receiver), kept for solver.exact_visibility
  // only: the rays between coarse elements decide for the refinement, but a leaf below may see part
  // of the source, which the final gather (LeafGather) evaluates again. Links from clusters and into
  // clusters too: a three-cube furnace room whose 128 hidden links from clusters were dropped missed
  // 6e-4 of some rows (a cube's face 63 % visible from leaves whose ancestor's 16 rays all met another
  // cube). Links between elements are not kept past kMaxLeafLinks (hidden_complete false: the gather
  // then does not retrace); the others have a room of their own (HiddenRoom, refiner.h).
  std::vector<Link> hidden_links;
  std::vector<std::size_t> hidden_start;
  std::vector<ClusterLink> hidden_cluster_links;  // links into clusters, the same way
  std::vector<std::size_t> hidden_cluster_start;  // CSR over receiving clusters
  bool hidden_complete = true;

  std::span<const LeafLink> leaf_links_of(int e) const {
    if (leaf_link_start.empty()) return {};
    return {leaf_links.data() + leaf_link_start[e], leaf_links.data() + leaf_link_start[e + 1]};
  }
  // The CSR offsets of every store (each sorted by receiver), and links_below.
  void index_links(std::size_t elements, const std::vector<Cluster>& clusters);
};

// Frees a vector's buffer. (`v = {}` would not: it picks the initializer-list assignment, which keeps
// the capacity.)
template <class T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}
// The links one thread finds, in blocks of 64 MiB. glibc maps blocks this large on their own (its
// mmap threshold is at most 32 MiB) and returns them to the system when they are freed, so take_sorted
// frees each block as soon as it is copied. A growing vector per thread would copy the links as it
// doubles, and be copied whole by the sort while still held (docs/BENCHMARKS.md: gigabytes at 167 M
// links).
template <class L>
class LinkBlocks {
 public:
  static constexpr std::size_t kBlock = (std::size_t{64} << 20) / sizeof(L);
  void push_back(const L& link) {
    if (blocks_.empty() || blocks_.back().size() == kBlock) {
      blocks_.emplace_back();
      blocks_.back().reserve(kBlock);  // address space: pages take memory as links are written
    }
    blocks_.back().push_back(link);
    ++size_;
  }
  std::size_t size() const { return size_; }
  // Appends the links to `to`, freeing each block once it is copied.
  void move_to(std::vector<L>& to) {
    for (std::vector<L>& block : blocks_) {
      to.insert(to.end(), block.begin(), block.end());
      release(block);
    }
    blocks_.clear();
    size_ = 0;
  }

 private:
  std::vector<std::vector<L>> blocks_;
  std::size_t size_ = 0;
};

// Links found by the refiner. Those whose visibility needs rays wait in `pending` with their
// unoccluded coefficients until Refiner::resolve() traces them together.
struct LinkBatch {
  LinkBlocks<Link> links;
  LinkBlocks<ClusterLink> cluster_links;
  LinkBlocks<Link> hidden;  // links that rays found hidden, for the final gather (LinkSet::hidden_links)
  LinkBlocks<ClusterLink> hidden_cluster;  // links into clusters that rays found hidden (the same)
  std::vector<Link> pending;
  std::vector<ClusterLink> cluster_pending;
  std::uint64_t rays = 0;  // link rays traced (resolve)
};

template <class L>
bool link_order(const L& a, const L& b) {
  return a.receiver != b.receiver ? a.receiver < b.receiver : a.source < b.source;
}

// The links that the threads found (one member of their batches), in one vector sorted by receiver,
// then source. The threads' blocks are freed as they are copied: the peak is one copy of the links
// and a block. `headroom` more links are reserved for merge_rechecked, in address space only: pages
// that are never written take no memory.
template <class L>
std::vector<L> take_sorted(tbb::enumerable_thread_specific<LinkBatch>& found, LinkBlocks<L> LinkBatch::*part,
                           double headroom = 0) {
  std::size_t total = 0;
  for (LinkBatch& batch : found) total += (batch.*part).size();
  std::vector<L> all;
  all.reserve(total + static_cast<std::size_t>(headroom * static_cast<double>(total)));
  for (LinkBatch& batch : found) (batch.*part).move_to(all);
  tbb::parallel_sort(all.begin(), all.end(), link_order<L>);
  return all;
}

// The links of the next round: those a recheck kept stay where they are, in order, and the sorted
// replacements are merged in from the back, so that the only extra memory is the replacements (a few
// per cent of the links after the first round), where a rebuild would hold the links twice. (A merge
// that outgrows the vector's reserve reallocates.)
template <class L>
void merge_rechecked(std::vector<L>& links, std::vector<L> fresh) {
  links.erase(std::remove_if(links.begin(), links.end(), [](const L& l) { return l.source == kReplaced; }),
              links.end());
  std::size_t i = links.size(), j = fresh.size();
  links.resize(i + j);
  for (std::size_t k = links.size(); j > 0;) {
    if (i > 0 && link_order(fresh[j - 1], links[i - 1])) links[--k] = links[--i];
    else links[--k] = fresh[--j];
  }
}

// A near link's point on its source S (Link::bin[0], bin[1]): see links.cpp.
std::array<unsigned char, 3> source_point_of(const Element& S, const Element& R);

}  // namespace lambert::hierarchical
