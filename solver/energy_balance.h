// The energy certificate shared by both solver paths: emitted = absorbed + escaped, in W integrated
// over the wavelength grid (REFERENCES R5; in an open scene the escaped part closes the balance).
#pragma once

#include <memory>
#include <vector>

#include "solver/light_model.h"
#include "solver/radiosity.h"

namespace lambert {

// Per patch and wavelength ([patch][λ] flat): reflectance, Lambertian emission, direct irradiance from
// all sources, and the part of it from sources of known flux (point-like, lobed emitters).
// `leak[i]` is the share of patch i's outgoing power that reaches no patch (1 − its row sum).
// `tau` ([patch][λ], empty: none) is the transmittance of panes' faces (solver/pipeline/panes.h): a
// face absorbs 1 − ρ − τ of what it receives, and what it transmits leaves the other face as
// radiosity, which the balance counts there (absorbed or escaped).
// Fills stats.emitted_W, absorbed_W, escaped_W and relative_imbalance.
void account_energy(const WavelengthGrid& grid, const std::vector<std::unique_ptr<LightModel>>& sources,
                    const std::vector<Patch>& patches, const std::vector<double>& rho, const std::vector<double>& M,
                    const std::vector<double>& E_direct, const std::vector<double>& E_known_flux,
                    const std::vector<double>& radiosity, const std::vector<double>& irradiance,
                    const std::vector<double>& leak, SolveStats& stats, const std::vector<double>& tau = {});

}  // namespace lambert
