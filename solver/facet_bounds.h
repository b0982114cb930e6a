// What a set of oriented triangles (the roots under one cluster of the hierarchical solver) can show
// in a direction, Σ A (n·w)⁺, and bounds of it that the refinement trusts to drop or keep a pair
// without looking at the triangles one by one. Split out of hierarchical.cpp so that each bound can
// be tested against the sum over the triangles themselves (tests/facet_bounds_test.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "mesh/geometry.h"

namespace lambert {

// Projected areas per axis direction: +x, −x, +y, −y, +z, −z.
using Bins = std::array<double, 6>;

inline Bins projected_bins(const Vector3& n, double area) {
  Bins b{};
  const double c[3] = {n.x, n.y, n.z};
  for (int a = 0; a < 3; ++a) (c[a] > 0 ? b[2 * a] : b[2 * a + 1]) = area * std::abs(c[a]);
  return b;
}

struct FacetBounds {
  Bounds3 box;               // of the triangles' corners
  Bins projected{};          // Σ A (n·e_k)⁺
  Vector3 area_vector{};     // Σ A n
  double area = 0;           // Σ A
  // A cone about `cone_axis` that holds every normal, of half-angle θ < 90° with sin θ = cone_sin
  // (2 where the normals are not within a hemisphere's cone, or nearly cancel: a closed object).
  Vector3 cone_axis{};
  double cone_sin = 2;
  bool axis_normals = true;  // every normal is ± an axis: the bins are exact (false for an empty set)

  // Adds a triangle (its unit normal n and area given, as the caller has them).
  void add(const Triangle& t, const Vector3& n, double a) {
    for (const Point3& p : t.v) box.add(p);
    const Bins b = projected_bins(n, a);
    for (int q = 0; q < 6; ++q) projected[q] += b[q];
    area_vector = area_vector + a * n;
    area += a;
    constexpr double kOffAxis = 1e-9;  // the bins then err by less than this, relative
    axis_normals = axis_normals && (std::abs(n.x) > kOffAxis) + (std::abs(n.y) > kOffAxis) + (std::abs(n.z) > kOffAxis) == 1;
  }

  // The normal cone about the mean normal, once every triangle is in: `each_normal(f)` calls f on
  // every unit normal again.
  template <class EachNormal>
  void fit_cone(EachNormal&& each_normal) {
    if (box.empty()) axis_normals = false;
    if (!(length(area_vector) > 1e-6 * area)) return;
    cone_axis = normalize(area_vector);
    double min_cos = 1;
    each_normal([&](const Vector3& n) { min_cos = std::min(min_cos, dot(n, cone_axis)); });
    if (min_cos > 0) cone_sin = std::sqrt(std::max(0.0, 1 - min_cos * min_cos));
  }
};

// Σ_a |w_a| bins[bin_a] over the bins facing direction w (unit).
inline double binned(const Bins& bins, const Vector3& w) {
  return std::abs(w.x) * bins[w.x > 0 ? 0 : 1] + std::abs(w.y) * bins[w.y > 0 ? 2 : 3] +
         std::abs(w.z) * bins[w.z > 0 ? 4 : 5];
}
// An upper bound of the area the set shows in direction w (unit), Σ A (n·w)⁺, exact only where every
// normal lies in w's octant or on an axis. A faceted sphere seen along a diagonal shows 1.7 times its
// disk in the bins.
inline double binned_area(const FacetBounds& F, const Vector3& w) { return binned(F.projected, w); }

// How much the area the set shows may change as the direction turns from w to any direction within δ
// of it (sin δ given), beyond the relative change sin δ × binned_area(w) that a one-point estimate
// already counts. Along axis a the cosine |u_a| moves by up to sin δ: the bin facing w may gain or
// lose bin × sin δ of which the relative term holds bin × |w_a| × sin δ; where the direction may cross
// the axis plane (|w_a| < sin δ), either side's bin may show, so the larger counts whole. A panel
// facing down, read from a direction just above its plane, shows nothing along w, yet a receiver
// below part of it sees it.
inline double turning_area(const FacetBounds& F, const Vector3& w, double sin_delta) {
  const double wa[3] = {w.x, w.y, w.z};
  double sum = 0;
  for (int a = 0; a < 3; ++a) {
    const double toward = F.projected[wa[a] > 0 ? 2 * a : 2 * a + 1];
    sum += std::abs(wa[a]) < sin_delta ? std::max(F.projected[2 * a], F.projected[2 * a + 1])
                                       : toward * (1 - std::abs(wa[a]));
  }
  return sum * sin_delta;
}
// The same for one flat piece of area A whose unit normal makes cos_w with w: A (n·u) moves by up to
// A sin δ, of which the relative term holds A |cos_w| sin δ.
inline double turning_area(double area, double cos_w, double sin_delta) {
  return area * sin_delta * (std::abs(cos_w) < sin_delta ? 1 : 1 - std::abs(cos_w));
}

// The largest area the set shows in any direction, Σ A (n·u)⁺ ≤ Σ_a |u_a| max(bin +a, bin −a), at
// most the norm of those three maxima (Cauchy–Schwarz, |u| = 1).
inline double max_projected(const FacetBounds& F) {
  double sum = 0;
  for (int a = 0; a < 3; ++a) {
    const double most = std::max(F.projected[2 * a], F.projected[2 * a + 1]);
    sum += most * most;
  }
  return std::sqrt(sum);
}

// Whether some triangle of the set may face some point of `receiver` (a box), which lies along
// directions within δ of w (unit, from the set; sin δ given): false only where none can. Two
// bounding spheres whose radii sum to `scale`, centres d apart, see each other along directions
// within δ = asin(scale/d) of the line between the centres, and the area shown along that line alone
// says nothing of them: a floor seen edge-on from its centre shows no area along it, yet a receiver
// above part of the floor sees that part.
inline bool may_face(const FacetBounds& F, const Vector3& w, double sin_delta, const Bounds3& receiver) {
  if (F.box.empty()) return false;
  if (F.axis_normals) {
    // A triangle facing +e_a faces some direction of the cone iff w_a > −sin δ, and some point of
    // the receiver only if the receiver reaches above the set's lowest point along e_a.
    const double wa[3] = {w.x, w.y, w.z};
    const double lo[3] = {F.box.lo.x, F.box.lo.y, F.box.lo.z}, hi[3] = {F.box.hi.x, F.box.hi.y, F.box.hi.z};
    const double r_lo[3] = {receiver.lo.x, receiver.lo.y, receiver.lo.z};
    const double r_hi[3] = {receiver.hi.x, receiver.hi.y, receiver.hi.z};
    for (int a = 0; a < 3; ++a)
      if ((F.projected[2 * a] > 0 && wa[a] > -sin_delta && r_hi[a] > lo[a]) ||
          (F.projected[2 * a + 1] > 0 && -wa[a] > -sin_delta && r_lo[a] < hi[a]))
        return true;
    return false;
  }
  if (F.cone_sin > 1) return true;
  constexpr double kHalfPi = 1.5707963267948966;
  const double alpha = std::acos(std::clamp(dot(F.cone_axis, w), -1.0, 1.0));
  return alpha - std::asin(F.cone_sin) - std::asin(std::min(1.0, sin_delta)) < kHalfPi;
}

}  // namespace lambert
