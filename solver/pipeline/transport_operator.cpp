#include "solver/pipeline/transport_operator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace lambert {

BatchOperator TransportOperator::among(std::span<const int> unknowns) const {
  if (unknowns.size() == size())
    return [this](const std::vector<const double*>& V, const std::vector<double*>& FV) { apply(V, FV); };
  const std::vector<int> at(unknowns.begin(), unknowns.end());
  return [this, at](const std::vector<const double*>& V, const std::vector<double*>& FV) {
    const std::size_t K = V.size(), N = size(), n = at.size();
    std::vector<std::vector<double>> full(K, std::vector<double>(N, 0.0)), out(K, std::vector<double>(N));
    std::vector<const double*> in(K);
    std::vector<double*> result(K);
    for (std::size_t k = 0; k < K; ++k) {
      for (std::size_t r = 0; r < n; ++r) full[k][at[r]] = V[k][r];
      in[k] = full[k].data();
      result[k] = out[k].data();
    }
    apply(in, result);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
      for (std::size_t k = 0; k < K; ++k)
        for (std::size_t r = range.begin(); r != range.end(); ++r) FV[k][r] = out[k][at[r]];
    });
  };
}

void TransportOperator::visit_factors(const FactorVisitor& visit) const {
  constexpr std::size_t kBatch = 64;
  const std::size_t N = size();
  std::vector<std::vector<double>> unit(kBatch, std::vector<double>(N, 0.0)), column(kBatch, std::vector<double>(N));
  for (std::size_t j0 = 0; j0 < N; j0 += kBatch) {
    const std::size_t K = std::min(kBatch, N - j0);
    std::vector<const double*> in(K);
    std::vector<double*> out(K);
    for (std::size_t k = 0; k < K; ++k) {
      std::fill(unit[k].begin(), unit[k].end(), 0.0);
      unit[k][j0 + k] = 1;
      in[k] = unit[k].data();
      out[k] = column[k].data();
    }
    apply(in, out);
    for (std::size_t k = 0; k < K; ++k)
      for (std::size_t i = 0; i < N; ++i)
        if (column[k][i] != 0) visit(i, j0 + k, column[k][i]);
  }
}

}  // namespace lambert
