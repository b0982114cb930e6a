// View factors and radiant exchange in JSON (SPEC §5): the "view_factors" and "thermal" objects of a
// result and of `lambert viewfactors`, and the saved factor files and thermal files that command reads
// back. nlohmann_json stays in the codecs (server/).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solver/thermal/radiant.h"

namespace lambert {

// {"surfaces": [{"name", "area"}], "F": [[F_IJ]], "row_sums", "reciprocity_residual", "geometry_hash"},
// with "emissivity" per surface where known (a View3D file's), "to_occluders" where occluders take a
// share, "total_exchange_factors" where computed, and with the patch matrix "patches" and
// "patch_factors" ({"i", "j", "F"}). Vertices in the scene's units (unit_m metres each).
nlohmann::json view_factors_json(const RadiantExchange& r, double unit_m,
                                 const std::vector<std::optional<double>>& emissivity = {});
// The same of a matrix alone (a saved factor file's).
nlohmann::json view_factors_json(const ViewFactorMatrix& m, const std::string& geometry_hash,
                                 const std::vector<std::optional<double>>& emissivity);

// The patch-level exchange: {"level": "patches", "geometry_hash", "surfaces": [{"name", "area",
// "thermal"}], "patches": [{"id", "surface", "vertices", "area", "thermal"}], "probes": [...],
// "balance": {"net_W", "occluders_net_W"}, "iterations", "residual"}; "thermal" is {"net_flux_W_m2",
// "net_W", "radiosity_W_m2", "irradiance_W_m2"} and, on a surface with a net flux, "temperature_K".
nlohmann::json thermal_json(const Scene& scene, const RadiantExchange& r);
// The surface-level exchange on a saved matrix: the same without patches and probes, "level": "surfaces".
nlohmann::json thermal_json(const ViewFactorMatrix& m, const GreyExchange& g, const std::string& geometry_hash);

// A saved factor file: the output of `lambert viewfactors` (or a result's "view_factors").
struct SavedFactors {
  ViewFactorMatrix matrix;
  std::string geometry_hash;
  std::vector<std::optional<double>> emissivity;  // per surface, where the file gives one
};
// nullopt when `doc` is not a factor file at all (no "F"); errors as "POINTER: message".
std::optional<SavedFactors> read_saved_factors(const nlohmann::json& doc, std::vector<std::string>& errors);

// A thermal file: {"geometry_hash"?: "...", "surfaces": {"NAME": {"emissivity"?, "temperature_K" |
// "net_flux_W_m2"}}}, by surface name. `names`: the surfaces it must cover, each with the emissivity
// it has where the input gives one (the entry may then leave it out). Errors as "POINTER: message".
struct ThermalFile {
  std::optional<std::string> geometry_hash;
  std::vector<SurfaceThermal> by_name;  // parallel to `names`
};
std::optional<ThermalFile> read_thermal_file(const std::string& text, const std::vector<std::string>& names,
                                             const std::vector<std::optional<double>>& emissivity,
                                             std::vector<std::string>& errors);

}  // namespace lambert
