#include "solver/hierarchical/hierarchy.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <stdexcept>

namespace lambert::hierarchical {

// Area-mean radiosity per element and projected power per cluster; V[k][leaf] × column_scale[leaf]
// where column_scale is given.
void Hierarchy::pull(const std::vector<const double*>& V, Values& out, const double* column_scale) const {
  const std::size_t K = V.size();
  out.K = K;
  out.B.assign(elements.size() * K, 0.0);
  out.Phi.assign(clusters.size() * 6 * K, 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, root_block.size(), 8), [&](const auto& range) {
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      const auto [first, end] = root_block[r];
      for (int e = end - 1; e >= first; --e) {  // children come after their parent
        const Element& el = elements[e];
        double* b = &out.B[e * K];
        if (el.leaf >= 0) {
          const double c = column_scale ? column_scale[el.leaf] : 1.0;
          for (std::size_t k = 0; k < K; ++k) b[k] = c * V[k][el.leaf];
        } else {
          for (int c = 0; c < 4; ++c) {
            const double w = child_weight(el.first_child + c, e);
            const double* bc = &out.B[(el.first_child + c) * K];
            for (std::size_t k = 0; k < K; ++k) b[k] += w * bc[k];
          }
        }
      }
    }
  });
  for (std::size_t c = clusters.size(); c-- > 0;) {  // children come after their parent
    const Cluster& cl = clusters[c];
    double* phi = &out.Phi[c * 6 * K];
    if (cl.root >= 0) {
      const double* b = &out.B[cl.root * K];
      for (int bin = 0; bin < 6; ++bin)
        for (std::size_t k = 0; k < K; ++k) phi[bin * K + k] = cl.projected[bin] * b[k];
    } else {
      for (int ch : cl.child) {
        const double* p = &out.Phi[ch * 6 * K];
        for (std::size_t q = 0; q < 6 * K; ++q) phi[q] += p[q];
      }
    }
  }
}

// Gathered irradiance at element e from its own links (not its ancestors'), K systems, as a linear
// field over the element: its values at the three vertices, h[v K + k].
void Hierarchy::gather_links(int e, const Values& v, double* h) const {
  const std::size_t K = v.K;
  const double* B = v.B.data();
  for (std::size_t l = link_start[e]; l < link_start[e + 1]; ++l) {
    const Link& link = links[l];
    if (!link.from_cluster) {
      const SourceRead read = source_read(link.source, link.read_point());
      for (std::size_t k = 0; k < K; ++k) {
        const double value = read.value(B, K, k);
        for (int n = 0; n < 3; ++n) h[n * K + k] += link.coeff[n] * value;
      }
    } else {
      const double* phi = &v.Phi[link.source * 6 * K];
      for (std::size_t k = 0; k < K; ++k) {
        double c = 0;
        for (int a = 0; a < 3; ++a) c += link.coeff[a] * bin_value(phi, link.bin[a], K, k);
        for (int n = 0; n < 3; ++n) h[n * K + k] += c;
      }
    }
  }
  for (const LeafLink& link : leaf_links_of(e)) {
    const SourceRead read = source_read(link.source, link.point);
    const double F = link.F;
    for (std::size_t k = 0; k < K; ++k) {
      const double c = F * read.value(B, K, k);
      for (int n = 0; n < 3; ++n) h[n * K + k] += c;
    }
  }
}

void Hierarchy::apply(const std::vector<const double*>& V, const std::vector<double*>& FV, bool scaled) const {
  if (!scaled) return gather_pass(V, FV, nullptr, nullptr);
  if (row_shift.empty()) return gather_pass(V, FV, source_scale.data(), leaf_scale.data());
  // F' V = d ∘ F (c ∘ V) + λ ∘ F (c ∘ g ∘ V): both in one pass over the links.
  const std::size_t N = leaves.size();
  for (std::size_t start = 0; start < V.size(); start += kMaxBatch / 2) {
    const std::size_t K = std::min(V.size() - start, kMaxBatch / 2);
    std::vector<std::vector<double>> in(2 * K, std::vector<double>(N)), out(2 * K, std::vector<double>(N));
    std::vector<const double*> in_ptr;
    std::vector<double*> out_ptr;
    for (std::size_t k = 0; k < K; ++k)
      for (std::size_t j = 0; j < N; ++j) {
        in[k][j] = source_scale[j] * V[start + k][j];
        in[K + k][j] = source_weight[j] * in[k][j];
      }
    for (std::size_t q = 0; q < 2 * K; ++q) in_ptr.push_back(in[q].data()), out_ptr.push_back(out[q].data());
    gather_pass(in_ptr, out_ptr, nullptr, nullptr);
    for (std::size_t k = 0; k < K; ++k)
      for (std::size_t i = 0; i < N; ++i) FV[start + k][i] = leaf_scale[i] * out[k][i] + row_shift[i] * out[K + k][i];
  }
}

// FV[k] = F (column_scale ∘ V[k]) over the leaves, times row_scale where given: pull, gather, push
// (the parent's linear field evaluated at the child's vertices, kChildVertex), the leaf's mean.
void Hierarchy::gather_pass(const std::vector<const double*>& V, const std::vector<double*>& FV,
                            const double* column_scale, const double* row_scale) const {
  Values v;
  pull(V, v, column_scale);
  const std::size_t K = V.size();
  std::vector<double> root_E;
  cluster_field(v, root_E);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, root_block.size(), 8), [&](const auto& range) {
    std::vector<double> H, own(3 * K);
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      const auto [first, end] = root_block[r];
      H.assign((end - first) * 3 * K, 0.0);
      const double root_spread = open_spread(first);
      for (int n = 0; n < 3; ++n)  // what links into clusters give the root: constant over it
        for (std::size_t k = 0; k < K; ++k) H[n * K + k] = root_spread * root_E[r * K + k];
      for (int e = first; e < end; ++e) {  // parents first: push down
        const Element& el = elements[e];
        double* h = &H[(e - first) * 3 * K];
        if (el.parent >= 0) {
          const double* hp = &H[(el.parent - first) * 3 * K];
          const auto& at = kChildVertex[e - elements[el.parent].first_child];
          for (int n = 0; n < 3; ++n)
            for (int m = 0; m < 3; ++m)
              if (at[n][m] != 0)
                for (std::size_t k = 0; k < K; ++k) h[n * K + k] += at[n][m] * hp[m * K + k];
        }
        if (open_area.empty()) {
          gather_links(e, v, h);
        } else {  // onto the open part (open_spread); an enclosed leaf receives nothing
          std::fill(own.begin(), own.end(), 0.0);
          gather_links(e, v, own.data());
          const double spread = open_spread(e);
          for (std::size_t q = 0; q < 3 * K; ++q) h[q] = spread > 0 ? h[q] + spread * own[q] : 0.0;
        }
        if (el.leaf >= 0) {
          const double s = (row_scale ? row_scale[el.leaf] : 1.0) / 3;
          for (std::size_t k = 0; k < K; ++k) FV[k][el.leaf] = s * (h[k] + h[K + k] + h[2 * K + k]);
        }
      }
    }
  });
}

// The irradiance that links into clusters give each root, K systems ([slot][k]): the vector
// irradiance V = Σ Ψ toward of a cluster's links and its ancestors', on the root's normal.
void Hierarchy::cluster_field(const Values& v, std::vector<double>& root_E) const {
  if (v.K > kMaxBatch) throw std::logic_error("cluster_field: more systems than one gather pass holds");
  root_E.assign(roots.size() * v.K, 0.0);
  if (!cluster_links.empty()) field_down(0, {}, false, v, root_E.data());
}
void Hierarchy::field_down(int c, Field V, bool carried, const Values& v, double* root_E) const {
  const std::size_t K = v.K;
  for (std::size_t l = cluster_link_start[c]; l < cluster_link_start[c + 1]; ++l) {
    const ClusterLink& link = cluster_links[l];
    for (std::size_t k = 0; k < K; ++k) {
      double psi = 0;
      if (link.from_cluster) {
        const double* phi = &v.Phi[link.source * 6 * K];
        for (int a = 0; a < 3; ++a) psi += link.coeff[a] * bin_value(phi, link.bin[a], K, k);
      } else {
        psi = link.coeff[0] * v.B[link.source * K + k];
      }
      for (int a = 0; a < 3; ++a) V[a * K + k] += psi * link.toward[a];
    }
    carried = true;
  }
  const Cluster& C = clusters[c];
  if (C.root >= 0) {
    if (!carried) return;
    const Vector3& n = elements[C.root].normal;
    for (std::size_t k = 0; k < K; ++k) root_E[C.slot * K + k] = n.x * V[k] + n.y * V[K + k] + n.z * V[2 * K + k];
    return;
  }
  if (!carried && !links_below[c]) return;
  if (C.root_count >= 4096) {
    tbb::parallel_invoke([&] { field_down(C.child[0], V, carried, v, root_E); },
                         [&] { field_down(C.child[1], V, carried, v, root_E); });
  } else {
    field_down(C.child[0], V, carried, v, root_E);
    field_down(C.child[1], V, carried, v, root_E);
  }
}
// The adjoint of field_down for one system: root_E_bar per slot into B_bar and Phi_bar; returns
// the adjoint of cluster c's V where c or an ancestor receives links (`needed`), else 0.
Vector3 Hierarchy::field_up(int c, bool needed, const double* root_E_bar, double* B_bar, double* Phi_bar) const {
  const Cluster& C = clusters[c];
  needed = needed || cluster_link_start[c + 1] > cluster_link_start[c];
  if (!needed && !links_below[c]) return {};
  Vector3 V_bar{};
  if (C.root >= 0) {
    V_bar = root_E_bar[C.slot] * elements[C.root].normal;
  } else {
    V_bar = field_up(C.child[0], needed, root_E_bar, B_bar, Phi_bar) + field_up(C.child[1], needed, root_E_bar, B_bar, Phi_bar);
  }
  for (std::size_t l = cluster_link_start[c]; l < cluster_link_start[c + 1]; ++l) {
    const ClusterLink& link = cluster_links[l];
    const double psi_bar = link.toward[0] * V_bar.x + link.toward[1] * V_bar.y + link.toward[2] * V_bar.z;
    if (link.from_cluster) {
      for (int a = 0; a < 3; ++a) scatter_bin(&Phi_bar[link.source * 6], link.bin[a], link.coeff[a] * psi_bar);
    } else {
      B_bar[link.source] += link.coeff[0] * psi_bar;
    }
  }
  return needed ? V_bar : Vector3{};
}

void Hierarchy::apply_transpose(const double* W, double* out, bool scaled) const {
  if (!scaled) return transpose_pass(W, out);
  transpose_rows_scaled(W, out);
  for (std::size_t j = 0; j < leaves.size(); ++j) out[j] *= source_scale[j];
}

void Hierarchy::transpose_rows_scaled(const double* W, double* out) const {
  const std::size_t N = leaves.size();
  std::vector<double> w(N);
  for (std::size_t i = 0; i < N; ++i) w[i] = leaf_scale[i] * W[i];
  transpose_pass(w.data(), out);
  if (row_shift.empty()) return;
  std::vector<double> shifted(N);
  for (std::size_t i = 0; i < N; ++i) w[i] = row_shift[i] * W[i];
  transpose_pass(w.data(), shifted.data());
  for (std::size_t j = 0; j < N; ++j) out[j] += source_weight[j] * shifted[j];
}

// out = Fᵀ W over the leaves: the adjoint of gather_pass, step by step in reverse (leaf mean,
// push-down, gather, pull). Sources receive from receivers of other roots, so each thread
// accumulates into its own copy of the element and cluster adjoints.
void Hierarchy::transpose_pass(const double* W, double* out) const {
  const std::size_t E = elements.size();
  std::vector<double> root_E_bar(roots.size(), 0.0);  // adjoint of cluster_field's root_E
  tbb::enumerable_thread_specific<std::vector<double>> adjoints(std::vector<double>(E + 6 * clusters.size(), 0.0));
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, root_block.size(), 8), [&](const auto& range) {
    std::vector<double>& a = adjoints.local();
    double* B_bar = a.data();
    double* Phi_bar = a.data() + E;
    std::vector<double> H;  // adjoint of the vertex irradiance, per element of the root's block
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      const auto [first, end] = root_block[r];
      H.assign((end - first) * 3, 0.0);
      for (int e = end - 1; e >= first; --e) {  // children first: the reverse of the push-down
        const Element& el = elements[e];
        double* h = &H[(e - first) * 3];
        if (el.leaf >= 0)
          for (int n = 0; n < 3; ++n) h[n] += W[el.leaf] / 3;
        // The adjoint of apply's spread onto the open part: what e gathers reaches its leaves times
        // open_spread, and what its parent pushes reaches them only where e is not all enclosed.
        const double spread = open_spread(e);
        if (spread == 0)
          for (int n = 0; n < 3; ++n) h[n] = 0;
        const double hs[3] = {spread * h[0], spread * h[1], spread * h[2]};
        for (std::size_t l = link_start[e]; l < link_start[e + 1]; ++l) {
          const Link& link = links[l];
          if (!link.from_cluster) {
            const double read_bar = link.coeff[0] * hs[0] + link.coeff[1] * hs[1] + link.coeff[2] * hs[2];
            source_read(link.source, link.read_point()).scatter(read_bar, B_bar);
          } else {
            const double total = hs[0] + hs[1] + hs[2];
            for (int k = 0; k < 3; ++k) scatter_bin(&Phi_bar[link.source * 6], link.bin[k], link.coeff[k] * total);
          }
        }
        for (const LeafLink& link : leaf_links_of(e)) {
          source_read(link.source, link.point).scatter(link.F * hs[0] + link.F * hs[1] + link.F * hs[2], B_bar);
        }
        if (el.parent >= 0) {
          double* hp = &H[(el.parent - first) * 3];
          const auto& at = kChildVertex[e - elements[el.parent].first_child];
          for (int n = 0; n < 3; ++n)
            for (int m = 0; m < 3; ++m) hp[m] += at[n][m] * h[n];
        }
      }
      root_E_bar[r] = open_spread(first) * (H[0] + H[1] + H[2]);
    }
  });
  std::vector<double> bar(E + 6 * clusters.size(), 0.0);
  for (const auto& a : adjoints)
    for (std::size_t q = 0; q < bar.size(); ++q) bar[q] += a[q];
  double* B_bar = bar.data();
  double* Phi_bar = bar.data() + E;
  if (!cluster_links.empty()) field_up(0, false, root_E_bar.data(), B_bar, Phi_bar);
  for (std::size_t c = 0; c < clusters.size(); ++c) {  // parents first: the reverse of the pull
    const Cluster& cl = clusters[c];
    const double* phi = &Phi_bar[c * 6];
    if (cl.root >= 0) {
      for (int bin = 0; bin < 6; ++bin) B_bar[cl.root] += cl.projected[bin] * phi[bin];
    } else {
      for (int ch : cl.child)
        for (int bin = 0; bin < 6; ++bin) Phi_bar[ch * 6 + bin] += phi[bin];
    }
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, root_block.size(), 8), [&](const auto& range) {
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      const auto [first, end] = root_block[r];
      for (int e = first; e < end; ++e) {
        const Element& el = elements[e];
        if (el.leaf >= 0) {
          out[el.leaf] = B_bar[e];
        } else {
          for (int c = 0; c < 4; ++c) B_bar[el.first_child + c] += child_weight(el.first_child + c, e) * B_bar[e];
        }
      }
    }
  });
}

}  // namespace lambert::hierarchical
