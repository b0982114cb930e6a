// Which pairs the solids' shafts clear without rays (solver/hierarchical/solid_shafts.h), checked
// against segments traced by hand: a cleared pair must have no segment between its elements (each
// end in front of the other's plane) that passes through another solid, and a pair that the bounding
// spheres' hull keeps apart from every other solid must be cleared.
#include "solver/hierarchical/solid_shafts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "solver/hierarchical/clusters.h"
#include "solver/hierarchical/elements.h"
#include "solver/radiosity.h"
#include "solver/solids.h"
#include "tests/scene_builder.h"

namespace lambert::hierarchical {
namespace {

// Whether the open segment from p to q passes through the open box (slab test).
bool segment_enters_box(const Point3& p, const Point3& q, const Point3& lo, const Point3& hi) {
  double t0 = 0, t1 = 1;
  for (int a = 0; a < 3; ++a) {
    const double d = q[a] - p[a];
    if (d == 0) {
      if (p[a] <= lo[a] || p[a] >= hi[a]) return false;
      continue;
    }
    double enter = (lo[a] - p[a]) / d, leave = (hi[a] - p[a]) / d;
    if (enter > leave) std::swap(enter, leave);
    t0 = std::max(t0, enter);
    t1 = std::min(t1, leave);
  }
  return t0 < t1;
}

// Whether the segment from p to q crosses the plane x = x0 inside the open rectangle (y, z) ∈ (lo, hi).
bool segment_crosses_square(const Point3& p, const Point3& q, double x0, const Point3& lo, const Point3& hi) {
  if ((p.x - x0) * (q.x - x0) >= 0) return false;
  const Point3 m = p + (q - p) * ((x0 - p.x) / (q.x - p.x));
  return m.y > lo.y && m.y < hi.y && m.z > lo.z && m.z < hi.z;
}

// A room (inward faces: loose triangles, not a solid; or none) with cubes A and B facing each other
// across x ∈ [2, 4], and a third object (or none): the small cube C between them, level with their
// upper parts, by default.
struct Scene3 {
  static constexpr Point3 kBlockerLo{2.9, 1.4, 1.75}, kBlockerHi{3.1, 1.6, 1.95};
  test::SceneBuilder b;
  ElementForest forest;
  ClusterTree tree;
  std::vector<Triangle> inputs;
  OutwardSolids solids;
  Scene3(bool blocker, bool room, const std::vector<Triangle>& third = test::box(kBlockerLo, kBlockerHi, false)) {
    const int grey = b.material("grey", 0.5);
    if (room) b.surface("room", grey, test::box({0, 0, 0}, {6, 3, 3}, true));
    b.surface("A", grey, test::box({1, 1, 1}, {2, 2, 2}, false));
    b.surface("B", grey, test::box({4, 1, 1}, {5, 2, 2}, false));
    if (blocker) b.surface("C", grey, third);
    b.max_patch_area(1.0 / 32);
    forest = build_forest(b.scene(), 1.0 / 32, {});
    tree = build_cluster_tree(forest);
    inputs = input_triangles(b.scene());
    solids = outward_solids(b.scene().surfaces);
  }
};

// The elements of A's face x = 2 and of B's face x = 4, at every level: every segment between them
// has both ends in front of both planes.
std::pair<std::vector<int>, std::vector<int>> facing_elements(const Scene3& s) {
  std::vector<int> on_a, on_b;
  for (int e = 0; e < static_cast<int>(s.forest.elements.size()); ++e) {
    const Element& E = s.forest.elements[e];
    if (std::abs(E.centre.x - 2) < 1e-12 && E.normal.x > 0.5) on_a.push_back(e);
    if (std::abs(E.centre.x - 4) < 1e-12 && E.normal.x < -0.5) on_b.push_back(e);
  }
  EXPECT_FALSE(on_a.empty());
  EXPECT_FALSE(on_b.empty());
  return {on_a, on_b};
}

// Segments between 21 points of each element (a barycentric grid of step 1/5, corners included):
// whether one of them meets `hit`.
template <class Hit>
bool any_segment(const Element& A, const Element& B, Hit&& hit) {
  for (int i = 0; i <= 5; ++i)
    for (int j = 0; i + j <= 5; ++j)
      for (int k = 0; k <= 5; ++k)
        for (int l = 0; k + l <= 5; ++l) {
          const Point3 p = barycentric(A.tri.v[0], A.tri.v[1], A.tri.v[2], 0, i / 5.0, j / 5.0);
          const Point3 q = barycentric(B.tri.v[0], B.tri.v[1], B.tri.v[2], 0, k / 5.0, l / 5.0);
          if (hit(p, q)) return true;
        }
  return false;
}

TEST(SolidShafts, ClearsOnlyPairsThatNoOtherSolidCanHide) {
  const Scene3 s(true, true);
  ASSERT_EQ(std::count(s.solids.convex.begin(), s.solids.convex.end(), 1), 3);  // A, B and C; the room is not one
  const SolidShafts shafts(s.forest, s.tree, s.inputs, s.solids.solid, s.solids.convex);
  const auto [on_a, on_b] = facing_elements(s);
  // C's bounding sphere, the blocker the hull of the pair's spheres is tested against.
  const Point3 c_centre{3.0, 1.5, 1.85};
  const double c_radius = 0.5 * length(Scene3::kBlockerHi - Scene3::kBlockerLo);
  int cleared = 0, must = 0, hidden_somewhere = 0;
  for (int a : on_a)
    for (int b : on_b) {
      const Element& A = s.forest.elements[a];
      const Element& B = s.forest.elements[b];
      const bool blocked = any_segment(A, B, [](const Point3& p, const Point3& q) {
        return segment_enters_box(p, q, Scene3::kBlockerLo, Scene3::kBlockerHi);
      });
      const bool clear = shafts.clear(a, b);
      hidden_somewhere += blocked;
      EXPECT_FALSE(clear && blocked) << "elements " << a << ", " << b << ": a segment between them meets C";
      cleared += clear;
      // The hull of the two spheres misses C's sphere by the distance from C's centre to the segment
      // between the pair's centres, less the larger radius (the hull lies in that capsule): cleared.
      const Vector3 axis = B.centre - A.centre;
      const double t = std::clamp(dot(c_centre - A.centre, axis) / length_squared(axis), 0.0, 1.0);
      if (distance(c_centre, A.centre + axis * t) > c_radius + std::max(A.radius, B.radius)) {
        ++must;
        EXPECT_TRUE(clear) << "elements " << a << ", " << b;
      }
    }
  EXPECT_GT(hidden_somewhere, 0);  // C does stand between some pairs
  EXPECT_GT(must, 0);
  EXPECT_GE(cleared, must);
}

TEST(SolidShafts, ACubesClusterSeesAnotherWhollyUnlessASolidStandsBetween) {
  // The clusters that are A and B (their twelve roots each, all on one convex solid): their own faces
  // cannot hide each other, so with nothing between them they are clear; with C between, not. (No
  // room: its walls' roots would share clusters with the cubes'.)
  for (const bool blocker : {false, true}) {
    const Scene3 s(blocker, false);
    const SolidShafts shafts(s.forest, s.tree, s.inputs, s.solids.solid, s.solids.convex);
    auto cube = [&](double x0) {
      for (int c = 0; c < static_cast<int>(s.tree.clusters.size()); ++c) {
        const Cluster& C = s.tree.clusters[c];
        if (std::abs(C.box.lo.x - x0) < 1e-12 && std::abs(C.box.hi.x - (x0 + 1)) < 1e-12 &&
            std::abs(C.box.lo.z - 1) < 1e-12 && std::abs(C.box.hi.z - 2) < 1e-12 && C.root_count >= 12)
          return c;
      }
      return -1;
    };
    const int a = cube(1), b = cube(4);
    ASSERT_GE(a, 0);
    ASSERT_GE(b, 0);
    EXPECT_EQ(shafts.clear_cluster(a, b, true), !blocker) << (blocker ? "with C" : "without C");
  }
}

TEST(SolidShafts, ALooseSquareBetweenHidesWhatCrossesIt) {
  // C is a square sheet facing +x at x = 3 (two triangles of no solid): its plane has the pair on both
  // sides, so a pair whose hull meets the sheet's sphere is not cleared; none cleared may have a
  // segment through the square.
  const Point3 lo{3, 1.4, 1.75}, hi{3, 1.6, 1.95};
  const std::vector<Triangle> sheet = {Triangle{{lo, Point3{3, hi.y, lo.z}, hi}}, Triangle{{lo, hi, Point3{3, lo.y, hi.z}}}};
  const Scene3 s(true, true, sheet);
  const SolidShafts shafts(s.forest, s.tree, s.inputs, s.solids.solid, s.solids.convex);
  const auto [on_a, on_b] = facing_elements(s);
  int cleared = 0, crossed = 0;
  for (int a : on_a)
    for (int b : on_b) {
      const bool cross = any_segment(s.forest.elements[a], s.forest.elements[b], [&](const Point3& p, const Point3& q) {
        return segment_crosses_square(p, q, 3, lo, hi);
      });
      const bool clear = shafts.clear(a, b);
      EXPECT_FALSE(clear && cross) << "elements " << a << ", " << b;
      cleared += clear;
      crossed += cross;
    }
  EXPECT_GT(crossed, 0);
  EXPECT_GT(cleared, 0);
}

TEST(SolidShafts, ASolidBesideThePairIsSetApartByItsFacePlane) {
  // C beside the corridor between A and B (y ∈ [2.02, 2.42], the faces' y ≤ 2): its bounding sphere
  // reaches into the hulls of the pairs along the corridor's edge, but every pair lies in front of its
  // face y = 2.02, behind which it lies whole. So every pair is cleared.
  const Point3 lo{2.8, 2.02, 1.3}, hi{3.2, 2.42, 1.7};
  const Scene3 s(true, true, test::box(lo, hi, false));
  const SolidShafts shafts(s.forest, s.tree, s.inputs, s.solids.solid, s.solids.convex);
  const auto [on_a, on_b] = facing_elements(s);
  const Point3 centre{3.0, 2.22, 1.5};
  const double radius = 0.5 * length(hi - lo);
  int near = 0;
  for (int a : on_a)
    for (int b : on_b) {
      const Element& A = s.forest.elements[a];
      const Element& B = s.forest.elements[b];
      EXPECT_TRUE(shafts.clear(a, b)) << "elements " << a << ", " << b;
      // The segment between the centres lies in the hull: within C's radius of its centre, the hull
      // meets C's sphere.
      const Vector3 axis = B.centre - A.centre;
      const double t = std::clamp(dot(centre - A.centre, axis) / length_squared(axis), 0.0, 1.0);
      near += distance(centre, A.centre + axis * t) < radius;
    }
  EXPECT_GT(near, 0);
}

// BallHull::outside against its definition, min over t ∈ [0, 1] of |x − c(t)| − r(t), found here by
// golden-section search (the function is convex in t) after a scan of 2 001 values of t, which
// guards the search; and against the hull's meaning: a point between a point of each ball lies
// inside. Cases: the balls apart, one inside the other (|k| ≥ 1, the ends only), concentric, points
// on the axis, inside and far away.
TEST(BallHull, OutsideIsTheLeastDistanceToTheInterpolatedBalls) {
  std::mt19937 rng(20261206);
  std::uniform_real_distribution<double> u(-1, 1), unit(0, 1);
  auto point = [&](double scale) { return Point3{scale * u(rng), scale * u(rng), scale * u(rng)}; };
  auto least = [](const Point3& ca, double ra, const Point3& cb, double rb, const Point3& x) {
    auto f = [&](double t) { return distance(x, ca + (cb - ca) * t) - ((1 - t) * ra + t * rb); };
    int best = 0;
    for (int i = 1; i <= 2000; ++i) best = f(i / 2000.0) < f(best / 2000.0) ? i : best;
    double lo = std::max(0.0, (best - 1) / 2000.0), hi = std::min(1.0, (best + 1) / 2000.0);
    const double g = (std::sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 100; ++it) {
      const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
      (f(m1) < f(m2) ? hi : lo) = f(m1) < f(m2) ? m2 : m1;
    }
    return std::min({f(lo), f(hi), f(0), f(1)});
  };
  int nested = 0, apart = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = trial % 3 == 0 ? 1e-3 : trial % 3 == 1 ? 1.0 : 1e3;
    const Point3 ca = point(scale);
    const Point3 cb = trial % 50 == 0 ? ca : point(scale);
    const double ra = scale * unit(rng), rb = scale * (trial % 7 == 0 ? 2 : 0.5) * unit(rng);
    const double L = distance(ca, cb);
    (std::abs(rb - ra) >= L ? nested : apart) += 1;
    const BallHull hull(ca, ra, cb, rb);
    for (int k = 0; k < 8; ++k) {
      const Point3 x = k == 0 ? ca + (cb - ca) * (2 * unit(rng) - 0.5) : point(scale * (k < 4 ? 1 : 10));
      // Tolerance: 1e-11 of the scale, a few roundings of distances up to 10 × the scale (the search
      // ends on an interval of t below 1e-23, so its own error is far smaller).
      EXPECT_NEAR(hull.outside(x), least(ca, ra, cb, rb, x), 1e-11 * scale) << "trial " << trial << " k " << k;
    }
    // Points between a point of each ball are in the hull (outside ≤ 0, to rounding).
    for (int k = 0; k < 8; ++k) {
      Vector3 da = point(1) - Point3{}, db = point(1) - Point3{};
      da = da * (unit(rng) / std::max(1.0, length(da))) * ra;
      db = db * (unit(rng) / std::max(1.0, length(db))) * rb;
      const double s = unit(rng);
      const Point3 x = (ca + da) + ((cb + db) - (ca + da)) * s;
      EXPECT_LE(hull.outside(x), 1e-11 * scale) << "trial " << trial;
    }
  }
  EXPECT_GT(nested, 100);  // both branches of outside() were exercised
  EXPECT_GT(apart, 100);
}

}  // namespace
}  // namespace lambert::hierarchical
