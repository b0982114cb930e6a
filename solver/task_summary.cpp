// The task-area summary (see task_summary.h).
#include "solver/task_summary.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lambert {
namespace {

constexpr double kCos45 = 0.70710678118654752440;

struct Accumulator {
  double area = 0, sum = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  void add(double A, double lx) {
    area += A, sum += A * lx;
    lo = std::min(lo, lx), hi = std::max(hi, lx);
  }
  std::optional<RoomSurfaceCheck> check(double mf) const {
    if (!(area > 0)) return std::nullopt;
    RoomSurfaceCheck c;
    c.area_m2 = area;
    c.mean_lx = mf * sum / area;
    c.min_lx = mf * lo;
    c.max_lx = mf * hi;
    c.u0 = c.mean_lx > 0 ? c.min_lx / c.mean_lx : 0;
    return c;
  }
};

}  // namespace

SurfaceRole patch_role(const Scene& scene, int surface, const Vector3& normal, bool by_role) {
  const Surface& s = scene.surfaces[surface];
  if (s.emission) return SurfaceRole::None;
  if (by_role) return s.role;
  const double c = dot(normal, scene.task_summary->up.value_or(Vector3{0, 0, 1}));
  if (c <= -kCos45) return SurfaceRole::Ceiling;
  if (std::abs(c) < kCos45) return SurfaceRole::Wall;
  return SurfaceRole::Floor;
}

std::optional<TaskSummary> make_task_summary(const Scene& scene, const Solution& sol, const Report& report) {
  if (!scene.task_summary) return std::nullopt;
  TaskSummary out;
  const double mf = scene.task_summary->maintenance_factor;
  out.maintenance_factor = mf;
  out.by_role = std::any_of(scene.surfaces.begin(), scene.surfaces.end(),
                            [](const Surface& s) { return s.role != SurfaceRole::None; });
  for (int k : scene.task_summary->grids) {
    const ProbeSummary& ps = report.probes.at(k);
    GridCheck g;
    g.name = scene.probes.at(k).name;
    g.quantity = scene.probes.at(k).quantity;
    g.points = ps.illuminance_lx.size();
    g.mean_lx = mf * ps.mean_lx;
    g.min_lx = mf * ps.min_lx;
    g.max_lx = mf * ps.max_lx;
    g.u0 = ps.min_over_mean;  // ratios: the maintenance factor cancels
    g.ud = ps.min_over_max;
    out.grids.push_back(std::move(g));
  }
  Accumulator walls, ceiling, floor;
  for (std::size_t i = 0; i < sol.patches.size(); ++i) {
    const Patch& patch = sol.patches[i];
    const double lx = report.patches[i].illuminance_lx;
    switch (patch_role(scene, patch.surface, patch.normal, out.by_role)) {
      case SurfaceRole::Wall: walls.add(patch.area_m2, lx); break;
      case SurfaceRole::Ceiling: ceiling.add(patch.area_m2, lx); break;
      case SurfaceRole::Floor: floor.add(patch.area_m2, lx); break;
      case SurfaceRole::None: break;
    }
  }
  out.walls = walls.check(mf);
  out.ceiling = ceiling.check(mf);
  out.floor = floor.check(mf);
  return out;
}

}  // namespace lambert
