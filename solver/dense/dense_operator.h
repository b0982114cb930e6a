// The dense transport operator (solver/pipeline/transport_operator.h): F over every pair of patches,
// formed once (solver/dense/form_factors.h) and closed by a symmetric scaling. 8 N² bytes.
#pragma once

#include <memory>
#include <vector>

#include "solver/dense/form_factors.h"
#include "solver/occluder_planes.h"
#include "solver/pipeline/hemisphere.h"
#include "solver/pipeline/transport_operator.h"

namespace lambert {

class DenseOperator final : public TransportOperator {
 public:
  // The visibility scene over the patches (the fast BVH: link rays are estimates), the occluder
  // planes of the scene's input triangles and every patch's sides of them (stats.time_visibility_s).
  DenseOperator(const Scene& scene, std::vector<Patch> patches, SolveStats& stats);

  const std::vector<Patch>& patches() const override { return patches_; }
  const Visibility& visibility() const override { return *vis_; }
  std::vector<LobedPiece> lobed_pieces(const Scene& scene) const override { return lobed_patches(scene, patches_); }

  void classify_hemispheres(const SolveControl& control) override;
  const std::vector<Hemisphere>& hemispheres() const override { return hemisphere_; }
  bool next_round(const SpectralSystems& systems, const SolveControl& control) override;
  void close_rows(const SpectralSystems& systems, const SolveControl& control) override;
  // F depends on the geometry alone: the solve's one round without its systems.
  void build_geometric(const SolveControl& control) override;

  void apply(const std::vector<const double*>& V, const std::vector<double*>& FV) const override;
  BatchOperator among(std::span<const int> unknowns) const override;
  void apply_transpose(const double* w, double* out) const override;
  std::unique_ptr<PointGather> point_gather(const std::vector<const double*>& B) const override;
  void visit_factors(const FactorVisitor& visit) const override;  // row by row
  void report(SolveStats& stats) const override;

 private:
  Hemisphere probe(std::size_t i) const;
  void form(const SolveControl& control);
  void close();
  void measure_reciprocity();

  const Scene& scene_;
  std::vector<Patch> patches_;
  std::unique_ptr<Visibility> vis_;
  std::unique_ptr<OccluderPlanes> planes_;
  std::vector<OccluderPlanes::Sides> sides_;  // per patch, where the planes can serve
  std::unique_ptr<HemisphereProbe> hemisphere_probe_;
  std::vector<Hemisphere> hemisphere_;
  std::vector<char> probed_;  // per patch: its verdict is the probe's (classify_hemispheres)
  DenseFactors factors_;
  bool formed_ = false;
  double max_closure_error_ = 0, closure_residual_ = 0, max_reciprocity_error_ = 0, mean_reciprocity_error_ = 0;
};

}  // namespace lambert
