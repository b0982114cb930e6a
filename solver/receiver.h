// What a probe point measures: the mean irradiance over a small receiving surface at a point, the
// quantities lighting designers check (EN 12464-1; CIE S 017 17-21-052..055). Each receiver weighs
// the radiance L(ω) arriving from direction ω (unit, from the point towards where the light comes
// from) by its own w(ω):
//
//   E = ∫_{4π} L(ω) w(ω) dω                                              [W m^-2 per W m^-2 sr^-1]
//
//   planar, normal n (a horizontal or vertical plane):   w = (n·ω)⁺
//   cylindrical, axis a (mean over the curved surface):  w = |ω_⊥| / π,         ω_⊥ = ω − (a·ω) a
//   semicylindrical, axis a, facing f ⊥ a:               w = (|ω_⊥| + f·ω) / π
//   hemispherical, pole n (mean over the curved surface): w = (1 + n·ω) / 4
//   spherical (mean over a small sphere):                 w = 1 / 4
//
// A beam of normal irradiance E_n at angle ε from the axis lights a cylinder of radius r and height h
// over its projected area 2 r h sin ε, spread over 2π r h: E_n sin ε / π (so a point source gives
// E_z = I sin ε / (π d²)); the half cylinder facing f shows the beam r h sin ε (1 + cos φ), φ the
// beam's azimuth from f, spread over π r h; a hemisphere shows π r² (1 + cos ε)/2 over 2π r²; a
// sphere shows π r² from every side over 4π r² (ISO 7726's mean radiant temperature is a sphere's).
// Equivalently each is the mean of the planar illuminance over the surface's normals: the
// cylindrical E over the normals ⊥ a, the semicylindrical over those within 90° of f, the
// hemispherical over the normals of the hemisphere, the spherical over all normals (receiver_kernel.h
// uses this as a second method).
//
// The kernels that take a Receiver: the operators' gather_at_point (transport_operator.h, through the
// shared kernel receiver_triangle_factor) and the lights' receiver_factor (light_model.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "mesh/geometry.h"

namespace lambert {

struct Receiver {
  enum class Kind : std::uint8_t { Planar, Cylindrical, Semicylindrical, Hemispherical, Spherical };
  Kind kind = Kind::Planar;
  Point3 point;    // metres
  Vector3 normal;  // unit. Planar: the side the plane receives on; cylindrical and semicylindrical:
                   // the axis; hemispherical: the pole (the side the hemisphere bulges to);
                   // spherical: unused
  Vector3 facing;  // unit, perpendicular to the axis: the direction a semicylinder faces
};

// w(ω) for a unit direction ω (dimensionless; see above).
inline double receiver_weight(const Receiver& r, const Vector3& omega) {
  constexpr double kInvPi = 0.318309886183790671537767526745;
  switch (r.kind) {
    case Receiver::Kind::Planar: return std::max(0.0, dot(r.normal, omega));
    case Receiver::Kind::Cylindrical: return length(cross(r.normal, omega)) * kInvPi;
    case Receiver::Kind::Semicylindrical:
      return std::max(0.0, length(cross(r.normal, omega)) + dot(r.facing, omega)) * kInvPi;
    case Receiver::Kind::Hemispherical: return 0.25 * (1 + dot(r.normal, omega));
    case Receiver::Kind::Spherical: return 0.25;
  }
  return 0;
}

}  // namespace lambert
