// The radiosity the refinement's oracle (refiner.h) weighs each link's error bound with: per leaf the
// largest |B| over the spectral systems, pulled up to elements (area mean) and clusters (max).
#pragma once

#include <vector>

#include "solver/hierarchical/hierarchy.h"
#include "solver/pipeline/spectral_systems.h"
#include "solver/visible_fraction.h"

namespace lambert::hierarchical {

struct OracleRadiosity {
  std::vector<double> leaf_B;  // per leaf
  double power = 0;            // Σ A B over the leaves that are not enclosed
};

// From the systems' current radiosity (before the first solve, the first bounce M + ρ E). With
// `with_ambient` (the first round), unlit reflectors are given ρ times the mean interreflected
// irradiance they will receive. `shoots` per leaf: it emits or reflects at some wavelength.
OracleRadiosity oracle_radiosity(const Hierarchy& h, const SpectralSystems& systems,
                                 const std::vector<Hemisphere>& hemisphere, const std::vector<char>& shoots,
                                 bool with_ambient);

struct OracleValues {
  std::vector<double> element_B;  // area mean of the leaves below
  std::vector<double> cluster_B;  // the largest leaf below
};
OracleValues oracle_values(const Hierarchy& h, const std::vector<double>& leaf_B);

}  // namespace lambert::hierarchical
