#include "mesh/contacts.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "mesh/convex2d.h"
#include "mesh/polygon_boolean.h"

namespace lambert {

bool contact_segment(const Triangle& t, const Vector3& n, const Triangle& u, double eps, Point3& a, Point3& b) {
  double d[3];
  int zero = 0, positive = 0, negative = 0;
  for (int k = 0; k < 3; ++k) {
    d[k] = dot(u.v[k] - t.v[0], n);
    if (std::abs(d[k]) <= eps) { d[k] = 0; ++zero; }
    else if (d[k] > 0) ++positive;
    else ++negative;
  }
  if (zero == 3 || (zero + positive == 3 && zero < 2) || (zero + negative == 3 && zero < 2)) return false;
  std::vector<Point3> ends;
  for (int k = 0; k < 3; ++k) {
    const int l = (k + 1) % 3;
    if (d[k] == 0) ends.push_back(u.v[k] - n * dot(u.v[k] - t.v[0], n));  // onto the plane exactly
    if (d[k] * d[l] < 0) {
      const Point3 q = u.v[k] + (u.v[l] - u.v[k]) * (d[k] / (d[k] - d[l]));
      ends.push_back(q - n * dot(q - t.v[0], n));
    }
  }
  if (ends.size() < 2) return false;
  a = ends[0];
  b = ends[1];
  // Clip a→b to t (Cyrus–Beck against the three edge half-planes, in t's plane).
  double lo = 0, hi = 1;
  const Vector3 ab = b - a;
  for (int e = 0; e < 3; ++e) {
    const Point3& p = t.v[e];
    const Point3& q = t.v[(e + 1) % 3];
    const Vector3 inward = cross(n, q - p);  // t is counter-clockwise about n
    const double da = dot(a - p, inward), dab = dot(ab, inward);
    const double scale = length(inward) * eps;
    if (std::abs(dab) <= 1e-300) {
      if (da < -scale) return false;
      continue;
    }
    const double s = -da / dab;
    if (dab > 0) lo = std::max(lo, s);
    else hi = std::min(hi, s);
  }
  if (!(hi - lo > 0) || length(ab) * (hi - lo) <= 8 * eps) return false;
  // Along an edge of t: both ends of the part inside within eps of the same edge line.
  const Point3 in_a = a + ab * lo, in_b = a + ab * hi;
  for (int e = 0; e < 3; ++e) {
    const Point3& p = t.v[e];
    const Vector3 edge = t.v[(e + 1) % 3] - p;
    const double len = length(edge);
    auto off_edge = [&](const Point3& x) { return length(cross(edge, x - p)) / len; };
    if (off_edge(in_a) <= 4 * eps && off_edge(in_b) <= 4 * eps) return false;
  }
  return true;
}

double coplanar_shared_area(const Triangle& t, const Vector3& n, const Triangle& u) {
  const Vector3 e1 = normalize(t.v[1] - t.v[0]), e2 = cross(n, e1);
  auto flat = [&](const Triangle& x) {
    Loop2d loop;
    for (const Point3& p : x.v) loop.push_back({dot(p - t.v[0], e1), dot(p - t.v[0], e2)});
    return loop;
  };
  double left = 0;
  for (const Loop2d& loop : convex_difference(flat(t), std::vector<Loop2d>{flat(u)})) left += signed_area(loop);
  return t.area() - left;
}

std::vector<unsigned char> flat_outline_edges(const TriangleMesh& mesh) {
  const std::vector<int> weld = weld_identical_positions(mesh.vertices);
  const std::vector<EdgeUse> uses = sorted_edge_uses(mesh.triangles.size(), [&](std::size_t t) {
    const auto& c = mesh.triangles[t];
    return std::array<int, 3>{weld[c[0]], weld[c[1]], weld[c[2]]};
  });
  std::vector<unsigned char> outline(mesh.triangles.size(), 0b111);
  // An edge inside a flat region: shared with a triangle in the same plane (normals within about
  // 0.1°; a flat panel's triangles agree to rounding).
  for_each_edge(uses, [&](std::span<const EdgeUse> edge) {
    for (const EdgeUse& x : edge)
      for (const EdgeUse& y : edge)
        if (x.triangle != y.triangle &&
            dot(mesh.triangle(x.triangle).normal(), mesh.triangle(y.triangle).normal()) > 1 - 1e-6)
          outline[x.triangle] &= static_cast<unsigned char>(~(1u << x.k));
  });
  return outline;
}

bool lies_just_in_front(const Triangle& t, const Vector3& n, const Triangle& u, double eps, double gap) {
  const double slab = near_slab(u, gap);
  double highest = -1;
  for (const Point3& p : u.v) {
    const double h = dot(p - t.v[0], n);
    if (h < -eps || h > slab) return false;
    highest = std::max(highest, h);
  }
  if (highest <= eps) return false;
  Triangle shadow;  // u projected onto t's plane, counter-clockwise about n as t is
  for (int k = 0; k < 3; ++k) shadow.v[k] = u.v[k] - n * dot(u.v[k] - t.v[0], n);
  if (dot(u.normal(), n) < 0) std::swap(shadow.v[1], shadow.v[2]);
  return coplanar_shared_area(t, n, shadow) > 1e-3 * std::min(t.area(), u.area());
}

}  // namespace lambert
