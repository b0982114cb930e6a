// The closure balance (solver/hierarchical/closure.h) on an operator whose factors are written down:
// links between the leaves of a square, one leaf to another, each with a given factor, so that the
// balanced operator F'_ij = c_j F_ij (d_i + λ_i g_j) can be written out and checked against what the
// balance promises: every closed row sums to 1, the emitting leaves of a root together give the scene
// exactly the power they send, and no factor turns negative, including on a row whose excess is more
// than its links from dim sources carry, which the balance must then scale whole.
#include "solver/hierarchical/closure.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "solver/hierarchical/clusters.h"
#include "solver/hierarchical/elements.h"
#include "tests/scene_builder.h"

namespace lambert::hierarchical {
namespace {

constexpr int kRows = 8;  // a 2 m square of two roots, each split once: 8 leaves of 0.5 m²

// The square's hierarchy with a link from every leaf j to every other leaf i, of factor F[i][j].
Hierarchy hierarchy_with_factors(const std::vector<std::vector<double>>& F) {
  test::SceneBuilder b;
  b.surface("square", b.material("grey", 0.5), test::rectangle({0, 0, 0}, {2, 0, 0}, {0, 2, 0}));
  Hierarchy h;
  static_cast<ElementForest&>(h) = build_forest(b.scene(), 0.5, {});
  static_cast<ClusterTree&>(h) = build_cluster_tree(h);
  for (int i = 0; i < kRows; ++i)
    for (int j = 0; j < kRows; ++j) {
      if (F[i][j] == 0) continue;
      Link link;
      link.receiver = h.leaves[i];
      link.source = h.leaves[j];
      const float f = static_cast<float>(F[i][j]);
      link.coeff = {f, f, f};  // the same factor at the receiver's three vertices: a leaf's mean
      h.links.push_back(link);
    }
  std::sort(h.links.begin(), h.links.end(), link_order<Link>);
  h.index_links(h.elements.size(), h.clusters);
  return h;
}

// F'_ij as the balance leaves it in h (closure.h).
double balanced_factor(const Hierarchy& h, const std::vector<std::vector<double>>& F, int i, int j) {
  const double shift = h.row_shift.empty() ? 0.0 : h.row_shift[i];
  return h.source_scale[j] * F[i][j] * (h.leaf_scale[i] + shift * h.source_weight[j]);
}

TEST(Closure, ClosesEveryRowAndTheEmittersColumnsWithoutANegativeFactor) {
  // Leaves 0 and 1 (one root) emit and send 100; the others send 1. Row 2 takes 1.1 from leaf 0
  // alone, and leaf 1's column is short (about 0.3), so the emitters' joint column scale lifts row 2's
  // bright factor further: its excess is more than its links from dim sources carry, and shifting it
  // onto them alone would turn their factors negative. The other rows are random, 0.74 to 1.34.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<std::vector<double>> F(kRows, std::vector<double>(kRows, 0.0));
  for (int i = 0; i < kRows; ++i) {
    if (i == 2) continue;
    double sum = 0;
    for (int j = 2; j < kRows; ++j)
      if (j != i) sum += F[i][j] = 0.1 + unit(rng);
    const double dim_share = 0.7 + 0.5 * unit(rng);
    for (int j = 2; j < kRows; ++j) F[i][j] *= dim_share / sum;
    if (i != 0) F[i][0] = 0.02 + 0.05 * unit(rng);
    if (i != 1) F[i][1] = 0.02 + 0.05 * unit(rng);
  }
  F[2][0] = 1.1;
  for (int j = 3; j < kRows; ++j) F[2][j] = 0.01;
  for (auto& row : F)
    for (double& f : row) f = static_cast<float>(f);  // as the links hold them

  Hierarchy h = hierarchy_with_factors(F);
  ASSERT_EQ(h.leaves.size(), std::size_t{kRows});
  ASSERT_EQ(h.elements[h.leaves[0]].root, h.elements[h.leaves[1]].root);
  const std::vector<Hemisphere> closed(kRows, Hemisphere::Closed);
  std::vector<double> sends(kRows, 1.0);
  std::vector<char> emits(kRows, 0);
  sends[0] = sends[1] = 100;
  emits[0] = emits[1] = 1;
  const std::vector<Patch> patches = h.leaf_patches();
  BalanceState state;
  const Balanced result = balance(h, state, closed, sends, emits, patches, 1e-12, true, SolveControl{});

  // The rows' largest miss before the balance, and after it.
  double raw = 0;
  for (const auto& row : F) {
    double sum = 0;
    for (const double f : row) sum += f;
    raw = std::max(raw, std::abs(1 - sum));
  }
  EXPECT_NEAR(result.raw_error, raw, 1e-12);
  EXPECT_LT(result.residual, 1e-10);

  // Row 2 was scaled whole (λ = 0, d < 1): every factor of it by the same ratio.
  EXPECT_EQ(h.row_shift[2], 0.0);
  EXPECT_LT(h.leaf_scale[2], 1.0);
  // And it had to be: the shift that would close it through g alone, λ = (1 − R)/G with R and G
  // the row's sums under the balanced column scales, takes a dim link below zero.
  double R = 0, G = 0;
  for (int j = 0; j < kRows; ++j) {
    R += h.source_scale[j] * F[2][j];
    G += h.source_scale[j] * F[2][j] * h.source_weight[j];
  }
  const double shift = (1 - R) / G;
  const double max_weight = *std::max_element(h.source_weight.begin(), h.source_weight.end());
  EXPECT_LT(1 + shift * max_weight, 0.0);
  // The other rows are closed by the shift (λ ≠ 0), which gives a dim link more of the correction
  // per unit of its factor than a bright one (g_j = 1/max(B_j, B̄)).
  int shifted = 0;
  for (int i = 0; i < kRows; ++i) shifted += h.row_shift[i] != 0;
  EXPECT_GE(shifted, kRows - 2);

  // The balanced operator, written out: rows 1, factors ≥ 0, and the emitters' joint column (what
  // the scene gathers of the power leaves 0 and 1 send, over that power) 1.
  double gathered = 0, sent = 0;
  for (int i = 0; i < kRows; ++i) {
    double row = 0;
    for (int j = 0; j < kRows; ++j) {
      const double f = balanced_factor(h, F, i, j);
      EXPECT_GE(f, 0.0) << i << " " << j;
      row += f;
      if (emits[j]) gathered += patches[i].area_m2 * f * sends[j];
    }
    EXPECT_NEAR(row, 1.0, 1e-10) << i;
  }
  for (int j = 0; j < kRows; ++j)
    if (emits[j]) sent += patches[j].area_m2 * sends[j];
  EXPECT_NEAR(gathered / sent, 1.0, 1e-10);

  // The operator applies what is written out: F' 1 = 1.
  const std::vector<double> ones(kRows, 1.0);
  std::vector<double> rows(kRows);
  h.apply({ones.data()}, {rows.data()}, true);
  for (int i = 0; i < kRows; ++i) EXPECT_NEAR(rows[i], 1.0, 1e-10) << i;
}

}  // namespace
}  // namespace lambert::hierarchical
