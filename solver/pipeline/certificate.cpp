#include "solver/pipeline/certificate.h"

#include "solver/energy_balance.h"

namespace lambert {

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
}

}  // namespace lambert
