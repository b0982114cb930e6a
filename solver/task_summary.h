// The task-area summary (SPEC §5 "task_summary"): the figures EN 12464-1:2021 checks a lighting
// scheme against, with the maintenance factor applied (maintained values: Ēm = MF × the new
// installation's mean).
//   - per named grid (a task area, its immediate surroundings, a cylindrical grid ...): Ēm, Emin,
//     Emax, U0 = Emin/Ē and Ud = Emin/Emax of the grid's quantity;
//   - the walls' and the ceiling's (and the floor's) Ēm, Emin and U0 over their patches (area
//     means; Emin of the patches' mean illuminance), which §5.2.3 of the standard bounds below
//     (e.g. Ēm ≥ 50 lx on walls and 30 lx on ceilings, U0 ≥ 0.10).
// Walls, ceiling and floor are identified by the surfaces' "role" where any surface has one (the
// others, furniture, count as none of them); otherwise by orientation: a patch whose front normal n
// makes n·up ≤ −cos 45° faces down (ceiling), |n·up| < cos 45° faces sideways (wall), the rest up
// (floor). Emitting surfaces (luminaires, luminous panels) are never walls or ceilings.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "solver/radiosity.h"
#include "solver/report.h"

namespace lambert {

struct GridCheck {
  std::string name;
  ProbeQuantity quantity = ProbeQuantity::Planar;
  std::size_t points = 0;
  double mean_lx = 0, min_lx = 0, max_lx = 0;  // maintained
  double u0 = 0, ud = 0;                       // Emin/Ē, Emin/Emax (0 where Ē or Emax is 0)
};

struct RoomSurfaceCheck {
  double area_m2 = 0;
  double mean_lx = 0, min_lx = 0, max_lx = 0;  // maintained; area-weighted mean
  double u0 = 0;
};

struct TaskSummary {
  double maintenance_factor = 1;
  bool by_role = false;  // walls and ceiling from the surfaces' roles (else by orientation)
  std::vector<GridCheck> grids;
  // Absent where no patch is of that kind.
  std::optional<RoomSurfaceCheck> walls, ceiling, floor;
};

// The summary of a solved scene with a task_summary (nullopt without one). `report` is the
// solution's (make_report): the patches' and probes' illuminances.
std::optional<TaskSummary> make_task_summary(const Scene& scene, const Solution& sol, const Report& report);

// The role a patch of the given surface and front normal plays (TaskSummary's rule above).
SurfaceRole patch_role(const Scene& scene, int surface, const Vector3& normal, bool by_role);

}  // namespace lambert
