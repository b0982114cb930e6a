// OpenMesh side of mesh/mesh_ops.h: longest-edge subdivision into patches (mesh files are read by
// Lambert's own readers, mesh/mesh_file.h).
// This is the only translation unit that includes OpenMesh; no OpenMesh type leaves it.
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <queue>

#include "mesh/mesh_ops.h"

namespace lambert {
namespace {

// Double-precision points: the default float points would round the file's coordinates.
struct DoubleTraits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using OmTriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// OpenMesh reports problems (e.g. "complex edge") on its own streams; this module reports them as
// errors itself, so the chatter is switched off once for the process.
void silence_openmesh() {
  static std::once_flag once;
  std::call_once(once, [] {
    ::omerr().disable();
    ::omlog().disable();
    ::omout().disable();
  });
}

Point3 to_point3(const OpenMesh::Vec3d& p) { return {p[0], p[1], p[2]}; }

// ---- subdivide_to_max_area ----------------------------------------------------------------

double triangle_area(const Point3& a, const Point3& b, const Point3& c) {
  return 0.5 * length(cross(b - a, c - a));
}

// A patch is too large when its area exceeds the limit A, or when its longest edge exceeds √(8A): a
// well-shaped patch of area A has L² ≤ 4A (2.3A equilateral), so only slivers (from the input, e.g. a
// floor triangulated around a box's footprint) are split for length: a constant-radiosity sliver
// reaching from a shadow into the light carries the light's radiosity right up to the box.
constexpr double kMaxEdgeSquaredPerArea = 8;

// Patches must not depend on the scene's scale or placement. Lengths that tie exactly in one frame
// (the equal sides of an isosceles half of a 2:1 rectangle, congruent triangles' areas) differ in their
// last bits in another (millimetres, geo-referenced coordinates), and a comparison that breaks such a
// tie by rounding splits a different edge, or splits in a different order, and so makes different
// patches. So lengths and areas are compared rounded to 20 significant bits (tie_key: a relative step
// of 2^-20 ≈ 1e-6, a total order, monotone) with ties broken by index, and a triangle counts as too
// large only beyond 1 + kTieTolerance times the limit (a strip 0.1 m × 1 m is not split at 0.05 m²).
constexpr double kTieTolerance = 1e-6;

double tie_key(double x) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  constexpr std::uint64_t kLow = (std::uint64_t{1} << 32) - 1;  // the mantissa's 32 lowest bits
  return std::bit_cast<double>((bits + (kLow >> 1) + 1) & ~kLow);
}

bool too_large(double area, double longest_squared, double max_area) {
  return area > max_area * (1 + kTieTolerance) ||
         longest_squared > kMaxEdgeSquaredPerArea * max_area * (1 + kTieTolerance);
}

// Rivara's longest-edge propagation path (LEPP) bisection on an OpenMesh triangle mesh: to split a
// face, walk to the neighbour across the longest edge until that edge is also the neighbour's
// longest ("terminal edge"), split the terminal edge at its midpoint (splitting both faces, so the
// mesh stays conforming), and repeat until the face itself is split. Bisecting only longest edges
// keeps the smallest angle bounded below (Rivara 1984). Edges are ordered by (length, index) so
// that ties break the same way from both sides and the path always terminates.
class LeppSubdivider {
 public:
  LeppSubdivider(OmTriMesh& mesh, std::vector<int>& face_parent, double max_area)
      : m_(mesh), parent_(face_parent), max_area_(max_area) {}

  void run() {
    for (const auto f : m_.faces()) push_if_too_large(f);
    while (!heap_.empty()) {
      const auto [key, index] = heap_.top();
      heap_.pop();
      const OmTriMesh::FaceHandle f(index);
      if (tie_key(face_area(f)) != key) continue;  // stale: the face was split (halved) since it was queued
      refine(f);
    }
  }

 private:
  double face_area(OmTriMesh::FaceHandle f) const {
    auto h = m_.halfedge_handle(f);
    const auto a = m_.point(m_.from_vertex_handle(h));
    const auto b = m_.point(m_.to_vertex_handle(h));
    const auto c = m_.point(m_.to_vertex_handle(m_.next_halfedge_handle(h)));
    return triangle_area(to_point3(a), to_point3(b), to_point3(c));
  }

  double edge_length_squared(OmTriMesh::EdgeHandle e) const {
    const auto h = m_.halfedge_handle(e, 0);  // same direction from both faces: same rounding
    return (m_.point(m_.to_vertex_handle(h)) - m_.point(m_.from_vertex_handle(h))).sqrnorm();
  }

  OmTriMesh::HalfedgeHandle longest_halfedge(OmTriMesh::FaceHandle f) const {
    OmTriMesh::HalfedgeHandle best;
    double best_length = -1;
    for (const auto h : m_.fh_range(f)) {
      const auto e = m_.edge_handle(h);
      const double l = tie_key(edge_length_squared(e));
      if (l > best_length || (l == best_length && e.idx() > m_.edge_handle(best).idx()))
        best = h, best_length = l;
    }
    return best;
  }

  void push_if_too_large(OmTriMesh::FaceHandle f) {
    const double a = face_area(f);
    if (too_large(a, edge_length_squared(m_.edge_handle(longest_halfedge(f))), max_area_))
      heap_.emplace(tie_key(a), f.idx());
  }

  void refine(OmTriMesh::FaceHandle f) {
    for (;;) {
      auto h = longest_halfedge(f);
      for (;;) {
        const auto opposite = m_.opposite_halfedge_handle(h);
        if (m_.is_boundary(opposite)) break;
        const auto next = longest_halfedge(m_.face_handle(opposite));
        if (m_.edge_handle(next) == m_.edge_handle(h)) break;
        h = next;
      }
      const bool splits_f = m_.face_handle(h) == f ||
                            m_.face_handle(m_.opposite_halfedge_handle(h)) == f;
      split(m_.edge_handle(h));
      if (splits_f) return;
    }
  }

  void split(OmTriMesh::EdgeHandle e) {
    const auto h = m_.halfedge_handle(e, 0);
    const auto v0 = m_.from_vertex_handle(h), v1 = m_.to_vertex_handle(h);
    const int faces_before = static_cast<int>(m_.n_faces());
    const auto mid = m_.add_vertex(m_.point(v0) * 0.5 + m_.point(v1) * 0.5);
    m_.split(e, mid);
    parent_.resize(m_.n_faces(), -1);
    // Each new face is the sibling of an old one across the edge from the midpoint to the apex.
    for (const auto out : m_.voh_range(mid)) {
      const auto w = m_.to_vertex_handle(out);
      if (w == v0 || w == v1) continue;
      const int a = m_.face_handle(out).idx(), b = m_.opposite_face_handle(out).idx();
      if (a >= faces_before) parent_[a] = parent_[b];
      if (b >= faces_before) parent_[b] = parent_[a];
    }
    for (const auto f : m_.vf_range(mid)) push_if_too_large(f);
  }

  OmTriMesh& m_;
  std::vector<int>& parent_;
  double max_area_;
  std::priority_queue<std::pair<double, int>> heap_;  // (tie_key(area), face index), largest first
};

// Bisects one triangle on its own, longest edge first, appending midpoints to `vertices`.
void bisect_alone(std::array<int, 3> t, double max_area, std::vector<Point3>& vertices,
                  std::vector<std::array<int, 3>>& out) {
  std::vector<std::array<int, 3>> stack{t};
  while (!stack.empty()) {
    t = stack.back();
    stack.pop_back();
    const Point3 p[3] = {vertices[t[0]], vertices[t[1]], vertices[t[2]]};
    int k = 0;  // longest edge t[k] -> t[k+1] (the first of tying ones)
    double longest = -1, longest_key = -1;
    for (int i = 0; i < 3; ++i) {
      const double l = length_squared(p[(i + 1) % 3] - p[i]);
      if (tie_key(l) > longest_key) longest = l, longest_key = tie_key(l), k = i;
    }
    if (!too_large(triangle_area(p[0], p[1], p[2]), longest, max_area)) {
      out.push_back(t);
      continue;
    }
    const int m = static_cast<int>(vertices.size());
    vertices.push_back(midpoint(p[k], p[(k + 1) % 3]));
    // Pushed second-half first so that the first half is emitted first.
    stack.push_back({m, t[(k + 1) % 3], t[(k + 2) % 3]});
    stack.push_back({t[k], m, t[(k + 2) % 3]});
  }
}

}  // namespace

SubdividedMesh subdivide_to_max_area_with_parents(const TriangleMesh& mesh, double max_area) {
  const int nv = static_cast<int>(mesh.vertices.size());
  const int nt = static_cast<int>(mesh.triangles.size());
  SubdividedMesh result;
  result.parent.resize(nt);
  std::iota(result.parent.begin(), result.parent.end(), 0);

  // Which triangles can be split at all (valid indices, finite area) and which need it.
  std::vector<char> splittable(nt, 0);
  bool any_too_large = false;
  for (int t = 0; t < nt; ++t) {
    const auto& i = mesh.triangles[t];
    const bool valid = std::all_of(i.begin(), i.end(), [&](int k) { return k >= 0 && k < nv; }) &&
                       i[0] != i[1] && i[1] != i[2] && i[2] != i[0];
    if (!valid) continue;
    const Triangle tri = mesh.triangle(t);
    const double a = tri.area(), longest = tri.max_edge_length();
    splittable[t] = std::isfinite(a) && std::isfinite(longest);
    any_too_large = any_too_large || (splittable[t] && max_area > 0 && too_large(a, longest * longest, max_area));
  }
  if (!(max_area > 0) || !std::isfinite(max_area) || !any_too_large) {
    result.mesh = mesh;
    return result;
  }

  silence_openmesh();
  OmTriMesh om;
  std::vector<OmTriMesh::VertexHandle> handles(nv);
  for (int i = 0; i < nv; ++i) {
    const Point3& p = mesh.vertices[i];
    handles[i] = om.add_vertex(OpenMesh::Vec3d(p.x, p.y, p.z));
  }
  // Faces OpenMesh refuses (a third face on an edge, an edge traversed twice the same way) are
  // bisected alone; so are invalid triangles, which bisect_alone passes through unchanged.
  std::vector<int> face_parent;  // by OpenMesh face index
  std::vector<int> alone;
  for (int t = 0; t < nt; ++t) {
    const auto& i = mesh.triangles[t];
    OmTriMesh::FaceHandle f;
    if (splittable[t]) f = om.add_face(handles[i[0]], handles[i[1]], handles[i[2]]);
    if (f.is_valid()) face_parent.push_back(t);
    else alone.push_back(t);
  }
  const int added_faces = static_cast<int>(face_parent.size());

  LeppSubdivider(om, face_parent, max_area).run();

  // Vertices: the input ones (same indices), the conforming midpoints, then the lone midpoints.
  result.mesh.vertices.reserve(om.n_vertices());
  for (const auto v : om.vertices()) result.mesh.vertices.push_back(to_point3(om.point(v)));
  // Triangles grouped by parent (counting sort; within a parent in creation order).
  std::vector<std::vector<std::array<int, 3>>> children(nt);
  for (const auto f : om.faces()) {
    std::array<int, 3> t;
    int k = 0;
    for (const auto v : om.fv_range(f)) t[k++] = v.idx();
    const int p = face_parent[f.idx()];
    if (f.idx() < added_faces) {  // keep an unsplit input triangle's own vertex rotation
      const auto& in = mesh.triangles[p];
      for (int r = 0; r < 3; ++r)
        if (t[r] == in[0] && t[(r + 1) % 3] == in[1] && t[(r + 2) % 3] == in[2]) t = in;
    }
    children[p].push_back(t);
  }
  for (int t : alone) {
    if (splittable[t]) bisect_alone(mesh.triangles[t], max_area, result.mesh.vertices, children[t]);
    else children[t].push_back(mesh.triangles[t]);
  }
  result.parent.clear();
  for (int p = 0; p < nt; ++p)
    for (const auto& t : children[p]) {
      result.mesh.triangles.push_back(t);
      result.parent.push_back(p);
    }
  return result;
}

TriangleMesh subdivide_to_max_area(const TriangleMesh& mesh, double max_area) {
  return subdivide_to_max_area_with_parents(mesh, max_area).mesh;
}

}  // namespace lambert
