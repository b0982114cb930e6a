// The radiosity solve (see radiosity.h for the equations). Stages, each timed in SolveStats:
//   meshing -> visibility scene -> direct light -> form factors -> linear solves -> probes -> energy.
#include "solver/radiosity.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <unordered_map>

#include "mesh/mesh_ops.h"
#include "solver/cubature.h"
#include "solver/energy_balance.h"
#include "solver/exact_visibility.h"
#include "solver/form_factor.h"
#include "solver/hierarchical.h"
#include "solver/light_model.h"
#include "solver/linear_solve.h"
#include "solver/occluder_planes.h"
#include "solver/patch_refinement.h"
#include "solver/pipeline/direct_light.h"
#include "solver/pipeline/hemisphere.h"
#include "solver/pipeline/prepare.h"
#include "solver/solids.h"
#include "solver/visibility.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The dense solver keeps G = A F in memory (8 N² bytes): refuse what would not fit comfortably.
constexpr std::size_t kMaxDensePatches = 20000;

void check_cancel(const SolveControl& control) {
  if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw SolveCancelled();
}

// The factors from a point (a probe) to the visible parts of patches. Rays from the point to each
// patch's corners (pulled 0.1 % towards the centroid: a straight shadow edge that crosses a triangle
// separates its corners, so it cannot slip between interior samples) and to 16 interior samples
// decide the common cases: all visible gives the unoccluded factor, none the value 0. The rays of all
// patches go to Embree as one stream; patches that no occluder plane separates from the point
// (occluder_planes.h) need none. Where they disagree, the visible part of the patch is computed
// exactly (solver/exact_visibility.h): the occluders in the cone from the point over the patch,
// projected onto its plane and subtracted (inclusion–exclusion over their convex intersections, or
// CGAL's exact Booleans beyond 8 of them). Per patch, not once per input triangle clipped to its
// patches: a patch's cone holds a few occluders, an input triangle's (a wall) often more than 8, and
// the Boolean path cost the Cornell box's probe grid 0.1 s of its 0.17 s (fifth session; the factors
// agree to 2e-15). candidates: (patch, unoccluded factor > 0); each factor is replaced by the visible
// one.
constexpr int kProbeRays = 3 + 16;
void visible_point_triangle_factors(const Point3& p, const Vector3& n, const std::vector<Patch>& patches,
                                    std::vector<std::pair<std::size_t, double>>& candidates, const Visibility& vis,
                                    const OccluderPlanes& planes, const std::vector<OccluderPlanes::Sides>& sides,
                                    const ExactVisibility& exact) {
  thread_local std::vector<Segment> rays;
  thread_local std::vector<std::uint8_t> visible;
  thread_local std::vector<std::size_t> traced;  // candidates whose rays are in the stream
  const Point3 from = vis.lift(p, n);
  const Point3 point[1] = {p};
  const OccluderPlanes::Sides point_sides = planes.sides(point);
  rays.clear(), traced.clear();
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const std::size_t j = candidates[c].first;
    if (!sides.empty() && planes.clear(point_sides, sides[j])) continue;  // wholly visible
    traced.push_back(c);
    const Patch& patch = patches[j];
    const Triangle& t = patch.triangle;
    for (int v = 0; v < 3; ++v) {
      const Point3 corner = barycentric(t.v[v], t.v[(v + 1) % 3], t.v[(v + 2) % 3], 0.998, 0.001, 0.001);
      rays.push_back({from, vis.lift(corner, patch.normal)});
    }
    for (int k = 0; k < 16; ++k) rays.push_back({from, vis.lift(visibility_sample(t, k), patch.normal)});
  }
  visible.resize(rays.size());
  vis.visible(rays, visible);
  for (std::size_t r = 0; r < traced.size(); ++r) {
    const std::size_t c = traced[r];
    const Patch& patch = patches[candidates[c].first];
    const int seen = static_cast<int>(std::count(visible.begin() + r * kProbeRays, visible.begin() + (r + 1) * kProbeRays, 1));
    double& factor = candidates[c].second;
    if (seen == kProbeRays) continue;
    factor = seen == 0 ? 0.0 : exact.visible_factor(p, n, patch.triangle);
  }
}


}  // namespace

namespace {

constexpr int kAdaptiveRounds = 2;

// The surfaces cut into patches of at most max_area (mesh_ops.h, subdivide_to_max_area_with_parents).
std::vector<Patch> mesh_patches(const Scene& scene, double max_area) {
  std::vector<Patch> out;
  int first_input = 0;  // index of the surface's first input triangle over all surfaces
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const SubdividedMesh patches = subdivide_to_max_area_with_parents(scene.surfaces[s].mesh, max_area);
    for (std::size_t t = 0; t < patches.mesh.triangles.size(); ++t) {
      Patch p;
      p.surface = static_cast<int>(s);
      p.input_triangle = first_input + patches.parent[t];
      p.triangle = patches.mesh.triangle(t);
      p.area_m2 = p.triangle.area();
      if (!(p.area_m2 > 0)) continue;  // degenerate input was rejected by the decoder; splits are not
      p.normal = p.triangle.normal();
      out.push_back(p);
    }
    first_input += static_cast<int>(scene.surfaces[s].mesh.triangles.size());
  }
  return out;
}

// Direct-light meshing (meshing.refine_direct): before the solve, split where the direct irradiance
// jumps between neighbours by more than kDirectRatio (where_varies), in up to two rounds, down to
// 1/16 of max_area. This puts small patches in penumbrae and along shadow edges before any factor is
// formed (meshing.adaptive solves the whole scene again for each round). The ratio is a jump, not a
// gradient: smooth fall-off (a wall below a ceiling light) stays coarse (patch_refinement.h).
// A round that would exceed `limit` patches is not taken.
std::vector<Patch> refine_where_direct_light_varies(const Scene& scene, std::vector<Patch> patches, double max_area,
                                                    std::size_t limit, const SolveControl& control) {
  if (!has_direct_light(scene)) return patches;
  std::vector<Triangle> input_triangles;
  for (const Surface& surface : scene.surfaces)
    for (std::size_t t = 0; t < surface.mesh.triangles.size(); ++t) input_triangles.push_back(surface.mesh.triangle(t));
  const Visibility vis(input_triangles);
  for (int round = 0; round < 2; ++round) {
    std::vector<char> marked = where_varies(patches, direct_irradiance_totals(scene, patches, vis, control), kDirectRatio);
    if (round == 0) mark_near_probes(patches, scene.probes, marked);
    std::vector<Patch> refined = split_marked(patches, marked, max_area / 16);
    if (refined.size() == patches.size() || refined.size() > limit) break;
    patches = std::move(refined);
  }
  return patches;
}

// Adaptive meshing (meshing.adaptive): split where the solved irradiance differs from a neighbour's by
// more than 20 % of the pair's mean (a ratio of 1.1/0.9), down to 1/16 of meshing.max_patch_area.
std::vector<Patch> refine_where_irradiance_varies(const Solution& sol) {
  const std::size_t N = sol.patches.size(), W = sol.wavelengths();
  std::vector<double> q(N, 0.0);
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t w = 0; w < W; ++w) q[i] += sol.grid.weight_nm[w] * sol.irradiance[i * W + w];
  return split_marked(sol.patches, where_varies(sol.patches, q, 1.1 / 0.9), sol.stats.max_patch_area_m2 / 16);
}

}  // namespace

double default_max_patch_area(const Scene& scene) {
  double total = 0;
  for (const Surface& s : scene.surfaces)
    for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) total += s.mesh.triangle(t).area();
  return total / 1200;
}

Solution solve_dense(const Scene& scene, const SolveControl& control, const std::vector<Patch>* premeshed);


std::size_t patch_limit(std::size_t solver_limit, const SolveControl& control) {
  return control.max_patches > 0 ? std::min(control.max_patches, solver_limit) : solver_limit;
}

void check_patch_count(double patches, bool estimate, std::size_t solver_limit, const SolveControl& control) {
  const std::size_t limit = patch_limit(solver_limit, control);
  // An estimate (total area / max area) is a lower bound up to rounding of the areas.
  if (!((estimate ? patches * (1 - 1e-9) : patches) > static_cast<double>(limit))) return;
  const std::string count =
      (estimate ? "at least " : "") + std::to_string(static_cast<std::size_t>(std::min(patches, 1e18)));
  if (limit == control.max_patches)
    throw SolveError("meshing gives " + count + " patches, more than this server's limit of " +
                     std::to_string(limit) + " (max_patches); increase meshing.max_patch_area");
  throw SolveError("meshing gives " + count + " patches, more than this solver's limit of " + std::to_string(limit) +
                   "; increase meshing.max_patch_area (it is in the scene's units squared)");
}

// The stages run in order: the scene prepared (solver/pipeline/prepare.h), then the method.
namespace {
Solution solve_method(const Scene& scene, const SolveControl& control);
}  // namespace

Solution solve(const Scene& scene, const SolveControl& control) {
  const PreparedScene prepared(scene, control);
  Solution sol = solve_method(prepared.scene(), control);
  prepared.finish(sol);
  return sol;
}

namespace {
Solution solve_method(const Scene& scene, const SolveControl& control) {
  // Method selection (scene.h SolverMethod): Auto estimates the meshed patch count from the areas.
  SolverMethod method = scene.solver.method;
  if (method == SolverMethod::Auto) {
    const double max_area = scene.meshing.max_patch_area_m2.value_or(default_max_patch_area(scene));
    double patches = 0;
    for (const Surface& s : scene.surfaces)
      for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t)
        patches += std::max(1.0, std::ceil(s.mesh.triangle(t).area() / max_area));
    method = patches <= kDenseAutoPatches || scene.output.per_source ? SolverMethod::Dense : SolverMethod::Hierarchical;
  }
  if (method == SolverMethod::Hierarchical) {
    if (scene.output.per_source) throw SolveError("output.per_source is not available with solver.method \"hierarchical\"");
    Solution sol = solve_hierarchical(scene, control);
    if (scene.meshing.adaptive)
      sol.warnings.push_back("meshing.adaptive applies to the dense solver only; the hierarchical method "
                             "refines its own links");
    sol.warnings.push_back("solved with the experimental hierarchical method: expect errors of a few per cent "
                           "(closed rows were corrected by up to " +
                           std::to_string(sol.stats.max_closure_error) + "); see stats");
    return sol;
  }
  if (!scene.meshing.adaptive) return solve_dense(scene, control, nullptr);
  // Adaptive meshing: solve, split the patches where the irradiance jumps between neighbours, solve
  // again (at most kAdaptiveRounds times). Each pass reports progress in its share of [0, 1].
  const auto t_start = Clock::now();
  auto pass_control = [&](int pass) {
    SolveControl c = control;
    if (control.progress)
      c.progress = [&control, pass](double f) { control.progress((pass + f) / (kAdaptiveRounds + 1)); };
    return c;
  };
  Solution sol = solve_dense(scene, pass_control(0), nullptr);
  for (int round = 1; round <= kAdaptiveRounds; ++round) {
    std::vector<Patch> refined = refine_where_irradiance_varies(sol);
    if (refined.size() == sol.patches.size()) break;
    const std::size_t direct_refinement = sol.stats.direct_refinement_patches;  // of the first pass
    sol = solve_dense(scene, pass_control(round), &refined);
    sol.stats.adaptive_rounds = round;
    sol.stats.direct_refinement_patches = direct_refinement;
  }
  sol.stats.time_total_s = seconds_since(t_start);
  if (control.progress) control.progress(1.0);
  return sol;
}

}  // namespace

Solution solve_dense(const Scene& scene, const SolveControl& control, const std::vector<Patch>* premeshed) {
  const auto t_start = Clock::now();
  Solution sol;
  sol.grid = scene.grid;
  sol.warnings = scene.warnings;
  const std::size_t W = scene.grid.size();
  auto report = [&](double f) { if (control.progress) control.progress(f); };

  // ---- meshing: surfaces -> patches ----
  auto t0 = Clock::now();
  const double max_area = scene.meshing.max_patch_area_m2.value_or(default_max_patch_area(scene));
  sol.stats.max_patch_area_m2 = max_area;
  // Every patch has an area <= max_area, so total area / max_area bounds the patch count from below:
  // a limit that is sure to be exceeded is reported before meshing, which a tiny max_patch_area
  // would otherwise drive out of memory.
  auto check_patch_count = [&](double patches, bool estimate) {
    lambert::check_patch_count(patches, estimate, kMaxDensePatches, control);
  };
  {
    double total_area = 0;
    for (const Surface& s : scene.surfaces)
      for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) total_area += s.mesh.triangle(t).area();
    if (!premeshed) check_patch_count(total_area / max_area, true);
  }
  if (premeshed) {
    sol.patches = *premeshed;
  } else {
    sol.patches = mesh_patches(scene, max_area);
    const std::size_t base = sol.patches.size();
    if (scene.meshing.refine_direct)
      sol.patches = refine_where_direct_light_varies(scene, std::move(sol.patches), max_area,
                                                     patch_limit(kMaxDensePatches, control), control);
    sol.stats.direct_refinement_patches = sol.patches.size() - base;
  }
  const std::size_t N = sol.patches.size();
  sol.stats.patches = N;
  check_patch_count(static_cast<double>(N), false);
  sol.stats.time_meshing_s = seconds_since(t0);
  check_cancel(control);
  report(0.05);

  // ---- visibility scene ----
  t0 = Clock::now();
  std::vector<Triangle> occluders(N);
  for (std::size_t i = 0; i < N; ++i) occluders[i] = sol.patches[i].triangle;
  const Visibility vis(occluders, Visibility::Estimates::fast);  // link rays in the fast BVH
  // Pairs that no occluder plane separates need no rays, links and probes alike (occluder_planes.h).
  std::vector<Triangle> input_triangles;
  for (const Surface& surface : scene.surfaces)
    for (std::size_t t = 0; t < surface.mesh.triangles.size(); ++t) input_triangles.push_back(surface.mesh.triangle(t));
  const OccluderPlanes occluder_planes(input_triangles);
  std::vector<char> two_sided(input_triangles.size(), 0);  // Surface::two_sided, over all surfaces
  {
    std::size_t first = 0;
    for (const Surface& surface : scene.surfaces) {
      for (std::size_t t = 0; t < surface.two_sided.size() && t < surface.mesh.triangles.size(); ++t)
        two_sided[first + t] = surface.two_sided[t];
      first += surface.mesh.triangles.size();
    }
  }
  std::vector<OccluderPlanes::Sides> sides(occluder_planes.usable() ? N : 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sides.size(), 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) sides[i] = occluder_planes.sides(sol.patches[i].triangle.v);
  });
  sol.stats.time_visibility_s = seconds_since(t0);

  // ---- sources and direct light (solver/pipeline/direct_light.h) ----
  DirectLight light = direct_light(scene, sol.patches, lobed_patches(scene, sol.patches), vis, control);
  std::vector<double>& rho = light.rho;
  std::vector<double>& M = light.M;
  const std::vector<double>& E_direct = light.E_direct;
  const std::vector<double>& E_point = light.E_known_flux;
  const auto& sources = light.sources;
  const std::vector<SourceTerms>& terms = light.terms;
  const std::vector<int>& term_of_source = light.term_of_source;
  check_cancel(control);
  report(0.1);

  // ---- form factors, only where radiosity can flow ----
  // G_ij = A_i F_ij = G_ji from the exact kernel integrated over the smaller patch of each pair, times
  // the kernel-weighted visible fraction from rays; computed once per unordered pair.
  t0 = Clock::now();
  const bool need_factors = light.needs_transport();
  std::vector<double> F;  // row-major N×N, F_ij = G_ij / A_i
  std::vector<double> row_sum(N, 0.0);
  // The hemisphere of each patch (solver/pipeline/hemisphere.h), probed on the patches themselves.
  std::vector<Hemisphere> closed(N, Hemisphere::Open);
  std::vector<Vector3> patch_normals(N);
  std::vector<char> patch_two_sided(N, 0);
  for (std::size_t i = 0; i < N; ++i) {
    patch_normals[i] = sol.patches[i].normal;
    const int input = sol.patches[i].input_triangle;
    patch_two_sided[i] = input >= 0 && static_cast<std::size_t>(input) < two_sided.size() && two_sided[input];
  }
  const HemisphereProbe hemisphere(vis, std::move(patch_normals), std::move(patch_two_sided));
  auto probe = [&](std::size_t i) {
    return hemisphere.classify(sol.patches[i].triangle, sol.patches[i].normal, i, kHemisphereRays);
  };
  std::atomic<std::size_t> rows_done{0}, links{0}, links_clear{0};
  std::atomic<std::uint64_t> link_rays{0}, link_ray_ns{0};  // rays of links and the thread time spent on them
  std::atomic<bool> cancelled{false};
  if (need_factors) {
    F.assign(N * N, 0.0);
    // The hemisphere probe first for every patch that may see a back face (all but those in front of
    // every occluder plane): a patch inside a closed solid (every ray meets a back face, e.g. a floor
    // under a box without a bottom) exchanges nothing with the scene, so its row and column are not
    // formed and it is left out of the result.
    const auto in_front_of_all = [&](std::size_t i) { return !sides.empty() && occluder_planes.in_front_of_all(sides[i]); };
    std::vector<char> probed(N, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
        if (!in_front_of_all(i)) closed[i] = probe(i), probed[i] = 1;
    });
    check_cancel(control);
    // Nor does it emit or reflect: a light sealed inside a box sends nothing, and its power is not
    // counted as emitted (nor as escaped) in the energy certificate.
    light.leave_out_enclosed(closed, W);
    // Whether any link of a patch's row needed rays (its row sum is then an estimate).
    const std::vector<Point3> samples = lifted_visibility_samples(sol.patches, vis);
    std::unique_ptr<std::atomic<char>[]> row_traced(new std::atomic<char>[N]);
    for (std::size_t i = 0; i < N; ++i) row_traced[i].store(0, std::memory_order_relaxed);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 1), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        if (control.cancel && control.cancel->load(std::memory_order_relaxed)) {
          cancelled = true;
          return;
        }
        const Patch& a = sol.patches[i];
        // The row's visibility first, as ray streams for the links that an occluder plane could cut,
        // then the unoccluded factor of every link not wholly hidden (the kernel costs as much as the
        // rays, and in a furnished room many links are hidden).
        thread_local std::vector<std::size_t> partners, traced, traced_partners;
        thread_local std::vector<double> unoccluded, fraction, traced_fraction;
        partners.clear(), traced.clear(), traced_partners.clear();
        for (std::size_t j = i + 1; j < N && closed[i] != Hemisphere::Enclosed; ++j) {
          const Patch& b = sol.patches[j];
          if (closed[j] == Hemisphere::Enclosed) continue;
          if (!any_in_front(a.triangle, a.normal, b.triangle) || !any_in_front(b.triangle, b.normal, a.triangle))
            continue;
          if (sides.empty() || !occluder_planes.clear(sides[i], sides[j])) {
            traced.push_back(partners.size());
            traced_partners.push_back(j);
          }
          partners.push_back(j);
        }
        fraction.assign(partners.size(), 1.0);
        if (!traced.empty()) {
          traced_fraction.resize(traced.size());
          const auto t_rays = Clock::now();
          link_rays += patch_visible_fractions(i, traced_partners, sol.patches, samples, vis, traced_fraction);
          link_ray_ns += static_cast<std::uint64_t>(
              std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t_rays).count());
          row_traced[i].store(1, std::memory_order_relaxed);
          for (std::size_t j : traced_partners) row_traced[j].store(1, std::memory_order_relaxed);
          for (std::size_t r = 0; r < traced.size(); ++r) fraction[traced[r]] = traced_fraction[r];
        }
        unoccluded.assign(partners.size(), 0.0);
        for (std::size_t l = 0; l < partners.size(); ++l) {
          if (fraction[l] <= 0) continue;
          const Patch& b = sol.patches[partners[l]];
          unoccluded[l] = exchange_area(a.triangle, b.triangle);
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
          F[j * N + i] = g / sol.patches[j].area_m2;
          ++row_links;
        }
        links += row_links;
        const std::size_t done = ++rows_done;
        // Rows shrink linearly with i: progress is the share of pairs, not of rows.
        if (control.progress && done % 64 == 0) report(0.1 + 0.75 * (1 - std::pow(1 - double(done) / N, 2)));
      }
    });
    if (cancelled) throw SolveCancelled();
    // Closure: a patch whose hemisphere is closed (no probe ray escapes or hits the back of a
    // surface) must have Σ_j F_ij = 1; the kernel is exact, so any deficit or excess comes from the
    // visible-fraction estimates of partly occluded links. We restore it with a symmetric diagonal
    // scaling G' = D G D (symmetric_row_scaling: Newton steps, or Sinkhorn sweeps where those stall;
    // D = 1 on open patches), which keeps reciprocity A_i F_ij = A_j F_ji exact while closing every
    // closed row: energy is conserved and the furnace gives B = M/(1 − ρ) exactly. The size of the
    // correction is reported.
    // A patch whose links were all decided without rays has an exact row (the kernel), and if it lies
    // in front of every occluder plane it sees no back face: its row sum tells whether its
    // hemisphere is closed (to 1e-3, finer than the probe's rays resolve), and no probe is needed.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        if (probed[i]) continue;
        if (!row_traced[i].load(std::memory_order_relaxed)) {
          closed[i] = hemisphere_from_coverage(std::accumulate(&F[i * N], &F[i * N] + N, 0.0));
        } else {
          closed[i] = probe(i);
        }
      }
    });
    std::vector<char> closing(N, 0);
    std::vector<double> area(N);
    for (std::size_t i = 0; i < N; ++i) closing[i] = closed[i] == Hemisphere::Closed, area[i] = sol.patches[i].area_m2;
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
    sol.stats.max_closure_error = scaling.initial_deviation;
    // The rows as the solve uses them (the scaled factors keep A_i F_ij = A_j F_ji, so the columns
    // weighted by area are the rows).
    for (std::size_t i = 0; i < N; ++i)
      if (closing[i]) sol.stats.closure_residual = std::max(sol.stats.closure_residual, std::abs(1 - row_sum[i]));
    report_hemisphere_findings(sol, scene, closed);
    double worst = 0, differ = 0, exchanged = 0;
    for (std::size_t i = 0; i < N; ++i)
      for (std::size_t j = i + 1; j < N; ++j) {
        const double gij = sol.patches[i].area_m2 * F[i * N + j], gji = sol.patches[j].area_m2 * F[j * N + i];
        const double big = std::max(gij, gji);
        if (big > 1e-9 * std::min(sol.patches[i].area_m2, sol.patches[j].area_m2)) {
          worst = std::max(worst, std::abs(gij - gji) / big);
          differ += std::abs(gij - gji);
          exchanged += big;
        }
      }
    sol.stats.max_reciprocity_error = worst;
    sol.stats.mean_reciprocity_error = exchanged > 0 ? differ / exchanged : 0;
  }
  sol.stats.links = links;
  sol.stats.links_clear = links_clear;
  sol.stats.link_rays = link_rays;
  sol.stats.link_ray_thread_s = 1e-9 * static_cast<double>(link_ray_ns.load());
  sol.stats.time_form_factors_s = seconds_since(t0);
  report(0.85);

  // ---- linear solves, one per distinct (reflectance column, right-hand side) ----
  // Right-hand-side sets: the joint sources first, then (output.per_source) each source alone. All
  // their systems are solved together, so F is streamed once per iteration for all of them.
  t0 = Clock::now();
  std::vector<std::pair<const std::vector<double>*, const std::vector<double>*>> sets = {{&M, &E_direct}};
  const std::vector<double> no_emission(N * W, 0.0);
  for (const SourceTerms& t : terms) sets.push_back({t.M.empty() ? &no_emission : &t.M, &t.E});
  std::vector<std::vector<double>> set_radiosity(sets.size(), std::vector<double>(N * W, 0.0));
  std::map<std::vector<double>, std::vector<std::size_t>> groups;  // ρ over materials -> wavelengths
  for (std::size_t w = 0; w < W; ++w) {
    std::vector<double> key(scene.materials.size());
    for (std::size_t m = 0; m < key.size(); ++m) key[m] = scene.materials[m].reflectance[w];
    groups[key].push_back(w);
  }
  // Unknowns: patches that reflect at some wavelength and exchange light with the scene. Patches black
  // at every wavelength keep B = M and are not iterated over; their emission enters the right-hand
  // sides. Patches inside closed solids (no factors) keep B = M + ρ E_direct: iterated over, a bright
  // one would set the scale of the solver's relative residual and leave the room unconverged.
  std::vector<int> active;
  for (std::size_t i = 0; i < N && need_factors; ++i)
    for (std::size_t w = 0; w < W && closed[i] != Hemisphere::Enclosed; ++w)
      if (rho[i * W + w] > 0) {
        active.push_back(static_cast<int>(i));
        break;
      }
  const std::size_t n = active.size();
  std::vector<char> is_active(N, 0);
  for (int i : active) is_active[i] = 1;
  for (std::size_t set = 0; set < sets.size(); ++set)
    for (std::size_t i = 0; i < N; ++i)
      if (!is_active[i])
        for (std::size_t w = 0; w < W; ++w) {
          const std::size_t k = i * W + w;
          set_radiosity[set][k] = (*sets[set].first)[k] + rho[k] * (*sets[set].second)[k];
        }
  if (n > 0) {
    // F restricted to the unknowns (a copy only when some patches are black everywhere).
    std::vector<double> compact;
    if (n < N) {
      compact.resize(n * n);
      for (std::size_t r = 0; r < n; ++r)
        for (std::size_t c = 0; c < n; ++c) compact[r * n + c] = F[active[r] * N + active[c]];
    }
    const std::vector<double>& Fa = n < N ? compact : F;
    // One system per distinct (reflectance column, right-hand side); (set, wavelength) map onto them.
    //   B_i − ρ_i Σ_{j active} F_ij B_j = M_i + ρ_i (E_i + Σ_{j black} F_ij M_j)
    std::vector<RadiositySystem> systems;
    std::map<std::pair<std::vector<double>, std::vector<double>>, std::size_t> system_of;
    std::vector<std::vector<std::size_t>> system_for(sets.size(), std::vector<std::size_t>(W));
    // The patches that are not unknowns, and of those the ones emitting at the wavelength at hand
    // (a short list: scanning every column of every row for them, 61 wavelengths over the Cornell
    // box's 1 507 patches, took a sixth of a second).
    std::vector<std::size_t> inactive, emitting;
    for (std::size_t j = 0; j < N; ++j)
      if (!is_active[j]) inactive.push_back(j);
    for (const auto& [key, wavelengths] : groups) {
      std::vector<double> rho_column(n);
      for (std::size_t r = 0; r < n; ++r) rho_column[r] = rho[active[r] * W + wavelengths.front()];
      for (std::size_t set = 0; set < sets.size(); ++set) {
        const std::vector<double>& Ms = *sets[set].first;
        const std::vector<double>& Es = *sets[set].second;
        for (std::size_t w : wavelengths) {
          emitting.clear();
          for (std::size_t j : inactive)
            if (Ms[j * W + w] != 0) emitting.push_back(j);
          std::vector<double> rhs(n);
          for (std::size_t r = 0; r < n; ++r) {
            const std::size_t i = active[r];
            double from_black = 0;
            for (std::size_t j : emitting) from_black += F[i * N + j] * Ms[j * W + w];
            rhs[r] = Ms[i * W + w] + rho_column[r] * (Es[i * W + w] + from_black);
          }
          auto [it, inserted] = system_of.try_emplace({rho_column, rhs}, systems.size());
          if (inserted) {
            RadiositySystem& sys = systems.emplace_back();
            sys.rho = rho_column;
            sys.x = rhs;  // first bounce as the starting guess
            sys.b = std::move(rhs);
          }
          system_for[set][w] = it->second;
        }
      }
    }
    solve_radiosity_systems(Fa, n, systems, scene.solver.tolerance, scene.solver.max_iterations,
                            [&] { return control.cancel && control.cancel->load(std::memory_order_relaxed); });
    for (const RadiositySystem& sys : systems) {
      sol.stats.iterations = std::max(sol.stats.iterations, sys.iterations);
      sol.stats.residual = std::max(sol.stats.residual, sys.residual);
    }
    sol.stats.spectral_systems_solved = static_cast<int>(systems.size());
    // A spectral radiosity is ≥ 0, so a negative x is round-off and is dropped; an rgb channel
    // value may be negative (signed O_c and I_c, solver/rgb_model.h) and is kept.
    const bool keep_sign = scene.mode == SpectrumMode::Rgb;
    for (std::size_t set = 0; set < sets.size(); ++set)
      for (std::size_t w = 0; w < W; ++w)
        for (std::size_t r = 0; r < n; ++r) {
          const double x = systems[system_for[set][w]].x[r];
          set_radiosity[set][active[r] * W + w] = keep_sign ? x : std::max(0.0, x);
        }
  }
  // H_i = Σ_j F_ij B_j + E_i^direct, for every set.
  auto gather = [&](const std::vector<double>& B, const std::vector<double>& E, std::vector<double>& H) {
    H.assign(N * W, 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        double* h = &H[i * W];
        if (need_factors) {
          const double* row = &F[i * N];
          for (std::size_t j = 0; j < N; ++j) {
            if (row[j] == 0) continue;
            const double* b = &B[j * W];
            for (std::size_t w = 0; w < W; ++w) h[w] += row[j] * b[w];
          }
        }
        for (std::size_t w = 0; w < W; ++w) h[w] += E[i * W + w];
      }
    });
  };
  sol.radiosity = std::move(set_radiosity[0]);
  gather(sol.radiosity, E_direct, sol.irradiance);
  for (std::size_t t = 0; t < terms.size(); ++t) {
    SourceContribution c{terms[t].pointer, terms[t].name, std::move(set_radiosity[t + 1]), {}, {}};
    gather(c.radiosity, terms[t].E, c.irradiance);
    sol.contributions.push_back(std::move(c));
  }
  sol.stats.time_solve_s = seconds_since(t0);
  report(0.9);

  // ---- probes: irradiance from every source and every patch at each point ----
  // Per point, the direct factor of each source and the visible factor of each radiating patch are
  // computed once and applied to the joint solution and to every source's contribution.
  t0 = Clock::now();
  sol.probes.resize(scene.probes.size());
  for (auto& c : sol.contributions) c.probes.resize(scene.probes.size());
  // Exact partial visibility works on the input triangles (fewer, larger occluders than the patches),
  // with the solids they bound (a convex solid's front faces hide the sum of their factors).
  const OutwardSolids solids = scene.probes.empty() ? OutwardSolids{} : outward_solids(scene.surfaces);
  const ExactVisibility exact(scene.probes.empty() ? std::vector<Triangle>{} : input_triangles, solids.solid, solids.convex, solids.cap);
  std::vector<char> radiates(N, 0);
  for (std::size_t j = 0; j < N; ++j) {
    const double* b = &sol.radiosity[j * W];
    radiates[j] = std::any_of(b, b + W, [](double v) { return v != 0; });
  }
  for (std::size_t k = 0; k < scene.probes.size(); ++k) {
    const Probe& probe = scene.probes[k];
    const std::size_t P = probe.points.size();
    sol.probes[k].irradiance.assign(P * W, 0.0);
    for (auto& c : sol.contributions) c.probes[k].irradiance.assign(P * W, 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P, 1), [&](const auto& range) {
      std::vector<std::pair<std::size_t, double>> seen;  // (patch, visible point-to-patch factor)
      for (std::size_t q = range.begin(); q != range.end(); ++q) {
        const Point3& p = probe.points[q];
        for (std::size_t s = 0; s < sources.size(); ++s) {
          const double g = sources[s]->point_factor(p, probe.normal, vis);
          if (g == 0) continue;
          const auto& S = sources[s]->spectrum();
          double* e = &sol.probes[k].irradiance[q * W];
          for (std::size_t w = 0; w < W; ++w) e[w] += g * S[w];
          if (term_of_source[s] >= 0) {
            double* own = &sol.contributions[term_of_source[s]].probes[k].irradiance[q * W];
            for (std::size_t w = 0; w < W; ++w) own[w] += g * S[w];
          }
        }
        seen.clear();
        for (std::size_t j = 0; j < N; ++j) {
          if (!radiates[j]) continue;
          const double f = point_triangle_factor(p, probe.normal, sol.patches[j].triangle);
          if (f > 0) seen.emplace_back(j, f);
        }
        visible_point_triangle_factors(p, probe.normal, sol.patches, seen, vis, occluder_planes, sides, exact);
        auto accumulate = [&](const std::vector<double>& B, double* e) {
          for (const auto& [j, fv] : seen)
            for (std::size_t w = 0; w < W; ++w) e[w] += fv * B[j * W + w];
        };
        accumulate(sol.radiosity, &sol.probes[k].irradiance[q * W]);
        for (auto& c : sol.contributions) accumulate(c.radiosity, &c.probes[k].irradiance[q * W]);
      }
    });
    check_cancel(control);
  }
  sol.stats.time_probes_s = seconds_since(t0);
  sol.stats.exact_visibility_evaluations = exact.occluded_evaluations();

  // ---- energy balance: emitted = absorbed + escaped ----
  std::vector<double> leak(N, 1.0);
  for (std::size_t i = 0; i < N && need_factors; ++i) leak[i] = 1 - row_sum[i];
  account_energy(scene.grid, sources, sol.patches, rho, M, E_direct, E_point, sol.radiosity, sol.irradiance, leak,
                 sol.stats);
  sol.stats.rays = vis.rays_traced();
  leave_out_enclosed(sol, closed);
  sol.stats.time_total_s = seconds_since(t_start);
  report(1.0);
  return sol;
}

}  // namespace lambert
