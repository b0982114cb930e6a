// The hierarchical method's final gather at the leaves (solver/hierarchical/final_gather.h) where a
// link's rays found its pair partly hidden: each leaf below takes its own share of the source by its
// own rays. The second method: the exact visible part of the point-to-polygon factor
// (ExactVisibility::visible_factor, the polygon formula less the occluders' shadows), integrated
// over each patch (test::patch_mean_by_parts).
#include "solver/radiosity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "solver/exact_visibility.h"
#include "tests/hierarchical_helpers.h"
#include "tests/scene_builder.h"

namespace lambert {
namespace {

using test::box;
using test::rectangle;
using test::SceneBuilder;
using test::solve_with;

TEST(LeafGather, LinksFoundPartlyHiddenAreSharedByTheLeavesOwnRays) {
  // A black 6 × 4 × 3 m room whose wall x = 0 emits M = 1; a black beam along the room, from x = 1 to
  // x = 5, leaves a corridor 0.4 m wide beside the wall y = 4 and gaps above and below it. A patch of
  // the wall x = 6 in the corner y = 4 sees much of the emitter down the corridor, one 0.5 m further
  // from the corner little of it: the elements above them gather the emitting wall with one visible
  // fraction each. Nothing reflects, so E = M F, F the exact visible factor to the emitter. With those
  // fractions shared by the leaves below, the wall's patches err by 1.6 % of the mean E (rms) and
  // 10.4 % (worst); with each leaf's own rays by 0.75 % and 3.2 %, what remains being the leaves' own
  // links, whose 16 to 64 rays estimate their visible part.
  SceneBuilder b;
  const int black = b.material("black", 0.0);
  std::vector<Triangle> room = box({0, 0, 0}, {6, 4, 3}, true);
  std::vector<Triangle> emitter;
  for (auto it = room.begin(); it != room.end();) {  // the wall x = 0 on its own
    if (std::max({it->v[0].x, it->v[1].x, it->v[2].x}) == 0) {
      emitter.push_back(*it);
      it = room.erase(it);
    } else {
      ++it;
    }
  }
  ASSERT_EQ(emitter.size(), 2u);
  const std::vector<Triangle> beam = box({1, 0, 0.6}, {5, 3.6, 2.4}, false);
  b.surface("room", black, room);
  b.surface("emitting wall", black, emitter, 1.0);
  b.surface("beam", black, beam);
  b.max_patch_area(0.03);
  const Solution sol = solve_with(b.scene(), SolverMethod::Hierarchical);
  std::vector<Triangle> occluders = room;
  occluders.insert(occluders.end(), beam.begin(), beam.end());
  const ExactVisibility exact(occluders);
  double sum2 = 0, worst = 0, mean = 0;
  int n = 0;
  for (std::size_t i = 0; i < sol.patches.size(); ++i) {
    const Patch& p = sol.patches[i];
    if (p.surface != 0 || p.triangle.centroid().x < 6 - 1e-9) continue;  // the wall x = 6
    const double expected = test::patch_mean_by_parts(p, [&](const Point3& x) {  // E = M F
      double F = 0;
      for (const Triangle& s : emitter) F += exact.visible_factor(x, p.normal, s);
      return F;
    });
    const double e = sol.irradiance[i] - expected;
    sum2 += e * e, worst = std::max(worst, std::abs(e)), mean += expected, ++n;
  }
  ASSERT_GT(n, 300);
  mean /= n;
  const double rms = std::sqrt(sum2 / n);
  std::printf("wall x = 6, %d patches: mean E %.4g, error rms %.3g, worst %.3g of the mean\n", n, mean, rms / mean,
              worst / mean);
  EXPECT_LT(rms / mean, 0.01);
  EXPECT_LT(worst / mean, 0.05);
}

}  // namespace
}  // namespace lambert
