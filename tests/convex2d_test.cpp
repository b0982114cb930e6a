// Convex polygons as disjoint convex pieces (mesh/convex2d.h) against CGAL's exact Booleans
// (mesh/polygon_boolean.h, a second method: exact constructions, polygons with holes) and against
// areas known in closed form; and the pieces' own promises: disjoint, inside the base, outside every
// cutter.
#include "mesh/convex2d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mesh/polygon_boolean.h"

namespace lambert {
namespace {

double area_of(const ConvexPieces& pieces) {
  double a = 0;
  for (std::size_t i = 0; i < pieces.size(); ++i) a += signed_area(pieces[i]);
  return a;
}

// Signed shoelace sum over CGAL's loops (outer boundaries counter-clockwise, holes clockwise).
double area_of(const std::vector<Loop2d>& loops) {
  double a = 0;
  for (const Loop2d& loop : loops) a += signed_area(loop);
  return a;
}

// The area that two convex counter-clockwise polygons share.
double overlap(std::span<const Point2d> u, std::span<const Point2d> w) {
  Loop2d out, scratch;
  clip_convex_into(u, w, out, scratch);
  return out.size() < 3 ? 0.0 : signed_area(out);
}

Loop2d square(double x0, double y0, double size) {
  return {{x0, y0}, {x0 + size, y0}, {x0 + size, y0 + size}, {x0, y0 + size}};
}

// A random convex polygon: the hull of 3 to 12 points about a centre.
Loop2d random_convex(std::mt19937& rng, double cx, double cy, double radius) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> count(3, 12);
  std::vector<Point2d> points;
  for (int k = count(rng); k > 0; --k) points.push_back({cx + radius * u(rng), cy + radius * u(rng)});
  Loop2d hull;
  convex_hull(points, hull);
  return hull;
}

// Every pair of pieces shares no area, every piece lies in `base` and outside every cutter.
void expect_disjoint_pieces(const ConvexPieces& pieces, std::span<const Point2d> base, const ConvexPieces& cutters,
                            double tolerance) {
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    EXPECT_GT(signed_area(pieces[i]), 0) << "piece " << i << " is not counter-clockwise";
    if (!base.empty()) {
      EXPECT_NEAR(overlap(pieces[i], base), signed_area(pieces[i]), tolerance) << "piece " << i;
    }
    for (std::size_t c = 0; c < cutters.size(); ++c) EXPECT_NEAR(overlap(pieces[i], cutters[c]), 0, tolerance);
    for (std::size_t j = i + 1; j < pieces.size(); ++j) EXPECT_NEAR(overlap(pieces[i], pieces[j]), 0, tolerance);
  }
}

TEST(Convex2d, SquareLessACentredSquareIsItsFrame) {
  // 1 − 0.25 in at most four pieces (one per edge of the cutter), none overlapping the hole.
  const Loop2d base = square(0, 0, 1), hole = square(0.25, 0.25, 0.5);
  ConvexPieces pieces, cutters;
  ConvexScratch scratch;
  subtract_convex(base, hole, 0, pieces, scratch);
  EXPECT_EQ(pieces.size(), 4u);
  EXPECT_NEAR(area_of(pieces), 0.75, 1e-15);
  cutters.add(hole);
  expect_disjoint_pieces(pieces, base, cutters, 1e-15);
}

TEST(Convex2d, WholeApartCoveredAndTouching) {
  ConvexScratch scratch;
  const Loop2d base = square(0, 0, 1);
  for (const Loop2d& apart : {square(2, 0, 1), square(1, 0, 1), square(1, 1, 1), square(0.5, -3, 1)}) {
    ConvexPieces pieces;
    subtract_convex(base, apart, 0, pieces, scratch);
    ASSERT_EQ(pieces.size(), 1u);  // untouched: the piece itself, with no clip
    EXPECT_TRUE(std::equal(base.begin(), base.end(), pieces[0].begin(), pieces[0].end()));
  }
  ConvexPieces none;
  subtract_convex(base, square(-1, -1, 3), 0, none, scratch);
  EXPECT_TRUE(none.empty());
  subtract_convex(base, base, 0, none, scratch);  // a cutter equal to the piece leaves nothing
  EXPECT_NEAR(area_of(none), 0, 1e-15);
}

TEST(Convex2d, UnionOfSquaresSharingEdgesAndCorners) {
  // Closed forms: abutting squares (an edge in common, opposite ways round), squares shifted along a
  // common edge line (the same way round), a square twice, and one inside another.
  struct Case {
    std::vector<Loop2d> polygons;
    double area;
  };
  const Case cases[] = {{{square(0, 0, 1), square(1, 0, 1)}, 2},
                        {{square(0, 0, 1), square(0.5, 0, 1)}, 1.5},
                        {{square(0, 0, 1), square(0.5, 0.5, 1), square(1, 1, 1)}, 2.5},
                        {{square(0, 0, 1), square(0, 0, 1)}, 1},
                        {{square(0, 0, 2), square(0.5, 0.5, 1)}, 4},
                        {{square(0, 0, 1), square(1, 1, 1)}, 2}};
  ConvexScratch scratch;
  for (const Case& c : cases) {
    ConvexPieces polygons, pieces;
    for (const Loop2d& p : c.polygons) polygons.add(p);
    convex_union_pieces(polygons, 0, pieces, scratch);
    EXPECT_NEAR(area_of(pieces), c.area, 1e-15) << "case " << (&c - cases);
    expect_disjoint_pieces(pieces, {}, {}, 1e-15);
  }
}

// CGAL's exact Booleans, the reference here, run some 20 times slower under AddressSanitizer (the
// CI's second build): there the first 20 trials, which cover 1 to 20 cutters and the near-edge ones.
#if defined(LAMBERT_ADDRESS_SANITIZER)
constexpr int kCgalTrials = 20;
#else
constexpr int kCgalTrials = 60;
#endif

TEST(Convex2d, DifferenceAndUnionAgreeWithCgal) {
  // Random convex polygons, from 1 to 40 cutters overlapping each other and the base's edges, some
  // nearly coincident with the base's edges (offsets of 1e-13): the pieces' area equals that of
  // CGAL's exact difference and union, and the pieces are disjoint, in the base, out of the cutters.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < kCgalTrials; ++trial) {
    const Loop2d base = random_convex(rng, 0, 0, 1);
    ASSERT_GE(base.size(), 3u);
    const int count = 1 + trial % 40;
    std::vector<Loop2d> cutters;
    ConvexPieces cutter_pieces;
    for (int k = 0; k < count; ++k) {
      Loop2d c = random_convex(rng, 1.2 * u(rng), 1.2 * u(rng), 0.1 + 0.4 * std::abs(u(rng)));
      if (k % 7 == 3) {  // along one of the base's edges, 1e-13 off it
        const Point2d& a = base[0];
        const Point2d& b = base[1];
        const double dx = b[0] - a[0], dy = b[1] - a[1], len = std::hypot(dx, dy);
        const double nx = dy / len, ny = -dx / len;  // outward: the base is counter-clockwise
        c = {{a[0] + 0.2 * dx + 1e-13 * nx, a[1] + 0.2 * dy + 1e-13 * ny},
             {a[0] + 0.7 * dx + 1e-13 * nx, a[1] + 0.7 * dy + 1e-13 * ny},
             {a[0] + 0.5 * dx - 0.3 * nx, a[1] + 0.5 * dy - 0.3 * ny}};
        if (signed_area(c) < 0) std::swap(c[1], c[2]);
      }
      if (c.size() < 3) continue;
      cutters.push_back(c);
      cutter_pieces.add(c);
    }
    ConvexPieces difference, united;
    ConvexScratch scratch;
    convex_difference_pieces(base, cutter_pieces, 0, difference, scratch);
    EXPECT_NEAR(area_of(difference), area_of(convex_difference(base, cutters)), 1e-13) << "trial " << trial;
    expect_disjoint_pieces(difference, base, cutter_pieces, 1e-13);

    convex_union_pieces(cutter_pieces, 0, united, scratch);
    double cgal_union = 0;
    for (const std::vector<Loop2d>& polygon : convex_union(cutters)) cgal_union += area_of(polygon);
    EXPECT_NEAR(area_of(united), cgal_union, 1e-13) << "trial " << trial;
    expect_disjoint_pieces(united, {}, {}, 1e-13);
  }
}

TEST(Convex2d, TidyMakesALoopStrictlyConvexAndKeepsItsArea) {
  // A unit square as a clip leaves it: a corner twice (1 − 2e-17 rounds to 1), vertices on edges, one
  // a rounding inside the edge between its neighbours (a right turn). What is left is the square's
  // four corners, counter-clockwise, each turning left, with the area unchanged to rounding.
  std::vector<Point2d> loop{{0, 0}, {0.5, 1e-17}, {1, 0}, {1, 1}, {1 - 2e-17, 1}, {0.5, 1}, {0, 1}, {0, 0.5 + 1e-17}};
  const double before = signed_area(loop);
  tidy_convex(loop);
  ASSERT_EQ(loop.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_GT(cross2(loop[i], loop[(i + 1) % 4], loop[(i + 2) % 4]), 0.5);
  EXPECT_NEAR(signed_area(loop), before, 1e-15);
  // Fewer than three distinct corners: empty.
  std::vector<Point2d> sliver{{0, 0}, {1, 0}, {1 + 1e-17, 1e-17}, {2, 0}};
  tidy_convex(sliver);
  EXPECT_TRUE(sliver.empty());
}

TEST(Convex2d, NegligiblePiecesAreDropped) {
  // A cutter that leaves a strip 1e-12 wide along the base's edge: with a threshold above the
  // strip's area it is dropped, below it kept.
  const Loop2d base = square(0, 0, 1);
  const Loop2d cutter = {{-1, 1e-12}, {2, 1e-12}, {2, 2}, {-1, 2}};
  ConvexScratch scratch;
  ConvexPieces kept, dropped;
  subtract_convex(base, cutter, 0, kept, scratch);
  subtract_convex(base, cutter, 1e-11, dropped, scratch);
  EXPECT_EQ(kept.size(), 1u);
  EXPECT_NEAR(area_of(kept), 1e-12, 1e-16);  // round-off of unit-sized coordinates
  EXPECT_TRUE(dropped.empty());
}

}  // namespace
}  // namespace lambert
