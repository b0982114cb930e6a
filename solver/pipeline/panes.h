// Glazing (SPEC §5 "Glazing", docs/METHOD.md): a surface whose material transmits is a pane of zero
// thickness with two faces, the given one and its back, added to the surface's mesh before meshing
// (Surface::pane_triangles). Both faces exchange light with the scene; each reflects ρ of its own
// irradiance and absorbs 1 − ρ − τ of it. A diffusely transmitting pane (opal glass) passes τ of
// the other face's irradiance on as Lambertian radiosity,
//
//   B_front = M + ρ H_front + τ P H_back,   B_back = ρ H_back + τ P H_front,
//
// which is exact in radiosity: rays do not cross the pane, the light crosses by re-emission. P maps
// the irradiance of one face's patches onto the other's: P_ij = |i ∩ j| / A_i, the share of patch i's
// area that lies on patch j of the other face (exact polygon overlap, so Σ_j P_ij = 1 and
// Σ_i A_i P_ij = A_j: whatever one face receives, the other passes on in full, whichever way each
// face was meshed or refined).
#pragma once

#include <vector>

#include "solver/linear_solve.h"
#include "solver/radiosity.h"

namespace lambert {

// Whether some surface's material transmits.
bool has_panes(const Scene& scene);

// Adds each pane's back face to its surface (the triangles reversed, on vertices of their own) and
// flags both faces two-sided (Surface::two_sided: a ray meets either face of the sheet, never a back
// face). Returns whether any surface changed.
bool add_pane_back_faces(Scene& scene);

// Per patch and wavelength ([patch][λ] flat) τ(λ) of the patch's material, or empty where no
// material transmits.
std::vector<double> patch_transmittance(const Scene& scene, const std::vector<Patch>& patches);

// P over all patches (PaneTransfer, solver/linear_solve.h): a row for every patch of a pane, with
// the patches of the other face that it overlaps. Patches of a pane lie in its input triangles, each
// face's triangle t facing its twin t ± pane_triangles.
PaneTransfer pane_transfer(const Scene& scene, const std::vector<Patch>& patches);

}  // namespace lambert
