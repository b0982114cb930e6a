// Isolux lines and the probe-grid map (server/isolines.h, server/grid_map.h) against closed forms:
// marching squares is exact on a linear field; the isolux line of a point source over a plane is a
// circle, E = I h / (h² + r²)^(3/2) (REFERENCES P1) giving its radius; and the map draws that circle
// where the layout puts it.
#include <gtest/gtest.h>

#include <cmath>

#include "server/grid_map.h"
#include "server/isolines.h"

namespace lambert {
namespace {

TEST(Isolines, ExactOnALinearField) {
  // E = 3 + 2 i − j on a 6 × 5 lattice: the level 5 is the line 2 i − j = 2.
  const int nu = 6, nv = 5;
  std::vector<double> E;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) E.push_back(3 + 2.0 * i - j);
  const std::vector<Segment2> lines = isolines(E, nu, nv, 5);
  ASSERT_FALSE(lines.empty());
  for (const Segment2& s : lines)
    for (const Point2& p : {s.a, s.b}) {
      EXPECT_NEAR(2 * p.x - p.y, 2, 1e-12);
      EXPECT_GE(p.x, 0);
      EXPECT_LE(p.y, nv - 1);
    }
  // The line runs from (1, 0) to (3, 4): its length is √20, made of the segments.
  double length = 0;
  for (const Segment2& s : lines) length += std::hypot(s.b.x - s.a.x, s.b.y - s.a.y);
  EXPECT_NEAR(length, std::sqrt(20.0), 1e-12);
  EXPECT_TRUE(isolines(E, nu, nv, 100).empty());  // above every value
}

TEST(Isolines, ASaddleIsCutByTheMeanOfItsCorners) {
  // Corners 1, 0, 1, 0 around the cell (mean 0.5): at level 0.4 the centre is above, so the two low
  // corners (1, 0) and (0, 1) are cut off; at 0.6 the two high ones.
  const std::vector<double> E = {1, 0, 0, 1};  // (0,0)=1 (1,0)=0 (0,1)=0 (1,1)=1
  for (double level : {0.4, 0.6}) {
    const std::vector<Segment2> lines = isolines(E, 2, 2, level);
    ASSERT_EQ(lines.size(), 2u);
    for (const Segment2& s : lines) {
      const Point2 mid{(s.a.x + s.b.x) / 2, (s.a.y + s.b.y) / 2};
      const bool near_low_corner = std::hypot(mid.x - 1, mid.y) < 0.6 || std::hypot(mid.x, mid.y - 1) < 0.6;
      EXPECT_EQ(near_low_corner, level < 0.5) << level;
    }
  }
}

// A 1 cd point source 1 m above the centre of a 4 m × 4 m grid of 41 × 41 points.
GridValues point_source_grid() {
  GridValues g;
  g.name = "floor";
  g.nu = g.nv = 41;
  g.cell_u = g.cell_v = 0.1;
  for (int b = 0; b < g.nv; ++b)
    for (int a = 0; a < g.nu; ++a) {
      const double x = (a - 20) * 0.1, y = (b - 20) * 0.1, h = 1;
      g.illuminance_lx.push_back(h / std::pow(h * h + x * x + y * y, 1.5));  // I h / d³
    }
  return g;
}

TEST(Isolines, APointSourcesIsoluxLineIsACircle) {
  const GridValues g = point_source_grid();
  // E = h / (h² + r²)^{3/2} = 0.5 lx at r = √(2^{2/3} − 1) h = 0.7664 m, 7.664 lattice steps.
  const double r = std::sqrt(std::pow(2.0, 2.0 / 3) - 1) / 0.1;
  const std::vector<Segment2> lines = isolines(g.illuminance_lx, g.nu, g.nv, 0.5);
  ASSERT_GT(lines.size(), 40u);
  for (const Segment2& s : lines)
    // Linear interpolation of a convex fall-off along 0.1 m edges: within 1 % of the radius.
    EXPECT_NEAR(std::hypot(s.a.x - 20, s.a.y - 20), r, 0.01 * r);
}

TEST(GridMap, DrawsTheCellsTheirColoursAndTheIsoluxCircleWhereTheLayoutSays) {
  const GridValues g = point_source_grid();
  const ColourScale scale = colour_scale(g.illuminance_lx, ScaleKind::Log);
  const GridMapLayout layout = grid_map_layout(g, scale);
  EXPECT_NEAR(layout.cell_w, layout.cell_h, 1e-12);  // square cells stay square
  const Image img = draw_grid_map(g, ScaleKind::Log);
  ASSERT_EQ(img.width, kGridMapWidth);
  // The centre cell holds the largest value: the top of the ramp, red.
  const Point2 c = layout.centre(20, 20);
  EXPECT_EQ(img.at(static_cast<int>(c.x), static_cast<int>(c.y) + 3), false_colour_ramp(1));
  // 1, 2 and 5 × 10^k strictly inside the values, from 1/27 lx at the corners (d² = 1 + 8 m²) to 1 lx
  // below the source: the isolux levels 0.05, 0.1, 0.2 and 0.5.
  EXPECT_EQ(isolux_levels(g, scale), (std::vector<double>{0.05, 0.1, 0.2, 0.5}));
  // Along ±u and ±v from the centre, the 0.5 lx line is drawn dark at the circle's radius (±2 px); one
  // of the four places may hold the line's label instead.
  const double r = std::sqrt(std::pow(2.0, 2.0 / 3) - 1) / 0.1;
  int dark_places = 0;
  for (const auto& [du, dv] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
    const Point2 on_circle = layout.centre(20 + du * r, 20 + dv * r);
    bool dark = false;
    for (int d = -2; d <= 2 && !dark; ++d) {
      const Rgb p = img.at(static_cast<int>(on_circle.x) + (du != 0 ? d : 0), static_cast<int>(on_circle.y) + (dv != 0 ? d : 0));
      dark = p.r < 80 && p.g < 80 && p.b < 80;
    }
    dark_places += dark;
  }
  EXPECT_GE(dark_places, 3);
  EXPECT_THROW(draw_grid_map(GridValues{"bad", 2, 2, 1, 1, "m", {1, 2, 3}}, ScaleKind::Log), std::invalid_argument);
}

}  // namespace
}  // namespace lambert
