// Exact configuration factors from Howell's catalogue (../shared/REFERENCES.md V1–V4), and the
// second moment that a graded sky adds to B-3: the independent answers that the tests and
// `lambert bench` compare the solver against. The solver itself never calls them.
#pragma once

#include <cmath>

namespace lambert::closed_form {

inline constexpr double kPi = 3.14159265358979323846;

// Howell C-11 (V3): identical, parallel, directly opposed rectangles a × b at distance c
// (X = a/c, Y = b/c).
inline double howell_c11(double X, double Y) {
  const double x2 = X * X, y2 = Y * Y;
  return 2 / (kPi * X * Y) *
         (std::log(std::sqrt((1 + x2) * (1 + y2) / (1 + x2 + y2))) +
          X * std::sqrt(1 + y2) * std::atan(X / std::sqrt(1 + y2)) +
          Y * std::sqrt(1 + x2) * std::atan(Y / std::sqrt(1 + x2)) - X * std::atan(X) - Y * std::atan(Y));
}

// Howell C-14 (V4): perpendicular rectangles with a common edge l; A1 has width w, A2 height h
// (W = w/l, H = h/l); returns F(1 -> 2).
inline double howell_c14(double W, double H) {
  const double w2 = W * W, h2 = H * H;
  const double term = (1 + w2) * (1 + h2) / (1 + w2 + h2) *
                      std::pow(w2 * (1 + w2 + h2) / ((1 + w2) * (w2 + h2)), w2) *
                      std::pow(h2 * (1 + h2 + w2) / ((1 + h2) * (h2 + w2)), h2);
  return 1 / (kPi * W) *
         (W * std::atan(1 / W) + H * std::atan(1 / H) - std::sqrt(h2 + w2) * std::atan(1 / std::sqrt(h2 + w2)) +
          0.25 * std::log(term));
}

// Howell B-3 (V1): element parallel to a rectangle, its normal through a corner (X = a/c, Y = b/c).
inline double howell_b3(double X, double Y) {
  return 1 / (2 * kPi) *
         (X / std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X)) +
          Y / std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y)));
}

// Howell V2 (REFERENCES.md): an element at the origin facing +z, a rectangle in the vertical plane
// y = c, x ∈ [0, a], z ∈ [0, b] from the foot of the perpendicular (X = a/c, Z = b/c):
//   F = (atan X − atan(X/√(1+Z²))/√(1+Z²)) / 2π.
inline double howell_v2(double X, double Z) {
  const double s = std::sqrt(1 + Z * Z);
  return (std::atan(X) - std::atan(X / s) / s) / (2 * kPi);
}

// An element at the origin facing +z and the rectangle x ∈ [x0, x1], z ∈ [z0, z1] (0 ≤ z0 < z1) of the
// plane y = c perpendicular to it: V2 by signed corners along x.
inline double perpendicular_rectangle(double x0, double x1, double z0, double z1, double c) {
  auto corner = [&](double x, double z) { return (x >= 0 ? 1 : -1) * howell_v2(std::abs(x) / c, z / c); };
  return corner(x1, z1) - corner(x0, z1) - corner(x1, z0) + corner(x0, z0);
}

// The second moment ∫ cos² θ dω of a rectangle seen from an element parallel to it, its normal through
// a corner (the set-up of B-3, X = a/c, Y = b/c): with u = x/c, v = y/c, cos θ = c/r and dω = c dA/r³,
//   ∫∫_{[0,X]×[0,Y]} (1 + u² + v²)^(-5/2) du dv = [atan(XY/D) + (XY/D)(1/(1 + X²) + 1/(1 + Y²))] / 3,
// D = √(1 + X² + Y²) (derived here by integrating in v, then u; checked against a double quadrature
// to 1e-15, and its limit over the hemisphere, 4 × π/6 = 2π/3 = ∫ cos² θ dω). It is what the CIE
// overcast sky, L = L_z (1 + 2 cos Z)/3, adds to B-3 through a horizontal opening above a horizontal
// element: E = (L_z/3)(π F + 2 M).
inline double second_moment_b3(double X, double Y) {
  const double D = std::sqrt(1 + X * X + Y * Y);
  return (std::atan(X * Y / D) + X * Y / D * (1 / (1 + X * X) + 1 / (1 + Y * Y))) / 3;
}

// A point at (px, py, 0) facing +z under the axis-aligned rectangle [x0,x1]×[y0,y1] at height h: a
// corner factor f (howell_b3, second_moment_b3) by signed corner decomposition.
template <class CornerFactor>
double under_rectangle(CornerFactor f, double px, double py, double h, double x0, double x1, double y0, double y1) {
  auto corner = [&](double x, double y) {  // signed value of [px, x] × [py, y]
    return (x >= px ? 1 : -1) * (y >= py ? 1 : -1) * f(std::abs(x - px) / h, std::abs(y - py) / h);
  };
  return corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0);
}

// A point at (px, py, 0) facing +z, an axis-aligned rectangle [x0,x1]×[y0,y1] at height h: B-3 by
// signed corner decomposition (V1, "a rectangle in general position").
inline double point_under_rectangle(double px, double py, double h, double x0, double x1, double y0, double y1) {
  return under_rectangle(howell_b3, px, py, h, x0, x1, y0, y1);
}

}  // namespace lambert::closed_form
