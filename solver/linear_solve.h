// The radiosity linear systems (I − diag(ρ_k) F) B_k = b_k, one per distinct spectral system k, all
// sharing the form-factor matrix F. They are solved together by restarted GMRES in lockstep, so that
// each iteration streams F from memory once for every system (a matrix–matrix product) instead of
// once per system: F is the large operand, and spectral scenes have tens of systems.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace lambert {

// Successive over-relaxation of a two-block Gauss–Seidel iteration (consistently ordered), as in the
// hierarchical solver's closure balance: a plain sweep contracts the error by μ = β² (β the Jacobi
// iteration's spectral radius), sweeps over-relaxed by ω by the λ with (λ + ω − 1)² = λ ω² β², fastest
// at ω* = 2 / (1 + √(1 − β²)), where λ = ω* − 1 (Young). From a rate λ observed at ω (≤ ω*), returns
// ω* for the β that it implies (β capped at 0.995, ω* ≤ 1.82).
inline double optimal_overrelaxation(double rate, double omega) {
  const double beta = std::min(0.995, (rate + omega - 1) / (omega * std::sqrt(rate)));
  return 2 / (1 + std::sqrt(1 - beta * beta));
}

// The symmetric diagonal scaling that closes the rows of F flagged in `rows`: d with
// d_i Σ_j F_ij d_j = 1 for each such row that has a positive sum (d = 1 on the others, whose rows
// and columns are left as they are), so that F' = D F D closes those rows and keeps reciprocity
// A_i F'_ij = A_j F'_ji (`area`: A). F: n×n row-major with A_i F_ij = A_j F_ji. Stops when
// max |1 − Σ_j F'_ij| over those rows is below `tolerance` or after max_passes passes over F (each
// streams F once; the first measures the raw deviation).
//
// Newton's method in log d, each step's linear equations solved by conjugate gradients, and each
// step halved until it decreases Σ_i (A_i (1 − Σ_j F'_ij))² (Armijo); the symmetric Sinkhorn sweep
// d_i ← √(d_i / (F d)_i) while the rows are more than 10 % off, and for good once a step has been
// halved 6 times in vain. The sweep contracts the error only by about (1 − λ_min)/2 per pass near
// the answer (λ_min the most negative eigenvalue of D F D: 0.66 per pass in the cube room, 58
// passes to 1e-13), and hardly at all where F is nearly bipartite (plates facing each other across
// a narrow gap), where the full Newton step overshoots and the halved one does not.
struct RowScaling {
  std::vector<double> d;
  int passes = 0;
  int newton_steps = 0;          // Newton steps taken (each after a solve of a few passes)
  int step_halvings = 0;         // times a Newton step was halved (one pass each)
  double initial_deviation = 0;  // max |1 − Σ_j F_ij| over the closed rows, before the scaling
  double deviation = 0;          // the same after it (the last measured)
};
RowScaling symmetric_row_scaling(const std::vector<double>& F, std::size_t n, const std::vector<char>& rows,
                                 const std::vector<double>& area, double tolerance, int max_passes);

struct RadiositySystem {
  std::vector<double> rho;   // ρ_i of the unknowns (size n)
  std::vector<double> tau;   // τ_i of the unknowns (size n) where some face of a pane transmits; else empty
  std::vector<double> b;     // right-hand side (size n)
  std::vector<double> x;     // in: starting guess (size n); out: the solution
  int iterations = 0;        // out
  double residual = 0;       // out: final ‖b − A x‖ / ‖b‖
};

// F: n×n row-major (row sums ≤ 1). Each system stops when its relative residual bounds its relative
// error below `tolerance` (‖e‖/‖x‖ ≤ κ ‖r‖/‖b‖ with κ ≤ (1 + ρ_max)/(1 − ρ_max)). Throws SolveError
// (solver/radiosity.h) if a system does not converge in max_iterations, SolveCancelled if
// `cancelled()` becomes true.
void solve_radiosity_systems(const std::vector<double>& F, std::size_t n, std::vector<RadiositySystem>& systems,
                             double tolerance, int max_iterations, const std::function<bool()>& cancelled);

// FV[k] = F V[k] for every vector of a batch (n-vectors; F: n×n row-major). Each FV[k][i] sums
// F_ij V[k][j] over j in order from 0, skipping the zeros of F, as the plain loop rounds.
void multiply_dense(const std::vector<double>& F, std::size_t n, const std::vector<const double*>& V,
                    const std::vector<double*>& FV);

// Matrix-free form, for operators that are never stored as a matrix (the hierarchical solver's
// gather / push–pull, solver/hierarchical.h): apply_F(V, FV) sets FV[k] = F V[k] for every vector
// of one lockstep batch (n-vectors; all systems, or as many as 256 MB of Krylov bases allow). The
// systems are (I − diag(ρ_k) F) B_k = b_k as above, with the same stopping rule.
using BatchOperator =
    std::function<void(const std::vector<const double*>& V, const std::vector<double*>& FV)>;

// What the faces of diffusely transmitting panes (solver/pipeline/panes.h) gather of the other face:
// row r's face i = row[r] passes on τ_i Σ_j P_ij H_j, where P_ij (entries [start[r], start[r+1]) of
// col and weight) is the share of face i's area that lies on face j of the other side. With it the
// systems are (I − diag(ρ_k) F − diag(τ_k) P F) B_k = b_k: a face's radiosity is ρ H of its own
// irradiance plus τ P H of its twin's. A clear pane's row (rays_carry_direct) passes on only the
// twin's interreflected irradiance: the sources' direct light crosses it by rays (glazing.h).
struct PaneTransfer {
  std::vector<int> row;
  std::vector<char> rays_carry_direct;  // per row
  std::vector<std::size_t> start{0};
  std::vector<int> col;
  std::vector<double> weight;
  bool empty() const { return row.empty(); }
  // out[row[r]] = Σ_s weight_s in[col_s] for every row r (other entries of `out` untouched).
  void apply(const double* in, double* out) const {
    for (std::size_t r = 0; r < row.size(); ++r) {
      double sum = 0;
      for (std::size_t e = start[r]; e < start[r + 1]; ++e) sum += weight[e] * in[col[e]];
      out[row[r]] = sum;
    }
  }
};

void solve_radiosity_systems(std::size_t n, const BatchOperator& apply_F, std::vector<RadiositySystem>& systems,
                             double tolerance, int max_iterations, const std::function<bool()>& cancelled,
                             const PaneTransfer* transfer = nullptr);

}  // namespace lambert
