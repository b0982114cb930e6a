// Convex polygons in the plane; see convex2d.h.
#include "mesh/convex2d.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace lambert {

double signed_area(std::span<const Point2d> loop) {
  double a = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Point2d& u = loop[i];
    const Point2d& w = loop[i + 1 < n ? i + 1 : 0];
    a += u[0] * w[1] - w[0] * u[1];
  }
  return 0.5 * a;
}

// Written by index into room made before the pass (with push_back and a modulo per vertex the clip was
// 7 % of a solve with solver.exact_visibility).
std::size_t clip_pass(Loop2d& loop, std::size_t n, const Point2d& a, const Point2d& b, Loop2d& scratch) {
  if (scratch.size() < 2 * n) scratch.resize(2 * n);
  const double ex = b[0] - a[0], ey = b[1] - a[1];
  auto side = [&](const Point2d& q) { return ex * (q[1] - a[1]) - ey * (q[0] - a[0]); };
  std::size_t k = 0;
  const Point2d* u = &loop[n - 1];  // the closing edge first: (loop[n−1], loop[0]) leads the loop
  double su = side(*u);
  for (std::size_t i = 0; i < n; ++i) {
    const Point2d& w = loop[i];
    const double sw = side(w);
    if ((su >= 0) != (sw >= 0)) {
      const double t = su / (su - sw);
      scratch[k++] = {(*u)[0] + (w[0] - (*u)[0]) * t, (*u)[1] + (w[1] - (*u)[1]) * t};
    }
    if (sw >= 0) scratch[k++] = w;
    u = &w, su = sw;
  }
  loop.swap(scratch);
  return k;
}

void clip_convex_into(std::span<const Point2d> subject, std::span<const Point2d> clip, Loop2d& out, Loop2d& scratch) {
  if (out.size() < subject.size()) out.resize(subject.size());
  std::copy(subject.begin(), subject.end(), out.begin());
  std::size_t n = subject.size();
  for (std::size_t e = 0, m = clip.size(); e < m && n >= 3; ++e)
    n = clip_pass(out, n, clip[e], clip[e + 1 < m ? e + 1 : 0], scratch);
  out.resize(n);
}

Loop2d clip_convex(const Loop2d& subject, const Loop2d& clip) {
  Loop2d out, scratch;
  clip_convex_into(subject, clip, out, scratch);
  return out;
}

void convex_hull(std::vector<Point2d>& points, std::vector<Point2d>& hull) {
  hull.clear();
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return;
  hull.resize(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {  // lower hull
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // upper hull
    while (k >= lower && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);  // the last point is the first
  tidy_convex(hull);
}

void tidy_convex(std::vector<Point2d>& loop) {
  if (loop.size() < 3) {
    loop.clear();
    return;
  }
  // Vertices within 1e-9 of the loop's size of the one kept before are dropped: as a clipper an edge
  // whose direction is rounding cuts at a random angle.
  const auto distance2 = [](const Point2d& a, const Point2d& b) {
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
  };
  double size2 = 0;
  for (const Point2d& y : loop) size2 = std::max(size2, distance2(y, loop[0]));
  std::size_t m = 0;
  for (const Point2d& y : loop)
    if (m == 0 || distance2(y, loop[m - 1]) > 1e-18 * size2) loop[m++] = y;
  while (m > 1 && distance2(loop[m - 1], loop[0]) <= 1e-18 * size2) --m;
  loop.resize(m);
  // Where two points differ by rounding (one corner of a shadow reached from two faces, or a clip
  // through a corner), the edge between them has no direction, the turn there is a coin toss, and
  // once one of them is dropped above the vertex before can be reflex: a plate's shadow (two pairs
  // of its points 2e-16 apart) came out of the hull's chain pinched, hiding 60 % less at that node.
  // So every vertex where the boundary does not turn left is dropped, until none is left.
  for (bool dropped = true; dropped && loop.size() >= 3;) {
    dropped = false;
    for (std::size_t i = 0; i < loop.size() && loop.size() >= 3;) {
      const std::size_t size = loop.size();
      if (cross2(loop[(i + size - 1) % size], loop[i], loop[(i + 1) % size]) <= 0) {
        loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
        dropped = true;
      } else {
        ++i;
      }
    }
  }
  if (loop.size() < 3) loop.clear();
}

namespace {

using Box2 = std::array<Point2d, 2>;  // lower and upper corners

Box2 box_of(std::span<const Point2d> polygon) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Box2 box{Point2d{kInf, kInf}, Point2d{-kInf, -kInf}};
  for (const Point2d& y : polygon)
    for (int a = 0; a < 2; ++a) box[0][a] = std::min(box[0][a], y[a]), box[1][a] = std::max(box[1][a], y[a]);
  return box;
}

// Boxes that at most touch: polygons inside them share no area.
bool apart(const Box2& u, const Box2& w) {
  return u[0][0] >= w[1][0] || w[0][0] >= u[1][0] || u[0][1] >= w[1][1] || w[0][1] >= u[1][1];
}

}  // namespace

void subtract_convex(std::span<const Point2d> piece, std::span<const Point2d> cutter, double negligible,
                     ConvexPieces& out, ConvexScratch& scratch) {
  const std::size_t m = cutter.size();
  bool disjoint = m < 3 || apart(box_of(piece), box_of(cutter));
  // Beyond one of the cutter's edges (every corner on its outer side or on it): untouched.
  for (std::size_t e = 0; e < m && !disjoint; ++e) {
    const Point2d& a = cutter[e];
    const Point2d& b = cutter[e + 1 < m ? e + 1 : 0];
    disjoint = std::all_of(piece.begin(), piece.end(), [&](const Point2d& q) { return cross2(a, b, q) <= 0; });
  }
  if (disjoint) {
    out.add(piece);
    return;
  }
  // Peel the piece edge by edge: what lies beyond edge e (and inside the edges before it) is a piece
  // of the difference; what lies inside goes on to the next edge; what is inside all of them is the
  // cutter's. Both sides of an edge are cut by the same pass with its direction reversed, so the
  // corners on the cut are the same numbers on both sides.
  Loop2d& rest = scratch.rest;
  Loop2d& part = scratch.part;
  if (rest.size() < piece.size()) rest.resize(piece.size());
  std::copy(piece.begin(), piece.end(), rest.begin());
  std::size_t n = piece.size();
  for (std::size_t e = 0; e < m && n >= 3; ++e) {
    const Point2d& a = cutter[e];
    const Point2d& b = cutter[e + 1 < m ? e + 1 : 0];
    if (std::all_of(rest.begin(), rest.begin() + static_cast<std::ptrdiff_t>(n),
                    [&](const Point2d& q) { return cross2(a, b, q) >= 0; }))
      continue;  // nothing of it beyond this edge
    if (part.size() < n) part.resize(n);
    std::copy(rest.begin(), rest.begin() + static_cast<std::ptrdiff_t>(n), part.begin());
    const std::size_t beyond = clip_pass(part, n, b, a, scratch.pass);
    const std::span<const Point2d> outside(part.data(), beyond);
    if (beyond >= 3 && signed_area(outside) > negligible) out.add(outside);
    n = clip_pass(rest, n, a, b, scratch.pass);
  }
}

void convex_difference_pieces(std::span<const Point2d> base, const ConvexPieces& cutters, double negligible,
                              ConvexPieces& out, ConvexScratch& scratch) {
  ConvexPieces* current = &scratch.a;
  ConvexPieces* next = &scratch.b;
  current->clear();
  current->add(base);
  for (std::size_t c = 0; c < cutters.size() && !current->empty(); ++c) {
    next->clear();
    for (std::size_t i = 0; i < current->size(); ++i) subtract_convex((*current)[i], cutters[c], negligible, *next, scratch);
    std::swap(current, next);
  }
  out.clear();
  for (std::size_t i = 0; i < current->size(); ++i) out.add((*current)[i]);
}

void convex_union_pieces(const ConvexPieces& polygons, double negligible, ConvexPieces& out, ConvexScratch& scratch) {
  out.clear();
  std::vector<Box2>& boxes = scratch.boxes;
  boxes.resize(polygons.size());
  for (std::size_t i = 0; i < polygons.size(); ++i) boxes[i] = box_of(polygons[i]);
  ConvexPieces* current = &scratch.a;
  ConvexPieces* next = &scratch.b;
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    current->clear();
    current->add(polygons[i]);
    for (std::size_t j = 0; j < i && !current->empty(); ++j) {
      if (apart(boxes[i], boxes[j])) continue;
      next->clear();
      for (std::size_t k = 0; k < current->size(); ++k) subtract_convex((*current)[k], polygons[j], negligible, *next, scratch);
      std::swap(current, next);
    }
    for (std::size_t k = 0; k < current->size(); ++k) out.add((*current)[k]);
  }
}

}  // namespace lambert
