// glTF 2.0 binary (.glb) of an ExportMesh: one node and one mesh per surface, one unlit material
// (KHR_materials_unlit) so that a viewer shows the vertex colours as they are, not lit again.
// Attributes: POSITION (metres), NORMAL, COLOR_0 (linear sRGB, the display colour) and the custom
// _ILLUMINANCE_LX and _LUMINANCE_CD_M2 (float scalars; custom names start with "_", glTF 2.0
// §3.7.2.1). The scene's extras give the white (cd/m²) and the shading.
#pragma once

#include <string>

#include "server/export/export_mesh.h"

namespace lambert {

// The file's bytes.
std::string write_glb(const ExportMesh& mesh);

}  // namespace lambert
