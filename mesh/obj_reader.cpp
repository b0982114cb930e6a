// Wavefront OBJ: `v` and `f` statements (Wavefront's "Object Files (.obj)", Advanced Visualizer
// manual, appendix B). Materials come from the scene, so `mtllib` and `usemtl` are skipped and no
// material library is ever opened: the mesh file is the only file an OBJ makes Lambert read.
#include <algorithm>
#include <array>
#include <vector>

#include "mesh/mesh_text.h"

namespace lambert::mesh_io {
namespace {

// Statements that carry nothing a radiosity surface uses: texture and normal data, grouping,
// smoothing, materials, display attributes, and lines and points (no area).
constexpr std::array<std::string_view, 21> kSkipped = {
    "vt", "vn", "vp", "g", "o", "s", "mtllib", "usemtl", "l", "p", "mg",
    "bevel", "c_interp", "d_interp", "lod", "maplib", "usemap", "shadow_obj", "trace_obj", "ctech", "stech"};
// Free-form curves and surfaces, which would need a tessellator.
constexpr std::array<std::string_view, 14> kFreeForm = {
    "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp", "end", "con"};

bool one_of(std::string_view word, const auto& list) {
  return std::find(list.begin(), list.end(), word) != list.end();
}

std::string number_problem(std::string_view word, NumberStatus status) {
  switch (status) {
    case NumberStatus::NotFinite: return in_quotes(word) + " is not finite";
    case NumberStatus::OutOfRange: return in_quotes(word) + " is out of the double range";
    default: return in_quotes(word) + " is not a number";
  }
}

// "v x y z", optionally followed by w (rational weight, unused for polygons) or by r g b (MeshLab's
// vertex colours).
std::optional<std::string> read_vertex(Words& words, PolygonMesh& m, const MeshReadLimits& limits) {
  if (m.vertices.size() >= limits.max_vertices)
    return "more than " + std::to_string(limits.max_vertices) + " vertices (the limit)";
  double c[7];
  std::size_t n = 0;
  while (auto w = words.next()) {
    if (n == 7) return std::string("a vertex has more than 7 numbers; expected x y z [w] or x y z r g b");
    const Real r = parse_real(*w);
    if (r.status == NumberStatus::NotFinite && n < 3)
      return "vertex " + std::to_string(m.vertices.size() + 1) + " has a coordinate that is not finite (" +
             "xyz"[n] + " = " + std::string(*w) + ")";
    if (r.status != NumberStatus::Ok) return "vertex " + std::to_string(m.vertices.size() + 1) + ": " +
                                             number_problem(*w, r.status);
    c[n++] = r.value;
  }
  if (n != 3 && n != 4 && n != 6)
    return "a vertex has " + std::to_string(n) + " numbers; expected x y z [w] or x y z r g b";
  m.vertices.push_back({c[0], c[1], c[2]});
  return std::nullopt;
}

// One corner "v", "v/vt", "v//vn" or "v/vt/vn": the vertex index resolved to 0-based (negative
// indices count back from the last vertex so far), texture and normal indices checked for form only.
std::optional<std::string> read_corner(std::string_view word, std::size_t vertex_count, int& index) {
  const std::size_t s1 = word.find('/');
  const std::string_view v = word.substr(0, s1);
  if (s1 != std::string_view::npos) {
    const std::string_view rest = word.substr(s1 + 1);
    const std::size_t s2 = rest.find('/');
    const std::string_view vt = rest.substr(0, s2), vn = s2 == std::string_view::npos ? "" : rest.substr(s2 + 1);
    const bool bad_vt = !vt.empty() && (!parse_integer(vt, -(1LL << 31), 1LL << 31) || vt == "0");
    const bool bad_vn = s2 != std::string_view::npos &&
                        (vn.find('/') != std::string_view::npos || !parse_integer(vn, -(1LL << 31), 1LL << 31) ||
                         vn == "0");
    if (bad_vt || bad_vn || (vt.empty() && s2 == std::string_view::npos))
      return "face corner " + in_quotes(word) + " is not v, v/vt, v//vn or v/vt/vn";
  }
  const auto i = parse_integer(v, -(1LL << 40), 1LL << 40);
  if (!i || *i == 0) return "face corner " + in_quotes(word) + " does not start with a vertex index (1, 2, ... or -1, -2, ...)";
  const long long n = static_cast<long long>(vertex_count);
  const long long resolved = *i > 0 ? *i - 1 : n + *i;
  if (resolved < 0 || resolved >= n)
    return "vertex index " + std::to_string(*i) + " is out of range (" + std::to_string(n) +
           " vertices so far; a face may use only vertices defined above it)";
  index = static_cast<int>(resolved);
  return std::nullopt;
}

std::optional<std::string> read_obj_face(Words& words, PolygonMesh& m, std::vector<int>& corners,
                                         std::size_t line, const MeshReadLimits& limits) {
  corners.clear();
  while (auto w = words.next()) {
    if (corners.size() == limits.max_face_vertices)
      return "a face has more than " + std::to_string(limits.max_face_vertices) + " vertices (the limit)";
    int index = 0;
    if (auto e = read_corner(*w, m.vertices.size(), index)) return e;
    corners.push_back(index);
  }
  return add_face(m, corners.data(), corners.size(), m.vertices.size(), line, limits, 1);
}

}  // namespace

PolygonMeshResult parse_obj(std::string_view bytes, const MeshReadLimits& limits) {
  PolygonMeshResult result;
  PolygonMesh& m = result.mesh;
  TextLines lines(bytes);
  std::vector<int> corners;
  while (lines.next()) {
    const std::string_view line = lines.line();
    Words words(line);
    const auto tag = words.next();
    if (!tag || tag->front() == '#') continue;
    std::optional<std::string> problem;
    if (line.back() == '\\') problem = "line continuation ('\\' at the end of a line) is not supported";
    else if (*tag == "v") problem = read_vertex(words, m, limits);
    else if (*tag == "f" || *tag == "fo") problem = read_obj_face(words, m, corners, lines.number(), limits);
    else if (one_of(*tag, kFreeForm))
      problem = "free-form geometry (" + in_quotes(*tag) + ") is not supported; export polygons";
    else if (!one_of(*tag, kSkipped))
      problem = "unknown statement " + in_quotes(*tag);
    if (problem) return failure(at_line(lines.number(), *problem));
  }
  if (m.face_count() == 0) return failure("the file has no faces");
  return result;
}

}  // namespace lambert::mesh_io
