// Exact 2D Boolean operations on convex polygons (CGAL Polygon_set_2 over the Epeck kernel, in
// polygon_boolean.cpp; no CGAL type leaves it). Used for exact partial visibility
// (solver/exact_visibility.h): a source polygon minus the projections of its occluders.
#pragma once

#include <array>
#include <span>
#include <vector>

namespace lambert {

using Point2d = std::array<double, 2>;
using Loop2d = std::vector<Point2d>;

// The region conv(base) \ ∪_k conv(cutters[k]), where conv is the convex hull of a loop's points
// (taken with exact predicates, so rounded, nearly collinear or repeated vertices are harmless;
// cutters that span no area are ignored). Returned as boundary loops: outer boundaries
// counter-clockwise, holes clockwise, so that a signed sum over all loops (area, or a contour
// integral) gives the region's value. The intersection points are constructed exactly and rounded
// to double only on output.
std::vector<Loop2d> convex_difference(const Loop2d& base, std::span<const Loop2d> cutters);

// The union of the convex hulls of `parts`, as polygons with holes: each entry is an outer boundary
// (counter-clockwise) followed by its holes (clockwise). Exact, like convex_difference.
std::vector<std::vector<Loop2d>> convex_union(std::span<const Loop2d> parts);

}  // namespace lambert
