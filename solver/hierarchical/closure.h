// The closure of the hierarchical operator.
//
// Closure and conservation. The links are estimates (rays, fits, cluster approximations) and not
// reciprocal, so their row sums Σ_j F_ij (what leaf i gathers of a uniform radiosity) and their
// area-weighted column sums Σ_i A_i F_ij / A_j (what the scene gathers of leaf j's power) both miss 1
// in a closed hemisphere. Correcting rows alone makes a furnace exact but not the energy: the power
// shot by j is received as its column sum. So rows and columns are corrected together (Sinkhorn–Knopp,
// alternating): a closed leaf's row sum becomes 1, and so does the column sum of a closed root's
// emitting leaves together; an open leaf's are only kept from exceeding 1 (never more than a
// hemisphere, never more than was shot).
//
// A row's correction goes where its links may err: F'_ij = c_j F_ij (1 + λ_i g_j), with g_j =
// 1 / max(B_j, B̄) (Balancer::source_weights in closure.cpp, which says why). A row whose excess
// would turn a factor negative (λ_i g_j < −1) is scaled whole instead, F'_ij = c_j d_i F_ij.
//
// Columns are the less accurate side, and only the emitters' are held. A link reads its source at
// one point, and in the transpose hands the source's leaves their shares by a linear field
// (links.h), while the kernel from the receiver may vary more than linearly over the source: each
// leaf's column misses 1 by a few per cent (3 % rms in the issue-4 room) even where every row is
// exact. Holding a reflecting leaf's column at 1 rescales what it sends to every receiver, which
// moved the rows of leaves at the room's edges by up to 4 % (docs/BENCHMARKS.md, "One engine: the
// hierarchical method converges"), and a dim room's light, whose links are the coarsest, by 1e-3 of
// itself (docs/BENCHMARKS.md, "The held balance stalls on an inconsistency"). Left free, the misses
// follow the light, and a closed scene gathers up to 8e-4 more or less than its leaves send, which
// the certificate counts as escaped (docs/BENCHMARKS.md, "A closed scene gathers what it sends").
// The reflecting roots cannot all be held at 1 as well: the closed rows fix the columns'
// area-weighted total, Σ_j A_j C_j = Σ_i A_i, and the roots' light-weighted targets ask for another
// (docs/BENCHMARKS.md, "The held balance stalls on an inconsistency"). Emitting leaves, whose
// exitance is given, are held together per root, weighted by what each sends, so that a closed
// scene gathers all the power they emit; held leaf by leaf, they move a floor's light by up to 8 %
// in a black room lit by its floor. Open leaves are only kept from giving away more than they send.
//
// Each sweep is one pass of F over the links for the rows (R = F c and G = F (c ∘ g) together) and
// two of Fᵀ for the columns (the part of each row scaled by d, and the part shifted by λ); plain
// sweeps shrink the error by about 0.65 each in the sphere furnaces, over-relaxed ones
// (optimal_overrelaxation, solver/linear_solve.h) by about 0.3. The scales and the over-relaxation
// of the previous refinement round, whose links mostly remain, are the starting point. The sweeps
// stop once every held row and column is within `target` of 1 (balance_target), or where a previous
// balance stalled short of a target at least as tight (a stall on the way to the oracle's target
// does not stop the final balance): a lit room's sweeps stall at 1e-6 to 1e-5 (leaves whose rows
// and columns are nearly free), far below the links' own errors, and aiming lower cost the
// 985 435-patch lit sphere room 20 sweeps a round. Returns the largest row-sum error of a closed
// leaf before any scaling (stats.max_closure_error) and, for the final balance, the largest error
// of a held row or column after it (stats.closure_residual).
//
// A row-sum error ε moves the radiosity of a closed scene by about ε / (1 − ρ) of itself (the furnace:
// B = M / (1 − ρ(1 − ε)); where nothing reflects, the irradiance by ε), so the error that moves it by
// `share` is share × (1 − ρ_max) (balance_target). A tighter aim whatever the reflectance stalls near
// 1e-6 and costs sweeps without moving the radiosity (docs/BENCHMARKS.md, "The closure balance aims at
// what the radiosity needs").
#pragma once

#include <vector>

#include "solver/hierarchical/hierarchy.h"
#include "solver/visible_fraction.h"

namespace lambert::hierarchical {

// How closely balance() holds closed rows and columns at 1, as a share of the radiosity it moves (see
// balance_target): the final operator's, and the earlier rounds', whose solutions only tell the
// refiner which links carry the most.
inline constexpr double kFinalBalance = 1e-5;
inline constexpr double kOracleBalance = 1e-3;
inline constexpr double kBalanceFloor = 1e-11;  // the aim where 1 − ρ_max vanishes

// The error of a row or column sum that moves the radiosity by `share` of itself.
double balance_target(double share, double rho_max);

// What one balance hands the next: the scales live in the Hierarchy (F' = D_r F D_c).
struct BalanceState {
  double omega = 1;        // ω of the last balance if it reached its target (the next one's start)
  double stalled_at = 0;   // the error where the last balance stalled short of its target (0: none)
  double stalled_aim = 0;  // its target: a stop only for balances whose target is no tighter
};

struct Balanced {
  double raw_error = 0;  // the largest row-sum error of a closed leaf before any scaling
  double residual = 0;   // the largest error of a held row or column after the balance (final only)
};

// Balances h's scales for the leaves' hemispheres `closed` (per leaf), what each leaf `sends` (its
// largest radiosity: it weighs the emitting leaves of a root) and whether it `emits`, toward `target`.
Balanced balance(Hierarchy& h, BalanceState& state, const std::vector<Hemisphere>& closed,
                 const std::vector<double>& sends, const std::vector<char>& emits, const std::vector<Patch>& patches,
                 double target, bool final_balance, const SolveControl& control);

}  // namespace lambert::hierarchical
