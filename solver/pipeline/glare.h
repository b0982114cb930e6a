// The glare stage: UGR per observer (SPEC §5 "glare", solver/glare.h), after the probes.
//   - L_b: the indirect illuminance at the eye on the plane facing the view, over π. Indirect is
//     the light the patches reflect (their radiosity less their own Lambertian emission: a luminous
//     panel is a luminaire, not background), gathered by the operator's point gather, plus ambient
//     light (the lecture's stand-in for interreflection).
//   - The luminaires: each light that shows the eye something (LightModel::glare_view: point-like
//     sources as points, Phong-lobed pieces as areas, a luminaire's openings), and each emitting
//     surface, whose input triangles in front of the eye are areas of luminance M/π (Lambertian)
//     with their solid angles times the visible share of 64 rays. A surface's pieces make one
//     luminaire: Σ L² ω / p² over them, or CIE 147's 200 I² / (r² p²) at their centre where their
//     projected area is below 0.005 m².
// Photometric at its end: luminances in cd/m², the intensity in cd, E_ind in lx.
#pragma once

#include <span>

#include "solver/pipeline/direct_light.h"
#include "solver/pipeline/outputs.h"

namespace lambert {

// op: nullptr where nothing is transported. `lobed`: the pieces behind light.sources past the
// scene's lights, in order (their surfaces name them).
void solve_glare(Solution& sol, const Scene& scene, const DirectLight& light, std::span<const LobedPiece> lobed,
                 const SpectralSystems& systems, const SystemFields& fields, const TransportOperator* op,
                 const Visibility& vis);

}  // namespace lambert
