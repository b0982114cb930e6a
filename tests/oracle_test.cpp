// The refinement oracle's view of the radiosity (solver/hierarchical/oracle.h) on fields whose element
// means are known in closed form: a field linear over a square, whose element means are its values at
// the elements' centroids, and a uniform field with one leaf dark. And the bound on an element
// source's vector estimate, against the exact point factor.
#include "solver/hierarchical/oracle.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "solver/hierarchical/clusters.h"
#include "solver/hierarchical/elements.h"
#include "solver/form_factor.h"
#include "tests/scene_builder.h"

namespace lambert::hierarchical {
namespace {

// A 2 m square of two roots, split down to 1/64 of each root (three levels below it).
Hierarchy square_hierarchy() {
  test::SceneBuilder b;
  b.surface("square", b.material("grey", 0.5), test::rectangle({0, 0, 0}, {2, 0, 0}, {0, 2, 0}));
  Hierarchy h;
  static_cast<ElementForest&>(h) = build_forest(b.scene(), 2.0 / 64, {});
  static_cast<ClusterTree&>(h) = build_cluster_tree(h);
  return h;
}

int depth(const Hierarchy& h, int e) {
  int d = 0;
  for (; h.elements[e].parent >= 0; e = h.elements[e].parent) ++d;
  return d;
}

TEST(Oracle, ALinearFieldDepartsFromNothing) {
  const Hierarchy h = square_hierarchy();
  ASSERT_EQ(h.leaves.size(), 128u);
  // B = 1 + 0.3 x − 0.2 y: a leaf's mean is B at its centroid, and so is every element's (the area
  // mean of a linear field), so the centre child's mean is the corner children's mean at every level.
  std::vector<double> leaf_B;
  for (int e : h.leaves) leaf_B.push_back(1 + 0.3 * h.elements[e].centre.x - 0.2 * h.elements[e].centre.y);
  const OracleValues v = oracle_values(h, leaf_B);
  for (std::size_t e = 0; e < h.elements.size(); ++e) {
    const Point3& c = h.elements[e].centre;
    EXPECT_NEAR(v.element_B[e], 1 + 0.3 * c.x - 0.2 * c.y, 1e-12);
    EXPECT_NEAR(v.element_departure[e], 0, 1e-12) << e;
  }
}

TEST(Oracle, ADarkLeafDepartsAtEveryAncestor) {
  const Hierarchy h = square_hierarchy();
  // Uniform B = 1 but for one leaf at 0; the elements off that leaf's path to its root depart from
  // nothing. A dark centre child (slot 3) gives its parent a centre mean of 0 against corners of 1, a
  // departure of 1; a dark corner child (slot 0), a centre of 1 against corners of (0 + 1 + 1) / 3, a
  // departure of 1/3. Further up, the parent's mean is 3/4 against 1 around it, which departs by at
  // most 1/4 (as a centre child) or 1/12 (as a corner), less than either; each ancestor takes the
  // largest departure below it.
  for (int dark_slot : {0, 3}) {
    int dark = -1;
    for (std::size_t i = 0; i < h.leaves.size() && dark < 0; ++i) {
      const int e = h.leaves[i];
      const int p = h.elements[e].parent;
      if (h.elements[p].first_child + dark_slot == e) dark = static_cast<int>(i);
    }
    ASSERT_GE(dark, 0);
    std::vector<double> leaf_B(h.leaves.size(), 1.0);
    leaf_B[dark] = 0;
    const OracleValues v = oracle_values(h, leaf_B);
    std::vector<char> on_path(h.elements.size(), 0);
    for (int e = h.leaves[dark]; e >= 0; e = h.elements[e].parent) on_path[e] = 1;
    const double expected = dark_slot == 3 ? 1.0 : 1.0 / 3;
    for (std::size_t e = 0; e < h.elements.size(); ++e) {
      if (!h.has_children(static_cast<int>(e))) {
        EXPECT_EQ(v.element_departure[e], 0);
        continue;
      }
      EXPECT_NEAR(v.element_departure[e], on_path[e] ? expected : 0.0, 1e-12)
          << "slot " << dark_slot << ", element " << e << " at depth " << depth(h, static_cast<int>(e));
    }
  }
}

TEST(VectorEstimate, BoundsTheFactorAnywhereInTheReceiversBallOnEveryNormalThatSeesTheWholeSource) {
  // vector_estimate_error's claim, checked with the exact point factor: a source triangle, receivers
  // within r of a centre c at distance d ≥ 2.5 (r + r_S), the source facing every receiver
  // (n_S · w ≥ sin δ) and every normal within π/2 − δ of the direction back to the source; then the
  // source lies wholly in front of every receiver's horizon, and its factor n · V(x) differs from the
  // estimate n · V(c) by at most A/π (1/d_min² − 1/(d − r_S)²). The worst ratio found shows the bound
  // is not loose by orders of magnitude.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), unit(0, 1);
  int checked = 0;
  double worst_ratio = 0;
  while (checked < 20000) {
    const Triangle t{{Point3{u(rng), u(rng), u(rng)}, Point3{u(rng), u(rng), u(rng)}, Point3{u(rng), u(rng), u(rng)}}};
    const Vector3 w = normalize(Vector3{u(rng), u(rng), u(rng)});
    const double r_S = t.bounding_radius(), r = 0.05 + 2 * unit(rng);
    const double d = (2.5 + 10 * unit(rng) * unit(rng)) * (r + r_S);
    const double sin_delta = (r + r_S) / d;
    if (dot(t.normal(), w) < sin_delta) continue;
    const Point3 c = t.centroid() + d * w;
    const Vector3 V = triangle_vector_factor(c, t);
    const double bound = vector_estimate_error(t.area(), r, d - r_S);
    for (int k = 0; k < 8; ++k) {
      Vector3 offset{u(rng), u(rng), u(rng)};
      if (length(offset) > 1) continue;
      const Point3 x = c + r * offset;
      // A normal within π/2 − δ of −w: −w turned by up to that angle towards a random direction.
      const Vector3 side = normalize(cross(w, Vector3{u(rng), u(rng), u(rng)}));
      const double turn = (kPi / 2 - std::asin(sin_delta)) * unit(rng);
      const Vector3 n = -std::cos(turn) * w + std::sin(turn) * side;
      for (const Point3& v : t.v) ASSERT_GT(dot(v - x, n), 0) << "the source crosses a receiver's horizon";
      const double error = std::abs(point_triangle_factor(x, n, t) - dot(n, V));
      EXPECT_LE(error, bound * (1 + 1e-9)) << checked;
      worst_ratio = std::max(worst_ratio, error / bound);
      ++checked;
    }
  }
  EXPECT_GT(worst_ratio, 0.4);
}

TEST(VectorEstimate, WhereAHorizonCutsTheSourceTheCutPartJoinsTheBound) {
  // The receivers' normals now turn up to π/2 − δ + ε from the direction back to the source, so a
  // receiver's horizon may cut it: the exact point factor (clipped at the horizon) differs from n · V(c)
  // by at most vector_estimate_error plus horizon_cut_error(sin(turn + δ − π/2), A, d_min), the part
  // behind the horizon counted at |n · u| ≤ sin of the excess. Some cases must cut (else this would
  // test nothing new), and the worst must come near the bound.
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1, 1), unit(0, 1);
  int checked = 0, cut = 0;
  double worst_ratio = 0;
  while (checked < 20000) {
    const Triangle t{{Point3{u(rng), u(rng), u(rng)}, Point3{u(rng), u(rng), u(rng)}, Point3{u(rng), u(rng), u(rng)}}};
    const Vector3 w = normalize(Vector3{u(rng), u(rng), u(rng)});
    const double r_S = t.bounding_radius(), r = 0.05 + 2 * unit(rng);
    const double d = (2.5 + 10 * unit(rng) * unit(rng)) * (r + r_S), d_min = d - r - r_S;
    const double sin_delta = (r + r_S) / d, delta = std::asin(sin_delta);
    if (dot(t.normal(), w) < sin_delta) continue;
    const Point3 c = t.centroid() + d * w;
    const Vector3 V = triangle_vector_factor(c, t);
    const Vector3 offset{u(rng), u(rng), u(rng)};
    if (length(offset) > 1) continue;
    const Point3 x = c + r * offset;
    const Vector3 side = normalize(cross(w, Vector3{u(rng), u(rng), u(rng)}));
    const double turn = (kPi / 2 - delta) + 2 * delta * unit(rng);  // α: up to δ past π/2 − δ
    const Vector3 n = -std::cos(turn) * w + std::sin(turn) * side;
    const double excess = turn + delta - kPi / 2;
    const double bound = vector_estimate_error(t.area(), r, d - r_S) +
                         (excess > 0 ? horizon_cut_error(std::sin(excess), t.area(), d_min) : 0);
    bool crosses = false;
    for (const Point3& v : t.v) crosses = crosses || dot(v - x, n) < 0;
    cut += crosses;
    const double error = std::abs(point_triangle_factor(x, n, t) - dot(n, V));
    EXPECT_LE(error, bound * (1 + 1e-9)) << checked;
    worst_ratio = std::max(worst_ratio, error / bound);
    ++checked;
  }
  EXPECT_GT(cut, 1000);
  EXPECT_GT(worst_ratio, 0.15);
}

}  // namespace
}  // namespace lambert::hierarchical
