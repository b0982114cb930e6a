// The clusters of the hierarchical method (Smits, Arvo & Greenberg 1994, "A clustering algorithm for
// radiosity in complex environments"): a bounding-volume hierarchy over the roots of the element
// forest, so that a group of far triangles sends (and receives) through one link and neither N²
// factors nor N² pairs are ever formed.
//
// A cluster sends its radiant intensity I(ω) = Σ_j B_j A_j (n_j·ω)⁺ / π from its radiosity-weighted
// projected areas on the six axis directions, Φ_k = Σ_j B_j A_j (n_j·e_k)⁺: where every normal faces
// ω, exactly as ω · Σ_j B_j A_j n_j (Φ_2a − Φ_2a+1 per axis); elsewhere as Σ_k (ω·e_k)⁺ Φ_k scaled
// so that the radiosity the refinement knows (the oracle's, oracle.h) sends exactly what it sends
// along ω (found through the clusters' normal cones: the bins alone overstate it up to √3 times
// wherever normals are not in ω's octant). A link takes the kernel from where that radiosity's power
// comes, over an element receiver as its mean. See ClusterView.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "solver/facet_bounds.h"
#include "solver/hierarchical/elements.h"

namespace lambert::hierarchical {

// Its FacetBounds (box, bins, area vector, normal cone) cover its roots.
struct Cluster : FacetBounds {
  Point3 centre;
  double radius = 0;
  int child[2] = {-1, -1};   // clusters; both −1 for a BVH leaf
  int root = -1;             // the root element of a BVH leaf
  int first_root = 0, root_count = 0;  // range in ClusterTree::root_order
  int samples = -1;          // its first kTabledClusterSamples in ClusterTree::cluster_samples, or −1
  int slot = -1;             // a BVH leaf: its root's index in ElementForest::roots
};

inline constexpr int kTabledClusterSamples = 16;  // see ClusterTree::cluster_samples

struct ClusterTree {
  std::vector<Cluster> clusters;  // clusters[0] is the top; children come after their parent
  std::vector<int> root_order;    // roots in BVH order (cluster ranges index into it)
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
};

// The tree over the roots of `forest` that are not wholly enclosed (median split on the longest
// axis of the centroids), with its visibility samples.
ClusterTree build_cluster_tree(const ElementForest& forest);

// Visibility sample k (< kMaxVisibilitySamples) of a cluster: a stratified sample point of one of its
// roots, the roots drawn spread over its BVH range.
ClusterTree::ClusterSample cluster_sample(const ClusterTree& tree, const Cluster& C, int k);

// What a link reads of its source cluster's six bins Φ_k (k = 2a for +e_a, 2a + 1 for −e_a), through
// three bins: 0–5 a bin, kAxisBin + a the difference Φ_2a − Φ_2a+1 = Σ_j B_j A_j (n_j · e_a), the
// a-th component of the radiosity-weighted area vector.
inline constexpr unsigned char kAxisBin = 6;
// The value of `bin` among the bins phi[k K + s] of system s (K systems interleaved).
inline double bin_value(const double* phi, unsigned char bin, std::size_t K, std::size_t s) {
  if (bin < kAxisBin) return phi[bin * K + s];
  const int a = bin - kAxisBin;
  return phi[2 * a * K + s] - phi[(2 * a + 1) * K + s];
}
// phi_bar[k] += value × ∂bin_value/∂Φ_k (one system): the adjoint of bin_value.
inline void scatter_bin(double* phi_bar, unsigned char bin, double value) {
  if (bin < kAxisBin) {
    phi_bar[bin] += value;
    return;
  }
  const int a = bin - kAxisBin;
  phi_bar[2 * a] += value;
  phi_bar[2 * a + 1] -= value;
}

// What the clusters' roots send under a given radiosity B ≥ 0 per root (the oracle's, oracle.h):
// Σ B A (n·e_k)⁺ and Σ B A n, as FacetBounds::projected and area_vector are without B.
struct SentFacets {
  Bins projected{};
  Vector3 area_vector{};
};

// How a link to cluster c from direction w (unit, from the cluster) reads its projected power Φ.
// Where every normal of the cluster faces w (its normal cone lies within π/2 of w), Σ_j B_j A_j (n_j ·
// w)⁺ = w · Σ_j B_j A_j n_j exactly whatever the radiosity: the three axis bins, weighted by w's
// components. (Like the bins, it is read along w alone; what the other directions of the pair
// change is the oracle's `turning` term.) Otherwise the three bins facing w, weighted so that a
// cluster of uniform radiosity B sends B × `projected` (the area it shows, within ± `uncertainty`)
// rather than the bins' upper bound, or with `sent` (per cluster) so that the radiosity it was taken
// from sends what it sends along w (to the bounds' uncertainty). Uniform weights err where the
// radiosity varies over the normals: a faceted sphere lit from above, B ∝ n_z, read 30° off its axis
// 13 % low, and the lit sphere room's panel gathered its links from clusters whose normals straddle
// its direction 15–35 % short, the spheres' bright tops read as if as dim as their sides. The bins
// are exact for any radiosity where every normal is ± an axis. The refiner links no cluster read
// the third way (reads_any_radiosity); the probes' gather does, with `sent` from the solved radiosity.
struct ClusterView {
  std::array<unsigned char, 3> bin{};
  std::array<double, 3> weight{};
  double projected = 0;  // 0: every root faces away from w
  double uncertainty = 0;
  double turning = 0;  // turning_area over the pair's directions (facet_bounds.h)
};
ClusterView cluster_view(const ClusterTree& tree, int c, const Vector3& w, double sin_delta,
                         const std::vector<SentFacets>* sent = nullptr);

// Whether the bins that cluster_view reads of C along w give what C sends along w whatever its
// radiosity: its normals are ± axes, or all face w. Otherwise the weights are fitted to one radiosity
// (`sent`), and a link that keeps them errs where the radiosity takes another shape, with one sign:
// among 48 reflecting spheres, links from whole spheres to the room read 1.7 % low once the
// interreflections had lit their sides and bottoms, and the closed room lost 0.43 % of its power
// (docs/BENCHMARKS.md, "Many reflecting objects").
inline bool reads_any_radiosity(const Cluster& C, const Vector3& w) {
  return C.axis_normals || (C.cone_sin < 1 && dot(C.cone_axis, w) > C.cone_sin);
}

// The weight of the view's bin a (taken along w) along a direction u near w: an axis bin's is u_a
// (exact: linear in the direction); a bin's, |u_a| times the view's scale for w, and 0 where u_a is on
// the bin's other side (that side is another bin, which the view does not read).
double weight_along(const ClusterView& view, int a, const Vector3& w, const Vector3& u);

// The factors by which an element receiver R (unit normal n_R) gathers the bins `view` reads of a
// cluster sending from `centre`, seen along w: the mean over R, by the degree-5 rule, of each bin's
// weight_along the node's own direction w_x times cos θ_x / (π d_x²). The kernel at R's centre alone
// misses its curvature over R, which for a far receiver off the cluster's axis is convex and
// one-signed: links from sphere tops to the lit sphere room's ceiling read 0.2–0.4 % low at
// scale/d = 0.1 and 2.7–5.3 % at 0.4, their means over R within 0.5 % (docs/BENCHMARKS.md).
std::array<double, 3> receiver_mean_factors(const ClusterView& view, const Vector3& w, const Point3& centre,
                                            const Triangle& R, const Vector3& n_R);

// The factors by which the roots of a receiving cluster centred at `to` gather the bins `view` reads
// of a cluster sending from `from` (seen along w from its centre): the bins' weights along the
// direction from `from` over π d², d from `from` to `to`; `toward` is the unit direction from `to` to
// `from`, along which every receiver takes its n · toward (ClusterLink).
std::array<double, 3> receivers_factors(const ClusterView& view, const Vector3& w, const Point3& to, const Point3& from,
                                        Vector3& toward);

// The bounds of the BF oracle (refiner.h) on a cluster's one-point estimate, per unit of the cluster's
// radiosity, toward a receiver across distance d between bounding spheres whose radii sum to `scale`
// (d_min = d − scale, directions within δ = asin(scale/d) of the line w between the centres):
//   - one_point_error: the transfer is at most projected/(π d_min²) (cos ≤ 1, distance ≥ d_min); the
//     estimate errs by about the pair's relative size scale/d of it, the projected area by its
//     uncertainty, and by what the area shown may gain or lose as the direction turns within δ
//     (turning: read along w alone, a panel seen at grazing incidence shows the receiver's other
//     points far more than it shows w);
//   - unseen_transfer: where the line between the centres misses (the cluster shows nothing along w,
//     or the receiver faces away from it: `receiver_faces` false), the estimate is 0, yet a cluster
//     seen edge-on from its centre's direction may face the receiver along the others. Along those,
//     the cosine on the side that misses is at most sin δ, so what passes is at most this.
double one_point_error(const ClusterView& view, double scale, double d, double d_min);
// The bound on an element source's vector estimate (Refiner::refine_pair): receivers within r_R of the
// point c where the source's vector factor V was taken, each of whose horizons leaves the whole source
// in front, receive n · V(x) exactly, and |n · (V(x) − V(c))| ≤ ∫₀¹ |DV(c + t (x − c))| r_R dt.
// V(x) = (1/π) ∫_S (n_S · z) (−z) / |z|⁴ dA with z = x − y; the integrand's derivative has operator
// norm √((4a² + 1 + √(8a² + 1)) / 2) / |z|³ ≤ 2 / |z|³ (a = n_S · ẑ; its singular values in the basis ẑ,
// the part of n_S across ẑ), and |z| ≥ D − t r_R where D bounds the distance from c to the source
// from below. The integral gives A/π (1/(D − r_R)² − 1/D²) per unit radiosity.
double vector_estimate_error(double source_area, double receivers_radius, double centre_to_source);
// What a link into clusters errs by where a receiver's horizon may cut the source (Refiner::refine_pair):
// V gives a receiver n · u along every direction u to the source, negative behind its horizon where
// the exact kernel has (n · u)⁺ = 0. With the receivers' normals within α + θ of the direction to the
// source and the directions within δ of it, n · u ≥ −sin(α + θ + δ − π/2) there, so the part behind
// the horizon adds at most sin of that excess times the area the source shows, over π d_min².
double horizon_cut_error(double sin_excess, double shown, double d_min);
double unseen_transfer(const Cluster& C, const ClusterView& view, bool receiver_faces, double sin_delta, double d_min);

// Whether some corner of `box` lies more than `tol` in front of the plane through o with normal n.
bool box_in_front(const Bounds3& box, const Point3& o, const Vector3& n, double tol);

}  // namespace lambert::hierarchical
