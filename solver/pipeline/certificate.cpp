#include "solver/pipeline/certificate.h"

#include "solver/energy_balance.h"

namespace lambert {
namespace {

// Clear panes (clear_panes.h) in the balance. A clear face i receives H_i = E_i + G_i (direct and
// interreflected), reflects ρ H_i, passes on τ ḡ G_i as radiosity of its twin (account_energy's τ,
// which counts (1 − ρ − τ ḡ) H_i as absorbed) and T_i of E_i by rays, so it absorbs
//   (1 − ρ) H_i − τ ḡ G_i − T_i = (1 − ρ − τ ḡ) H_i + τ ḡ E_i − T_i.
// The rays' light lands on the patches beyond as direct irradiance, counted there a second time:
// of a source of known flux it did not escape unless it crossed to nothing (escaped += T), and a
// source of unknown flux, counted as emitted where it lands, did not emit it again (emitted −= T).
void count_clear_panes(Solution& sol, const Scene& scene, const DirectLight& light) {
  const std::size_t W = scene.grid.size();
  const auto& wt = scene.grid.weight_nm;
  double absorbed = 0, escaped = 0, emitted = 0;
  for (std::size_t i = 0; i < sol.patches.size(); ++i) {
    if (!light.clear_face[i]) continue;
    const double A = sol.patches[i].area_m2;
    for (std::size_t w = 0; w < W; ++w) {
      const std::size_t k = i * W + w;
      const double T_known = light.transmitted_known_flux[k], T_unknown = light.transmitted_unknown_flux[k];
      absorbed += wt[w] * A * (light.tau[k] * light.E_direct[k] - T_known - T_unknown);
      escaped += wt[w] * A * T_known;
      emitted -= wt[w] * A * T_unknown;
    }
  }
  SolveStats& s = sol.stats;
  s.absorbed_W += absorbed;
  s.escaped_W += escaped;
  s.emitted_W += emitted;
  s.relative_imbalance = s.emitted_W > 0 ? (s.emitted_W - s.absorbed_W - s.escaped_W) / s.emitted_W : 0;
}

}  // namespace

void certify_energy(Solution& sol, const Scene& scene, const DirectLight& light, const TransportOperator* op) {
  const std::size_t N = sol.patches.size();
  std::vector<double> leak(N, 1.0);
  if (op && N > 0) {
    std::vector<double> area(N), gathered(N);
    for (std::size_t i = 0; i < N; ++i) area[i] = sol.patches[i].area_m2;
    op->apply_transpose(area.data(), gathered.data());
    for (std::size_t j = 0; j < N; ++j) leak[j] = 1 - gathered[j] / area[j];
  }
  account_energy(scene.grid, light.sources, sol.patches, light.rho, light.M, light.E_direct, light.E_known_flux,
                 sol.radiosity, sol.irradiance, leak, sol.stats, light.tau);
  if (!light.clear_face.empty()) count_clear_panes(sol, scene, light);
}

}  // namespace lambert
