#include "server/export/ply_writer.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "solver/spectrum.h"

namespace lambert {
namespace {

template <typename T>
void put(std::string& out, T value) {  // x86 and arm64 are little-endian, as the header says
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// A name on one comment line: line breaks would end the header's line early.
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

}  // namespace

std::string write_ply(const ExportMesh& mesh) {
  std::size_t vertices = 0, faces = 0;
  for (const ExportSurface& s : mesh.surfaces) vertices += s.position_m.size(), faces += s.indices.size() / 3;
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment Lambert result";
  if (!mesh.name.empty()) {
    out += " ";
    out += one_line(mesh.name);
  }
  out += "\ncomment colour: sRGB of the luminance, white = ";
  out += std::to_string(mesh.white_cd_m2);
  out += mesh.shading == Shading::Smooth ? " cd/m2; shading smooth" : " cd/m2; shading flat";
  out += "; positions in metres\n";
  for (std::size_t k = 0; k < mesh.surfaces.size(); ++k) {
    out += "comment surface ";
    out += std::to_string(k);
    out += " ";
    out += one_line(mesh.surfaces[k].name);
    out += "\n";
  }
  out += "element vertex ";
  out += std::to_string(vertices);
  out += "\nproperty float x\nproperty float y\nproperty float z\n"
         "property float nx\nproperty float ny\nproperty float nz\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\n"
         "property float illuminance_lx\nproperty float luminance_cd_m2\n"
         "element face ";
  out += std::to_string(faces);
  out += "\nproperty list uchar uint vertex_indices\nproperty uint surface\nend_header\n";
  for (const ExportSurface& s : mesh.surfaces)
    for (std::size_t v = 0; v < s.position_m.size(); ++v) {
      for (float x : s.position_m[v]) put(out, x);
      for (float x : s.normal[v]) put(out, x);
      for (float c : s.colour[v]) put(out, static_cast<std::uint8_t>(std::lround(255 * srgb_encode(c))));
      put(out, s.illuminance_lx[v]);
      put(out, s.luminance_cd_m2[v]);
    }
  std::uint32_t base = 0;
  for (std::size_t k = 0; k < mesh.surfaces.size(); ++k) {
    const ExportSurface& s = mesh.surfaces[k];
    for (std::size_t t = 0; t + 2 < s.indices.size(); t += 3) {
      put(out, std::uint8_t{3});
      for (int c = 0; c < 3; ++c) put(out, base + s.indices[t + c]);
      put(out, static_cast<std::uint32_t>(k));
    }
    base += static_cast<std::uint32_t>(s.position_m.size());
  }
  return out;
}

}  // namespace lambert
