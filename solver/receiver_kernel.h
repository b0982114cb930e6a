// The irradiance a receiver (solver/receiver.h) takes from a Lambertian triangle, per unit of the
// triangle's radiosity B: one kernel for every method's gather at a point (the dense operator's,
// solver/dense/point_gather.cpp, and the hierarchical one's) and for the glare's background light.
//
//   K(receiver, T) = (1/π) ∫_{Ω(T)} w(ω) dω,     E = K B            (only T's front side radiates)
//
//   planar:          the Lambert/Hottel contour integral, clipped at the receiver's horizon
//                    (point_triangle_factor, solver/form_factor.h);
//   spherical:       w = 1/4: K = Ω(T)/(4π), the solid angle (Van Oosterom & Strackee);
//   hemispherical:   w = (1 + n·ω)/4 is linear in ω, so K = Ω(T)/(4π) + (1/4π) n·V(T), with Ω the solid
//                    angle (Van Oosterom & Strackee) and V(T) = ∫_{Ω(T)} ω dω the vector irradiance, whose
//                    component along n is the contour sum π point_boundary_factor(p, n, T) — exact
//                    for any direction of n, no clipping (w ≥ 0 everywhere);
//   semicylindrical: w = (|ω_⊥| + f·ω)/π: the cylindrical part plus (1/π) point_boundary_factor(p, f, T);
//   cylindrical:     w = |ω_⊥|/π = sin θ/π has no contour form (∫ sin θ dω over a spherical polygon
//                    leads to ∫ arccot(k cos φ) dφ, which is not elementary). It is integrated over T in
//                    area, ∫_T sin θ (n_T·(p − y)) / r³ dA_y / π², by the degree-5 rule refined where
//                    the children disagree (solver/cubature.h), after grading: pieces of T nearer to the
//                    point than twice their size are split 1:4 (or bisected when elongated) until they
//                    are not, so that the 1/r² peak under a near point is resolved by pieces about as
//                    small as its distance.
// Tests (tests/receiver_test.cpp): the area cubature with the planar weight against the contour
// integral, the hemispherical closed form against the cubature, the cylindrical kernel against an
// independent quadrature in solid angle (polar coordinates about the axis, the inner integral
// ∫ sin² θ dθ exact).
#pragma once

#include <functional>

#include "mesh/geometry.h"
#include "solver/exact_visibility.h"
#include "solver/receiver.h"

namespace lambert {

// K(receiver, t), unoccluded; 0 when the receiver's point is not in front of t.
double receiver_triangle_factor(const Receiver& receiver, const Triangle& t);

// The cylindrical part alone, (1/π²) ∫_{Ω(T)} sin θ dω with θ from the unit axis, for a triangle in
// front of p (exposed for the tests).
double cylinder_triangle_factor(const Point3& p, const Vector3& axis, const Triangle& t);

// K by the graded area cubature for any receiver (the cylindrical kernel's method), for the tests:
// against the contour integral (planar) and the closed form (hemispherical).
double receiver_triangle_cubature(const Receiver& receiver, const Triangle& t);

// K over the visible part of `source` seen from the receiver's point: the loops of
// ExactVisibility::visible_region, fanned into triangles each signed by its orientation about the
// source's normal (a hole subtracts), summed with receiver_triangle_factor.
double receiver_region_factor(const Receiver& receiver, const ExactVisibility::VisibleRegion& region,
                              const Vector3& source_normal);

// The normal to pass ExactVisibility::visible_region for a receiver: its own for a planar receiver
// (whose horizon clips the source); for the others, which see every direction, the source's inward
// normal, whose horizon plane (through the point, parallel to the source) leaves all of the source in
// front of the point.
Vector3 region_normal(const Receiver& receiver, const Vector3& source_normal);

// K over the part of `source` the receiver sees, exactly: for a planar receiver the contour integral
// over the visible part (ExactVisibility::visible_factor, with its shortcuts for a single occluder or
// convex solid), for the others receiver_region_factor over visible_region's loops. What both point
// gathers use for a patch that their rays found partly hidden, where the rays' fraction would carry
// their noise (1/16 of the patch's share) into the probe.
double exact_visible_factor(const Receiver& receiver, const Triangle& source, const ExactVisibility& exact);

// The planar decomposition: the receiver's E from the illuminance E(n) of planes through its point,
//   cylindrical      (1/2π) ∫_0^{2π} E(n(φ)) dφ,        n(φ) ⊥ a
//   semicylindrical  (1/π) ∫_{−π/2}^{π/2} E(n(φ)) dφ,    φ from f
//   hemispherical    (1/2π) ∫_{m·n ≥ 0} E(m) dΩ_m        (polar angle and azimuth, nested)
//   spherical        (1/4π) ∫_{4π} E(m) dΩ_m
// by adaptive Gauss–Kronrod to rel_tolerance (planar: E(n) itself). Exact for any light whose planar
// E is; the default receiver_factor of a light without a closed form (light_model.h).
double receiver_by_planes(const Receiver& receiver, const std::function<double(const Vector3& normal)>& planar,
                          double rel_tolerance = 1e-7);

}  // namespace lambert
