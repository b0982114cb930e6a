// A luminaire's standard UGR table (solver/ugr_table.h) as the result's "ugr_table" (SPEC §2,
// "luminaires") and as the text `lambert ugr-table` prints.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "solver/ugr_table.h"

namespace lambert {

// {"method", "H_m", "spacing_to_height", "luminous_flux_lm", "rooms", "reflectances", "crosswise",
// "endwise"}; null where there is no table (no luminous area).
nlohmann::json ugr_table_json(const std::optional<UgrTable>& table);

// The table laid out as makers publish it: a row per room, the five reflectance sets crosswise then
// endwise, one decimal ("-" where undefined).
std::string ugr_table_text(const UgrTable& table);

}  // namespace lambert
