// The closure of the hierarchical operator.
//
// Closure and conservation. The links are estimates (rays, fits, cluster approximations) and not
// reciprocal, so their row sums Σ_j F_ij (what leaf i gathers of a uniform radiosity) and their
// area-weighted column sums Σ_i A_i F_ij / A_j (what the scene gathers of leaf j's power) both miss 1
// in a closed hemisphere. Scaling rows alone makes a furnace exact but not the energy: the power shot
// by j is received as its column sum. So rows and columns are scaled together, F' = D_r F D_c
// (Sinkhorn–Knopp, alternating): a closed leaf's row and column sums become 1, an open leaf's are
// only kept from exceeding 1 (never more than a hemisphere, never more than was shot).
//
// Columns are the less accurate side: a coarse source spreads what it sends over its leaves by a
// linear field at most (Link::bin, the point where a near link reads its source), and where it meets
// a small receiver at an edge the kernel is far from even (leaf columns 0.85–1.34 in a black room lit
// by its floor while the spread was even, whose rows were within 1.2 %). So a column is held at 1
// only where that conserves power the scene computes. Leaves that send nothing (`sends` 0: black and
// not emitting) are left alone. Emitting leaves, whose exitance is given, are held together per
// root, weighted by what each sends: held leaf by leaf, they moved the floor's light in that room by
// up to 8 % (17 % while the black walls' columns were held too). Reflecting leaves keep their own
// columns: their power is the solution's, and without them a closed room lit by a point source
// lost 1.2 % of it (held per root, or per group of 16 leaves, 0.7 %: the power a root sends is
// not spread over it as its radiosity is). The price was the same distortion where reflectors meet
// at an edge: with grey walls that room was 8.3 % off the dense solver at worst while coarse sources
// were read at their centroid, 1.0 % since near links read them where the receiver sees them.
//
// Each sweep is one apply() and one apply_transpose(); plain sweeps shrink the error by about 0.65
// each in the sphere furnaces, over-relaxed ones (optimal_overrelaxation, solver/linear_solve.h) by
// about 0.3. The scales and the over-relaxation of the previous refinement round, whose links mostly
// remain, are the starting point. The sweeps stop once every held row and column is within `target`
// of 1 (balance_target), or where a previous balance stalled short of a target at least as tight
// (a stall on the way to the oracle's target does not stop the final balance): a lit room's sweeps
// stall at 1e-6 to 1e-5 (leaves whose rows and columns are nearly free), far below the links' own
// errors, and aiming lower cost the 985 435-patch lit sphere room 20 sweeps a round. Returns the
// largest row-sum error of a closed leaf before any scaling (stats.max_closure_error) and, for the
// final balance, the largest error of a held row or column after it (stats.closure_residual).
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
// largest radiosity; 0: black and not emitting) and whether it `emits`, toward `target`.
Balanced balance(Hierarchy& h, BalanceState& state, const std::vector<Hemisphere>& closed,
                 const std::vector<double>& sends, const std::vector<char>& emits, const std::vector<Patch>& patches,
                 double target, bool final_balance, const SolveControl& control);

}  // namespace lambert::hierarchical
