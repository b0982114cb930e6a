// Geometry value types used everywhere below the server: double precision points, vectors and
// triangles. Points and vectors are distinct types so that "point minus point is a vector" and
// "point plus point" does not compile (pbrt-v4 style). Lengths are metres inside the solver.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

namespace lambert {

struct Vector3 {
  double x = 0, y = 0, z = 0;
  constexpr Vector3() = default;
  constexpr Vector3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vector3 operator+(const Vector3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vector3 operator-(const Vector3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vector3 operator-() const { return {-x, -y, -z}; }
  constexpr Vector3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vector3 operator/(double s) const { return {x / s, y / s, z / s}; }
  Vector3& operator+=(const Vector3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  Vector3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
};
constexpr Vector3 operator*(double s, const Vector3& v) { return v * s; }

struct Point3 {
  double x = 0, y = 0, z = 0;
  constexpr Point3() = default;
  constexpr Point3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vector3 operator-(const Point3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Point3 operator+(const Vector3& v) const { return {x + v.x, y + v.y, z + v.z}; }
  constexpr Point3 operator-(const Vector3& v) const { return {x - v.x, y - v.y, z - v.z}; }
  constexpr bool operator==(const Point3&) const = default;
};

constexpr double dot(const Vector3& a, const Vector3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vector3 cross(const Vector3& a, const Vector3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vector3& v) { return std::sqrt(dot(v, v)); }
constexpr double length_squared(const Vector3& v) { return dot(v, v); }
inline Vector3 normalize(const Vector3& v) { return v / length(v); }
inline double distance(const Point3& a, const Point3& b) { return length(a - b); }
// A unit vector perpendicular to the unit vector n (with cross(n, perpendicular(n)), an orthonormal
// right-handed frame about n). Crosses n with the axis it is farthest from, so it never degenerates.
inline Vector3 perpendicular(const Vector3& n) {
  return normalize(std::abs(n.x) < 0.9 ? cross(n, Vector3{1, 0, 0}) : cross(n, Vector3{0, 1, 0}));
}
constexpr Vector3 to_vector(const Point3& p) { return {p.x, p.y, p.z}; }
constexpr Point3 to_point(const Vector3& v) { return {v.x, v.y, v.z}; }
// Affine combination w0 a + w1 b + w2 c with w0 + w1 + w2 = 1 (barycentric point), formed as
// a + w1 (b − a) + w2 (c − a): a coordinate that a, b and c share comes out exactly (a point of a
// wall at x = −3 lies on its plane, not 4e-16 behind it, which decided what exact visibility saw from
// there), and the rounding does not depend on where the triangle sits. (w0 is implied.)
constexpr Point3 barycentric(const Point3& a, const Point3& b, const Point3& c, double /*w0*/, double w1,
                             double w2) {
  return {a.x + (w1 * (b.x - a.x) + w2 * (c.x - a.x)), a.y + (w1 * (b.y - a.y) + w2 * (c.y - a.y)),
          a.z + (w1 * (b.z - a.z) + w2 * (c.z - a.z))};
}

// The midpoint of a and b: the same bits whichever comes first (an edge shared by two triangles has
// one midpoint), and exact in a coordinate they share.
constexpr Point3 midpoint(const Point3& a, const Point3& b) {
  return {0.5 * (a.x + b.x), 0.5 * (a.y + b.y), 0.5 * (a.z + b.z)};
}

// sin and cos of an angle in degrees, exact at multiples of 90° (a rotation by 90° maps axes onto
// axes, and a wall tilted by 90° stands exactly upright, with no 6e-17 residues).
inline std::pair<double, double> sincos_degrees(double deg) {
  double r = std::fmod(deg, 360.0);
  if (r < 0) r += 360.0;
  if (r == 0) return {0, 1};
  if (r == 90) return {1, 0};
  if (r == 180) return {0, -1};
  if (r == 270) return {-1, 0};
  constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180;
  return {std::sin(r * kRadiansPerDegree), std::cos(r * kRadiansPerDegree)};
}

struct Triangle {
  std::array<Point3, 3> v;
  Vector3 area_vector() const { return cross(v[1] - v[0], v[2] - v[0]) * 0.5; }  // |.| = area, along normal
  double area() const { return length(area_vector()); }
  Vector3 normal() const { return normalize(area_vector()); }  // counter-clockwise = front
  Point3 centroid() const { return barycentric(v[0], v[1], v[2], 1.0 / 3, 1.0 / 3, 1.0 / 3); }
  double max_edge_length() const {  // one root: the square root is monotone, so the same value
    return std::sqrt(std::max({length_squared(v[1] - v[0]), length_squared(v[2] - v[1]), length_squared(v[0] - v[2])}));
  }
  // Largest distance from the centroid to a vertex: the radius of a sphere around the centroid that
  // holds the triangle (used for near/far decisions).
  double bounding_radius() const {
    const Point3 c = centroid();
    return std::max({distance(c, v[0]), distance(c, v[1]), distance(c, v[2])});
  }
};

// Distance from p to the nearest point of triangle t (its interior, an edge or a corner), by the
// Voronoi regions of the corners and edges (Ericson, "Real-Time Collision Detection", 5.1.5).
inline double distance_to_triangle(const Point3& p, const Triangle& t) {
  const Point3 &a = t.v[0], &b = t.v[1], &c = t.v[2];
  const Vector3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return length(ap);
  const Vector3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return length(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return length(ap - ab * (d1 / (d1 - d3)));
  const Vector3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return length(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return length(ap - ac * (d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return length(bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denominator = va + vb + vc;
  if (!(denominator > 0)) return std::min({length(ap), length(bp), length(cp)});  // degenerate
  return length(ap - ab * (vb / denominator) - ac * (vc / denominator));
}

// Whether any vertex of b lies strictly in front of the plane of a (unit normal na), with a tolerance
// relative to the triangles' size: b can receive from, or radiate to, a's front side only then.
// (The tolerance's scale is bounded first by the edges' taxicab lengths, which are no shorter: only a
// vertex within that bound of the plane needs the lengths themselves. This test runs for every pair
// of the final gather's rows.)
inline bool any_in_front(const Triangle& a, const Vector3& na, const Triangle& b) {
  const double d[3] = {dot(b.v[0] - a.v[0], na), dot(b.v[1] - a.v[0], na), dot(b.v[2] - a.v[0], na)};
  const double highest = std::max({d[0], d[1], d[2]});
  if (!(highest > 0)) return false;
  const auto taxicab = [](const Triangle& t) {
    double longest = 0;
    for (int k = 0; k < 3; ++k) {
      const Vector3 e = t.v[(k + 1) % 3] - t.v[k];
      longest = std::max(longest, std::abs(e.x) + std::abs(e.y) + std::abs(e.z));
    }
    return longest;
  };
  if (highest > 1e-12 * (taxicab(a) + taxicab(b))) return true;
  return highest > 1e-12 * (a.max_edge_length() + b.max_edge_length());
}

// A map key for the plane through a triangle (unit normal n, offset d from some common origin): the
// normal quantised to 1e-9 and the offset to `offset_unit`, so that the triangles of one flat face,
// which share their plane up to rounding, share a key and faces that only look alike do not.
using PlaneKey = std::tuple<long long, long long, long long, long long>;
inline PlaneKey plane_key(const Vector3& n, double d, double offset_unit) {
  auto q = [](double x, double unit) { return static_cast<long long>(std::llround(x / unit)); };
  return {q(n.x, 1e-9), q(n.y, 1e-9), q(n.z, 1e-9), q(d, offset_unit)};
}

// An indexed triangle mesh (front side: counter-clockwise vertex order).
struct TriangleMesh {
  std::vector<Point3> vertices;
  std::vector<std::array<int, 3>> triangles;
  Triangle triangle(std::size_t t) const {
    const auto& i = triangles[t];
    return {{vertices[i[0]], vertices[i[1]], vertices[i[2]]}};
  }
};

// Welds points at identical positions: out[i] is the same index for every point with p_i's exact
// coordinates (that of the first of them in sorted order), −1 for a point that is not finite.
// Adjacency is then geometric: faces that carry their own copies of shared corners (OBJ exports, a
// box given as six surfaces) still meet.
inline std::vector<int> weld_identical_positions(const std::vector<Point3>& points) {
  std::vector<int> weld(points.size(), -1), order;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (std::isfinite(points[i].x) && std::isfinite(points[i].y) && std::isfinite(points[i].z))
      order.push_back(static_cast<int>(i));
  auto key = [&](int i) { return std::make_tuple(points[i].x, points[i].y, points[i].z); };
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return key(i) < key(j); });
  for (std::size_t k = 0; k < order.size(); ++k)
    weld[order[k]] = (k > 0 && key(order[k]) == key(order[k - 1])) ? weld[order[k - 1]] : order[k];
  return weld;
}

// One side of a triangle: side k runs from the triangle's corner k to corner k + 1, between the welded
// vertices lo < hi, from lo to hi where `forward`.
struct EdgeUse {
  int lo, hi, triangle, k;
  bool forward;
};

// Every side of every triangle, sorted by its ends and then its triangle, so that the uses of one edge
// are adjacent. corners(t) gives triangle t's welded corners; a triangle with a corner below 0 (not
// finite, or left out by the caller) has no sides listed.
template <class Corners>
std::vector<EdgeUse> sorted_edge_uses(std::size_t triangles, Corners corners) {
  std::vector<EdgeUse> uses;
  uses.reserve(3 * triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    const std::array<int, 3> c = corners(t);
    if (c[0] < 0 || c[1] < 0 || c[2] < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const int a = c[k], b = c[(k + 1) % 3];
      uses.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t), k, a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.lo, x.hi, x.triangle, x.k) < std::tie(y.lo, y.hi, y.triangle, y.k);
  });
  return uses;
}

// Calls f once per edge with the run of its uses (a span of sorted_edge_uses' result).
template <class F>
void for_each_edge(const std::vector<EdgeUse>& uses, F f) {
  for (std::size_t i = 0, j; i < uses.size(); i = j) {
    for (j = i + 1; j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi; ++j) {
    }
    f(std::span<const EdgeUse>(uses.data() + i, j - i));
  }
}

// Axis-aligned bounding box, empty until a point is added.
struct Bounds3 {
  Point3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(const Point3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  // The union with another box (nothing where that one is empty).
  void add(const Bounds3& b) {
    if (!b.empty()) add(b.lo), add(b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  // Corner k of 8: bit 0 picks hi.x over lo.x, bit 1 hi.y, bit 2 hi.z.
  Point3 corner(int k) const { return {k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z}; }
  Vector3 diagonal() const { return empty() ? Vector3{} : hi - lo; }
  Point3 center() const { return barycentric(lo, hi, hi, 0.5, 0.5, 0.0); }
};

inline Bounds3 bounds(const Triangle& t) {
  Bounds3 b;
  for (const Point3& p : t.v) b.add(p);
  return b;
}

}  // namespace lambert
