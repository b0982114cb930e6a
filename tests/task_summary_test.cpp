// The task-area summary (solver/task_summary.h) in a black room lit by an isotropic point source,
// where every figure has a closed form: a patch's mean irradiance is I Ω(T) / A(T) (REFERENCES P1:
// the flux into a triangle is I times its solid angle), a grid point's is I h / d³.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "solver/form_factor.h"
#include "solver/radiosity.h"
#include "solver/report.h"
#include "solver/task_summary.h"
#include "tests/scene_builder.h"

namespace lambert {
namespace {

using test::rectangle;
using test::SceneBuilder;

constexpr double kI = 100;  // W/sr at 555 nm: 68 300 cd
const Point3 kLight{2, 1.5, 2.5};

// A 4 × 3 × 3 m black room, z up; its six faces as separate surfaces (each with a role if asked).
SceneBuilder room(bool roles) {
  SceneBuilder b;
  const int black = b.material("black", 0.0);
  const double X = 4, Y = 3, Z = 3;
  auto face = [&](const char* name, const Point3& o, const Vector3& u, const Vector3& v, SurfaceRole role) {
    Surface& s = b.surface(name, black, rectangle(o, u, v));
    if (roles) s.role = role;
  };
  face("floor", {0, 0, 0}, {X, 0, 0}, {0, Y, 0}, SurfaceRole::Floor);
  face("ceiling", {0, 0, Z}, {0, Y, 0}, {X, 0, 0}, SurfaceRole::Ceiling);
  face("south", {0, 0, 0}, {0, 0, Z}, {X, 0, 0}, SurfaceRole::Wall);
  face("north", {0, Y, 0}, {X, 0, 0}, {0, 0, Z}, SurfaceRole::Wall);
  face("west", {0, 0, 0}, {0, Y, 0}, {0, 0, Z}, SurfaceRole::Wall);
  face("east", {X, 0, 0}, {0, 0, Z}, {0, Y, 0}, SurfaceRole::Wall);
  b.point_light(kLight, kI);
  Probe grid;
  grid.name = "workplane";
  grid.normal = {0, 0, 1};
  grid.is_grid = true;
  grid.nu = 4, grid.nv = 3;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) grid.points.push_back({0.5 + i, 0.5 + j, 0.8});
  b.scene().probes.push_back(grid);
  b.max_patch_area(0.25);
  return b;
}

struct Expected {
  double area = 0, sum = 0, lo = std::numeric_limits<double>::infinity();
};

TEST(TaskSummary, RoomAndGridAgainstThePointSourceClosedForms) {
  for (const bool roles : {true, false}) {
    SceneBuilder b = room(roles);
    b.scene().task_summary = TaskSummaryOptions{0.8, roles ? std::nullopt : std::optional<Vector3>(Vector3{0, 0, 1}), {0}};
    const Solution sol = solve(b.scene());
    const Report report = make_report(b.scene(), sol);
    const auto summary = make_task_summary(b.scene(), sol, report);
    ASSERT_TRUE(summary);
    EXPECT_EQ(summary->by_role, roles);
    // Illuminance per W m^-2 at 555 nm: 683 lm/W × ȳ(555) (the grid's single wavelength).
    const double lx_per_W = report.patches[0].illuminance_lx / sol.irradiance[0];
    const double mf = 0.8;
    Expected walls, ceiling;
    for (const Patch& p : sol.patches) {
      const double E = kI * triangle_solid_angle(kLight, p.triangle) / p.area_m2 * lx_per_W;
      const std::string& name = b.scene().surfaces[p.surface].name;
      Expected* e = name == "ceiling" ? &ceiling : (name == "floor" ? nullptr : &walls);
      if (!e) continue;
      e->area += p.area_m2, e->sum += p.area_m2 * E, e->lo = std::min(e->lo, E);
    }
    ASSERT_TRUE(summary->walls && summary->ceiling && summary->floor);
    EXPECT_NEAR(summary->walls->area_m2, 2 * (4 + 3) * 3, 1e-9);
    EXPECT_NEAR(summary->walls->mean_lx, mf * walls.sum / walls.area, 1e-9 * walls.sum / walls.area);
    EXPECT_NEAR(summary->walls->min_lx, mf * walls.lo, 1e-9 * walls.lo);
    EXPECT_NEAR(summary->walls->u0, walls.lo / (walls.sum / walls.area), 1e-9);
    EXPECT_NEAR(summary->ceiling->mean_lx, mf * ceiling.sum / ceiling.area, 1e-9 * ceiling.sum / ceiling.area);
    EXPECT_NEAR(summary->ceiling->min_lx, mf * ceiling.lo, 1e-9 * ceiling.lo);
    // The walls' flux is the point's solid angle of the walls: Σ A E = I Ω(walls); the mean is
    // independent of the meshing.
    ASSERT_EQ(summary->grids.size(), 1u);
    const GridCheck& g = summary->grids[0];
    double sum = 0, lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (const Point3& q : b.scene().probes[0].points) {
      const Vector3 d = kLight - q;
      const double E = kI * d.z / std::pow(length(d), 3) * lx_per_W;  // E = I h / d³
      sum += E, lo = std::min(lo, E), hi = std::max(hi, E);
    }
    EXPECT_EQ(g.points, 12u);
    EXPECT_NEAR(g.mean_lx, mf * sum / 12, 1e-9 * sum / 12);
    EXPECT_NEAR(g.min_lx, mf * lo, 1e-9 * lo);
    EXPECT_NEAR(g.max_lx, mf * hi, 1e-9 * hi);
    EXPECT_NEAR(g.u0, lo / (sum / 12), 1e-9);
    EXPECT_NEAR(g.ud, lo / hi, 1e-9);
  }
}

TEST(TaskSummary, OrientationRule) {
  // Without roles: faces within 45° of down are ceiling, within 45° of horizontal walls; an emitter
  // is neither (a luminous panel on the ceiling is a luminaire).
  SceneBuilder b;
  const int m = b.material("m", 0.5);
  b.surface("panel", m, rectangle({0, 0, 3}, {0, 1, 0}, {1, 0, 0}), 1.0);
  b.scene().task_summary = TaskSummaryOptions{1, Vector3{0, 0, 1}, {}};
  const Scene& s = b.scene();
  EXPECT_EQ(patch_role(s, 0, {0, 0, -1}, false), SurfaceRole::None);  // the emitting panel
  b.surface("x", m, rectangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  EXPECT_EQ(patch_role(s, 1, normalize(Vector3{1, 0, -1.01}), false), SurfaceRole::Ceiling);
  EXPECT_EQ(patch_role(s, 1, normalize(Vector3{1, 0, -0.99}), false), SurfaceRole::Wall);
  EXPECT_EQ(patch_role(s, 1, normalize(Vector3{1, 0, 0.99}), false), SurfaceRole::Wall);
  EXPECT_EQ(patch_role(s, 1, normalize(Vector3{1, 0, 1.01}), false), SurfaceRole::Floor);
}

}  // namespace
}  // namespace lambert
