// Tests of mesh/mesh_ops.h: polygon triangulation and mesh checks (CGAL) and subdivision (OpenMesh);
// mesh files are tested in mesh_file_test.cpp. Expected areas come from closed forms (shoelace, box and tetrahedron
// surface areas) written next to each number.
#include "mesh/mesh_ops.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include "tests/test_geometry.h"

namespace lambert {
namespace {

const std::string kData = std::string(LAMBERT_SOURCE_DIR) + "/tests/data/";

double total_area(const TriangleMesh& m) {
  double a = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) a += m.triangle(t).area();
  return a;
}

// Shoelace formula for a polygon in the xy-plane (positive when counter-clockwise).
double shoelace(const std::vector<Point3>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Point3 &u = p[i], &v = p[(i + 1) % p.size()];
    a += u.x * v.y - v.x * u.y;
  }
  return 0.5 * a;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// ---- distance_to_triangle (mesh/geometry.h) ---------------------------------------------------

TEST(DistanceToTriangle, EachVoronoiRegionAgainstAFineSearch) {
  // Second method: the smallest distance to a 400 × 400 grid of the triangle's points, refined
  // around its best point; the two agree to the grid's resolution, and the function is never above
  // the search (it is the minimum over the whole triangle). Points over the interior, beside each
  // edge and beyond each corner are all met; and the regions' closed forms where they are simple.
  const Triangle t{{Point3{0, 0, 0}, Point3{2, 0, 0.5}, Point3{0.3, 1.5, -0.2}}};
  EXPECT_NEAR(distance_to_triangle(Point3{0, 0, 0}, t), 0, 1e-15);
  EXPECT_NEAR(distance_to_triangle(Point3{-1, -1, 0}, t), std::sqrt(2.0), 1e-12);  // beyond corner 0
  EXPECT_NEAR(distance_to_triangle(t.centroid() + t.normal() * 0.7, t), 0.7, 1e-12);  // over the interior
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(-2, 3);
  for (int k = 0; k < 300; ++k) {
    const Point3 p{u(random), u(random), u(random)};
    double best = 1e300, ba = 0, bb = 0;
    for (int i = 0; i <= 400; ++i)
      for (int j = 0; i + j <= 400; ++j) {
        const double d = distance(p, barycentric(t.v[0], t.v[1], t.v[2], 1 - (i + j) / 400.0, i / 400.0, j / 400.0));
        if (d < best) best = d, ba = i / 400.0, bb = j / 400.0;
      }
    for (int i = -50; i <= 50; ++i)  // refine around the grid's best point
      for (int j = -50; j <= 50; ++j) {
        const double a = std::clamp(ba + i * 5e-5, 0.0, 1.0), b = std::clamp(bb + j * 5e-5, 0.0, 1.0 - a);
        best = std::min(best, distance(p, barycentric(t.v[0], t.v[1], t.v[2], 1 - a - b, a, b)));
      }
    const double d = distance_to_triangle(p, t);
    EXPECT_LE(d, best + 1e-12) << k;
    EXPECT_NEAR(d, best, 1e-7) << k;
  }
}

// ---- triangulate_polygon ------------------------------------------------------------------

// Checks a triangulation of a polygon: n - 2 triangles, areas summing to `area`, every
// triangle facing along `normal`, every vertex an original one (bitwise).
void expect_triangulation(const std::vector<Point3>& polygon, const PolygonTriangulation& r,
                          double area, const Vector3& normal) {
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.mesh.triangles.size(), polygon.size() - 2);  // Euler: simple n-gon, no Steiner points
  ASSERT_EQ(r.mesh.vertices.size(), polygon.size());
  for (std::size_t i = 0; i < polygon.size(); ++i) EXPECT_EQ(r.mesh.vertices[i], polygon[i]);
  EXPECT_NEAR(total_area(r.mesh), area, 1e-12 * std::max(1.0, area));
  for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    EXPECT_GT(r.mesh.triangle(t).area(), 0) << "triangle " << t;
    EXPECT_GT(dot(r.mesh.triangle(t).normal(), normal), 0.999) << "triangle " << t;
  }
}

TEST(TriangulatePolygon, UnitSquareCounterClockwiseFacesPlusZ) {
  const std::vector<Point3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  expect_triangulation(square, triangulate_polygon(square), 1.0, {0, 0, 1});
}

TEST(TriangulatePolygon, ClockwiseSquareFacesMinusZ) {
  // The vertex order defines the front: clockwise seen from +z means the normal is -z.
  const std::vector<Point3> square{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
  expect_triangulation(square, triangulate_polygon(square), 1.0, {0, 0, -1});
}

TEST(TriangulatePolygon, TiltedConcaveLShape) {
  // L = [0,2]x[0,1] + [0,1]x[1,2], area 3 (shoelace), placed in a tilted plane spanned by the
  // orthonormal u, v; the notch [1,2]x[1,2] must stay uncovered.
  const std::vector<std::pair<double, double>> l2{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const Vector3 u = normalize(Vector3{1, 1, 0}), v = normalize(Vector3{-1, 1, 1});
  const Vector3 n = cross(u, v);
  const Point3 origin{0.3, -1.2, 2.5};
  std::vector<Point3> l3;
  for (auto [a, b] : l2) l3.push_back(origin + u * a + v * b);
  const PolygonTriangulation r = triangulate_polygon(l3);
  expect_triangulation(l3, r, 3.0, n);
  for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    const Vector3 c = r.mesh.triangle(t).centroid() - origin;
    const double a = dot(c, u), b = dot(c, v);
    EXPECT_FALSE(a > 1 && b > 1) << "triangle " << t << " covers the notch";
  }
}

TEST(TriangulatePolygon, FivePointedStar) {
  // Alternating radii R = 2, r = 1 at 36 degree steps: 10 triangles (centre, i, i+1) of area
  // R r sin(36 deg) / 2 each, total 5 R r sin(pi/5) = 5.877852522924732.
  std::vector<Point3> star;
  for (int i = 0; i < 10; ++i) {
    const double radius = i % 2 == 0 ? 2.0 : 1.0, angle = i * std::numbers::pi / 5;
    star.push_back({radius * std::cos(angle), radius * std::sin(angle), 1.5});
  }
  const double expected = 5 * 2.0 * 1.0 * std::sin(std::numbers::pi / 5);
  EXPECT_NEAR(shoelace(star), expected, 1e-12);
  expect_triangulation(star, triangulate_polygon(star), expected, {0, 0, 1});
}

TEST(TriangulatePolygon, CollinearMiddleVerticesAreKept) {
  // A unit square with extra vertices in the middle of two edges: still area 1, and no
  // zero-area triangle may be produced along the straight edges.
  const std::vector<Point3> p{{0, 0, 0}, {0.5, 0, 0}, {1, 0, 0}, {1, 0.5, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_DOUBLE_EQ(shoelace(p), 1.0);
  expect_triangulation(p, triangulate_polygon(p), 1.0, {0, 0, 1});
}

TEST(TriangulatePolygon, NonPlanarNamesTheVertex) {
  // A planar hexagon with vertex 3 lifted by 0.1 m: far beyond 1e-6 of the 2 m diameter.
  std::vector<Point3> p;
  for (int i = 0; i < 6; ++i) p.push_back({std::cos(i * std::numbers::pi / 3), std::sin(i * std::numbers::pi / 3), 0});
  p[3].z = 0.1;
  const PolygonTriangulation r = triangulate_polygon(p);
  EXPECT_TRUE(contains(r.error, "non-planar: vertex 3 is")) << r.error;
  // A looser tolerance (0.1 of the diameter) accepts it.
  EXPECT_TRUE(triangulate_polygon(p, 0.1).ok());
}

TEST(TriangulatePolygon, SymmetricBowTieIsSelfIntersecting) {
  // Zero signed area, but not collinear: edges 0-1 and 2-3 cross at (0.5, 0.5).
  const std::vector<Point3> p{{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}};
  const PolygonTriangulation r = triangulate_polygon(p);
  EXPECT_TRUE(contains(r.error, "self-intersecting: edge 0-1 meets edge 2-3")) << r.error;
}

TEST(TriangulatePolygon, AsymmetricBowTieIsSelfIntersecting) {
  const std::vector<Point3> p{{0, 0, 0}, {2, 2, 0}, {2, 0, 0}, {0, 1, 0}};
  const PolygonTriangulation r = triangulate_polygon(p);
  EXPECT_TRUE(contains(r.error, "self-intersecting: edge 0-1 meets edge 2-3")) << r.error;
}

TEST(TriangulatePolygon, VertexOnAnotherEdgeIsSelfIntersecting) {
  // Vertex 4 = (1, 0) touches edge 0-1 = (0,0)-(2,0): not simple.
  const std::vector<Point3> p{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {1, 2, 0}, {1, 0, 0}, {0, 2, 0}};
  const PolygonTriangulation r = triangulate_polygon(p);
  EXPECT_TRUE(contains(r.error, "self-intersecting")) << r.error;
}

TEST(TriangulatePolygon, RepeatedVertices) {
  const std::vector<Point3> p{{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(triangulate_polygon(p).error, "vertex 2 repeats vertex 1");
  const std::vector<Point3> closed{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}};
  const std::string e = triangulate_polygon(closed).error;
  EXPECT_TRUE(contains(e, "vertex 3 repeats vertex 0") && contains(e, "last vertex equals the first")) << e;
}

TEST(TriangulatePolygon, TooFewVerticesAndCollinear) {
  EXPECT_TRUE(contains(triangulate_polygon({{0, 0, 0}, {1, 0, 0}}).error, "at least 3 vertices"));
  EXPECT_TRUE(contains(triangulate_polygon({}).error, "at least 3 vertices"));
  const PolygonTriangulation r = triangulate_polygon({{0, 0, 0}, {1, 1, 1}, {3, 3, 3}, {2, 2, 2}});
  EXPECT_TRUE(contains(r.error, "collinear")) << r.error;
  const PolygonTriangulation nan = triangulate_polygon({{0, 0, 0}, {1, std::nan(""), 0}, {0, 1, 0}});
  EXPECT_EQ(nan.error, "vertex 1 has a non-finite coordinate");
}

// ---- check_mesh ---------------------------------------------------------------------------

// Unit cube [0,1]^3, 12 triangles counter-clockwise seen from outside.
TriangleMesh unit_cube() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

TEST(CheckMesh, ClosedCubeIsHealthy) {
  const TriangleMesh cube = unit_cube();
  // Outward normals: the divergence theorem gives volume = sum(centroid . area vector) / 3 = 1.
  double volume = 0;
  for (std::size_t t = 0; t < cube.triangles.size(); ++t)
    volume += dot(to_vector(cube.triangle(t).centroid()), cube.triangle(t).area_vector()) / 3;
  ASSERT_NEAR(volume, 1.0, 1e-15);
  const MeshHealth h = check_mesh(cube);
  EXPECT_TRUE(h.degenerate_triangles.empty());
  EXPECT_TRUE(h.self_intersections.empty());  // neighbours touch only along shared edges/corners
  EXPECT_TRUE(h.consistently_oriented);
  EXPECT_TRUE(h.manifold);
  EXPECT_EQ(h.boundary_edges, 0);
}

TEST(CheckMesh, CubeWithUnsharedCornersIsStillClosed) {
  // Each triangle with its own copies of its corners (as in many OBJ exports): positions are
  // welded, so the cube is still closed and consistent.
  const TriangleMesh cube = unit_cube();
  TriangleMesh soup;
  for (std::size_t t = 0; t < cube.triangles.size(); ++t) {
    const int base = static_cast<int>(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(cube.vertices[cube.triangles[t][k]]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  const MeshHealth h = check_mesh(soup);
  EXPECT_TRUE(h.self_intersections.empty());
  EXPECT_TRUE(h.consistently_oriented);
  EXPECT_EQ(h.boundary_edges, 0);
}

TEST(CheckMesh, FlippedFaceIsInconsistent) {
  TriangleMesh cube = unit_cube();
  std::swap(cube.triangles[5][1], cube.triangles[5][2]);
  const MeshHealth h = check_mesh(cube);
  EXPECT_FALSE(h.consistently_oriented);
  EXPECT_TRUE(h.manifold);
  EXPECT_EQ(h.boundary_edges, 0);
  EXPECT_TRUE(h.self_intersections.empty());
}

TEST(CheckMesh, CrossingTrianglesIntersect) {
  // Triangle 0 in z = 0, triangle 1 in x = 0.5 piercing it; triangle 2 far away.
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},  {0.5, 0.1, -1}, {0.5, 0.1, 1},
                {0.5, 0.5, 0}, {5, 5, 5}, {6, 5, 5}, {5, 6, 5}};
  m.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  const MeshHealth h = check_mesh(m);
  ASSERT_EQ(h.self_intersections.size(), 1u);
  EXPECT_EQ(h.self_intersections[0], std::make_pair(0, 1));
  EXPECT_EQ(h.boundary_edges, 9);
}

TEST(CheckMesh, TrianglesSharingAVertexOrEdgeOnlyTouch) {
  // Fan around vertex 0 in the plane (edge neighbours), plus a triangle touching only vertex 0
  // from above: none of these pairs intersects beyond what they share.
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, 0, 1}, {1, 1, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 4, 5}};
  EXPECT_TRUE(check_mesh(m).self_intersections.empty());
  // Folding triangle 1 onto triangle 0 (same side of the shared edge 0-2) makes them overlap.
  m.vertices[3] = {0.5, 0.2, 0};
  const MeshHealth h = check_mesh(m);
  ASSERT_EQ(h.self_intersections.size(), 1u);
  EXPECT_EQ(h.self_intersections[0], std::make_pair(0, 1));
  // A triangle sharing vertex 0 that dips through triangle 0 intersects it.
  m.vertices[3] = {-1, 0, 0};
  m.vertices[4] = {0.3, 0.3, -1};
  m.vertices[5] = {0.3, 0.3, 1};
  EXPECT_EQ(check_mesh(m).self_intersections, (std::vector<std::pair<int, int>>{{0, 2}}));
}

TEST(CheckMesh, CoplanarOverlaps) {
  // Triangle 0 = unit right triangle in z = 0. Triangle 1 shares vertex 0 and lies in the same
  // plane, overlapping it; triangle 2 shares nothing and overlaps triangle 0 too; triangle 3 is
  // coplanar but separate; triangle 4 is coplanar and touches triangle 0 only at vertex 0.
  TriangleMesh m;
  m.vertices = {{0, 0, 0},  {1, 0, 0},     {0, 1, 0},  {1, 0.2, 0}, {0.2, 1, 0}, {0.1, 0.1, 0},
                {0.9, 0.05, 0}, {0.05, 0.9, 0}, {2, 2, 0}, {3, 2, 0}, {2, 3, 0}, {-1, 0, 0}, {0, -1, 0}};
  m.triangles = {{0, 1, 2}, {0, 3, 4}, {5, 6, 7}, {8, 9, 10}, {0, 12, 11}};
  // Pairs: 0-1 (overlap), 0-2 (2 inside 0), 1-2 (both near the origin).
  EXPECT_EQ(check_mesh(m).self_intersections,
            (std::vector<std::pair<int, int>>{{0, 1}, {0, 2}, {1, 2}}));
}

TEST(CheckMesh, TJunctionsTouchButDoNotIntersect) {
  // Non-conforming meshes: a floor strip ending in the middle of a perpendicular wall triangle's
  // bottom edge, a coplanar T-junction (two small triangles along one big triangle's edge), and a
  // triangle standing with its edge on another's interior. None shares a vertex index with the
  // other; all only touch. A triangle pushed 1 mm through the floor does cross it.
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 0, 1},                  // 0: wall in y = 0, edge along x
                {0.5, 0, 0}, {1.5, 0, 0}, {1, 1, 0},              // 1: floor triangle on the wall's edge
                {0, -1, 0}, {2, -1, 0}, {1, -2, 0},               // 2: big floor triangle, edge y = -1
                {0, -1, 0.0}, {1, -1, 0}, {0.5, -0.5, 0},         // 3, 4: small ones on that edge
                {1, -1, 0}, {2, -1, 0}, {1.5, -0.5, 0},
                {0.8, -1.5, 0}, {1.2, -1.5, 0}, {1, -1.5, 0.5}};  // 5: stands on triangle 2
  m.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 8, 7}, {9, 10, 11}, {12, 13, 14}, {15, 16, 17}};
  EXPECT_TRUE(check_mesh(m).self_intersections.empty());
  m.vertices[15].z = m.vertices[16].z = -0.001;
  EXPECT_EQ(check_mesh(m).self_intersections, (std::vector<std::pair<int, int>>{{2, 5}}));
}

TEST(CheckMesh, DegenerateTrianglesAreReportedWithoutCrashing) {
  TriangleMesh m = unit_cube();
  m.vertices.push_back({0.5, 0, 0});                  // on the edge 0-1
  m.triangles.push_back({0, 1, 8});                   // 12: collinear corners (zero area)
  m.triangles.push_back({2, 2, 3});                   // 13: repeated index
  m.triangles.push_back({0, 1, 99});                  // 14: index out of range
  const MeshHealth h = check_mesh(m);
  EXPECT_EQ(h.degenerate_triangles, (std::vector<int>{12, 13, 14}));
  EXPECT_TRUE(h.self_intersections.empty());
}

TEST(CheckMesh, FinIsNonManifold) {
  // Three triangles on the edge 0-1, meeting only along it.
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshHealth h = check_mesh(m);
  EXPECT_FALSE(h.manifold);
  EXPECT_TRUE(h.self_intersections.empty());
  EXPECT_EQ(h.boundary_edges, 6);  // the two free edges of each triangle
}

// ---- subdivide_to_max_area ----------------------------------------------------------------

// Volume by the divergence theorem: positive when all faces face outwards.
double signed_volume(const TriangleMesh& m) {
  double v = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    v += dot(to_vector(m.triangle(t).centroid()), m.triangle(t).area_vector()) / 3;
  return v;
}

TriangleMesh unit_square() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

// Undirected edge -> number of triangles using it.
std::map<std::pair<int, int>, int> edge_uses(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  return uses;
}

double min_angle(const Triangle& t) {
  double smallest = std::numbers::pi;
  for (int k = 0; k < 3; ++k) {
    const Vector3 a = t.v[(k + 1) % 3] - t.v[k], b = t.v[(k + 2) % 3] - t.v[k];
    smallest = std::min(smallest, std::acos(dot(a, b) / (length(a) * length(b))));
  }
  return smallest;
}

TEST(Subdivide, UnitSquareIsConformingAndKeepsArea) {
  const double max_area = 0.01;
  const SubdividedMesh s = subdivide_to_max_area_with_parents(unit_square(), max_area);
  const TriangleMesh& m = s.mesh;
  // Halving from 1/2 gives areas 1/2^k; the first <= 0.01 is 1/128, so exactly 128 triangles.
  EXPECT_EQ(m.triangles.size(), 128u);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    EXPECT_LE(m.triangle(t).area(), max_area);
    EXPECT_GT(m.triangle(t).area_vector().z, 0) << "orientation of triangle " << t;
  }
  EXPECT_NEAR(total_area(m), 1.0, 1e-12);
  // Conforming: an edge used once lies on the square's boundary; interior edges are used twice.
  for (const auto& [e, n] : edge_uses(m)) {
    const Point3 a = m.vertices[e.first], b = m.vertices[e.second];
    const bool on_boundary = (a.x == b.x && (a.x == 0 || a.x == 1)) || (a.y == b.y && (a.y == 0 || a.y == 1));
    EXPECT_EQ(n, on_boundary ? 1 : 2) << "edge " << e.first << "-" << e.second;
  }
  // Input vertices keep their indices; children are grouped by parent in input order.
  for (int i = 0; i < 4; ++i) EXPECT_EQ(m.vertices[i], unit_square().vertices[i]);
  ASSERT_EQ(s.parent.size(), m.triangles.size());
  EXPECT_TRUE(std::is_sorted(s.parent.begin(), s.parent.end()));
  EXPECT_EQ(std::count(s.parent.begin(), s.parent.end(), 0), 64);
  // Each child lies in its parent: the parent triangle {0,1,2} is the half y <= x.
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Point3 c = m.triangle(t).centroid();
    EXPECT_EQ(s.parent[t], c.y < c.x ? 0 : 1) << "triangle " << t;
  }
}

TEST(Subdivide, SliverKeepsRivaraAngleBound) {
  // 100:1 right triangle, smallest angle atan(1/100). Longest-edge bisection keeps every angle
  // >= half the smallest initial angle (Rivara 1984).
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {100, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  const double alpha0 = min_angle(m.triangle(0));
  ASSERT_NEAR(alpha0, std::atan(0.01), 1e-13);
  const TriangleMesh s = subdivide_to_max_area(m, 0.5);  // area 50 -> at least 100 patches
  EXPECT_GE(s.triangles.size(), 100u);
  EXPECT_NEAR(total_area(s), 50.0, 1e-10);
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    EXPECT_LE(s.triangle(t).area(), 0.5);
    EXPECT_GE(min_angle(s.triangle(t)), alpha0 / 2 - 1e-12);
    EXPECT_GT(s.triangle(t).area_vector().z, 0);
  }
}

TEST(Subdivide, SliversAreSplitForLengthWellShapedPatchesAreNot) {
  // A sliver below the area limit (40 × 0.05, area 1, limit 2) is still split until its longest
  // edge is at most √(8 · 2) = 4; a right isosceles triangle of area 1.9 (edges up to √7.6) and the
  // unit square's halves at limit 0.5 are left as they are.
  TriangleMesh sliver;
  sliver.vertices = {{0, 0, 0}, {40, 0, 0}, {0, 0.05, 0}};
  sliver.triangles = {{0, 1, 2}};
  const TriangleMesh s = subdivide_to_max_area(sliver, 2.0);
  EXPECT_GE(s.triangles.size(), 10u);
  EXPECT_NEAR(total_area(s), 1.0, 1e-12);
  for (std::size_t t = 0; t < s.triangles.size(); ++t) EXPECT_LE(s.triangle(t).max_edge_length(), 4 + 1e-12);
  TriangleMesh right;
  const double leg = std::sqrt(3.8);
  right.vertices = {{0, 0, 0}, {leg, 0, 0}, {0, leg, 0}};
  right.triangles = {{0, 1, 2}};
  EXPECT_EQ(subdivide_to_max_area(right, 2.0).triangles.size(), 1u);
  EXPECT_EQ(subdivide_to_max_area(unit_square(), 0.5).triangles.size(), 2u);
}

TEST(Subdivide, OrientationFollowsEachParent) {
  // A closed cube: every child must face outwards like its parent (normal agrees).
  const TriangleMesh cube = unit_cube();
  const SubdividedMesh s = subdivide_to_max_area_with_parents(cube, 0.02);
  EXPECT_NEAR(total_area(s.mesh), 6.0, 1e-12);
  EXPECT_NEAR(signed_volume(s.mesh), 1.0, 1e-12);
  for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) {
    EXPECT_GT(dot(s.mesh.triangle(t).normal(), cube.triangle(s.parent[t]).normal()), 0.999999);
    EXPECT_LE(s.mesh.triangle(t).area(), 0.02);
  }
  const MeshHealth h = check_mesh(s.mesh);
  EXPECT_EQ(h.boundary_edges, 0);  // conforming across the cube's edges too
  EXPECT_TRUE(h.consistently_oriented);
}

TEST(Subdivide, SoupWithFlippedFaceAndFinLosesNothing) {
  // A cube with one flipped triangle, plus a fin on the edge 0-1: OpenMesh cannot add all of
  // them to one surface; those are bisected alone. Nothing may be lost or flipped.
  TriangleMesh m = unit_cube();
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  m.vertices.push_back({0.5, -1, -1});
  m.triangles.push_back({0, 1, 8});
  m.triangles.push_back({1, 1, 2});  // degenerate: passed through unchanged
  const double max_area = 0.05;
  const SubdividedMesh s = subdivide_to_max_area_with_parents(m, max_area);
  ASSERT_EQ(s.parent.size(), s.mesh.triangles.size());
  std::vector<double> area_by_parent(m.triangles.size(), 0);
  for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) {
    const Triangle child = s.mesh.triangle(t), parent = m.triangle(s.parent[t]);
    area_by_parent[s.parent[t]] += child.area();
    EXPECT_LE(child.area(), max_area);
    if (parent.area() > 0) {
      EXPECT_GT(dot(child.normal(), parent.normal()), 0.999999);
    }
  }
  for (std::size_t p = 0; p < m.triangles.size(); ++p)
    EXPECT_NEAR(area_by_parent[p], m.triangle(p).area(), 1e-14) << "parent " << p;
  EXPECT_EQ(s.mesh.triangles.back(), (std::array<int, 3>{1, 1, 2}));
}

TEST(Subdivide, GuardsAndNoOp) {
  const TriangleMesh sq = unit_square();
  for (double bad : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    const TriangleMesh r = subdivide_to_max_area(sq, bad);
    EXPECT_EQ(r.triangles, sq.triangles) << bad;
    EXPECT_EQ(r.vertices, sq.vertices) << bad;
  }
  // Already small enough: unchanged, triangle by triangle.
  EXPECT_EQ(subdivide_to_max_area(sq, 0.5).triangles, sq.triangles);
}

TEST(Subdivide, HundredThousandPatchesFastAndDeterministic) {
  const auto start = std::chrono::steady_clock::now();
  const TriangleMesh a = subdivide_to_max_area(unit_square(), 1e-5);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Areas halve from 1/2: 1/2^17 <= 1e-5 < 1/2^16, so 2^17 = 131072 triangles.
  EXPECT_EQ(a.triangles.size(), 131072u);
  EXPECT_NEAR(total_area(a), 1.0, 1e-12);
  std::printf("subdivision into %zu triangles: %.3f s\n", a.triangles.size(), seconds);
  const TriangleMesh b = subdivide_to_max_area(unit_square(), 1e-5);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.vertices, b.vertices);
}

// A room's walls and a ceiling ring around a light's opening (the issue-4 room) subdivide into the
// same patches, placed the same way, at millimetre and kilometre scale and at geo-referenced
// coordinates: lengths that tie exactly at one scale (isosceles halves of a 2:1 rectangle) differ in
// their last bits at another, and the patches must not depend on which way rounding breaks a tie.
TEST(Subdivide, PatchesDoNotDependOnScaleOrPlacement) {
  const TriangleMesh room{{{0, 0, 0}, {6, 0, 0}, {6, 4, 0}, {0, 4, 0}, {0, 0, 3}, {6, 0, 3}, {6, 4, 3}, {0, 4, 3},
                           {2.5, 1.5, 3}, {3.5, 1.5, 3}, {3.5, 2.5, 3}, {2.5, 2.5, 3}},
                          {{0, 1, 2}, {0, 2, 3}, {0, 4, 5}, {0, 5, 1}, {3, 2, 6}, {3, 6, 7}, {0, 3, 7}, {0, 7, 4},
                           {1, 5, 6}, {1, 6, 2}, {4, 8, 5}, {5, 8, 9}, {5, 9, 6}, {6, 9, 10}, {6, 10, 7},
                           {7, 10, 11}, {7, 11, 4}, {4, 11, 8}}};
  const double max_area = 0.036;
  const TriangleMesh reference = subdivide_to_max_area(room, max_area);
  ASSERT_GT(reference.triangles.size(), 3000u);
  struct Placement {
    double scale;
    Vector3 offset;
  };
  for (const Placement& place : {Placement{1e-3, {0, 0, 0}}, Placement{1e3, {0, 0, 0}}, Placement{0.1, {0, 0, 0}},
                                 Placement{1, {512345.678, 5523456.789, 100}}}) {
    SCOPED_TRACE(testing::Message() << "scale " << place.scale << ", offset " << place.offset.x);
    TriangleMesh moved = room;
    for (Point3& p : moved.vertices) p = Point3{0, 0, 0} + (p - Point3{0, 0, 0}) * place.scale + place.offset;
    const TriangleMesh s = subdivide_to_max_area(moved, max_area * place.scale * place.scale);
    ASSERT_EQ(s.triangles.size(), reference.triangles.size());
    ASSERT_TRUE(s.triangles == reference.triangles);
    ASSERT_EQ(s.vertices.size(), reference.vertices.size());
    double worst = 0;
    for (std::size_t k = 0; k < s.vertices.size(); ++k)
      worst = std::max(worst, length((s.vertices[k] - place.offset - Point3{0, 0, 0}) * (1 / place.scale) -
                                     (reference.vertices[k] - Point3{0, 0, 0})));
    EXPECT_LT(worst, 1e-8);
  }
}

}  // namespace
}  // namespace lambert

namespace lambert {
namespace {

TriangleMesh quad_mesh(const Point3& o, const Vector3& u, const Vector3& v) {
  return {{o, o + u, o + u + v, o + v}, {{0, 1, 2}, {0, 2, 3}}};
}

double mesh_area(const TriangleMesh& m) {
  double a = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) a += m.triangle(t).area();
  return a;
}

// The area of `cut`'s pieces inside the rectangle [x0, x1] × [y0, y1] (in x and y), with a failure
// for any piece that straddles its outline: each must lie wholly inside or wholly outside.
double area_inside_rectangle(const TriangleMesh& cut, double x0, double x1, double y0, double y1) {
  double inside_area = 0;
  for (std::size_t t = 0; t < cut.triangles.size(); ++t) {
    const Triangle tri = cut.triangle(t);
    const Point3 g = tri.centroid();
    const bool inside = g.x > x0 && g.x < x1 && g.y > y0 && g.y < y1;
    for (const Point3& p : tri.v) {
      const bool in_closed = p.x >= x0 - 1e-12 && p.x <= x1 + 1e-12 && p.y >= y0 - 1e-12 && p.y <= y1 + 1e-12;
      const bool out_closed = p.x <= x0 + 1e-12 || p.x >= x1 - 1e-12 || p.y <= y0 + 1e-12 || p.y >= y1 - 1e-12;
      EXPECT_TRUE(inside ? in_closed : out_closed) << "piece " << t << " straddles the rectangle's outline";
    }
    if (inside) inside_area += tri.area();
  }
  return inside_area;
}

TEST(ImprintContacts, FloorIsCutAlongTheFootprintOfABoxStandingOnIt) {
  // A 2 × 2 floor (two triangles) and the four walls of a 0.6 × 0.6 × 0.5 box standing on it,
  // off-centre so that its footprint crosses the floor's diagonal.
  const TriangleMesh floor = quad_mesh({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  TriangleMesh walls;
  const double x0 = -0.5, x1 = 0.1, y0 = -0.2, y1 = 0.4, h = 0.5;
  const Point3 c[4] = {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
  for (int k = 0; k < 4; ++k) {
    const int b = static_cast<int>(walls.vertices.size());
    const Point3 a = c[k], d = c[(k + 1) % 4];
    walls.vertices.insert(walls.vertices.end(), {a, d, d + Vector3{0, 0, h}, a + Vector3{0, 0, h}});
    walls.triangles.push_back({b, b + 1, b + 2});
    walls.triangles.push_back({b, b + 2, b + 3});
  }
  const ContactImprint r = imprint_contacts({floor, walls});
  EXPECT_EQ(r.triangles_cut, 2u);  // both floor triangles; the walls are not cut by the floor's plane
  EXPECT_EQ(r.meshes[1].triangles.size(), walls.triangles.size());
  const TriangleMesh& cut = r.meshes[0];
  EXPECT_NEAR(mesh_area(cut), 4.0, 1e-12);  // nothing lost or doubled
  // No piece straddles the footprint, and the pieces inside add up to the footprint's area. Pieces
  // keep the floor's orientation (+z).
  for (std::size_t t = 0; t < cut.triangles.size(); ++t) EXPECT_GT(cut.triangle(t).area_vector().z, 0);
  EXPECT_NEAR(area_inside_rectangle(cut, x0, x1, y0, y1), (x1 - x0) * (y1 - y0), 1e-12);
}

TEST(ImprintContacts, AFaceJustInFrontCutsAlongItsOutline) {
  // A 1 × 1 panel of two triangles 1 mm under a 6 × 4 ceiling, both facing down: within a 1 cm
  // near gap the ceiling is cut along the panel's outline (its four outer edges, not its diagonal),
  // and the pieces under it add up to the panel's area. The panel, behind which the ceiling lies, is
  // not cut.
  const TriangleMesh ceiling = quad_mesh({0, 0, 3}, {0, 4, 0}, {6, 0, 0});
  const double x0 = 2.5, x1 = 3.5, y0 = 1.5, y1 = 2.5;
  for (double gap : {0.001, 0.02}) {
    const TriangleMesh panel = quad_mesh({x0, y0, 3 - gap}, {0, y1 - y0, 0}, {x1 - x0, 0, 0});
    const ContactImprint r = imprint_contacts({ceiling, panel}, 1e-9, 0.01);
    EXPECT_EQ(r.meshes[1].triangles.size(), 2u) << gap;
    EXPECT_NEAR(mesh_area(r.meshes[0]), 24.0, 1e-12) << gap;
    if (gap > 0.01) {  // beyond the near gap: nothing is cut
      EXPECT_EQ(r.triangles_cut, 0u);
      continue;
    }
    EXPECT_EQ(r.triangles_cut, 2u);  // the ceiling's diagonal crosses the panel's centre
    EXPECT_EQ(r.segments, 8u);       // each ceiling triangle: the two outline edges of each panel triangle
    EXPECT_NEAR(area_inside_rectangle(r.meshes[0], x0, x1, y0, y1), 1.0, 1e-12);
    for (const std::vector<char>& flags : r.on_opposite_face)
      EXPECT_EQ(std::count(flags.begin(), flags.end(), 1), 0);  // nothing lies face to face
  }
  // Without a near gap (the default) a face 1 mm away does not cut.
  const TriangleMesh panel = quad_mesh({x0, y0, 2.999}, {0, y1 - y0, 0}, {x1 - x0, 0, 0});
  EXPECT_EQ(imprint_contacts({ceiling, panel}).triangles_cut, 0u);
  // Nor does a face small against its gap (a 1 cm tile 1 mm away: light comes in from every side).
  const TriangleMesh tile = quad_mesh({3, 2, 2.999}, {0, 0.01, 0}, {0.01, 0, 0});
  EXPECT_EQ(imprint_contacts({ceiling, tile}, 1e-9, 0.01).triangles_cut, 0u);
}

TEST(ImprintContacts, AFaceBesideOneStepUpDoesNotCut) {
  // Two floor halves meeting at x = 1, the second 0.5 mm higher: it lies within the near gap in front
  // of the first, but its outline only meets the first along their common edge, where a cut would
  // leave slivers of rounding. Neither is cut.
  const TriangleMesh low = quad_mesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const TriangleMesh high = quad_mesh({1, 0, 0.0005}, {1, 0, 0}, {0, 1, 0});
  EXPECT_EQ(imprint_contacts({low, high}, 1e-9, 0.01).triangles_cut, 0u);
}

// Area of a mesh's triangles flagged (or not) as lying on an opposite-facing face.
double flagged_area(const ContactImprint& r, std::size_t m, bool flagged) {
  double area = 0;
  for (std::size_t t = 0; t < r.meshes[m].triangles.size(); ++t)
    if ((r.on_opposite_face[m][t] != 0) == flagged) area += r.meshes[m].triangle(t).area();
  return area;
}

TEST(ImprintContacts, FaceToFacePiecesAreCutAndFlagged) {
  // A box's bottom (facing down) lying on a floor (facing up): the floor is cut along the footprint
  // and its pieces under the bottom are flagged, as is all of the bottom; nothing is lost (whether
  // it is contact or a two-sided sheet is the solver's call: radiosity_test, TwoSidedSheet…).
  const TriangleMesh floor = quad_mesh({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  const TriangleMesh bottom = quad_mesh({-0.5, -0.2, 0}, {0, 0.6, 0}, {0.6, 0, 0});  // normal -z
  const ContactImprint r = imprint_contacts({floor, bottom});
  ASSERT_EQ(r.on_opposite_face.size(), 2u);
  ASSERT_EQ(r.on_opposite_face[0].size(), r.meshes[0].triangles.size());
  ASSERT_EQ(r.on_opposite_face[1].size(), r.meshes[1].triangles.size());
  EXPECT_NEAR(flagged_area(r, 0, true), 0.36, 1e-12);
  EXPECT_NEAR(flagged_area(r, 0, false), 4.0 - 0.36, 1e-12);
  EXPECT_NEAR(flagged_area(r, 1, true), 0.36, 1e-12);
  EXPECT_NEAR(flagged_area(r, 1, false), 0.0, 1e-12);
  for (std::size_t t = 0; t < r.meshes[0].triangles.size(); ++t) {
    const Point3 g = r.meshes[0].triangle(t).centroid();
    const bool under = g.x > -0.5 && g.x < 0.1 && g.y > -0.2 && g.y < 0.4;
    EXPECT_EQ(r.on_opposite_face[0][t] != 0, under) << "piece " << t;
  }
  // Each flagged piece names the mesh of the face it lies on.
  for (std::size_t m = 0; m < 2; ++m) {
    ASSERT_EQ(r.opposite_mesh[m].size(), r.meshes[m].triangles.size());
    for (std::size_t t = 0; t < r.meshes[m].triangles.size(); ++t)
      EXPECT_EQ(r.opposite_mesh[m][t], r.on_opposite_face[m][t] ? int(1 - m) : -1) << m << " " << t;
  }
}

TEST(ImprintContacts, NoSliversWhereFootprintsCrossTheFloorsDiagonal) {
  // Three closed desks standing on a 20 × 10 floor whose diagonal y = x/2 crosses two footprints:
  // the crossings are constructed in double precision; no piece may be a rounding sliver (the
  // 2·10⁻¹⁶ m² piece such a crossing once left had a factor of pure noise), and no area is lost.
  const TriangleMesh floor = quad_mesh({0, 0, 0}, {20, 0, 0}, {0, 10, 0});
  std::vector<TriangleMesh> meshes = {floor};
  for (int i = 0; i < 3; ++i) {
    const double x = 1 + 1.9 * i;
    TriangleMesh desk;
    test::for_each_box_face({x, 0.8, 0}, {x + 1.6, 1.6, 0.75}, [&](const Point3& o, const Vector3& u, const Vector3& v) {
      const TriangleMesh q = quad_mesh(o, v, u);  // outward faces
      const int b = static_cast<int>(desk.vertices.size());
      desk.vertices.insert(desk.vertices.end(), q.vertices.begin(), q.vertices.end());
      for (const auto& t : q.triangles) desk.triangles.push_back({b + t[0], b + t[1], b + t[2]});
    });
    meshes.push_back(desk);
  }
  const ContactImprint r = imprint_contacts(meshes);
  EXPECT_NEAR(mesh_area(r.meshes[0]), 200, 1e-9);
  EXPECT_NEAR(flagged_area(r, 0, true), 3 * 1.28, 1e-9);
  for (std::size_t m = 1; m < meshes.size(); ++m) EXPECT_NEAR(flagged_area(r, m, true), 1.28, 1e-9);
  for (const TriangleMesh& m : r.meshes)
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const Triangle tri = m.triangle(t);
      EXPECT_GT(2 * tri.area() / tri.max_edge_length(), 1e-6) << "a sliver: piece " << t;
    }
}

TEST(ImprintContacts, CoplanarAndDistantSurfacesAndOwnNeighboursDoNotCut) {
  const TriangleMesh floor = quad_mesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const TriangleMesh rug = quad_mesh({0.2, 0.2, 0}, {0.3, 0, 0}, {0, 0.3, 0});        // coplanar
  const TriangleMesh shelf = quad_mesh({0.2, 0.2, 0.5}, {0.3, 0, 0}, {0, 0.3, 0});    // parallel, above
  const TriangleMesh wall = quad_mesh({0, 0, 0}, {1, 0, 0}, {0, 0, 1});              // along the edge
  const ContactImprint r = imprint_contacts({floor, rug, shelf, wall});
  EXPECT_EQ(r.triangles_cut, 0u);
  for (std::size_t m = 0; m < 4; ++m) EXPECT_EQ(r.meshes[m].triangles.size(), 2u);
  // The rug overlaps the floor in its plane: reported once, with the shared area.
  ASSERT_EQ(r.overlaps.size(), 1u);
  EXPECT_EQ(r.overlaps[0].mesh_a, 0);
  EXPECT_EQ(r.overlaps[0].mesh_b, 1);
  EXPECT_NEAR(r.overlaps[0].area, 0.09, 1e-12);
}

// A w × h rectangle in the plane z = z0 cut into n strips along x (2 triangles each), facing +z or −z.
TriangleMesh strips(double w, double h, int n, double z0, bool up) {
  TriangleMesh m;
  for (int i = 0; i <= n; ++i) {
    m.vertices.push_back({w * i / n, 0, z0});
    m.vertices.push_back({w * i / n, h, z0});
  }
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i, b = 2 * i + 2, c = 2 * i + 3, d = 2 * i + 1;
    if (up) {
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    } else {
      m.triangles.push_back({a, c, b});
      m.triangles.push_back({a, d, c});
    }
  }
  return m;
}

TEST(MergeSliverRegions, StripsOfARectangleBecomeTheRectangle) {
  for (bool up : {true, false}) {
    const TriangleMesh mesh = strips(0.04 * 100, 3, 100, 1.5, up);  // aspect 75 strips
    const SliverMerge r = merge_sliver_regions(mesh);
    EXPECT_EQ(r.slivers, 200u);
    EXPECT_EQ(r.regions, 1u);
    EXPECT_EQ(r.mesh.triangles.size(), 2u);
    EXPECT_NEAR(mesh_area(r.mesh), 12.0, 1e-12);
    for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
      const Triangle tri = r.mesh.triangle(t);
      EXPECT_NEAR(tri.normal().z, up ? 1.0 : -1.0, 1e-12) << "orientation kept";
      EXPECT_NEAR(tri.centroid().z, 1.5, 1e-12);
      EXPECT_LT(tri.max_edge_length() * tri.max_edge_length(), kSliverElongation * tri.area());
    }
  }
}

TEST(MergeSliverRegions, StripsWhoseSharedCornersDifferInTheLastBitsJoinWhole) {
  // Each strip with its own four corners (a triangle soup, as exports and SceneBuilder make them),
  // the next strip's near corners moved by an ulp from this strip's far ones, as separately computed
  // sums leave them. The exact union would keep those gaps as cuts; within the tolerance they weld.
  TriangleMesh mesh;
  const int n = 60;
  for (int i = 0; i < n; ++i) {
    const double x0 = 4.0 * i / n, x1 = std::nextafter(4.0 * (i + 1) / n, i % 2 ? 0.0 : 10.0);
    const int base = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back({x0, 0, 0});
    mesh.vertices.push_back({x1, 0, 0});
    mesh.vertices.push_back({x1, 2.5, 0});
    mesh.vertices.push_back({x0, 2.5, 0});
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
  }
  const SliverMerge r = merge_sliver_regions(mesh);
  EXPECT_EQ(r.regions, 1u);
  EXPECT_EQ(r.mesh.triangles.size(), 2u);
  EXPECT_NEAR(mesh_area(r.mesh), 10.0, 1e-12);
}

TEST(MergeSliverRegions, AHoleStaysAHoleAndOtherPlanesAreUntouched) {
  // Strips around a 1 × 1 hole (four strip fields framing it) and, in another plane, a plain quad.
  TriangleMesh mesh;
  auto add = [&](const TriangleMesh& part, const Vector3& shift) {
    const int base = static_cast<int>(mesh.vertices.size());
    for (const Point3& p : part.vertices) mesh.vertices.push_back(p + shift);
    for (const auto& t : part.triangles) mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  };
  add(strips(3, 1, 60, 0, true), {0, 0, 0});  // y in [0, 1]
  add(strips(3, 1, 60, 0, true), {0, 2, 0});  // y in [2, 3]
  add(strips(1, 1, 20, 0, true), {0, 1, 0});  // x in [0, 1], y in [1, 2]
  add(strips(1, 1, 20, 0, true), {2, 1, 0});  // x in [2, 3]
  const std::size_t plain_first = mesh.triangles.size();
  add(quad_mesh({0, 0, 5}, {3, 0, 0}, {0, 3, 0}), {0, 0, 0});
  const SliverMerge r = merge_sliver_regions(mesh);
  EXPECT_EQ(r.regions, 1u);
  EXPECT_NEAR(mesh_area(r.mesh), 8.0 + 9.0, 1e-12);
  EXPECT_LT(r.mesh.triangles.size(), 20u);
  std::size_t plain = 0;
  for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    const Triangle tri = r.mesh.triangle(t);
    if (tri.centroid().z > 1) {
      ++plain;
      continue;
    }
    const Point3 g = tri.centroid();
    EXPECT_FALSE(g.x > 1 && g.x < 2 && g.y > 1 && g.y < 2) << "a triangle in the hole";
  }
  EXPECT_EQ(plain, mesh.triangles.size() - plain_first);
}

TEST(MergeSliverRegions, MeshesWithoutSliversAreReturnedAsTheyAre) {
  const TriangleMesh mesh = quad_mesh({0, 0, 0}, {2, 0, 0}, {0, 1, 0});
  const SliverMerge r = merge_sliver_regions(mesh);
  EXPECT_EQ(r.slivers, 0u);
  EXPECT_EQ(r.regions, 0u);
  EXPECT_EQ(r.mesh.triangles, mesh.triangles);
}

// A 3 × 3 square at height z cut into an n × n grid of squares (two triangles each), without the
// cells of the middle third when `hole`, facing up or down.
TriangleMesh fine_grid(int n, double z, bool hole, bool up) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.push_back({3.0 * i / n, 3.0 * j / n, z});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = 3.0 * (i + 0.5) / n, y = 3.0 * (j + 0.5) / n;
      if (hole && x > 1 && x < 2 && y > 1 && y < 2) continue;
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      if (up)
        m.triangles.push_back({a, b, d}), m.triangles.push_back({a, d, c});
      else
        m.triangles.push_back({a, d, b}), m.triangles.push_back({a, c, d});
    }
  return m;
}

TEST(MergeSliverRegions, OverTessellatedRegionsAreJoinedWhenAskedTo) {
  for (bool up : {true, false}) {
    const TriangleMesh mesh = fine_grid(30, 0.5, true, up);  // 1 600 triangles of 0.005 m², a 1 × 1 hole
    ASSERT_EQ(mesh.triangles.size(), 2u * (900 - 100));
    // Not asked (fine_area 0), or the triangles not small enough: left as they are.
    EXPECT_EQ(merge_sliver_regions(mesh).mesh.triangles, mesh.triangles);
    EXPECT_EQ(merge_sliver_regions(mesh, 1e-9, 0.004).mesh.triangles, mesh.triangles);
    const SliverMerge r = merge_sliver_regions(mesh, 1e-9, 0.01);
    EXPECT_EQ(r.slivers, 0u);
    EXPECT_EQ(r.regions, 1u);
    EXPECT_EQ(r.fine_regions, 1u);
    EXPECT_EQ(r.fine_triangles, mesh.triangles.size());
    EXPECT_LT(r.mesh.triangles.size(), 20u);          // the square with a hole: 8 triangles
    EXPECT_NEAR(mesh_area(r.mesh), 8.0, 1e-12);       // nothing lost or doubled; the hole stays
    for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
      const Triangle tri = r.mesh.triangle(t);
      EXPECT_NEAR(tri.normal().z, up ? 1.0 : -1.0, 1e-12) << "orientation kept";
      const Point3 g = tri.centroid();
      EXPECT_NEAR(g.z, 0.5, 1e-12);
      EXPECT_FALSE(g.x > 1 && g.x < 2 && g.y > 1 && g.y < 2) << "a triangle in the hole";
    }
  }
  // Fewer than 64 triangles: a deliberately small mesh is not touched.
  const TriangleMesh few = fine_grid(5, 0, false, true);  // 50 triangles
  EXPECT_EQ(merge_sliver_regions(few, 1e-9, 10.0).mesh.triangles, few.triangles);
}

}  // namespace
}  // namespace lambert
