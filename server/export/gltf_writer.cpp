// The GLB container (glTF 2.0 §4.4): a 12-byte header ("glTF", version 2, total length), then a JSON
// chunk padded with spaces and a BIN chunk padded with zeros, each to a multiple of 4 bytes.
#include "server/export/gltf_writer.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace lambert {
namespace {

using json = nlohmann::json;

// glTF's enums (the WebGL constants).
enum ComponentType : int { kFloat = 5126, kUnsignedInt = 5125 };
enum BufferTarget : int { kArrayBuffer = 34962, kElementArrayBuffer = 34963 };
enum PrimitiveMode : int { kPoints = 0 };
constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kGlbVersion = 2;
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"

class GltfBuilder {
 public:
  // Appends `count` elements of `components` floats (or uint32) and returns the accessor's index.
  template <typename T>
  int add(const T* data, std::size_t count, int components, ComponentType type, BufferTarget target,
          bool with_bounds) {
    const std::size_t bytes = count * components * sizeof(float);
    static_assert(sizeof(T) % 4 == 0);
    const std::size_t offset = bin_.size();
    bin_.resize(offset + bytes);
    std::memcpy(bin_.data() + offset, data, bytes);
    views_.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}, {"target", target}});
    static const char* kTypes[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
    json accessor = {{"bufferView", views_.size() - 1}, {"componentType", type}, {"count", count},
                     {"type", kTypes[components]}};
    if (with_bounds) bounds(accessor, reinterpret_cast<const float*>(data), count, components);
    accessors_.push_back(std::move(accessor));
    return static_cast<int>(accessors_.size() - 1);
  }

  json views() const { return views_; }
  json accessors() const { return accessors_; }
  const std::string& bin() const { return bin_; }

 private:
  // min and max per component, as the float values themselves (the validator compares exactly).
  static void bounds(json& accessor, const float* data, std::size_t count, int components) {
    std::vector<float> lo(components, std::numeric_limits<float>::infinity()), hi(components, -lo[0]);
    for (std::size_t i = 0; i < count; ++i)
      for (int c = 0; c < components; ++c) {
        lo[c] = std::min(lo[c], data[i * components + c]);
        hi[c] = std::max(hi[c], data[i * components + c]);
      }
    accessor["min"] = json(std::vector<double>(lo.begin(), lo.end()));
    accessor["max"] = json(std::vector<double>(hi.begin(), hi.end()));
  }

  std::string bin_;
  json views_ = json::array(), accessors_ = json::array();
};

void put_u32(std::string& out, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((v >> (8 * b)) & 0xFF));  // little-endian
}

std::string pad(std::string s, char with) {
  s.resize((s.size() + 3) / 4 * 4, with);
  return s;
}

}  // namespace

std::string write_glb(const ExportMesh& mesh) {
  GltfBuilder b;
  json meshes = json::array(), nodes = json::array(), roots = json::array();
  for (const ExportSurface& s : mesh.surfaces) {
    if (s.indices.empty()) throw std::invalid_argument("write_glb: surface " + s.name + " has no triangles");
    const std::size_t n = s.position_m.size();
    json attributes = {
        {"POSITION", b.add(s.position_m.data(), n, 3, kFloat, kArrayBuffer, true)},
        {"NORMAL", b.add(s.normal.data(), n, 3, kFloat, kArrayBuffer, false)},
        {"COLOR_0", b.add(s.colour.data(), n, 3, kFloat, kArrayBuffer, false)},
        {"_ILLUMINANCE_LX", b.add(s.illuminance_lx.data(), n, 1, kFloat, kArrayBuffer, true)},
        {"_LUMINANCE_CD_M2", b.add(s.luminance_cd_m2.data(), n, 1, kFloat, kArrayBuffer, true)}};
    const int indices = b.add(s.indices.data(), s.indices.size(), 1, kUnsignedInt, kElementArrayBuffer, false);
    meshes.push_back({{"name", s.name}, {"primitives", {{{"attributes", attributes}, {"indices", indices}, {"material", 0}}}}});
    roots.push_back(nodes.size());
    nodes.push_back({{"name", s.name}, {"mesh", meshes.size() - 1}});
  }
  // Probes as point clouds (mode 0, POINTS): a glTF viewer shows where they are, and Lambert's own
  // viewer reads each grid's nu × nv from the node's extras to draw its isolux lines.
  for (const ExportProbe& p : mesh.probes) {
    if (p.position_m.empty()) continue;
    const std::size_t n = p.position_m.size();
    json attributes = {{"POSITION", b.add(p.position_m.data(), n, 3, kFloat, kArrayBuffer, true)},
                       {"_ILLUMINANCE_LX", b.add(p.illuminance_lx.data(), n, 1, kFloat, kArrayBuffer, true)}};
    meshes.push_back({{"name", p.name}, {"primitives", {{{"attributes", attributes}, {"mode", kPoints}}}}});
    roots.push_back(nodes.size());
    nodes.push_back({{"name", p.name}, {"mesh", meshes.size() - 1},
                     {"extras", {{"probe", p.is_grid ? "grid" : "point"}, {"nu", p.nu}, {"nv", p.nv}}}});
  }
  json doc = {
      {"asset", {{"version", "2.0"}, {"generator", "Lambert " LAMBERT_VERSION " (lambert export)"}}},
      {"extensionsUsed", {"KHR_materials_unlit"}},
      {"scene", 0},
      {"scenes", {{{"name", mesh.name.empty() ? "lambert result" : mesh.name},
                   {"nodes", roots},
                   {"extras", {{"white_cd_m2", mesh.white_cd_m2},
                               {"shading", mesh.shading == Shading::Smooth ? "smooth" : "flat"},
                               {"colour", "linear sRGB of the luminance over white_cd_m2, clipped to 1"}}}}}},
      {"nodes", nodes},
      {"meshes", meshes},
      {"materials", {{{"name", "lambert radiance (unlit)"},
                      {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
                      {"extensions", {{"KHR_materials_unlit", json::object()}}}}}},
      {"buffers", {{{"byteLength", b.bin().size()}}}},
      {"bufferViews", b.views()},
      {"accessors", b.accessors()}};

  const std::string json_chunk = pad(doc.dump(), ' ');
  const std::string bin_chunk = pad(b.bin(), '\0');
  // The header's lengths are 32-bit.
  if (json_chunk.size() + bin_chunk.size() + 28 > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("write_glb: a GLB file holds at most 4 GiB; export fewer patches");
  std::string out;
  put_u32(out, kGlbMagic);
  put_u32(out, kGlbVersion);
  put_u32(out, static_cast<std::uint32_t>(12 + 8 + json_chunk.size() + 8 + bin_chunk.size()));
  put_u32(out, static_cast<std::uint32_t>(json_chunk.size()));
  put_u32(out, kChunkJson);
  out += json_chunk;
  put_u32(out, static_cast<std::uint32_t>(bin_chunk.size()));
  put_u32(out, kChunkBin);
  out += bin_chunk;
  return out;
}

}  // namespace lambert
