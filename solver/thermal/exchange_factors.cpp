// Hottel's total exchange factors on the operator (grey_exchange.h, total_exchange_factors): one
// right-hand-side set per reported surface in the spectral-systems stage, solved in lockstep.
#include <algorithm>

#include "solver/linear_solve.h"
#include "solver/pipeline/spectral_systems.h"
#include "solver/radiosity.h"
#include "solver/thermal/grey_exchange.h"

namespace lambert {

std::vector<double> total_exchange_factors(const TransportOperator& op, const SurfaceGroups& groups,
                                           const ViewFactorMatrix& m, const std::vector<double>& emissivity,
                                           const SolveControl& control) {
  const std::size_t N = op.size(), S = groups.size();
  const std::vector<int> group = patch_groups(op, groups);
  // Reported patches reflect 1 − ε; occluders and patches inside solids are black and emit nothing.
  std::vector<double> rho(N, 0.0), eps(N, 0.0), zero(N, 0.0);
  std::vector<int> unknowns;
  for (std::size_t i = 0; i < N; ++i) {
    if (group[i] < 0) continue;
    eps[i] = emissivity.at(op.patches()[i].surface);
    rho[i] = 1 - eps[i];
    if (rho[i] != 0) unknowns.push_back(static_cast<int>(i));
  }
  std::vector<std::vector<double>> M(S, std::vector<double>(N, 0.0));  // set I: ε on I's patches
  std::vector<RhsSet> sets;
  for (std::size_t i = 0; i < N; ++i)
    if (group[i] >= 0) M[group[i]][i] = eps[i];
  for (std::size_t I = 0; I < S; ++I) sets.push_back({&M[I], &zero});
  SpectralSystems systems(rho, sets, unknowns, N, 1);
  systems.set_right_hand_sides(&op, true);
  if (!unknowns.empty())
    solve_radiosity_systems(unknowns.size(), op.among(unknowns), systems.systems(), kThermalTolerance, 10000,
                            [&] { return control.cancel && control.cancel->load(std::memory_order_relaxed); });
  // A_I ℱ_IJ = Σ_{j∈J} A_j ε_j H_j^(I), H^(I) = F B^(I), kBatch sources at a time.
  std::vector<double> script_F(S * S, 0.0);
  constexpr std::size_t kBatch = 32;
  for (std::size_t I0 = 0; I0 < S; I0 += kBatch) {
    const std::size_t K = std::min(kBatch, S - I0);
    std::vector<std::vector<double>> B(K), H(K, std::vector<double>(N));
    std::vector<const double*> in(K);
    std::vector<double*> out(K);
    for (std::size_t k = 0; k < K; ++k) {
      B[k] = systems.radiosity_vector(systems.system_of(I0 + k, 0), false);
      in[k] = B[k].data();
      out[k] = H[k].data();
    }
    op.apply(in, out);
    for (std::size_t k = 0; k < K; ++k)
      for (std::size_t j = 0; j < N; ++j)
        if (group[j] >= 0) script_F[(I0 + k) * S + group[j]] += op.patches()[j].area_m2 * eps[j] * H[k][j];
  }
  for (std::size_t I = 0; I < S; ++I)
    for (std::size_t J = 0; J < S && m.area_m2[I] > 0; ++J) script_F[I * S + J] /= m.area_m2[I];
  return script_F;
}

}  // namespace lambert
