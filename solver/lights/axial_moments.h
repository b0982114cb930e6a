// The double-axis moment of the directions from a point to a polygon (Arvo 1995, "Applications of
// irradiance tensors to the simulation of non-Lambertian phenomena", SIGGRAPH 95, §4–5):
//
//   τ^{n,1}(A; a, b) = ∫_A (a·u)^n (b·u) dσ(u)
//
// over the spherical polygon A that the polygon subtends, for whole n ≥ 0. A Phong-lobed emitter's
// irradiance at a point is R (n+1)/(2π) τ^{n−1,1}(A; −normal, receiver normal)
// (solver/lights/phong_emitter.cpp). It follows from the surface divergence theorem on the sphere:
// for V = (a·u)^{n−1} ∇(a·u), ∇·V = (n−1)(a·u)^{n−2} − (n+1)(a·u)^n, and for V = (a·u)^n ∇(b·u),
// ∇·V = n (a·b)(a·u)^{n−1} − (n+2)(a·u)^n (b·u), so that with the axial moments τ^n = ∫_A (a·u)^n dσ
//
//   (n+1) τ^n      = (n−1) τ^{n−2} + Σ_i (a·m_i) C_i^{n−1}
//   (n+2) τ^{n,1}  = n (a·b) τ^{n−1} + Σ_i (b·m_i) C_i^n
//
// with m_i the unit normal of edge i's great circle (u_i × u_{i+1}), C_i^k = ∫_{edge i} (a·u)^k ds
// (itself the recurrence of ∫ cos^k t dt along the arc) and τ^0 the solid angle. τ^{0,1} is
// Lambert's contour integral. Cost O(n × edges) without allocation.
//
// Stability: the recurrences run upwards with coefficients in [0, 1], so the absolute error stays
// near the rounding of τ^0 (the solid angle); a polygon far off the axis, where τ^n ≪ τ^0, carries
// that absolute error, not a relative one (lights_test, "AxialMomentsAgreeWithThePolarIntegral").
#pragma once

#include <span>

#include "mesh/geometry.h"

namespace lambert {

// τ^{n,1}(A; a, b) for `polygon` seen from `origin` (a, b unit; n ≥ 0). The polygon is planar and
// convex, of up to 8 vertices, and must not contain the origin; its orientation does not matter. The
// caller keeps a·u and b·u from changing sign over A where it needs their positive parts (clip the
// polygon first).
double double_axis_moment(const Point3& origin, std::span<const Point3> polygon, const Vector3& a, const Vector3& b,
                          int n);

}  // namespace lambert
