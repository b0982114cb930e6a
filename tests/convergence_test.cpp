// Convergence under refinement, for both transport operators: the issue-4 room (6 × 4 × 3 m, every
// surface ρ = 0.5, a 1 m² Lambertian panel flush in the ceiling) has no closed form with
// interreflection, so the independent answer is the dense method on a finer mesh than any rung
// (for the hierarchical method a second method; for the dense method the same one, refined).
// What is checked: the sensors' error against it falls monotonically, rung by rung, in rms and at the
// worst sensor; the solve's own error estimate (output.error_estimate) is at least that error; and
// tightening solver.accuracy brings the hierarchical answer toward its limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tests/scene_builder.h"

namespace lambert {
namespace {

using test::SceneBuilder;

constexpr double kRoomArea = 2 * (6 * 4 + 6 * 3 + 4 * 3);  // m², what max_patch_area divides

Scene room(double target_patches, SolverMethod method, double accuracy = 1e-3) {
  SceneBuilder b;
  const int grey = b.material("grey", 0.5);
  std::vector<Triangle> walls_floor;
  test::for_each_box_face({0, 0, 0}, {6, 4, 3}, [&](const Point3& o, const Vector3& u, const Vector3& v) {
    if (o.z == 3 && u.z == 0 && v.z == 0) return;  // the ceiling: a ring around the panel, below
    for (const Triangle& t : test::rectangle(o, u, v)) walls_floor.push_back(t);
  });
  b.surface("walls-floor", grey, walls_floor);
  // The ceiling's ring, facing down: the outer corners and the panel's corners at z = 3.
  const Point3 o[4] = {{0, 0, 3}, {6, 0, 3}, {6, 4, 3}, {0, 4, 3}};
  const Point3 i[4] = {{2.5, 1.5, 3}, {3.5, 1.5, 3}, {3.5, 2.5, 3}, {2.5, 2.5, 3}};
  std::vector<Triangle> ring;
  for (int k = 0; k < 4; ++k) {
    const int n = (k + 1) % 4;
    ring.push_back(Triangle{{o[k], i[k], o[n]}});
    ring.push_back(Triangle{{o[n], i[k], i[n]}});
  }
  b.surface("ceiling", grey, ring);
  b.surface("panel", grey, test::rectangle({2.5, 1.5, 3}, {0, 1, 0}, {1, 0, 0}), kPi);  // L = 1
  Probe sensors;
  sensors.name = "sensors";
  sensors.normal = {0, 0, 1};
  for (int v = 0; v < 8; ++v)
    for (int u = 0; u < 12; ++u) sensors.points.push_back({(u + 0.5) * 0.5, (v + 0.5) * 0.5, 0.01});
  b.scene().probes.push_back(sensors);
  b.max_patch_area(kRoomArea / target_patches);
  b.scene().solver.method = method;
  b.scene().solver.accuracy = accuracy;
  return b.scene();
}

struct Error {
  double rms = 0, worst = 0;  // relative, over the sensors
};

Error error_against(const Solution& sol, const Solution& reference) {
  const std::vector<double>& e = sol.probes[0].irradiance;
  const std::vector<double>& r = reference.probes[0].irradiance;
  Error out;
  for (std::size_t k = 0; k < r.size(); ++k) {
    const double rel = e[k] / r[k] - 1;
    out.rms += rel * rel / r.size();
    out.worst = std::max(out.worst, std::abs(rel));
  }
  out.rms = std::sqrt(out.rms);
  return out;
}

const Solution& reference() {
  static const Solution ref = solve(room(2300, SolverMethod::Dense));  // about 3 800 patches
  return ref;
}

class RefinementLadder : public ::testing::TestWithParam<SolverMethod> {};

TEST_P(RefinementLadder, TheSensorsErrorFallsRungByRungTowardAFinerDenseSolve) {
  const Solution& ref = reference();
  ASSERT_EQ(ref.probes[0].irradiance.size(), 96u);
  Error previous{1e300, 1e300};
  std::size_t previous_patches = 0;
  for (double rung : {150.0, 500.0, 1200.0}) {
    Scene scene = room(rung, GetParam());
    scene.output.error_estimate = true;
    const Solution sol = solve(scene);
    ASSERT_EQ(sol.stats.method, GetParam());
    ASSERT_GT(sol.patches.size(), previous_patches);
    ASSERT_LT(sol.patches.size(), ref.patches.size());
    const Error e = error_against(sol, ref);
    SCOPED_TRACE(std::to_string(sol.patches.size()) + " patches: rms " + std::to_string(e.rms) + ", worst " +
                 std::to_string(e.worst));
    EXPECT_LT(e.rms, previous.rms);
    EXPECT_LT(e.worst, previous.worst);
    // The solve's own estimate (the change from patches four times larger, error_estimate.h) bounds
    // the error it states.
    ASSERT_TRUE(sol.stats.error_estimate.has_value());
    EXPECT_GE(sol.stats.error_estimate->probe_irradiance_rms, e.rms);
    EXPECT_GE(sol.stats.error_estimate->probe_irradiance_max, e.worst);
    previous = e;
    previous_patches = sol.patches.size();
  }
  // The finest rung, about half the reference's patches: within 0.2 % rms and 1 % worst of it
  // (the reference's own error against a 12 900-patch dense solve is 0.04 % rms, docs/BENCHMARKS.md).
  EXPECT_LT(previous.rms, 2e-3);
  EXPECT_LT(previous.worst, 1e-2);
}

TEST(RefinementLadder, TighterAccuracyConvergesAtAFixedMesh) {
  // At a fixed mesh (no refinement by the direct light, so that every accuracy meshes alike) the
  // hierarchical answer must approach its own limit as solver.accuracy tightens: 1e-2, 1e-3, 1e-4
  // against 1e-5 (a Cauchy sequence; the two methods mesh differently, so the dense answer at the
  // same patch size is not this limit). Measured: sensors rms 9.0e-4, 9.6e-5, 9.7e-5; worst 1.3e-3,
  // 1.8e-4, 1.1e-4. Below 1e-3 the rms settles near 1e-4 of the limit, a floor that the worst sensor
  // does not share; it is far below the mesh's own error here (0.05 % rms against the dense solve on
  // twice the patches), and the bound below holds it.
  auto at_accuracy = [](double accuracy) {
    Scene scene = room(1200, SolverMethod::Hierarchical, accuracy);
    scene.meshing.refine_direct = false;
    return solve(scene);
  };
  const Solution limit = at_accuracy(1e-5);
  Error previous{1e300, 1e300};
  for (double accuracy : {1e-2, 1e-3, 1e-4}) {
    const Solution sol = at_accuracy(accuracy);
    ASSERT_EQ(sol.patches.size(), limit.patches.size());
    const Error e = error_against(sol, limit);
    SCOPED_TRACE("accuracy " + std::to_string(accuracy) + ": rms " + std::to_string(e.rms) + ", worst " +
                 std::to_string(e.worst));
    EXPECT_LT(e.rms, std::max(previous.rms, 2e-4));
    EXPECT_LT(e.worst, previous.worst);
    EXPECT_LT(e.worst, std::max(0.2 * accuracy, 2e-4));  // a fraction of solver.accuracy, down to the floor
    previous = e;
  }
}

TEST(ErrorEstimate, ADarkSceneStatesNoChange) {
  // Nothing emits: every irradiance is 0 at both levels, and the relative changes are 0, not 0/0.
  for (const SolverMethod method : {SolverMethod::Dense, SolverMethod::Hierarchical}) {
    Scene scene = room(150, method);
    for (Surface& s : scene.surfaces) s.emission.reset();
    scene.output.error_estimate = true;
    const Solution sol = solve(scene);
    ASSERT_TRUE(sol.stats.error_estimate.has_value());
    EXPECT_EQ(sol.stats.error_estimate->surface_irradiance_max, 0.0);
    EXPECT_EQ(sol.stats.error_estimate->probe_irradiance_rms, 0.0);
    EXPECT_EQ(sol.stats.error_estimate->probe_irradiance_max, 0.0);
    EXPECT_GT(sol.stats.error_estimate->coarse_patches, 0u);
    EXPECT_LT(sol.stats.error_estimate->coarse_patches, sol.patches.size());
  }
}

INSTANTIATE_TEST_SUITE_P(BothMethods, RefinementLadder,
                         ::testing::Values(SolverMethod::Dense, SolverMethod::Hierarchical),
                         [](const auto& info) { return std::string(method_name(info.param)); });

}  // namespace
}  // namespace lambert
