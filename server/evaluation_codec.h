// The evaluations of a result (SPEC §5): "task_summary" (solver/task_summary.h) and "glare"
// (solver/glare.h), written beside the result's other sections by write_result.
#pragma once

#include <nlohmann/json.hpp>

#include "solver/radiosity.h"
#include "solver/report.h"

namespace lambert {

// Adds "task_summary" and "glare" to `out` where the scene asks for them.
void write_evaluations(nlohmann::json& out, const Scene& scene, const Solution& sol, const Report& report);

}  // namespace lambert
