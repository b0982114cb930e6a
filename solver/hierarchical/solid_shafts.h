// Pairs of elements and clusters that see each other wholly because nothing but their own convex
// solids comes near the segments between them: their links need no rays.
//
// Why a pair's own convex solids may be set aside: a convex solid lies behind the plane of each of
// its faces, so a segment from a point of one face to a point in front of that face's plane stays in
// front of it and never enters the solid. The kernel weighs only such segments (cos θ > 0 at both
// ends), so the solid a receiving facet bounds cannot hide any of a source from it, nor can the
// source's own. A cluster whose roots all bound one convex solid sets that solid aside in the same
// way, root by root.
//
// Every other occluder must keep out of the pair's shaft. The shaft lies in the hull of the two ends'
// bounding spheres, which is the union over t ∈ [0, 1] of the balls centred at (1 − t) c_a + t c_b
// with radius (1 − t) r_a + t r_b (a convex combination of two balls is a ball). An occluder is a
// solid, or the triangles of no solid that lie in one plane and are joined across their edges (a
// room's wall, a floor cut around what stands on it). It is out of the shaft if its bounding sphere
// misses that hull; a plane of triangles also if every corner of the pair lies on one side of it
// (the room's walls for every pair inside it); a convex solid of at most kFacePlanes face planes
// also if the pair lies in front of one of them (a building across the street). The test is
// conservative: a pair it does not clear takes rays.
//
// The occluder planes (occluder_planes.h) are exact, but hold at most 128 planes. A faceted sphere
// gives every facet a plane of its own, so in the sphere rooms they cleared no pair. There, 79.5 % of
// the links into clusters had no occluder in their shaft but their own spheres (docs/BENCHMARKS.md,
// "The cluster tree's splits").
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "mesh/geometry.h"
#include "solver/hierarchical/clusters.h"
#include "solver/hierarchical/elements.h"

namespace lambert::hierarchical {

// The hull of two balls (c_a, r_a) and (c_b, r_b). outside(x) is how far x lies outside it (negative
// inside): the least over t ∈ [0, 1] of |x − c(t)| − r(t), c(t) = (1 − t) c_a + t c_b,
// r(t) = (1 − t) r_a + t r_b. That is convex in t (a norm of an affine map less an affine one), so its
// minimum on [0, 1] is its stationary point, clamped. With the axis u = (c_b − c_a)/L, x's coordinates
// along it (a) and across it (y), and k = −(r_b − r_a)/L, the stationary point has x − c(t) making
// cos = k with u: a − tL = k y / √(1 − k²). Where |k| ≥ 1 one ball holds the other: the least is at
// an end.
class BallHull {
 public:
  BallHull(const Point3& ca, double ra, const Point3& cb, double rb)
      : ca_(ca), ra_(ra), dr_(rb - ra), axis_(cb - ca), L_(length(axis_)) {
    const double k = -dr_ / L_;
    ends_only_ = !(L_ > 0) || !(std::abs(k) < 1);
    if (!ends_only_) slope_ = k / std::sqrt(1 - k * k);
  }
  double outside(const Point3& x) const {
    auto at = [&](double t) { return distance(x, ca_ + axis_ * t) - (ra_ + t * dr_); };
    if (ends_only_) return std::min(at(0), at(1));
    const Vector3 to = x - ca_;
    const double along = dot(to, axis_) / L_;
    const double across = length(cross(to, axis_)) / L_;  // not √(|to|² − along²), which cancels near the axis
    return at(std::clamp((along - slope_ * across) / L_, 0.0, 1.0));
  }

 private:
  Point3 ca_;
  double ra_, dr_;
  Vector3 axis_;
  double L_, slope_ = 0;
  bool ends_only_;
};

class SolidShafts {
 public:
  // inputs: the scene's input triangles (Element::input); solid, convex: OutwardSolids' (solids.h),
  // per input triangle and per solid. A solid open at a cap is convex with the cap as a face, so its
  // faces lie on its hull's boundary as a closed one's do.
  SolidShafts(const ElementForest& forest, const ClusterTree& tree, std::span<const Triangle> inputs,
              std::span<const int> solid, std::span<const char> convex);

  // Whether elements a and b see each other wholly.
  bool clear(int a, int b) const { return used_ && clear(element_end(a), element_end(b)); }
  // The same for cluster c and an element, or another cluster where `other_is_cluster`.
  bool clear_cluster(int c, int other, bool other_is_cluster) const {
    return used_ && clear(cluster_end(c), other_is_cluster ? cluster_end(other) : element_end(other));
  }

 private:
  // One end of a pair: its bounding sphere, the convex solid it lies on (−1: none, or not one), and
  // the corners that hold it (an element's three, a cluster box's eight).
  struct End {
    Point3 centre;
    double radius = 0;
    int solid = -1;
    std::array<Point3, 8> corners;
    int count = 0;
  };
  End element_end(int e) const;
  End cluster_end(int c) const;
  bool clear(const End& a, const End& b) const;

  struct Plane {
    Vector3 normal;  // unit (zero for a degenerate triangle's, which hides nothing)
    Point3 on;
  };
  // An occluder: a solid, or triangles of no solid that lie in one plane and are joined across edges.
  struct Blocker {
    Point3 centre;
    double radius = 0;
    int solid = -1;
    bool convex = false;
    Plane plane;  // the triangles' plane (solid −1)
    int first_face = 0, face_count = 0;  // a convex solid's face planes in face_planes_ (none past kFacePlanes)
  };
  static constexpr std::size_t kFacePlanes = 16;
  // Past this many occluders the test is not made (clear() is false). It pays where a few objects of
  // many facets each fill the scene (a sphere room's 55 occluders: half the link rays spared); in a
  // city block's 2 209 buildings every pair's hull meets several of them, the test cleared 7 % of the
  // link rays and doubled the solve's time (docs/BENCHMARKS.md).
  static constexpr std::size_t kMaxBlockers = 256;
  // Nor past this many triangles of no solid (a CAD export of 10⁶ loose triangles): joining them
  // into planes is a map over their edges, O(n log n), which the scenes it serves do not need.
  static constexpr std::size_t kMaxLooseTriangles = 65'536;
  // Whether every corner of both ends lies on one side of the plane (in front of it if `front_only`).
  bool one_side(const Plane& plane, const End& a, const End& b, bool front_only) const;
  // Whether a blocker whose sphere meets the pair's hull, not the pair's own, may hide part of one end
  // from the other.
  bool may_hide(const Blocker& blocker, const End& a, const End& b) const;
  void build(int node, int first, int count);

  struct Node {
    Bounds3 box;
    int first = 0, count = 0;  // leaf: blockers_[first, first + count)
    int right = -1;            // inner node: the left child is the next node
  };
  const ElementForest& forest_;
  const ClusterTree& tree_;
  std::vector<Blocker> blockers_;
  std::vector<Plane> face_planes_;
  std::vector<Node> nodes_;
  std::vector<int> element_solid_;  // per element: the convex solid its input triangle bounds, or −1
  std::vector<int> cluster_solid_;  // per cluster: the convex solid all its roots bound, or −1
  double tolerance_ = 0;            // 1e-9 of the scene's size
  bool used_ = false;               // at most kMaxBlockers occluders: the test is made
};

}  // namespace lambert::hierarchical
