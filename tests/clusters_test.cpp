// The cluster tree of the hierarchical method (solver/hierarchical/clusters.h): where it splits a
// scene of separate objects, known by construction (which root belongs to which object); what a link
// reads of a cluster's bins, against the sum over its triangles Σ_j B_j A_j (n_j · w)⁺; where the
// cluster sends from (oracle.h), against the power-weighted centroid by hand; and the factors over an
// element receiver, against the point cluster's kernel integrated over the receiver finely.
#include "solver/hierarchical/clusters.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "solver/hierarchical/elements.h"
#include "solver/hierarchical/hierarchy.h"
#include "solver/hierarchical/oracle.h"
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

// A square pyramid's four faces (normals 45° from +z, one on each side), each a root and a leaf.
Hierarchy pyramid_hierarchy() {
  test::SceneBuilder b;
  const Point3 apex{0, 0, 1};
  const Point3 base[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  std::vector<Triangle> faces;
  for (int k = 0; k < 4; ++k) faces.push_back(Triangle{base[k], base[(k + 1) % 4], apex});
  b.surface("pyramid", b.material("grey", 0.5), faces);
  Hierarchy h;
  static_cast<ElementForest&>(h) = build_forest(b.scene(), 10.0, {});
  static_cast<ClusterTree&>(h) = build_cluster_tree(h);
  return h;
}

// A square pyramid's four faces (normals 45° from +z, one on each side) with radiosities 1, 2, 3 and
// 8, as a lit object's sides differ. Read from a direction w within 45° of the axis, every face
// faces w, and the link reads the area vector weighted by radiosity: exactly Σ_j B_j A_j (n_j · w)⁺
// for any radiosity. Farther off the axis the facing bins, weighted for a uniform radiosity, are
// exact for a uniform one.
TEST(ClusterView, ReadsAnyRadiosityExactlyWhereEveryNormalFacesTheReceiver) {
  const Hierarchy h = pyramid_hierarchy();
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

// A regular octahedron (normals in all eight octants: no direction is faced by every face), its faces
// at radiosities 1 … 8 as a lit object's differ. Read along any w, the bins weighted for a uniform
// radiosity miss the lit one's Σ_j B_j A_j (n_j · w)⁺; weighted by what the cluster sends under that
// radiosity (SentFacets, from oracle_values), they read it exactly: each root faces w or not as a
// whole, so the bounds meet.
TEST(ClusterView, ReadsTheRadiosityItsBinsWereWeightedByWhereNormalsStraddleTheReceiver) {
  test::SceneBuilder b;
  const Point3 v[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<Triangle> faces;
  for (int x : {0, 1})
    for (int y : {2, 3})
      for (int z : {4, 5}) {
        Triangle t{v[x], v[y], v[z]};
        if (dot(cross(t.v[1] - t.v[0], t.v[2] - t.v[0]), to_vector(t.centroid())) < 0) std::swap(t.v[1], t.v[2]);
        faces.push_back(t);  // facing out
      }
  b.surface("octahedron", b.material("grey", 0.5), faces);
  Hierarchy h;
  static_cast<ElementForest&>(h) = build_forest(b.scene(), 10.0, {});
  static_cast<ClusterTree&>(h) = build_cluster_tree(h);
  ASSERT_EQ(h.leaves.size(), 8u);
  ASSERT_GT(h.clusters[0].cone_sin, 1);  // the normals fill every direction
  std::vector<double> radiosity(8);
  for (std::size_t i = 0; i < 8; ++i) radiosity[i] = 1.0 + static_cast<double>(i);
  const OracleValues oracle = oracle_values(h, radiosity);
  Hierarchy::Values values;
  h.pull({radiosity.data()}, values);
  double worst_unweighted = 0;
  for (const double tilt : {0.0, 20.0, 50.0, 90.0, 130.0, 170.0}) {
    for (const double turn : {0.0, 30.0, 100.0, 200.0, 290.0}) {
      const double t = tilt * kPi / 180, p = turn * kPi / 180;
      const Vector3 w{std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
      double exact = 0;
      for (std::size_t i = 0; i < h.leaves.size(); ++i) {
        const Element& e = h.elements[h.leaves[i]];
        exact += radiosity[i] * e.area * std::max(0.0, dot(e.normal, w));
      }
      auto read = [&](const ClusterView& view) {
        double sum = 0;
        for (int a = 0; a < 3; ++a) sum += view.weight[a] * bin_value(&values.Phi[0], view.bin[a], 1, 0);
        return sum;
      };
      const ClusterView weighted = cluster_view(h, 0, w, 0.1, &oracle.sending.sent);
      ASSERT_LT(weighted.bin[0], kAxisBin);
      EXPECT_NEAR(read(weighted), exact, 1e-12 * exact) << tilt << " " << turn;
      worst_unweighted = std::max(worst_unweighted, std::abs(read(cluster_view(h, 0, w, 0.1)) / exact - 1));
    }
  }
  EXPECT_GT(worst_unweighted, 0.05);  // what the weighting is for
}

// Where a cluster sends from: its leaves' centroids weighted by the power A B each sends, at every
// cluster of the tree (here two separate squares, and the top cluster over both); the box's centre
// where nothing is sent.
TEST(ClusterSending, IsTheCentroidOfItsPower) {
  test::SceneBuilder b;
  const int grey = b.material("grey", 0.5);
  b.surface("near", grey, test::rectangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  b.surface("far", grey, test::rectangle({4, 0, 0}, {2, 0, 0}, {0, 2, 0}));
  Hierarchy h;
  static_cast<ElementForest&>(h) = build_forest(b.scene(), 0.25, {});
  static_cast<ClusterTree&>(h) = build_cluster_tree(h);
  std::vector<double> radiosity(h.leaves.size());
  double power = 0;
  Vector3 moment;
  for (std::size_t i = 0; i < h.leaves.size(); ++i) {
    const Element& e = h.elements[h.leaves[i]];
    radiosity[i] = e.centre.x < 3 ? 1.0 : 3.0;
    power += e.area * radiosity[i];
    moment += e.area * radiosity[i] * to_vector(e.centre);
  }
  // By hand: the near square sends 1 W from (0.5, 0.5), the far one 12 W from (5, 1).
  EXPECT_NEAR(power, 13.0, 1e-12);
  const OracleValues oracle = oracle_values(h, radiosity);
  const Point3 top = oracle.sending.source[0];
  EXPECT_NEAR(top.x, (0.5 * 1 + 5 * 12) / 13.0, 1e-12);
  EXPECT_NEAR(top.y, (0.5 * 1 + 1 * 12) / 13.0, 1e-12);
  EXPECT_NEAR(top.z, 0, 1e-12);
  const OracleValues dark = oracle_values(h, std::vector<double>(h.leaves.size(), 0.0));
  for (std::size_t c = 0; c < h.clusters.size(); ++c) EXPECT_EQ(dark.sending.source[c], h.clusters[c].centre);
}

// A square pyramid (every normal within 45° of +z) at radiosities 1, 2, 3 and 8, seen from a
// triangle above it as large as its distance: the factors the receiver gathers the axis bins by are
// the mean over the receiver of the point cluster's kernel, Σ_j B_j A_j (n_j · u) cos θ / (π d²) from
// where it sends, here integrated over 4⁷ sub-triangles' centroids (within 1e-6 of its limit: 4⁵
// cells differ from it by 1e-4). The degree-5 rule errs by 5e-4 over a receiver this large; the
// kernel at the receiver's centroid alone by 13 %: the curvature a one-point read misses.
TEST(ReceiverMeanFactors, AreTheKernelsMeanOverTheReceiver) {
  const Hierarchy h = pyramid_hierarchy();
  const std::vector<double> radiosity = {1, 2, 3, 8};
  Hierarchy::Values values;
  h.pull({radiosity.data()}, values);
  const Point3 from = oracle_values(h, radiosity).sending.source[0];
  Vector3 sent;  // Σ_j B_j A_j n_j
  for (std::size_t i = 0; i < 4; ++i) sent += radiosity[i] * h.elements[h.leaves[i]].area * h.elements[h.leaves[i]].normal;
  // The receiver: 5 m above, tilted, facing down, 5 m across.
  const Triangle R{{Point3{-1, -2, 6}, Point3{2, 3, 5.5}, Point3{4, -2, 5}}};
  const Vector3 n_R = normalize(cross(R.v[1] - R.v[0], R.v[2] - R.v[0]));
  ASSERT_LT(n_R.z, 0);
  const Vector3 w = normalize(R.centroid() - h.clusters[0].centre);
  const ClusterView view = cluster_view(h, 0, w, 0.5);
  ASSERT_GE(view.bin[0], kAxisBin);
  const std::array<double, 3> factor = receiver_mean_factors(view, w, from, R, n_R);
  double read = 0;
  for (int a = 0; a < 3; ++a) read += factor[a] * bin_value(&values.Phi[0], view.bin[a], 1, 0);
  auto kernel = [&](const Point3& x) {
    const Vector3 u = x - from;
    const double d2 = dot(u, u);
    const Vector3 unit = u / std::sqrt(d2);
    return dot(sent, unit) * std::max(0.0, -dot(n_R, unit)) / (kPi * d2);
  };
  // The mean over R by the midpoint rule on 4⁷ congruent sub-triangles (error O(h²)).
  std::vector<Triangle> cells = {R}, next;
  for (int level = 0; level < 7; ++level) {
    next.clear();
    for (const Triangle& t : cells) {
      const Point3 m01 = barycentric(t.v[0], t.v[1], t.v[2], 0.5, 0.5, 0), m12 = barycentric(t.v[0], t.v[1], t.v[2], 0, 0.5, 0.5),
                   m20 = barycentric(t.v[0], t.v[1], t.v[2], 0.5, 0, 0.5);
      next.insert(next.end(), {Triangle{t.v[0], m01, m20}, Triangle{m01, t.v[1], m12}, Triangle{m20, m12, t.v[2]}, Triangle{m01, m12, m20}});
    }
    cells.swap(next);
  }
  double mean = 0;
  for (const Triangle& t : cells) mean += kernel(t.centroid());
  mean /= static_cast<double>(cells.size());
  EXPECT_NEAR(read, mean, 1e-3 * mean);
  // At one receiving point (links into clusters, probes): the kernel there, its cos θ taken along
  // `toward` by the receiver.
  Vector3 toward;
  const std::array<double, 3> at_point = receivers_factors(view, w, R.centroid(), from, toward);
  double point_read = 0;
  for (int a = 0; a < 3; ++a) point_read += at_point[a] * bin_value(&values.Phi[0], view.bin[a], 1, 0);
  EXPECT_NEAR(point_read * std::max(0.0, dot(n_R, toward)), kernel(R.centroid()), 1e-12 * kernel(R.centroid()));
  EXPECT_GT(std::abs(kernel(R.centroid()) / mean - 1), 0.05);  // what the mean is for
}

}  // namespace
}  // namespace lambert::hierarchical
