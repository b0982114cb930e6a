// The surface view-factor matrix (solver/thermal/view_factors.h) in the exchange formats of
// `lambert viewfactors` besides JSON (radiant_json.h):
// - CSV (RFC 4180): "i,j,F_ij", one row per non-zero factor, surfaces numbered from 0 in the input's
//   order; a pair left out has factor 0.
// - View3D's text output (its SaveF0, format 0, as ViewHT and View3D's own readers read it): a header
//   line "PROGRAM VERSION 0 ENCL DIDEMIT N" padded to 30 characters, the N areas, the N × N factors
//   row by row, the N emissivities; numbers separated by blanks (more digits than View3D prints).
// - EnergyPlus: one ZoneProperty:UserViewFactors:BySurfaceName object (Input Output Reference: "Zone
//   or ZoneList or Space or SpaceList Name", then extensible triplets "From Surface", "To Surface",
//   "View Factor"), every one of the N² pairs, by surface name.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/thermal/view_factors.h"

namespace lambert {

std::string view_factors_csv(const ViewFactorMatrix& m);

struct View3dHeader {
  std::string program = "Lambert", version;
  bool enclosure = false;     // the input's encl
  bool with_emittances = false;  // the factors are Hottel's total exchange factors (emit=1)
};
// `factors`: S × S row-major (m.F, or the total exchange factors); `emissivity` per surface (1 where
// absent).
std::string view_factors_view3d(const ViewFactorMatrix& m, const std::vector<double>& factors,
                                const std::vector<std::optional<double>>& emissivity, const View3dHeader& header);

// Throws std::invalid_argument where a surface name cannot be an EnergyPlus name (empty, more than
// 100 characters, a ',', ';' or '!', or equal to another's but for case) or the zone's cannot.
std::string view_factors_idf(const ViewFactorMatrix& m, const std::string& zone, const std::string& comment);

}  // namespace lambert
