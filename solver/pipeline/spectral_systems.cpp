#include "solver/pipeline/spectral_systems.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <unordered_map>

#include "solver/pipeline/transport_operator.h"

namespace lambert {

SpectralSystems::SpectralSystems(const std::vector<double>& rho, std::vector<RhsSet> sets, std::vector<int> unknowns,
                                 std::size_t patches, std::size_t wavelengths, const std::vector<double>& tau,
                                 const PaneTransfer& panes)
    : rho_(rho), tau_(tau), panes_(panes), sets_(std::move(sets)), unknowns_(std::move(unknowns)), N_(patches),
      W_(wavelengths) {
  unknown_of_.assign(N_, -1);
  for (std::size_t r = 0; r < unknowns_.size(); ++r) unknown_of_[unknowns_[r]] = static_cast<int>(r);
  for (std::size_t i = 0; i < N_; ++i)
    if (unknown_of_[i] < 0) known_.push_back(static_cast<int>(i));
  if (!panes_.empty()) {
    pane_row_of_.assign(N_, -1);
    for (std::size_t r = 0; r < panes_.row.size(); ++r) {
      pane_row_of_[panes_.row[r]] = static_cast<int>(r);
      if (unknown_of_[panes_.row[r]] < 0) continue;
      transfer_.row.push_back(unknown_of_[panes_.row[r]]);
      for (std::size_t e = panes_.start[r]; e < panes_.start[r + 1]; ++e)
        if (unknown_of_[panes_.col[e]] >= 0) transfer_.col.push_back(unknown_of_[panes_.col[e]]), transfer_.weight.push_back(panes_.weight[e]);
      transfer_.start.push_back(transfer_.col.size());
    }
  }
  system_of_.resize(sets_.size() * W_);
  // Candidates by a hash of everything that defines a system, then compared value by value against
  // the system's first (set, λ): no copy of the keys (N doubles each) is kept.
  std::unordered_multimap<std::size_t, std::size_t> by_hash;
  for (std::size_t set = 0; set < sets_.size(); ++set)
    for (std::size_t w = 0; w < W_; ++w) {
      const std::size_t h = hash(set, w);
      std::size_t found = systems_.size();
      for (auto [it, end] = by_hash.equal_range(h); it != end; ++it)
        if (same_system(set, w, representative_[it->second])) {
          found = it->second;
          break;
        }
      if (found == systems_.size()) {
        by_hash.emplace(h, found);
        representative_.push_back({set, w});
        RadiositySystem& sys = systems_.emplace_back();
        const std::size_t n = unknowns_.size();
        sys.rho.resize(n);
        sys.b.resize(n);
        if (!transfer_.empty()) sys.tau.resize(n);
        for (std::size_t r = 0; r < n; ++r) {
          const std::size_t i = unknowns_[r];
          sys.rho[r] = rho_[i * W_ + w];
          if (!sys.tau.empty()) sys.tau[r] = transmittance(w, i);
          sys.b[r] = rhs(set, w, i, nullptr);
        }
        sys.x = sys.b;
      }
      system_of_[set * W_ + w] = found;
    }
}

double SpectralSystems::known_radiosity(std::size_t set, std::size_t w, std::size_t i) const {
  return emission(set, w, i) + rho_[i * W_ + w] * direct(set, w, i);
}

double SpectralSystems::twin_irradiance(std::size_t set, std::size_t w, std::size_t i, const double* gathered) const {
  if (pane_row_of_.empty() || pane_row_of_[i] < 0) return 0;
  const std::size_t r = static_cast<std::size_t>(pane_row_of_[i]);
  double H = 0;
  for (std::size_t e = panes_.start[r]; e < panes_.start[r + 1]; ++e) {
    const std::size_t j = static_cast<std::size_t>(panes_.col[e]);
    const double sources = panes_.rays_carry_direct[r] ? 0.0 : direct(set, w, j);
    H += panes_.weight[e] * (sources + (gathered ? gathered[j] : 0.0));
  }
  return H;
}

double SpectralSystems::rhs(std::size_t set, std::size_t w, std::size_t i, const double* gathered) const {
  const double own = direct(set, w, i) + (gathered ? gathered[i] : 0.0);
  const double tau = transmittance(w, i);
  return emission(set, w, i) + rho_[i * W_ + w] * own + (tau != 0 ? tau * twin_irradiance(set, w, i, gathered) : 0.0);
}

std::size_t SpectralSystems::hash(std::size_t set, std::size_t w) const {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the values' bits (0 and −0 alike)
  auto add = [&](double v) {
    const std::uint64_t bits = v == 0 ? 0 : std::bit_cast<std::uint64_t>(v);
    h = (h ^ bits) * 1099511628211ull;
  };
  for (int i : unknowns_) {
    add(rho_[i * W_ + w]);
    add(transmittance(w, i));
    add(emission(set, w, i));
    add(direct(set, w, i));
  }
  for (int j : known_) add(known_radiosity(set, w, j));
  return static_cast<std::size_t>(h);
}

bool SpectralSystems::same_system(std::size_t set, std::size_t w, const Representative& r) const {
  for (int i : unknowns_)
    if (rho_[i * W_ + w] != rho_[i * W_ + r.w] || transmittance(w, i) != transmittance(r.w, i) ||
        emission(set, w, i) != emission(r.set, r.w, i) ||
        direct(set, w, i) != direct(r.set, r.w, i))
      return false;
  for (int j : known_)
    if (known_radiosity(set, w, j) != known_radiosity(r.set, r.w, j)) return false;
  return true;
}

double SpectralSystems::radiosity(std::size_t k, std::size_t i) const {
  const int r = unknown_of_[i];
  return r >= 0 ? systems_[k].x[r] : known_radiosity(representative_[k].set, representative_[k].w, i);
}

std::vector<double> SpectralSystems::radiosity_vector(std::size_t k, bool keep_sign) const {
  std::vector<double> B(N_);
  const Representative& rep = representative_[k];
  for (std::size_t i = 0; i < N_; ++i) {
    const int r = unknown_of_[i];
    B[i] = r < 0 ? known_radiosity(rep.set, rep.w, i) : keep_sign ? systems_[k].x[r] : std::max(0.0, systems_[k].x[r]);
  }
  return B;
}

void SpectralSystems::set_right_hand_sides(const TransportOperator* op, bool first_guess) {
  const std::size_t K = systems_.size(), n = unknowns_.size();
  // F B_known per system, where some known patch sends something.
  std::vector<std::vector<double>> fold(K);
  if (op) {
    std::vector<std::vector<double>> known(K);
    std::vector<const double*> V;
    std::vector<double*> FV;
    for (std::size_t k = 0; k < K; ++k) {
      const Representative& rep = representative_[k];
      bool any = false;
      for (int j : known_) any = any || known_radiosity(rep.set, rep.w, j) != 0;
      if (!any) continue;
      known[k].assign(N_, 0.0);
      for (int j : known_) known[k][j] = known_radiosity(rep.set, rep.w, j);
      fold[k].assign(N_, 0.0);
      V.push_back(known[k].data());
      FV.push_back(fold[k].data());
    }
    if (!V.empty()) op->apply(V, FV);
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, K, 1), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      RadiositySystem& sys = systems_[k];
      const Representative& rep = representative_[k];
      const double* gathered = fold[k].empty() ? nullptr : fold[k].data();
      for (std::size_t r = 0; r < n; ++r) sys.b[r] = rhs(rep.set, rep.w, unknowns_[r], gathered);
      if (first_guess) sys.x = sys.b;
    }
  });
}

}  // namespace lambert
