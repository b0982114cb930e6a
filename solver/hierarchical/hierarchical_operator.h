// The hierarchical method's transport operator (solver/pipeline/transport_operator.h): hierarchical
// radiosity (Hanrahan, Salzman & Aupperle 1991, "A rapid hierarchical radiosity algorithm") with BF
// refinement and clusters (Smits, Arvo & Greenberg 1994), so that neither N² factors nor N² pairs are
// ever formed. The rooms of solver/hierarchical/, in the order a solve meets them:
//
//   discretise.h      the element forest (elements.h) at the patch size, the visibility scene
//   hierarchical_operator.cpp  hemispheres per leaf, then the clusters over the roots (clusters.h),
//                     and which pairs need no rays (plane_verdicts.h, solid_shafts.h)
//   rounds.cpp        the refine–solve rounds: the oracle's radiosity (oracle.h), the refinement
//                     (refiner.h: links, links.h), the final gather at the leaves (final_gather.h),
//                     the closure balance (closure.h)
//   hierarchy.h       F applied matrix-free: pull, gather, push, and its adjoint
//   point_gather.h    the gather at probe points
//   reciprocity.h     what the links miss of A_i F_ij = A_j F_ji
//
// The method's write-up is docs/METHOD.md ("The hierarchical operator").
#pragma once

#include <memory>
#include <vector>

#include "solver/exact_visibility.h"
#include "solver/hierarchical/closure.h"
#include "solver/hierarchical/hierarchy.h"
#include "solver/hierarchical/plane_verdicts.h"
#include "solver/hierarchical/refiner.h"
#include "solver/hierarchical/solid_shafts.h"
#include "solver/occluder_planes.h"
#include "solver/pipeline/transport_operator.h"
#include "solver/solids.h"

namespace lambert::hierarchical {

// Up to three refine–solve rounds: the first with the first-bounce radiosity plus an ambient
// estimate, then with the solved one.
inline constexpr int kRefineRounds = 3;

class HierarchicalOperator final : public TransportOperator {
 public:
  // `forest`: the scene's element forest (discretise.h). Builds the visibility scene over its roots,
  // the shafts and exact visibility over the input triangles, and the occluder planes
  // (stats.time_visibility_s).
  HierarchicalOperator(const Scene& scene, ElementForest forest, SolveStats& stats);

  const std::vector<Patch>& patches() const override { return patches_; }
  const Visibility& visibility() const override { return *vis_; }
  // One piece per root element: a lobed emitter's direct sources stay as many as the roots.
  std::vector<LobedPiece> lobed_pieces(const Scene& scene) const override;

  void classify_hemispheres(const SolveControl& control) override;
  const std::vector<Hemisphere>& hemispheres() const override { return hemisphere_; }
  bool next_round(const SpectralSystems& systems, const SolveControl& control) override;
  void close_rows(const SpectralSystems& systems, const SolveControl& control) override;
  void build_geometric(const SolveControl& control) override;

  void apply(const std::vector<const double*>& V, const std::vector<double*>& FV) const override;
  void apply_transpose(const double* w, double* out) const override;
  std::unique_ptr<PointGather> point_gather(const std::vector<const double*>& B) const override;
  void report(SolveStats& stats) const override;

 private:
  // The loop's rooms (rounds.cpp).
  void prepare_rounds(const SpectralSystems& systems);
  bool refine(const SpectralSystems& systems, bool first, OracleRadiosity& oracle, const SolveControl& control);
  bool refine_for(const OracleRadiosity& oracle, bool first, const SolveControl& control);
  // The oracle's budget ε per link (refiner.h): the accuracy times the mean radiosity, over kPowerShare.
  double oracle_epsilon(const OracleRadiosity& oracle) const;
  void close(const SolveControl& control);  // the balance toward this round's target (closure.h)
  void refine_first(const Refiner& refiner, const SolveControl& control);
  bool recheck(const Refiner& refiner);
  void store_links(bool first);
  // `oracle`: the radiosity the last round refined with, which says which leaf links are bright.
  void gather_at_leaves(const OracleRadiosity& oracle, const SolveControl& control);
  std::vector<double> largest_radiosity(const SpectralSystems& systems) const;

  const Scene& scene_;
  Hierarchy h_;
  std::vector<Patch> patches_;
  std::vector<Triangle> inputs_;  // the scene's input triangles (Element::input)
  std::unique_ptr<Visibility> vis_;
  std::unique_ptr<ExactVisibility> shafts_;
  std::unique_ptr<OccluderPlanes> occluder_planes_;
  std::unique_ptr<PlaneVerdicts> planes_;  // once the clusters are built
  OutwardSolids solids_;                   // of the input triangles (solids.h)
  std::unique_ptr<SolidShafts> solid_shafts_;  // once the clusters are built
  std::vector<Hemisphere> hemisphere_;

  // The refine–solve loop's state (rounds.cpp).
  struct Rounds {
    int round = 0;          // the next refinement round
    bool started = false, done = false, gathered = false;
    std::vector<char> emits, shoots;  // per leaf: emits at some wavelength; emits or reflects
    double total_area = 0;  // of the leaves that are not enclosed
    double final_target = 0, oracle_target = 0;
    std::vector<double> sends;  // what each leaf sends, for the next balance
    bool final_balance = false;  // whether the next balance is the final one
    ExchangeCache exchange;
    HiddenRoom hidden_room;
    BalanceState balance;
  } rounds_;
  tbb::enumerable_thread_specific<LinkBatch> found_;

  // What the method reports (report()).
  SolveStats::Hierarchical own_;
  std::uint64_t own_links_clear_ = 0, own_link_rays_ = 0;
  double max_closure_error_ = 0, closure_residual_ = 0, max_reciprocity_error_ = 0, mean_reciprocity_error_ = 0;
};

}  // namespace lambert::hierarchical
