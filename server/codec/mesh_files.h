// Meshes read from files ("file" surfaces, SPEC §1) inside the FileAccess sandbox, and the health
// check every mesh surface gets once it is in the solver's frame.
#pragma once

#include <optional>
#include <string>

#include "server/codec/decoder.h"

namespace lambert::codec {

// The mesh of a "file" surface, in scene units as the file has it; nullopt after an error at p.
std::optional<TriangleMesh> decode_file_mesh(Decoder& d, const json& j, const std::string& p);

// How a mesh was given, which decides where its problems point.
enum class MeshSource { Inline, File };

// Degenerate triangles are errors, the rest (self-intersections, orientation, non-manifold edges)
// warnings. mesh in metres, after its transform.
void check_mesh_health(Decoder& d, const TriangleMesh& mesh, const std::string& p,
                       MeshSource source);

}  // namespace lambert::codec
