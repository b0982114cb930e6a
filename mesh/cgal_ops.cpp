// CGAL side of mesh/mesh_ops.h: polygon triangulation, mesh health checks, sliver merging and the
// contact imprint. With polygon_boolean.cpp, one of the two translation units that include CGAL (it
// costs about 15 s to compile), and no CGAL type leaves it.
//
// All decisions (collinearity, simplicity, intersections) use the exact predicates of the Epick
// kernel on the input coordinates; no constructed (rounded) point is ever tested.
#include "mesh/mesh_ops.h"
#include "mesh/contacts.h"
#include "mesh/polygon_boolean.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

namespace lambert {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P2 = K::Point_2;
using P3 = K::Point_3;

std::string format_number(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

bool is_finite(const Point3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
P3 to_cgal(const Point3& p) { return {p.x, p.y, p.z}; }

// ---- triangulate_polygon ------------------------------------------------------------------

// Newell's normal: twice the vector area of a (possibly non-planar) polygon; its direction is the
// normal seen from the side where the vertices turn counter-clockwise (Sutherland et al. 1974).
Vector3 newell_normal(const std::vector<Point3>& p) {
  Vector3 n;
  for (std::size_t i = 0, m = p.size(); i < m; ++i) {
    const Point3& a = p[i];
    const Point3& b = p[(i + 1) % m];
    n += Vector3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  return n;
}

// Largest distance between two vertices; the bounding-box diagonal (an upper bound within a
// factor sqrt(3)) for very long polygons, where the exact O(n^2) value is too slow.
double polygon_diameter(const std::vector<Point3>& p) {
  if (p.size() > 4096) {
    Bounds3 b;
    for (const Point3& q : p) b.add(q);
    return length(b.diagonal());
  }
  double d2 = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) d2 = std::max(d2, length_squared(p[i] - p[j]));
  return std::sqrt(d2);
}

// True if the closed polygon edges i -> i+1 and j -> j+1 share a point they should not share:
// any point for non-adjacent edges, more than the common vertex for adjacent ones.
bool edges_conflict(const std::vector<P2>& q, std::size_t i, std::size_t j) {
  const std::size_t n = q.size();
  const P2 &a = q[i], &b = q[(i + 1) % n], &c = q[j], &d = q[(j + 1) % n];
  if ((i + 1) % n == j) {  // b == c: the edges fold back onto each other?
    return CGAL::collinear(a, b, d) && CGAL::angle(a, b, d) == CGAL::ACUTE;
  }
  if ((j + 1) % n == i) {  // d == a
    return CGAL::collinear(c, a, b) && CGAL::angle(c, a, b) == CGAL::ACUTE;
  }
  return CGAL::do_intersect(K::Segment_2(a, b), K::Segment_2(c, d));
}

// Constrained Delaunay triangulation of the polygon boundary; the faces inside the polygon are
// those separated from the infinite face by an odd number of constrained edges.
struct FaceInfo {
  int nesting_level = -1;
  bool in_domain() const { return nesting_level % 2 == 1; }
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, K>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds,
                                                       CGAL::No_constraint_intersection_tag>;

void mark_domains(CDT& cdt) {
  std::deque<CDT::Edge> border;
  auto flood = [&](CDT::Face_handle start, int level) {
    if (start->info().nesting_level != -1) return;
    std::deque<CDT::Face_handle> queue{start};
    while (!queue.empty()) {
      CDT::Face_handle f = queue.front();
      queue.pop_front();
      if (f->info().nesting_level != -1) continue;
      f->info().nesting_level = level;
      for (int i = 0; i < 3; ++i) {
        CDT::Face_handle g = f->neighbor(i);
        if (g->info().nesting_level != -1) continue;
        if (cdt.is_constrained(CDT::Edge(f, i))) border.emplace_back(f, i);
        else queue.push_back(g);
      }
    }
  };
  flood(cdt.infinite_face(), 0);
  while (!border.empty()) {
    CDT::Edge e = border.front();
    border.pop_front();
    flood(e.first->neighbor(e.second), e.first->info().nesting_level + 1);
  }
}

PolygonTriangulation failure(std::string message) {
  PolygonTriangulation r;
  r.error = std::move(message);
  return r;
}

}  // namespace

PolygonTriangulation triangulate_polygon(const std::vector<Point3>& polygon,
                                         double planarity_tolerance) {
  const std::size_t n = polygon.size();
  if (!(planarity_tolerance >= 0) || !std::isfinite(planarity_tolerance))
    return failure("planarity tolerance " + format_number(planarity_tolerance) +
                   " must be finite and >= 0");
  if (n < 3)
    return failure("a polygon needs at least 3 vertices, got " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i)
    if (!is_finite(polygon[i]))
      return failure("vertex " + std::to_string(i) + " has a non-finite coordinate");
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    if (polygon[i] == polygon[j]) {
      if (j == 0)
        return failure("vertex " + std::to_string(i) +
                       " repeats vertex 0 (the last vertex equals the first: do not close the "
                       "polygon explicitly)");
      return failure("vertex " + std::to_string(j) + " repeats vertex " + std::to_string(i));
    }
  }

  std::vector<P3> p3(n);
  for (std::size_t i = 0; i < n; ++i) p3[i] = to_cgal(polygon[i]);
  // Exact collinearity of all vertices (zero area for any plane).
  std::size_t far = 1;  // a vertex not on the line p0 p1, if any
  while (far < n && CGAL::collinear(p3[0], p3[1], p3[far])) ++far;
  if (far == n) return failure("zero area: all vertices are collinear");

  const double diameter = polygon_diameter(polygon);
  Vector3 normal = newell_normal(polygon);
  // A non-collinear polygon whose signed area vanishes (e.g. a symmetric bow-tie) is necessarily
  // self-intersecting; fit its plane through three of its vertices so that the simplicity test
  // below can name the crossing edges.
  const bool vanishing_area = length(normal) <= 1e-14 * diameter * diameter;
  if (vanishing_area) normal = cross(polygon[1] - polygon[0], polygon[far] - polygon[0]);
  const Vector3 unit_normal = normalize(normal);

  // Plane through the vertex centroid with the fitted normal; every vertex must be close to it.
  Vector3 centroid;
  for (const Point3& p : polygon) centroid += to_vector(p);
  const Point3 origin = to_point(centroid / static_cast<double>(n));
  std::size_t worst = 0;
  double worst_distance = -1;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = std::abs(dot(polygon[i] - origin, unit_normal));
    if (d > worst_distance) worst_distance = d, worst = i;
  }
  const double tolerance = planarity_tolerance * diameter;
  if (worst_distance > tolerance)
    return failure("non-planar: vertex " + std::to_string(worst) + " is " +
                   format_number(worst_distance) + " from the plane (tolerance " +
                   format_number(tolerance) + ", lengths in the polygon's units)");

  // Project by dropping the dominant coordinate of the normal: the 2D points are exact copies of
  // input coordinates, so the exact predicates below judge the input itself. The two kept axes
  // are ordered so that counter-clockwise in 2D means front side (along the normal).
  const double an[3] = {std::abs(normal.x), std::abs(normal.y), std::abs(normal.z)};
  const int drop = an[0] >= an[1] && an[0] >= an[2] ? 0 : (an[1] >= an[2] ? 1 : 2);
  int u = (drop + 1) % 3, v = (drop + 2) % 3;  // (y,z), (z,x) or (x,y): right-handed with drop
  if (normal[drop] < 0) std::swap(u, v);
  std::vector<P2> q(n);
  for (std::size_t i = 0; i < n; ++i) q[i] = P2(polygon[i][u], polygon[i][v]);

  if (vanishing_area || !CGAL::is_simple_2(q.begin(), q.end(), K())) {
    if (n <= 5000) {
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
          if (edges_conflict(q, i, j))
            return failure("self-intersecting: edge " + std::to_string(i) + "-" +
                           std::to_string((i + 1) % n) + " meets edge " + std::to_string(j) + "-" +
                           std::to_string((j + 1) % n));
    }
    if (!vanishing_area) return failure("self-intersecting: the polygon is not simple");
    return failure("zero area: the signed area of the polygon vanishes");
  }

  CDT cdt;
  std::vector<CDT::Vertex_handle> handles(n);
  try {
    for (std::size_t i = 0; i < n; ++i) {
      handles[i] = cdt.insert(q[i]);
      handles[i]->info() = static_cast<int>(i);
    }
    for (std::size_t i = 0; i < n; ++i) cdt.insert_constraint(handles[i], handles[(i + 1) % n]);
  } catch (const std::exception& e) {  // constraints crossing: cannot happen for a simple polygon
    return failure(std::string("internal: constrained triangulation failed: ") + e.what());
  }
  mark_domains(cdt);

  PolygonTriangulation result;
  result.mesh.vertices = polygon;  // original 3D positions: no projection error
  for (CDT::Face_handle f : cdt.finite_face_handles()) {
    if (!f->info().in_domain()) continue;
    result.mesh.triangles.push_back(
        {f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  // A triangulation of a simple n-gon without interior vertices has exactly n - 2 triangles.
  if (result.mesh.triangles.size() != n - 2)
    return failure("internal: triangulation produced " +
                   std::to_string(result.mesh.triangles.size()) + " triangles for " +
                   std::to_string(n) + " vertices");
  return result;
}

// ---- check_mesh ---------------------------------------------------------------------------

namespace {

// Do two non-degenerate triangles, given by welded vertex ids, share more than the vertices or
// the edge they have in common? For a shared edge pq (t1 = pqr, t2 = pqs) the triangles overlap
// exactly when they are coplanar and r, s lie on the same side of pq. For a shared vertex p they
// meet elsewhere exactly when the edge opposite p of one triangle meets the other triangle (the
// intersection is convex and contains p, so its far boundary lies on such an edge). Triangles that
// share nothing and only touch (along a line or at a point: a T-junction between separately meshed
// faces, a box standing on a floor) are not reported: only crossing or overlapping interiors are.
//
// Coplanar pairs (every pair of neighbours on a flat wall) are decided in 2D, dropping the
// dominant axis of the plane's normal: that projection is a bijection of the plane, uses the input
// coordinates unchanged, and the 2D predicates are much cheaper than CGAL's coplanar 3D ones.
bool triangles_intersect(const std::array<int, 3>& a, const std::array<int, 3>& b,
                         const std::vector<P3>& pts) {
  int shared_a[3], shared_b[3], shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j]) shared_a[shared] = i, shared_b[shared] = j, ++shared;
  if (shared == 3) return true;  // the same triangle twice
  auto A = [&](int i) -> const P3& { return pts[a[i]]; };
  auto B = [&](int j) -> const P3& { return pts[b[j]]; };
  auto is_shared_b = [&](int j) { return std::find(shared_b, shared_b + shared, j) != shared_b + shared; };

  bool coplanar = true;
  for (int j = 0; j < 3 && coplanar; ++j)
    coplanar = is_shared_b(j) || CGAL::orientation(A(0), A(1), A(2), B(j)) == CGAL::COPLANAR;

  if (coplanar) {
    const K::Vector_3 n = CGAL::cross_product(A(1) - A(0), A(2) - A(0));
    const double an[3] = {std::abs(n.x()), std::abs(n.y()), std::abs(n.z())};
    const int drop = an[0] >= an[1] && an[0] >= an[2] ? 0 : (an[1] >= an[2] ? 1 : 2);
    auto flat = [&](const P3& p) { return P2(p[(drop + 1) % 3], p[(drop + 2) % 3]); };
    P2 a2[3], b2[3];
    for (int i = 0; i < 3; ++i) a2[i] = flat(A(i)), b2[i] = flat(B(i));
    if (!CGAL::collinear(a2[0], a2[1], a2[2])) {  // always, unless the normal was badly rounded
      if (shared == 2) {
        const int ra = 3 - shared_a[0] - shared_a[1], sb = 3 - shared_b[0] - shared_b[1];
        const P2 &p = a2[shared_a[0]], &q = a2[shared_a[1]];
        return CGAL::orientation(p, q, a2[ra]) == CGAL::orientation(p, q, b2[sb]);
      }
      // Interiors overlap unless an edge line of one separates the other (closed): triangles
      // meeting only along a line or at a point (a T-junction) touch, they do not intersect.
      auto separated_by_edge_of = [](const P2* x, const P2* y) {
        for (int e = 0; e < 3; ++e) {
          const CGAL::Orientation inner = CGAL::orientation(x[e], x[(e + 1) % 3], x[(e + 2) % 3]);
          bool outside = true;
          for (int k = 0; k < 3 && outside; ++k) outside = CGAL::orientation(x[e], x[(e + 1) % 3], y[k]) != inner;
          if (outside) return true;
        }
        return false;
      };
      return !separated_by_edge_of(a2, b2) && !separated_by_edge_of(b2, a2);
    }
  }

  if (shared == 2) {
    const int ra = 3 - shared_a[0] - shared_a[1], sb = 3 - shared_b[0] - shared_b[1];
    const P3 &p = A(shared_a[0]), &q = A(shared_a[1]), &r = A(ra), &s = B(sb);
    return CGAL::coplanar(p, q, r, s) && CGAL::coplanar_orientation(p, q, r, s) == CGAL::POSITIVE;
  }
  // Not coplanar, at most one shared vertex. If one triangle lies on one closed side of the other's
  // plane, the two can meet only along its edge or at its corner: contact (a box standing on a
  // floor, a T-junction between separately meshed faces), not a crossing; only crossings count.
  auto one_side = [](const P3& p, const P3& q, const P3& r, const P3* x) {
    bool above = false, below = false;
    for (int k = 0; k < 3; ++k) {
      const CGAL::Orientation o = CGAL::orientation(p, q, r, x[k]);
      above |= o == CGAL::POSITIVE;
      below |= o == CGAL::NEGATIVE;
    }
    return !(above && below);
  };
  const P3 av[3] = {A(0), A(1), A(2)}, bv[3] = {B(0), B(1), B(2)};
  if (one_side(av[0], av[1], av[2], bv) || one_side(bv[0], bv[1], bv[2], av)) return false;
  if (shared == 1) {
    const int ia = shared_a[0], ib = shared_b[0];
    const K::Segment_3 opposite_a(A((ia + 1) % 3), A((ia + 2) % 3));
    const K::Segment_3 opposite_b(B((ib + 1) % 3), B((ib + 2) % 3));
    return CGAL::do_intersect(opposite_a, K::Triangle_3(B(0), B(1), B(2))) ||
           CGAL::do_intersect(opposite_b, K::Triangle_3(A(0), A(1), A(2)));
  }
  return CGAL::do_intersect(K::Triangle_3(A(0), A(1), A(2)), K::Triangle_3(B(0), B(1), B(2)));
}

}  // namespace

MeshHealth check_mesh(const TriangleMesh& mesh) {
  MeshHealth health;
  const int nv = static_cast<int>(mesh.vertices.size());
  const int nt = static_cast<int>(mesh.triangles.size());

  // Weld vertices at identical positions, so that adjacency is geometric: a mesh whose faces
  // carry their own copies of shared corners (common in OBJ exports) is still closed.
  const std::vector<int> weld = weld_identical_positions(mesh.vertices);
  std::vector<P3> pts(nv);
  for (int i = 0; i < nv; ++i) pts[i] = is_finite(mesh.vertices[i]) ? to_cgal(mesh.vertices[i]) : P3();

  // Degenerate: index out of range, non-finite vertex, repeated vertex or exactly collinear.
  std::vector<std::array<int, 3>> tri(nt);
  std::vector<char> degenerate(nt, 0), usable_edges(nt, 0);
  for (int t = 0; t < nt; ++t) {
    const auto& idx = mesh.triangles[t];
    bool valid = true;
    for (int k = 0; k < 3; ++k) {
      valid = valid && idx[k] >= 0 && idx[k] < nv && weld[idx[k]] >= 0;
      tri[t][k] = valid ? weld[idx[k]] : -1;
    }
    const bool distinct = valid && tri[t][0] != tri[t][1] && tri[t][1] != tri[t][2] &&
                          tri[t][2] != tri[t][0];
    usable_edges[t] = distinct;  // a zero-area triangle with 3 distinct corners still has edges
    degenerate[t] = !distinct || CGAL::collinear(pts[tri[t][0]], pts[tri[t][1]], pts[tri[t][2]]);
    if (degenerate[t]) health.degenerate_triangles.push_back(t);
  }

  // Edge topology: every undirected edge with the directions in which its triangles traverse it.
  const std::vector<EdgeUse> uses = sorted_edge_uses(tri.size(), [&](std::size_t t) {
    return usable_edges[t] ? tri[t] : std::array<int, 3>{-1, -1, -1};
  });
  for_each_edge(uses, [&](std::span<const EdgeUse> edge) {
    const auto forward = std::count_if(edge.begin(), edge.end(), [](const EdgeUse& u) { return u.forward; });
    if (edge.size() == 1) ++health.boundary_edges;
    if (edge.size() > 2) health.manifold = false;
    if (edge.size() == 2 && forward != 1) health.consistently_oriented = false;
  });

  // Self-intersections: bounding-box broad phase, exact narrow phase; degenerate triangles are
  // skipped (they are reported above, and the predicates need proper triangles).
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;
  std::vector<Box> boxes;
  for (int t = 0; t < nt; ++t) {
    if (degenerate[t]) continue;
    const auto& v = tri[t];
    boxes.emplace_back(pts[v[0]].bbox() + pts[v[1]].bbox() + pts[v[2]].bbox(), t);
  }
  std::vector<std::pair<int, int>> hits;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    const int s = a.info(), t = b.info();
    if (triangles_intersect(tri[s], tri[t], pts)) hits.emplace_back(std::min(s, t), std::max(s, t));
  });
  std::sort(hits.begin(), hits.end());
  health.self_intersections = std::move(hits);
  return health;
}

// ---- merge_sliver_regions -----------------------------------------------------------------

namespace {

// Drops the vertices of a closed loop that lie within eps of the line through their neighbours
// (repeatedly, as a dropped vertex changes its neighbours' lines).
Loop2d without_collinear_vertices(Loop2d loop, double eps) {
  bool changed = true;
  while (changed && loop.size() > 3) {
    changed = false;
    for (std::size_t i = 0; i < loop.size() && loop.size() > 3; ++i) {
      const Point2d& a = loop[(i + loop.size() - 1) % loop.size()];
      const Point2d& b = loop[i];
      const Point2d& c = loop[(i + 1) % loop.size()];
      const double dx = c[0] - a[0], dy = c[1] - a[1];
      const double len = std::hypot(dx, dy);
      const double off = len > 0 ? std::abs(dx * (b[1] - a[1]) - dy * (b[0] - a[0])) / len
                                 : std::hypot(b[0] - a[0], b[1] - a[1]);
      const bool between = (b[0] - a[0]) * dx + (b[1] - a[1]) * dy >= 0 && (c[0] - b[0]) * dx + (c[1] - b[1]) * dy >= 0;
      if (off <= eps && between) {
        loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
        --i;
      }
    }
  }
  return loop;
}

// Moves each 2D point that lies within eps of a point seen before onto that point. Strips whose
// shared corners were computed separately differ there in the last bits (1e-16 m at the origin),
// and their exact union keeps such a gap as a cut: a wall of 60 strips came out as up to 13 pieces.
// Far from the origin the same corners round to one double, so without this the two placements
// were meshed differently (x ≈ 5e5, y ≈ 5.5e6 m: 1 piece).
class PointWelder {
 public:
  explicit PointWelder(double eps) : eps_(eps) {}
  Point2d operator()(const Point2d& p) {
    if (!(eps_ > 0)) return p;  // a tolerance of 0: nothing to weld (and no cells to divide into)
    const std::int64_t cx = cell(p[0]), cy = cell(p[1]);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto found = cells_.find({cx + dx, cy + dy});
        if (found == cells_.end()) continue;
        for (const Point2d& q : found->second)
          if (std::hypot(q[0] - p[0], q[1] - p[1]) <= eps_) return q;
      }
    cells_[{cx, cy}].push_back(p);
    return p;
  }

 private:
  std::int64_t cell(double x) const { return static_cast<std::int64_t>(std::floor(x / eps_)); }
  double eps_;
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<Point2d>> cells_;
};

}  // namespace

SliverMerge merge_sliver_regions(const TriangleMesh& mesh, double tolerance, double fine_area) {
  SliverMerge out;
  out.mesh = mesh;
  Bounds3 box;
  for (const Point3& p : mesh.vertices) box.add(p);
  if (box.empty()) return out;
  const double eps = tolerance * std::max(length(box.diagonal()), 1e-300);
  const Point3 centre = box.center();
  // Planes of the triangles (quantised unit normal and offset from the centre), and which hold slivers.
  struct Region {
    Vector3 n;
    double d = 0;
    std::vector<int> triangles;
    bool has_sliver = false;
    double area = 0;
  };
  std::map<PlaneKey, Region> regions;
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
    const Triangle tri = mesh.triangle(t);
    const double area = tri.area();
    if (!(area > 0) || !std::isfinite(area)) continue;
    const Vector3 n = tri.normal();
    const double d = dot(n, tri.v[0] - centre);
    Region& r = regions.try_emplace(plane_key(n, d, eps), Region{n, d, {}, false, 0}).first->second;
    r.triangles.push_back(t);
    r.area += area;
    const double longest = tri.max_edge_length();
    const bool sliver = longest * longest > kSliverElongation * area;
    r.has_sliver |= sliver;
    out.slivers += sliver;
  }
  auto over_tessellated = [&](const Region& r) {
    return fine_area > 0 && r.triangles.size() >= 64 && r.area / static_cast<double>(r.triangles.size()) < fine_area;
  };
  if (out.slivers == 0 && std::none_of(regions.begin(), regions.end(),
                                       [&](const auto& kv) { return over_tessellated(kv.second); }))
    return out;
  std::vector<char> replaced(mesh.triangles.size(), 0);
  std::vector<std::array<int, 3>> added;
  for (auto& [key, region] : regions) {
    const bool fine = over_tessellated(region);
    if ((!region.has_sliver && !fine) || region.triangles.size() < 2) continue;
    const Vector3& n = region.n;
    const Vector3 u = perpendicular(n);
    const Vector3 v = cross(n, u);  // (u, v, n) right-handed: counter-clockwise about n is CCW in (u, v)
    std::vector<Loop2d> parts;
    PointWelder weld(eps);
    for (int t : region.triangles) {
      const Triangle tri = mesh.triangle(t);
      Loop2d loop;
      for (const Point3& p : tri.v) loop.push_back(weld({dot(u, p - centre), dot(v, p - centre)}));
      parts.push_back(std::move(loop));
    }
    std::vector<std::array<int, 3>> pieces;
    std::vector<Point3> points;
    bool ok = true;
    try {
      for (const std::vector<Loop2d>& polygon : convex_union(parts)) {
        CDT cdt;
        std::map<CDT::Vertex_handle, int> index;  // into `points`
        for (const Loop2d& raw : polygon) {
          const Loop2d loop = without_collinear_vertices(raw, eps);
          if (loop.size() < 3) continue;
          std::vector<CDT::Vertex_handle> handles;
          for (const Point2d& p : loop) {
            CDT::Vertex_handle h = cdt.insert(P2(p[0], p[1]));
            if (index.try_emplace(h, static_cast<int>(points.size())).second)
              points.push_back(centre + u * p[0] + v * p[1] + n * region.d);
            handles.push_back(h);
          }
          for (std::size_t k = 0; k < handles.size(); ++k) {
            if (handles[k] == handles[(k + 1) % handles.size()]) continue;
            cdt.insert_constraint(handles[k], handles[(k + 1) % handles.size()]);
          }
        }
        mark_domains(cdt);
        for (CDT::Face_handle f : cdt.finite_face_handles()) {
          if (!f->info().in_domain()) continue;
          std::array<int, 3> tri{};
          for (int k = 0; k < 3; ++k) {
            const auto it = index.find(f->vertex(k));
            if (it == index.end()) {
              ok = false;  // a vertex the triangulation made up (constraints crossing): keep the input
              break;
            }
            tri[k] = it->second;
          }
          if (ok) pieces.push_back(tri);
        }
      }
    } catch (const std::exception&) {
      ok = false;  // CGAL refused the boundary (crossing constraints after rounding): keep the input
    }
    // Keep the region as it was unless the new triangles cover the same area.
    double before = 0, after = 0;
    for (int t : region.triangles) before += mesh.triangle(t).area();
    for (const auto& tri : pieces)
      after += Triangle{{points[tri[0]], points[tri[1]], points[tri[2]]}}.area();
    // ... and unless that takes fewer triangles (a strip that is one thin rectangle stays as it is).
    if (!ok || pieces.empty() || pieces.size() >= region.triangles.size() || std::abs(after - before) > 1e-9 * before)
      continue;
    const int base = static_cast<int>(out.mesh.vertices.size());
    out.mesh.vertices.insert(out.mesh.vertices.end(), points.begin(), points.end());
    for (const auto& tri : pieces) added.push_back({base + tri[0], base + tri[1], base + tri[2]});
    for (int t : region.triangles) replaced[t] = 1;
    ++out.regions;
    if (fine && !region.has_sliver) {
      ++out.fine_regions;
      out.fine_triangles += region.triangles.size();
    }
  }
  if (out.regions == 0) return out;
  out.mesh.triangles.clear();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (!replaced[t]) out.mesh.triangles.push_back(mesh.triangles[t]);
  out.mesh.triangles.insert(out.mesh.triangles.end(), added.begin(), added.end());
  return out;
}

// ---- imprint_contacts ---------------------------------------------------------------------

namespace {

// Constraints may cross (two boxes' footprints): Exact_predicates_tag lets the triangulation insert
// the crossing points (constructed in double precision).
using ImprintCDT = CGAL::Constrained_Delaunay_triangulation_2<K, CGAL::Default, CGAL::Exact_predicates_tag>;

// Adds to `mesh` the pieces of triangle t (corners `original` in it) cut along `cuts`, each flagged
// where it lies on one of `facing` (triangles facing the other way in t's plane, with their meshes).
// Returns how many pieces, and how many lie on such a face.
std::pair<std::size_t, std::size_t> add_pieces(const Triangle& t, const std::array<int, 3>& original,
                                               const std::vector<std::pair<Point3, Point3>>& cuts,
                                               const std::vector<std::pair<Triangle, int>>& facing, double eps,
                                               TriangleMesh& mesh, std::vector<char>& flags, std::vector<int>& opposite) {
  const Vector3 n = t.normal();
  const Vector3 e1 = normalize(t.v[1] - t.v[0]), e2 = cross(n, e1);
  auto to_2d = [&](const Point3& p) { return P2(dot(p - t.v[0], e1), dot(p - t.v[0], e2)); };
  ImprintCDT cdt;
  std::vector<ImprintCDT::Vertex_handle> corners;
  for (const Point3& p : t.v) corners.push_back(cdt.insert(to_2d(p)));
  for (int k = 0; k < 3; ++k) cdt.insert_constraint(corners[k], corners[(k + 1) % 3]);
  for (const auto& [a, b] : cuts) cdt.insert_constraint(to_2d(a), to_2d(b));
  std::map<ImprintCDT::Vertex_handle, int> index;
  for (int k = 0; k < 3; ++k) index[corners[k]] = original[k];  // the corners stay shared
  std::size_t pieces = 0, pieces_on_opposite = 0;
  for (ImprintCDT::Face_handle f : cdt.finite_face_handles()) {
    // Segments reach beyond t: keep the faces inside it (centroid inside t's three edges).
    const P2 centroid = CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
    bool inside = true;
    for (int k = 0; k < 3; ++k)
      inside &= CGAL::orientation(corners[k]->point(), corners[(k + 1) % 3]->point(), centroid) != CGAL::RIGHT_TURN;
    if (!inside) continue;
    // Crossings of nearly collinear constraints are constructed in double precision and can leave
    // slivers narrower than the tolerance (2·10⁻¹⁶ m² at a desk's corner): rounding, not geometry,
    // and their factors would be noise. Such pieces are dropped (their area is below eps × edge).
    {
      const P2 &a = f->vertex(0)->point(), &b = f->vertex(1)->point(), &c = f->vertex(2)->point();
      const double longest = std::sqrt(std::max({CGAL::squared_distance(a, b), CGAL::squared_distance(b, c),
                                                 CGAL::squared_distance(c, a)}));
      if (2 * std::abs(CGAL::area(a, b, c)) <= 4 * eps * longest) continue;
    }
    const auto on = std::find_if(facing.begin(), facing.end(), [&](const std::pair<Triangle, int>& face) {
      const Triangle& u = face.first;
      const P2 a = to_2d(u.v[0]), b = to_2d(u.v[1]), c = to_2d(u.v[2]);  // clockwise in t's frame
      return CGAL::orientation(a, b, centroid) != CGAL::LEFT_TURN &&
             CGAL::orientation(b, c, centroid) != CGAL::LEFT_TURN &&
             CGAL::orientation(c, a, centroid) != CGAL::LEFT_TURN;
    });
    const bool on_opposite = on != facing.end();
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const auto v = f->vertex(k);
      auto [it, added] = index.try_emplace(v, 0);
      if (added) {
        const P2& q = v->point();
        mesh.vertices.push_back(t.v[0] + e1 * q.x() + e2 * q.y());
        it->second = static_cast<int>(mesh.vertices.size()) - 1;
      }
      tri[k] = it->second;
    }
    // The triangulation is counter-clockwise in (e1, e2), i.e. about n: t's orientation.
    mesh.triangles.push_back(tri);
    flags.push_back(on_opposite ? 1 : 0);
    opposite.push_back(on_opposite ? on->second : -1);
    pieces_on_opposite += on_opposite;
    ++pieces;
  }
  return {pieces, pieces_on_opposite};
}

}  // namespace

ContactImprint imprint_contacts(const std::vector<TriangleMesh>& meshes, double tolerance, double near_gap) {
  ContactImprint out;
  out.meshes = meshes;
  for (const TriangleMesh& m : meshes) {
    out.on_opposite_face.emplace_back(m.triangles.size(), 0);
    out.opposite_mesh.emplace_back(m.triangles.size(), -1);
  }
  struct Ref { int mesh, triangle; };
  std::vector<Ref> refs;
  Bounds3 all;
  for (int m = 0; m < static_cast<int>(meshes.size()); ++m)
    for (int t = 0; t < static_cast<int>(meshes[m].triangles.size()); ++t) {
      refs.push_back({m, t});
      for (const Point3& p : meshes[m].triangle(t).v) all.add(p);
    }
  if (refs.size() < 2) return out;
  const double eps = tolerance * std::max(length(all.diagonal()), 1e-300);
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;
  std::vector<Box> boxes;
  for (int r = 0; r < static_cast<int>(refs.size()); ++r) {
    const Triangle tri = meshes[refs[r].mesh].triangle(refs[r].triangle);
    const Bounds3 b = bounds(tri);
    // How far from it another triangle may lie and still be cut by it: a face just in front lies
    // within its own slab (lies_just_in_front), so each box grows by its own triangle's, and a huge
    // near_gap (patches as large as the input triangles) does not make every box meet every other.
    const double reach = std::max(eps, near_slab(tri, near_gap));
    double lo[3] = {b.lo.x - reach, b.lo.y - reach, b.lo.z - reach};
    double hi[3] = {b.hi.x + reach, b.hi.y + reach, b.hi.z + reach};
    boxes.emplace_back(Box(lo, hi, r));
  }
  std::vector<std::vector<std::pair<Point3, Point3>>> cuts(refs.size());
  std::vector<std::vector<int>> facing(refs.size());  // coplanar triangles facing the other way
  std::vector<std::vector<unsigned char>> outlines(meshes.size());  // flat_outline_edges, when first asked
  auto outline_of = [&](const Ref& r) {
    std::vector<unsigned char>& mask = outlines[r.mesh];
    if (mask.empty()) mask = flat_outline_edges(meshes[r.mesh]);
    return mask[r.triangle];
  };
  auto consider = [&](int ti, int ui) {
    const Ref& rt = refs[ti];
    const Ref& ru = refs[ui];
    if (rt.mesh == ru.mesh) {  // neighbours in one mesh meet along their own edges
      const auto& a = meshes[rt.mesh].triangles[rt.triangle];
      const auto& b = meshes[ru.mesh].triangles[ru.triangle];
      for (int x : a)
        for (int y : b)
          if (x == y) return;
    }
    const Triangle t = meshes[rt.mesh].triangle(rt.triangle);
    const Triangle u = meshes[ru.mesh].triangle(ru.triangle);
    if (!(t.area() > 0) || !(u.area() > 0)) return;
    const Vector3 n = t.normal();
    Point3 a, b;
    if (contact_segment(t, n, u, eps, a, b)) {
      cuts[ti].emplace_back(a, b);
    } else if (dot(u.normal(), n) < 0 && std::all_of(u.v.begin(), u.v.end(), [&](const Point3& p) {
                 return std::abs(dot(p - t.v[0], n)) <= eps;
               })) {
      // Face to face in one plane (a box's bottom on a floor, or the two faces of a thin sheet): u's
      // edges cut t, and the pieces of t on u are flagged; which of the two it is, the caller decides.
      for (int k = 0; k < 3; ++k) cuts[ti].emplace_back(u.v[k], u.v[(k + 1) % 3]);
      facing[ti].push_back(ui);
    } else if (ti < ui && rt.mesh != ru.mesh && dot(u.normal(), n) > 0 &&
               std::all_of(u.v.begin(), u.v.end(), [&](const Point3& p) { return std::abs(dot(p - t.v[0], n)) <= eps; })) {
      // Coplanar and facing the same way: if they overlap, both radiate from the same place.
      const double shared = coplanar_shared_area(t, n, u);
      if (shared > 1e-9 * t.area()) out.overlaps.push_back({rt.mesh, ru.mesh, shared});
    } else if (near_gap > eps && lies_just_in_front(t, n, u, eps, near_gap)) {
      // A face just in front of t (a panel mounted under a ceiling): t is cut along its outline, the
      // edges as they are (add_pieces projects them onto t's plane).
      const unsigned char outline = outline_of(ru);
      for (int k = 0; k < 3; ++k)
        if (outline & (1u << k)) cuts[ti].emplace_back(u.v[k], u.v[(k + 1) % 3]);
    }
  };
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    consider(a.info(), b.info());
    consider(b.info(), a.info());
  });

  // Rebuild each mesh: untouched triangles as they were, cut ones by their pieces.
  for (int m = 0; m < static_cast<int>(meshes.size()); ++m) {
    out.meshes[m].triangles.clear();
    out.on_opposite_face[m].clear();
    out.opposite_mesh[m].clear();
  }
  for (int r = 0; r < static_cast<int>(refs.size()); ++r) {
    TriangleMesh& mesh = out.meshes[refs[r].mesh];
    std::vector<char>& flags = out.on_opposite_face[refs[r].mesh];
    std::vector<int>& opposite = out.opposite_mesh[refs[r].mesh];
    const auto& original = meshes[refs[r].mesh].triangles[refs[r].triangle];
    if (cuts[r].empty()) {
      mesh.triangles.push_back(original);
      flags.push_back(0);
      opposite.push_back(-1);
      continue;
    }
    std::vector<std::pair<Triangle, int>> faces;  // the faces t lies on, and their meshes
    for (int ui : facing[r]) faces.emplace_back(meshes[refs[ui].mesh].triangle(refs[ui].triangle), refs[ui].mesh);
    const auto [pieces, pieces_on_opposite] = add_pieces(meshes[refs[r].mesh].triangle(refs[r].triangle), original,
                                                          cuts[r], faces, eps, mesh, flags, opposite);
    if (pieces > 1 || pieces_on_opposite > 0) {
      ++out.triangles_cut;
      out.segments += cuts[r].size();
    }
  }
  // One entry per pair of meshes, their shared areas summed.
  std::map<std::pair<int, int>, double> pairs;
  for (const auto& o : out.overlaps) pairs[{std::min(o.mesh_a, o.mesh_b), std::max(o.mesh_a, o.mesh_b)}] += o.area;
  out.overlaps.clear();
  for (const auto& [key, area] : pairs) out.overlaps.push_back({key.first, key.second, area});
  return out;
}

}  // namespace lambert
