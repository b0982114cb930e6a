#include "solver/hierarchical/closure.h"

#include <algorithm>
#include <cmath>

#include "solver/linear_solve.h"

namespace lambert::hierarchical {
namespace {

constexpr int kMaxBalanceSweeps = 100;  // the error usually halves per sweep

// One balance: the sweeps over rows and columns (see closure.h).
class Balancer {
 public:
  Balancer(Hierarchy& h, const std::vector<Hemisphere>& closed, const std::vector<double>& sends,
           const std::vector<char>& emits, const std::vector<Patch>& patches)
      : h_(h), closed_(closed), sends_(sends), emits_(emits), N_(h.leaves.size()), R_(N_), G_(N_),
        cg_(N_), areas_(N_), cols_(N_), full_row_(N_), root_of_(N_), root_sent_(h.roots.size()),
        root_gathered_(h.roots.size()) {
    for (std::size_t j = 0; j < N_; ++j) {
      root_of_[j] = h.root_slot(h.elements[h.leaves[j]].root);
      areas_[j] = patches[j].area_m2;
    }
    source_weights();
  }
  // The largest row-sum error of a closed leaf before any scaling; marks the rows held at 1.
  double raw_error();
  double rows(bool update, double omega);
  double columns(bool update, double omega);

 private:
  void source_weights();
  static double relax(double old, double target, double omega) {
    return omega == 1 ? target : old * std::pow(target / old, omega);
  }

  Hierarchy& h_;
  const std::vector<Hemisphere>& closed_;
  const std::vector<double>& sends_;
  const std::vector<char>& emits_;
  std::size_t N_;
  double floor_ = 0;       // the radiosity below which links take the correction alike (source_weights)
  double max_weight_ = 1;  // the largest g_j
  std::vector<double> R_, G_, cg_, areas_, cols_;
  std::vector<char> full_row_;
  std::vector<int> root_of_;  // index into h.roots
  std::vector<double> root_sent_, root_gathered_;
};

// Where a row's links miss a closed hemisphere, which of them err? The oracle bounds each link's
// transfer error B_s ΔF by the same ε, so the factor error it lets a link from source s carry grows as
// 1 / B_s: a bright emitter's links are refined until their factors are nearly exact, a dim wall's
// may err by the whole row's miss. So a row's correction is shared by its links in proportion to
// F_ij g_j, g_j = 1 / max(B_j, B̄), B_j what leaf j sends and B̄ its area mean (below it, links are
// held by their geometry as much as by the budget, and are weighted alike). A uniform radiosity
// gives the plain row scale. In the lit sphere room, scaling rows whole moved the panel's exact
// direct light on the spheres' tops by −0.11 % (docs/BENCHMARKS.md).
void Balancer::source_weights() {
  double sent = 0, area = 0;
  for (std::size_t j = 0; j < N_; ++j) sent += areas_[j] * sends_[j], area += areas_[j];
  floor_ = area > 0 ? sent / area : 0;
  h_.source_weight.assign(N_, 1.0);
  max_weight_ = 1;
  if (!(floor_ > 0)) return;
  for (std::size_t j = 0; j < N_; ++j) h_.source_weight[j] = 1 / std::max(sends_[j], floor_);
  max_weight_ = 1 / floor_;
}

double Balancer::raw_error() {
  const std::vector<double> ones(N_, 1.0);
  h_.apply({ones.data()}, {R_.data()}, false);  // Σ_j F_ij, unscaled
  // Rows held at 1: closed leaves, and leaking ones (some probe rays met back faces) whose links
  // already gather a whole hemisphere. Columns held at 1: closed leaves; capped at 1: open ones.
  double error = 0;
  for (std::size_t i = 0; i < N_; ++i) {
    if (closed_[i] == Hemisphere::Closed && R_[i] > 0) error = std::max(error, std::abs(1 - R_[i]));
    full_row_[i] = closed_[i] == Hemisphere::Closed || (closed_[i] == Hemisphere::Leaking && R_[i] >= 1);
  }
  return error;
}

// Where `update`, each held row moves toward its target, d_i R_i + λ_i G_i = 1 with R = F c and G =
// F (c ∘ g): by λ_i, with d_i = 1, unless that would turn a link's factor negative (λ_i g_j < −1, a
// row whose excess is more than its links from dim sources carry), and then by d_i, λ_i = 0, as a
// plain scale. Returns the rows' error before.
double Balancer::rows(bool update, double omega) {
  for (std::size_t j = 0; j < N_; ++j) cg_[j] = h_.source_scale[j] * h_.source_weight[j];
  h_.apply({h_.source_scale.data(), cg_.data()}, {R_.data(), G_.data()}, false);
  double error = 0;
  for (std::size_t i = 0; i < N_; ++i) {
    const double S = h_.leaf_scale[i] * R_[i] + h_.row_shift[i] * G_[i];
    if (full_row_[i] && S > 0) error = std::max(error, std::abs(1 - S));
    if (!update) continue;
    if (!(R_[i] > 0 && (full_row_[i] || R_[i] > 1))) {
      h_.leaf_scale[i] = 1, h_.row_shift[i] = 0;
      continue;
    }
    // (G_i > 0 where R_i > 0: every g_j > 0.)
    const double shift = (1 - R_[i]) / G_[i];
    if (shift * max_weight_ >= -1) {  // then no λ_i g_j < −1
      h_.leaf_scale[i] = 1;
      h_.row_shift[i] += omega * (shift - h_.row_shift[i]);
    } else {
      h_.leaf_scale[i] = relax(h_.leaf_scale[i], 1 / R_[i], omega);
      h_.row_shift[i] = 0;
    }
  }
  return error;
}

// Where `update`, each held column moves toward its target; returns the columns' error before.
double Balancer::columns(bool update, double omega) {
  h_.transpose_rows_scaled(areas_.data(), cols_.data());  // Σ_i A_i F_ij (d_i + λ_i g_j)
  // Closed emitting leaves: per root, what the scene gathers of the power they send, over that power.
  std::fill(root_sent_.begin(), root_sent_.end(), 0.0);
  std::fill(root_gathered_.begin(), root_gathered_.end(), 0.0);
  for (std::size_t j = 0; j < N_; ++j) {
    if (closed_[j] != Hemisphere::Closed || !emits_[j]) continue;
    root_sent_[root_of_[j]] += sends_[j] * areas_[j];
    root_gathered_[root_of_[j]] += sends_[j] * cols_[j] * h_.source_scale[j];
  }
  double error = 0;
  for (std::size_t j = 0; j < N_; ++j) {
    double& c = h_.source_scale[j];
    if (closed_[j] == Hemisphere::Closed && emits_[j]) {
      // What the scene gathers of the power the root's emitting leaves send, over that power.
      const double sent = root_sent_[root_of_[j]];
      const double C = root_gathered_[root_of_[j]] / sent;
      if (!(sent > 0 && C > 0)) {
        if (update) c = 1.0;  // sends nothing: no power to conserve
        continue;
      }
      error = std::max(error, std::abs(1 - C));
      if (update) c = relax(c, c / C, omega);
    } else {  // reflecting leaves: free, but an open one never gives away more than it sends
      const double t = cols_[j] / areas_[j];
      if (update) c = closed_[j] == Hemisphere::Open && t > 1 ? relax(c, 1 / t, omega) : 1.0;
    }
  }
  return error;
}

}  // namespace

double balance_target(double share, double rho_max) {
  return std::max(kBalanceFloor, share * (1 - std::min(rho_max, 1.0)));
}

Balanced balance(Hierarchy& h, BalanceState& state, const std::vector<Hemisphere>& closed,
                 const std::vector<double>& sends, const std::vector<char>& emits, const std::vector<Patch>& patches,
                 double target, bool final_balance, const SolveControl& control) {
  const std::size_t N = h.leaves.size();
  if (h.leaf_scale.size() != N) h.leaf_scale.assign(N, 1.0);
  if (h.source_scale.size() != N) h.source_scale.assign(N, 1.0);
  if (h.row_shift.size() != N) h.row_shift.assign(N, 0.0);
  Balancer balancer(h, closed, sends, emits, patches);
  const double raw_error = balancer.raw_error();
  // Over-relaxed: a held scale moves ω times as far as a plain sweep would take it, on a log scale
  // (a row's shift λ, linearly). The previous round's ω, fitted to nearly the same links, is the
  // starting point if that round converged: an ω read from a stall (rates near 1) is far too large,
  // and started the next round of the lit room above at ω = 1.8, with errors of 0.2 that 40 sweeps
  // brought down to 1e-4 only.
  double omega = state.omega;
  const double stop_at = std::max(target, target >= state.stalled_aim ? state.stalled_at : 0.0);
  // Stops at convergence, or when ten sweeps have not cut the error tenfold (leaves partly inside
  // solids, whose rows and columns are free, can make the balance crawl: it would cost sweeps, not
  // accuracy). Healthy sweeps gain 10⁴ in ten, plain or over-relaxed. Over-relaxed sweeps do keep
  // crawling down, at about 0.8 a sweep, where plain ones stall; a rule that asks only for halving in
  // ten sweeps lets a lit room of 984 320 patches spend 100 sweeps a round.
  double best = 1e300, best_ten_ago = 1e300;
  std::vector<double> errors;  // of the sweeps since ω last changed
  for (int sweep = 0; sweep < kMaxBalanceSweeps; ++sweep) {
    control.check_cancel();
    const double row_error = balancer.rows(true, omega);
    const double col_error = balancer.columns(true, omega);
    const double error = std::max(row_error, col_error);
    best = std::min(best, error);
    if (error < stop_at) break;
    errors.push_back(error);
    const std::size_t n = errors.size();
    if (n >= 4) {
      const double rate = std::sqrt(errors[n - 1] / errors[n - 3]);  // per sweep, over the last two
      if (rate < 1) {  // (a rate below ω − 1 is faster than the model allows: nothing to infer)
        const double omega_best = rate >= omega - 1 ? optimal_overrelaxation(rate, omega) : omega;
        if (omega_best > omega + 0.02) {
          omega = omega_best;
          errors.clear();
        }
      } else if (omega > 1) {  // not converging: back to plain sweeps
        omega = 1;
        errors.clear();
      }
    }
    if (sweep % 10 == 9) {
      if (best > 0.1 * best_ten_ago) break;
      best_ten_ago = best;
    }
  }
  const bool reached = best < stop_at;
  state.omega = reached ? omega : 1;
  if (!reached) state.stalled_at = best, state.stalled_aim = target;
  // Rows last: a furnace with ρ = 0.999 multiplies a row's error by 1000. Where the sweeps stopped
  // short of convergence, the columns keep a small error, which the energy certificate shows as
  // imbalance, and which the final balance's residual reports (one sweep more, not updating).
  balancer.rows(true, 1);
  if (!final_balance) return {raw_error, 0};
  const double row_residual = balancer.rows(false, 1);
  return {raw_error, std::max(row_residual, balancer.columns(false, 1))};
}

}  // namespace lambert::hierarchical
