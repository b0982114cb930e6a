// Exact partial visibility of an area source from a point (issue 4, item 5).
//
// Where rays find a source partly occluded, the factor of the part that is visible is computed
// exactly: every occluding triangle between the point and the source's plane is projected centrally
// from the point onto that plane, the projections are subtracted from the source polygon — for a few
// shadows by inclusion–exclusion over their convex intersections, for more by peeling the source
// shadow by shadow into disjoint convex pieces (mesh/convex2d.h) — and the point-to-polygon contour
// integral is summed over what is left. So E = π L F(visible part) holds to round-off, for any number
// and shape of occluders (the CIE 171 case 5.7 geometry, REFERENCES V9). CGAL's exact 2D Booleans
// (mesh/polygon_boolean.h) do the same subtraction with exact constructions; the tests hold the
// double-precision ways to them (set_inclusion_exclusion_limit).
// Where only one triangle or one convex solid occludes, the hidden factor is summed over its front
// faces' parts in the cone over the source, with no union (hidden_factor, Shadow).
// Rays remain the fast path for wholly visible and wholly hidden sources; this is for the rest.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "mesh/convex2d.h"
#include "mesh/geometry.h"
#include "mesh/polygon_boolean.h"

namespace lambert {

// Where a solid of ExactVisibility is open: the plane that closes it (unit outward normal, a point on
// it). See OutwardSolids::cap (solver/solids.h).
struct SolidCap {
  bool open = false;
  Vector3 normal;
  Point3 point;
};

class ExactVisibility {
 public:
  // Occluders: the scene's triangles in metres (the input triangles, not the patches: fewer and larger
  // occluders make fewer, simpler projections). Indexed by a bounding-volume hierarchy.
  // `solid` (empty, or one per occluder): the index of the closed solid whose faces face out that the
  // occluder bounds, or −1 (OutwardSolids, solver/solids.h); `convex` (per solid): whether that solid
  // is convex. From a point outside the solid a face seen from behind hides nothing that the solid's
  // front faces do not, so it is not projected: a box seen from a point casts the shadows of its two
  // to six front triangles, not of all twelve. The front faces of a convex solid are seen in
  // directions that do not overlap, so the factor they hide is the sum of theirs, with no Boolean
  // operation (visible_factor). `caps` (per solid, or empty: all closed): an open solid counts as one
  // only for a point and a source on or behind its cap's plane, the point not inside it; otherwise its
  // faces are occluders like any other.
  explicit ExactVisibility(std::span<const Triangle> occluders, std::span<const int> solid = {},
                           std::span<const char> convex = {}, std::span<const SolidCap> caps = {});
  ~ExactVisibility();
  ExactVisibility(const ExactVisibility&) = delete;
  ExactVisibility& operator=(const ExactVisibility&) = delete;

  // Point-to-polygon factor F(dA_p -> visible part of `source`), for a receiver at p with unit normal
  // n; equal to point_triangle_factor(p, n, source) when nothing occludes. Occluders lying in the
  // source's plane or in p's horizon plane (the surfaces the source and p sit on) do not occlude.
  // Where what occludes is one triangle, or front faces of one convex solid, their parts in the cone
  // from p over the source are disjoint in direction and the hidden factor is their factors' sum
  // (no projection, no Boolean); otherwise visible_region's.
  double visible_factor(const Point3& p, const Vector3& n, const Triangle& source) const;
  // The factor of the part of `source` that the occluders hide from p: point_triangle_factor minus
  // visible_factor (a wholly hidden source's may exceed the former by round-off), 0 where nothing
  // occludes; the unoccluded factor is not evaluated unless shadows must be united.
  double hidden_factor(const Point3& p, const Vector3& n, const Triangle& source) const;
  // The same, looking only at `candidates` (occluder indices, from shaft_occluders of a hull that
  // holds p and the source): source by source, the way Shadow::hidden_factor is checked against
  // (the gather itself uses Shadow).
  double hidden_factor(const Point3& p, const Vector3& n, const Triangle& source, std::span<const int> candidates) const;

  // The part of `source` that p sees, kept as loops in the source's plane, so that the visible factor
  // of any convex part of the source (a patch cut from it) follows by clipping the loops to the part:
  // one Boolean evaluation serves every patch of an input triangle seen from one point.
  class VisibleRegion {
   public:
    // F(dA_p -> visible part of `part`), `part` a triangle inside the source (its plane).
    double factor_of(const Triangle& part) const;
    // The loops themselves, for integrals over the visible part other than the factor (a sky's
    // luminance): point (u, v) of a loop is origin() + e1() u + e2() v. Each loop is convex (but with
    // Beyond::kCgalBooleans) and signed by its orientation, counter-clockwise about the source's normal
    // adding, clockwise subtracting; all lie in the part of the source in front of p's horizon.
    const std::vector<Loop2d>& loops() const { return loops_; }
    const Point3& origin() const { return origin_; }
    const Vector3& e1() const { return e1_; }
    const Vector3& e2() const { return e2_; }

   private:
    friend class ExactVisibility;
    Point3 p_, origin_;
    Vector3 n_, e1_, e2_;
    std::vector<Loop2d> loops_;  // in (e1_, e2_) about origin_: outer boundaries CCW, holes CW
  };
  VisibleRegion visible_region(const Point3& p, const Vector3& n, const Triangle& source) const;

  // What occludes the plane of a triangle (`carrier`: an input triangle, say) from p, cast onto that
  // plane, so that one projection serves every source inside the carrier (the patches cut from it)
  // seen from p. What occludes, among `candidates` (occluder indices from shaft_occluders of a hull
  // holding p and the carrier), falls into groups: the front faces of one convex solid, or one
  // triangle. Each group's shadow is one convex polygon, the projection of its parts inside the cone
  // from p over the carrier; where several groups hide something, their shadows (which may overlap)
  // are united once, as disjoint convex pieces (mesh/convex2d.h), and each source sums its parts of
  // them.
  class Shadow {
   public:
    // hidden_factor(p, n, part) for a triangle `part` inside the carrier; +∞ where one piece of the
    // shadow covers all of it (the factor hidden is then point_triangle_factor(p, n, part), which the
    // caller usually has: no contour sum is spent on it).
    double hidden_factor(const Triangle& part) const;
    // How many disjoint convex pieces the shadow is made of (0: nothing hides any of the carrier).
    std::size_t pieces() const { return pieces_.size(); }

   private:
    friend class ExactVisibility;
    struct Bounds {
      Point2d lo, hi;
    };
    Point3 origin_;               // the carrier's first corner, in metres
    Vector3 n_, e1_, e2_;         // the receiver's normal; the carrier's plane's axes
    Vector3 to_origin_;           // origin_ − p
    // The union of the groups' shadows as disjoint convex polygons, counter-clockwise in (e1_, e2_)
    // about origin_, and their bounding boxes.
    ConvexPieces pieces_;
    std::vector<Bounds> bounds_;
  };
  // Forms `out` (its storage reused) for p, normal n and the carrier.
  void shadow(const Point3& p, const Vector3& n, const Triangle& carrier, std::span<const int> candidates,
              Shadow& out) const;

  // Whether no occluder reaches into the interior of the convex hull of `points` (at most 16): for
  // the vertices of two elements, the shaft that holds every segment between them, so a clear shaft
  // means the pair sees each other wholly, with no ray traced (Haines & Wallace's shaft culling, with
  // exact clipping instead of boxes). Occluders that only touch the hull's boundary (the elements' own
  // surfaces, a wall meeting them at an edge) do not count; a margin of 1e-9 of the hull's size is
  // allowed for rounding. Conservative: an occluder in the hull that blocks no segment also counts.
  bool shaft_is_clear(std::span<const Point3> points) const;
  // The occluders that shaft_is_clear would find in the hull (their indices, in `out`): every one that
  // can hide any part of one element from any point of the other.
  void shaft_occluders(std::span<const Point3> points, std::vector<int>& out) const;
  // About how many occluders lie near `box`, in constant time: those whose centroids lie in the cells
  // of a grid over the scene (64 cells along its longest axis) that the box meets. At least the
  // occluders whose centroids lie in the box, at most those within one cell of it: an estimate of
  // what a shaft inside the box may hold, for budgets, not a bound.
  std::size_t occluders_near_box(const Bounds3& box) const;
  // The number of occluders (input triangles of some area).
  std::size_t occluders() const;

  // Number of visible_factor evaluations that found something occluding, and of those that needed
  // the shadows' union (visible_region: several occluders whose directions may overlap).
  std::uint64_t occluded_evaluations() const { return occluded_.load(std::memory_order_relaxed); }
  std::uint64_t boolean_evaluations() const { return booleans_.load(std::memory_order_relaxed); }

  // How visible_region unites the shadows of several occluders: up to `shadows` of them by
  // inclusion–exclusion over their convex intersections (2^k terms at most), beyond that by peeling
  // the source shadow by shadow into disjoint convex pieces (mesh/convex2d.h), both in doubles; or,
  // beyond it, by CGAL's exact Boolean difference (mesh/polygon_boolean.h). All give the same factor
  // to round-off (tests/exact_visibility_test.cpp).
  enum class Beyond { kConvexPieces, kCgalBooleans };
  void set_inclusion_exclusion_limit(int shadows, Beyond beyond = Beyond::kConvexPieces) {
    inclusion_exclusion_limit_ = shadows;
    beyond_ = beyond;
  }

 private:
  VisibleRegion visible_region(const Point3& p, const Vector3& n, const Triangle& source, bool count) const;
  // hidden_factor among `candidates` (null: the tree's); where the shadows had to be united, also the
  // visible factor in `*visible` (if given).
  double hidden_among(const Point3& p, const Vector3& n, const Triangle& source, const std::span<const int>* candidates,
                      double* visible) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  mutable std::atomic<std::uint64_t> occluded_{0}, booleans_{0};
  int inclusion_exclusion_limit_ = 8;
  Beyond beyond_ = Beyond::kConvexPieces;
};

}  // namespace lambert
