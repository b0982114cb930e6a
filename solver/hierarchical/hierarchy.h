// The hierarchy of the hierarchical method, and its transport operator F applied matrix-free:
//
//   H_i = Σ_links at i and its ancestors F_link B_source + what links into its clusters give it
//
// pull (the radiosity up to elements and clusters), gather over links, push (each parent's linear
// field down to its children's vertices; a leaf takes the mean), and the adjoint of each step for Fᵀ.
// The closure balance (closure.h) makes it F' = D_r F D_c.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "solver/hierarchical/clusters.h"
#include "solver/hierarchical/elements.h"
#include "solver/hierarchical/links.h"

namespace lambert::hierarchical {

inline constexpr std::size_t kMaxBatch = 16;  // systems per gather pass (the GMRES batch size)

struct Hierarchy : ElementForest, ClusterTree, LinkSet {
  // The closure (closure.h): the operator applied is F'_ij = c_j F_ij (d_i + λ_i g_j), per leaf: c =
  // source_scale on the radiosity shot (columns); d = leaf_scale and λ = row_shift on the gathered
  // irradiance (rows); g = source_weight, how much of its row's correction a link from leaf j takes
  // per unit of its factor. With row_shift empty, F' = D_r F D_c.
  std::vector<double> leaf_scale;
  std::vector<double> source_scale;
  std::vector<double> row_shift;
  std::vector<double> source_weight;

  // Per-node values of one gather pass, K systems interleaved ([node][k]).
  struct Values {
    std::size_t K = 0;
    std::vector<double> B;    // per element: area-mean radiosity
    std::vector<double> Phi;  // per cluster: 6 bins × K
  };

  // Area-mean radiosity per element and projected power per cluster of K leaf vectors (K ≤ any);
  // V[k][leaf] × column_scale[leaf] where column_scale is given.
  void pull(const std::vector<const double*>& V, Values& out, const double* column_scale = nullptr) const;

  // How an element link reads its source element at its read point (Link::bin[0], bin[1] or
  // LeafLink::point): the source's radiosity B, or off the centroid the linear field fitted to its
  // corner children, B + Σ_v w_v m_v (corner_weights); and the adjoint of that read.
  struct SourceRead {
    int source = 0;
    int children = -1;  // the first of the corner children 0, 1, 2 (kChildVertex), or −1: B alone
    std::array<double, 3> w{};
    double value(const double* B, std::size_t K, std::size_t k) const {
      const double b = B[source * K + k];
      if (children < 0) return b;
      const double* m = &B[children * K];
      return b + w[0] * m[k] + w[1] * m[K + k] + w[2] * m[2 * K + k];
    }
    void scatter(double read_bar, double* B_bar) const {  // B_bar += read_bar ∂value/∂B
      B_bar[source] += read_bar;
      if (children < 0) return;
      for (int q = 0; q < 3; ++q) B_bar[children + q] += w[q] * read_bar;
    }
  };
  SourceRead source_read(int source, std::array<unsigned char, 2> point) const {
    // (The centroid test first: it needs only the link, and most links read the centroid.)
    if (point[0] == kCentroid && point[1] == kCentroid) return {source};
    const int children = elements[source].first_child;
    if (children < 0) return {source};
    return {source, children, corner_weights(point[0], point[1])};
  }

  // FV[k] = F V[k] over the leaves for K ≤ kMaxBatch vectors; with `scaled`, F' V[k].
  void apply(const std::vector<const double*>& V, const std::vector<double*>& FV, bool scaled = true) const;
  // out = F'ᵀ W over the leaves (`scaled`), or Fᵀ W.
  void apply_transpose(const double* W, double* out, bool scaled) const;
  // out_j = Σ_i W_i F_ij (d_i + λ_i g_j): F'ᵀ W without the column scales, for the balance.
  void transpose_rows_scaled(const double* W, double* out) const;

 private:
  using Field = std::array<double, 3 * kMaxBatch>;  // V, [axis][k]
  void gather_pass(const std::vector<const double*>& V, const std::vector<double*>& FV, const double* column_scale,
                   const double* row_scale) const;
  void transpose_pass(const double* W, double* out) const;
  void gather_links(int e, const Values& v, double* h) const;
  void cluster_field(const Values& v, std::vector<double>& root_E) const;
  void field_down(int c, Field V, bool carried, const Values& v, double* root_E) const;
  Vector3 field_up(int c, bool needed, const double* root_E_bar, double* B_bar, double* Phi_bar) const;
};

}  // namespace lambert::hierarchical
