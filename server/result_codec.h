// Solution -> result JSON (SPEC §2), and the short human summary printed by `lambert solve`.
#pragma once

#include <ostream>
#include <string>

#include "solver/radiosity.h"
#include "solver/report.h"

namespace lambert {

// Positions are written in the scene's units; every per-area value is per square metre and every
// area is in m² (SPEC "Lengths").
// The result JSON (SPEC §2), compact. write_result streams it: the patches, most of a large result,
// are never held as a document.
void write_result(std::ostream& os, const Scene& scene, const Solution& solution, const Report& report);
std::string encode_result(const Scene& scene, const Solution& solution, const Report& report);

std::string summarize(const Scene& scene, const Solution& solution, const Report& report);

}  // namespace lambert
