#include "solver/pipeline/pipeline.h"

#include <algorithm>

#include "solver/pipeline/certificate.h"
#include "solver/pipeline/direct_light.h"
#include "solver/pipeline/glare.h"
#include "solver/pipeline/hemisphere.h"
#include "solver/pipeline/outputs.h"
#include "solver/pipeline/probes.h"
#include "solver/pipeline/spectral_systems.h"
#include "solver/stopwatch.h"

namespace lambert {
namespace {

using Clock = std::chrono::steady_clock;

// The right-hand-side sets: the joint sources, then (output.per_source) each source alone.
std::vector<RhsSet> rhs_sets(const DirectLight& light) {
  std::vector<RhsSet> sets = {{&light.M, &light.E_direct}};
  for (const SourceTerms& t : light.terms) sets.push_back({t.M.empty() ? nullptr : &t.M, &t.E});
  return sets;
}

// The unknowns: patches that reflect or transmit at some wavelength and take part in the exchange.
std::vector<int> unknown_patches(const DirectLight& light, const std::vector<Hemisphere>& hemisphere, std::size_t N,
                                 std::size_t W) {
  std::vector<int> unknowns;
  auto nonzero = [](const double* v, std::size_t n) { return std::any_of(v, v + n, [](double r) { return r != 0; }); };
  for (std::size_t i = 0; i < N; ++i) {
    if (hemisphere[i] == Hemisphere::Enclosed) continue;
    if (nonzero(&light.rho[i * W], W) || (!light.tau.empty() && nonzero(&light.tau[i * W], W)))
      unknowns.push_back(static_cast<int>(i));
  }
  return unknowns;
}

void solve_round(SpectralSystems& systems, const TransportOperator& op, const Scene& scene,
                 const SolveControl& control) {
  if (systems.unknowns().empty()) return;
  for (RadiositySystem& sys : systems.systems()) sys.iterations = 0;
  solve_radiosity_systems(systems.unknowns().size(), op.among(systems.unknowns()), systems.systems(),
                          scene.solver.tolerance, scene.solver.max_iterations,
                          [&] { return control.cancel && control.cancel->load(std::memory_order_relaxed); },
                          &systems.transfer());
}

}  // namespace

Solution run_pipeline(const Scene& scene, TransportOperator& op, SolveStats stats, const SolveControl& control,
                      Clock::time_point t_start) {
  Solution sol;
  sol.grid = scene.grid;
  sol.warnings = scene.warnings;
  sol.stats = stats;
  sol.patches = op.patches();
  const std::size_t N = sol.patches.size(), W = scene.grid.size();
  auto report = [&](double f) { if (control.progress) control.progress(f); };
  sol.stats.patches = N;
  report(0.05);

  const std::vector<LobedPiece> lobed = op.lobed_pieces(scene);
  DirectLight light = direct_light(scene, sol.patches, lobed, op.visibility(), control);
  report(0.1);

  // ---- hemispheres, then the rounds: build (refine) F, close its rows, solve ----
  auto t0 = Clock::now();
  const bool transport = light.needs_transport() && N > 0;
  std::vector<Hemisphere> open(N, Hemisphere::Open);
  if (transport) {
    op.classify_hemispheres(control);
    // Nor does a patch inside a closed solid emit or reflect: a light sealed inside a box sends
    // nothing, and its power is not counted as emitted (nor as escaped) in the energy certificate.
    light.leave_out_enclosed(op.hemispheres(), W);
  }
  const std::vector<Hemisphere>& hemisphere = transport ? op.hemispheres() : open;
  SpectralSystems systems(light.rho, rhs_sets(light),
                          transport ? unknown_patches(light, hemisphere, N, W) : std::vector<int>{}, N, W, light.tau,
                          light.panes);
  double time_build = 0, time_solve = 0;
  if (transport) {
    time_build += seconds_since(t0);
    for (bool first = true;; first = false) {
      t0 = Clock::now();
      enter_stage(control, SolveStage::Links);
      if (!op.next_round(systems, control)) break;
      op.close_rows(systems, control);
      time_build += seconds_since(t0);
      t0 = Clock::now();
      enter_stage(control, SolveStage::Solve);
      systems.set_right_hand_sides(&op, first);
      solve_round(systems, op, scene, control);
      time_solve += seconds_since(t0);
    }
    time_build += seconds_since(t0);
    report_hemisphere_findings(sol, scene, hemisphere);
  }
  report(0.85);

  // ---- outputs: B and H = F B + E per set ----
  t0 = Clock::now();
  enter_stage(control, SolveStage::Solve);
  if (!systems.unknowns().empty())
    for (const RadiositySystem& sys : systems.systems()) {
      sol.stats.iterations = std::max(sol.stats.iterations, sys.iterations);
      sol.stats.residual = std::max(sol.stats.residual, sys.residual);
    }
  sol.stats.spectral_systems_solved = systems.unknowns().empty() ? 0 : static_cast<int>(systems.size());
  const SystemFields fields = system_fields(systems, transport ? &op : nullptr, scene.mode == SpectrumMode::Rgb);
  write_outputs(sol, systems, fields, light);
  sol.stats.time_form_factors_s = time_build;
  sol.stats.time_solve_s = time_solve + seconds_since(t0);
  report(0.9);

  t0 = Clock::now();
  enter_stage(control, SolveStage::Probes);
  solve_probes(sol, scene, light, systems, fields, transport ? &op : nullptr, op.visibility(), control);
  solve_glare(sol, scene, light, lobed, systems, fields, transport ? &op : nullptr, op.visibility());
  sol.stats.time_probes_s = seconds_since(t0);

  certify_energy(sol, scene, light, transport ? &op : nullptr);
  op.report(sol.stats);
  leave_out_enclosed(sol, hemisphere);
  sol.stats.time_total_s = seconds_since(t_start);
  report(1.0);
  return sol;
}

}  // namespace lambert
