#include "solver/dense/dense_operator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "solver/dense/point_gather.h"

namespace lambert {

DenseOperator::DenseOperator(const Scene& scene, std::vector<Patch> patches, SolveStats& stats)
    : scene_(scene), patches_(std::move(patches)) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t N = patches_.size();
  std::vector<Triangle> occluders(N);
  for (std::size_t i = 0; i < N; ++i) occluders[i] = patches_[i].triangle;
  vis_ = std::make_unique<Visibility>(occluders, Visibility::Estimates::fast);  // link rays in the fast BVH
  // Pairs that no occluder plane separates need no rays, links and probes alike (occluder_planes.h).
  std::vector<Point3> probe_points;  // probes in the air are behind planes that nothing else is behind
  for (const Probe& probe : scene.probes) probe_points.insert(probe_points.end(), probe.points.begin(), probe.points.end());
  planes_ = std::make_unique<OccluderPlanes>(input_triangles(scene), probe_points);
  const std::vector<char> two_sided = input_two_sided(scene);
  sides_.resize(planes_->usable() ? N : 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sides_.size(), 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) sides_[i] = planes_->sides(patches_[i].triangle.v);
  });
  // The hemisphere probe on the patches themselves.
  std::vector<Vector3> normals(N);
  std::vector<char> patch_two_sided(N, 0);
  for (std::size_t i = 0; i < N; ++i) {
    normals[i] = patches_[i].normal;
    const int input = patches_[i].input_triangle;
    patch_two_sided[i] = input >= 0 && static_cast<std::size_t>(input) < two_sided.size() && two_sided[input];
  }
  hemisphere_probe_ = std::make_unique<HemisphereProbe>(*vis_, std::move(normals), std::move(patch_two_sided));
  hemisphere_.assign(N, Hemisphere::Open);
  stats.time_visibility_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Hemisphere DenseOperator::probe(std::size_t i) const {
  return hemisphere_probe_->classify(patches_[i].triangle, patches_[i].normal, i, kHemisphereRays);
}

// The probe first for every patch that may see a back face (all but those in front of every
// occluder plane): a patch inside a closed solid (every ray meets a back face, e.g. a floor under a
// box without a bottom) exchanges nothing with the scene, so its row and column are not formed.
void DenseOperator::classify_hemispheres(const SolveControl& control) {
  const std::size_t N = patches_.size();
  probed_.assign(N, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      if (sides_.empty() || !planes_->in_front_of_all(sides_[i])) hemisphere_[i] = probe(i), probed_[i] = 1;
  });
  if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw SolveCancelled();
}

// One round: F is formed once. The patches not probed yet are settled with it: one whose links were
// all decided without rays has an exact row (the kernel), and lying in front of every occluder plane
// it sees no back face, so its row sum tells whether its hemisphere is closed (to 1e-3, finer than
// the probe's rays resolve) and no probe is needed; the others are probed.
bool DenseOperator::next_round(const SpectralSystems&, const SolveControl& control) {
  if (formed_) return false;
  form(control);
  return true;
}

void DenseOperator::form(const SolveControl& control) {
  formed_ = true;
  const std::size_t N = patches_.size();
  factors_ = form_dense_factors(patches_, *vis_, *planes_, sides_, hemisphere_, control);
  const std::vector<double>& F = factors_.F;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (probed_[i]) continue;
      hemisphere_[i] = factors_.row_traced[i].load(std::memory_order_relaxed)
                           ? probe(i)
                           : hemisphere_from_coverage(std::accumulate(&F[i * N], &F[i * N] + N, 0.0));
    }
  });
}

// Closure: a patch whose hemisphere is closed (no probe ray escapes or hits the back of a surface)
// must have Σ_j F_ij = 1; the kernel is exact, so any deficit or excess comes from the visible-
// fraction estimates of partly occluded links. A symmetric diagonal scaling G' = D G D
// (symmetric_row_scaling: Newton steps, or Sinkhorn sweeps where those stall; D = 1 on open patches)
// restores it, keeping reciprocity A_i F_ij = A_j F_ji exact while closing every closed row: energy
// is conserved and the furnace gives B = M/(1 − ρ) exactly. The size of the correction is reported.
void DenseOperator::close_rows(const SpectralSystems&, const SolveControl&) { close(); }

void DenseOperator::build_geometric(const SolveControl& control) {
  classify_hemispheres(control);
  form(control);
  close();
}

void DenseOperator::close() {
  const std::size_t N = patches_.size();
  std::vector<double>& F = factors_.F;
  std::vector<char> closing(N, 0);
  std::vector<double> area(N), row_sum(N, 0.0);
  for (std::size_t i = 0; i < N; ++i) closing[i] = hemisphere_[i] == Hemisphere::Closed, area[i] = patches_[i].area_m2;
  const RowScaling scaling = symmetric_row_scaling(F, N, closing, area, 1e-13, 500);
  const std::vector<double>& d = scaling.d;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 32), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      double* row = &F[i * N];
      double sum = 0;
      for (std::size_t j = 0; j < N; ++j) sum += row[j] *= d[i] * d[j];
      row_sum[i] = sum;
    }
  });
  max_closure_error_ = scaling.initial_deviation;
  closure_residual_ = 0;
  for (std::size_t i = 0; i < N; ++i)
    if (closing[i]) closure_residual_ = std::max(closure_residual_, std::abs(1 - row_sum[i]));
  measure_reciprocity();
}

void DenseOperator::measure_reciprocity() {
  const std::size_t N = patches_.size();
  const std::vector<double>& F = factors_.F;
  double worst = 0, differ = 0, exchanged = 0;
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = i + 1; j < N; ++j) {
      const double gij = patches_[i].area_m2 * F[i * N + j], gji = patches_[j].area_m2 * F[j * N + i];
      const double big = std::max(gij, gji);
      if (big > 1e-9 * std::min(patches_[i].area_m2, patches_[j].area_m2)) {
        worst = std::max(worst, std::abs(gij - gji) / big);
        differ += std::abs(gij - gji);
        exchanged += big;
      }
    }
  max_reciprocity_error_ = worst;
  mean_reciprocity_error_ = exchanged > 0 ? differ / exchanged : 0;
}

void DenseOperator::apply(const std::vector<const double*>& V, const std::vector<double*>& FV) const {
  multiply_dense(factors_.F, patches_.size(), V, FV);
}

// F restricted to the unknowns: a copy, made once, where some patches are not unknowns.
BatchOperator DenseOperator::among(std::span<const int> unknowns) const {
  const std::size_t N = patches_.size(), n = unknowns.size();
  if (n == N) return [this](const std::vector<const double*>& V, const std::vector<double*>& FV) { apply(V, FV); };
  auto compact = std::make_shared<std::vector<double>>(n * n);
  const std::vector<double>& F = factors_.F;
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t c = 0; c < n; ++c) (*compact)[r * n + c] = F[unknowns[r] * N + unknowns[c]];
  return [compact, n](const std::vector<const double*>& V, const std::vector<double*>& FV) {
    multiply_dense(*compact, n, V, FV);
  };
}

// Column blocks, each summed over the rows in order: the same bits however the blocks are shared.
void DenseOperator::apply_transpose(const double* w, double* out) const {
  const std::size_t N = patches_.size();
  const std::vector<double>& F = factors_.F;
  constexpr std::size_t kColumns = 256;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (N + kColumns - 1) / kColumns, 1), [&](const auto& range) {
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      const std::size_t j0 = b * kColumns, j1 = std::min(N, j0 + kColumns);
      std::fill(out + j0, out + j1, 0.0);
      for (std::size_t i = 0; i < N; ++i) {
        const double* row = &F[i * N];
        for (std::size_t j = j0; j < j1; ++j) out[j] += w[i] * row[j];
      }
    }
  });
}

std::unique_ptr<PointGather> DenseOperator::point_gather(const std::vector<const double*>& B) const {
  return std::make_unique<DensePointGather>(scene_, patches_, *vis_, *planes_, sides_, B);
}

void DenseOperator::visit_factors(const FactorVisitor& visit) const {
  const std::size_t N = patches_.size();
  const std::vector<double>& F = factors_.F;
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < N; ++j)
      if (F[i * N + j] != 0) visit(i, j, F[i * N + j]);
}

void DenseOperator::report(SolveStats& stats) const {
  stats.links = factors_.links;
  stats.links_clear = factors_.links_clear;
  stats.link_rays = factors_.link_rays;
  stats.method = SolverMethod::Dense;
  stats.dense.link_ray_thread_s = factors_.link_ray_thread_s;
  stats.max_closure_error = max_closure_error_;
  stats.closure_residual = closure_residual_;
  stats.max_reciprocity_error = max_reciprocity_error_;
  stats.mean_reciprocity_error = mean_reciprocity_error_;
  stats.rays = vis_->rays_traced();
}

}  // namespace lambert
