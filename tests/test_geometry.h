// Small helpers shared by the physics tests: rectangles as triangle pairs, and the closed forms.
#pragma once

#include <cmath>
#include <vector>

#include "mesh/geometry.h"
#include "solver/closed_forms.h"

namespace lambert::test {

// Rectangle origin + s u + t v (s, t in [0,1]) as two triangles, front side along u × v.
inline std::vector<Triangle> rectangle(const Point3& origin, const Vector3& u, const Vector3& v) {
  const Point3 a = origin, b = origin + u, c = origin + u + v, d = origin + v;
  return {Triangle{{a, b, c}}, Triangle{{a, c, d}}};
}

// The closed forms the tests compare against (Howell C-11, C-14, B-3 and its corner decomposition).
using closed_form::howell_b3;
using closed_form::howell_c11;
using closed_form::howell_c14;
using closed_form::point_under_rectangle;

}  // namespace lambert::test
