#include "solver/pipeline/outputs.h"

namespace lambert {

std::vector<const double*> SystemFields::radiosity() const {
  std::vector<const double*> out;
  for (const auto& b : B) out.push_back(b.data());
  return out;
}

SystemFields system_fields(const SpectralSystems& systems, const TransportOperator* op, bool keep_sign) {
  SystemFields f;
  const std::size_t K = systems.size();
  for (std::size_t k = 0; k < K; ++k) f.B.push_back(systems.radiosity_vector(k, keep_sign));
  if (op && systems.patches() > 0) {
    f.FB.assign(K, std::vector<double>(systems.patches(), 0.0));
    std::vector<double*> out;
    for (auto& h : f.FB) out.push_back(h.data());
    op->apply(f.radiosity(), out);
  }
  return f;
}

void write_outputs(Solution& sol, const SpectralSystems& systems, const SystemFields& fields, const DirectLight& light) {
  const std::size_t N = systems.patches(), W = sol.wavelengths();
  auto write = [&](std::size_t set, const std::vector<double>& E, std::vector<double>& B, std::vector<double>& H) {
    B.assign(N * W, 0.0);
    H.assign(N * W, 0.0);
    for (std::size_t w = 0; w < W; ++w) {
      const std::size_t k = systems.system_of(set, w);
      for (std::size_t i = 0; i < N; ++i) {
        B[i * W + w] = fields.B[k][i];
        H[i * W + w] = (fields.FB.empty() ? 0.0 : fields.FB[k][i]) + E[i * W + w];
      }
    }
  };
  write(0, light.E_direct, sol.radiosity, sol.irradiance);
  for (std::size_t t = 0; t < light.terms.size(); ++t) {
    SourceContribution c{light.terms[t].pointer, light.terms[t].name, {}, {}, {}};
    write(t + 1, light.terms[t].E, c.radiosity, c.irradiance);
    sol.contributions.push_back(std::move(c));
  }
}

}  // namespace lambert
