// Values at the corners of patches, for drawing and export: each patch's own (flat), or blended
// across the patches that meet at a corner (smooth), so that the facets of the mesh do not show.
#pragma once

#include <cstddef>
#include <vector>

#include "mesh/geometry.h"

namespace lambert {

enum class Shading { Smooth, Flat };

// Corners whose patches' normals differ by more than this are creases (a box's edges): smoothing
// does not blend across them. A faceted sphere of a few hundred facets turns 7–10° per facet.
constexpr double kCreaseAngle_deg = 40;

// `values` holds `stride` numbers per triangle; the answer holds `stride` per corner, corner k of
// triangle i at (3 i + k) × stride. Flat: the triangle's own. Smooth: at each corner the mean over
// the triangles of the same surface (`surface`, parallel to `triangles`; empty: one surface) that
// share the corner's exact position and whose normals lie within kCreaseAngle_deg of the
// triangle's, weighted by area — the mean value of the patches around the vertex.
std::vector<double> corner_values(const std::vector<Triangle>& triangles, const std::vector<int>& surface,
                                  const std::vector<double>& values, std::size_t stride, Shading shading);

}  // namespace lambert
