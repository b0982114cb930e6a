// Adaptive one-dimensional quadrature for smooth integrands with a few kinks at known points:
// Gauss–Kronrod G7–K15 (QUADPACK's qk15 nodes and error estimate) over a list of intervals, the piece
// with the largest error estimate bisected first (QUADPACK's QAG strategy; Piessens et al. 1983).
// Measure: the integration variable's own (dx). Used by the cone integral of the point-like lights
// (solver/lights/point_like.cpp) and by the planar decomposition of a receiver (receiver_kernel.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <queue>
#include <span>
#include <utility>

namespace lambert::quadrature {
// ---- adaptive Gauss–Kronrod (G7–K15, QUADPACK's qk15 nodes) over a list of breakpoints ----------

constexpr std::array<double, 8> kXgk = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.0};
constexpr std::array<double, 8> kWgk = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
// Gauss weights of the 7-point rule, whose nodes are kXgk[1], kXgk[3], kXgk[5], kXgk[7].
constexpr std::array<double, 4> kWg = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                                       0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

struct Piece {
  double a, b, value, error;
  bool operator<(const Piece& o) const { return error < o.error; }  // max-heap on the error
};

// K15 on [a, b] with QUADPACK's error estimate: |K15 − G7| scaled by the integrand's variation
// (resasc), ((200 |K − G| / resasc)^1.5), which is realistic for smooth integrands instead of the
// very pessimistic |K − G| (QUADPACK qk15; Piessens et al. 1983, §2.2.1).
template <class F>
Piece gauss_kronrod(F& f, double a, double b) {
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  std::array<double, 15> fx;
  fx[7] = f(c);
  for (int j = 0; j < 7; ++j) {
    fx[j] = f(c - h * kXgk[j]);
    fx[14 - j] = f(c + h * kXgk[j]);
  }
  double kronrod = kWgk[7] * fx[7], gauss = kWg[3] * fx[7];
  for (int j = 0; j < 7; ++j) {
    const double s = fx[j] + fx[14 - j];
    kronrod += kWgk[j] * s;
    if (j % 2 == 1) gauss += kWg[j / 2] * s;
  }
  const double mean = 0.5 * kronrod;
  double resasc = kWgk[7] * std::abs(fx[7] - mean);
  for (int j = 0; j < 7; ++j) resasc += kWgk[j] * (std::abs(fx[j] - mean) + std::abs(fx[14 - j] - mean));
  resasc *= std::abs(h);
  double error = std::abs((kronrod - gauss) * h);
  if (resasc != 0 && error != 0) error = resasc * std::min(1.0, std::pow(200 * error / resasc, 1.5));
  return {a, b, kronrod * h, error};
}

using Interval = std::pair<double, double>;

// ∫ f over the union of disjoint intervals, bisecting the piece with the largest error estimate
// (QUADPACK's QAG strategy) until the total estimate is below rel_tolerance × |integral|.
template <class F>
double integrate_1d(F&& f, std::span<const Interval> intervals, double rel_tolerance, int max_pieces) {
  std::priority_queue<Piece> heap;
  double value = 0, error = 0;
  for (const auto& [a, b] : intervals) {
    if (!(b > a)) continue;
    const Piece p = gauss_kronrod(f, a, b);
    value += p.value;
    error += p.error;
    heap.push(p);
  }
  int pieces = static_cast<int>(heap.size());
  while (!heap.empty() && error > rel_tolerance * std::abs(value) && error > 1e-300 && pieces < max_pieces) {
    const Piece worst = heap.top();
    heap.pop();
    const double mid = 0.5 * (worst.a + worst.b);
    if (!(mid > worst.a && mid < worst.b)) break;  // interval exhausted at double precision
    const Piece left = gauss_kronrod(f, worst.a, mid), right = gauss_kronrod(f, mid, worst.b);
    value += left.value + right.value - worst.value;
    error += left.error + right.error - worst.error;
    heap.push(left);
    heap.push(right);
    ++pieces;
  }
  return value;
}

}  // namespace lambert::quadrature
