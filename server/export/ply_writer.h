// PLY (binary little-endian) of an ExportMesh: the same vertices as the glTF file, all surfaces in
// one mesh. Vertex properties x y z (metres), nx ny nz, red green blue (8-bit, the display colour
// after the sRGB transfer curve, as PLY viewers expect), illuminance_lx and luminance_cd_m2 (float);
// faces carry vertex_indices and `surface`, an index into the surfaces the header's comments list.
#pragma once

#include <string>

#include "server/export/export_mesh.h"

namespace lambert {

std::string write_ply(const ExportMesh& mesh);

}  // namespace lambert
