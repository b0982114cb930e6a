// Small helpers shared by the physics tests: rectangles as triangle pairs, exact reference formulas.
#pragma once

#include <cmath>
#include <vector>

#include "mesh/geometry.h"

namespace lambert::test {

// Rectangle origin + s u + t v (s, t in [0,1]) as two triangles, front side along u × v.
inline std::vector<Triangle> rectangle(const Point3& origin, const Vector3& u, const Vector3& v) {
  const Point3 a = origin, b = origin + u, c = origin + u + v, d = origin + v;
  return {Triangle{{a, b, c}}, Triangle{{a, c, d}}};
}

// Howell C-11: identical, parallel, directly opposed rectangles a x b at distance c (X = a/c, Y = b/c).
inline double howell_c11(double X, double Y) {
  const double x2 = X * X, y2 = Y * Y;
  return 2 / (M_PI * X * Y) *
         (std::log(std::sqrt((1 + x2) * (1 + y2) / (1 + x2 + y2))) +
          X * std::sqrt(1 + y2) * std::atan(X / std::sqrt(1 + y2)) +
          Y * std::sqrt(1 + x2) * std::atan(Y / std::sqrt(1 + x2)) - X * std::atan(X) - Y * std::atan(Y));
}

// Howell C-14: perpendicular rectangles with a common edge l; A1 has width w, A2 height h (W = w/l,
// H = h/l); returns F(1 -> 2).
inline double howell_c14(double W, double H) {
  const double w2 = W * W, h2 = H * H;
  const double term =
      (1 + w2) * (1 + h2) / (1 + w2 + h2) *
      std::pow(w2 * (1 + w2 + h2) / ((1 + w2) * (w2 + h2)), w2) *
      std::pow(h2 * (1 + h2 + w2) / ((1 + h2) * (h2 + w2)), h2);
  return 1 / (M_PI * W) *
         (W * std::atan(1 / W) + H * std::atan(1 / H) - std::sqrt(h2 + w2) * std::atan(1 / std::sqrt(h2 + w2)) +
          0.25 * std::log(term));
}

// Howell B-3 (REFERENCES V1): element parallel to a rectangle, normal through a corner.
inline double howell_b3(double X, double Y) {
  return 1 / (2 * M_PI) *
         (X / std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X)) +
          Y / std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y)));
}

}  // namespace lambert::test
