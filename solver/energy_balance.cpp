#include "solver/energy_balance.h"

namespace lambert {

void account_energy(const WavelengthGrid& grid, const std::vector<std::unique_ptr<LightModel>>& sources,
                    const std::vector<Patch>& patches, const std::vector<double>& rho, const std::vector<double>& M,
                    const std::vector<double>& E_direct, const std::vector<double>& E_known_flux,
                    const std::vector<double>& radiosity, const std::vector<double>& irradiance,
                    const std::vector<double>& leak, SolveStats& stats, const std::vector<double>& tau) {
  const std::size_t W = grid.size();
  const auto& wt = grid.weight_nm;
  double emitted = 0, absorbed = 0, escaped = 0;
  for (const auto& source : sources) {
    // Known-flux sources: all of it is emitted; what reached no patch escaped (subtracted below).
    const double flux = source->flux_factor();
    const auto& S = source->spectrum();
    for (std::size_t w = 0; w < W; ++w) {
      emitted += wt[w] * flux * S[w];
      escaped += wt[w] * flux * S[w];
    }
  }
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const double A = patches[i].area_m2;
    for (std::size_t w = 0; w < W; ++w) {
      const std::size_t k = i * W + w;
      // Directional and ambient light count as emitted where they land: their flux has no total.
      emitted += wt[w] * A * (M[k] + E_direct[k] - E_known_flux[k]);
      absorbed += wt[w] * A * (1 - rho[k] - (tau.empty() ? 0.0 : tau[k])) * irradiance[k];
      escaped += wt[w] * A * (radiosity[k] * leak[i] - E_known_flux[k]);
    }
  }
  stats.emitted_W = emitted;
  stats.absorbed_W = absorbed;
  stats.escaped_W = escaped;
  stats.relative_imbalance = emitted > 0 ? (emitted - absorbed - escaped) / emitted : 0;
}

}  // namespace lambert
