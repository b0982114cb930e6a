// Mesh files (tests/fuzz/entries.h): the bytes go through parse_mesh and triangulate_polygons, which is
// read_mesh_file after its sandboxed open of the file.
#include <cmath>
#include <string>

#include "mesh/mesh_file.h"
#include "tests/fuzz/entries.h"

namespace lambert::fuzz {

namespace {

bool finite(const Point3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// What mesh_file.h promises of an accepted file: at least one face, finite coordinates (as doubles),
// every triangle's corners in range and distinct.
std::string broken_promise(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) return "accepted without a triangle";
  for (const Point3& p : mesh.vertices)
    if (!finite(p)) return "accepted a coordinate that is not finite";
  const long n = static_cast<long>(mesh.vertices.size());
  for (const auto& t : mesh.triangles) {
    for (int i : t)
      if (i < 0 || i >= n) return "a triangle's index " + std::to_string(i) + " is outside [0, " + std::to_string(n) + ")";
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return "a triangle repeats a corner";
  }
  return {};
}

MeshFormat format_of(Target target) {
  switch (target) {
    case Target::kPly: return MeshFormat::Ply;
    case Target::kOff: return MeshFormat::Off;
    case Target::kStl: return MeshFormat::Stl;
    default: return MeshFormat::Obj;
  }
}

}  // namespace

Outcome read_mesh_bytes(Target format, std::string_view bytes) {
  const std::string name(kInputName);
  PolygonMeshResult polygons = parse_mesh(bytes, format_of(format));
  // read_mesh_file names the file before the reader's "line N: why".
  if (!polygons.ok()) return {Verdict::kRefused, name + ": " + polygons.error};
  MeshFileResult file = triangulate_polygons(polygons.mesh, name);
  if (!file.ok()) return {Verdict::kRefused, file.error};
  std::string broken = broken_promise(file.mesh);
  if (!broken.empty()) return {Verdict::kBroken, std::move(broken)};
  return {Verdict::kAccepted, {}};
}

}  // namespace lambert::fuzz
