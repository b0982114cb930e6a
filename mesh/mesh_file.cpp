// Opening a mesh file safely, choosing its reader, and triangulating its polygons (mesh/mesh_file.h).
//
// Lambert reads mesh files itself rather than through OpenMesh's readers, which parse coordinates as
// float (500000.3 came back as 500000.3125), open an OBJ's material library wherever `mtllib`
// points (a FIFO there blocked the server, /dev/zero was read without end), allocate what a header
// declares (std::bad_alloc on `element vertex 2000000000`), loop for ever on a PLY without
// end_header, and drop or duplicate faces without saying so (STACK.md P13).
#include "mesh/mesh_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "mesh/mesh_ops.h"
#include "mesh/mesh_text.h"

namespace lambert {

namespace {

// Fan triangulation is right for convex faces; a face where some fan triangle turns against the
// face's Newell normal is concave and goes through the constrained Delaunay triangulation.
std::string append_face(const int* face, std::size_t count, const std::vector<Point3>& vertices,
                        TriangleMesh& mesh) {
  if (count == 3) {
    mesh.triangles.push_back({face[0], face[1], face[2]});
    return {};
  }
  std::vector<Point3> p;
  p.reserve(count);
  for (std::size_t i = 0; i < count; ++i) p.push_back(vertices[face[i]]);
  Vector3 n;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Point3 &a = p[i], &b = p[(i + 1) % p.size()];
    n += Vector3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  bool convex = true;
  for (std::size_t i = 1; i + 1 < count && convex; ++i) convex = dot(cross(p[i] - p[0], p[i + 1] - p[0]), n) > 0;
  if (convex) {
    for (std::size_t i = 1; i + 1 < count; ++i) mesh.triangles.push_back({face[0], face[i], face[i + 1]});
    return {};
  }
  // Concave polygons in files are planar only to the precision of the written digits.
  PolygonTriangulation t = triangulate_polygon(p, 1e-4);
  if (!t.ok()) return t.error;
  for (const auto& tri : t.mesh.triangles) mesh.triangles.push_back({face[tri[0]], face[tri[1]], face[tri[2]]});
  return {};
}

MeshFileResult failure(const std::string& name, const std::string& why) {
  MeshFileResult r;
  r.error = name + ": " + why;
  return r;
}

}  // namespace

// O_NONBLOCK: opening a FIFO must not wait for a writer; fstat on the opened descriptor then refuses
// anything but a regular file, so what is checked is what is read.
std::optional<std::string> read_regular_file(const std::string& path, std::uint64_t max_bytes, std::string& bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return errno == ENOENT ? std::string("file does not exist") : "cannot open it (" + std::string(std::strerror(errno)) + ")";
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) return "cannot stat it (" + std::string(std::strerror(errno)) + ")";
  if (!S_ISREG(st.st_mode)) return std::string("not a regular file");
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes)
    return "the file has " + std::to_string(size) + " bytes; the limit is " + std::to_string(max_bytes);
  bytes.resize(size);
  std::size_t got = 0;
  while (got < size) {  // a file that shrinks meanwhile is read as far as it goes
    const ssize_t n = ::read(fd, bytes.data() + got, size - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return "cannot read it (" + std::string(std::strerror(errno)) + ")";
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  bytes.resize(got);
  return std::nullopt;
}

MeshFileResult triangulate_polygons(const PolygonMesh& polygons, const std::string& name) {
  MeshFileResult result;
  result.mesh.vertices = polygons.vertices;
  result.mesh.triangles.reserve(polygons.indices.size() - 2 * polygons.face_count());
  for (std::size_t f = 0; f < polygons.face_count(); ++f) {
    const std::size_t start = polygons.face_start[f], count = polygons.face_start[f + 1] - start;
    const std::string error = append_face(polygons.indices.data() + start, count, polygons.vertices, result.mesh);
    if (error.empty()) continue;
    const std::size_t line = polygons.face_line[f];
    return failure(name, (line > 0 ? "line " + std::to_string(line) + ": the face" : "face " + std::to_string(f)) +
                             " cannot be triangulated: " + error);
  }
  return result;
}

MeshFileResult read_mesh_file(const std::string& path, const MeshReadLimits& limits) {
  const auto format = mesh_format_of(path);
  if (!format)
    return failure(path, "unsupported extension '" + std::filesystem::path(path).extension().string() +
                             "' (expected .obj, .ply, .off or .stl)");
  std::string bytes;
  if (auto problem = read_regular_file(path, limits.max_file_bytes, bytes)) return failure(path, *problem);
  PolygonMeshResult polygons = parse_mesh(bytes, *format, limits);
  if (!polygons.ok()) return failure(path, polygons.error);
  bytes.clear();
  bytes.shrink_to_fit();
  return triangulate_polygons(polygons.mesh, path);
}

}  // namespace lambert
