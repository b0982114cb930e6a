// The cluster tree of the hierarchical method (solver/hierarchical/clusters.h): where it splits a
// scene of separate objects, known by construction (which root belongs to which object); and what a
// link reads of a cluster's bins, against the sum over its triangles Σ_j B_j A_j (n_j · w)⁺.
#include "solver/hierarchical/clusters.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "solver/hierarchical/elements.h"
#include "solver/hierarchical/hierarchy.h"
#include "tests/scene_builder.h"

namespace lambert::hierarchical {
namespace {

// Three unit cubes in a row, 1 m apart (boxes [0, 1], [2, 3] and [4, 5] along x), each of N roots.
// The median of the 3N centroids lies in the middle cube, so a median split leaves no cluster that is
// that cube. Every normal is axis-aligned, so the tree splits by area (Σ half-area of a child's box ×
// its roots): 3 N + 7 × 2N = 17 N m² cut at a gap, against 7 × 1.5 N × 2 = 21 N through the middle
// cube (each side's box then reaches across that whole cube), and each cube ends as one cluster.
TEST(ClusterTree, EachOfThreeSeparateBoxesIsACluster) {
  test::SceneBuilder b;
  const int grey = b.material("grey", 0.5);
  const std::vector<double> origins = {0, 2, 4};
  for (double x : origins) b.surface("cube", grey, test::box({x, 0, 0}, {x + 1, 1, 1}, false));
  const ElementForest forest = build_forest(b.scene(), 1.0, {});
  const ClusterTree tree = build_cluster_tree(forest);
  const int roots = static_cast<int>(tree.ordered_roots.size());
  ASSERT_EQ(roots % 3, 0);
  ASSERT_GE(roots, 6);
  auto cube_of = [&](int root) {
    const double x = tree.ordered_roots[root].tri.centroid().x;
    return x < 1.5 ? 0 : x < 3.5 ? 1 : 2;
  };
  std::vector<bool> found(origins.size(), false);
  for (const Cluster& c : tree.clusters) {
    if (c.root_count != roots / 3) continue;
    const int k0 = cube_of(c.first_root);
    bool whole = true;
    for (int k = c.first_root; k < c.first_root + c.root_count; ++k) whole = whole && cube_of(k) == k0;
    if (whole) found[k0] = true;
  }
  for (std::size_t k = 0; k < origins.size(); ++k) EXPECT_TRUE(found[k]) << "cube " << k;
}

// A square pyramid's four faces (normals 45° from +z, one on each side) with radiosities 1, 2, 3 and
// 8, as a lit object's sides differ. Read from a direction w within 45° of the axis, every face
// faces w, and the link reads the area vector weighted by radiosity: exactly Σ_j B_j A_j (n_j · w)⁺
// for any radiosity. Farther off the axis the facing bins, weighted for a uniform radiosity, are
// exact for a uniform one.
TEST(ClusterView, ReadsAnyRadiosityExactlyWhereEveryNormalFacesTheReceiver) {
  test::SceneBuilder b;
  const Point3 apex{0, 0, 1};
  const Point3 base[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  std::vector<Triangle> faces;
  for (int k = 0; k < 4; ++k) faces.push_back(Triangle{base[k], base[(k + 1) % 4], apex});
  b.surface("pyramid", b.material("grey", 0.5), faces);
  Hierarchy h;
  static_cast<ElementForest&>(h) = build_forest(b.scene(), 10.0, {});
  static_cast<ClusterTree&>(h) = build_cluster_tree(h);
  ASSERT_EQ(h.leaves.size(), 4u);
  const std::vector<double> radiosity = {1, 2, 3, 8};
  auto exact = [&](const std::vector<double>& B, const Vector3& w) {
    double sum = 0;
    for (std::size_t i = 0; i < h.leaves.size(); ++i) {
      const Element& e = h.elements[h.leaves[i]];
      sum += B[i] * e.area * std::max(0.0, dot(e.normal, w));
    }
    return sum;
  };
  auto read = [&](const std::vector<double>& B, const Vector3& w) {
    Hierarchy::Values values;
    h.pull({B.data()}, values);
    const ClusterView view = cluster_view(h, 0, w, 0.1);
    double sum = 0;
    for (int a = 0; a < 3; ++a) sum += view.weight[a] * bin_value(&values.Phi[0], view.bin[a], 1, 0);
    return std::pair{sum, view};
  };
  const std::vector<double> uniform(4, 2.0);
  for (const double tilt : {0.0, 20.0, 40.0, 44.0, 50.0, 70.0}) {
    for (const double turn : {0.0, 30.0, 45.0, 100.0}) {
      const double t = tilt * kPi / 180, p = turn * kPi / 180;
      const Vector3 w{std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
      const auto [lit, view] = read(radiosity, w);
      // The faces' normal cone: about +z, 45° wide. Within it every face faces w; beyond it the
      // view falls back to the bins, even where (as at tilt 50°, turn 45°) every face still would.
      const bool vector = view.bin[0] >= kAxisBin;
      EXPECT_EQ(vector, tilt < 45) << tilt << " " << turn;
      if (vector) {
        EXPECT_GT(w.z, std::max(std::abs(w.x), std::abs(w.y)));  // n_j · w > 0 for n_j ∝ (±1, 0, 1), (0, ±1, 1)
        EXPECT_NEAR(lit, exact(radiosity, w), 1e-12 * exact(radiosity, w)) << tilt << " " << turn;
      }
      EXPECT_NEAR(read(uniform, w).first, exact(uniform, w), 1e-9 * exact(uniform, w)) << tilt << " " << turn;
    }
  }
}

}  // namespace
}  // namespace lambert::hierarchical
