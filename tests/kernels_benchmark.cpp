// Google Benchmark for the inner kernels: point-to-triangle factor, patch-pair cubature (far, near,
// touching), exact visible factor past a box and its shadow cut to patches, Embree visibility (single and stream), and
// one row of link rays with their set-up. Not a test: speed figures belong here and in
// docs/BENCHMARKS.md, never in timed unit tests.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "solver/cubature.h"
#include "solver/exact_visibility.h"
#include "solver/form_factor.h"
#include "solver/patch_refinement.h"
#include "solver/radiosity.h"
#include "solver/solids.h"
#include "solver/visibility.h"
#include "tests/scene_builder.h"

namespace lambert {
namespace {

const Triangle kReceiver{{Point3{0, 0, 0}, Point3{0.05, 0, 0}, Point3{0, 0.05, 0}}};

void BM_PointTriangleFactor(benchmark::State& state) {
  const Triangle source{{Point3{0, 0, 1}, Point3{0, 0.1, 1}, Point3{0.1, 0, 1}}};
  Point3 p{0.01, 0.02, 0};
  for (auto _ : state) {
    benchmark::DoNotOptimize(point_triangle_factor(p, {0, 0, 1}, source));
    p.x += 1e-9;
  }
}
BENCHMARK(BM_PointTriangleFactor);

// The degree-5 rule's 7 points of a receiver, one call each against one batched call.
std::vector<Point3> receiver_points() {
  const TriangleRule rule = triangle_rule_degree5();
  std::vector<Point3> points;
  for (int q = 0; q < rule.size; ++q) {
    const auto& w = rule.nodes[q];
    points.push_back(barycentric(kReceiver.v[0], kReceiver.v[1], kReceiver.v[2], w[0], w[1], w[2]));
  }
  return points;
}

// A source seen under small angles from the receiver (a 0.1 m triangle 1 m away: every edge takes the
// series), and one seen under wide angles (a 1 m triangle 0.5 m away: the angle's reduction).
const Triangle kSmallSource{{Point3{0, 0, 1}, Point3{0, 0.1, 1}, Point3{0.1, 0, 1}}};
const Triangle kWideSource{{Point3{-0.5, -0.5, 0.5}, Point3{0, 0.6, 0.5}, Point3{0.5, -0.5, 0.5}}};

void PointTriangleFactor7(benchmark::State& state, const Triangle& source) {
  const std::vector<Point3> points = receiver_points();
  for (auto _ : state) {
    double sum = 0;
    for (const Point3& p : points) sum += point_triangle_factor(p, {0, 0, 1}, source);
    benchmark::DoNotOptimize(sum);
  }
}
void PointTriangleFactorsBatch7(benchmark::State& state, const Triangle& source) {
  const std::vector<Point3> points = receiver_points();
  std::vector<double> out(points.size());
  for (auto _ : state) {
    point_triangle_factors(points, {0, 0, 1}, source, out);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK_CAPTURE(PointTriangleFactor7, small_angles, kSmallSource);
BENCHMARK_CAPTURE(PointTriangleFactorsBatch7, small_angles, kSmallSource);
BENCHMARK_CAPTURE(PointTriangleFactor7, wide_angles, kWideSource);
BENCHMARK_CAPTURE(PointTriangleFactorsBatch7, wide_angles, kWideSource);

void BM_AreaFormFactor(benchmark::State& state) {
  // state.range(0): distance between the patches in units of 1 mm (patch size 50 mm).
  const double h = state.range(0) * 1e-3;
  const Triangle source{{Point3{0, 0, h}, Point3{0, 0.05, h}, Point3{0.05, 0, h}}};
  for (auto _ : state) benchmark::DoNotOptimize(area_form_factor(kReceiver, source));
}
BENCHMARK(BM_AreaFormFactor)->Arg(1000)->Arg(200)->Arg(50)->Arg(5);

void BM_AreaFormFactorTouching(benchmark::State& state) {
  const Triangle wall{{Point3{0, 0, 0}, Point3{0, 0, 0.05}, Point3{0.05, 0, 0}}};
  for (auto _ : state) benchmark::DoNotOptimize(area_form_factor(kReceiver, wall));
}
BENCHMARK(BM_AreaFormFactorTouching);

// The visible factor of a 1 m floor triangle from 64 points on a 3 m ceiling, past a floating 1 m box
// (the cube room of docs/BENCHMARKS.md): every point sees the source partly hidden. `convex`: the
// box is known convex (its front faces' factors summed), else their shadows are united
// (inclusion–exclusion).
void ExactVisibleFactor(benchmark::State& state, bool convex) {
  const std::vector<Triangle> cube = test::box({1, 1, 1}, {2, 2, 2}, false);
  const std::vector<int> solid(cube.size(), 0);
  const std::vector<char> is_convex(1, convex ? 1 : 0);
  const ExactVisibility exact(cube, solid, is_convex);
  const Triangle source{{Point3{1.2, 1.1, 0}, Point3{2.3, 1.4, 0}, Point3{1.5, 2.2, 0}}};
  std::vector<Point3> points;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) points.push_back({1.1 + 0.12 * i, 1.1 + 0.12 * j, 3});
  for (auto _ : state) {
    double sum = 0;
    for (const Point3& p : points) sum += exact.visible_factor(p, {0, 0, -1}, source);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * points.size());
}
BENCHMARK_CAPTURE(ExactVisibleFactor, convex_sum, true);
BENCHMARK_CAPTURE(ExactVisibleFactor, shadows_united, false);

// One receiving point's shadow of the same box on a 6 × 4 m floor triangle (ExactVisibility::Shadow),
// and the factor it hides of each 0.2 m patch of the floor's 4 × 3 m below the box: the final
// gather's inner loop with solver.exact_visibility (patches in the shadow, outside it and across its
// edge; `across_only`: those across the edge alone).
void ShadowHiddenFactor(benchmark::State& state, bool across_only) {
  const std::vector<Triangle> cube = test::box({1, 1, 1}, {2, 2, 2}, false);
  const std::vector<int> solid(cube.size(), 0);
  const std::vector<char> is_convex(1, 1);
  const ExactVisibility exact(cube, solid, is_convex);
  const Triangle floor{{Point3{0, 0, 0}, Point3{6, 0, 0}, Point3{0, 4, 0}}};
  std::vector<int> candidates(cube.size());
  std::iota(candidates.begin(), candidates.end(), 0);
  ExactVisibility::Shadow shadow;
  exact.shadow({0.4, 0.5, 2.9}, {0, 0, -1}, floor, candidates, shadow);
  std::vector<Triangle> patches;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 15; ++j) {
      const double x = 0.2 * i, y = 0.2 * j;
      patches.push_back({{Point3{x, y, 0}, Point3{x + 0.2, y, 0}, Point3{x, y + 0.2, 0}}});
      patches.push_back({{Point3{x + 0.2, y, 0}, Point3{x + 0.2, y + 0.2, 0}, Point3{x, y + 0.2, 0}}});
    }
  int kinds[3] = {};  // all hidden, none, part
  for (const Triangle& t : patches) {
    const double hidden = shadow.hidden_factor(t);
    ++kinds[std::isinf(hidden) ? 0 : hidden == 0 ? 1 : 2];
  }
  state.counters["hidden"] = kinds[0], state.counters["clear"] = kinds[1], state.counters["part"] = kinds[2];
  if (across_only)  // the patches across the shadow's edge alone: the clip and its contour sum
    std::erase_if(patches, [&](const Triangle& t) {
      const double hidden = shadow.hidden_factor(t);
      return std::isinf(hidden) || hidden == 0;
    });
  for (auto _ : state) {
    double sum = 0;
    for (const Triangle& t : patches) {
      const double hidden = shadow.hidden_factor(t);
      sum += std::isinf(hidden) ? 1 : hidden;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * patches.size());
}
BENCHMARK_CAPTURE(ShadowHiddenFactor, every_patch, false);
BENCHMARK_CAPTURE(ShadowHiddenFactor, across_the_edge, true);

std::vector<Triangle> room() { return test::box({0, 0, 0}, {4, 3, 2.5}, true); }

// 4096 random segments inside the room (fixed seed: the same rays in every run).
std::vector<Segment> random_segments() {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.1, 2.4);
  std::vector<Segment> segments(4096);
  for (auto& s : segments) s = {{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
  return segments;
}

void BM_VisibilitySingle(benchmark::State& state) {
  const auto tris = room();
  const Visibility vis(tris);
  const std::vector<Segment> segments = random_segments();
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& s = segments[k++ % segments.size()];
    benchmark::DoNotOptimize(vis.visible(s.from, s.to));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_VisibilitySingle);

void BM_VisibilityStream(benchmark::State& state) {
  const auto tris = room();
  const Visibility vis(tris);
  const std::vector<Segment> segments = random_segments();
  std::vector<std::uint8_t> out(segments.size());
  for (auto _ : state) vis.visible(segments, out);
  state.SetItemsProcessed(state.iterations() * segments.size());
}
BENCHMARK(BM_VisibilityStream);

// One row of the dense solve's link rays (patch_visible_fractions): a floor patch of the room above
// against the 600 patches of its ceiling, past a 1 m box standing on the floor, so that links take
// 4, 16 or 64 rays. Items: rays traced (Embree's share and the rays' set-up and tally together).
void PatchVisibleFractions(benchmark::State& state) {
  std::vector<Patch> patches;
  auto grid = [&](double z, bool up) {
    constexpr int nx = 20, ny = 15;
    const double dx = 4.0 / nx, dy = 3.0 / ny;
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j) {
        const Point3 a{i * dx, j * dy, z}, b{(i + 1) * dx, j * dy, z}, c{(i + 1) * dx, (j + 1) * dy, z},
            d{i * dx, (j + 1) * dy, z};
        for (Triangle t : {Triangle{{a, b, c}}, Triangle{{a, c, d}}}) {
          if (!up) std::swap(t.v[1], t.v[2]);
          patches.push_back({0, t, t.area(), t.normal(), -1});
        }
      }
  };
  grid(0, true);
  const std::size_t ceiling = patches.size();
  grid(2.5, false);
  std::vector<Triangle> occluders = room();
  for (const Triangle& t : test::box({1.5, 1, 0}, {2.5, 2, 1}, false)) occluders.push_back(t);
  const Visibility vis(occluders);
  const std::vector<Point3> samples = lifted_visibility_samples(patches, vis);
  std::vector<std::size_t> partners(patches.size() - ceiling);
  std::iota(partners.begin(), partners.end(), ceiling);
  std::vector<double> fractions(partners.size());
  const std::size_t a = 7 * 30 + 11;  // a floor patch (x 1.4-1.6 m, y 1-1.2 m) reaching under the box
  std::size_t rays = 0;
  for (auto _ : state) rays += patch_visible_fractions(a, partners, patches, samples, vis, fractions);
  state.SetItemsProcessed(static_cast<std::int64_t>(rays));
}
BENCHMARK(PatchVisibleFractions);

}  // namespace
}  // namespace lambert

BENCHMARK_MAIN();
