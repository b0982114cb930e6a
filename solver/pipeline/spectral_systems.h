// The spectral-systems stage of the solve: the radiosity equation B = M + ρ (F B + E) at every
// wavelength of every right-hand-side set (the joint sources, then with output.per_source each source
// alone), grouped into the distinct linear systems that are actually solved.
//
// Unknowns are the patches that reflect at some wavelength (ρ ≠ 0: rgb channel values are signed)
// and exchange light with the scene. The others are known: a patch black at every wavelength keeps
// B = M + ρ E = M, and enters the unknowns' right-hand sides through F; a patch inside a closed
// solid (ρ = M = 0 there) keeps B = 0. Solved for, a bright known patch would set the scale of the
// solver's relative residual and leave the rest unconverged.
//
//   B_u − ρ_u Σ_{v unknown} F_uv B_v = M_u + ρ_u (E_u + Σ_{j known} F_uj B_j)
//
// Faces of diffusely transmitting panes (panes.h) add τ_u Σ_v P_uv H_v, what they pass on of the other
// face's irradiance H = F B + E, on both sides (the twin faces are unknowns too).
//
// Two (set, wavelength) pairs share a system where ρ, τ, M and E over the unknowns and B over the known
// patches are the same: grey scenes solve one system for all wavelengths, and a per-source set whose
// source lights everything the joint one does shares the joint system.
#pragma once

#include <cstddef>
#include <vector>

#include "solver/linear_solve.h"

namespace lambert {

class TransportOperator;

// One right-hand-side set: per patch and wavelength ([patch][λ] flat) the Lambertian emission M
// (nullptr: none) and the direct irradiance E.
struct RhsSet {
  const std::vector<double>* M = nullptr;
  const std::vector<double>* E = nullptr;
};

class SpectralSystems {
 public:
  // rho: [patch][λ]; `unknowns` ascending. Each system starts with b = x = M + ρ E (the first
  // bounce, without what known patches send: F is not formed yet).
  // tau ([patch][λ], empty: no pane) and `panes` (over all patches) from DirectLight.
  SpectralSystems(const std::vector<double>& rho, std::vector<RhsSet> sets, std::vector<int> unknowns,
                  std::size_t patches, std::size_t wavelengths, const std::vector<double>& tau = {},
                  const PaneTransfer& panes = {});

  std::size_t size() const { return systems_.size(); }
  std::vector<RadiositySystem>& systems() { return systems_; }
  const std::vector<RadiositySystem>& systems() const { return systems_; }
  const std::vector<int>& unknowns() const { return unknowns_; }
  // P among the unknowns (rows and columns are indices into unknowns()), for the linear solve.
  const PaneTransfer& transfer() const { return transfer_; }
  std::size_t patches() const { return N_; }
  std::size_t sets() const { return sets_.size(); }
  std::size_t system_of(std::size_t set, std::size_t w) const { return system_of_[set * W_ + w]; }

  // Patch i in system k: its radiosity (x for an unknown, M + ρ E for a known patch) and reflectance.
  double radiosity(std::size_t k, std::size_t i) const;
  double reflectance(std::size_t k, std::size_t i) const { return rho_[i * W_ + representative_[k].w]; }
  // Patch i's Lambertian emission in system k (the same for every (set, λ) the system serves).
  double emission(std::size_t k, std::size_t i) const {
    return emission(representative_[k].set, representative_[k].w, i);
  }
  // System k's radiosity over all patches. A spectral radiosity is ≥ 0, so a negative x is round-off
  // and is dropped; an rgb channel value may be negative (solver/rgb_model.h) and is kept (keep_sign).
  std::vector<double> radiosity_vector(std::size_t k, bool keep_sign) const;

  // b = M + ρ (E + F B_known) over the unknowns, F from `op` (nullptr, or no known patch sends
  // anything: F B_known = 0). With `first_guess`, x = b as well (the first bounce).
  void set_right_hand_sides(const TransportOperator* op, bool first_guess);

 private:
  struct Representative {
    std::size_t set = 0, w = 0;
  };
  double known_radiosity(std::size_t set, std::size_t w, std::size_t i) const;
  bool same_system(std::size_t set, std::size_t w, const Representative& r) const;
  std::size_t hash(std::size_t set, std::size_t w) const;
  double emission(std::size_t set, std::size_t w, std::size_t i) const {
    return sets_[set].M ? (*sets_[set].M)[i * W_ + w] : 0.0;
  }
  double direct(std::size_t set, std::size_t w, std::size_t i) const { return (*sets_[set].E)[i * W_ + w]; }
  double transmittance(std::size_t w, std::size_t i) const { return tau_.empty() ? 0.0 : tau_[i * W_ + w]; }
  // Σ_v P_iv (E_v + G_v): the other face's irradiance as far as it is known before the solve (G: F
  // B_known over all patches, nullptr: none); 0 for a patch that is no pane face.
  double twin_irradiance(std::size_t set, std::size_t w, std::size_t i, const double* gathered) const;
  // b of unknown i: M + ρ (E + G) + τ P (E + G).
  double rhs(std::size_t set, std::size_t w, std::size_t i, const double* gathered) const;

  const std::vector<double>& rho_;
  const std::vector<double>& tau_;
  const PaneTransfer& panes_;      // over all patches
  std::vector<int> pane_row_of_;   // per patch: its row of panes_, or −1 (empty without panes)
  PaneTransfer transfer_;          // among the unknowns
  std::vector<RhsSet> sets_;
  std::vector<int> unknowns_, known_;
  std::vector<int> unknown_of_;  // per patch: its index among the unknowns, or −1
  std::size_t N_, W_;
  std::vector<RadiositySystem> systems_;
  std::vector<Representative> representative_;  // per system: the first (set, λ) it serves
  std::vector<std::size_t> system_of_;           // per (set, λ)
};

}  // namespace lambert
