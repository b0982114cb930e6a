// The map of a probe grid (`lambert render --probe-grid NAME`): the grid seen square-on, each cell
// in the false colour of its illuminance with its value written in it where it fits, isolux lines
// at the legend's tick values (isolines.h) with their values, the legend, and the grid's minimum,
// mean, maximum and uniformity.
#pragma once

#include <string>
#include <vector>

#include "server/canvas.h"
#include "server/colour_scale.h"

namespace lambert {

struct GridValues {
  std::string name;
  int nu = 1, nv = 1;
  double cell_u = 1, cell_v = 1;  // the cells' sides, in `unit`
  std::string unit = "m";
  std::vector<double> illuminance_lx;  // nu × nv, u fastest
};

struct GridMapLayout {
  Point2 origin;              // the map's bottom-left corner (cell (0, 0) is just above and right)
  double cell_w = 0, cell_h = 0;
  // The pixel of lattice point (i, j), the centre of cell (i, j): x right along u, y up along v.
  Point2 centre(double i, double j) const { return {origin.x + (i + 0.5) * cell_w, origin.y - (j + 0.5) * cell_h}; }
};

inline constexpr int kGridMapWidth = 960, kGridMapHeight = 720;

// Where the cells go in the picture (cells keep the grid's aspect ratio).
GridMapLayout grid_map_layout(const GridValues& grid, const ColourScale& scale);

// The isolux levels: the legend's ticks strictly inside the range of the values.
std::vector<double> isolux_levels(const GridValues& grid, const ColourScale& scale);

// Draws the map; throws std::invalid_argument for a grid whose values do not match nu × nv.
Image draw_grid_map(const GridValues& grid, ScaleKind kind);

}  // namespace lambert
