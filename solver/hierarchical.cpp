// Hierarchical radiosity with clusters (see hierarchical.h for the method and its references).
// Stages, each timed in SolveStats: meshing (roots, element trees, cluster BVH) -> visibility scene ->
// direct light -> refine–solve rounds (links = form factors; GMRES = solve) -> closure -> outputs ->
// probes -> energy.
#include "solver/hierarchical.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/concurrent_unordered_map.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <stdexcept>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "mesh/mesh_ops.h"
#include "solver/cubature.h"
#include "solver/energy_balance.h"
#include "solver/exact_visibility.h"
#include "solver/facet_bounds.h"
#include "solver/form_factor.h"
#include "solver/light_model.h"
#include "solver/linear_solve.h"
#include "solver/occluder_planes.h"
#include "solver/patch_refinement.h"
#include "solver/pipeline/direct_light.h"
#include "solver/pipeline/hemisphere.h"
#include "solver/solids.h"
#include "solver/visibility.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The solver's own patch limit. Elements, links and spectra take 2.5–7 KB per patch, one wavelength
// (measured: 4.9 GB at 1.9 M patches of the office furnace, 7.2 GB at 0.98 M patches of faceted
// spheres, one root each), so this is 5–14 GB.
constexpr std::size_t kMaxHierarchicalPatches = 2'000'000;
constexpr int kRootLevels = 3;         // a root holds at most 4^3 = 64 output patches
constexpr int kRefineRounds = 3;
// ε = accuracy × (mean radiosity) / kPowerShare: the irradiance error a link may carry at the patch
// scale (see Refiner::area_weight above it). Not yet calibrated against measured errors.
constexpr double kPowerShare = 1;
constexpr double kUnitPatches = 4;   // the oracle's area weight starts above this many patches
constexpr double kWellSeparated = 1.5;  // cluster links need d ≥ 1.5 (r_source + r_receiver)
// Links into clusters need d ≥ 2.5 (r_source + r_receivers). The one-point estimate is biased low (the
// mean of 1/r² over the pair exceeds 1/d²), and every receiver under the cluster shares the bias: at
// 1.5 the city block's surface means of the benchmarks fell by 3e-4, at 2.5 by less than 1e-4.
constexpr double kReceiversSeparated = 2.5;
constexpr int kTabledClusterSamples = 16;  // see Hierarchy::cluster_samples
constexpr std::size_t kResolveBatch = 4096;  // pending links traced together (Refiner::resolve)
constexpr double kCachedSeparation = 1.5;  // see Refiner::leaf_exchange
// Distances between elements are compared with their thresholds, and sizes with each other (which of
// a pair to split), with a margin of 1e-9: a regular mesh has pairs exactly at a threshold (centroids
// 4 radii apart) and congruent elements, where rounding would pick the side, differently at another
// scale or placement of the same scene.
constexpr double kTie = 1 + 1e-9;
constexpr std::size_t kMaxBatch = 16;   // systems per gather pass (the GMRES batch size)
constexpr int kMaxBalanceSweeps = 100;  // of the closure balance; the error usually halves per sweep
// How closely balance() holds closed rows and columns at 1, as a share of the radiosity it moves (see
// balance_target): the final operator's, and the earlier rounds', whose solutions only tell the
// refiner which links carry the most.
constexpr double kFinalBalance = 1e-5;
constexpr double kOracleBalance = 1e-3;
constexpr double kBalanceFloor = 1e-11;  // the aim where 1 − ρ_max vanishes (and the former aim for all)
constexpr int kExpandedClusterRoots = 16;  // clusters of at most this many roots are expanded (LeafGather)

struct Element {
  Triangle tri;
  Vector3 normal;
  Point3 centre;
  double radius = 0;   // about the centroid
  double area = 0;
  int surface = 0;
  int parent = -1;
  int first_child = -1;  // four children, contiguous; -1 for a leaf
  int leaf = -1;         // index of the unknown (output patch) for a leaf
  int root = -1;         // the root element of its tree
  int input = -1;        // the input triangle its tree was cut from (every surface's, in order)
};

// A node of the BVH over the roots. Its FacetBounds (box, bins, area vector, normal cone) cover its
// roots.
struct Cluster : FacetBounds {
  Point3 centre;
  double radius = 0;
  int child[2] = {-1, -1};   // clusters; both −1 for a BVH leaf
  int root = -1;             // the root element of a BVH leaf
  int first_root = 0, root_count = 0;  // range in Hierarchy::root_order
  int samples = -1;          // its first kTabledClusterSamples in Hierarchy::cluster_samples, or −1
  int slot = -1;             // a BVH leaf: its root's index in Hierarchy::roots
};

// A link's point on its element source (Link::bin): barycentric coordinates in 255ths.
constexpr double kPointScale = 255;
constexpr unsigned char kCentroid = 85;  // 1/3

struct Link {
  int receiver = 0;          // element
  int source = 0;            // element or cluster
  bool from_cluster = false;
  // Cluster source: the bins of Φ that the three weights apply to. Element source: bin[0], bin[1]
  // are β1, β2 of the point y* where the link reads the source's radiosity (corner_weights), y* =
  // ∫ f(y) y dA / ∫ f(y) dA with f(y) the factor from y to the receiver: exact for a radiosity linear
  // over the source, and in the transpose the link's share of each of the source's leaves then has
  // the kernel's first moment. The centroid where the kernel is about even. (One field for both
  // keeps a link at 28 bytes: the 10⁶-triangle room has 182 M of them.)
  std::array<unsigned char, 3> bin{kCentroid, kCentroid, 0};
  std::array<float, 3> coeff{};  // element source: F at the receiver's vertices (linear); cluster: weights of Φ_bin
  float error_per_B = 0;     // error bound of the factor: irradiance error per unit source radiosity
};
static_assert(sizeof(Link) == 28);
// The weights w_v = 2 (β_v − 1/3) of an element link's point on its source, by which it reads the
// source's corner children: the linear field fitted to their means m_v is B + Σ_v D_v β_v with
// D_v = 2 (m_v − Σ m / 3), so the field at β is B + Σ_v w_v m_v. All 0 at the centroid (or no point).
std::array<double, 3> corner_weights(unsigned char q1, unsigned char q2) {
  const double b1 = q1 / kPointScale, b2 = q2 / kPointScale;
  return {2 * (1 - b1 - b2 - 1.0 / 3), 2 * (b1 - 1.0 / 3), 2 * (b2 - 1.0 / 3)};
}

// A link that the final gather formed at a leaf (LeafGather), from an element: its factor is one
// value over the leaf, so it keeps neither its receiver (Hierarchy::leaf_link_start gives it) nor
// three coefficients. 12 bytes against a Link's 28: the passes of the closure balance and the solve
// go over these links, which are most of a gathered scene's (8.9 M of 9.1 M in the cube room of
// docs/BENCHMARKS.md), at the speed of memory.
struct LeafLink {
  int source = 0;                                       // element
  float F = 0;                                          // the factor, the same at the three vertices
  std::array<unsigned char, 2> point{kCentroid, kCentroid};  // Link::bin[0], bin[1]: where it reads its source
};
static_assert(sizeof(LeafLink) == 12);
// What is known of an element link's visibility, in bin[2] (unused otherwise by element links): the
// final gather at the leaves (LeafGather) takes the link's verdict for every leaf below its receiver
// where it is certain, and traces the leaves' own rays where it is not.
constexpr unsigned char kVisibilityUnknown = 0;  // partly hidden by its rays (or not yet traced)
constexpr unsigned char kShaftClear = 1;         // no occluder in the pair's hull: wholly visible
constexpr unsigned char kRaysUnanimous = 2;      // every ray of it was unobstructed
// What a leaf of the final gather takes from a link whose rays were unanimous and whose shaft holds
// too many occluders for exact visibility (LeafGather::mark_crowded_links): wholly visible, as by default.
constexpr unsigned char kRaysTrusted = 3;

// A link into a cluster of roots whose normals all face the source (Refiner::refine_pair): it adds
// Ψ × `toward` to the cluster's vector irradiance V, Ψ being the irradiance on a surface facing the
// source, and every root below the cluster receives n · V. Exact for (n · u)⁺ since n · u ≥ 0 there.
struct ClusterLink {
  int receiver = 0;          // cluster
  int source = 0;            // cluster, or element when !from_cluster
  bool from_cluster = false;
  std::array<unsigned char, 3> bin{};
  std::array<float, 3> coeff{};   // cluster source: weights of Φ_bin; element source: Ψ = coeff[0] × B
  std::array<float, 3> toward{};  // unit direction from the receiver to the source
  float error_per_B = 0;
};

bool box_in_front(const Bounds3& box, const Point3& o, const Vector3& n, double tol) {
  for (int c = 0; c < 8; ++c) {
    const Point3 p{c & 1 ? box.hi.x : box.lo.x, c & 2 ? box.hi.y : box.lo.y, c & 4 ? box.hi.z : box.lo.z};
    if (dot(p - o, n) > tol) return true;
  }
  return false;
}

// Barycentric coordinates, in the parent, of child c's vertex n: split4's children are {v0, m01, m20},
// {m01, v1, m12}, {m20, m12, v2}, {m01, m12, m20}. Push-down evaluates the parent's linear field there.
constexpr double kChildVertex[4][3][3] = {{{1, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}},
                                          {{0.5, 0.5, 0}, {0, 1, 0}, {0, 0.5, 0.5}},
                                          {{0.5, 0, 0.5}, {0, 0.5, 0.5}, {0, 0, 1}},
                                          {{0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}}};

class Hierarchy {
 public:
  std::vector<Element> elements;
  std::vector<int> roots;           // element index of every root
  std::vector<std::pair<int, int>> root_block;  // [first, end) of each root's tree in `elements`
  std::vector<int> root_order;      // roots in BVH order (cluster ranges index into it)
  // What a cluster's visibility samples need of its roots, in root_order: contiguous per cluster and
  // a tenth of the elements' size, so the link rays' far ends do not miss the cache element by element.
  struct RootSample {
    Triangle tri;
    Vector3 normal;
  };
  std::vector<RootSample> ordered_roots;
  // A visibility sample of a cluster (cluster_sample): a point on one of its roots (not lifted) and the
  // root's normal. The first kTabledClusterSamples of each cluster of more roots than that are kept
  // together: drawn from ordered_roots, each ray of a cluster link missed the cache (a fifth of the
  // link rays' set-up time in the city block), and the link rays use at most that many in most links.
  struct ClusterSample {
    Point3 point;
    Vector3 normal;
  };
  std::vector<ClusterSample> cluster_samples;
  std::vector<Cluster> clusters;    // clusters[0] is the top
  std::vector<int> leaves;          // element of each unknown
  std::vector<Link> links;
  std::vector<std::size_t> link_start;  // CSR over receivers: links of element e in [start[e], start[e+1])
  // The final gather's links (LeafGather::run), CSR over receiving elements (leaves), each receiver's
  // sorted by source; empty until then.
  std::vector<LeafLink> leaf_links;
  std::vector<std::size_t> leaf_link_start;
  std::span<const LeafLink> leaf_links_of(int e) const {
    if (leaf_link_start.empty()) return {};
    return {leaf_links.data() + leaf_link_start[e], leaf_links.data() + leaf_link_start[e + 1]};
  }
  std::vector<ClusterLink> cluster_links;
  // Links whose rays were all blocked (factor 0, sorted by receiver), kept for solver.exact_visibility
  // only: the rays between coarse elements decide for the refinement, but a leaf below may see part
  // of the source, which the final gather (LeafGather) evaluates again. Links from clusters and into
  // clusters too: a three-cube furnace room whose 128 hidden links from clusters were dropped missed
  // 6e-4 of some rows (a cube's face 63 % visible from leaves whose ancestor's 16 rays all met another
  // cube). Links between elements are not kept past kMaxLeafLinks (hidden_complete false: the gather
  // then does not retrace); the others have a room of their own (HiddenRoom).
  std::vector<Link> hidden_links;
  std::vector<std::size_t> hidden_start;
  std::vector<ClusterLink> hidden_cluster_links;  // links into clusters, the same way
  std::vector<std::size_t> hidden_cluster_start;  // CSR over receiving clusters
  bool hidden_complete = true;
  std::vector<std::size_t> cluster_link_start;  // CSR over receiving clusters
  std::vector<char> links_below;  // cluster c or one below it receives cluster links
  // Per element: every leaf below lies inside a closed solid (the hemisphere probe's 3; e.g. floor
  // under a crate). Such elements take no links, and roots that are wholly enclosed are left out of
  // the clusters, so that they neither send nor receive through them. Empty: none known.
  std::vector<char> enclosed;
  bool is_enclosed(int e) const { return !enclosed.empty() && enclosed[e]; }
  // Closure scaling (see balance()): the operator applied is F' = D_r F D_c, with D_r = leaf_scale on
  // the gathered irradiance (rows) and D_c = source_scale on the radiosity shot (columns).
  std::vector<double> leaf_scale;
  std::vector<double> source_scale;
  double balance_omega = 1;  // ω of the last balance() if it reached its target (the next one's start)
  double balance_stalled_at = 0;  // the error where the last balance() stalled short of its target (0: none)
  double balance_stalled_aim = 0;  // its target: a stop only for balances whose target is no tighter

  // Per-node values of one gather pass, K systems interleaved ([node][k]).
  struct Values {
    std::size_t K = 0;
    std::vector<double> B;    // per element: area-mean radiosity
    std::vector<double> Phi;  // per cluster: 6 bins × K
  };

  // Area-mean radiosity per element and projected power per cluster; V[k][leaf] × column_scale[leaf]
  // where column_scale is given.
  void pull(const std::vector<const double*>& V, Values& out, const double* column_scale = nullptr) const {
    const std::size_t K = V.size();
    out.K = K;
    out.B.assign(elements.size() * K, 0.0);
    out.Phi.assign(clusters.size() * 6 * K, 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, root_block.size(), 8), [&](const auto& range) {
      for (std::size_t r = range.begin(); r != range.end(); ++r) {
        const auto [first, end] = root_block[r];
        for (int e = end - 1; e >= first; --e) {  // children come after their parent
          const Element& el = elements[e];
          double* b = &out.B[e * K];
          if (el.leaf >= 0) {
            const double c = column_scale ? column_scale[el.leaf] : 1.0;
            for (std::size_t k = 0; k < K; ++k) b[k] = c * V[k][el.leaf];
          } else {
            for (int c = 0; c < 4; ++c) {
              const double w = elements[el.first_child + c].area / el.area;
              const double* bc = &out.B[(el.first_child + c) * K];
              for (std::size_t k = 0; k < K; ++k) b[k] += w * bc[k];
            }
          }
        }
      }
    });
    for (std::size_t c = clusters.size(); c-- > 0;) {  // children come after their parent
      const Cluster& cl = clusters[c];
      double* phi = &out.Phi[c * 6 * K];
      if (cl.root >= 0) {
        const double* b = &out.B[cl.root * K];
        for (int bin = 0; bin < 6; ++bin)
          for (std::size_t k = 0; k < K; ++k) phi[bin * K + k] = cl.projected[bin] * b[k];
      } else {
        for (int ch : cl.child) {
          const double* p = &out.Phi[ch * 6 * K];
          for (std::size_t q = 0; q < 6 * K; ++q) phi[q] += p[q];
        }
      }
    }
  }

  // How an element link reads its source element at its read point (Link::bin[0], bin[1] or
  // LeafLink::point): the source's radiosity B, or off the centroid the linear field fitted to its
  // corner children, B + Σ_v w_v m_v (corner_weights); and the adjoint of that read.
  struct SourceRead {
    int source = 0;
    int children = -1;  // the first of the corner children 0, 1, 2 (kChildVertex), or −1: B alone
    std::array<double, 3> w{};
    double value(const double* B, std::size_t K, std::size_t k) const {
      const double b = B[source * K + k];
      if (children < 0) return b;
      const double* m = &B[children * K];
      return b + w[0] * m[k] + w[1] * m[K + k] + w[2] * m[2 * K + k];
    }
    void scatter(double read_bar, double* B_bar) const {  // B_bar += read_bar ∂value/∂B
      B_bar[source] += read_bar;
      if (children < 0) return;
      for (int q = 0; q < 3; ++q) B_bar[children + q] += w[q] * read_bar;
    }
  };
  SourceRead source_read(int source, std::array<unsigned char, 2> point) const {
    // (The centroid test first: it needs only the link, and most links read the centroid.)
    if (point[0] == kCentroid && point[1] == kCentroid) return {source};
    const int children = elements[source].first_child;
    if (children < 0) return {source};
    return {source, children, corner_weights(point[0], point[1])};
  }

  // Gathered irradiance at element e from its own links (not its ancestors'), K systems, as a linear
  // field over the element: its values at the three vertices, h[v K + k].
  void gather_links(int e, const Values& v, double* h) const {
    const std::size_t K = v.K;
    const double* B = v.B.data();
    for (std::size_t l = link_start[e]; l < link_start[e + 1]; ++l) {
      const Link& link = links[l];
      if (!link.from_cluster) {
        const SourceRead read = source_read(link.source, {link.bin[0], link.bin[1]});
        for (std::size_t k = 0; k < K; ++k) {
          const double value = read.value(B, K, k);
          for (int n = 0; n < 3; ++n) h[n * K + k] += link.coeff[n] * value;
        }
      } else {
        const double* phi = &v.Phi[link.source * 6 * K];
        for (std::size_t k = 0; k < K; ++k) {
          double c = 0;
          for (int a = 0; a < 3; ++a) c += link.coeff[a] * phi[link.bin[a] * K + k];
          for (int n = 0; n < 3; ++n) h[n * K + k] += c;
        }
      }
    }
    for (const LeafLink& link : leaf_links_of(e)) {
      const SourceRead read = source_read(link.source, link.point);
      const double F = link.F;
      for (std::size_t k = 0; k < K; ++k) {
        const double c = F * read.value(B, K, k);
        for (int n = 0; n < 3; ++n) h[n * K + k] += c;
      }
    }
  }

  // FV[k] = F V[k] over the leaves: pull, gather, push (the parent's linear field evaluated at the
  // child's vertices, kChildVertex), the leaf's mean; with `scaled`, F' = D_r F D_c (balance()).
  void apply(const std::vector<const double*>& V, const std::vector<double*>& FV, bool scaled = true) const {
    Values v;
    pull(V, v, scaled ? source_scale.data() : nullptr);
    const std::size_t K = V.size();
    std::vector<double> root_E;
    cluster_field(v, root_E);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, root_block.size(), 8), [&](const auto& range) {
      std::vector<double> H;
      for (std::size_t r = range.begin(); r != range.end(); ++r) {
        const auto [first, end] = root_block[r];
        H.assign((end - first) * 3 * K, 0.0);
        for (int n = 0; n < 3; ++n)  // what links into clusters give the root: constant over it
          for (std::size_t k = 0; k < K; ++k) H[n * K + k] = root_E[r * K + k];
        for (int e = first; e < end; ++e) {  // parents first: push down
          const Element& el = elements[e];
          double* h = &H[(e - first) * 3 * K];
          if (el.parent >= 0) {
            const double* hp = &H[(el.parent - first) * 3 * K];
            const auto& at = kChildVertex[e - elements[el.parent].first_child];
            for (int n = 0; n < 3; ++n)
              for (int m = 0; m < 3; ++m)
                if (at[n][m] != 0)
                  for (std::size_t k = 0; k < K; ++k) h[n * K + k] += at[n][m] * hp[m * K + k];
          }
          gather_links(e, v, h);
          if (el.leaf >= 0) {
            const double s = (scaled ? leaf_scale[el.leaf] : 1.0) / 3;
            for (std::size_t k = 0; k < K; ++k) FV[k][el.leaf] = s * (h[k] + h[K + k] + h[2 * K + k]);
          }
        }
      }
    });
  }

  // The irradiance that links into clusters give each root, K systems ([slot][k]): the vector
  // irradiance V = Σ Ψ toward of a cluster's links and its ancestors', on the root's normal.
  void cluster_field(const Values& v, std::vector<double>& root_E) const {
    if (v.K > kMaxBatch) throw std::logic_error("cluster_field: more systems than one gather pass holds");
    root_E.assign(roots.size() * v.K, 0.0);
    if (!cluster_links.empty()) field_down(0, {}, false, v, root_E.data());
  }
  using Field = std::array<double, 3 * kMaxBatch>;  // V, [axis][k]
  void field_down(int c, Field V, bool carried, const Values& v, double* root_E) const {
    const std::size_t K = v.K;
    for (std::size_t l = cluster_link_start[c]; l < cluster_link_start[c + 1]; ++l) {
      const ClusterLink& link = cluster_links[l];
      for (std::size_t k = 0; k < K; ++k) {
        double psi = 0;
        if (link.from_cluster) {
          const double* phi = &v.Phi[link.source * 6 * K];
          for (int a = 0; a < 3; ++a) psi += link.coeff[a] * phi[link.bin[a] * K + k];
        } else {
          psi = link.coeff[0] * v.B[link.source * K + k];
        }
        for (int a = 0; a < 3; ++a) V[a * K + k] += psi * link.toward[a];
      }
      carried = true;
    }
    const Cluster& C = clusters[c];
    if (C.root >= 0) {
      if (!carried) return;
      const Vector3& n = elements[C.root].normal;
      for (std::size_t k = 0; k < K; ++k) root_E[C.slot * K + k] = n.x * V[k] + n.y * V[K + k] + n.z * V[2 * K + k];
      return;
    }
    if (!carried && !links_below[c]) return;
    if (C.root_count >= 4096) {
      tbb::parallel_invoke([&] { field_down(C.child[0], V, carried, v, root_E); },
                           [&] { field_down(C.child[1], V, carried, v, root_E); });
    } else {
      field_down(C.child[0], V, carried, v, root_E);
      field_down(C.child[1], V, carried, v, root_E);
    }
  }
  // The adjoint of field_down for one system: root_E_bar per slot into B_bar and Phi_bar; returns
  // the adjoint of cluster c's V where c or an ancestor receives links (`needed`), else 0.
  Vector3 field_up(int c, bool needed, const double* root_E_bar, double* B_bar, double* Phi_bar) const {
    const Cluster& C = clusters[c];
    needed = needed || cluster_link_start[c + 1] > cluster_link_start[c];
    if (!needed && !links_below[c]) return {};
    Vector3 V_bar{};
    if (C.root >= 0) {
      V_bar = root_E_bar[C.slot] * elements[C.root].normal;
    } else {
      V_bar = field_up(C.child[0], needed, root_E_bar, B_bar, Phi_bar) + field_up(C.child[1], needed, root_E_bar, B_bar, Phi_bar);
    }
    for (std::size_t l = cluster_link_start[c]; l < cluster_link_start[c + 1]; ++l) {
      const ClusterLink& link = cluster_links[l];
      const double psi_bar = link.toward[0] * V_bar.x + link.toward[1] * V_bar.y + link.toward[2] * V_bar.z;
      if (link.from_cluster) {
        for (int a = 0; a < 3; ++a) Phi_bar[link.source * 6 + link.bin[a]] += link.coeff[a] * psi_bar;
      } else {
        B_bar[link.source] += link.coeff[0] * psi_bar;
      }
    }
    return needed ? V_bar : Vector3{};
  }

  // out = Fᵀ W over the leaves, for the unscaled operator: the adjoint of apply(), step by step in
  // reverse (leaf mean, push-down, gather, pull). Sources receive from receivers of other roots, so
  // each thread accumulates into its own copy of the element and cluster adjoints.
  void apply_transpose(const double* W, double* out) const {
    const std::size_t E = elements.size();
    std::vector<double> root_E_bar(roots.size(), 0.0);  // adjoint of cluster_field's root_E
    tbb::enumerable_thread_specific<std::vector<double>> adjoints(std::vector<double>(E + 6 * clusters.size(), 0.0));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, root_block.size(), 8), [&](const auto& range) {
      std::vector<double>& a = adjoints.local();
      double* B_bar = a.data();
      double* Phi_bar = a.data() + E;
      std::vector<double> H;  // adjoint of the vertex irradiance, per element of the root's block
      for (std::size_t r = range.begin(); r != range.end(); ++r) {
        const auto [first, end] = root_block[r];
        H.assign((end - first) * 3, 0.0);
        for (int e = end - 1; e >= first; --e) {  // children first: the reverse of the push-down
          const Element& el = elements[e];
          double* h = &H[(e - first) * 3];
          if (el.leaf >= 0)
            for (int n = 0; n < 3; ++n) h[n] += W[el.leaf] / 3;
          for (std::size_t l = link_start[e]; l < link_start[e + 1]; ++l) {
            const Link& link = links[l];
            if (!link.from_cluster) {
              const double read_bar = link.coeff[0] * h[0] + link.coeff[1] * h[1] + link.coeff[2] * h[2];
              source_read(link.source, {link.bin[0], link.bin[1]}).scatter(read_bar, B_bar);
            } else {
              const double total = h[0] + h[1] + h[2];
              for (int k = 0; k < 3; ++k) Phi_bar[link.source * 6 + link.bin[k]] += link.coeff[k] * total;
            }
          }
          for (const LeafLink& link : leaf_links_of(e)) {
            source_read(link.source, link.point).scatter(link.F * h[0] + link.F * h[1] + link.F * h[2], B_bar);
          }
          if (el.parent >= 0) {
            double* hp = &H[(el.parent - first) * 3];
            const auto& at = kChildVertex[e - elements[el.parent].first_child];
            for (int n = 0; n < 3; ++n)
              for (int m = 0; m < 3; ++m) hp[m] += at[n][m] * h[n];
          }
        }
        root_E_bar[r] = H[0] + H[1] + H[2];
      }
    });
    std::vector<double> bar(E + 6 * clusters.size(), 0.0);
    for (const auto& a : adjoints)
      for (std::size_t q = 0; q < bar.size(); ++q) bar[q] += a[q];
    double* B_bar = bar.data();
    double* Phi_bar = bar.data() + E;
    if (!cluster_links.empty()) field_up(0, false, root_E_bar.data(), B_bar, Phi_bar);
    for (std::size_t c = 0; c < clusters.size(); ++c) {  // parents first: the reverse of the pull
      const Cluster& cl = clusters[c];
      const double* phi = &Phi_bar[c * 6];
      if (cl.root >= 0) {
        for (int bin = 0; bin < 6; ++bin) B_bar[cl.root] += cl.projected[bin] * phi[bin];
      } else {
        for (int ch : cl.child)
          for (int bin = 0; bin < 6; ++bin) Phi_bar[ch * 6 + bin] += phi[bin];
      }
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, root_block.size(), 8), [&](const auto& range) {
      for (std::size_t r = range.begin(); r != range.end(); ++r) {
        const auto [first, end] = root_block[r];
        for (int e = first; e < end; ++e) {
          const Element& el = elements[e];
          if (el.leaf >= 0) {
            out[el.leaf] = B_bar[e];
          } else {
            for (int c = 0; c < 4; ++c) B_bar[el.first_child + c] += elements[el.first_child + c].area / el.area * B_bar[e];
          }
        }
      }
    });
  }

  bool has_children(int e) const { return elements[e].first_child >= 0; }

  // The CSR offsets of links and cluster_links (each sorted by receiver), and links_below.
  void index_links() {
    auto offsets = [](const auto& list, std::size_t receivers, std::vector<std::size_t>& start) {
      start.assign(receivers + 1, 0);
      for (const auto& l : list) ++start[l.receiver + 1];
      for (std::size_t r = 0; r < receivers; ++r) start[r + 1] += start[r];
    };
    offsets(links, elements.size(), link_start);
    offsets(hidden_links, elements.size(), hidden_start);
    offsets(cluster_links, clusters.size(), cluster_link_start);
    offsets(hidden_cluster_links, clusters.size(), hidden_cluster_start);
    links_below.assign(clusters.size(), 0);
    for (std::size_t c = clusters.size(); c-- > 0;) {  // children come after their parent
      const Cluster& cl = clusters[c];
      links_below[c] = cluster_link_start[c + 1] > cluster_link_start[c] ||
                       (cl.root < 0 && (links_below[cl.child[0]] || links_below[cl.child[1]]));
    }
  }
};

void check_cancel(const SolveControl& control) {
  if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw SolveCancelled();
}

// Closure and conservation. The links are estimates (rays, fits, cluster approximations) and not
// reciprocal, so their row sums Σ_j F_ij (what leaf i gathers of a uniform radiosity) and their
// area-weighted column sums Σ_i A_i F_ij / A_j (what the scene gathers of leaf j's power) both miss 1
// in a closed hemisphere. Scaling rows alone makes a furnace exact but not the energy: the power shot
// by j is received as its column sum. So rows and columns are scaled together, F' = D_r F D_c
// (Sinkhorn–Knopp, alternating): a closed leaf's row and column sums become 1, an open leaf's are
// only kept from exceeding 1 (never more than a hemisphere, never more than was shot).
//
// Columns are the less accurate side: a coarse source spreads what it sends over its leaves by a
// linear field at most (Link::bin, the point where a near link reads its source), and where it meets
// a small receiver at an edge the kernel is far from even (leaf columns 0.85–1.34 in a black room lit
// by its floor while the spread was even, whose rows were within 1.2 %). So a column is held at 1
// only where that conserves power the scene computes. Leaves that send nothing (`sends` 0: black and
// not emitting) are left alone. Emitting leaves, whose exitance is given, are held together per
// root, weighted by what each sends: held leaf by leaf, they moved the floor's light in that room by
// up to 8 % (17 % while the black walls' columns were held too). Reflecting leaves keep their own
// columns: their power is the solution's, and without them a closed room lit by a point source
// lost 1.2 % of it (held per root, or per group of 16 leaves, 0.7 %: the power a root sends is
// not spread over it as its radiosity is). The price was the same distortion where reflectors meet
// at an edge: with grey walls that room was 8.3 % off the dense solver at worst while coarse sources
// were read at their centroid, 1.0 % since near links read them where the receiver sees them.
//
// Each sweep is one apply() and one apply_transpose(); plain sweeps shrink the error by about 0.65
// each in the sphere furnaces, over-relaxed ones (optimal_overrelaxation, solver/linear_solve.h) by
// about 0.3. The scales and the over-relaxation of the previous refinement round, whose links mostly
// remain, are the starting point. The sweeps stop once every held row and column is within `target`
// of 1 (balance_target), or where a previous balance stalled short of a target at least as tight
// (a stall on the way to the oracle's target does not stop the final balance): a lit room's sweeps
// stall at 1e-6 to 1e-5 (leaves whose rows and columns are nearly free), far below the links' own
// errors, and aiming lower cost the 985 435-patch lit sphere room 20 sweeps a round. Returns the
// largest row-sum error of a closed leaf before any scaling (stats.max_closure_error) and, for the
// final balance, the largest error of a held row or column after it (stats.closure_residual).
//
// A row-sum error ε moves the radiosity of a closed scene by about ε / (1 − ρ) of itself (the furnace:
// B = M / (1 − ρ(1 − ε)); where nothing reflects, the irradiance by ε), so the error that moves it by
// `share` is share × (1 − ρ_max). Every round used to aim for 1e-11 whatever the reflectance, and
// stalled near 1e-6: 48 sweeps in the three rounds of a 61 454-triangle lit sphere room, 11 % of
// its time, where 17 now reach these targets (results within 6e-5, rms 3e-6).
double balance_target(double share, double rho_max) {
  return std::max(kBalanceFloor, share * (1 - std::min(rho_max, 1.0)));
}

struct Balanced {
  double raw_error = 0;  // the largest row-sum error of a closed leaf before any scaling
  double residual = 0;   // the largest error of a held row or column after the balance
};

Balanced balance(Hierarchy& h, const std::vector<Hemisphere>& closed, const std::vector<double>& sends,
                 const std::vector<char>& emits, const std::vector<Patch>& patches, double target,
                 bool final_balance, const SolveControl& control) {
  const std::size_t N = h.leaves.size();
  std::vector<double> rows(N), weighted(N), cols(N), raw(N);
  std::vector<int> root_of(N);  // index into h.roots
  for (std::size_t j = 0; j < N; ++j)
    root_of[j] = static_cast<int>(std::lower_bound(h.roots.begin(), h.roots.end(), h.elements[h.leaves[j]].root) - h.roots.begin());
  std::vector<double> root_sent(h.roots.size()), root_gathered(h.roots.size());
  double raw_error = 0;
  const std::vector<double> ones(N, 1.0);
  h.apply({ones.data()}, {raw.data()}, false);  // Σ_j F_ij, unscaled
  // Rows held at 1: closed leaves, and leaking ones (some probe rays met back faces) whose links
  // already gather a whole hemisphere. Columns held at 1: closed leaves; capped at 1: open ones.
  std::vector<char> full_row(N);
  for (std::size_t i = 0; i < N; ++i) {
    if (closed[i] == Hemisphere::Closed && raw[i] > 0) raw_error = std::max(raw_error, std::abs(1 - raw[i]));
    full_row[i] = closed[i] == Hemisphere::Closed || (closed[i] == Hemisphere::Leaking && raw[i] >= 1);
  }
  if (std::getenv("LAMBERT_DEBUG_ROWS") && final_balance)
    for (std::size_t i = 0; i < N; ++i)
      if (closed[i] == Hemisphere::Closed && std::abs(1 - raw[i]) > 1e-4) {
        const Triangle& t = patches[i].triangle;
        std::fprintf(stderr, "row %zu err %.3g  (%.4f %.4f %.4f) (%.4f %.4f %.4f) (%.4f %.4f %.4f)\n", i, 1 - raw[i],
                     t.v[0].x, t.v[0].y, t.v[0].z, t.v[1].x, t.v[1].y, t.v[1].z, t.v[2].x, t.v[2].y, t.v[2].z);
      }
  if (h.leaf_scale.size() != N) h.leaf_scale.assign(N, 1.0);
  if (h.source_scale.size() != N) h.source_scale.assign(N, 1.0);
  // Over-relaxed: a held scale moves ω times as far as a plain sweep would take it, on a log scale.
  // The previous round's ω, fitted to nearly the same links, is the starting point if that round
  // converged: an ω read from a stall (rates near 1) is far too large, and started the next round
  // of the lit room above at ω = 1.8, with errors of 0.2 that 40 sweeps brought down to 1e-4 only.
  double omega = h.balance_omega;
  const double stop_at = std::max(target, target >= h.balance_stalled_aim ? h.balance_stalled_at : 0.0);
  auto relax = [&](double old, double target) { return omega == 1 ? target : old * std::pow(target / old, omega); };
  // The rows: where `update`, each scale moves toward its row's target; returns the rows' error before.
  auto scale_rows = [&](bool update) {
    h.apply({h.source_scale.data()}, {rows.data()}, false);  // Σ_j F_ij d_c,j
    double row_error = 0;
    for (std::size_t i = 0; i < N; ++i) {
      const double S = rows[i] * h.leaf_scale[i];
      if (full_row[i] && S > 0) row_error = std::max(row_error, std::abs(1 - S));
      if (update) h.leaf_scale[i] = rows[i] > 0 && (full_row[i] || rows[i] > 1) ? relax(h.leaf_scale[i], 1 / rows[i]) : 1.0;
    }
    return row_error;
  };
  // The columns: where `update`, each held scale moves toward its column's target; returns the
  // columns' error before.
  auto scale_columns = [&](bool update) {
    for (std::size_t i = 0; i < N; ++i) weighted[i] = patches[i].area_m2 * h.leaf_scale[i];
    h.apply_transpose(weighted.data(), cols.data());  // Σ_i A_i d_r,i F_ij
    // Closed emitting leaves: per root, what the scene gathers of the power they send, over that power.
    std::fill(root_sent.begin(), root_sent.end(), 0.0);
    std::fill(root_gathered.begin(), root_gathered.end(), 0.0);
    for (std::size_t j = 0; j < N; ++j) {
      if (closed[j] != Hemisphere::Closed || !emits[j]) continue;
      root_sent[root_of[j]] += sends[j] * patches[j].area_m2;
      root_gathered[root_of[j]] += sends[j] * cols[j] * h.source_scale[j];
    }
    double col_error = 0;
    for (std::size_t j = 0; j < N; ++j) {
      if (closed[j] == Hemisphere::Closed) {
        // What the scene gathers of the power sent, over that power: the root's emitting leaves
        // together, or the leaf alone.
        const double sent = emits[j] ? root_sent[root_of[j]] : sends[j] * patches[j].area_m2;
        const double C = (emits[j] ? root_gathered[root_of[j]] : sends[j] * cols[j] * h.source_scale[j]) / sent;
        if (!(sent > 0 && C > 0)) {
          if (update) h.source_scale[j] = 1.0;  // sends nothing: no power to conserve
          continue;
        }
        col_error = std::max(col_error, std::abs(1 - C));
        if (update) h.source_scale[j] = relax(h.source_scale[j], h.source_scale[j] / C);
      } else {
        const double t = cols[j] / patches[j].area_m2;
        if (update) h.source_scale[j] = closed[j] == Hemisphere::Open && t > 1 ? relax(h.source_scale[j], 1 / t) : 1.0;
      }
    }
    return col_error;
  };
  // Stops at convergence, or when ten sweeps have not cut the error tenfold (leaves partly inside
  // solids, whose rows and columns are free, can make the balance crawl: it would cost sweeps, not
  // accuracy). Healthy sweeps gain 10⁴ in ten, plain or over-relaxed. Over-relaxed sweeps do keep
  // crawling down, at about 0.8 a sweep, where plain ones stall. Halving in ten sweeps was not enough:
  // a lit room of 984 320 patches spent 100 sweeps a round, 320 s of its 861.
  double best = 1e300, best_ten_ago = 1e300;
  std::vector<double> errors;  // of the sweeps since ω last changed
  for (int sweep = 0; sweep < kMaxBalanceSweeps; ++sweep) {
    check_cancel(control);
    const double row_error = scale_rows(true);
    const double col_error = scale_columns(true);
    const double error = std::max(row_error, col_error);
    best = std::min(best, error);
    if (error < stop_at) break;
    errors.push_back(error);
    const std::size_t n = errors.size();
    if (n >= 4) {
      const double rate = std::sqrt(errors[n - 1] / errors[n - 3]);  // per sweep, over the last two
      if (rate < 1) {  // (a rate below ω − 1 is faster than the model allows: nothing to infer)
        const double omega_best = rate >= omega - 1 ? optimal_overrelaxation(rate, omega) : omega;
        if (omega_best > omega + 0.02) {
          omega = omega_best;
          errors.clear();
        }
      } else if (omega > 1) {  // not converging: back to plain sweeps
        omega = 1;
        errors.clear();
      }
    }
    if (sweep % 10 == 9) {
      if (best > 0.1 * best_ten_ago) break;
      best_ten_ago = best;
    }
  }
  const bool reached = best < stop_at;
  h.balance_omega = reached ? omega : 1;
  if (!reached) h.balance_stalled_at = best, h.balance_stalled_aim = target;
  omega = 1;
  // Rows last: a furnace with ρ = 0.999 multiplies a row's error by 1000. Where the sweeps stopped
  // short of convergence, the columns keep a small error, which the energy certificate shows as
  // imbalance, and which the final balance's residual reports (one sweep more, not updating).
  scale_rows(true);
  if (!final_balance) return {raw_error, 0};
  const double row_residual = scale_rows(false);
  return {raw_error, std::max(row_residual, scale_columns(false))};
}

// Least-squares f ≈ Σ_v a_v β_v over points with barycentric coordinates β (normal equations, Cramer).
template <std::size_t P>
std::array<double, 3> linear_fit(const std::array<std::array<double, 3>, P>& beta, const std::array<double, P>& f) {
  double m[3][3] = {}, r[3] = {};
  for (std::size_t q = 0; q < P; ++q)
    for (int u = 0; u < 3; ++u) {
      r[u] += beta[q][u] * f[q];
      for (int v = 0; v < 3; ++v) m[u][v] += beta[q][u] * beta[q][v];
    }
  auto det = [](const double (&x)[3][3]) {
    return x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1]) - x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0]) +
           x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]);
  };
  const double d = det(m);
  std::array<double, 3> a{};
  for (int c = 0; c < 3; ++c) {
    double x[3][3];
    for (int u = 0; u < 3; ++u)
      for (int v = 0; v < 3; ++v) x[u][v] = v == c ? r[u] : m[u][v];
    a[c] = det(x) / d;
  }
  return a;
}

// Visibility sample k (< 64) of a cluster: a stratified sample point of one of its roots, the roots
// drawn spread over its BVH range.
Hierarchy::ClusterSample cluster_sample(const Hierarchy& h, const Cluster& C, int k) {
  if (C.samples >= 0 && k < kTabledClusterSamples) return h.cluster_samples[C.samples + k];
  const int pick = (37 * k + 11) % kMaxVisibilitySamples;
  const Hierarchy::RootSample& root =
      h.ordered_roots[C.first_root + static_cast<int>(static_cast<long long>(pick) * C.root_count / kMaxVisibilitySamples)];
  return {visibility_sample(root.tri, k), root.normal};
}

// Bounds of Σ A (n·w)⁺ over the roots of cluster c, added to [lower, upper]. A subtree whose normal
// cone lies wholly in front of w's horizon adds its area vector · w, one wholly behind adds nothing,
// and one with axis-aligned normals adds its bins, all exactly; only clusters whose normals straddle
// the horizon are descended into, at most `budget` of them. Past the budget a cluster adds
// (area vector · w)⁺ below and its bins above.
void bound_projected_area(const Hierarchy& h, int c, const Vector3& w, int& budget, double& lower, double& upper) {
  const Cluster& C = h.clusters[c];
  double exact = -1;
  if (C.axis_normals) {
    exact = binned_area(C, w);
  } else if (C.cone_sin <= 1 || C.root >= 0) {
    const double along = dot(C.cone_axis, w);
    if (along >= C.cone_sin || C.root >= 0) exact = std::max(0.0, dot(C.area_vector, w));
    else if (along <= -C.cone_sin) exact = 0;
  }
  if (exact >= 0) {
    lower += exact, upper += exact;
  } else if (budget-- <= 0) {
    lower += std::max(0.0, dot(C.area_vector, w)), upper += binned_area(C, w);
  } else {
    bound_projected_area(h, C.child[0], w, budget, lower, upper);
    bound_projected_area(h, C.child[1], w, budget, lower, upper);
  }
}
constexpr int kProjectionBudget = 256;  // clusters descended into per bound_projected_area

// How a link to cluster c from direction w (unit, from the cluster) reads its projected power Φ: the
// three bins facing w, weighted so that a cluster of uniform radiosity B sends B × `projected` (the
// area it shows, within ± `uncertainty`) rather than the bins' upper bound. Where the radiosity is
// not uniform, the bins still tell the sides of the cluster apart.
struct ClusterView {
  std::array<unsigned char, 3> bin{};
  std::array<double, 3> weight{};
  double projected = 0;  // 0: every root faces away from w
  double uncertainty = 0;
};
ClusterView cluster_view(const Hierarchy& h, int c, const Vector3& w) {
  ClusterView view;
  const double wa[3] = {w.x, w.y, w.z};
  for (int a = 0; a < 3; ++a) view.bin[a] = static_cast<unsigned char>(wa[a] > 0 ? 2 * a : 2 * a + 1);
  const Cluster& C = h.clusters[c];
  const double binned = binned_area(C, w);
  if (binned <= 0) return view;
  if (C.axis_normals) {  // the bins are exact (the common case in buildings)
    view.projected = binned;
    for (int a = 0; a < 3; ++a) view.weight[a] = std::abs(wa[a]);
    return view;
  }
  double lower = 0, upper = 0;
  int budget = kProjectionBudget;
  bound_projected_area(h, c, w, budget, lower, upper);
  view.projected = 0.5 * (lower + upper);
  view.uncertainty = 0.5 * (upper - lower);
  for (int a = 0; a < 3; ++a) view.weight[a] = std::abs(wa[a]) * view.projected / binned;
  return view;
}

// Fills Hierarchy::cluster_samples (see there) once the clusters and ordered_roots are built.
void table_cluster_samples(Hierarchy& h) {
  for (Cluster& C : h.clusters) {
    if (C.root_count <= kTabledClusterSamples) continue;
    const int first = static_cast<int>(h.cluster_samples.size());
    for (int k = 0; k < kTabledClusterSamples; ++k) h.cluster_samples.push_back(cluster_sample(h, C, k));
    C.samples = first;
  }
}

// The coefficients of a pending leaf-to-leaf link whose factor is computed once its rays find it
// visible (a NaN: no fit or factor is one).
constexpr float kFactorPending = std::numeric_limits<float>::quiet_NaN();
bool factor_pending(const Link& link) { return std::isnan(link.coeff[0]); }

// A_r F_rs = A_s F_sr of near pairs of leaves (exchange_area), keyed by the pair (the lower element
// index in the high 32 bits): see Refiner::leaf_exchange.
using ExchangeCache = tbb::concurrent_unordered_map<std::uint64_t, double>;

// Frees a vector's buffer. (`v = {}` would not: it picks the initializer-list assignment, which keeps
// the capacity.)
template <class T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

// The links one thread finds, in blocks of 64 MiB. glibc maps blocks this large on their own (its
// mmap threshold is at most 32 MiB) and returns them to the system when they are freed, so take_sorted
// frees each block as soon as it is copied. In one growing vector per thread, the vector's doublings
// copied the links while they were being found (1.6–1.9 GB bumps at 167 M links), and the first
// round's sort copied each thread's vector whole while it was still held (+2.2 GB).
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
  LinkBlocks<Link> hidden;  // links that rays found hidden, for the final gather (Hierarchy::hidden_links)
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

// A link that a recheck replaced by finer ones is marked by its source (see merge_rechecked).
constexpr int kReplaced = -1;

// The links of the next round: those a recheck kept stay where they are, in order, and the sorted
// replacements are merged in from the back. Rebuilding the whole set each round held the links twice
// (the previous round's and the threads' copies): 14.0 GB at peak for 167 M links, where one copy is
// 4.7 GB. Now the only extra memory is the replacements, a few per cent of the links after the first
// round. (A merge that outgrows the vector's reserve reallocates, as before.)
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
// Links from or into clusters have a room of their own, past which they are dropped (the city
// block's overran kMaxLeafLinks, and with one room for both its gather did not retrace).
struct HiddenRoom {
  std::atomic<std::int64_t> elements{0}, clustered{0};
};

constexpr std::size_t kMaxSidedElements = 250'000;  // occluder-plane sides for at most this many (64 MB)
constexpr double kMaxClosureFactors = 2e6;  // leaves × input triangles for closure without rays (≤ 0.7 s of CPU)

// The occluder planes' verdicts on pairs of elements (occluder_planes.h): clear where nothing can lie
// between them, without rays. Built once per solve, for the refinement's links and the final gather.
// In a convex room there is no occluder plane and every pair is clear: the refinement then traces no
// link ray (2.1 M in the issue-4 room at 5 524 patches while only the gather asked the planes), and its
// links carry no rays' noise. The room with a floating cube: 4.7 M of 18.9 M rays fewer, 12 % less time.
class PlaneVerdicts {
 public:
  // planes: of the scene's triangles (the roots). The sides of every element and of every cluster's
  // box (its eight corners) are kept, 256 bytes each, where the planes can serve and there are at
  // most kMaxSidedElements of them.
  PlaneVerdicts(const Hierarchy& h, const OccluderPlanes& planes) : planes_(planes) {
    all_clear_ = planes_.usable() && planes_.planes() == 0;
    if (!planes_.usable() || planes_.planes() == 0 || h.elements.size() + h.clusters.size() > kMaxSidedElements)
      return;
    sides_.resize(h.elements.size());
    cluster_sides_.resize(h.clusters.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sides_.size(), 256), [&](const auto& range) {
      for (std::size_t e = range.begin(); e != range.end(); ++e) sides_[e] = planes_.sides(h.elements[e].tri.v);
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cluster_sides_.size(), 256), [&](const auto& range) {
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        const Bounds3& b = h.clusters[c].box;
        std::array<Point3, 8> corners;
        for (int k = 0; k < 8; ++k) corners[k] = {k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z};
        cluster_sides_[c] = planes_.sides(corners);
      }
    });
  }
  // Whether elements a and b see each other wholly: no occluder can lie between them.
  bool clear(int a, int b) const { return all_clear_ || (!sides_.empty() && planes_.clear(sides_[a], sides_[b])); }
  // The same for cluster c and an element, or another cluster where `other_is_cluster`.
  bool clear_cluster(int c, int other, bool other_is_cluster) const {
    return all_clear_ ||
           (!sides_.empty() && planes_.clear(cluster_sides_[c], other_is_cluster ? cluster_sides_[other] : sides_[other]));
  }
  // A point (a probe's): its sides, then whether it sees element e, or cluster c, wholly.
  OccluderPlanes::Sides sides(const Point3& p) const {
    return sides_.empty() ? OccluderPlanes::Sides{} : planes_.sides(std::span<const Point3>(&p, 1));
  }
  bool point_sees(const OccluderPlanes::Sides& point, int e) const {
    return all_clear_ || (!sides_.empty() && planes_.clear(point, sides_[e]));
  }
  bool point_sees_cluster(const OccluderPlanes::Sides& point, int c) const {
    return all_clear_ || (!sides_.empty() && planes_.clear(point, cluster_sides_[c]));
  }

 private:
  const OccluderPlanes& planes_;
  bool all_clear_ = false;                            // no occluder plane at all
  std::vector<OccluderPlanes::Sides> sides_;          // per element, where planes_ is usable
  std::vector<OccluderPlanes::Sides> cluster_sides_;  // per cluster, the same
};

// The refinement of one (receiver element, source) pair into links, with the BF oracle.
class Refiner {
 public:
  Refiner(const Hierarchy& h, const Visibility& vis, const ExactVisibility& shafts, const PlaneVerdicts& planes,
          const std::vector<double>& element_B, const std::vector<double>& cluster_B, double epsilon, double unit_area,
          double accuracy, ExchangeCache& exchange, HiddenRoom& hidden_room)
      : h_(h), vis_(vis), shafts_(shafts), planes_(planes), element_B_(element_B), cluster_B_(cluster_B), epsilon_(epsilon),
        unit_area_(unit_area), exchange_(exchange), hidden_room_(hidden_room) {
    // The cubature of near pairs may err by a tenth of what the oracle allows a link (relative), not
    // the dense solver's 1e-5: the city block of the benchmarks solved 1.3× faster, its radiosity
    // moving by 7e-6 of the mean (rms; 4e-4 on the worst patch) at the default accuracy 1e-3.
    near_field_.rel_tolerance = std::max(near_field_.rel_tolerance, 0.1 * accuracy);
    near_field_.abs_tolerance = std::max(near_field_.abs_tolerance, 1e-3 * accuracy);
  }

  // The oracle bounds irradiance errors at the patch scale and power errors above it: an error of
  // δE over a receiver of area A counts δE × max(1, A / unit_area). Coarse receivers (many patches)
  // may err more per unit area, since their links are pushed down to children that also gather
  // their own finer links; this keeps the link count near-linear.
  double area_weight(double receiver_area) const { return std::max(1.0, receiver_area / unit_area_); }

  // The error bound per unit source radiosity of a one-point link across distance d between bounding
  // spheres whose radii sum to `scale` (d_min = d − scale): the transfer is at most
  // projected/(π d_min²) (cos θ ≤ 1, distance ≥ d_min); the one-point estimate errs by about the
  // pair's relative size scale/d of it, and the projected area by its uncertainty.
  double one_point_error(const ClusterView& view, double scale, double d, double d_min, double receiver_area) const {
    return (view.projected * scale / d + view.uncertainty) / (kPi * d_min * d_min) * area_weight(receiver_area);
  }

  void refine_to_element(int r, int s, LinkBatch& out) const {
    const Element& R = h_.elements[r];
    const Element& S = h_.elements[s];
    if (r == s || h_.is_enclosed(r) || h_.is_enclosed(s) || !any_in_front(R.tri, R.normal, S.tri) ||
        !any_in_front(S.tri, S.normal, R.tri))
      return;
    if (!h_.has_children(r) && !h_.has_children(s)) return link_leaves(r, s, out);
    const double B = element_B_[s];
    // The point kernel at the receiver's degree-5 nodes and next to its corners (it peaks at edges
    // shared with the source), fitted by a linear function over the receiver (least squares in
    // barycentric coordinates). The link carries that linear factor, so that push-down hands each
    // child the factor at its own place; the fit's residual is the link's error.
    const TriangleRule rule = triangle_rule_degree5();
    constexpr int kPoints = 10;
    std::array<std::array<double, 3>, kPoints> beta;
    std::array<double, kPoints> f;
    std::array<Point3, kPoints> points;
    for (int q = 0; q < kPoints; ++q) {
      if (q < rule.size) {
        beta[q] = *(rule.nodes + q);
      } else {
        constexpr double t = 1e-3;
        beta[q] = {t / 3, t / 3, t / 3};
        beta[q][q - rule.size] += 1 - t;
      }
      const auto& w = beta[q];
      points[q] = barycentric(R.tri.v[0], R.tri.v[1], R.tri.v[2], w[0], w[1], w[2]);
    }
    // One batch, whose lanes give point_triangle_factor's values (10 calls one by one were 6 % of the
    // cube room's solve with solver.exact_visibility).
    point_triangle_factors(points, R.normal, S.tri, f);
    double mean = 0, hi = 0;
    for (int q = 0; q < kPoints; ++q) {
      if (q < rule.size) mean += rule.weights[q] * f[q];
      hi = std::max(hi, f[q]);
    }
    if (hi <= 0) return;
    std::array<double, 3> a = linear_fit(beta, f);
    double residual = 0;
    for (int q = 0; q < kPoints; ++q)
      residual = std::max(residual, std::abs(f[q] - (a[0] * beta[q][0] + a[1] * beta[q][1] + a[2] * beta[q][2])));
    const double weight = area_weight(R.area);
    if (B * residual * weight > epsilon_) return split(r, s, out);
    // Near pairs: the mean by adaptive cubature over the smaller of the two (exchange_area; exact
    // kernel, log-singular near contact).
    const double separation = distance(R.centre, S.centre) / (R.radius + S.radius);
    // (The fixed rule's mean only where S's plane does not cut R: see cubature.h, front_part.)
    const bool smooth = separation > 4 * kTie && !plane_cuts(R.tri, S.tri.v[0], S.tri.area_vector());
    const double F = smooth ? mean : exchange_area(R.tri, S.tri, near_field_) / R.area;
    if (F <= 0) return;
    const double shift = F - (a[0] + a[1] + a[2]) / 3;  // the linear factor's mean is F exactly
    for (double& value : a) value += shift;
    // Visibility. An occluder in the shaft (the hull of the two elements) makes the link uncertain
    // even when rays would agree: unanimous rays between coarse elements can miss a partly hidden part
    // (and drop a link that is half visible) or a small occluder, and a missed occluder is counted
    // twice (through the link and through the occluder's own links), which biased row sums by tens
    // of %. Half the factor bounds the error either way; where that is over the oracle's budget, a
    // clear shaft means wholly visible, exactly and without rays, and any other is split. Where it is
    // within the budget, the link takes rays (16 before the first vote) without the shaft test: in
    // the lit sphere rooms 95 % of the tested pairs were of this kind and 0.7 % of them clear, so the
    // test (9 % of the solve's time, about 40 rays' worth) mostly bought nothing. Before either, the
    // occluder planes, a few word operations: a pair they clear is wholly visible.
    const double uncertain = 0.5 * F;
    bool clear = planes_.clear(r, s);
    if (!clear && B * uncertain * weight > epsilon_) {
      const std::array<Point3, 6> hull = {R.tri.v[0], R.tri.v[1], R.tri.v[2], S.tri.v[0], S.tri.v[1], S.tri.v[2]};
      clear = shafts_.shaft_is_clear(hull);
    }
    const double partial = clear ? 0 : uncertain;
    if (B * partial * weight > epsilon_) return split(r, s, out);
    Link link;
    link.receiver = r;
    link.source = s;
    for (int k = 0; k < 3; ++k) link.coeff[k] = static_cast<float>(a[k]);
    link.error_per_B = static_cast<float>((residual + partial) * weight);
    if (!smooth && h_.has_children(s)) link.bin = source_point_of(S, R);
    link.bin[2] = clear ? kShaftClear : kVisibilityUnknown;
    if (clear) out.links.push_back(link);
    else out.pending.push_back(link);
  }

  void refine_to_cluster(int r, int c, LinkBatch& out) const {
    if (h_.is_enclosed(r)) return;
    const Element& R = h_.elements[r];
    const Cluster& C = h_.clusters[c];
    if (C.root >= 0) return refine_to_element(r, C.root, out);
    const double scale = R.radius + C.radius;
    if (!box_in_front(C.box, R.tri.v[0], R.normal, 1e-12 * scale)) return;
    const Vector3 d_vec = R.centre - C.centre;  // from the cluster to the receiver
    const double d = length(d_vec);
    const double d_min = d - C.radius - R.radius;
    if (d >= kWellSeparated * scale * kTie && d_min > 0) {
      const Vector3 w = d_vec / d;
      // Nothing passes only where no direction between the two faces both ways (see may_face); where
      // the line between the centres misses but others may not, the pair is split below, unless all
      // that could pass is within the oracle's budget.
      const double sin_delta = scale / d;
      const double cos_r = -dot(R.normal, w);
      if (cos_r <= -sin_delta || !may_face(C, w, sin_delta, bounds(R.tri))) return;
      const ClusterView view = cluster_view(h_, c, w);
      if (view.projected <= 0 || cos_r <= 0) {
        // A link of factor 0: the line between the centres misses, others may not. Along those, the
        // cosine on the side it misses is at most sin δ, so what passes is at most this.
        const double reach = max_projected(C) * (view.projected > 0 ? 1 : sin_delta) * (cos_r > 0 ? 1 : sin_delta) /
                             (kPi * d_min * d_min) * area_weight(R.area);
        if (cluster_B_[c] * reach <= epsilon_) return;
      }
      const double error_per_B = one_point_error(view, scale, d, d_min, R.area);
      if (view.projected > 0 && cos_r > 0 && cluster_B_[c] * error_per_B <= epsilon_) {
        Link link;
        link.receiver = r;
        link.source = c;
        link.from_cluster = true;
        link.bin = view.bin;
        for (int a = 0; a < 3; ++a) link.coeff[a] = static_cast<float>(view.weight[a] * cos_r / (kPi * d * d));
        link.error_per_B = static_cast<float>(error_per_B);
        if (planes_.clear_cluster(c, r, false)) out.links.push_back(link);  // wholly visible, no rays
        else out.pending.push_back(link);
        return;
      }
    }
    if (C.radius * kTie >= R.radius || !h_.has_children(r)) {
      for (int ch : C.child) refine_to_cluster(r, ch, out);
    } else {
      const int first = h_.elements[r].first_child;
      for (int k = 0; k < 4; ++k) refine_to_cluster(first + k, c, out);
    }
  }

  // The refinement of the pair (receivers in cluster rc, source s: a cluster, or an element where
  // !from_cluster). A well separated pair links as a whole where the receivers' normals all face the
  // source (their cone lies in front of the direction between the centres, so (n · u)⁺ = n · u is
  // linear and V = Σ Ψ u serves them all) and the oracle allows the one-point estimate; otherwise the
  // larger side is split, the receivers where their normals are the obstacle. A receiver that is one
  // root goes on as refine_to_cluster or refine_to_element.
  void refine_pair(int rc, int s, bool from_cluster, LinkBatch& out) const {
    const Cluster& R = h_.clusters[rc];
    if (R.root >= 0) {
      from_cluster ? refine_to_cluster(R.root, s, out) : refine_to_element(R.root, s, out);
      if (out.pending.size() + out.cluster_pending.size() >= kResolveBatch) resolve(out);
      return;
    }
    if (from_cluster && h_.clusters[s].root >= 0) return refine_pair(rc, h_.clusters[s].root, false, out);
    const Point3& s_centre = from_cluster ? h_.clusters[s].centre : h_.elements[s].centre;
    const double s_radius = from_cluster ? h_.clusters[s].radius : h_.elements[s].radius;
    auto split_receiver = [&] {
      refine_pair(R.child[0], s, from_cluster, out);
      refine_pair(R.child[1], s, from_cluster, out);
    };
    auto split = [&] {
      if (R.radius * kTie >= s_radius || (!from_cluster && !h_.has_children(s))) return split_receiver();
      if (from_cluster) {
        for (int c : h_.clusters[s].child) refine_pair(rc, c, true, out);
      } else {
        for (int k = 0; k < 4; ++k) refine_pair(rc, h_.elements[s].first_child + k, false, out);
      }
    };
    const double scale = R.radius + s_radius;
    const Vector3 between = R.centre - s_centre;  // from the source to the receivers
    const double d = length(between);
    const double d_min = d - scale;
    if ((from_cluster && rc == s) || d < kReceiversSeparated * scale * kTie || d_min <= 0) return split();
    if (R.cone_sin > 1) return split_receiver();
    const Vector3 w = between / d;
    // α: between the receivers' cone axis and u = −w; θ: the cone's half-angle; δ: how far the
    // directions between points of the two bounding spheres stray from u.
    const double alpha = std::acos(std::clamp(-dot(R.cone_axis, w), -1.0, 1.0));
    const double theta = std::asin(R.cone_sin);
    const double delta = std::asin(std::min(1.0, scale / d));
    if (alpha - theta - delta >= kPi / 2) return;  // every receiver faces away from every source point
    // The source: nothing passes where none of it faces any direction of the cone (may_face); where
    // only the line between the centres misses it, the pair is split unless all that could pass is
    // within the oracle's budget.
    const double sin_delta = std::min(1.0, scale / d);
    ClusterView view;
    if (from_cluster) {
      if (!may_face(h_.clusters[s], w, sin_delta, R.box)) return;
      view = cluster_view(h_, s, w);
    } else {
      const Element& E = h_.elements[s];
      if (dot(E.normal, w) <= -sin_delta) return;
      view.projected = E.area * std::max(0.0, dot(E.normal, w));
    }
    const double B = from_cluster ? cluster_B_[s] : element_B_[s];
    if (view.projected <= 0) {  // a link of factor 0, as in refine_to_cluster
      const double shown = from_cluster ? max_projected(h_.clusters[s]) : h_.elements[s].area;
      const double reach = shown * sin_delta / (kPi * d_min * d_min) * area_weight(R.area);
      return B * reach <= epsilon_ ? void() : split();
    }
    const double error_per_B = one_point_error(view, scale, d, d_min, R.area);
    if (alpha + theta > kPi / 2) return split_receiver();
    if (B * error_per_B > epsilon_) return split();
    ClusterLink link;
    link.receiver = rc;
    link.source = s;
    link.from_cluster = from_cluster;
    link.bin = view.bin;
    if (from_cluster) {
      for (int a = 0; a < 3; ++a) link.coeff[a] = static_cast<float>(view.weight[a] / (kPi * d * d));
    } else {
      link.coeff[0] = static_cast<float>(view.projected / (kPi * d * d));
    }
    link.toward = {static_cast<float>(-w.x), static_cast<float>(-w.y), static_cast<float>(-w.z)};
    link.error_per_B = static_cast<float>(error_per_B);
    if (planes_.clear_cluster(rc, s, from_cluster)) out.cluster_links.push_back(link);  // wholly visible, no rays
    else out.cluster_pending.push_back(link);
  }

  // Traces the rays of the pending links, all at once as streams (16 per link before the first vote:
  // four unanimous rays between large elements miss small occluders; but four blocked rays may drop
  // a link whose whole transfer is within the oracle's ε), and keeps the visible ones with
  // their coefficients times the visible fraction. Element links pair the two elements' stratified
  // samples; cluster links go to points of the cluster's roots spread over its BVH range, each
  // weighted by the differential kernel with the sampled element's own normal (elements of the
  // cluster that face away, often hidden by the cluster itself, weigh nothing).
  void resolve(LinkBatch& out) const {
    resolve_cluster_links(out);
    if (out.pending.empty()) return;
    thread_local std::vector<double> fraction;
    fraction.resize(out.pending.size());
    // Links whose whole unoccluded transfer is within the oracle's budget ε may be found hidden by 4
    // rays (weighted_visible_fractions): a wrong verdict errs by no more than a link may.
    thread_local std::vector<char> early;
    early.resize(out.pending.size());
    for (std::size_t l = 0; l < out.pending.size(); ++l) {
      const Link& link = out.pending[l];
      double transfer = 0;  // irradiance at the receiver per its area weight, unoccluded
      if (link.from_cluster) {
        const Cluster& C = h_.clusters[link.source];
        for (int a = 0; a < 3; ++a) transfer += link.coeff[a] * C.projected[link.bin[a]];
        transfer *= cluster_B_[link.source];
      } else if (!factor_pending(link)) {
        transfer = element_B_[link.source] * (link.coeff[0] + link.coeff[1] + link.coeff[2]) / 3;
      } else {
        // Two leaves, whose factor is computed after the rays: twice the point factor at the
        // receiver's centroid stands for it, for pairs whose bounding spheres are well apart.
        const Element& R = h_.elements[link.receiver];
        const Element& S = h_.elements[link.source];
        const bool apart = distance(R.centre, S.centre) > 2 * (R.radius + S.radius) * kTie;
        transfer = apart ? 2 * element_B_[link.source] * point_triangle_factor(R.centre, R.normal, S.tri) : 1e300;
      }
      early[l] = transfer * area_weight(h_.elements[link.receiver].area) <= epsilon_;
    }
    Vector3 source_normal;  // of the sample just drawn (weight() follows endpoints() for each ray)
    out.rays += weighted_visible_fractions(
        vis_, out.pending.size(),
        [&](std::size_t l, int k) {
          const Link& link = out.pending[l];
          const Element& R = h_.elements[link.receiver];
          const Point3 p = vis_.lift(visibility_sample(R.tri, k), R.normal);
          if (link.from_cluster) {
            const Hierarchy::ClusterSample S = cluster_sample(h_, h_.clusters[link.source], k);
            source_normal = S.normal;
            return std::pair{p, vis_.lift(S.point, S.normal)};
          }
          const Element& S = h_.elements[link.source];
          source_normal = S.normal;
          return std::pair{p, vis_.lift(visibility_sample(S.tri, paired_sample(k)), S.normal)};
        },
        [&](std::size_t l, const Point3& p, const Point3& q) {
          return link_weight(p, h_.elements[out.pending[l].receiver].normal, q, source_normal);
        },
        fraction, 16, early);
    for (std::size_t l = 0; l < out.pending.size(); ++l) {
      if (!(fraction[l] > 0)) {
        if (keeps_hidden(out.pending[l].from_cluster, out.pending[l].from_cluster, out.pending[l].source))
          out.hidden.push_back(out.pending[l]);
        continue;
      }
      Link link = out.pending[l];
      if (factor_pending(link)) {  // two leaves (link_leaves): the mean factor, now
        const double F = leaf_exchange(link.receiver, link.source) / h_.elements[link.receiver].area;
        if (!(F > 0)) continue;
        link.coeff.fill(static_cast<float>(F));
      }
      for (float& c : link.coeff) c = static_cast<float>(c * fraction[l]);
      if (!link.from_cluster && fraction[l] == 1) link.bin[2] = kRaysUnanimous;
      out.links.push_back(link);
    }
    out.pending.clear();
  }

  // The rays of links into clusters: between samples of the receiving cluster's roots and of the
  // source's, each weighted by the kernel with both samples' own normals; 16 before the first vote.
  void resolve_cluster_links(LinkBatch& out) const {
    if (out.cluster_pending.empty()) return;
    thread_local std::vector<double> fraction;
    fraction.resize(out.cluster_pending.size());
    Vector3 receiver_normal, source_normal;  // of the samples just drawn
    out.rays += weighted_visible_fractions(
        vis_, out.cluster_pending.size(),
        [&](std::size_t l, int k) {
          const ClusterLink& link = out.cluster_pending[l];
          const Hierarchy::ClusterSample R = cluster_sample(h_, h_.clusters[link.receiver], k);
          receiver_normal = R.normal;
          const Point3 p = vis_.lift(R.point, R.normal);
          if (link.from_cluster) {
            const Hierarchy::ClusterSample S = cluster_sample(h_, h_.clusters[link.source], paired_sample(k));
            source_normal = S.normal;
            return std::pair{p, vis_.lift(S.point, S.normal)};
          }
          const Element& S = h_.elements[link.source];
          source_normal = S.normal;
          return std::pair{p, vis_.lift(visibility_sample(S.tri, paired_sample(k)), S.normal)};
        },
        [&](std::size_t, const Point3& p, const Point3& q) { return link_weight(p, receiver_normal, q, source_normal); },
        fraction, 16);
    for (std::size_t l = 0; l < out.cluster_pending.size(); ++l) {
      if (!(fraction[l] > 0)) {
        if (keeps_hidden(true, out.cluster_pending[l].from_cluster, out.cluster_pending[l].source))
          out.hidden_cluster.push_back(out.cluster_pending[l]);
        continue;
      }
      ClusterLink link = out.cluster_pending[l];
      for (float& c : link.coeff) c = static_cast<float>(c * fraction[l]);
      out.cluster_links.push_back(link);
    }
    out.cluster_pending.clear();
  }

  // Whether a link that rays found hidden is kept for the final gather (Hierarchy::hidden_links):
  // while there is room, if the gather can expand its source (an element, or a cluster of at most
  // kExpandedClusterRoots roots). `clustered`: from a cluster or into one.
  bool keeps_hidden(bool clustered, bool from_cluster, int source) const {
    if (from_cluster && h_.clusters[source].root_count > kExpandedClusterRoots) return false;
    std::atomic<std::int64_t>& room = clustered ? hidden_room_.clustered : hidden_room_.elements;
    return room.load(std::memory_order_relaxed) > 0 && room.fetch_sub(1, std::memory_order_relaxed) > 0;
  }

  // Re-examines a kept link into a cluster: keeps it (false) or refines the pair again (true).
  bool recheck(const ClusterLink& link, LinkBatch& out) const {
    const double B = link.from_cluster ? cluster_B_[link.source] : element_B_[link.source];
    if (B * link.error_per_B <= epsilon_) return false;
    refine_pair(link.receiver, link.source, link.from_cluster, out);
    return true;
  }

  // Re-examines a link with the current radiosity: keeps it (false) or refines it into `out` (true).
  bool recheck(const Link& link, LinkBatch& out) const {
    const double B = link.from_cluster ? cluster_B_[link.source] : element_B_[link.source];
    if (B * link.error_per_B <= epsilon_) return false;
    if (link.from_cluster) {
      refine_to_cluster(link.receiver, link.source, out);
    } else if (h_.has_children(link.receiver) || h_.has_children(link.source)) {
      split(link.receiver, link.source, out);
    } else {
      return false;  // leaves both: nothing finer to link
    }
    return true;
  }

 private:
  // Two leaves: nothing can be split, so the link needs neither the linear fit (a leaf takes the mean
  // of what it gathers) nor an error bound (recheck keeps leaf-to-leaf links), nor a shaft test (it
  // would only spare the rays of a clear link, and in cluttered scenes most links are not clear: a city
  // block cleared 6 % of its shafts at 3.8 µs each, the price of 40 rays).
  // Its factor waits for the rays (resolve()): most leaf pairs in a cluttered scene turn out wholly
  // hidden, and the factor of a near pair (adaptive cubature) cost more than their rays.
  // A pair that the occluder planes clear needs no rays: its factor now, and wholly visible.
  void link_leaves(int r, int s, LinkBatch& out) const {
    Link link;
    link.receiver = r;
    link.source = s;
    if (planes_.clear(r, s)) {
      const double F = leaf_exchange(r, s) / h_.elements[r].area;
      if (!(F > 0)) return;
      link.coeff.fill(static_cast<float>(F));
      link.bin[2] = kShaftClear;
      out.links.push_back(link);
      return;
    }
    link.coeff.fill(kFactorPending);
    out.pending.push_back(link);
  }

  // A_r F_rs = A_s F_sr of two leaves (exchange_area: the same whichever asks). Near pairs (adaptive
  // cubature, tens of µs at contact) are cached and computed once for both directions of their links:
  // in the city block of the benchmarks, pairs closer than 1.5 times their radii took 85 % of the
  // cubature.
  double leaf_exchange(int r, int s) const {
    const Element& R = h_.elements[r];
    const Element& S = h_.elements[s];
    if (distance(R.centre, S.centre) > kCachedSeparation * (R.radius + S.radius))
      return exchange_area(R.tri, S.tri, near_field_);
    const std::uint64_t key = (static_cast<std::uint64_t>(std::min(r, s)) << 32) | static_cast<std::uint32_t>(std::max(r, s));
    if (const auto found = exchange_.find(key); found != exchange_.end()) return found->second;
    const double value = exchange_area(R.tri, S.tri, near_field_);
    exchange_.emplace(key, value);
    return value;
  }

  // Splits the larger element of the pair (or the one that can be split) and links the children.
  void split(int r, int s, LinkBatch& out) const {
    const Element& R = h_.elements[r];
    const Element& S = h_.elements[s];
    const bool split_receiver = h_.has_children(r) && (!h_.has_children(s) || R.area * kTie >= S.area);
    if (split_receiver) {
      for (int k = 0; k < 4; ++k) refine_to_element(R.first_child + k, s, out);
    } else {
      for (int k = 0; k < 4; ++k) refine_to_element(r, S.first_child + k, out);
    }
  }

  const Hierarchy& h_;
  const Visibility& vis_;
  const ExactVisibility& shafts_;
  const PlaneVerdicts& planes_;
  const std::vector<double>& element_B_;
  const std::vector<double>& cluster_B_;
  double epsilon_;
  double unit_area_;
  AreaFactorOptions near_field_;
  ExchangeCache& exchange_;
  HiddenRoom& hidden_room_;
};

// ---- The final gather at the leaves ----
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
// (occluder_planes.h). Links found partly hidden stay as they are. With `retrace` (the scene's
// solver.exact_visibility), every link is expanded, those found hidden too (Hierarchy::hidden_links),
// and each leaf link whose visibility is not proven is evaluated exactly, with no ray: the occluders
// in the shaft between the leaf and the input triangle its source was cut from
// (ExactVisibility::shaft_occluders; none: wholly visible), and at each node of the leaf's rule the
// factor they hide (their shadow on that triangle's plane, ExactVisibility::Shadow). Links whose
// pair's box holds too many occluders are crowded (mark_crowded_links): they stay as by default (the
// partly hidden keep their rays' estimate, the hidden stay hidden, the unanimous are trusted), which
// bounds the work where many occluders stand between many patches (a city block: 133 s, against
// more than 15 minutes while every link was evaluated exactly). The raw closure error of the
// room with a floating cube (18 176 patches): 2.1 % before the gather, 1.6 % after it by default (the
// partly hidden links stay), 2e-6 with retrace, as in the room without the cube; with the leaf's own
// 16 rays in place of the exact evaluation it was 7e-4 (rays that agreed by chance), and 1.7e-4 with
// the leaf-wide rule in place of leaf_rule's pieces. Retrace costs about 1.6 × the time there.
//
// Memory and time grow with the leaf links, about 10 per expanded link in the rooms of
// docs/BENCHMARKS.md; a scene whose leaf links would exceed the budget keeps its links.
constexpr double kLeafFarField = 4;        // the rule alone beyond this many leaf radii
constexpr int kMaxCuttingPlanes = 3;       // planes that divide a leaf's rule (LeafGather::leaf_pieces)
constexpr double kRuleTolerance = 1e-5;    // of a row, from its near sources (LeafGather::gather_leaf)
constexpr int kRuleLevels = 3;             // times gather_leaf may split the pieces near them
// With exact visibility, links near whose boxes lie more than kExactOccluders occluders, in a scene of
// more than kSmallScene, keep their rays' estimate, as every link does by default
// (LeafGather::mark_crowded_links): the exact gather projects each occluder at every node of every
// leaf below, and across a city block (22 082 occluders), where such shafts hold hundreds, that was
// more than 15 minutes of work for far links whose rays are accurate enough (133 s in all with
// these limits, 31 s by default; 54 s with 32 occluders, whose results differ from these by 0.18 %
// rms, 46 s with 24). A room with up to a few dozen floating boxes is gathered exactly everywhere.
constexpr std::size_t kExactOccluders = 48;
constexpr std::size_t kSmallScene = 256;
constexpr double kRuleSplitDistance = kLeafFarField;  // pieces this near a near source are split (radii)
// The budget of leaf links: at most this many per link of the refinement or per patch, whichever is
// more, and kMaxLeafLinks in all (28 bytes each as the threads form them, copied block by block
// into the 12-byte LeafLinks: 1.3 GB at most while they are copied, 0.4 GB after, beside the
// refinement's links, which the 10⁶-patch scenes of docs/BENCHMARKS.md leave room for within 8 GiB;
// 1.8 GB while the leaf links were merged into those).
constexpr std::size_t kLeafLinksPerLink = 24;
constexpr std::size_t kLeafLinksPerPatch = 1000;
constexpr std::size_t kMaxLeafLinks = 32'000'000;
constexpr std::size_t kMaxCheckedPairs = 1 << 16;     // root pairs a link into a cluster may check

struct LeafGatherStats {
  std::size_t leaf_links = 0;  // links formed at the leaves
  std::size_t traced = 0;      // of which took the leaf's own rays (retrace)
  std::size_t exact = 0;       // of which were partly visible, with the exact visible part (retrace)
};

class LeafGather {
 public:
  // inputs: the input triangles (Element::input), which ExactVisibility holds as its occluders.
  LeafGather(Hierarchy& h, const ExactVisibility& exact, const PlaneVerdicts& planes, std::span<const Triangle> inputs,
             bool retrace, const AreaFactorOptions& near_field)
      : h_(h), exact_(exact), planes_(planes), inputs_(inputs), retrace_(retrace), near_field_(near_field) {
    const std::size_t E = h.elements.size();
    leaves_below_.assign(E, 0);
    for (std::size_t e = E; e-- > 0;) {  // children come after their parent
      const Element& el = h.elements[e];
      if (el.leaf >= 0) leaves_below_[e] = 1;
      if (el.parent >= 0) leaves_below_[el.parent] += leaves_below_[e];
    }
    cluster_parent_.assign(h.clusters.size(), -1);
    cluster_of_root_.assign(E, -1);
    for (std::size_t c = 0; c < h.clusters.size(); ++c) {
      const Cluster& C = h.clusters[c];
      if (C.root >= 0) cluster_of_root_[C.root] = static_cast<int>(c);
      else
        for (int ch : C.child) cluster_parent_[ch] = static_cast<int>(c);
    }
  }

  // Whether there are leaf links to form, at most `budget` of them; where there would be more, the
  // hidden links from and into clusters are left out first. Prepares run().
  bool fits(std::size_t budget) {
    cluster_link_expands_.assign(h_.cluster_links.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h_.cluster_links.size(), 16), [&](const auto& range) {
      for (std::size_t l = range.begin(); l != range.end(); ++l) cluster_link_expands_[l] = expands(h_.cluster_links[l]);
    });
    if (retrace_) {
      mark_crowded_links();
      for (std::size_t l = 0; l < h_.cluster_links.size(); ++l)
        if (crowded_.cluster[l]) cluster_link_expands_[l] = 0;
    }
    std::size_t n = count();
    if (n > budget && clustered_hidden_) {  // without the hidden links from and into clusters
      clustered_hidden_ = false;
      n = count();
    }
    return n > 0 && n <= budget;
  }

  // Replaces the links that expand by leaf links (see above); the others stay. The links that expand
  // are marked in place and dropped; the leaf links go to their own compact store
  // (Hierarchy::leaf_links), each block's as it is copied, so that they are held twice only a block
  // at a time.
  LeafGatherStats run(const SolveControl& control) {
    const std::size_t blocks = h_.root_block.size();
    std::vector<std::vector<Link>> out(blocks);
    tbb::combinable<LeafGatherStats> stats;
    std::atomic<bool> stop{false};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const auto& range) {
      for (std::size_t r = range.begin(); r != range.end(); ++r) {
        if (stop.load(std::memory_order_relaxed)) return;
        if (control.cancel && control.cancel->load(std::memory_order_relaxed)) {
          stop = true;
          return;
        }
        gather_block(r, out[r], stats.local());
      }
    });
    check_cancel(control);
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
        h_.leaf_links.push_back({l.source, l.coeff[0], {l.bin[0], l.bin[1]}});
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
      a.leaf_links += b.leaf_links, a.traced += b.traced, a.exact += b.exact;
      return a;
    });
  }

 private:
  // A source to expand for a leaf: an element, and what is known of its visibility from there.
  struct Entry {
    int source;
    unsigned char verdict;
  };

  // The number of leaf links the gather would form (an upper bound: some turn out 0).
  std::size_t count() const {
    std::size_t n = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, h_.elements.size(), 1024), std::size_t{0},
        [&](const auto& range, std::size_t sum) {
          for (std::size_t e = range.begin(); e != range.end(); ++e) {
            for (std::size_t l = h_.link_start[e]; l < h_.link_start[e + 1]; ++l)
              if (expanded(h_.links[l], l, static_cast<int>(e)))
                sum += leaves_below_[e] * sources_of(h_.links[l], l, static_cast<int>(e));
            if (retrace_)
              for (std::size_t l = h_.hidden_start[e]; l < h_.hidden_start[e + 1]; ++l)
                sum += leaves_below_[e] * sources_of_hidden(l).size();
          }
          return sum;
        },
        std::plus<>());
    for (std::size_t l = 0; l < h_.cluster_links.size(); ++l)
      if (cluster_link_expands_[l])
        n += cluster_leaves(h_.cluster_links[l].receiver) * roots_of(h_.cluster_links[l]);
    if (retrace_ && clustered_hidden_)
      for (std::size_t l = 0; l < h_.hidden_cluster_links.size(); ++l)
        if (!crowded_.hidden_cluster[l])
          n += cluster_leaves(h_.hidden_cluster_links[l].receiver) * roots_of(h_.hidden_cluster_links[l]);
    return n;
  }

  bool clear(int a, int b) const { return planes_.clear(a, b); }
  // The roots of a cluster of at most kExpandedClusterRoots roots (none for a larger one).
  std::span<const int> small_cluster(int c) const {
    const Cluster& C = h_.clusters[c];
    if (C.root_count > kExpandedClusterRoots) return {};
    return {h_.root_order.data() + C.first_root, static_cast<std::size_t>(C.root_count)};
  }
  // How many element sources link l at `receiver` expands to (0: it stays as it is). Element links:
  // 1; links from small clusters: their roots. With retrace, all of those; by default only where the
  // visibility is certain for every leaf below (element links: its verdict, or the occluder planes;
  // links from clusters, whose rays are cast to the cluster as a whole: the planes, root by root).
  // Link l, h_.links[index] at `receiver`; with retrace, links whose shaft is crowded (keeps_rays)
  // are treated as by default.
  std::size_t sources_of(const Link& l, std::size_t index, int receiver) const {
    const bool exact = retrace_ && !keeps_rays(index);
    if (!l.from_cluster)
      return exact || l.bin[2] == kShaftClear || l.bin[2] == kRaysUnanimous || clear(receiver, l.source) ? 1 : 0;
    const auto roots = small_cluster(l.source);
    if (roots.empty()) return 0;
    if (!exact)
      for (int r : roots)
        if (!clear(receiver, r)) return 0;
    return roots.size();
  }
  // The element sources of h_.hidden_links[index], which the refinement's rays found hidden: its
  // source, or the roots of a small cluster (links from larger ones are not kept:
  // Refiner::keeps_hidden); none where its shaft is crowded (it stays hidden, as by default).
  std::span<const int> sources_of_hidden(std::size_t index) const {
    const Link& l = h_.hidden_links[index];
    if (crowded_.hidden[index]) return {};
    if (!l.from_cluster) return {&l.source, 1};
    return clustered_hidden_ ? small_cluster(l.source) : std::span<const int>{};
  }
  // The verdict a leaf takes from element link h_.links[index]: with retrace, rays found unanimous
  // are trusted only where the shaft is crowded.
  unsigned char verdict_of(const Link& l, std::size_t index) const {
    return retrace_ && crowded_.link[index] && l.bin[2] == kRaysUnanimous ? kRaysTrusted : l.bin[2];
  }
  bool keeps_rays(std::size_t index) const { return crowded_.link[index]; }

  // With retrace, whether many occluders may stand between a link's two ends: more than
  // kExactOccluders near the box of its receiver and source, which holds its shaft
  // (ExactVisibility::occluders_near_box, constant time: a city block has 31 M links and hidden
  // links, which took 20–60 µs each to count by their shafts). A link's box holds more than its shaft
  // does (the box of a link along a street takes in the buildings beside it).
  Bounds3 box_of(int element) const { return bounds(h_.elements[element].tri); }
  bool crowded(const Bounds3& receiver, const Bounds3& source) const {
    Bounds3 box = receiver;
    box.add(source.lo), box.add(source.hi);
    return exact_.occluders_near_box(box) > kExactOccluders;
  }
  bool crowded(const Link& l) const {
    return crowded(box_of(l.receiver), l.from_cluster ? h_.clusters[l.source].box : box_of(l.source));
  }
  bool crowded(const ClusterLink& l) const {
    return crowded(h_.clusters[l.receiver].box, l.from_cluster ? h_.clusters[l.source].box : box_of(l.source));
  }

 public:
  // How many links (refinement links and links into clusters, and those found hidden) keep their
  // rays' estimate or stay hidden, their shafts crowded (with retrace; 0 otherwise).
  std::size_t crowded_links() const {
    const auto ones = [](const std::vector<char>& v) { return static_cast<std::size_t>(std::count(v.begin(), v.end(), 1)); };
    return ones(crowded_.link) + ones(crowded_.hidden) + ones(crowded_.hidden_cluster) + ones(crowded_.cluster);
  }

 private:
  // With retrace: which links are crowded, among those that the gather would evaluate exactly (the
  // others' visibility is proven). In a scene of at most kSmallScene occluders, none.
  void mark_crowded_links() {
    crowded_.link.assign(h_.links.size(), 0);
    crowded_.hidden.assign(h_.hidden_links.size(), 0);
    crowded_.hidden_cluster.assign(h_.hidden_cluster_links.size(), 0);
    crowded_.cluster.assign(h_.cluster_links.size(), 0);
    if (exact_.occluders() <= kSmallScene) return;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h_.elements.size(), 256), [&](const auto& range) {
      for (std::size_t e = range.begin(); e != range.end(); ++e) {
        for (std::size_t l = h_.link_start[e]; l < h_.link_start[e + 1]; ++l) {
          const Link& link = h_.links[l];
          if (!link.from_cluster && (link.bin[2] == kShaftClear || clear(static_cast<int>(e), link.source))) continue;
          crowded_.link[l] = crowded(link);
        }
        for (std::size_t l = h_.hidden_start[e]; l < h_.hidden_start[e + 1]; ++l) crowded_.hidden[l] = crowded(h_.hidden_links[l]);
      }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h_.cluster_links.size(), 16), [&](const auto& range) {
      for (std::size_t l = range.begin(); l != range.end(); ++l)
        crowded_.cluster[l] = cluster_link_expands_[l] && crowded(h_.cluster_links[l]);
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, h_.hidden_cluster_links.size(), 16), [&](const auto& range) {
      for (std::size_t l = range.begin(); l != range.end(); ++l) crowded_.hidden_cluster[l] = crowded(h_.hidden_cluster_links[l]);
    });
  }
  std::size_t roots_of(const ClusterLink& l) const { return l.from_cluster ? small_cluster(l.source).size() : 1; }
  bool expands(const ClusterLink& l) const {
    std::array<int, 1> element{l.source};
    const std::span<const int> sources = l.from_cluster ? small_cluster(l.source) : std::span<const int>(element);
    if (sources.empty()) return false;
    if (retrace_) return true;
    const Cluster& R = h_.clusters[l.receiver];
    if (static_cast<std::size_t>(R.root_count) * sources.size() > kMaxCheckedPairs) return false;
    for (int k = R.first_root; k < R.first_root + R.root_count; ++k)
      for (int s : sources)
        if (!clear(h_.root_order[k], s)) return false;
    return true;
  }
  std::size_t cluster_leaves(int c) const {
    const Cluster& C = h_.clusters[c];
    std::size_t n = 0;
    for (int k = C.first_root; k < C.first_root + C.root_count; ++k) n += leaves_below_[h_.root_order[k]];
    return n;
  }

  // Whether link l at `receiver` is replaced by leaf links: it expands, unless it is a leaf's own
  // element link, which is a leaf link already (the refiner gave it the exact mean over the leaf) —
  // with retrace, one whose visibility is not proven is formed again, its visibility evaluated.
  bool expanded(const Link& l, std::size_t index, int receiver) const {
    if (sources_of(l, index, receiver) == 0) return false;
    if (h_.elements[receiver].leaf < 0 || l.from_cluster) return true;
    return retrace_ && !keeps_rays(index) && l.bin[2] != kShaftClear && !clear(receiver, l.source);
  }

  // The leaf links of root block r, in element order, each leaf's sorted by source.
  void gather_block(std::size_t r, std::vector<Link>& out, LeafGatherStats& stats) const {
    const auto [first, end] = h_.root_block[r];
    // Expanded links into the clusters above this root: the same sources for all its leaves.
    std::vector<Entry> from_cluster_links;
    auto add_sources = [&](const ClusterLink& link) {
      if (!link.from_cluster) from_cluster_links.push_back({link.source, kVisibilityUnknown});
      for (int s : link.from_cluster ? small_cluster(link.source) : std::span<const int>{})
        from_cluster_links.push_back({s, kVisibilityUnknown});
    };
    for (int c = cluster_of_root_[first]; c >= 0; c = cluster_parent_[c]) {
      for (std::size_t l = h_.cluster_link_start[c]; l < h_.cluster_link_start[c + 1]; ++l)
        if (cluster_link_expands_[l]) add_sources(h_.cluster_links[l]);
      if (retrace_ && clustered_hidden_)
        for (std::size_t l = h_.hidden_cluster_start[c]; l < h_.hidden_cluster_start[c + 1]; ++l)
          if (!crowded_.hidden_cluster[l]) add_sources(h_.hidden_cluster_links[l]);
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
          if (!link.from_cluster) entries.push_back({link.source, verdict_of(link, l)});
          for (int s : link.from_cluster ? small_cluster(link.source) : std::span<const int>{})
            entries.push_back({s, kVisibilityUnknown});
        }
        if (retrace_)
          for (std::size_t l = h_.hidden_start[p]; l < h_.hidden_start[p + 1]; ++l)
            for (int s : sources_of_hidden(l)) entries.push_back({s, kVisibilityUnknown});
      }
      row.clear();
      gather_leaf(e, entries, row, stats);
      std::sort(row.begin(), row.end(), link_order<Link>);
      out.insert(out.end(), row.begin(), row.end());
    }
  }

  // The rule a leaf's links are integrated with (weights summing to 1): the degree-5 rule on the
  // leaf; with retrace, on the pieces into which the planes of the sources that cut the leaf divide
  // it. The exact visible factors at the nodes of one rule sum to 1 over a closed scene, so a row
  // closes as well as its links' exact means (exchange_area: near and cut sources) agree with the
  // rule; across a cutting plane the kernel has a kink that a leaf-wide rule misses (1.7e-4 of the
  // row at the cube room's leaves cut by the cube's faces' planes), and on the pieces there is none.
  // cut[k]: whether the plane of entries[k]'s source cuts the leaf (front_part), computed once by the caller.
  void leaf_pieces(const Element& L, const std::vector<Entry>& entries, const std::vector<char>& cut,
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
  // Whether p lies within `reach` of element S (distance_to_triangle), the sphere about S first: most
  // sources of a row are far beyond it. (A margin of 1e-9 keeps the verdict the distance's own.)
  static bool within(const Point3& p, const Element& S, double reach) {
    const double bound = reach + S.radius;
    if (length_squared(p - S.centre) > bound * bound * (1 + 1e-9)) return false;
    return distance_to_triangle(p, S.tri) <= reach * kTie;
  }
  // The degree-5 rule on each piece, weighted by its share of the leaf.
  static void leaf_rule(const Element& L, const std::vector<Triangle>& pieces, std::vector<Point3>& nodes,
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

  // Splits 1:4 the pieces nearer one of the `near` sources than kRuleSplitDistance of their radius.
  // Returns whether any was split.
  static bool split_near(std::vector<Triangle>& pieces, std::span<const Triangle* const> near) {
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
  void gather_leaf(int e, const std::vector<Entry>& entries, std::vector<Link>& row, LeafGatherStats& stats) const {
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
        kept_F.push_back((double{link.coeff[0]} + link.coeff[1] + link.coeff[2]) / 3);
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

  // The links of leaf e for the rule (nodes, weights), appended to `row` (those found hidden with
  // source kReplaced), and each one's entry to `row_entry`.
  void form_links(int e, const std::vector<Entry>& entries, const std::vector<char>& usable,
                  const std::vector<double>& near_F, std::span<const Point3> node_span, std::span<const double> weights,
                  std::vector<Link>& row, std::vector<int>& row_entry, LeafGatherStats& stats) const {
    const Element& L = h_.elements[e];
    const std::size_t size = node_span.size();
    thread_local std::vector<double> f, hidden, pending_f;
    f.resize(size), hidden.resize(size);
    // The links whose visibility is evaluated at the leaf: their index into row, and their row of
    // pending_f, the factors at the rule's nodes where the pass below computed them (else −1).
    std::vector<std::pair<int, int>> pending;
    pending_f.clear();
    for (std::size_t k = 0; k < entries.size(); ++k) {
      if (!usable[k]) continue;
      const Entry& entry = entries[k];
      const Element& S = h_.elements[entry.source];
      const bool proven = entry.verdict == kShaftClear || clear(e, entry.source);
      const bool visible =
          proven || entry.verdict == kRaysTrusted || (!retrace_ && entry.verdict == kRaysUnanimous);
      const bool near = near_F[k] >= 0;
      double F = 0;
      int f_row = -1;
      if (near) {
        F = near_F[k];
      } else if (!h_.has_children(entry.source)) {  // leaf pairs as the refiner's: A F the same both ways
        F = exchange_area(L.tri, S.tri, near_field_) / L.area;
      } else {
        point_triangle_factors(node_span, L.normal, S.tri, f);
        for (std::size_t q = 0; q < size; ++q) F += weights[q] * f[q];
        if (!visible) {  // kept for the visibility pass below, which needs the same factors
          f_row = static_cast<int>(pending_f.size() / size);
          pending_f.insert(pending_f.end(), f.begin(), f.end());
        }
      }
      if (!(F > 0)) continue;
      Link link;
      link.receiver = e;
      link.source = entry.source;
      link.coeff.fill(static_cast<float>(F));
      // Where the source is not small beside the distance, the link reads its radiosity where the
      // leaf sees it (Link::bin), as the refiner's near links do.
      if (h_.has_children(entry.source) &&
          (near || distance(L.centre, S.centre) <= kLeafFarField * (L.radius + S.radius) * kTie))
        link.bin = source_point_of(S, L);
      link.bin[2] = proven ? kShaftClear : visible ? kRaysUnanimous : kVisibilityUnknown;
      if (!visible) pending.emplace_back(static_cast<int>(row.size()), f_row);
      row.push_back(link);
      row_entry.push_back(static_cast<int>(k));
    }
    if (pending.empty()) return;
    // The visible part at the rule's nodes, exactly (no rays: rays that agree by chance were what kept
    // the rows near an occluder from closing): F(x_q -> S) less the factor the occluders hide at
    // each node, as a fraction of the link's unoccluded rule. The links are taken by the input
    // triangle their source was cut from: the occluders in the shaft between the leaf and that
    // triangle are the only ones any node can see in front of its sources (none: every one is wholly
    // visible). Their shadows on its plane from each node (one convex polygon per group: a convex
    // solid or a single triangle), united once as disjoint convex pieces, serve all its sources
    // (ExactVisibility::Shadow). (Until the twenty-third session more than eight groups were left to
    // hidden_factor per source, whose union was CGAL's: on the city block, whose carriers include
    // the ground, the gather had not left CGAL's Booleans after 15 minutes.)
    stats.traced += pending.size();
    // By input triangle, root and element: the carriers of the shadows, from the largest down.
    const auto key = [&](const std::pair<int, int>& entry) {
      const int source = row[entry.first].source;
      return std::tuple{h_.elements[source].input, h_.elements[source].root, source, entry.first};
    };
    std::sort(pending.begin(), pending.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
    thread_local std::vector<int> candidates;
    thread_local std::vector<ExactVisibility::Shadow> shadows;
    if (shadows.size() < size) shadows.resize(size);
    // The links pending[first, last), whose sources lie in `carrier`, past the occluders in the shaft
    // between the leaf and the carrier (none: wholly visible). One shadow per node serves them all.
    // Where that shaft holds more occluders than the links' own (a city block's ground, whose shaft
    // from a facade takes in most buildings), they are taken root by root, then source by source: a
    // source's shaft lies in its link's box, near which about kExactOccluders occluders lie at most.
    const auto evaluate = [&](const auto& self, const Triangle& carrier, int level, std::size_t first,
                              std::size_t last) -> void {
      const std::array<Point3, 6> hull{L.tri.v[0], L.tri.v[1], L.tri.v[2], carrier.v[0], carrier.v[1], carrier.v[2]};
      exact_.shaft_occluders(hull, candidates);
      if (candidates.empty()) {
        for (std::size_t l = first; l < last; ++l) row[pending[l].first].bin[2] = kShaftClear;
        return;
      }
      if (level < 2 && candidates.size() > kExactOccluders && last - first > 1) {
        const auto part = [&](std::size_t l) {
          const Element& S = h_.elements[row[pending[l].first].source];
          return level == 0 ? S.root : row[pending[l].first].source;
        };
        for (std::size_t g = first, next; g < last; g = next) {
          for (next = g + 1; next < last && part(next) == part(g); ++next) {
          }
          self(self, h_.elements[part(g)].tri, level + 1, g, next);
        }
        return;
      }
      for (std::size_t q = 0; q < size; ++q) exact_.shadow(node_span[q], L.normal, carrier, candidates, shadows[q]);
      for (std::size_t l = first; l < last; ++l) {
        Link& link = row[pending[l].first];
        const Triangle& source = h_.elements[link.source].tri;
        bool any = false;
        for (std::size_t q = 0; q < size; ++q) {
          // +∞: wholly in the shadow, f[q] − hidden[q] is then 0 below
          hidden[q] = shadows[q].hidden_factor(source);
          any = any || hidden[q] > 0;
        }
        double v = 1;
        if (any) {
          const int f_row = pending[l].second;
          if (f_row < 0) point_triangle_factors(node_span, L.normal, source, f);
          const double* fq = f_row < 0 ? f.data() : pending_f.data() + static_cast<std::size_t>(f_row) * size;
          double seen = 0, whole = 0;
          for (std::size_t q = 0; q < size; ++q) {
            seen += weights[q] * std::max(0.0, fq[q] - hidden[q]);
            whole += weights[q] * fq[q];
          }
          v = whole > 0 ? std::clamp(seen / whole, 0.0, 1.0) : 0.0;
          ++stats.exact;
        }
        if (v == 1) link.bin[2] = kRaysUnanimous;
        for (float& c : link.coeff) c = static_cast<float>(c * v);
        if (!(v > 0)) link.source = kReplaced;  // hidden: dropped below
      }
    };
    for (std::size_t g = 0, next; g < pending.size(); g = next) {
      const int input = h_.elements[row[pending[g].first].source].input;
      for (next = g + 1; next < pending.size() && h_.elements[row[pending[next].first].source].input == input; ++next) {
      }
      evaluate(evaluate, inputs_[input], 0, g, next);
    }
  }

  Hierarchy& h_;
  const ExactVisibility& exact_;
  const PlaneVerdicts& planes_;
  std::span<const Triangle> inputs_;
  bool retrace_;
  bool clustered_hidden_ = true;  // the hidden links from and into clusters are expanded (fits())
  AreaFactorOptions near_field_;
  std::vector<std::size_t> leaves_below_;     // per element
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

// Over the element links whose reverse link exists at the same pair of elements: the largest
// |A_r F_rs − A_s F_sr| / max(A_r F_rs, A_s F_sr), and the sum of the differences over the sum of the
// larger exchanges (each pair counted from both ends). The two directions' visible fractions come
// from different rays, so a small link partly hidden can differ by most of its value (0.94 in the lit
// sphere rooms of docs/BENCHMARKS.md, on factors of 1e-5 to 1e-3) while the sums differ by 0.9 % (the
// six-sphere room, 7 636 patches). The reverse link is looked up in the receiver-sorted CSRs of both
// stores, the refinement's links and the leaf links (each sorted by source within a receiver), so
// the check needs no memory of its own and runs on every core.
struct Reciprocity {
  double worst = 0, differ = 0, exchanged = 0;
};
Reciprocity reciprocity_error(const Hierarchy& h) {
  // A_r F_rs of element r's link from element s, in either store; −1 where r has none from s.
  auto exchange_from = [&](int r, int s) {
    const auto first = h.links.begin() + h.link_start[r];
    const auto last = h.links.begin() + h.link_start[r + 1];
    auto it = std::lower_bound(first, last, s, [](const Link& a, int x) { return a.source < x; });
    while (it != last && it->source == s && it->from_cluster) ++it;
    if (it != last && it->source == s)
      return h.elements[r].area * (double(it->coeff[0]) + it->coeff[1] + it->coeff[2]) / 3;
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
            add(r, area * (double(l.coeff[0]) + l.coeff[1] + l.coeff[2]) / 3, exchange_from(l.source, receiver));
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

// Builds the BVH over roots[first, first + count) of `order` (median split on the longest axis of the
// centroids); returns the cluster's index. Children are appended after their parent.
int build_clusters(Hierarchy& h, int first, int count) {
  const int index = static_cast<int>(h.clusters.size());
  h.clusters.emplace_back();
  FacetBounds facets;
  Bounds3 centroids;
  for (int k = first; k < first + count; ++k) {
    const Element& e = h.elements[h.root_order[k]];
    facets.add(e.tri, e.normal, e.area);
    centroids.add(e.centre);
  }
  facets.fit_cone([&](auto&& f) {
    for (int k = first; k < first + count; ++k) f(h.elements[h.root_order[k]].normal);
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
    h.clusters[index].slot = static_cast<int>(std::lower_bound(h.roots.begin(), h.roots.end(), h.root_order[first]) - h.roots.begin());
    return index;
  }
  const Vector3 extent = centroids.diagonal();
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  auto key = [&](int e) {
    const Point3& p = h.elements[e].centre;
    return axis == 0 ? p.x : axis == 1 ? p.y : p.z;
  };
  const int half = count / 2;
  std::nth_element(h.root_order.begin() + first, h.root_order.begin() + first + half,
                   h.root_order.begin() + first + count, [&](int a, int b) { return key(a) < key(b); });
  const int left = build_clusters(h, first, half);
  const int right = build_clusters(h, first + half, count - half);
  h.clusters[index].child[0] = left;
  h.clusters[index].child[1] = right;
  return index;
}

Element make_element(const Triangle& t, int surface, int parent, int root) {
  Element e;
  e.tri = t;
  e.area = t.area();
  e.normal = t.normal();
  e.centre = t.centroid();
  e.radius = std::max({distance(e.centre, t.v[0]), distance(e.centre, t.v[1]), distance(e.centre, t.v[2])});
  e.surface = surface;
  e.parent = parent;
  e.root = root;
  return e;
}


}  // namespace

Solution solve_hierarchical(const Scene& scene, const SolveControl& control) {
  const auto t_start = Clock::now();
  Solution sol;
  sol.grid = scene.grid;
  sol.warnings = scene.warnings;
  const std::size_t W = scene.grid.size();
  auto report = [&](double f) { if (control.progress) control.progress(f); };
  auto cancelled = [&] { return control.cancel && control.cancel->load(std::memory_order_relaxed); };

  // ---- meshing: roots (pre-split input triangles), element trees down to the patch size, clusters ----
  auto t0 = Clock::now();
  const double max_area = scene.meshing.max_patch_area_m2.value_or(default_max_patch_area(scene));
  sol.stats.max_patch_area_m2 = max_area;
  Hierarchy h;
  std::vector<Triangle> occluders;  // the roots, for Embree
  {
    double total_area = 0;
    for (const Surface& s : scene.surfaces)
      for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) total_area += s.mesh.triangle(t).area();
    check_patch_count(total_area / max_area, true, kMaxHierarchicalPatches, control);
  }
  const double root_area = max_area * std::pow(4.0, kRootLevels);
  std::vector<char> occluder_two_sided;  // per root, from its input triangle (Surface::two_sided)
  // Element trees: breadth-first 1:4 splits until the leaves are no larger than max_area, and further
  // (down to max_area/16) where meshing.refine_direct marked a leaf (`split_further`, by its exact
  // vertices; a rebuild makes the same triangles); a parent precedes its children, and every tree
  // is one contiguous block.
  std::set<std::array<double, 9>> split_further;
  auto vertex_key = [](const Triangle& t) {
    return std::array<double, 9>{t.v[0].x, t.v[0].y, t.v[0].z, t.v[1].x, t.v[1].y, t.v[1].z, t.v[2].x, t.v[2].y, t.v[2].z};
  };
  auto build_trees = [&] {
    h = Hierarchy{};
    occluders.clear(), occluder_two_sided.clear();
    for (std::size_t s = 0, first_input = 0; s < scene.surfaces.size(); first_input += scene.surfaces[s++].mesh.triangles.size()) {
      const Surface& surface = scene.surfaces[s];
      const SubdividedMesh subdivided = subdivide_to_max_area_with_parents(surface.mesh, root_area);
      const TriangleMesh& pieces = subdivided.mesh;
      for (std::size_t t = 0; t < pieces.triangles.size(); ++t) {
        const Triangle tri = pieces.triangle(t);
        if (!(tri.area() > 0)) continue;
        const int root = static_cast<int>(h.elements.size());
        h.elements.push_back(make_element(tri, static_cast<int>(s), -1, root));
        h.roots.push_back(root);
        occluders.push_back(tri);
        const std::size_t parent = static_cast<std::size_t>(subdivided.parent[t]);
        h.elements[root].input = static_cast<int>(first_input + parent);
        occluder_two_sided.push_back(parent < surface.two_sided.size() ? surface.two_sided[parent] : 0);
        for (int e = root; e < static_cast<int>(h.elements.size()); ++e) {
          const Element& el = h.elements[e];
          if (el.area <= max_area &&
              !(el.area / 4 >= max_area / 16 && split_further.count(vertex_key(el.tri)) > 0))
            continue;
          const auto children = split4(el.tri);
          h.elements[e].first_child = static_cast<int>(h.elements.size());
          for (const Triangle& c : children) {
            h.elements.push_back(make_element(c, static_cast<int>(s), e, root));
            h.elements.back().input = h.elements[root].input;
          }
        }
        h.root_block.emplace_back(root, static_cast<int>(h.elements.size()));
      }
    }
    h.leaves.clear();
    for (std::size_t e = 0; e < h.elements.size(); ++e)
      if (h.elements[e].first_child < 0) {
        h.elements[e].leaf = static_cast<int>(h.leaves.size());
        h.leaves.push_back(static_cast<int>(e));
      }
  };
  auto leaf_patches = [&] {
    std::vector<Patch> patches(h.leaves.size());
    for (std::size_t i = 0; i < h.leaves.size(); ++i) {
      const Element& e = h.elements[h.leaves[i]];
      patches[i] = Patch{e.surface, e.tri, e.area, e.normal};
    }
    return patches;
  };
  build_trees();
  // meshing.refine_direct, as in the dense solver (patch_refinement.h): leaves where the direct light
  // jumps between neighbours, or next to a probe point, are split, in up to two rounds; a round that
  // would pass the patch limit is not taken.
  if (scene.meshing.refine_direct && has_direct_light(scene)) {
    const std::size_t base = h.leaves.size();
    const Visibility roots_vis(occluders);
    for (int round = 0; round < 2; ++round) {
      const std::vector<Patch> patches = leaf_patches();
      std::vector<char> marked =
          where_varies(patches, direct_irradiance_totals(scene, patches, roots_vis, control), kDirectRatio);
      if (round == 0) mark_near_probes(patches, scene.probes, marked);
      std::size_t added = 0;
      for (std::size_t i = 0; i < patches.size(); ++i)
        added += marked[i] && patches[i].area_m2 / 4 >= max_area / 16 ? 3 : 0;
      if (added == 0 || patches.size() + added > patch_limit(kMaxHierarchicalPatches, control)) break;
      for (std::size_t i = 0; i < patches.size(); ++i)
        if (marked[i]) split_further.insert(vertex_key(patches[i].triangle));
      build_trees();
    }
    sol.stats.direct_refinement_patches = h.leaves.size() - base;
  }
  const std::size_t N = h.leaves.size();
  check_patch_count(static_cast<double>(N), false, kMaxHierarchicalPatches, control);
  sol.patches = leaf_patches();
  sol.stats.patches = N;
  sol.stats.time_meshing_s = seconds_since(t0);
  check_cancel(control);
  report(0.05);

  // ---- visibility scene (the roots: the same surfaces, fewer triangles than the leaves) ----
  t0 = Clock::now();
  const Visibility vis(occluders, Visibility::Estimates::fast);  // link rays in the fast BVH
  // Shafts and exact visible parts on the input triangles: fewer and larger occluders than the roots
  // (the cube room's 24 against its 1 000 roots), so each query visits fewer of them.
  std::vector<Triangle> input_triangles;
  for (const Surface& s : scene.surfaces)
    for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) input_triangles.push_back(s.mesh.triangle(t));
  const OutwardSolids solids = outward_solids(scene.surfaces);
  const ExactVisibility shafts(input_triangles, solids.solid, solids.convex, solids.cap);
  std::vector<Vector3> occluder_normals(occluders.size());
  for (std::size_t k = 0; k < occluders.size(); ++k) occluder_normals[k] = h.elements[h.roots[k]].normal;
  const OccluderPlanes occluder_planes(occluders);
  sol.stats.time_visibility_s = seconds_since(t0);

  // ---- sources and direct light (solver/pipeline/direct_light.h): lobed emitters per root ----
  std::vector<LobedPiece> lobed;
  for (int root : h.roots) {
    const Surface& s = scene.surfaces[h.elements[root].surface];
    if (s.emission && s.emission->lobe_exponent != 1.0) lobed.push_back({h.elements[root].tri, h.elements[root].surface});
  }
  DirectLight light = direct_light(scene, sol.patches, lobed, vis, control);
  std::vector<double>& rho = light.rho;
  std::vector<double>& M = light.M;
  const std::vector<double>& E_direct = light.E_direct;
  const std::vector<double>& E_point = light.E_known_flux;
  const auto& sources = light.sources;
  check_cancel(control);
  report(0.1);

  const bool need_links = light.needs_transport();
  // ---- hemisphere probe per leaf, then the clusters over the roots that are not wholly enclosed ----
  // Leaves inside closed solids (3: every probe ray met a back face, e.g. the floor under a crate)
  // exchange no light with the scene, as in the dense solver, which links no such pair. They are
  // found before any link: rays between elements can slip through a solid's seams (the fast BVH),
  // and a 6 mm room with a crate, ρ = 0.999, had 245 leaf links between the floor under the crate
  // and the walls (a furnace 0.34 % low), and clusters holding such roots sent their radiosity on.
  t0 = Clock::now();
  std::vector<Hemisphere> closed(N, Hemisphere::Open);  // per leaf (solver/pipeline/hemisphere.h)
  const HemisphereProbe hemisphere(vis, occluder_normals, occluder_two_sided);
  // Without any occluder plane (a convex room) no leaf sees a back face, and no input triangle hides
  // another from it: its exact factors to the input triangles (the degree-5 rule over the leaf) add up
  // to the share of its hemisphere they cover, and the hemisphere is closed where that is 1 (to 1e-3,
  // as the dense solver reads its exact rows). No probe ray is then traced (4 M in the issue-4 room).
  const bool closure_from_factors = occluder_planes.usable() && occluder_planes.planes() == 0 &&
                                    static_cast<double>(N) * static_cast<double>(input_triangles.size()) <= kMaxClosureFactors;
  if (need_links && N > 0) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
      const int rays = static_cast<int>(std::clamp<std::size_t>(4000000 / std::max<std::size_t>(N, 1), 64, 1024));
      const TriangleRule rule = triangle_rule_degree5();
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const Element& L = h.elements[h.leaves[i]];
        if (!closure_from_factors) {
          closed[i] = hemisphere.classify(L.tri, L.normal, i, rays);
          continue;
        }
        double covered = 0;
        for (int q = 0; q < rule.size; ++q) {
          const auto& w = rule.nodes[q];
          const Point3 p = barycentric(L.tri.v[0], L.tri.v[1], L.tri.v[2], w[0], w[1], w[2]);
          for (const Triangle& t : input_triangles) covered += rule.weights[q] * point_triangle_factor(p, L.normal, t);
        }
        closed[i] = hemisphere_from_coverage(covered);
      }
    });
    if (std::find(closed.begin(), closed.end(), Hemisphere::Enclosed) != closed.end()) {
      h.enclosed.assign(h.elements.size(), 0);
      for (std::size_t e = h.elements.size(); e-- > 0;) {  // children come after their parent
        const Element& el = h.elements[e];
        if (el.first_child < 0) {
          h.enclosed[e] = closed[static_cast<std::size_t>(el.leaf)] == Hemisphere::Enclosed;
        } else {
          h.enclosed[e] = 1;
          for (int k = 0; k < 4; ++k) h.enclosed[e] = h.enclosed[e] && h.enclosed[el.first_child + k];
        }
      }
    }
  }
  for (int root : h.roots)
    if (!h.is_enclosed(root)) h.root_order.push_back(root);
  if (!h.root_order.empty()) build_clusters(h, 0, static_cast<int>(h.root_order.size()));
  for (int root : h.root_order) h.ordered_roots.push_back({h.elements[root].tri, h.elements[root].normal});
  table_cluster_samples(h);
  const double time_probe = seconds_since(t0);
  const PlaneVerdicts planes(h, occluder_planes);  // once the clusters are built

  // Leaves inside closed solids take no part in the exchange: they neither emit nor reflect (ρ and M
  // 0, so B = 0), and what the links of their parent elements push down onto them is absorbed there.
  // Solved for, a bright one would set the scale of the relative residual and leave the scene
  // unconverged; and while they kept their ρ, they reflected that pushed-down light back into the
  // scene from inside a solid (a panel 1 mm below a ceiling: 3.7e-5 of its power, against an energy
  // certificate otherwise exact to 1e-13).
  light.leave_out_enclosed(closed, W);

  // ---- spectral systems: one per distinct (reflectance column, right-hand side) ----
  // Key: ρ over materials, emission over surfaces and the spectrum of every direct source at λ; the
  // right-hand side b = M + ρ E_direct is a function of exactly these.
  std::vector<RadiositySystem> systems;
  std::vector<std::size_t> wavelength_system(W);
  {
    std::map<std::vector<double>, std::size_t> system_of;
    for (std::size_t w = 0; w < W; ++w) {
      std::vector<double> key;
      for (const Material& m : scene.materials) key.push_back(m.reflectance[w]);
      for (const Surface& s : scene.surfaces) key.push_back(s.emission ? s.emission->exitance_W_m2_nm[w] : 0.0);
      for (const auto& source : sources) key.push_back(source->spectrum()[w]);
      auto [it, inserted] = system_of.try_emplace(key, systems.size());
      if (inserted) {
        RadiositySystem& sys = systems.emplace_back();
        sys.rho.resize(N);
        sys.b.resize(N);
        for (std::size_t i = 0; i < N; ++i) {
          sys.rho[i] = rho[i * W + w];
          sys.b[i] = M[i * W + w] + rho[i * W + w] * E_direct[i * W + w];
        }
        sys.x = sys.b;
      }
      wavelength_system[w] = it->second;
    }
  }
  const std::size_t K = systems.size();
  // Per leaf: whether it emits at some wavelength, and whether it sends anything at all (emits or
  // reflects); one that does not is black and keeps B = 0 whatever it receives.
  std::vector<char> emits(N, 0), shoots(N, 0);
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t w = 0; w < W; ++w) {
      emits[i] = emits[i] || M[i * W + w] > 0;
      shoots[i] = shoots[i] || emits[i] || rho[i * W + w] != 0;
    }

  // Radiosity for the oracle: per leaf the largest |B| over the systems, pulled up (area mean per
  // element, max per cluster).
  auto oracle_values = [&](const std::vector<double>& leaf_B, std::vector<double>& element_B,
                           std::vector<double>& cluster_B) {
    Hierarchy::Values v;
    h.pull({leaf_B.data()}, v);
    element_B = v.B;
    std::vector<double> root_max(h.elements.size(), 0.0);  // the largest leaf of each root's tree
    for (std::size_t i = 0; i < N; ++i) {
      double& m = root_max[h.elements[h.leaves[i]].root];
      m = std::max(m, leaf_B[i]);
    }
    cluster_B.assign(h.clusters.size(), 0.0);
    for (std::size_t c = h.clusters.size(); c-- > 0;) {
      const Cluster& cl = h.clusters[c];
      cluster_B[c] = cl.root >= 0 ? root_max[cl.root] : std::max(cluster_B[cl.child[0]], cluster_B[cl.child[1]]);
    }
  };
  auto largest_B = [&](bool with_ambient) {
    std::vector<double> leaf_B(N, 0.0);
    double power = 0, area = 0, rho_mean = 0;
    for (std::size_t i = 0; i < N; ++i) {
      if (closed[i] == Hemisphere::Enclosed) continue;  // enclosed: neither part of the scene's power nor of its area
      for (const auto& sys : systems) leaf_B[i] = std::max(leaf_B[i], std::abs(sys.x[i]));
      power += sol.patches[i].area_m2 * leaf_B[i];
      area += sol.patches[i].area_m2;
      double r = 0;
      for (const auto& sys : systems) r = std::max(r, std::abs(sys.rho[i]));
      rho_mean += sol.patches[i].area_m2 * std::min(r, 0.95);
    }
    if (with_ambient && area > 0) {
      // First round: unlit reflectors will receive about the mean interreflected irradiance.
      rho_mean /= area;
      const double ambient = power / area / (1 - rho_mean);
      for (std::size_t i = 0; i < N; ++i) {
        double r = 0;
        for (const auto& sys : systems) r = std::max(r, std::abs(sys.rho[i]));
        leaf_B[i] = std::max(leaf_B[i], r * ambient);
      }
    }
    // Black leaves as sources, where closed rows are known: the balance scales closed rows to 1 by
    // their sums, which include the links from black leaves. With their B of 0 the oracle left those
    // links as coarse as a cluster: in a black room lit by its floor the row sums missed 1 by 20 %,
    // and the floor's part moved with them. They are refined as if they sent the scene's mean
    // radiosity, from the first round on: pairs that the first round drops as within the budget
    // (B = 0 passes any test) are not found again, and their share was missing from the rows of that
    // room after the final gather (closure 9.7e-3 instead of 1.9e-6).
    if (area > 0 && std::find(closed.begin(), closed.end(), Hemisphere::Closed) != closed.end())
      for (std::size_t i = 0; i < N; ++i)
        if (!shoots[i]) leaf_B[i] = power / area;
    for (std::size_t i = 0; i < N; ++i)
      if (closed[i] == Hemisphere::Enclosed) leaf_B[i] = 0;
    return std::pair{leaf_B, power};
  };

  double total_area = 0;  // of the leaves that are not enclosed
  for (std::size_t i = 0; i < N; ++i) total_area += closed[i] == Hemisphere::Enclosed ? 0 : sol.patches[i].area_m2;
  h.leaf_scale.assign(N, 1.0);
  h.source_scale.assign(N, 1.0);
  double time_links = time_probe, time_solve = 0;
  if (need_links && N > 0) {
    const double accuracy = scene.solver.accuracy;
    auto gather_all = [&](const std::vector<const double*>& V, const std::vector<double*>& FV) {
      for (std::size_t start = 0; start < V.size(); start += kMaxBatch) {
        const std::size_t end = std::min(V.size(), start + kMaxBatch);
        h.apply({V.begin() + start, V.begin() + end}, {FV.begin() + start, FV.begin() + end});
      }
    };
    ExchangeCache exchange;
    // ---- the final gather at the leaves (LeafGather) ----
    // Once the links are final: in the last round before its balance, or after the round that found
    // nothing to change. Returns whether it formed leaf links (the links then need a balance).
    bool gathered = false;
    auto gather_at_leaves = [&] {
      gathered = true;
      // The refinement's final element links that the occluder planes cleared (no rays).
      sol.stats.links_clear = static_cast<std::uint64_t>(std::count_if(h.links.begin(), h.links.end(), [&](const Link& l) {
        return !l.from_cluster && l.source >= 0 && planes.clear(l.receiver, l.source);
      }));
      const bool retrace = scene.solver.exact_visibility;
      AreaFactorOptions near_field;  // as the refiner's
      near_field.rel_tolerance = std::max(near_field.rel_tolerance, 0.1 * accuracy);
      near_field.abs_tolerance = std::max(near_field.abs_tolerance, 1e-3 * accuracy);
      LeafGather gather(h, shafts, planes, input_triangles, retrace, near_field);
      const std::size_t budget =
          std::min(std::max(kLeafLinksPerLink * h.links.size(), kLeafLinksPerPatch * N), kMaxLeafLinks);
      if (!scene.solver.leaf_gather || (retrace && !h.hidden_complete) || !gather.fits(budget)) return false;
      const std::size_t refined_links = h.links.size();
      const LeafGatherStats g = gather.run(control);
      sol.stats.leaf_links = g.leaf_links;
      sol.stats.leaf_links_traced = g.traced;
      sol.stats.leaf_links_exact = g.exact;
      sol.stats.crowded_links = gather.crowded_links();
      h.index_links();
      // Where the leaf links are a small share of the links, the last balance's scales and its stop
      // are the start, as between refinement rounds; where the gather changed most rows (a room
      // whose rows closed to 2 % before and to 2e-6 after) they would be a worse start than 1.
      if (g.leaf_links > refined_links / 10) {
        h.leaf_scale.assign(N, 1.0);
        h.source_scale.assign(N, 1.0);
        h.balance_omega = 1;
        h.balance_stalled_at = 0;
        h.balance_stalled_aim = 0;
      }
      return true;
    };
    // Hidden links are kept for the final gather's retrace only (solver.exact_visibility).
    HiddenRoom hidden_room;
    if (scene.solver.exact_visibility) {
      hidden_room.elements = static_cast<std::int64_t>(kMaxLeafLinks);
      hidden_room.clustered = static_cast<std::int64_t>(kMaxLeafLinks / 4);
    }
    double rho_max = 0;  // of the leaves that are not enclosed, over the systems
    for (const auto& sys : systems)
      for (std::size_t i = 0; i < N; ++i)
        if (closed[i] != Hemisphere::Enclosed) rho_max = std::max(rho_max, std::abs(sys.rho[i]));
    const double final_target = balance_target(kFinalBalance, rho_max);
    const double oracle_target = balance_target(kOracleBalance, rho_max);
    bool final_balance = false;  // whether the last balance aimed at final_target
    for (int round = 0; round < kRefineRounds; ++round) {
      // ---- links (form factors) ----
      auto t1 = Clock::now();
      const auto oracle = largest_B(round == 0);
      const std::vector<double>& leaf_B = oracle.first;
      const double power = oracle.second;
      std::vector<double> element_B, cluster_B;
      oracle_values(leaf_B, element_B, cluster_B);
      const double epsilon = accuracy * power / total_area / kPowerShare;
      const Refiner refiner(h, vis, shafts, planes, element_B, cluster_B, epsilon, kUnitPatches * max_area, accuracy,
                            exchange, hidden_room);
      tbb::enumerable_thread_specific<LinkBatch> found;
      bool changed = round == 0;
      if (round == 0) {
        // Receivers against the top cluster, refined as pairs of clusters. A receiving cluster cannot
        // link with the top cluster, which holds it, so the receivers are split breadth-first first,
        // until there are enough pairs to share among the threads.
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
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs.size(), 1), [&](const auto& range) {
          auto& out = found.local();
          for (std::size_t p = range.begin(); p != range.end(); ++p) {
            if (cancelled()) return;
            refiner.refine_pair(pairs[p].first, pairs[p].second, true, out);
            refiner.resolve(out);
          }
        });
      } else {
        tbb::combinable<bool> any_change([] { return false; });
        auto recheck_all = [&](auto& links, std::size_t grain) {
          tbb::parallel_for(tbb::blocked_range<std::size_t>(0, links.size(), grain), [&](const auto& range) {
            auto& out = found.local();
            bool& c = any_change.local();
            for (std::size_t l = range.begin(); l != range.end(); ++l)
              if (refiner.recheck(links[l], out)) {
                links[l].source = kReplaced;
                c = true;
              }
            refiner.resolve(out);
          });
        };
        recheck_all(h.links, 64);
        recheck_all(h.cluster_links, 16);
        changed = any_change.combine([](bool a, bool b) { return a || b; });
      }
      check_cancel(control);
      for (const LinkBatch& batch : found) sol.stats.link_rays += batch.rays;
      if (!changed) {
        time_links += seconds_since(t1);
        break;
      }
      // Round 0 found every link; later rounds only the replacements of those their rechecks refined.
      constexpr double kHeadroom = 0.5;
      if (round == 0) {
        h.links = take_sorted(found, &LinkBatch::links, kHeadroom);
        h.cluster_links = take_sorted(found, &LinkBatch::cluster_links, kHeadroom);
      } else {
        merge_rechecked(h.links, take_sorted(found, &LinkBatch::links));
        merge_rechecked(h.cluster_links, take_sorted(found, &LinkBatch::cluster_links));
      }
      if (hidden_room.elements.load() <= 0) {  // none kept, or past kMaxLeafLinks: the gather will not retrace
        h.hidden_complete = false;
        release(h.hidden_links);
        release(h.hidden_cluster_links);
        for (LinkBatch& batch : found) batch.hidden = {}, batch.hidden_cluster = {};
      } else {
        merge_rechecked(h.hidden_links, take_sorted(found, &LinkBatch::hidden));
        merge_rechecked(h.hidden_cluster_links, take_sorted(found, &LinkBatch::hidden_cluster));
      }
      h.index_links();
      if (round == kRefineRounds - 1) gather_at_leaves();

      // ---- closure: row sums of the links; closed leaves are scaled to 1 ----
      // What each leaf sends: the radiosity of the last solve; before the first, the oracle's
      // estimate (M + ρ E_direct, and ρ times the mean interreflected irradiance), since a room lit
      // by an emitting panel has M + ρ E_direct = 0 on every reflector, whose columns would then be
      // left free in the first round, and the later rounds' balances would start without them.
      std::vector<double> sends(N, 0.0);
      if (round == 0) {
        sends = leaf_B;
      } else {
        for (const auto& sys : systems)
          for (std::size_t i = 0; i < N; ++i) sends[i] = std::max(sends[i], std::abs(sys.x[i]));
      }
      final_balance = round == kRefineRounds - 1;
      const Balanced balanced = balance(h, closed, sends, emits, sol.patches,
                                        final_balance ? final_target : oracle_target, final_balance, control);
      sol.stats.max_closure_error = balanced.raw_error;
      sol.stats.closure_residual = balanced.residual;
      time_links += seconds_since(t1);
      report(0.1 + 0.2 * (round + 1));

      // ---- solve ----
      t1 = Clock::now();
      for (auto& sys : systems) sys.iterations = 0;
      solve_radiosity_systems(N, gather_all, systems, scene.solver.tolerance, scene.solver.max_iterations, cancelled);
      time_solve += seconds_since(t1);
    }
    // The loop ended on a round that changed no link: the gather comes after that round's balance and
    // solve, which are taken again; so are they without a gather, since that balance aimed only at
    // the oracle's target.
    auto t1 = Clock::now();
    if ((!gathered && gather_at_leaves()) || !final_balance) {
      std::vector<double> sends(N, 0.0);
      for (const auto& sys : systems)
        for (std::size_t i = 0; i < N; ++i) sends[i] = std::max(sends[i], std::abs(sys.x[i]));
      const Balanced balanced = balance(h, closed, sends, emits, sol.patches, final_target, true, control);
      sol.stats.max_closure_error = balanced.raw_error;
      sol.stats.closure_residual = balanced.residual;
      time_links += seconds_since(t1);
      t1 = Clock::now();
      for (auto& sys : systems) sys.iterations = 0;
      solve_radiosity_systems(N, gather_all, systems, scene.solver.tolerance, scene.solver.max_iterations, cancelled);
      time_solve += seconds_since(t1);
    } else {
      time_links += seconds_since(t1);
    }
    report_hemisphere_findings(sol, scene, closed);
    const Reciprocity reciprocity = reciprocity_error(h);
    sol.stats.max_reciprocity_error = reciprocity.worst;
    sol.stats.mean_reciprocity_error = reciprocity.exchanged > 0 ? reciprocity.differ / reciprocity.exchanged : 0;
  }
  sol.stats.links = h.links.size() + h.leaf_links.size() + h.cluster_links.size();
  for (const auto& sys : systems) {
    sol.stats.iterations = std::max(sol.stats.iterations, sys.iterations);
    sol.stats.residual = std::max(sol.stats.residual, sys.residual);
  }
  sol.stats.spectral_systems_solved = need_links ? static_cast<int>(K) : 0;

  // ---- outputs: B per leaf, H = F B + E_direct ----
  auto t1 = Clock::now();
  const bool keep_sign = scene.mode == SpectrumMode::Rgb;
  std::vector<std::vector<double>> gathered(K, std::vector<double>(N, 0.0));
  if (need_links && N > 0)
    for (std::size_t start = 0; start < K; start += kMaxBatch) {
      std::vector<const double*> V;
      std::vector<double*> FV;
      for (std::size_t k = start; k < std::min(K, start + kMaxBatch); ++k) {
        V.push_back(systems[k].x.data());
        FV.push_back(gathered[k].data());
      }
      h.apply(V, FV);
    }
  sol.radiosity.assign(N * W, 0.0);
  sol.irradiance.assign(N * W, 0.0);
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t w = 0; w < W; ++w) {
      const auto& sys = systems[wavelength_system[w]];
      const double x = !need_links ? sys.b[i] : sys.x[i];
      sol.radiosity[i * W + w] = keep_sign ? x : std::max(0.0, x);
      sol.irradiance[i * W + w] = gathered[wavelength_system[w]][i] + E_direct[i * W + w];
    }
  time_solve += seconds_since(t1);
  sol.stats.time_form_factors_s = time_links;
  sol.stats.time_solve_s = time_solve;
  report(0.9);

  // ---- probes: direct sources, then a traversal of the hierarchy from the top cluster per point ----
  t0 = Clock::now();
  sol.probes.resize(scene.probes.size());
  if (!scene.probes.empty()) {
    // Per-node radiosity of every system, and the subtree's spread of B (largest over the systems),
    // which decides how deep a probe must look into an element.
    std::vector<const double*> X(K);
    for (std::size_t k = 0; k < K; ++k) X[k] = need_links ? systems[k].x.data() : systems[k].b.data();
    Hierarchy::Values values;
    h.pull(X, values);
    std::vector<double> lo(h.elements.size(), 1e300), hi(h.elements.size(), -1e300), cluster_B(h.clusters.size(), 0);
    for (std::size_t e = h.elements.size(); e-- > 0;) {
      const Element& el = h.elements[e];
      if (el.leaf >= 0)
        for (std::size_t k = 0; k < K; ++k) lo[e] = std::min(lo[e], X[k][el.leaf]), hi[e] = std::max(hi[e], X[k][el.leaf]);
      if (el.parent >= 0) lo[el.parent] = std::min(lo[el.parent], lo[e]), hi[el.parent] = std::max(hi[el.parent], hi[e]);
    }
    for (std::size_t c = h.clusters.size(); c-- > 0;) {
      const Cluster& cl = h.clusters[c];
      cluster_B[c] = cl.root >= 0 ? std::max(std::abs(lo[cl.root]), std::abs(hi[cl.root]))
                                  : std::max(cluster_B[cl.child[0]], cluster_B[cl.child[1]]);
    }
    double power = 0, area = 0;
    for (std::size_t i = 0; i < N; ++i) {
      if (closed[i] == Hemisphere::Enclosed) continue;  // enclosed: no part of what a probe can see
      power += sol.patches[i].area_m2 * std::max(std::abs(lo[h.leaves[i]]), std::abs(hi[h.leaves[i]]));
      area += sol.patches[i].area_m2;
    }
    // A probe link may err by accuracy/10 of the scene's mean radiosity... per unit of projected solid angle.
    const double e_tolerance = area > 0 ? 0.1 * scene.solver.accuracy * power / area : 0;
    for (std::size_t k = 0; k < scene.probes.size(); ++k) {
      const Probe& probe = scene.probes[k];
      const Vector3 n = probe.normal;
      std::vector<double> E(probe.points.size() * K, 0.0);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probe.points.size(), 1), [&](const auto& range) {
        std::vector<int> stack;
        for (std::size_t q = range.begin(); q != range.end(); ++q) {
          const Point3& p = probe.points[q];
          const Point3 from = vis.lift(p, n);
          const OccluderPlanes::Sides p_sides = planes.sides(p);
          double* e = &E[q * K];
          // Wholly visible where the occluder planes say so; otherwise rays to the element's samples,
          // 16 before the first vote (as for links: four unanimous rays to a coarse element miss small
          // occluders).
          auto element_visibility = [&](int node, const Element& S) {
            if (planes.point_sees(p_sides, node)) return 1.0;
            return weighted_visible_fraction(
                vis, [&](int j) { return std::pair{from, vis.lift(visibility_sample(S.tri, j), S.normal)}; },
                [&](const Point3&, const Point3& qq) { return link_weight(p, n, qq, S.normal); }, 16);
          };
          stack.assign(h.clusters.empty() ? 0 : 1, -1);  // −1 − c: cluster c; ≥ 0: element
          while (!stack.empty()) {
            const int node = stack.back();
            stack.pop_back();
            if (node >= 0) {
              const Element& S = h.elements[node];
              const double f = point_triangle_factor(p, n, S.tri);
              if (f <= 0) continue;
              const bool splittable = S.first_child >= 0;
              // An element is taken whole where its radiosity varies little (f × spread within the
              // tolerance) and it is wholly visible or hidden: the visible part of a partly hidden
              // element need not have its mean radiosity (a probe under a floating cube read 3 %
              // high when partly hidden elements were taken whole).
              double v = -1;
              if (splittable && f * (hi[node] - lo[node]) <= e_tolerance) {
                v = element_visibility(node, S);
                if (v > 0 && v < 1 && f * std::max(std::abs(lo[node]), std::abs(hi[node])) > e_tolerance) v = -1;
              } else if (!splittable) {
                v = element_visibility(node, S);
              }
              if (v < 0) {
                for (int c = 0; c < 4; ++c) stack.push_back(S.first_child + c);
                continue;
              }
              for (std::size_t kk = 0; kk < K; ++kk) e[kk] += f * v * values.B[node * K + kk];
              continue;
            }
            const int c = -1 - node;
            const Cluster& C = h.clusters[c];
            if (C.root >= 0) {
              stack.push_back(C.root);
              continue;
            }
            if (!box_in_front(C.box, p, n, 0)) continue;
            const Vector3 d_vec = p - C.centre;
            const double d = length(d_vec), d_min = d - C.radius;
            bool accepted = false;
            if (d >= 2 * C.radius * kTie && d_min > 0) {
              const Vector3 w = d_vec / d;
              const ClusterView view = cluster_view(h, c, w);
              if (cluster_B[c] * (view.projected + view.uncertainty) / (kPi * d_min * d_min) <= e_tolerance) {
                accepted = true;
                const double cos_p = std::max(0.0, -dot(n, w));
                if (cos_p > 0 && view.projected > 0) {
                  Vector3 source_normal;
                  const double v = planes.point_sees_cluster(p_sides, c) ? 1.0 : weighted_visible_fraction(
                      vis,
                      [&](int j) {
                        const Hierarchy::ClusterSample S = cluster_sample(h, C, j);
                        source_normal = S.normal;
                        return std::pair{from, vis.lift(S.point, S.normal)};
                      },
                      [&](const Point3&, const Point3& qq) { return link_weight(p, n, qq, source_normal); });
                  for (int a = 0; a < 3; ++a) {
                    const double coeff = view.weight[a] * cos_p * v / (kPi * d * d);
                    for (std::size_t kk = 0; kk < K; ++kk) e[kk] += coeff * values.Phi[(c * 6 + view.bin[a]) * K + kk];
                  }
                }
              }
            }
            if (!accepted) {
              stack.push_back(-1 - C.child[0]);
              stack.push_back(-1 - C.child[1]);
            }
          }
        }
      });
      auto& out = sol.probes[k].irradiance;
      out.assign(probe.points.size() * W, 0.0);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probe.points.size(), 4), [&](const auto& range) {
        for (std::size_t q = range.begin(); q != range.end(); ++q) {
          double* o = &out[q * W];
          for (std::size_t w = 0; w < W; ++w) o[w] = E[q * K + wavelength_system[w]];
          for (const auto& source : sources) {
            const double g = source->point_factor(probe.points[q], n, vis);
            if (g == 0) continue;
            const auto& S = source->spectrum();
            for (std::size_t w = 0; w < W; ++w) o[w] += g * S[w];
          }
        }
      });
      check_cancel(control);
    }
  }
  sol.stats.time_probes_s = seconds_since(t0);

  // ---- energy balance: emitted = absorbed + escaped (W, integrated over the grid) ----
  // The power that leaf j shoots and no leaf gathers is A_j B_j (1 − its column sum of F'): the
  // balance is then exact for the operator solved, whatever the links' errors.
  std::vector<double> received(N, 0.0);
  if (need_links && N > 0) {
    std::vector<double> weighted(N);
    for (std::size_t i = 0; i < N; ++i) weighted[i] = sol.patches[i].area_m2 * h.leaf_scale[i];
    h.apply_transpose(weighted.data(), received.data());
    for (std::size_t j = 0; j < N; ++j) received[j] *= h.source_scale[j] / sol.patches[j].area_m2;
  }
  std::vector<double> leak(N);
  for (std::size_t i = 0; i < N; ++i) leak[i] = 1 - received[i];
  account_energy(scene.grid, sources, sol.patches, rho, M, E_direct, E_point, sol.radiosity, sol.irradiance, leak,
                 sol.stats);
  sol.stats.rays = vis.rays_traced();
  leave_out_enclosed(sol, closed);
  sol.stats.time_total_s = seconds_since(t_start);
  report(1.0);
  return sol;
}

}  // namespace lambert
