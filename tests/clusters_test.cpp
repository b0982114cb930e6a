// The cluster tree of the hierarchical method (solver/hierarchical/clusters.h): where it splits a
// scene of separate objects. The answer is known by construction: which root belongs to which object.
#include "solver/hierarchical/clusters.h"

#include <gtest/gtest.h>

#include <vector>

#include "solver/hierarchical/elements.h"
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

}  // namespace
}  // namespace lambert::hierarchical
