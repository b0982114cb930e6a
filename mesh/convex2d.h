// Convex polygons in the plane, in double precision: half-plane clipping (Sutherland–Hodgman), the
// convex hull, and the difference and union of convex polygons as disjoint convex pieces. Used for
// exact partial visibility (solver/exact_visibility.h), where the pieces' contour integrals give the
// factor of a visible or hidden region: every piece is a closed convex loop, so rounding moves its
// corners by a few ulps but never opens a boundary, and a sliver left by two nearly coincident edges
// costs its own (tiny) area, never a whole edge. CGAL's exact Booleans (mesh/polygon_boolean.h) are
// the second method the tests hold these to.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "mesh/polygon_boolean.h"  // Point2d, Loop2d

namespace lambert {

// Twice the signed area of the triangle (o, a, b): positive where a → b turns left seen from o.
inline double cross2(const Point2d& o, const Point2d& a, const Point2d& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// Signed area (shoelace): positive for a counter-clockwise loop.
double signed_area(std::span<const Point2d> loop);

// One Sutherland–Hodgman pass: the first n vertices of `loop` cut to the left of the line a → b
// (points on it kept), by way of `scratch`, which is swapped with it; returns the count left. A pass
// adds a vertex per crossing: one net for a convex loop, at most n for any.
std::size_t clip_pass(Loop2d& loop, std::size_t n, const Point2d& a, const Point2d& b, Loop2d& scratch);

// The part of `subject` inside convex counter-clockwise `clip`, into `out` (with `scratch` for the
// passes between: no allocation once they have room). The subject keeps its orientation; a subject
// that is not convex may come out with edges doubling back along the clip's boundary, which cancel in
// a contour sum.
void clip_convex_into(std::span<const Point2d> subject, std::span<const Point2d> clip, Loop2d& out, Loop2d& scratch);
Loop2d clip_convex(const Loop2d& subject, const Loop2d& clip);

// The convex hull of `points` (reordered), counter-clockwise, without collinear or nearly coincident
// points (Andrew's monotone chain; vertices within 1e-9 of the hull's size of their neighbour are
// merged, and any vertex where the boundary does not turn left is dropped); fewer than 3: empty.
void convex_hull(std::vector<Point2d>& points, std::vector<Point2d>& hull);

// Makes a nearly convex counter-clockwise loop (a hull, or a piece cut by half-planes, whose corners
// on a cut may nearly coincide) strictly convex: vertices within 1e-9 of its size of the one before
// are merged and every vertex where the boundary does not turn left is dropped, so that each edge has
// a direction and can serve as a clipper; fewer than 3 left: empty.
void tidy_convex(std::vector<Point2d>& loop);

// Convex polygons stored back to back: polygon i is vertices[start[i], start[i + 1]), counter-clockwise.
struct ConvexPieces {
  std::vector<Point2d> vertices;
  std::vector<int> start{0};
  std::size_t size() const { return start.size() - 1; }
  bool empty() const { return start.size() == 1; }
  std::span<const Point2d> operator[](std::size_t i) const {
    return {vertices.data() + start[i], vertices.data() + start[i + 1]};
  }
  void clear() {
    vertices.clear();
    start.assign(1, 0);
  }
  void add(std::span<const Point2d> polygon) {
    vertices.insert(vertices.end(), polygon.begin(), polygon.end());
    start.push_back(static_cast<int>(vertices.size()));
  }
};

// Work space for the operations below (kept by the caller: no allocation once it has room).
struct ConvexScratch {
  Loop2d rest, part, pass;
  ConvexPieces a, b;
  std::vector<std::array<Point2d, 2>> boxes;  // lower and upper corners
};

// Appends to `out` the part of convex counter-clockwise `piece` outside convex counter-clockwise
// `cutter`, as at most |cutter| disjoint convex pieces: the part beyond the cutter's first edge, then
// the part inside that edge but beyond the second, and so on; what is inside every edge is left out.
// Pieces of area at most `negligible` are dropped. A piece that lies beyond one of the cutter's edges
// (or whose box misses the cutter's) is appended whole, with no clip.
void subtract_convex(std::span<const Point2d> piece, std::span<const Point2d> cutter, double negligible,
                     ConvexPieces& out, ConvexScratch& scratch);

// `base` ∖ ∪ cutters (all convex, counter-clockwise) as disjoint convex pieces, into `out` (which is
// not one of the scratch's).
void convex_difference_pieces(std::span<const Point2d> base, const ConvexPieces& cutters, double negligible,
                              ConvexPieces& out, ConvexScratch& scratch);

// ∪ polygons (convex, counter-clockwise, possibly overlapping) as disjoint convex pieces, into `out`
// (not one of the scratch's):
// each polygon less the ones before it. Taking larger polygons first leaves fewer pieces (a small
// polygon inside a larger one then vanishes whole), so callers pass them in that order.
void convex_union_pieces(const ConvexPieces& polygons, double negligible, ConvexPieces& out, ConvexScratch& scratch);

}  // namespace lambert
