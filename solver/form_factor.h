// Diffuse configuration (form) factors from the exact point-to-polygon contour integral.
//
//   F(dA_p -> P) = (1/2π) Σ_i γ_i  n · (R_i × R_{i+1}) / |R_i × R_{i+1}|          (Lambert / Hottel)
//
// R_i runs from p to the polygon's vertices, γ_i is the angle between R_i and R_{i+1}, n is the unit
// normal at p. The formula holds for a polygon wholly in front of p; we clip the polygon at p's horizon
// plane first, so any polygon position is handled exactly. Visibility (occlusion) is not part of these
// functions: the caller multiplies by a visible fraction (solver/visibility.h).
#pragma once

#include <span>

#include "mesh/geometry.h"

namespace lambert {

// Point-to-polygon factor: fraction of the flux leaving a Lambertian polygon... equivalently the
// irradiance at p per unit exitance of the polygon, E(p) = M F. Only the polygon's front side
// (counter-clockwise seen from p) emits: a polygon seen from behind gives 0. The polygon may have up to
// 16 vertices (it is clipped, which adds at most one vertex per clipping plane).
double point_polygon_factor(const Point3& p, const Vector3& n, std::span<const Point3> polygon);
double point_triangle_factor(const Point3& p, const Vector3& n, const Triangle& t);
// The vector form factor of t at p, V = (1/2π) Σ_i γ_i ĉ_i (ĉ_i the unit normal of the plane through p
// and edge i): n · V = point_triangle_factor(p, n, t) for every unit n whose horizon leaves t wholly in
// front (the contour sum is linear in n there), so one V serves receivers of any such normal at p.
// Zero where p is not in front of t.
Vector3 triangle_vector_factor(const Point3& p, const Triangle& t);
// point_triangle_factor at every point of `points` (a common normal n), into out (the same size).
// Points in the common case (t in front and wholly above the horizon: all but points next to t's
// plane) are evaluated together in vectorised lanes, the rest one by one; each value is
// point_triangle_factor's. 7 points: 143 ns against 360 ns one call each (kernels_benchmark, AVX2,
// before the lanes took edges seen under more than 14°).
void point_triangle_factors(std::span<const Point3> points, const Vector3& n, const Triangle& t, std::span<double> out);

// The contour sum alone, signed, for a closed boundary (any number of vertices) that lies wholly in
// front of p's horizon, NOT clipped: a boundary counter-clockwise about the normal n_s of the plane it
// lies in, seen from p on the front side, adds its factor, a clockwise one (a hole) subtracts it. Summed
// over the outer boundaries and holes of a polygon set, it gives the set's factor.
double point_boundary_factor(const Point3& p, const Vector3& n, std::span<const Point3> boundary);

// Solid angle [sr] subtended at p by triangle t (Van Oosterom & Strackee 1983), regardless of
// orientation. Used for the exact patch-average irradiance from an isotropic point source:
// ∫_T I cos α / r² dA = I Ω(T).
double triangle_solid_angle(const Point3& p, const Triangle& t);

// A_i F_ij for two triangles (unoccluded): ∫_{A_i} F(dA_p -> T_j) dA_p, integrated over `receiver`
// with adaptive cubature (the integrand is bounded but has a logarithmic derivative singularity where
// patches touch; the cubature refines towards it until the estimated error is below rel_tolerance).
// Symmetric in exact arithmetic: A_i F_ij = A_j F_ji (reciprocity).
struct AreaFactorOptions {
  double rel_tolerance = 1e-5;   // relative to the pair's own value
  double abs_tolerance = 1e-7;   // times the receiver's area: floor for pairs that barely see each other
  int max_depth = 7;             // 4^7 sub-triangles at most
  // Pairs farther apart than this many times the sum of their bounding radii use the fixed degree-5
  // rule alone (measured error < 1e-5 there, see form_factor_test "FarField").
  double far_field_separation = 4;
};
double area_form_factor(const Triangle& receiver, const Triangle& source,
                        const AreaFactorOptions& options = {});

// A_a F_ab = A_b F_ba (m², unoccluded), the same bit for bit in either order: area_form_factor
// integrated over the triangle of smaller bounding radius (ties: smaller area, then the first by
// vertex coordinates). The kernel is exact over the other triangle, and the rule's error grows with
// the extent of the domain it samples: a strip 100 times longer than the common edge it shares with
// a square errs by 4e-3 to 6e-3 integrated over the strip and by 1e-6 over the square, at the same
// tolerance (form_factor_test, "ExchangeAreaIntegratesOverTheSmallerTriangle").
double exchange_area(const Triangle& a, const Triangle& b, const AreaFactorOptions& options = {});

}  // namespace lambert
