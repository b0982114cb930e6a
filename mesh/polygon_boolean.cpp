// CGAL side of mesh/polygon_boolean.h.
#include "mesh/polygon_boolean.h"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/convex_hull_2.h>

#include <iterator>

namespace lambert {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point2 = K::Point_2;
using Polygon2 = CGAL::Polygon_2<K>;
using PolygonWithHoles2 = CGAL::Polygon_with_holes_2<K>;
using PolygonSet2 = CGAL::Polygon_set_2<K>;

// Counter-clockwise convex hull without repeated or collinear vertices; empty if it spans no area.
Polygon2 convex_polygon(const Loop2d& loop) {
  std::vector<Point2> points, hull;
  points.reserve(loop.size());
  for (const Point2d& p : loop) points.emplace_back(p[0], p[1]);
  CGAL::convex_hull_2(points.begin(), points.end(), std::back_inserter(hull));
  if (hull.size() < 3) return {};
  return Polygon2(hull.begin(), hull.end());
}

Loop2d to_loop(const Polygon2& polygon) {
  Loop2d loop;
  loop.reserve(polygon.size());
  for (const Point2& p : polygon.vertices()) loop.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y())});
  return loop;
}

}  // namespace

std::vector<Loop2d> convex_difference(const Loop2d& base, std::span<const Loop2d> cutters) {
  const Polygon2 base_polygon = convex_polygon(base);
  if (base_polygon.is_empty()) return {};
  std::vector<Polygon2> cut;
  for (const Loop2d& c : cutters) {
    Polygon2 polygon = convex_polygon(c);
    if (!polygon.is_empty()) cut.push_back(std::move(polygon));
  }
  if (cut.empty()) return {to_loop(base_polygon)};
  PolygonSet2 removed;
  removed.join(cut.begin(), cut.end());
  PolygonSet2 region(base_polygon);
  region.difference(removed);
  std::vector<PolygonWithHoles2> pieces;
  region.polygons_with_holes(std::back_inserter(pieces));
  std::vector<Loop2d> loops;
  for (const PolygonWithHoles2& piece : pieces) {
    loops.push_back(to_loop(piece.outer_boundary()));
    for (auto hole = piece.holes_begin(); hole != piece.holes_end(); ++hole) loops.push_back(to_loop(*hole));
  }
  return loops;
}

std::vector<std::vector<Loop2d>> convex_union(std::span<const Loop2d> parts) {
  std::vector<Polygon2> polygons;
  for (const Loop2d& part : parts) {
    Polygon2 polygon = convex_polygon(part);
    if (!polygon.is_empty()) polygons.push_back(std::move(polygon));
  }
  if (polygons.empty()) return {};
  PolygonSet2 all;
  all.join(polygons.begin(), polygons.end());
  std::vector<PolygonWithHoles2> pieces;
  all.polygons_with_holes(std::back_inserter(pieces));
  std::vector<std::vector<Loop2d>> out;
  for (const PolygonWithHoles2& piece : pieces) {
    std::vector<Loop2d>& loops = out.emplace_back();
    loops.push_back(to_loop(piece.outer_boundary()));
    for (auto hole = piece.holes_begin(); hole != piece.holes_end(); ++hole) loops.push_back(to_loop(*hole));
  }
  return out;
}

}  // namespace lambert
