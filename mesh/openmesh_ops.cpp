// OpenMesh side of mesh/mesh_ops.h: reading mesh files and longest-edge subdivision into patches.
// This is the only translation unit that includes OpenMesh; no OpenMesh type leaves it.
#include <OpenMesh/Core/IO/MeshIO.hh>  // first: older OpenMesh releases require it (STACK.md P12)
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <numeric>
#include <queue>
#include <set>
#include <sstream>
#include <tuple>

#include "mesh/mesh_ops.h"

namespace lambert {
namespace {

// Double-precision points: the default float points would round the file's coordinates.
struct DoubleTraits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using OmPolyMesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;
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

// ---- read_mesh_file -----------------------------------------------------------------------

// Element counts as the file declares them, to detect faces or vertices OpenMesh dropped or
// added while loading (STACK.md P13). vertices < 0: not comparable (STL stores corners per facet).
struct FileCounts {
  long vertices = -1;
  long faces = -1;
  std::string error;
};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

FileCounts count_obj(std::istream& in) {
  FileCounts c;
  c.vertices = c.faces = 0;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") ++c.vertices;
    else if (tag == "f") ++c.faces;
  }
  return c;
}

// OFF header: [ST][C][N][4][n]OFF [BINARY], comments with '#', then nV nF nE.
FileCounts count_off(std::istream& in) {
  FileCounts c;
  std::vector<std::string> tokens;
  std::string line;
  while (tokens.size() < 6 && std::getline(in, line)) {
    line = line.substr(0, line.find('#'));
    std::istringstream s(line);
    for (std::string t; s >> t;) tokens.push_back(t);
  }
  if (tokens.empty() || tokens[0].size() < 3 || tokens[0].substr(tokens[0].size() - 3) != "OFF") {
    c.error = "not an OFF file (no OFF header)";
    return c;
  }
  std::size_t k = 1;
  if (k < tokens.size() && tokens[k] == "BINARY") ++k;
  if (tokens[0].find('n') != std::string::npos) ++k;  // nOFF: dimension before the counts
  try {
    if (k + 1 >= tokens.size()) throw std::invalid_argument("missing counts");
    c.vertices = std::stol(tokens[k]);
    c.faces = std::stol(tokens[k + 1]);
  } catch (const std::exception&) {
    c.error = "OFF header has no vertex and face counts";
  }
  return c;
}

// OpenMesh's OFF reader misreads '#' comments (it then loads no vertices or faces) and counts on
// the header line. Ascii OFF is therefore handed to it normalized: comments and blank lines
// removed, the header keyword alone on the first line. Binary OFF is passed through unchanged.
std::string normalize_ascii_off(const std::string& text, bool& binary) {
  std::istringstream in(text);
  std::ostringstream out;
  std::string line;
  bool header = true;
  binary = false;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find('#'));
    std::istringstream s(line);
    std::string first;
    if (!(s >> first)) continue;  // blank or comment-only line
    if (header) {
      header = false;
      std::string rest;
      std::getline(s, rest);
      if (rest.find("BINARY") != std::string::npos) {
        binary = true;
        return text;
      }
      out << first << '\n';
      if (rest.find_first_not_of(" \t\r") != std::string::npos) out << rest << '\n';
      continue;
    }
    out << line << '\n';
  }
  return out.str();
}

// PLY header (ascii for every PLY flavour): "element vertex N", "element face N".
FileCounts count_ply(std::istream& in) {
  FileCounts c;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string word, element;
    long n = -1;
    s >> word;
    if (word == "end_header") break;
    if (word != "element") continue;
    s >> element >> n;
    if (element == "vertex") c.vertices = n;
    if (element == "face") c.faces = n;
  }
  if (c.vertices < 0 || c.faces < 0) c.error = "PLY header declares no vertex or face element";
  return c;
}

// STL: binary when the size matches the 84-byte header plus 50 bytes per facet, else ascii.
FileCounts count_stl(const std::string& path) {
  FileCounts c;
  std::ifstream in(path, std::ios::binary);
  char header[84] = {};
  in.read(header, 84);
  const auto size = std::filesystem::file_size(path);
  if (in.gcount() == 84) {
    std::uint32_t n = 0;
    for (int i = 0; i < 4; ++i) n |= std::uint32_t(static_cast<unsigned char>(header[80 + i])) << (8 * i);
    if (size == 84 + 50 * static_cast<std::uintmax_t>(n)) {
      c.faces = n;
      return c;
    }
  }
  in.clear();
  in.seekg(0);
  c.faces = 0;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string word;
    s >> word;
    if (word == "facet") ++c.faces;
  }
  return c;
}

MeshFileResult read_failure(const std::string& path, const std::string& why) {
  MeshFileResult r;
  r.error = path + ": " + why;
  return r;
}

// Fan triangulation is right for convex faces; a face where some fan triangle turns against the
// face's Newell normal is concave and goes through the constrained Delaunay triangulation.
std::string append_face(const std::vector<int>& face, TriangleMesh& mesh) {
  std::vector<Point3> p;
  for (int i : face) p.push_back(mesh.vertices[i]);
  Vector3 n;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Point3 &a = p[i], &b = p[(i + 1) % p.size()];
    n += Vector3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  bool convex = true;
  for (std::size_t i = 1; i + 1 < face.size(); ++i)
    convex = convex && dot(cross(p[i] - p[0], p[i + 1] - p[0]), n) > 0;
  if (convex || face.size() == 3) {
    for (std::size_t i = 1; i + 1 < face.size(); ++i)
      mesh.triangles.push_back({face[0], face[i], face[i + 1]});
    return {};
  }
  // Concave polygons in files are planar only to the precision of the written digits.
  PolygonTriangulation t = triangulate_polygon(p, 1e-4);
  if (!t.ok()) return t.error;
  for (const auto& tri : t.mesh.triangles) mesh.triangles.push_back({face[tri[0]], face[tri[1]], face[tri[2]]});
  return {};
}

}  // namespace

MeshFileResult read_mesh_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) return read_failure(path, "file does not exist");
  if (!fs::is_regular_file(path, ec)) return read_failure(path, "not a regular file");
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".stl")
    return read_failure(path, "unsupported extension '" + ext + "' (expected .obj, .ply, .off or .stl)");

  FileCounts counts;
  std::string normalized_off;  // non-empty: ascii OFF given to OpenMesh from memory
  if (ext == ".stl") {
    counts = count_stl(path);
  } else {
    std::ifstream in(path, std::ios::binary);
    if (!in) return read_failure(path, "cannot open the file");
    if (ext == ".off") {
      const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      bool binary = false;
      std::string normalized = normalize_ascii_off(text, binary);
      std::istringstream header(normalized);
      counts = count_off(header);
      if (!binary) normalized_off = std::move(normalized);
    } else {
      counts = ext == ".obj" ? count_obj(in) : count_ply(in);
    }
  }
  if (!counts.error.empty()) return read_failure(path, counts.error);

  silence_openmesh();
  OmPolyMesh om;
  {
    // OpenMesh's IO manager and readers are process-wide singletons with state.
    static std::mutex io_mutex;
    std::lock_guard<std::mutex> lock(io_mutex);
    OpenMesh::IO::Options options;
    bool parsed = false;
    if (normalized_off.empty()) {
      parsed = OpenMesh::IO::read_mesh(om, path, options);
    } else {
      std::istringstream in(normalized_off);
      parsed = OpenMesh::IO::read_mesh(om, in, ".off", options);
    }
    if (!parsed) return read_failure(path, "OpenMesh could not parse the file");
  }

  const long nv = static_cast<long>(om.n_vertices()), nf = static_cast<long>(om.n_faces());
  if (counts.faces == 0) return read_failure(path, "the file has no faces");
  if (nf != counts.faces)
    return read_failure(path, "OpenMesh loaded " + std::to_string(nf) + " of the " +
                                  std::to_string(counts.faces) +
                                  " faces in the file (faces with a repeated or invalid vertex, "
                                  "or fewer than 3 vertices, were dropped)");
  if (nf == 0) return read_failure(path, "the file has no faces");
  long file_vertices = counts.vertices;
  if (file_vertices < 0) {  // STL: OpenMesh merges corners, so any repeated position was added by it
    std::set<std::tuple<double, double, double>> distinct;
    for (const auto v : om.vertices()) {
      const auto& p = om.point(v);
      distinct.emplace(p[0], p[1], p[2]);
    }
    file_vertices = static_cast<long>(distinct.size());
  }
  if (nv != file_vertices)
    return read_failure(path, "OpenMesh turned the " + std::to_string(file_vertices) +
                                  " vertices of the file into " + std::to_string(nv) +
                                  " (faces at a non-manifold edge or vertex were detached onto "
                                  "duplicated vertices): the mesh is non-manifold");

  MeshFileResult result;
  result.mesh.vertices.reserve(nv);
  for (const auto v : om.vertices()) {
    const Point3 p = to_point3(om.point(v));
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return read_failure(path, "vertex " + std::to_string(v.idx()) + " has a non-finite coordinate");
    result.mesh.vertices.push_back(p);
  }
  std::vector<int> face;
  for (const auto f : om.faces()) {
    face.clear();
    for (const auto v : om.fv_range(f)) face.push_back(v.idx());
    const std::string error = append_face(face, result.mesh);
    if (!error.empty())
      return read_failure(path, "face " + std::to_string(f.idx()) + " cannot be triangulated: " + error);
  }
  return result;
}

// ---- subdivide_to_max_area ----------------------------------------------------------------

namespace {

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
