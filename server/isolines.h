// Isolines (isolux lines) of values sampled on a lattice, by marching squares: on each cell the
// crossings of the level on its four edges, by linear interpolation along the edge, joined into
// segments; a saddle cell (opposite corners on the same side) is resolved by the mean of its corners.
// Exact for a field that is linear along the edges; for a smooth field the error is second order in
// the cell size.
#pragma once

#include <vector>

#include "server/canvas.h"

namespace lambert {

struct Segment2 {
  Point2 a, b;
};

// `values` holds nu × nv samples, u fastest; sample (i, j) sits at lattice point (i, j). Cells with
// a non-finite corner are skipped.
std::vector<Segment2> isolines(const std::vector<double>& values, int nu, int nv, double level);

}  // namespace lambert
