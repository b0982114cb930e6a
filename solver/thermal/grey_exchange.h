// Radiant exchange between grey, diffuse surfaces (total radiation; Siegel & Howell, the net-radiation
// method): the radiosity equation of the light solve with one "wavelength",
//
//   B_i = M_i + ρ_i H_i,   H_i = Σ_j F_ij B_j
//   a surface with a temperature T:   M = ε σ T⁴,  ρ = 1 − ε
//   a surface with a net flux q:      M = q,       ρ = 1          (B − H = q)
//
// and per patch the net flux q_i = B_i − H_i = ε_i (σ T_i⁴ − H_i): emitted minus absorbed, positive on
// a surface that loses heat. A flux surface's temperature follows from σ T⁴ = H + q/ε. Openings of an
// enclosure see black space at 0 K.
//
// Two levels:
// - on a transport operator (every patch its own radiosity): the operator's apply() and the
//   spectral-systems stage (solver/pipeline/spectral_systems.h) with one system, solved by lockstep
//   GMRES (solver/linear_solve.h); probes gather from the patches (ISO 7726 radiant temperatures).
// - on a surface matrix F_IJ (view_factors.h), the classic net-radiation method: each surface's
//   radiosity uniform over it. Exact where every patch of a surface sees the rest alike (concentric
//   spheres); elsewhere it differs from the patch solution by how much the radiosity varies over
//   each surface (a few tenths of a per cent in a room with two hot walls, docs/BENCHMARKS.md). This
//   is what a saved factor file can give for new temperatures in milliseconds.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "solver/pipeline/transport_operator.h"
#include "solver/thermal/view_factors.h"

namespace lambert {

inline constexpr double kStefanBoltzmann = 5.670374419e-8;  // σ, W m^-2 K^-4 (CODATA 2018, exact)

// The systems are solved to a relative residual of kThermalTolerance (of the temperatures' spread:
// the radiosity is solved as its difference from a uniform σ T⁴, so an isothermal enclosure is
// solved exactly and the net fluxes, differences of nearly equal radiosities, keep their digits).
inline constexpr double kThermalTolerance = 1e-6;

struct ThermalValues {
  double net_flux_W_m2 = 0;   // emitted − absorbed, per m²
  double net_W = 0;
  double radiosity_W_m2 = 0;  // B (area mean over a surface)
  double irradiance_W_m2 = 0; // H
  std::optional<double> temperature_K;  // a flux surface's (over a surface: (Σ A_i T_i⁴ / A)^¼)
};

// ISO 7726 at a probe point, from the radiosity it sees: the mean radiant temperature (a small sphere:
// σ T_mr⁴ = Σ_j (Ω_j / 4π) B_j; with black surfaces Σ_I F_p→I T_I⁴) and the plane radiant temperature
// (a plane facing the probe's normal: σ T_pr⁴ = Σ_j F_p→j B_j), and the sphere's view factors to every
// reported surface (its solid angle of the surface / 4π).
struct RadiantPoint {
  double mean_radiant_temperature_K = 0;
  double plane_radiant_temperature_K = 0;  // a planar or vertical probe's (0 for the others)
  std::vector<double> view_factors;  // per reported surface
};

struct GreyExchange {
  std::vector<ThermalValues> surfaces;  // per reported surface
  std::vector<ThermalValues> patches;   // per patch (operator level)
  std::vector<std::vector<RadiantPoint>> probes;  // per scene probe, per point (operator level)
  double net_sum_W = 0;        // Σ net_W over every patch (or surface): 0 in a closed enclosure
  double occluders_net_W = 0;  // of which the occluders' (surfaces not reported)
  int iterations = 0;
  double residual = 0;
};

// On the geometric operator of `scene` (GeometricOperator::scene(): every surface with `thermal`).
// Throws SolveError for a surface without `thermal`, for net fluxes alone in a closed enclosure
// (temperatures undetermined) and for a flux no temperature can give (σ T⁴ < 0).
GreyExchange grey_exchange(const Scene& scene, const TransportOperator& op, const SurfaceGroups& groups,
                           const SolveControl& control);

// On a surface matrix, each surface uniform (boundary: per surface of m).
GreyExchange grey_exchange(const ViewFactorMatrix& m, const std::vector<SurfaceThermal>& boundary,
                           const SolveControl& control);

// Hottel's total exchange factors ("script F", View3D's emit=1): the share of surface I's black-body
// emission, ε_I A_I σ T⁴ per unit ε, that surface J absorbs after any number of diffuse reflections,
// A_I ℱ_IJ = Σ_{j∈J} A_j ε_j H_j^(I) with H^(I) the irradiance when only I emits (M = ε on I's
// patches, 0 elsewhere; one system per surface, solved in lockstep on the operator). Row sums are ε_I
// in a closed enclosure; A_I ℱ_IJ = A_J ℱ_JI. `emissivity` per scene surface; occluders absorb what
// reaches them (black). S × S row-major.
std::vector<double> total_exchange_factors(const TransportOperator& op, const SurfaceGroups& groups,
                                           const ViewFactorMatrix& m, const std::vector<double>& emissivity,
                                           const SolveControl& control);

}  // namespace lambert
