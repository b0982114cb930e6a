// Integrals over the directions through a convex planar polygon, in polar coordinates (ψ, φ) about an
// axis (measure dω = sin ψ dψ dφ), for integrands whose integral along each half-plane of constant φ
// is known in closed form:
//
//   ∫_{Ω(P)} f dω = ∫_0^{2π} dφ B(φ, ψ1(φ), ψ2(φ)),   B(φ, ψ1, ψ2) = ∫_{ψ1}^{ψ2} f(φ, ψ) sin ψ dψ,
//
// where [ψ1, ψ2] is the section of the polygon by the half-plane of azimuth φ (an interval, since the
// polygon is convex). The outer integral is adaptive Gauss–Kronrod in φ, broken at the azimuths where
// B has kinks or its narrowest features: polygon vertices, the points of each edge nearest to and
// farthest from the axis, the crossings of the edges with the cone ψ = ψ_max, and any azimuths the
// caller adds (the planes of a tabulated distribution). The point-like lights' cone integral
// (point_like.h: B closed form for cos^m ψ) and the luminaires' tabulated distributions
// (solver/photometry/distribution.h: B exact for the bilinear interpolant) are its two users.
#pragma once

#include <cmath>
#include <functional>
#include <span>

#include "mesh/geometry.h"
#include "solver/quadrature_1d.h"
#include "solver/spectrum.h"

namespace lambert {

// An orthonormal frame (a, b, c) about the polar axis c; azimuth φ is measured from a towards b.
// By default right-handed with a = perpendicular(c); a caller may give a and b (either handedness:
// only e(φ) = a cos φ + b sin φ is used).
struct PolarFrame {
  Vector3 a, b, c;
  explicit PolarFrame(const Vector3& axis) : a(perpendicular(axis)), b(cross(axis, perpendicular(axis))), c(axis) {}
  PolarFrame(const Vector3& zero, const Vector3& quarter, const Vector3& axis) : a(zero), b(quarter), c(axis) {}
  double azimuth(const Vector3& v) const {
    const double phi = std::atan2(dot(b, v), dot(a, v));
    return phi < 0 ? phi + 2 * kPi : phi;
  }
};

// B(φ, ψ1, ψ2) as above (φ may lie anywhere in [0, 4π): callers that care reduce it).
using BandIntegral = std::function<double(double phi, double psi1, double psi2)>;

// ∫ f dω over the directions from `origin` through the convex planar polygon (≤ 8 vertices, either
// orientation); 0 if the origin lies in the polygon's plane. psi_max: where f is cut off (π: nowhere);
// its cone's crossings become breakpoints. rel_tolerance bounds the outer integral's error estimate.
double polar_integral(const Point3& origin, const PolarFrame& frame, std::span<const Point3> polygon,
                      const BandIntegral& band, double psi_max, std::span<const double> azimuth_breaks,
                      double rel_tolerance);

}  // namespace lambert
