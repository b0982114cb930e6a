// Meshes read from files ("file" surfaces, SPEC §1) inside the FileAccess sandbox, and the health
// check every mesh surface gets once it is in the solver's frame. The sandbox also serves every other
// file a scene names (luminaires' photometric files).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "server/codec/decoder.h"

namespace lambert::codec {

// The path of a file the scene names at p (rel, as written) under the FileAccess policy: relative to
// the scene's folder (command line), or inside the mesh root and never out of it through ".." or a
// symbolic link (the service), or refused (a service without a root). `what` names the file in
// messages ("mesh file"), `refused` the kind of scene item a service without a root refuses
// ("file surfaces"). nullopt after an error at p.
std::optional<std::filesystem::path> resolve_scene_file(Decoder& d, const std::string& rel, const std::string& p,
                                                        std::string_view what, std::string_view refused);

// The mesh of a "file" surface, in scene units as the file has it; nullopt after an error at p.
std::optional<TriangleMesh> decode_file_mesh(Decoder& d, const json& j, const std::string& p);

// How a mesh was given, which decides where its problems point.
enum class MeshSource { Inline, File };

// Degenerate triangles are errors, the rest (self-intersections, orientation, non-manifold edges)
// warnings. mesh in metres, after its transform.
void check_mesh_health(Decoder& d, const TriangleMesh& mesh, const std::string& p,
                       MeshSource source);

}  // namespace lambert::codec
