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
// Two (set, wavelength) pairs share a system where ρ, M and E over the unknowns and B over the known
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
  SpectralSystems(const std::vector<double>& rho, std::vector<RhsSet> sets, std::vector<int> unknowns,
                  std::size_t patches, std::size_t wavelengths);

  std::size_t size() const { return systems_.size(); }
  std::vector<RadiositySystem>& systems() { return systems_; }
  const std::vector<RadiositySystem>& systems() const { return systems_; }
  const std::vector<int>& unknowns() const { return unknowns_; }
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

  const std::vector<double>& rho_;
  std::vector<RhsSet> sets_;
  std::vector<int> unknowns_, known_;
  std::vector<int> unknown_of_;  // per patch: its index among the unknowns, or −1
  std::size_t N_, W_;
  std::vector<RadiositySystem> systems_;
  std::vector<Representative> representative_;  // per system: the first (set, λ) it serves
  std::vector<std::size_t> system_of_;           // per (set, λ)
};

}  // namespace lambert
