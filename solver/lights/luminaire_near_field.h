// The luminaire's two forms (luminaire.h), shared by luminaire.cpp (the light model) and
// luminaire_near_field.cpp (the area form). Internal to solver/lights/.
#pragma once

#include "mesh/geometry.h"
#include "solver/lights/luminaire.h"
#include "solver/visibility.h"

namespace lambert {

// ∫ I_file(ω) dω over the directions from `from` through triangle t [cd sr]: the polar integral about
// the goniometer's axis, exact in θ for the bilinear interpolant, with the web's planes as breakpoints.
double distribution_through(const PlacedLuminaire& l, const Point3& from, const Triangle& t);

// The area form, per candela of the file (× the light's spectrum gives E(λ)):
// E at p with unit normal n, unshadowed [cd sr m⁻²] ...
double opening_irradiance(const PlacedLuminaire& l, const Point3& p, const Vector3& n);
// ... the same shadowed by kernel-weighted rays from the opening to p ...
double opening_point_factor(const PlacedLuminaire& l, const Point3& p, const Vector3& n, const Visibility& vis);
// ... and its area average over triangle t, shadowed by rays between the opening and t.
double opening_patch_factor(const PlacedLuminaire& l, const Triangle& t, const Visibility& vis);

}  // namespace lambert
