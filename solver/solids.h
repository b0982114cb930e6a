// Closed surfaces (and convex ones that one plane closes): which triangles bound a solid. The triangles of all surfaces are joined into
// components across edges whose ends coincide (a box given as six surfaces, one per face, is one
// component); a component is closed when its vector area Σ A n vanishes (as it does for any closed
// surface, T-junctions or not), every edge of one triangle has another running back over it (as at a
// T-junction; not along a hole, which holes facing each other hide from the vector area) and it
// encloses a volume (which a sheet's two faces back to back do not). Its faces may point out of that volume (a box) or into it (a room).
#pragma once

#include <memory>
#include <vector>

#include "solver/exact_visibility.h"
#include "solver/scene.h"

namespace lambert {

// Per surface: whether any of its triangles is in a closed component.
std::vector<char> surfaces_bounding_solids(const std::vector<Surface>& surfaces);

// The closed components whose faces point out of the volume they enclose, consistently (every edge
// shared by two of its triangles runs opposite ways in them; an edge shared by more of them is taken
// as inconsistent). An edge that more than two triangles of the scene share joins none of them (a
// crate's wall and the floor's triangles meeting under it): each component counts its own uses. A segment between two points outside that volume that crosses such a triangle from
// behind, leaving the volume, has crossed one of the component's triangles from the front before: for
// visibility between points outside it, its triangles seen from behind are redundant
// (ExactVisibility). Where the solid is also convex, the triangles it turns towards a point outside
// it are seen in directions that do not overlap: the factor they hide is the sum of theirs.
struct OutwardSolids {
  // Per triangle of every surface (surface by surface, in mesh order): the index of the outward solid
  // it bounds, or −1.
  std::vector<int> solid;
  // Per solid: whether it is convex (every corner on or behind every face's plane, to 1e-9 of the
  // solid's size). At most kMaxConvexityChecks corner–face pairs are checked over all solids (about
  // 0.1 s); a closed solid beyond that budget is checked locally (every edge convex, no corner's
  // angles above 2π, the topology of a sphere), and an open one beyond it is not (false).
  std::vector<char> convex;
  static constexpr double kMaxConvexityChecks = 5e7;
  // Per solid: where it is open, the plane that closes it. A connected, consistently oriented surface
  // whose edges with one triangle all lie in one plane (a building's walls and roof, standing on the
  // ground with no floor of their own) and that is convex with that plane as a face is such a solid
  // (closed ones have no cap). What holds for a closed solid holds for it only between points on or
  // behind the cap's plane (never through the missing face), seen from outside it (ExactVisibility).
  using Cap = SolidCap;
  std::vector<Cap> cap;
};
OutwardSolids outward_solids(const std::vector<Surface>& surfaces);

// Exact visibility among the scene's input triangles, with their outward solids: what the point
// gathers and the tests evaluate visible factors against.
std::unique_ptr<ExactVisibility> scene_exact_visibility(const Scene& scene);

}  // namespace lambert
