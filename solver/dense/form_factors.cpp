#include "solver/dense/form_factors.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>

#include "solver/form_factor.h"
#include "solver/patch_refinement.h"

namespace lambert {

DenseFactors form_dense_factors(const std::vector<Patch>& patches, const Visibility& vis,
                                const OccluderPlanes& planes, const std::vector<OccluderPlanes::Sides>& sides,
                                const std::vector<Hemisphere>& hemisphere, const SolveControl& control) {
  using Clock = std::chrono::steady_clock;
  const std::size_t N = patches.size();
  DenseFactors out;
  out.F.assign(N * N, 0.0);
  std::vector<double>& F = out.F;
  const std::vector<Point3> samples = lifted_visibility_samples(patches, vis);
  out.row_traced.reset(new std::atomic<char>[N]);
  for (std::size_t i = 0; i < N; ++i) out.row_traced[i].store(0, std::memory_order_relaxed);
  std::atomic<std::size_t> rows_done{0}, links{0}, links_clear{0};
  std::atomic<std::uint64_t> link_rays{0}, link_ray_ns{0};
  std::atomic<bool> cancelled{false};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 1), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (control.cancel && control.cancel->load(std::memory_order_relaxed)) {
        cancelled = true;
        return;
      }
      const Patch& a = patches[i];
      // The row's visibility first, as ray streams for the links that an occluder plane could cut,
      // then the unoccluded factor of every link not wholly hidden (the kernel costs as much as the
      // rays, and in a furnished room many links are hidden).
      thread_local std::vector<std::size_t> partners, traced, traced_partners;
      thread_local std::vector<double> unoccluded, fraction, traced_fraction;
      partners.clear(), traced.clear(), traced_partners.clear();
      for (std::size_t j = i + 1; j < N && hemisphere[i] != Hemisphere::Enclosed; ++j) {
        const Patch& b = patches[j];
        if (hemisphere[j] == Hemisphere::Enclosed) continue;
        if (!any_in_front(a.triangle, a.normal, b.triangle) || !any_in_front(b.triangle, b.normal, a.triangle)) continue;
        if (sides.empty() || !planes.clear(sides[i], sides[j])) {
          traced.push_back(partners.size());
          traced_partners.push_back(j);
        }
        partners.push_back(j);
      }
      fraction.assign(partners.size(), 1.0);
      if (!traced.empty()) {
        traced_fraction.resize(traced.size());
        const auto t_rays = Clock::now();
        link_rays += patch_visible_fractions(i, traced_partners, patches, samples, vis, traced_fraction);
        link_ray_ns += static_cast<std::uint64_t>(
            std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t_rays).count());
        out.row_traced[i].store(1, std::memory_order_relaxed);
        for (std::size_t j : traced_partners) out.row_traced[j].store(1, std::memory_order_relaxed);
        for (std::size_t r = 0; r < traced.size(); ++r) fraction[traced[r]] = traced_fraction[r];
      }
      unoccluded.assign(partners.size(), 0.0);
      for (std::size_t l = 0; l < partners.size(); ++l) {
        if (fraction[l] <= 0) continue;
        unoccluded[l] = exchange_area(a.triangle, patches[partners[l]].triangle);
      }
      // Links wholly visible without rays: no occluder plane can come between.
      for (std::size_t l = 0, r = 0; l < partners.size(); ++l) {
        const bool was_traced = r < traced.size() && traced[r] == l;
        r += was_traced;
        links_clear += !was_traced && unoccluded[l] > 0;
      }
      std::size_t row_links = 0;
      for (std::size_t l = 0; l < partners.size(); ++l) {
        const std::size_t j = partners[l];
        const double g = unoccluded[l] * fraction[l];
        if (g <= 0) continue;
        F[i * N + j] = g / a.area_m2;  // each (i, j) with i < j is written by row i's task only
        F[j * N + i] = g / patches[j].area_m2;
        ++row_links;
      }
      links += row_links;
      const std::size_t done = ++rows_done;
      // Rows shrink linearly with i: progress is the share of pairs, not of rows.
      if (control.progress && done % 64 == 0) control.progress(0.1 + 0.75 * (1 - std::pow(1 - double(done) / N, 2)));
    }
  });
  if (cancelled) throw SolveCancelled();
  out.links = links;
  out.links_clear = links_clear;
  out.link_rays = link_rays;
  out.link_ray_thread_s = 1e-9 * static_cast<double>(link_ray_ns.load());
  return out;
}

}  // namespace lambert
