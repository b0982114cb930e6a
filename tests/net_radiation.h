// The net-radiation method for grey, diffuse surfaces, solved by hand for the tests (Siegel & Howell):
// the radiosities J of S surfaces, each uniform over its surface, from
//
//   J_I − (1 − ε_I) Σ_J F_IJ J_J = ε_I σ T_I⁴
//
// by Gauss–Jordan elimination with partial pivoting: a second method that shares no code with the
// solver's (solver/thermal/grey_exchange.h, GMRES on the operator or the surface matrix).
#pragma once

#include <cmath>
#include <functional>
#include <utility>
#include <vector>

namespace lambert::test {

inline constexpr double kSigma = 5.670374419e-8;  // W m^-2 K^-4 (CODATA 2018)

// F(I, J): the surfaces' factors; emissivity and temperature_K per surface.
inline std::vector<double> net_radiation_radiosity(const std::function<double(int, int)>& F,
                                                   const std::vector<double>& emissivity,
                                                   const std::vector<double>& temperature_K) {
  const int S = static_cast<int>(emissivity.size());
  std::vector<std::vector<double>> A(S, std::vector<double>(S + 1));
  for (int I = 0; I < S; ++I) {
    for (int J = 0; J < S; ++J) A[I][J] = (I == J) - (1 - emissivity[I]) * F(I, J);
    A[I][S] = emissivity[I] * kSigma * std::pow(temperature_K[I], 4);
  }
  for (int c = 0; c < S; ++c) {
    int p = c;
    for (int r = c + 1; r < S; ++r)
      if (std::abs(A[r][c]) > std::abs(A[p][c])) p = r;
    std::swap(A[c], A[p]);
    for (int r = 0; r < S; ++r) {
      if (r == c) continue;
      const double f = A[r][c] / A[c][c];
      for (int k = c; k <= S; ++k) A[r][k] -= f * A[c][k];
    }
  }
  std::vector<double> J(S);
  for (int I = 0; I < S; ++I) J[I] = A[I][S] / A[I][I];
  return J;
}

}  // namespace lambert::test
