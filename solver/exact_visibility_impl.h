// The occluders of ExactVisibility, kept in a bounding-volume hierarchy, and the clipping they are
// queried with: shared by point visibility (exact_visibility.cpp) and shaft culling (shafts.cpp).
// Private to those two files.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "solver/exact_visibility.h"

namespace lambert::exact_visibility_detail {


// A half-space {x : dot(normal, x − origin) >= offset}.
struct HalfSpace {
  Vector3 normal;
  Point3 origin;
  double offset = 0;
  double signed_distance(const Point3& x) const { return dot(normal, x - origin) - offset; }
};

// Sutherland–Hodgman: the part of the convex polygon in[0, count) inside h, written to `out` (at most
// count + 1 vertices); returns its vertex count.
inline int clip(const Point3* in, int count, const HalfSpace& h, Point3* out) {
  int m = 0;
  for (int i = 0; i < count; ++i) {
    const Point3& a = in[i];
    const Point3& b = in[i + 1 < count ? i + 1 : 0];
    const double da = h.signed_distance(a), db = h.signed_distance(b);
    if (da >= 0) out[m++] = a;
    if ((da >= 0) != (db >= 0)) out[m++] = a + (b - a) * (da / (da - db));
  }
  return m;
}

// Room for a triangle clipped by up to 29 planes (a projection's region has 6, a cone 5, a shaft's
// hull at most 2·16 − 4 = 28 faces), in two buffers that the clips alternate between: no allocation,
// no copy per plane.
struct ClipBuffers {
  static constexpr std::size_t kPlanes = 29;
  std::array<Point3, 3 + kPlanes> a, b;
};

// The part of a triangle inside every half-space of a region (fewer than 3 vertices: none), in one
// of the buffers.
inline std::span<const Point3> clip_to_region(const Triangle& t, std::span<const HalfSpace> region, ClipBuffers& buffers) {
  Point3* in = buffers.a.data();
  Point3* out = buffers.b.data();
  std::copy(t.v.begin(), t.v.end(), in);
  int count = 3;
  for (std::size_t k = 0; k < region.size() && k < ClipBuffers::kPlanes && count >= 3; ++k) {
    count = clip(in, count, region[k], out);
    std::swap(in, out);
  }
  return {in, static_cast<std::size_t>(count < 3 ? 0 : count)};
}

// What a triangle's corners tell of it against a convex region: wholly outside one half-space (−1),
// inside all of them (1), or neither (0: it has to be clipped).
inline int corner_verdict(const Triangle& t, std::span<const HalfSpace> region) {
  bool inside = true;
  for (const HalfSpace& r : region) {
    const double d0 = r.signed_distance(t.v[0]), d1 = r.signed_distance(t.v[1]), d2 = r.signed_distance(t.v[2]);
    if (d0 < 0 && d1 < 0 && d2 < 0) return -1;
    inside = inside && d0 >= 0 && d1 >= 0 && d2 >= 0;
  }
  return inside ? 1 : 0;
}

// Whether a box lies wholly outside the half-space (its farthest corner along the normal is outside).
inline bool box_outside(const Bounds3& box, const HalfSpace& h) {
  const Point3 far{h.normal.x >= 0 ? box.hi.x : box.lo.x, h.normal.y >= 0 ? box.hi.y : box.lo.y,
                   h.normal.z >= 0 ? box.hi.z : box.lo.z};
  return h.signed_distance(far) < 0;
}

}  // namespace lambert::exact_visibility_detail

namespace lambert {

using exact_visibility_detail::box_outside;
using exact_visibility_detail::ClipBuffers;
using exact_visibility_detail::clip;
using exact_visibility_detail::clip_to_region;
using exact_visibility_detail::corner_verdict;
using exact_visibility_detail::HalfSpace;

// Bounding-volume hierarchy over the occluders (median split on the longest axis of the centroids'
// box, leaves of up to 4 triangles), queried with the convex region that can occlude.
struct ExactVisibility::Impl {
  struct Node {
    Bounds3 box;
    int first = 0, count = 0;  // leaf: triangles [first, first + count) of `order`
    int right = -1;            // inner node: left child is the next node
  };
  Point3 centre;                   // occluders are stored relative to it (geo-referenced scenes)
  std::vector<Triangle> triangles;
  std::vector<char> outward_solid;  // per triangle: a face of a solid facing out (closed, or open: solid_holds)
  std::vector<int> convex_solid;    // per triangle: the convex solid it bounds, or −1
  std::vector<int> solid_of;        // per triangle: the solid it bounds, or −1
  // Per solid that is open (SolidCap): its cap's plane and its faces' distinct planes, relative to
  // `centre`, within `tolerance`; empty for a closed one.
  struct Open {
    bool open = false;
    Vector3 normal;
    Point3 point;
    std::vector<std::pair<Vector3, Point3>> faces;
    double tolerance = 0;
  };
  std::vector<Open> open;
  static constexpr std::size_t kMaxOpenFacePlanes = 32;

  // Whether what holds for a closed solid holds for triangle k's solid between p and a source S: it
  // is closed, or p and S lie on or behind its cap's plane and p is not inside it (on or in front
  // of some face's plane). Otherwise its triangles are occluders like any other.
  bool solid_holds(int k, const Point3& p, const Triangle& S) const {
    const int id = solid_of[k];
    if (id < 0) return false;
    if (static_cast<std::size_t>(id) >= open.size() || !open[id].open) return true;
    const Open& o = open[id];
    const auto behind_cap = [&](const Point3& q) { return dot(o.normal, q - o.point) <= o.tolerance; };
    if (!behind_cap(p) || !behind_cap(S.v[0]) || !behind_cap(S.v[1]) || !behind_cap(S.v[2])) return false;
    return std::any_of(o.faces.begin(), o.faces.end(),
                       [&](const auto& f) { return dot(f.first, p - f.second) >= -o.tolerance; });
  }
  std::vector<int> order;
  std::vector<Node> nodes;
  // Occluders counted by the cell of their centroid, on a grid of at most 64 cells along the scene's
  // longest axis, as a summed-volume table ((n + 1)³ entries, 0 on the first plane of each axis):
  // how many lie in a block of cells is eight look-ups (occluders_near_box).
  struct Grid {
    Point3 origin;
    std::array<double, 3> cell{};
    std::array<int, 3> n{};
    std::vector<std::uint32_t> table;
  } grid;

  void build_grid(const std::vector<Point3>& centroids) {
    Bounds3 box;
    for (const Point3& c : centroids) box.add(c);
    if (box.empty()) return;
    const Vector3 d = box.diagonal();
    const double longest = std::max({d.x, d.y, d.z});
    if (!(longest > 0)) return;
    for (int a = 0; a < 3; ++a) {
      grid.n[a] = std::max(1, static_cast<int>(std::ceil(64 * d[a] / longest)));
      grid.cell[a] = d[a] > 0 ? d[a] / grid.n[a] * (1 + 1e-12) : 1.0;
    }
    grid.origin = box.lo;
    const std::size_t nx = grid.n[0] + 1, ny = grid.n[1] + 1, nz = grid.n[2] + 1;
    grid.table.assign(nx * ny * nz, 0);
    for (const Point3& c : centroids) {
      std::array<std::size_t, 3> i;
      for (int a = 0; a < 3; ++a)
        i[a] = 1 + static_cast<std::size_t>(std::clamp(static_cast<int>((c[a] - grid.origin[a]) / grid.cell[a]), 0, grid.n[a] - 1));
      ++grid.table[(i[2] * ny + i[1]) * nx + i[0]];
    }
    for (std::size_t k = 1; k < nz; ++k)  // prefix sums along each axis in turn
      for (std::size_t j = 1; j < ny; ++j)
        for (std::size_t i = 1; i < nx; ++i) grid.table[(k * ny + j) * nx + i] += grid.table[(k * ny + j) * nx + i - 1];
    for (std::size_t k = 1; k < nz; ++k)
      for (std::size_t j = 1; j < ny; ++j)
        for (std::size_t i = 1; i < nx; ++i) grid.table[(k * ny + j) * nx + i] += grid.table[(k * ny + j - 1) * nx + i];
    for (std::size_t k = 1; k < nz; ++k)
      for (std::size_t j = 1; j < ny; ++j)
        for (std::size_t i = 1; i < nx; ++i) grid.table[(k * ny + j) * nx + i] += grid.table[((k - 1) * ny + j) * nx + i];
  }

  int build(int first, int count, std::vector<Point3>& centroids) {
    const int index = static_cast<int>(nodes.size());
    nodes.emplace_back();
    Bounds3 box, centroid_box;
    for (int k = first; k < first + count; ++k) {
      for (const Point3& v : triangles[order[k]].v) box.add(v);
      centroid_box.add(centroids[order[k]]);
    }
    nodes[index].box = box;
    if (count <= 4) {
      nodes[index].first = first;
      nodes[index].count = count;
      return index;
    }
    const Vector3 d = centroid_box.diagonal();
    const int axis = d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
    const int half = count / 2;
    std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                     [&](int a, int b) { return centroids[a][axis] < centroids[b][axis]; });
    build(first, half, centroids);
    const int right = build(first + half, count - half, centroids);
    nodes[index].right = right;
    return index;
  }

  // The occluders whose parts in front of a point are seen in directions that do not overlap share a
  // group: the front faces of one convex solid. Any other occluder is a group of its own.
  // (For a source S seen from p: see solid_holds.)
  int group(int k, const Point3& p, const Triangle& S) const {
    return convex_solid[k] >= 0 && solid_holds(k, p, S) ? convex_solid[k] : -2 - k;
  }

  // What the corners of occluder k tell of it against the region that can occlude source S seen from
  // p (corner_verdict), −1 also for a face of an outward solid that p sees from behind.
  int verdict(int k, const Point3& p, const Triangle& S, std::span<const HalfSpace> region) const {
    const Triangle& t = triangles[k];
    if (outward_solid[k] && dot(t.area_vector(), p - t.v[0]) <= 0 && solid_holds(k, p, S)) return -1;
    return corner_verdict(t, region);
  }

  // Whether occluder k reaches into the interior of a convex region. Most triangles lie wholly outside
  // one half-space or wholly inside every one: their corners decide, as clip_to_region would (an
  // empty part, or the whole triangle), and only triangles that cross a face are clipped.
  bool meets(int k, std::span<const HalfSpace> region) const {
    thread_local ClipBuffers buffers;
    const Triangle& t = triangles[k];
    const int verdict = corner_verdict(t, region);
    return verdict > 0 || (verdict == 0 && clip_to_region(t, region, buffers).size() >= 3);
  }

  // Calls visit(triangle index) for the triangles in leaves whose boxes meet the region, until it
  // returns true; returns whether one did.
  template <class Visit>
  bool query(std::span<const HalfSpace> region, Visit&& visit) const {
    if (nodes.empty()) return false;
    thread_local std::vector<int> stack;  // reused: one allocation per thread, not per query
    stack.assign(1, 0);
    while (!stack.empty()) {
      const Node& node = nodes[stack.back()];
      const int index = stack.back();
      stack.pop_back();
      if (std::any_of(region.begin(), region.end(), [&](const HalfSpace& h) { return box_outside(node.box, h); }))
        continue;
      if (node.right < 0) {
        for (int k = node.first; k < node.first + node.count; ++k)
          if (visit(order[k])) return true;
      } else {
        stack.push_back(node.right);
        stack.push_back(index + 1);
      }
    }
    return false;
  }
};

}  // namespace lambert
