// Exact configuration factors from Howell's catalogue (../shared/REFERENCES.md V1, V3, V4): the
// independent answers that the tests and `lambert bench` compare the solver against. The solver
// itself never calls them.
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

// A point at (px, py, 0) facing +z, an axis-aligned rectangle [x0,x1]×[y0,y1] at height h: B-3 by
// signed corner decomposition (V1, "a rectangle in general position").
inline double point_under_rectangle(double px, double py, double h, double x0, double x1, double y0, double y1) {
  auto corner = [&](double x, double y) {  // signed factor of [px, x] × [py, y]
    return (x >= px ? 1 : -1) * (y >= py ? 1 : -1) * howell_b3(std::abs(x - px) / h, std::abs(y - py) / h);
  };
  return corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0);
}

}  // namespace lambert::closed_form
