// Closed surfaces: which triangles bound a solid. The triangles of all surfaces are joined into
// components across edges whose ends coincide (a box given as six surfaces, one per face, is one
// component); a component is closed when its vector area Σ A n vanishes (as it does for any closed
// surface, T-junctions or not) and it encloses a volume (which a sheet's two faces back to back do
// not). Its faces may point out of that volume (a box) or into it (a room).
#pragma once

#include <vector>

#include "solver/scene.h"

namespace lambert {

// Per surface: whether any of its triangles is in a closed component.
std::vector<char> surfaces_bounding_solids(const std::vector<Surface>& surfaces);

// Per triangle of every surface (surface by surface, in mesh order): whether it is in a closed
// component whose faces point out of the volume it encloses, consistently (every edge shared by two
// of its triangles runs opposite ways in them; an edge shared by more is taken as inconsistent). A
// segment between two points outside that volume that crosses such a triangle from behind, leaving
// the volume, has crossed one of the component's triangles from the front before: for visibility
// between points outside it, its triangles seen from behind are redundant (ExactVisibility).
std::vector<char> outward_solid_triangles(const std::vector<Surface>& surfaces);

}  // namespace lambert
