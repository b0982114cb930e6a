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

#include "mesh/mesh_ops.h"
#include "solver/form_factor.h"
#include "solver/lights.h"
#include "solver/visibility.h"

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

// Whether any part of triangle b lies strictly in front of the plane of triangle a.
bool any_in_front(const Triangle& a, const Vector3& na, const Triangle& b) {
  const double scale = a.max_edge_length() + b.max_edge_length();
  for (const Point3& v : b.v)
    if (dot(v - a.v[0], na) > 1e-12 * scale) return true;
  return false;
}

// Visible fraction between two patches: rays between stratified samples of both, each weighted by
// the differential kernel cos θ_i cos θ_j / r² at its ends, so that the estimate is of the visible
// share of the form factor rather than of the area. Four rays first, sixteen if they disagree.
double patch_visible_fraction(const Patch& a, const Patch& b, const Visibility& vis) {
  const auto& samples = triangle_visibility_samples();
  double seen = 0, total = 0;
  int visible_count = 0;
  for (int k = 0; k < 16; ++k) {
    if (k == 4 && (visible_count == 0 || visible_count == 4)) break;
    const auto& wa = samples[k];
    const auto& wb = samples[(5 * k + 7) % 16];  // a fixed permutation decorrelates the pairs
    const Point3 p = barycentric(a.triangle.v[0], a.triangle.v[1], a.triangle.v[2], wa[0], wa[1], wa[2]);
    const Point3 q = barycentric(b.triangle.v[0], b.triangle.v[1], b.triangle.v[2], wb[0], wb[1], wb[2]);
    const Vector3 d = q - p;
    const double r2 = length_squared(d);
    const double weight = std::max(0.0, dot(a.normal, d)) * std::max(0.0, -dot(b.normal, d)) / (r2 * r2) + 1e-300;
    const bool v = vis.visible(p, q);
    visible_count += v;
    seen += v ? weight : 0;
    total += weight;
  }
  return seen / total;
}

// Preconditioned conjugate gradients for (D − G_aa) x = b on the active set (patches with ρ > 0).
// D = A/ρ, G symmetric with zero diagonal, so the Jacobi preconditioner is D itself. Stops when the
// relative residual bounds the relative error below `tolerance`: ‖e‖/‖x‖ ≤ κ ‖r‖/‖b‖ with
// κ ≤ (1 + ρ_max)/(1 − ρ_max) for the Jacobi-scaled system.
struct CgResult { int iterations; double residual; };
CgResult conjugate_gradient(const std::vector<double>& G, std::size_t N, const std::vector<int>& active,
                            const std::vector<double>& D, const std::vector<double>& b,
                            std::vector<double>& x, double tolerance, int max_iterations, double rho_max) {
  const std::size_t n = active.size();
  auto apply = [&](const std::vector<double>& v, std::vector<double>& out) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const auto& range) {
      for (std::size_t r = range.begin(); r != range.end(); ++r) {
        const double* row = &G[static_cast<std::size_t>(active[r]) * N];
        double s = 0;
        for (std::size_t c = 0; c < n; ++c) s += row[active[c]] * v[c];
        out[r] = D[r] * v[r] - s;
      }
    });
  };
  const double kappa = rho_max < 1 ? (1 + rho_max) / (1 - rho_max) : 1e300;
  const double target = tolerance / kappa;
  std::vector<double> r(n), z(n), p(n), q(n);
  apply(x, q);
  double b_norm = 0;
  for (std::size_t k = 0; k < n; ++k) {
    r[k] = b[k] - q[k];
    b_norm += b[k] * b[k];
  }
  b_norm = std::sqrt(b_norm);
  if (b_norm == 0) {
    std::fill(x.begin(), x.end(), 0.0);
    return {0, 0};
  }
  double rz = 0;
  for (std::size_t k = 0; k < n; ++k) {
    z[k] = r[k] / D[k];
    p[k] = z[k];
    rz += r[k] * z[k];
  }
  int it = 0;
  double rel = 0;
  for (; it < max_iterations; ++it) {
    double r_norm = 0;
    for (double v : r) r_norm += v * v;
    rel = std::sqrt(r_norm) / b_norm;
    if (rel <= target) break;
    apply(p, q);
    double pq = 0;
    for (std::size_t k = 0; k < n; ++k) pq += p[k] * q[k];
    if (!(pq > 0)) throw SolveError("the radiosity system is singular (reflectance 1 in a closed scene?)");
    const double alpha = rz / pq;
    double rz_new = 0;
    for (std::size_t k = 0; k < n; ++k) {
      x[k] += alpha * p[k];
      r[k] -= alpha * q[k];
      z[k] = r[k] / D[k];
      rz_new += r[k] * z[k];
    }
    const double beta = rz_new / rz;
    rz = rz_new;
    for (std::size_t k = 0; k < n; ++k) p[k] = z[k] + beta * p[k];
  }
  if (rel > target)
    throw SolveError("the radiosity solve did not converge in " + std::to_string(max_iterations) +
                     " iterations (relative residual " + std::to_string(rel) + ")");
  return {it, rel};
}

}  // namespace

double default_max_patch_area(const Scene& scene) {
  double total = 0;
  for (const Surface& s : scene.surfaces)
    for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) total += s.mesh.triangle(t).area();
  return total / 1200;
}

Solution solve(const Scene& scene, const SolveControl& control) {
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
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const TriangleMesh patches = subdivide_to_max_area(scene.surfaces[s].mesh, max_area);
    for (std::size_t t = 0; t < patches.triangles.size(); ++t) {
      Patch p;
      p.surface = static_cast<int>(s);
      p.triangle = patches.triangle(t);
      p.area_m2 = p.triangle.area();
      if (!(p.area_m2 > 0)) continue;  // degenerate input was rejected by the decoder; splits are not
      p.normal = p.triangle.normal();
      sol.patches.push_back(p);
    }
  }
  const std::size_t N = sol.patches.size();
  sol.stats.patches = N;
  if (N > kMaxDensePatches)
    throw SolveError(std::to_string(N) + " patches exceed this solver's limit of " +
                     std::to_string(kMaxDensePatches) + "; increase meshing.max_patch_area");
  sol.stats.time_meshing_s = seconds_since(t0);
  check_cancel(control);
  report(0.05);

  // ---- visibility scene ----
  t0 = Clock::now();
  std::vector<Triangle> occluders(N);
  for (std::size_t i = 0; i < N; ++i) occluders[i] = sol.patches[i].triangle;
  const Visibility vis(occluders);
  sol.stats.time_visibility_s = seconds_since(t0);

  // ---- per-patch reflectance, emission and direct irradiance ----
  std::vector<double> rho(N * W), M(N * W, 0.0), E_direct(N * W, 0.0), E_point(N * W, 0.0);
  bool any_emitter = false, any_reflector = false;
  for (std::size_t i = 0; i < N; ++i) {
    const Surface& s = scene.surfaces[sol.patches[i].surface];
    const auto& refl = scene.materials[s.material].reflectance;
    for (std::size_t w = 0; w < W; ++w) {
      rho[i * W + w] = refl[w];
      any_reflector |= refl[w] > 0;
    }
    if (s.emission) {
      if (s.emission->lobe_exponent != 1.0)
        throw SolveError(s.pointer + "/emission/lobe: Phong-lobed emitters are not solved by this "
                         "version yet (only \"lambert\")");
      for (std::size_t w = 0; w < W; ++w) M[i * W + w] = s.emission->exitance_W_m2_nm[w];
      any_emitter = true;
    }
  }
  if (!scene.lights.empty()) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        for (const Light& light : scene.lights) {
          const double g = light_patch_factor(light, sol.patches[i].triangle, vis);
          if (g == 0) continue;
          const auto& S = light_spectrum(light);
          const bool is_point = std::holds_alternative<PointLight>(light);
          for (std::size_t w = 0; w < W; ++w) {
            E_direct[i * W + w] += g * S[w];
            if (is_point) E_point[i * W + w] += g * S[w];
          }
        }
      }
    });
  }
  check_cancel(control);
  report(0.1);

  // ---- form factors G_ij = A_i F_ij (symmetric), only where radiosity can flow ----
  t0 = Clock::now();
  const bool need_factors = any_emitter || (any_reflector && !scene.lights.empty());
  std::vector<double> G;
  std::vector<double> row_sum(N, 0.0);
  std::atomic<std::size_t> rows_done{0}, links{0};
  std::atomic<bool> cancelled{false};
  if (need_factors) {
    G.assign(N * N, 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 1), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        if (control.cancel && control.cancel->load(std::memory_order_relaxed)) {
          cancelled = true;
          return;
        }
        const Patch& a = sol.patches[i];
        std::size_t row_links = 0;
        for (std::size_t j = i + 1; j < N; ++j) {
          const Patch& b = sol.patches[j];
          if (!any_in_front(a.triangle, a.normal, b.triangle) || !any_in_front(b.triangle, b.normal, a.triangle))
            continue;
          // Integrate over the smaller patch: its point-to-polygon factor varies least across it.
          const double unoccluded = a.area_m2 <= b.area_m2 ? area_form_factor(a.triangle, b.triangle)
                                                           : area_form_factor(b.triangle, a.triangle);
          if (unoccluded <= 0) continue;
          const double g = unoccluded * patch_visible_fraction(a, b, vis);
          if (g <= 0) continue;
          G[i * N + j] = g;
          G[j * N + i] = g;
          ++row_links;
        }
        links += row_links;
        const std::size_t done = ++rows_done;
        // Rows shrink linearly with i: progress is the share of pairs, not of rows.
        if (control.progress && done % 64 == 0) {
          const double f = 1 - std::pow(1 - double(done) / N, 2);
          report(0.1 + 0.75 * f);
        }
      }
    });
    if (cancelled) throw SolveCancelled();
    for (std::size_t i = 0; i < N; ++i) {
      double s = 0;
      for (std::size_t j = 0; j < N; ++j) s += G[i * N + j];
      row_sum[i] = s / sol.patches[i].area_m2;
    }
  }
  sol.stats.links = links;
  sol.stats.time_form_factors_s = seconds_since(t0);
  report(0.85);

  // ---- linear solves, one per distinct (reflectance column, right-hand side) ----
  t0 = Clock::now();
  sol.radiosity.assign(N * W, 0.0);
  sol.irradiance.assign(N * W, 0.0);
  std::map<std::vector<double>, std::vector<std::size_t>> groups;  // ρ over materials -> wavelengths
  for (std::size_t w = 0; w < W; ++w) {
    std::vector<double> key(scene.materials.size());
    for (std::size_t m = 0; m < key.size(); ++m) key[m] = scene.materials[m].reflectance[w];
    groups[key].push_back(w);
  }
  for (const auto& [key, wavelengths] : groups) {
    check_cancel(control);
    const std::size_t w0 = wavelengths.front();
    std::vector<int> active;
    std::vector<double> D;
    double rho_max = 0;
    for (std::size_t i = 0; i < N; ++i) {
      const double r = rho[i * W + w0];
      if (r > 0 && need_factors) {
        active.push_back(static_cast<int>(i));
        D.push_back(sol.patches[i].area_m2 / r);
        rho_max = std::max(rho_max, r);
      }
    }
    std::map<std::vector<double>, std::vector<double>> solved;  // rhs -> solution (dedupe)
    for (std::size_t w : wavelengths) {
      // Known radiosity of black patches: B = M.
      for (std::size_t i = 0; i < N; ++i)
        if (!(rho[i * W + w] > 0 && need_factors)) sol.radiosity[i * W + w] = M[i * W + w];
      if (active.empty()) continue;
      std::vector<double> rhs(active.size());
      for (std::size_t r = 0; r < active.size(); ++r) {
        const std::size_t i = active[r];
        double s = sol.patches[i].area_m2 * (M[i * W + w] / rho[i * W + w] + E_direct[i * W + w]);
        for (std::size_t j = 0; j < N; ++j)
          if (!(rho[j * W + w] > 0) && M[j * W + w] != 0) s += G[i * N + j] * M[j * W + w];
        rhs[r] = s;
      }
      auto it = solved.find(rhs);
      if (it == solved.end()) {
        std::vector<double> x(active.size());
        for (std::size_t r = 0; r < active.size(); ++r) x[r] = rhs[r] / D[r];  // first bounce
        const CgResult cg = conjugate_gradient(G, N, active, D, rhs, x, scene.solver.tolerance,
                                               scene.solver.max_iterations, rho_max);
        sol.stats.iterations = std::max(sol.stats.iterations, cg.iterations);
        sol.stats.residual = std::max(sol.stats.residual, cg.residual);
        ++sol.stats.spectral_systems_solved;
        it = solved.emplace(rhs, std::move(x)).first;
      }
      for (std::size_t r = 0; r < active.size(); ++r)
        sol.radiosity[active[r] * W + w] = std::max(0.0, it->second[r]);
    }
  }
  // H_i = Σ_j F_ij B_j + E_i^direct
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
    std::vector<double> h(W);
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      std::fill(h.begin(), h.end(), 0.0);
      if (need_factors) {
        const double* row = &G[i * N];
        for (std::size_t j = 0; j < N; ++j) {
          if (row[j] == 0) continue;
          const double* b = &sol.radiosity[j * W];
          for (std::size_t w = 0; w < W; ++w) h[w] += row[j] * b[w];
        }
      }
      for (std::size_t w = 0; w < W; ++w)
        sol.irradiance[i * W + w] = h[w] / sol.patches[i].area_m2 + E_direct[i * W + w];
    }
  });
  sol.stats.time_solve_s = seconds_since(t0);
  report(0.9);

  // ---- probes: irradiance from every light and every patch at each point ----
  t0 = Clock::now();
  sol.probes.resize(scene.probes.size());
  for (std::size_t k = 0; k < scene.probes.size(); ++k) {
    const Probe& probe = scene.probes[k];
    auto& out = sol.probes[k].irradiance;
    out.assign(probe.points.size() * W, 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probe.points.size(), 1), [&](const auto& range) {
      for (std::size_t q = range.begin(); q != range.end(); ++q) {
        const Point3& p = probe.points[q];
        double* e = &out[q * W];
        for (const Light& light : scene.lights) {
          const double g = light_point_factor(light, p, probe.normal, vis);
          if (g == 0) continue;
          const auto& S = light_spectrum(light);
          for (std::size_t w = 0; w < W; ++w) e[w] += g * S[w];
        }
        for (std::size_t j = 0; j < N; ++j) {
          const double* b = &sol.radiosity[j * W];
          if (std::all_of(b, b + W, [](double v) { return v == 0; })) continue;
          const double f = point_triangle_factor(p, probe.normal, sol.patches[j].triangle);
          if (f == 0) continue;
          // Visible fraction of the patch from the point, kernel weighted like the patch pairs.
          const auto& samples = triangle_visibility_samples();
          double seen = 0, total = 0;
          int visible_count = 0;
          const Triangle& t = sol.patches[j].triangle;
          for (int s = 0; s < 16; ++s) {
            if (s == 4 && (visible_count == 0 || visible_count == 4)) break;
            const auto& ws = samples[s];
            const Point3 qs = barycentric(t.v[0], t.v[1], t.v[2], ws[0], ws[1], ws[2]);
            const Vector3 d = qs - p;
            const double r2 = length_squared(d);
            const double weight = std::max(0.0, dot(probe.normal, d)) *
                                      std::max(0.0, -dot(sol.patches[j].normal, d)) / (r2 * r2) + 1e-300;
            const bool v = vis.visible(p, qs);
            visible_count += v;
            seen += v ? weight : 0;
            total += weight;
          }
          const double fv = f * seen / total;
          for (std::size_t w = 0; w < W; ++w) e[w] += fv * b[w];
        }
      }
    });
    check_cancel(control);
  }
  sol.stats.time_probes_s = seconds_since(t0);

  // ---- energy balance: emitted = absorbed + escaped (all in W, integrated over the grid) ----
  const auto& wt = scene.grid.weight_nm;
  double emitted = 0, absorbed = 0, escaped = 0, max_closure = 0;
  for (const Light& light : scene.lights) {
    const double flux = light_flux_factor(light);
    const auto& S = light_spectrum(light);
    for (std::size_t w = 0; w < W; ++w) emitted += wt[w] * flux * S[w];
  }
  for (std::size_t i = 0; i < N; ++i) {
    const double A = sol.patches[i].area_m2;
    const double leak = need_factors ? 1 - row_sum[i] : 1;
    max_closure = std::max(max_closure, std::abs(leak));
    for (std::size_t w = 0; w < W; ++w) {
      const std::size_t k = i * W + w;
      const double non_point_direct = E_direct[k] - E_point[k];  // directional and ambient
      emitted += wt[w] * A * (M[k] + non_point_direct);
      absorbed += wt[w] * A * (1 - rho[k]) * sol.irradiance[k];
      escaped += wt[w] * A * sol.radiosity[k] * leak;
      escaped -= wt[w] * A * E_point[k];  // point flux that reached a patch did not escape
    }
  }
  for (const Light& light : scene.lights) {
    if (!std::holds_alternative<PointLight>(light)) continue;
    const double flux = light_flux_factor(light);
    const auto& S = light_spectrum(light);
    for (std::size_t w = 0; w < W; ++w) escaped += wt[w] * flux * S[w];
  }
  sol.stats.emitted_W = emitted;
  sol.stats.absorbed_W = absorbed;
  sol.stats.escaped_W = escaped;
  sol.stats.relative_imbalance = emitted > 0 ? (emitted - absorbed - escaped) / emitted : 0;
  sol.stats.max_closure_error = max_closure;
  sol.stats.rays = vis.rays_traced();
  sol.stats.time_total_s = seconds_since(t_start);
  report(1.0);
  return sol;
}

}  // namespace lambert
