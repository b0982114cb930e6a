// File meshes behind the --mesh-root sandbox, and mesh health checks (server/codec/mesh_files.h).
#include "server/codec/mesh_files.h"

#include <algorithm>
#include <filesystem>
#include <system_error>
#include <utility>

#include "mesh/mesh_ops.h"

namespace lambert::codec {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxListedPerMesh = 20;  // degenerate triangles listed per surface

// Policy::UnderRoot. Messages here never show server paths: the scene may come from an HTTP client.
std::optional<fs::path> resolve_under_root(Decoder& d, const fs::path& path, const std::string& rel,
                                           const std::string& p, std::string_view what) {
  if (path.is_absolute() || path.has_root_name() || path.has_root_directory()) {
    d.error(p, "the file path must be relative to the mesh root, got " + quote_text(rel));
    return std::nullopt;
  }
  for (const fs::path& part : path)
    if (part == "..") {
      d.error(p, "the file path must not contain '..'");
      return std::nullopt;
    }
  std::error_code ec;
  const fs::path root = fs::canonical(d.files().root, ec);
  if (ec) {
    d.error(p, "the server's mesh root cannot be resolved");
    return std::nullopt;
  }
  // Symlinks are followed; what counts is where the file really is. (A link swapped between
  // this check and the read is outside this threat model: the root is the operator's.)
  const fs::path real = fs::canonical(root / path, ec);
  if (ec || !fs::is_regular_file(real, ec)) {
    d.error(p, std::string(what) + " " + quote_text(rel) + " not found under the mesh root");
    return std::nullopt;
  }
  auto [root_end, real_it] = std::mismatch(root.begin(), root.end(), real.begin(), real.end());
  if (root_end != root.end() || real_it == real.end()) {
    d.error(p, std::string(what) + " " + quote_text(rel) + " resolves (through a symbolic link) outside the mesh root");
    return std::nullopt;
  }
  return real;
}

}  // namespace

std::optional<std::filesystem::path> resolve_scene_file(Decoder& d, const std::string& rel, const std::string& p,
                                                        std::string_view what, std::string_view refused) {
  if (rel.empty()) {
    d.error(p, "the file path must not be empty");
    return std::nullopt;
  }
  if (rel.find('\0') != std::string::npos) {
    d.error(p, "the file path must not contain NUL characters");
    return std::nullopt;
  }
  const fs::path path(rel);
  switch (d.files().policy) {
    case FileAccess::Policy::Deny:
      d.error(p, std::string(refused) + " are not allowed here (start the server with --mesh-root)");
      return std::nullopt;
    case FileAccess::Policy::Anywhere: {
      const fs::path full = path.is_absolute() ? path : d.files().base_dir / path;
      std::error_code ec;
      if (!fs::is_regular_file(full, ec)) {
        d.error(p, std::string(what) + " " + quote_text(rel) + " not found (looked for " + full.string() + ")");
        return std::nullopt;
      }
      return full;
    }
    case FileAccess::Policy::UnderRoot: return resolve_under_root(d, path, rel, p, what);
  }
  return std::nullopt;
}

std::optional<TriangleMesh> decode_file_mesh(Decoder& d, const json& j, const std::string& p) {
  auto rel = d.string(j, p);
  if (!rel) return std::nullopt;
  auto path = resolve_scene_file(d, *rel, p, "mesh file", "file surfaces");
  if (!path) return std::nullopt;
  MeshFileResult file = read_mesh_file(path->string());
  if (!file.ok()) {
    // The reader names the full path; show the scene's own path instead, so that an HTTP client
    // never learns where the server's mesh root is.
    std::string message = file.error;
    if (const std::string full = path->string() + ": "; message.rfind(full, 0) == 0)
      message = *rel + ": " + message.substr(full.size());
    d.error(p, message);
    return std::nullopt;
  }
  if (file.mesh.triangles.empty()) {
    d.error(p, "the mesh file has no triangles");
    return std::nullopt;
  }
  const int n = static_cast<int>(file.mesh.vertices.size());
  for (std::size_t k = 0; k < file.mesh.vertices.size(); ++k) {
    if (!within_coordinate_limit(file.mesh.vertices[k])) {
      d.error(p, "vertex " + std::to_string(k) +
                     " is not finite or beyond the coordinate limit of 1e9 scene units");
      return std::nullopt;
    }
  }
  for (std::size_t k = 0; k < file.mesh.triangles.size(); ++k)
    for (int idx : file.mesh.triangles[k])
      if (idx < 0 || idx >= n) {
        d.error(p, "triangle " + std::to_string(k) + " has a vertex index out of range");
        return std::nullopt;
      }
  return std::move(file.mesh);
}

// In the solver's frame (metres, after transform). Degenerate triangles would make the solver
// divide by zero areas: errors. The rest a radiosity solve survives: warnings.
void check_mesh_health(Decoder& d, const TriangleMesh& mesh, const std::string& p,
                       MeshSource source) {
  const MeshHealth health = check_mesh(mesh);
  const std::size_t listed = std::min(health.degenerate_triangles.size(), kMaxListedPerMesh);
  for (std::size_t k = 0; k < listed; ++k) {
    const int t = health.degenerate_triangles[k];
    if (source == MeshSource::Inline)
      d.error(index_ptr(p + "/triangles", static_cast<std::size_t>(t)),
              "degenerate triangle (zero area)");
    else
      d.error(p, "triangle " + std::to_string(t) + " of the file is degenerate (zero area)");
  }
  if (health.degenerate_triangles.size() > listed)
    d.error(p, std::to_string(health.degenerate_triangles.size() - listed) +
                   " more degenerate triangles");
  if (!health.self_intersections.empty()) {
    const auto [a, b] = health.self_intersections.front();
    d.warn(p, std::to_string(health.self_intersections.size()) +
                  " pairs of triangles intersect each other (e.g. triangles " + std::to_string(a) +
                  " and " + std::to_string(b) + ")");
  }
  if (!health.consistently_oriented)
    d.warn(p, "triangles are not consistently oriented (front and back sides mixed)");
  if (!health.manifold) d.warn(p, "some edges are shared by more than two triangles (non-manifold)");
}

}  // namespace lambert::codec
