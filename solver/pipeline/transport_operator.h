// The interface both methods implement (pbrt-v4's ImageTileIntegrator / Li split, Mitsuba 3's
// SamplingIntegrator): the pipeline (solver/pipeline/pipeline.h) runs the solve once, and a method
// differs only in the transport operator F it hands it,
//
//   H_i = Σ_j F_ij B_j + E_i^direct        (F: what patch i gathers of patch j's radiosity)
//
// dense (solver/dense/: every patch pair, N² factors) or hierarchical (solver/hierarchical/: links
// between elements and clusters). An operator is made by its method's discretise step, which meshes
// the scene into its patches and builds the visibility scene the sources are shadowed in.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "solver/linear_solve.h"
#include "solver/pipeline/direct_light.h"
#include "solver/radiosity.h"
#include "solver/receiver.h"
#include "solver/visibility.h"

namespace lambert {

class SpectralSystems;

// The irradiance at points from every patch's radiosity, for K radiosity vectors at once (one per
// spectral system); made by TransportOperator::point_gather for one set of vectors. Called from many
// threads at once.
class PointGather {
 public:
  virtual ~PointGather() = default;
  // E[k] = Σ_j (the share of patch j's exitance that reaches the receiver, visible part) B_k[j].
  virtual void gather_at_point(const Receiver& receiver, double* E) const = 0;
  // Exact visible-part evaluations so far (stats.exact_visibility_evaluations).
  virtual std::uint64_t exact_evaluations() const { return 0; }
};

class TransportOperator {
 public:
  virtual ~TransportOperator() = default;

  // ---- the discretisation (made by the method's discretise step) ----
  virtual const std::vector<Patch>& patches() const = 0;
  std::size_t size() const { return patches().size(); }
  // The visibility scene the direct light is shadowed in.
  virtual const Visibility& visibility() const = 0;
  // The pieces of Phong-lobed emitters that become direct sources (direct_light.h).
  virtual std::vector<LobedPiece> lobed_pieces(const Scene& scene) const = 0;

  // ---- building the operator ----
  // Each patch's hemisphere (solver/pipeline/hemisphere.h), before any factor or link: in
  // particular every Hemisphere::Enclosed, which takes no part in the exchange. The build may
  // settle other verdicts later (hemispheres() is final once the rounds are done).
  virtual void classify_hemispheres(const SolveControl& control) = 0;
  virtual const std::vector<Hemisphere>& hemispheres() const = 0;
  // The refine–solve rounds: (re)builds F for the next solve from the systems' current radiosity
  // (their right-hand sides before the first solve). Returns false when the last solve stands.
  virtual bool next_round(const SpectralSystems& systems, const SolveControl& control) = 0;
  // The closure of this round's F: rows of closed patches held at 1 (dense: a symmetric scaling
  // that keeps reciprocity; hierarchical: rows and columns balanced, Sinkhorn–Knopp).
  virtual void close_rows(const SpectralSystems& systems, const SolveControl& control) = 0;

  // ---- building it for the geometry alone (view factors and radiant exchange, solver/thermal/) ----
  // F as if every patch sent unit radiosity: the hemispheres classified, F built (a refining method
  // refines as it would for uniform radiosity on every patch) and the closed rows balanced, without
  // any spectral system. Afterwards hemispheres(), apply(), among(), apply_transpose(),
  // point_gather() and report() serve as they do after a solve's rounds.
  virtual void build_geometric(const SolveControl& control) = 0;

  // ---- applying it ----
  // FV[k] = F V[k] for K vectors over all patches.
  virtual void apply(const std::vector<const double*>& V, const std::vector<double*>& FV) const = 0;
  // The same restricted to the unknowns (F's rows and columns at `unknowns`, vectors over them).
  // By default embedded in all patches (zero elsewhere), applied, and read back.
  virtual BatchOperator among(std::span<const int> unknowns) const;
  // out = Fᵀ w over all patches: in the energy certificate, Σ_i A_i F_ij / A_j is the share of patch
  // j's power that some patch gathers.
  virtual void apply_transpose(const double* w, double* out) const = 0;
  // Gathering at points from the radiosity vectors B (all patches each).
  virtual std::unique_ptr<PointGather> point_gather(const std::vector<const double*>& B) const = 0;
  // Every factor F_ij that is not zero, once, as visit(i, j, F_ij), in no promised order (the patch-to-
  // patch matrix of `lambert viewfactors --patches`). By default F's columns from apply() on unit
  // vectors, 64 at a time (N applications of F in all: small scenes); a method that stores F
  // overrides it.
  using FactorVisitor = std::function<void(std::size_t i, std::size_t j, double F_ij)>;
  virtual void visit_factors(const FactorVisitor& visit) const;

  // The method's stats (links, rays, closure, reciprocity, its own counters).
  virtual void report(SolveStats& stats) const = 0;
};

}  // namespace lambert
