// Lockstep restarted GMRES for many radiosity systems sharing F (see linear_solve.h).
#include "solver/linear_solve.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "solver/radiosity.h"

namespace lambert {
namespace {

constexpr int kRestart = 40;
// Systems per lockstep batch: at least 16, and as many as fit in kKrylovBudget bytes of Krylov bases
// (kRestart + 1 vectors of n per system), so that small and medium scenes solve every wavelength in
// one batch and stream F once per iteration for all of them.
constexpr std::size_t kMinBatch = 16;
constexpr double kKrylovBudget = 256.0 * (1 << 20);

double norm(const double* v, std::size_t n) {
  double s = 0;
  for (std::size_t i = 0; i < n; ++i) s += v[i] * v[i];
  return std::sqrt(s);
}

// Y[k] = V[k] − ρ_k ⊙ (F V[k]) for the systems in `batch`; V and Y hold one n-vector per system.
using SystemOperator = std::function<void(const std::vector<RadiositySystem*>& batch,
                                          const std::vector<const double*>& V, const std::vector<double*>& Y)>;

// acc[k] += F_ij · vt[j·K + k] over the listed columns j of one row (`row`: the row's n entries), in
// blocks of 16 accumulators that stay in registers over the list. Compiled for AVX2 and for the
// baseline and chosen at load time; neither uses FMA, and each k sums over j in order, so both round
// as the plain loop does.
__attribute__((target_clones("avx2", "default"))) void gather_row(const double* row, const std::uint32_t* columns,
                                                                  std::size_t count, const double* vt, std::size_t K,
                                                                  double* acc) {
  constexpr std::size_t kBlock = 16;
  std::size_t k0 = 0;
  for (; k0 + kBlock <= K; k0 += kBlock) {
    double a[kBlock];
    std::copy(acc + k0, acc + k0 + kBlock, a);
    for (std::size_t c = 0; c < count; ++c) {
      const double f = row[columns[c]];
      const double* v = vt + static_cast<std::size_t>(columns[c]) * K + k0;
      for (std::size_t k = 0; k < kBlock; ++k) a[k] += f * v[k];
    }
    std::copy(a, a + kBlock, acc + k0);
  }
  for (std::size_t c = 0; c < count && k0 < K; ++c) {
    const double f = row[columns[c]];
    const double* v = vt + static_cast<std::size_t>(columns[c]) * K;
    for (std::size_t k = k0; k < K; ++k) acc[k] += f * v[k];
  }
}

}  // namespace

void multiply_dense(const std::vector<double>& F, std::size_t n, const std::vector<const double*>& V,
                    const std::vector<double*>& FV) {
  const std::size_t K = V.size();
  // The K vectors interleaved (VT[j·K + k] = V[k][j]), so that each nonzero F_ij updates K
  // contiguous accumulators: one vectorised loop per entry instead of K scattered loads.
  // (Thread-local to the caller; the workers below reach it through the pointer.)
  thread_local std::vector<double> VT;
  VT.resize(n * K);
  double* vt = VT.data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    for (std::size_t j = range.begin(); j != range.end(); ++j)
      for (std::size_t k = 0; k < K; ++k) vt[j * K + k] = V[k][j];
  });
  // Rows in ranges, columns in tiles whose part of VT stays in cache while the range's rows read it
  // (the whole of VT did not: 0.7 MB for the Cornell box's 61 systems). Each row sums its columns in
  // order, tile after tile.
  constexpr std::size_t kTile = 256;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16), [&](const auto& range) {
    std::vector<double> acc(range.size() * K, 0.0);
    // A row's nonzero columns, listed first without a branch per entry: most of a room's F is zero
    // (78 % of the Cornell box's), and a test per entry mispredicted.
    std::vector<std::uint32_t> columns(kTile);
    for (std::size_t j0 = 0; j0 < n; j0 += kTile) {
      const std::size_t j1 = std::min(n, j0 + kTile);
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const double* row = &F[i * n];
        std::size_t count = 0;
        for (std::size_t j = j0; j < j1; ++j) {
          columns[count] = static_cast<std::uint32_t>(j);
          count += row[j] != 0;
        }
        gather_row(row, columns.data(), count, vt, K, &acc[(i - range.begin()) * K]);
      }
    }
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      for (std::size_t k = 0; k < K; ++k) FV[k][i] = acc[(i - range.begin()) * K + k];
  });
}

namespace {

// Y[k] = V[k] − ρ_k ⊙ (F V[k]).
void apply_dense(const std::vector<double>& F, std::size_t n, const std::vector<RadiositySystem*>& batch,
                 const std::vector<const double*>& V, const std::vector<double*>& Y) {
  multiply_dense(F, n, V, Y);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    for (std::size_t k = 0; k < batch.size(); ++k)
      for (std::size_t i = range.begin(); i != range.end(); ++i) Y[k][i] = V[k][i] - batch[k]->rho[i] * Y[k][i];
  });
}

struct Krylov {
  std::vector<std::vector<double>> V;   // kRestart + 1 basis vectors
  std::vector<std::vector<double>> H;   // (kRestart + 1) × kRestart Hessenberg, rotated in place
  std::vector<double> cs, sn, g, w;
  double b_norm = 0, target = 0, beta = 0;
  int m = 0;              // basis size in the current cycle
  bool done = false;      // converged
  bool cycle_open = false;
  explicit Krylov(std::size_t n)
      : V(kRestart + 1, std::vector<double>(n)), H(kRestart + 1, std::vector<double>(kRestart, 0.0)),
        cs(kRestart), sn(kRestart), g(kRestart + 1), w(n) {}
};

void update_solution(Krylov& s, RadiositySystem& sys, std::size_t n) {
  std::vector<double> y(s.m);
  for (int i = s.m - 1; i >= 0; --i) {
    double v = s.g[i];
    for (int j = i + 1; j < s.m; ++j) v -= s.H[i][j] * y[j];
    if (s.H[i][i] == 0) throw SolveError("the radiosity system is singular (reflectance 1 in a closed scene?)");
    y[i] = v / s.H[i][i];
  }
  for (int i = 0; i < s.m; ++i)
    for (std::size_t k = 0; k < n; ++k) sys.x[k] += y[i] * s.V[i][k];
}

void solve_batch(const SystemOperator& apply_batch, std::size_t n, std::vector<RadiositySystem*>& batch,
                 double tolerance, int max_iterations, const std::function<bool()>& cancelled) {
  std::vector<Krylov> state;
  state.reserve(batch.size());
  for (RadiositySystem* sys : batch) {
    Krylov& s = state.emplace_back(n);
    s.b_norm = norm(sys->b.data(), n);
    // |ρ|: in rgb mode (solver/rgb_model.h) channel reflectances are signed and may exceed 1. For
    // |ρ| ≥ 1 there is no a-priori bound; ask for a residual 1e6 below the tolerance, which GMRES
    // reaches in double precision unless the system is singular (ρ = 1 in a closed scene).
    // A pane's face gives out ρ + τ of what it receives (PaneTransfer).
    double rho_max = 0;
    for (std::size_t i = 0; i < sys->rho.size(); ++i)
      rho_max = std::max(rho_max, std::abs(sys->rho[i]) + (sys->tau.empty() ? 0.0 : std::abs(sys->tau[i])));
    const double kappa = rho_max < 1 ? (1 + rho_max) / (1 - rho_max) : 1e6;
    s.target = tolerance / kappa;
    if (s.b_norm == 0) {
      std::fill(sys->x.begin(), sys->x.end(), 0.0);
      s.done = true;
    }
  }
  std::vector<RadiositySystem*> live;
  std::vector<const double*> in;
  std::vector<double*> out;
  for (int iteration = 0;; ++iteration) {
    if (cancelled && cancelled()) throw SolveCancelled();
    // Systems that start a cycle need their true residual r = b − A x first (one batched product).
    live.clear(), in.clear(), out.clear();
    for (std::size_t k = 0; k < batch.size(); ++k)
      if (!state[k].done && !state[k].cycle_open) {
        live.push_back(batch[k]);
        in.push_back(batch[k]->x.data());
        out.push_back(state[k].w.data());
      }
    if (!live.empty()) apply_batch(live, in, out);
    for (std::size_t k = 0; k < batch.size(); ++k) {
      Krylov& s = state[k];
      if (s.done || s.cycle_open) continue;
      RadiositySystem& sys = *batch[k];
      for (std::size_t i = 0; i < n; ++i) s.V[0][i] = sys.b[i] - s.w[i];
      s.beta = norm(s.V[0].data(), n);
      sys.residual = s.beta / s.b_norm;
      if (sys.residual <= s.target) {
        s.done = true;
        continue;
      }
      if (sys.iterations >= max_iterations)
        throw SolveError("the radiosity solve did not converge in " + std::to_string(max_iterations) +
                         " iterations (relative residual " + std::to_string(sys.residual) +
                         "; is the reflectance 1 in a closed scene?)");
      for (double& v : s.V[0]) v /= s.beta;
      std::fill(s.g.begin(), s.g.end(), 0.0);
      s.g[0] = s.beta;
      s.m = 0;
      s.cycle_open = true;
    }
    // One Arnoldi step for every open cycle, with one batched product.
    live.clear(), in.clear(), out.clear();
    std::vector<std::size_t> index;
    for (std::size_t k = 0; k < batch.size(); ++k)
      if (!state[k].done && state[k].cycle_open) {
        live.push_back(batch[k]);
        in.push_back(state[k].V[state[k].m].data());
        out.push_back(state[k].w.data());
        index.push_back(k);
      }
    if (live.empty()) return;
    apply_batch(live, in, out);
    for (std::size_t k : index) {
      Krylov& s = state[k];
      RadiositySystem& sys = *batch[k];
      const int m = s.m;
      for (int i = 0; i <= m; ++i) {  // modified Gram–Schmidt
        double h = 0;
        for (std::size_t q = 0; q < n; ++q) h += s.w[q] * s.V[i][q];
        s.H[i][m] = h;
        for (std::size_t q = 0; q < n; ++q) s.w[q] -= h * s.V[i][q];
      }
      const double h_next = norm(s.w.data(), n);
      if (h_next > 0)
        for (std::size_t q = 0; q < n; ++q) s.V[m + 1][q] = s.w[q] / h_next;
      for (int i = 0; i < m; ++i) {  // previous Givens rotations on the new column
        const double t = s.cs[i] * s.H[i][m] + s.sn[i] * s.H[i + 1][m];
        s.H[i + 1][m] = -s.sn[i] * s.H[i][m] + s.cs[i] * s.H[i + 1][m];
        s.H[i][m] = t;
      }
      const double r = std::hypot(s.H[m][m], h_next);
      s.cs[m] = r > 0 ? s.H[m][m] / r : 1;
      s.sn[m] = r > 0 ? h_next / r : 0;
      s.H[m][m] = r;
      s.g[m + 1] = -s.sn[m] * s.g[m];
      s.g[m] = s.cs[m] * s.g[m];
      s.m = m + 1;
      ++sys.iterations;
      const double estimate = std::abs(s.g[m + 1]) / s.b_norm;
      if (estimate <= s.target || h_next == 0 || s.m == kRestart || sys.iterations >= max_iterations) {
        update_solution(s, sys, n);
        s.cycle_open = false;  // the next pass checks the true residual
      }
    }
    (void)iteration;
  }
}

void solve_all(const SystemOperator& apply_batch, std::size_t n, std::vector<RadiositySystem>& systems,
               double tolerance, int max_iterations, const std::function<bool()>& cancelled) {
  const std::size_t per_batch = std::max<std::size_t>(
      kMinBatch, static_cast<std::size_t>(kKrylovBudget / (8.0 * (kRestart + 1) * std::max<std::size_t>(n, 1))));
  for (std::size_t start = 0; start < systems.size(); start += per_batch) {
    std::vector<RadiositySystem*> batch;
    for (std::size_t k = start; k < std::min(systems.size(), start + per_batch); ++k) batch.push_back(&systems[k]);
    solve_batch(apply_batch, n, batch, tolerance, max_iterations, cancelled);
  }
}

}  // namespace

RowScaling symmetric_row_scaling(const std::vector<double>& F, std::size_t n, const std::vector<char>& rows,
                                 const std::vector<double>& area, double tolerance, int max_passes) {
  std::vector<std::size_t> R;  // the rows to close (those with a positive sum, after the first pass)
  for (std::size_t i = 0; i < n; ++i)
    if (rows[i]) R.push_back(i);
  RowScaling out;
  std::vector<double>& d = out.d;
  d.assign(n, 1.0);
  int& passes = out.passes;
  // out_r = Σ_j F_rj u_j for the rows r in R (u: an n-vector), one pass over those rows of F.
  auto multiply = [&](const std::vector<double>& u, std::vector<double>& out) {
    ++passes;
    out.resize(R.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, R.size(), 32), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        const double* row = &F[R[k] * n];
        double t = 0;
        for (std::size_t j = 0; j < n; ++j) t += row[j] * u[j];
        out[k] = t;
      }
    });
  };
  // The state at a scaling d: t = F d on R, w = d ⊙ t (the row sums of D F D), the deviation
  // max |1 − w| and the merit Σ (A (1 − w))², which a Newton step decreases along its direction.
  struct State {
    std::vector<double> d, t, w;
    double deviation = 0, merit = 0;
  };
  State now, base;  // base: where the pending Newton step started
  std::vector<double> u(n, 0.0), e, r, z, p, q;
  bool newton = true, pending = false;  // Newton allowed; a Newton step awaits its check
  double alpha = 1;                     // the pending step's length
  while (true) {
    multiply(d, now.t);
    if (passes == 1) {  // the raw row sums: rows that gather nothing are left out
      std::size_t kept = 0;
      for (std::size_t k = 0; k < R.size(); ++k)
        if (now.t[k] > 0) R[kept] = R[k], now.t[kept++] = now.t[k];
      R.resize(kept), now.t.resize(kept);
    }
    const std::size_t m = R.size();
    now.w.resize(m);
    now.deviation = now.merit = 0;
    for (std::size_t k = 0; k < m; ++k) {
      now.w[k] = d[R[k]] * now.t[k];
      now.deviation = std::max(now.deviation, std::abs(1 - now.w[k]));
      now.merit += std::pow(area[R[k]] * (1 - now.w[k]), 2);
    }
    if (passes == 1) out.initial_deviation = now.deviation;
    if (now.deviation < tolerance || passes >= max_passes) break;
    if (pending) {
      // The step is kept if it decreased the merit (Armijo's condition); otherwise it is halved,
      // and after 6 halvings given up for the sweeps, from where it started.
      if (now.merit <= (1 - 1e-4 * alpha) * base.merit) {
        pending = false;
      } else if ((alpha /= 2) >= 1.0 / 64) {
        ++out.step_halvings;
        for (std::size_t k = 0; k < m; ++k) d[R[k]] = base.d[R[k]] * std::exp(alpha * e[k]);
        continue;
      } else {
        pending = newton = false;
        std::swap(now, base);
        d = now.d;
      }
    }
    // Newton once the rows are within 10 % of closed; the sweeps before that, or once a Newton
    // step has failed.
    if (!newton || now.deviation >= 0.1) {
      for (std::size_t k = 0; k < m; ++k) d[R[k]] = std::sqrt(d[R[k]] / now.t[k]);
      continue;
    }
    // The step in x = log d, where the scaling minimises the convex Σ_ij A_i F_ij d_i d_j / 2 −
    // Σ_i A_i log d_i: K e = A ⊙ (1 − w) with the Hessian K e = A ⊙ (w ⊙ e + d ⊙ F (d ⊙ e)),
    // symmetric and diagonally dominant, so positive semi-definite; conjugate gradients solve it,
    // preconditioned by diag(A ⊙ w), to 1e-3 of the deviation (the step's own error is then below
    // the quadratic term's). The update d ⊙ exp(α e) keeps d positive.
    const std::vector<double>& w = now.w;
    auto apply_K = [&](const std::vector<double>& x, std::vector<double>& out) {
      for (std::size_t k = 0; k < m; ++k) u[R[k]] = d[R[k]] * x[k];
      multiply(u, out);
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t i = R[k];
        out[k] = area[i] * (w[k] * x[k] + d[i] * out[k]);
      }
    };
    e.assign(m, 0.0), r.resize(m), z.resize(m), p.resize(m), q.resize(m);
    double rz = 0;
    for (std::size_t k = 0; k < m; ++k) {
      r[k] = area[R[k]] * (1 - w[k]);
      z[k] = r[k] / (area[R[k]] * w[k]);
      p[k] = z[k];
      rz += r[k] * z[k];
    }
    const double goal = std::max(1e-3 * now.deviation, 0.1 * tolerance);
    bool moved = false;
    while (passes < max_passes) {
      apply_K(p, q);
      double pq = 0;
      for (std::size_t k = 0; k < m; ++k) pq += p[k] * q[k];
      if (!(pq > 0)) break;  // p in K's null space (rounding): the step so far
      moved = true;
      const double step = rz / pq;
      double left = 0, rz_next = 0;
      for (std::size_t k = 0; k < m; ++k) {
        e[k] += step * p[k];
        r[k] -= step * q[k];
        left = std::max(left, std::abs(r[k]) / area[R[k]]);
        z[k] = r[k] / (area[R[k]] * w[k]);
        rz_next += r[k] * z[k];
      }
      if (left <= goal) break;
      const double beta = rz_next / rz;
      rz = rz_next;
      for (std::size_t k = 0; k < m; ++k) p[k] = z[k] + beta * p[k];
    }
    if (!moved) {  // no direction to step along: the sweeps from here
      newton = false;
      continue;
    }
    ++out.newton_steps;
    base = now;
    base.d = d;
    pending = true, alpha = 1;
    for (std::size_t k = 0; k < m; ++k) d[R[k]] *= std::exp(e[k]);
  }
  out.deviation = now.deviation;
  return out;
}

void solve_radiosity_systems(const std::vector<double>& F, std::size_t n, std::vector<RadiositySystem>& systems,
                             double tolerance, int max_iterations, const std::function<bool()>& cancelled) {
  solve_all([&](const std::vector<RadiositySystem*>& batch, const std::vector<const double*>& V,
                const std::vector<double*>& Y) { apply_dense(F, n, batch, V, Y); },
            n, systems, tolerance, max_iterations, cancelled);
}

void solve_radiosity_systems(std::size_t n, const BatchOperator& apply_F, std::vector<RadiositySystem>& systems,
                             double tolerance, int max_iterations, const std::function<bool()>& cancelled,
                             const PaneTransfer* transfer) {
  const bool panes = transfer && !transfer->empty();
  solve_all(
      [&](const std::vector<RadiositySystem*>& batch, const std::vector<const double*>& V,
          const std::vector<double*>& Y) {
        apply_F(V, Y);  // Y = F V, then Y = V − ρ ⊙ Y − τ ⊙ P Y in place
        std::vector<std::vector<double>> PY(panes ? batch.size() : 0);
        for (std::size_t k = 0; k < PY.size(); ++k) {
          PY[k].assign(n, 0.0);
          transfer->apply(Y[k], PY[k].data());
        }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
          for (std::size_t k = 0; k < batch.size(); ++k) {
            const RadiositySystem& sys = *batch[k];
            for (std::size_t i = range.begin(); i != range.end(); ++i) Y[k][i] = V[k][i] - sys.rho[i] * Y[k][i];
            if (panes && !sys.tau.empty())
              for (std::size_t i = range.begin(); i != range.end(); ++i) Y[k][i] -= sys.tau[i] * PY[k][i];
          }
        });
      },
      n, systems, tolerance, max_iterations, cancelled);
}

}  // namespace lambert
