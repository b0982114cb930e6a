// The probes of a result as CSV (RFC 4180): one row per point, for spreadsheets and plotting, with
// the probe's quantity last (planar, vertical, cylindrical, semicylindrical, hemispherical).
// Columns: probe (name), u, v (the grid cell, u fastest; 0, 0 for a single point), x, y, z (scene
// units, as in the result), illuminance_lx.
#pragma once

#include <string>

#include "server/export/result_model.h"

namespace lambert {

std::string write_probe_csv(const ResultModel& model);

}  // namespace lambert
