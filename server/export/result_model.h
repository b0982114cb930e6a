// A result file (SPEC §2) read back for drawing and export: each patch's triangle with its
// photometric values and colour, and the probes. Everything that is drawn or exported from a result
// (`lambert render RESULT.json`, `lambert export`, GET /v1/jobs/{id}/result.glb) reads it here, so a
// result means the same in every picture and file.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "mesh/geometry.h"

namespace lambert {

struct ResultPatch {
  Triangle triangle;                 // scene units (SPEC §5: patch vertices are in scene units)
  double area_m2 = 0;
  double illuminance_lx = 0;
  double luminance_cd_m2 = 0;
  std::array<double, 3> srgb{};      // linear sRGB of the radiance, absolute (Y in cd/m²)
  int surface = 0;                   // index into ResultModel::surfaces
};

// A probe: one point, or a grid of nu × nv points (u fastest) at cell centres.
struct ResultProbe {
  std::string name;
  bool is_grid = false;
  int nu = 1, nv = 1;
  std::vector<Point3> points;        // scene units
  std::vector<double> illuminance_lx;  // parallel to points
  std::string quantity = "planar";     // what the probe measures (SPEC §5 "quantity")
};

struct ResultModel {
  std::string name;
  std::vector<std::string> surfaces;  // names, in the order their first patch appears
  std::vector<ResultPatch> patches;
  std::vector<ResultProbe> probes;
  // Metres per scene unit: the patches' areas in m² against their vertices' (1, 0.01 or 0.001 when
  // it is one of the scene units of SPEC §1 to within 1e-6).
  double unit_m = 1;
  // The luminance the result's srgb_encoded shows as white (its brightest reflecting patch), when a
  // channel strictly inside (0, 1) tells it.
  std::optional<double> white_cd_m2;
};

// Reads a result document. Throws std::invalid_argument naming the JSON pointer of the first field
// it cannot use ("/patches/3/vertices: expected three points").
ResultModel read_result(const std::string& result_json);

// The display white for `model`: `requested` if given, else the result's own white, else its
// brightest patch's luminance, else 1.
double display_white(const ResultModel& model, std::optional<double> requested);

}  // namespace lambert
