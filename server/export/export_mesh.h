// What the exchange formats carry of a result (lambert export, GET /v1/jobs/{id}/result.glb): per
// surface, indexed triangles whose vertices hold the position (metres), the patch normal, the
// display colour and the illuminance and luminance, smooth or flat (corner_values.h); and each
// probe's points with their illuminance.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "server/export/corner_values.h"
#include "server/export/result_model.h"

namespace lambert {

struct ExportOptions {
  Shading shading = Shading::Smooth;
  std::optional<double> white_cd_m2;  // absent: the result's own white (display_white)
};

// One surface's triangles. Vertices that agree in every attribute are shared.
struct ExportSurface {
  std::string name;
  std::vector<std::array<float, 3>> position_m, normal;
  // Linear sRGB of the radiance over the white, clipped to [0, 1]: the display colour before the
  // sRGB transfer curve (glTF's COLOR_0 is linear; the result's srgb_encoded is this, encoded).
  std::vector<std::array<float, 3>> colour;
  std::vector<float> illuminance_lx, luminance_cd_m2;
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from the front
};

// A probe's points in metres (a grid's nu × nv, u fastest) with their illuminance.
struct ExportProbe {
  std::string name;
  bool is_grid = false;
  int nu = 1, nv = 1;
  std::vector<std::array<float, 3>> position_m;
  std::vector<float> illuminance_lx;
};

struct ExportMesh {
  std::string name;
  Shading shading = Shading::Smooth;
  double white_cd_m2 = 1;
  std::vector<ExportSurface> surfaces;  // in the result's order, each with at least one triangle
  std::vector<ExportProbe> probes;      // in the result's order
};

ExportMesh export_mesh(const ResultModel& model, const ExportOptions& options);

}  // namespace lambert
