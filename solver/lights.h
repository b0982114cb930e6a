// Light sources other than emitting surfaces (SPEC §1 "Light models"). Every model is linear in its
// spectrum S(λ): E(λ) = g · S(λ), with a purely geometric factor g computed here. S is the light's
// intensity I_0(λ) [W sr^-1 nm^-1] for point-like sources (g in sr m^-2) and its irradiance
// [W m^-2 nm^-1] for directional and ambient light (g dimensionless).
#pragma once

#include <vector>

#include "mesh/geometry.h"
#include "solver/scene.h"
#include "solver/visibility.h"

namespace lambert {

const std::vector<double>& light_spectrum(const Light& light);

// g at a point p with unit normal n (a probe), shadowed with one ray where the model says so.
double light_point_factor(const Light& light, const Point3& p, const Vector3& n, const Visibility& vis);

// Area average of g over a triangle (exact flux/area where a closed form exists, adaptive cubature
// otherwise), times the visible fraction of the light seen from the triangle.
double light_patch_factor(const Light& light, const Triangle& t, const Visibility& vis);

// Unshadowed g at a point (no ray); exposed for tests of the models' closed forms.
double light_unshadowed_factor(const Light& light, const Point3& p, const Vector3& n);

// Flux the source emits per unit of its spectrum [sr for intensity sources]: Φ(λ) = Ω_eff S(λ).
// Zero for directional and ambient light, whose flux depends on the scene they fall on.
double light_flux_factor(const Light& light);

}  // namespace lambert
