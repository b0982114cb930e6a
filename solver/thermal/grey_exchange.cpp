#include "solver/thermal/grey_exchange.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "solver/linear_solve.h"
#include "solver/pipeline/spectral_systems.h"
#include "solver/radiosity.h"
#include "solver/thermal/radiant_temperature.h"

namespace lambert {
namespace {

// What one element (a patch, or a surface of a matrix) contributes: its area, reported surface (or
// −1 for an occluder's) and boundary condition; nullptr: it takes no part (inside a closed solid).
struct Element {
  double area_m2 = 0;
  int group = -1;
  const SurfaceThermal* boundary = nullptr;
};

// ρ and M of the radiosity equation (file comment).
double reflectance(const SurfaceThermal& b) { return b.temperature_K ? 1 - b.emissivity : 1.0; }
double emission(const SurfaceThermal& b) {
  return b.temperature_K ? b.emissivity * kStefanBoltzmann * std::pow(*b.temperature_K, 4) : *b.net_flux_W_m2;
}

// The uniform radiosity the systems are solved about: the area mean of σ T⁴ over the surfaces with a
// temperature (0 where there is none).
double reference_radiosity(const std::vector<Element>& elements) {
  double sum = 0, area = 0;
  for (const Element& e : elements)
    if (e.boundary && e.boundary->temperature_K) {
      sum += e.area_m2 * kStefanBoltzmann * std::pow(*e.boundary->temperature_K, 4);
      area += e.area_m2;
    }
  return area > 0 ? sum / area : 0.0;
}

// σ T⁴ = H + q/ε of a flux element; a negative value beyond round-off asks more than it receives.
double flux_temperature(const SurfaceThermal& b, double H, const std::string& surface) {
  const double sigma_T4 = H + *b.net_flux_W_m2 / b.emissivity;
  if (sigma_T4 < -1e-9 * std::max(H, std::abs(*b.net_flux_W_m2)))
    throw SolveError("surface \"" + surface + "\" cannot have a net flux of " + std::to_string(*b.net_flux_W_m2) +
                     " W/m²: it receives only " + std::to_string(H) + " W/m², and no temperature absorbs more (ε = " +
                     std::to_string(b.emissivity) + ")");
  return std::pow(std::max(0.0, sigma_T4) / kStefanBoltzmann, 0.25);
}

// Per element and per reported surface, from the radiosity B and irradiance H of every element.
void tally(const std::vector<Element>& elements, const std::vector<double>& B, const std::vector<double>& H,
           const std::vector<std::string>& names, const std::vector<std::string>& element_surface,
           GreyExchange& out, bool keep_elements) {
  const std::size_t S = names.size();
  out.surfaces.assign(S, ThermalValues{});
  std::vector<double> area(S, 0.0), T4_area(S, 0.0);
  std::vector<char> flux(S, 0);
  if (keep_elements) out.patches.assign(elements.size(), ThermalValues{});
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const Element& e = elements[i];
    if (!e.boundary) continue;
    ThermalValues v;
    v.radiosity_W_m2 = B[i];
    v.irradiance_W_m2 = H[i];
    v.net_flux_W_m2 = B[i] - H[i];
    v.net_W = v.net_flux_W_m2 * e.area_m2;
    if (e.boundary->net_flux_W_m2) v.temperature_K = flux_temperature(*e.boundary, H[i], element_surface[i]);
    out.net_sum_W += v.net_W;
    if (e.group < 0) out.occluders_net_W += v.net_W;
    if (e.group >= 0) {
      ThermalValues& s = out.surfaces[e.group];
      s.net_W += v.net_W;
      s.radiosity_W_m2 += B[i] * e.area_m2;
      s.irradiance_W_m2 += H[i] * e.area_m2;
      area[e.group] += e.area_m2;
      if (v.temperature_K) flux[e.group] = 1, T4_area[e.group] += std::pow(*v.temperature_K, 4) * e.area_m2;
    }
    if (keep_elements) out.patches[i] = v;
  }
  for (std::size_t I = 0; I < S; ++I) {
    if (!(area[I] > 0)) continue;
    ThermalValues& s = out.surfaces[I];
    s.net_flux_W_m2 = s.net_W / area[I];
    s.radiosity_W_m2 /= area[I];
    s.irradiance_W_m2 /= area[I];
    if (flux[I]) s.temperature_K = std::pow(T4_area[I] / area[I], 0.25);
  }
}

std::vector<Element> patch_elements(const Scene& scene, const TransportOperator& op, const SurfaceGroups& groups) {
  const std::vector<int> group = patch_groups(op, groups);
  const std::vector<Hemisphere>& hemisphere = op.hemispheres();
  std::vector<Element> elements(op.size());
  for (std::size_t i = 0; i < op.size(); ++i) {
    const Patch& p = op.patches()[i];
    const Surface& surface = scene.surfaces.at(p.surface);
    if (!surface.thermal)
      throw SolveError(surface.pointer + ": the radiant exchange needs \"thermal\" on every surface (\"" +
                       surface.name + "\" has none)");
    elements[i].area_m2 = p.area_m2;
    elements[i].group = group[i];
    if (hemisphere.empty() || hemisphere[i] != Hemisphere::Enclosed) elements[i].boundary = &*surface.thermal;
  }
  return elements;
}

// Net fluxes alone leave a closed enclosure's temperatures undetermined (B up to a constant).
void check_determined(const std::vector<Element>& elements, const std::vector<Hemisphere>& hemisphere) {
  bool closed = true;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (!elements[i].boundary) continue;
    if (elements[i].boundary->temperature_K) return;
    closed = closed && !hemisphere.empty() && hemisphere[i] == Hemisphere::Closed;
  }
  if (closed)
    throw SolveError("every surface has a net flux and none a temperature, in a closed enclosure: the temperatures "
                     "are then undetermined; give at least one surface \"temperature_K\"");
}

}  // namespace

GreyExchange grey_exchange(const Scene& scene, const TransportOperator& op, const SurfaceGroups& groups,
                           const SolveControl& control) {
  const std::size_t N = op.size();
  const std::vector<Element> elements = patch_elements(scene, op, groups);
  check_determined(elements, op.hemispheres());
  // B = c + x: the systems are solved for x (file comment of grey_exchange.h), with
  //   x_u − ρ_u Σ_j F_uj x_j = (M_u − c) + ρ_u c Σ_j F_uj
  // which is the spectral-systems stage's b = M' + ρ (E' + F x_known) with M' = M − c, E' = c F 1.
  const double c = reference_radiosity(elements);
  std::vector<double> rho(N, 0.0), M(N, 0.0), E(N, 0.0), ones(N, 0.0);
  std::vector<int> unknowns;
  for (std::size_t i = 0; i < N; ++i) {
    const SurfaceThermal* b = elements[i].boundary;
    if (!b) continue;
    rho[i] = reflectance(*b);
    M[i] = emission(*b) - c;
    ones[i] = 1;
    if (rho[i] != 0) unknowns.push_back(static_cast<int>(i));
  }
  op.apply({ones.data()}, {E.data()});
  for (double& e : E) e *= c;
  SpectralSystems systems(rho, {RhsSet{&M, &E}}, unknowns, N, 1);
  systems.set_right_hand_sides(&op, true);
  GreyExchange out;
  if (!unknowns.empty()) {
    solve_radiosity_systems(unknowns.size(), op.among(unknowns), systems.systems(), kThermalTolerance,
                            scene.solver.max_iterations,
                            [&] { return control.cancel && control.cancel->load(std::memory_order_relaxed); });
    out.iterations = systems.systems()[0].iterations;
    out.residual = systems.systems()[0].residual;
  }
  std::vector<double> B = systems.radiosity_vector(0, true), H(N, 0.0);
  for (std::size_t i = 0; i < N; ++i) B[i] = elements[i].boundary ? B[i] + c : 0.0;
  op.apply({B.data()}, {H.data()});
  std::vector<std::string> surface_of(N);
  for (std::size_t i = 0; i < N; ++i) surface_of[i] = scene.surfaces[op.patches()[i].surface].name;
  tally(elements, B, H, groups.names, surface_of, out, true);
  out.probes = radiant_probes(scene, op, groups, B, control);
  return out;
}

GreyExchange grey_exchange(const ViewFactorMatrix& m, const std::vector<SurfaceThermal>& boundary,
                           const SolveControl& control) {
  const std::size_t S = m.size();
  std::vector<Element> elements(S);
  for (std::size_t I = 0; I < S; ++I) elements[I] = {m.area_m2[I], static_cast<int>(I), &boundary.at(I)};
  std::vector<Hemisphere> closed(S);
  for (std::size_t I = 0; I < S; ++I)
    closed[I] = std::abs(1 - m.row_sums[I]) < 1e-6 ? Hemisphere::Closed : Hemisphere::Open;
  check_determined(elements, closed);
  const double c = reference_radiosity(elements);
  RadiositySystem sys;
  sys.rho.resize(S);
  sys.b.resize(S);
  for (std::size_t I = 0; I < S; ++I) {
    sys.rho[I] = reflectance(boundary[I]);
    sys.b[I] = emission(boundary[I]) - c + sys.rho[I] * c * m.row_sums[I];
  }
  sys.x = sys.b;
  std::vector<RadiositySystem> systems = {std::move(sys)};
  solve_radiosity_systems(m.F, S, systems, kThermalTolerance, 10000,
                          [&] { return control.cancel && control.cancel->load(std::memory_order_relaxed); });
  std::vector<double> B(S), H(S, 0.0);
  for (std::size_t I = 0; I < S; ++I) B[I] = systems[0].x[I] + c;
  for (std::size_t I = 0; I < S; ++I)
    for (std::size_t J = 0; J < S; ++J) H[I] += m.at(I, J) * B[J];
  GreyExchange out;
  out.iterations = systems[0].iterations;
  out.residual = systems[0].residual;
  tally(elements, B, H, m.names, m.names, out, false);
  return out;
}

}  // namespace lambert
