// Solution -> result JSON (SPEC §2), and the short human summary printed by `lambert solve`.
#pragma once

#include <string>

#include "solver/radiosity.h"
#include "solver/report.h"

namespace lambert {

// Positions are written in the scene's units; every per-area value is per square metre and every
// area is in m² (SPEC "Lengths").
std::string encode_result(const Scene& scene, const Solution& solution, const Report& report,
                          int indent = -1);

std::string summarize(const Scene& scene, const Solution& solution, const Report& report);

}  // namespace lambert
