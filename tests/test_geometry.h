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

// The six faces of the axis-aligned box [lo, hi]: face(origin, u, v) for each, with u × v pointing
// into the box (a room's walls; swap u and v for an obstacle's outward faces). Bottom, top, y = lo,
// y = hi, x = lo, x = hi.
template <class Face>
void for_each_box_face(const Point3& lo, const Point3& hi, Face&& face) {
  const double dx = hi.x - lo.x, dy = hi.y - lo.y, dz = hi.z - lo.z;
  face(lo, Vector3{dx, 0, 0}, Vector3{0, dy, 0});                 // z = lo: inward normal +z
  face(Point3{lo.x, lo.y, hi.z}, Vector3{0, dy, 0}, Vector3{dx, 0, 0});  // z = hi: -z
  face(lo, Vector3{0, 0, dz}, Vector3{dx, 0, 0});                 // y = lo: +y
  face(Point3{lo.x, hi.y, lo.z}, Vector3{dx, 0, 0}, Vector3{0, 0, dz});  // y = hi: -y
  face(lo, Vector3{0, dy, 0}, Vector3{0, 0, dz});                 // x = lo: +x
  face(Point3{hi.x, lo.y, lo.z}, Vector3{0, 0, dz}, Vector3{0, dy, 0});  // x = hi: -x
}

// The closed forms the tests compare against (Howell C-11, C-14, B-3 and its corner decomposition).
using closed_form::howell_b3;
using closed_form::howell_c11;
using closed_form::howell_c14;
using closed_form::howell_v2;
using closed_form::perpendicular_rectangle;
using closed_form::point_under_rectangle;
using closed_form::second_moment_b3;
using closed_form::under_rectangle;

}  // namespace lambert::test
