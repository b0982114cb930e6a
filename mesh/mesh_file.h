// Reading mesh files (OBJ, PLY ascii and binary, OFF, STL ascii and binary) into triangle meshes.
// Lambert's own strict readers, written for input from strangers: the file is the only file read
// (an OBJ's `mtllib` is never opened), it must be a regular file (never a FIFO or a device), every
// count a header declares is checked against the limits and against the bytes that follow before
// anything is allocated, every read ends within the file, coordinates are parsed as doubles, and
// anything not understood is an error that names the file and the line (or, in binary files, the
// element). Nothing is dropped, merged or repaired silently, except that STL's per-facet corners
// are welded where their coordinates are identical (the format has no shared vertices).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/geometry.h"

namespace lambert {

enum class MeshFormat { Obj, Ply, Off, Stl };

// The format named by a path's extension (case-insensitive .obj, .ply, .off, .stl).
std::optional<MeshFormat> mesh_format_of(std::string_view path);

// Bounds on what one file may make the reader allocate or compute. Counts are also checked against
// the file's size: a header may not declare more elements than the bytes after it can hold.
struct MeshReadLimits {
  std::uint64_t max_file_bytes = std::uint64_t{256} << 20;  // 256 MiB
  std::size_t max_vertices = 10'000'000;                    // 240 MB of double points
  std::size_t max_faces = 10'000'000;
  // Vertices of one polygon. A face with more is refused: real polygons (a circle in a CAD export)
  // have hundreds, and the concave ones go through a constrained triangulation.
  std::size_t max_face_vertices = 4096;
};

// Polygons as a file gives them: face f has the vertex indices indices[face_start[f] ..
// face_start[f + 1]) (0-based, counter-clockwise = front), and came from line face_line[f] of a
// text file (0 in a binary one).
struct PolygonMesh {
  std::vector<Point3> vertices;
  std::vector<std::size_t> face_start{0};
  std::vector<int> indices;
  std::vector<std::size_t> face_line;
  std::size_t face_count() const { return face_start.size() - 1; }
};

struct PolygonMeshResult {
  PolygonMesh mesh;
  std::string error;  // empty on success; else "line N: why" (text) or "why, naming the element"
  bool ok() const { return error.empty(); }
};

// Parses a whole file's bytes. Indices are checked (in range, no vertex twice in a face), every
// coordinate is finite, and there is at least one face.
PolygonMeshResult parse_mesh(std::string_view bytes, MeshFormat format, const MeshReadLimits& limits = {});

struct MeshFileResult {
  TriangleMesh mesh;           // polygons of the file triangulated (fans; concave ones constrained)
  std::string error;           // empty on success; else "PATH: [line N: ]why"
  bool ok() const { return error.empty(); }
};

// Polygons to triangles: a fan where the polygon is convex, a constrained Delaunay triangulation
// inside it where it is not. `name` prefixes the errors ("NAME: line N: face cannot be ...").
MeshFileResult triangulate_polygons(const PolygonMesh& polygons, const std::string& name);

// The whole of a regular file (never a FIFO or a device) of at most max_bytes, into `bytes`; the
// reason it cannot be read otherwise ("not a regular file", "the file has N bytes; the limit is M").
// Every file a scene names is read this way.
std::optional<std::string> read_regular_file(const std::string& path, std::uint64_t max_bytes, std::string& bytes);

// Opens `path` (which must be a regular file of at most limits.max_file_bytes), parses it in the
// format its extension names and triangulates its polygons.
MeshFileResult read_mesh_file(const std::string& path, const MeshReadLimits& limits = {});

}  // namespace lambert
